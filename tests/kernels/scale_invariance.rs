//! Kernels give accurate answers at every scale the docs promise: the same
//! configurations scaled by powers of two from 2^-150 to 2^150 (about 1e-45
//! to 1e45; scaling by a power of two is exact, so the exact distance scales
//! exactly too). Beyond that, intermediate squares may underflow or
//! overflow, but the answer is still never NaN.

use nearmiss::exact;
use nearmiss::kernels::{point_segment_distance, triangle_distance, PointEdgeFormula};
use nearmiss::math::Point;
use nearmiss::samples::{point_segment_queries, triangle_pairs, InputClass};

#[test]
fn triangle_distance_is_relative_accurate_at_every_scale() {
    let pairs = triangle_pairs(InputClass::NearlyTouching, 40, 21);
    for exponent in (-150..=150).step_by(25) {
        let k = (2.0f64).powi(exponent);
        for (i, (a, b)) in pairs.iter().enumerate() {
            let (a, b) = (a.map(|v| v * k), b.map(|v| v * k));
            let d = triangle_distance(&a, &b).distance;
            let expected = exact::triangle_distance_f64(&a, &b);
            assert!(d.is_finite() && d >= 0.0, "2^{exponent} pair {i}: {d}");
            assert!((d - expected).abs() <= 1e-12 * expected, "2^{exponent} pair {i}: {d:e} vs {expected:e}");
        }
    }
}

#[test]
fn point_segment_vector_is_relative_accurate_at_every_scale() {
    let queries = point_segment_queries(InputClass::Needle, 200, 23);
    for exponent in (-150..=150).step_by(25) {
        let k = (2.0f64).powi(exponent);
        for (p, a, b) in &queries {
            let [p, a, b]: [Point; 3] = [p * k, a * k, b * k];
            let d = point_segment_distance(&p, &a, &b, PointEdgeFormula::Vector);
            let expected = exact::to_f64(&exact::point_segment_distance_squared(&p, &a, &b)).sqrt();
            assert!(
                (d - expected).abs() <= 8.0 * f64::EPSILON * expected,
                "2^{exponent}: {d:e} vs {expected:e}"
            );
        }
    }
}

#[test]
fn never_nan_at_extreme_scales() {
    let pairs = triangle_pairs(InputClass::NearlyTouching, 40, 25);
    let queries = point_segment_queries(InputClass::Needle, 40, 27);
    for exponent in [-1070, -1000, -700, -500, 300, 500, 700, 1000] {
        let k = (2.0f64).powi(exponent);
        for (a, b) in &pairs {
            let d = triangle_distance(&a.map(|v| v * k), &b.map(|v| v * k)).distance;
            assert!(!d.is_nan() && d >= 0.0, "2^{exponent}: {d}");
        }
        for (p, a, b) in &queries {
            for formula in PointEdgeFormula::ALL {
                let d = point_segment_distance(&(p * k), &(a * k), &(b * k), formula);
                assert!(!d.is_nan() && d >= 0.0, "2^{exponent} {formula:?}: {d}");
            }
        }
    }
}

/// `x · 2^k`, exactly for a normal result.
fn times_power_of_two(x: f64, k: i32) -> f64 {
    x * 2f64.powi(k / 2) * 2f64.powi(k - k / 2)
}

#[test]
fn triangle_distance_is_right_at_every_uniform_scale_of_the_f64_range() {
    // Issue 13 §2: beyond 1e±45 the squares overflowed or underflowed (inf,
    // or a false 0). The exact distance of the scaled pair is the unscaled
    // exact distance times 2^k, exactly.
    let pairs = triangle_pairs(InputClass::NearlyTouching, 30, 31);
    for k in (-900..=1000).step_by(50) {
        for (i, (a, b)) in pairs.iter().enumerate() {
            let expected = times_power_of_two(exact::triangle_distance_f64(a, b), k);
            let scale = |p: &Point| p.map(|c| times_power_of_two(c, k));
            let found = triangle_distance(&a.map(|p| scale(&p)), &b.map(|p| scale(&p)));
            assert!(
                (found.distance - expected).abs() <= 1e-12 * expected,
                "2^{k} pair {i}: {:e} vs {expected:e}",
                found.distance
            );
            assert!(found.within_range, "2^{k} pair {i}");
            assert!(found.point_a.iter().chain(found.point_b.iter()).all(|c| c.is_finite()));
        }
    }
}

#[test]
fn the_issues_extreme_pairs_get_their_exact_distance_or_say_they_are_out_of_range() {
    use nearmiss::math::Vector;
    let unit = [Point::new(0.0, 0.0, 0.0), Point::new(1.0, 0.0, 0.0), Point::new(0.0, 1.0, 0.0)];
    let lift = |t: &[Point; 3], v: Vector| t.map(|p| p + v);
    // Two parallel triangles of size 1e-170, 1e-170 apart (was a false 0).
    let s = 1e-170;
    let (a, b) = (unit.map(|p| p * s), unit.map(|p| p * s + Vector::new(0.0, 0.0, s)));
    let expected = exact::triangle_distance_f64(&unit, &lift(&unit, Vector::new(0.0, 0.0, 1.0)));
    let found = triangle_distance(&a, &b);
    assert!((found.distance - expected * s).abs() <= 1e-15 * s, "{:e}", found.distance);
    // Two parallel triangles of size 1e100, 1 apart (was 0).
    let big = unit.map(|p| p * 1e100);
    let found = triangle_distance(&big, &lift(&big, Vector::new(0.0, 0.0, 1.0)));
    assert_eq!(found.distance, 1.0);
    assert!(!found.within_range, "a distance 1e-100 of the coordinates is beyond the stated range");
    // A unit triangle 1 above triangles of size 1e30 to 1e300 (was 1.414 or
    // 1.732 from 1e80 on): the distance is 1 throughout; the stated range
    // (sizes at least 2^-200 of the coordinates) says when it holds.
    for exponent in [30, 50, 60, 61, 80, 150, 300] {
        let size = 10f64.powi(exponent);
        let floor = [Point::new(-size, -size, 0.0), Point::new(size, -size, 0.0), Point::new(0.0, size, 0.0)];
        let small = lift(&unit, Vector::new(0.1, 0.1, 1.0));
        let found = triangle_distance(&floor, &small);
        assert_eq!(found.distance, 1.0, "1e{exponent}");
        assert_eq!(found.within_range, size * nearmiss::kernels::MIN_RELATIVE_SIZE <= 1.0, "1e{exponent}");
    }
}

#[test]
fn point_segment_and_dyop_are_right_at_every_uniform_scale() {
    let queries = point_segment_queries(InputClass::Needle, 100, 33);
    let pairs = triangle_pairs(InputClass::WellConditioned, 30, 35);
    for k in (-900..=1000).step_by(100) {
        let scale = |p: &Point| p.map(|c| times_power_of_two(c, k));
        for (p, a, b) in &queries {
            let expected =
                times_power_of_two(exact::to_f64(&exact::point_segment_distance_squared(p, a, b)).sqrt(), k);
            let d = point_segment_distance(&scale(p), &scale(a), &scale(b), PointEdgeFormula::Vector);
            assert!((d - expected).abs() <= 8.0 * f64::EPSILON * expected, "2^{k}: {d:e} vs {expected:e}");
        }
        for (a, b) in &pairs {
            for formula in PointEdgeFormula::ALL {
                let unscaled = nearmiss::kernels::dyop_distance(a, b, formula);
                let scaled =
                    nearmiss::kernels::dyop_distance(&a.map(|p| scale(&p)), &b.map(|p| scale(&p)), formula);
                assert_eq!(scaled, times_power_of_two(unscaled, k), "2^{k} {formula:?}");
            }
        }
    }
}

#[test]
fn linear_vertex_ccd_gives_the_same_times_at_every_uniform_scale() {
    use nearmiss::ccd::{edge_edge_time_of_impact_detailed, vertex_face_time_of_impact_detailed, CcdOptions};
    let options = CcdOptions::default();
    let face = [Point::new(0.0, 0.0, 0.0), Point::new(1.0, 0.0, 0.0), Point::new(0.0, 1.0, 0.0)];
    let (v0, v1) = (Point::new(0.25, 0.25, 1.0), Point::new(0.25, 0.25, -1.0));
    let (ea, eb0, eb1) = (
        [Point::new(0.0, 0.0, 0.0), Point::new(1.0, 0.0, 0.0)],
        [Point::new(0.5, -1.0, 1.0), Point::new(0.5, 1.0, 1.0)],
        [Point::new(0.5, -1.0, -1.0), Point::new(0.5, 1.0, -1.0)],
    );
    let vf = vertex_face_time_of_impact_detailed(&v0, &face, &v1, &face, &options);
    let ee = edge_edge_time_of_impact_detailed(&ea, &eb0, &ea, &eb1, &options);
    let (t_vf, t_ee) = (vf.time_of_impact.unwrap(), ee.time_of_impact.unwrap());
    assert!(t_vf <= 0.5 && t_ee <= 0.5);
    for k in (-1000..=1000).step_by(100) {
        let s = |p: &Point| p.map(|c| times_power_of_two(c, k));
        let f = face.map(|p| s(&p));
        let vf = vertex_face_time_of_impact_detailed(&s(&v0), &f, &s(&v1), &f, &options);
        let (a, b0, b1) = (ea.map(|p| s(&p)), eb0.map(|p| s(&p)), eb1.map(|p| s(&p)));
        let ee = edge_edge_time_of_impact_detailed(&a, &b0, &a, &b1, &options);
        for (found, unscaled, name) in [(vf, t_vf, "vf"), (ee, t_ee, "ee")] {
            let t = found.time_of_impact.unwrap_or_else(|| panic!("2^{k} {name}: no contact"));
            assert!(t <= 0.5 && (t - unscaled).abs() <= 1e-12, "2^{k} {name}: {t} vs {unscaled}");
            assert!(found.contact_distance.is_finite() && found.contact_distance > 0.0, "2^{k} {name}");
        }
    }
}

#[test]
fn the_checked_kernels_refuse_ratios_beyond_the_stated_range() {
    use nearmiss::kernels::{dyop_distance_checked, point_segment_distance_checked, MIN_RELATIVE_SIZE};
    let (a, b) = (Point::new(0.0, 0.0, 0.0), Point::new(1.0, 0.0, 0.0));
    for k in [-150, -199, -201, -250, -400] {
        let gap = 2f64.powi(k);
        let p = Point::new(0.5, gap, 0.0);
        let found = point_segment_distance_checked(&p, &a, &b, PointEdgeFormula::Vector);
        // Within the range: the exact distance; beyond it: None.
        assert_eq!(found, (gap >= MIN_RELATIVE_SIZE).then_some(gap), "2^{k}");
        let small = [
            p,
            p + nearmiss::math::Vector::new(gap, 0.0, 0.0),
            p + nearmiss::math::Vector::new(0.0, gap, 0.0),
        ];
        let big = [a, b, Point::new(0.0, 1.0, 0.0)];
        let dyop = dyop_distance_checked(&big, &small, PointEdgeFormula::Vector);
        assert_eq!(dyop.is_some(), gap >= MIN_RELATIVE_SIZE, "2^{k}");
    }
}

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

//! `triangle_distance` against the exact rational reference on every input
//! class.
//!
//! The bound, for every class: `|d - d*| ≤ 1e-12·d* + 4ε²·S`, where `d*` is
//! the exact distance and `S` the largest coordinate of the pair relative to
//! the first vertex of `a`. Above `1e-3·S` the plain f64 pass errs by about
//! `2ε·S` (≤ 1e-12 relative there); below it the distance is refined from
//! exact differences in double-double, whose error is of order `ε²·S`. So
//! the error is relative, 1e-12, down to gaps of about 1e-19·S. Also: the
//! distance is exactly 0 whenever the exact reference says the triangles
//! meet.

use nearmiss::exact;
use nearmiss::kernels::{posed_triangle_distance, triangle_distance};
use nearmiss::math::{max_abs_coordinate, MatrixPose, Point, Triangle};
use nearmiss::samples::pair_extent;
use nearmiss::samples::{triangle_pairs, InputClass};
use num_traits::Zero;

const PAIRS_PER_CLASS: usize = 800;
const RELATIVE: f64 = 1e-12;
/// In units of `ε²·S`.
const ABSOLUTE: f64 = 4.0;

fn check_class(class: InputClass) {
    let mut worst: f64 = 0.0;
    for (i, (a, b)) in triangle_pairs(class, PAIRS_PER_CLASS, 7).iter().enumerate() {
        let computed = triangle_distance(a, b);
        let exact_squared = exact::triangle_distance_squared(a, b);
        let expected = exact::to_f64(&exact_squared).sqrt();
        let extent = pair_extent(a, b);
        let bound = RELATIVE * expected + ABSOLUTE * f64::EPSILON * f64::EPSILON * extent;
        let error = (computed.distance - expected).abs();
        assert!(
            error <= bound,
            "{class:?} pair {i}: distance {:e}, exact {expected:e}, error {error:e} > bound {bound:e}\na = {a:?}\nb = {b:?}",
            computed.distance
        );
        if exact_squared.is_zero() {
            assert_eq!(computed.distance, 0.0, "{class:?} pair {i}: the triangles meet");
        }
        // The reported points lie on their triangles and realise the distance.
        let realised = (computed.point_a - computed.point_b).norm();
        assert!((realised - computed.distance).abs() <= 8.0 * f64::EPSILON * extent.max(a[0].coords.amax()));
        for (point, triangle) in [(&computed.point_a, a), (&computed.point_b, b)] {
            let off = exact::to_f64(&exact::point_triangle_distance_squared(point, triangle)).sqrt();
            assert!(
                off <= 8.0 * f64::EPSILON * extent.max(a[0].coords.amax()),
                "{class:?} pair {i}: point off by {off:e}"
            );
        }
        if expected > 0.0 {
            worst = worst.max(error / expected);
        }
    }
    println!("{class:?}: worst relative error {worst:.1e}");
}

#[test]
fn well_conditioned() {
    check_class(InputClass::WellConditioned);
}

#[test]
fn nearly_touching_gaps_down_to_1e_12() {
    check_class(InputClass::NearlyTouching);
}

#[test]
fn sliver_triangles() {
    check_class(InputClass::Needle);
}

#[test]
fn offset_by_1e6() {
    check_class(InputClass::Offset1e6);
}

#[test]
fn parallel_edges() {
    check_class(InputClass::ParallelEdges);
}

#[test]
fn coplanar() {
    check_class(InputClass::Coplanar);
}

#[test]
fn intersecting_is_exactly_zero() {
    check_class(InputClass::Intersecting);
}

#[test]
fn degenerate_triangles() {
    check_class(InputClass::Degenerate);
}

/// A rotation matrix in f64 (orthonormal to rounding, not exactly) and a
/// translation of about `reach`.
fn random_matrix_pose(rng: &mut nearmiss::samples::Rng, reach: f64) -> MatrixPose {
    let axis = rng.in_unit_ball() * 3.0;
    let rotation = nalgebra::Rotation3::new(axis).into_inner();
    MatrixPose { rotation, translation: rng.in_unit_ball() * reach }
}

/// Triangles posed by matrices as given (a mesh distance's closest pair):
/// `posed_triangle_distance` is within an ulp of the largest posed
/// coordinate of the exact distance of the pair posed exactly (rational
/// products and sums of the matrices' and vertices' own values), far from
/// the origin, separated and nearly touching. Posing in plain f64 first,
/// as a quaternion or matrix product does, misses that bound on some of
/// the same pairs: the bound tells the two apart.
#[test]
fn posed_by_matrices_within_an_ulp_of_the_exact_posing() {
    let mut rng = nearmiss::samples::Rng::new(4501);
    let (mut plain_over, mut worst) = (0, 0.0_f64);
    for class in [InputClass::WellConditioned, InputClass::NearlyTouching, InputClass::Needle] {
        for (i, (a, b)) in triangle_pairs(class, 200, 45).iter().enumerate() {
            // Each triangle in its own frame, so that its pose takes it back
            // (to rounding) to where the sample put it, 100 from the origin.
            let shift = rng.unit_vector() * 100.0;
            let (pose_a, pose_b) = (random_matrix_pose(&mut rng, 1.0), random_matrix_pose(&mut rng, 1.0));
            let local = |t: &Triangle, pose: &MatrixPose| {
                t.map(|p| Point::from(pose.rotation.tr_mul(&(p.coords + shift - pose.translation))))
            };
            let (la, lb) = (local(a, &pose_a), local(b, &pose_b));
            let exact_posed = |t: &Triangle, pose: &MatrixPose| {
                t.map(|p| exact::RationalVector::posed(&p, &pose.rotation, &pose.translation))
            };
            let expected = exact::to_f64(&exact::rational_triangle_distance_squared(
                &exact_posed(&la, &pose_a),
                &exact_posed(&lb, &pose_b),
            ))
            .sqrt();
            let plain = |t: &Triangle, pose: &MatrixPose| {
                t.map(|p| Point::from(pose.rotation * p.coords + pose.translation))
            };
            let (pa, pb) = (plain(&la, &pose_a), plain(&lb, &pose_b));
            let ulp = ulp_of(max_abs_coordinate(&[pa, pb].concat()));
            let found = posed_triangle_distance(&la, &pose_a, &lb, &pose_b);
            let error = (found.distance - expected).abs() / ulp;
            assert!(
                error <= 1.0,
                "{class:?} pair {i}: {:e} against exact {expected:e}: {error:.2} ulps",
                found.distance
            );
            worst = worst.max(error);
            // The points are on the posed triangles and realise the distance.
            assert!(((found.point_a - found.point_b).norm() - found.distance).abs() <= 4.0 * ulp);
            if (triangle_distance(&pa, &pb).distance - expected).abs() > ulp {
                plain_over += 1;
            }
        }
    }
    println!(
        "posed exactly: worst {worst:.2} ulps; posed in plain f64: {plain_over} of 600 pairs over 1 ulp"
    );
    assert!(plain_over > 0, "plain posing met the bound everywhere: the check does not tell them apart");
}

/// The spacing of f64 values at `x`.
fn ulp_of(x: f64) -> f64 {
    f64::from_bits(x.abs().to_bits() + 1) - x.abs()
}

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
use nearmiss::kernels::triangle_distance;
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

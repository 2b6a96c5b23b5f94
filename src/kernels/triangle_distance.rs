//! The triangle–triangle distance as callers ask it: the CPU's best
//! instruction set picked once, the pair's candidates in vector lanes
//! (`pair_lanes.rs`) from AVX2 on, one after another otherwise
//! (`triangle_triangle.rs`). Results are bit-identical at every level.

use super::dispatch::SimdLevel;
use super::double_double::{posed_point, DoubleDouble};
#[cfg(target_arch = "x86_64")]
use super::pair_lanes;
use super::triangle_triangle::{normalised_triangle_distance, Sequential, TriangleDistance};
use crate::math::{MatrixPose, Point, Triangle, Vector};

/// Distance between triangles `a` and `b`.
///
/// Degenerate triangles (repeated or collinear vertices) are treated as the
/// segments or points they are. Never panics, never NaN on finite input.
///
/// ```
/// use nearmiss::kernels::{triangle_distance, Feature};
/// use nearmiss::math::Point;
/// let a = [Point::new(0.0, 0.0, 0.0), Point::new(1.0, 0.0, 0.0), Point::new(0.0, 1.0, 0.0)];
/// let b = [Point::new(0.2, 0.2, 0.5), Point::new(2.0, 2.0, 3.0), Point::new(2.0, 0.0, 3.0)];
/// let d = triangle_distance(&a, &b);
/// assert_eq!(d.distance, 0.5);
/// assert_eq!((d.feature_a, d.feature_b), (Feature::Face, Feature::Vertex(0)));
/// assert_eq!(d.point_a, Point::new(0.2, 0.2, 0.0));
/// ```
#[inline]
pub fn triangle_distance(a: &Triangle, b: &Triangle) -> TriangleDistance {
    triangle_distance_with(SimdLevel::detect(), a, b)
}

/// [`triangle_distance`] at the given [`SimdLevel`] (lowered to the best the
/// CPU supports): for tests and benchmarks. Results are bit-identical at
/// every level. From AVX2 on, the pair's 15 candidates run side by side in
/// vector lanes (`pair_lanes.rs`); at the baseline one after another.
pub fn triangle_distance_with(level: SimdLevel, a: &Triangle, b: &Triangle) -> TriangleDistance {
    #[cfg(target_arch = "x86_64")]
    if level.min(SimdLevel::detect()) >= SimdLevel::Avx2 {
        // SAFETY: the CPU has AVX2 and FMA (the level is lowered to what it supports).
        return unsafe { pair_lanes::triangle_distance(a, b) };
    }
    let _ = level;
    normalised_triangle_distance::<Sequential>(a, b)
}

/// The distance between triangle `a` posed by `pose_a` and triangle `b`
/// posed by `pose_b`, the poses taken exactly: each vertex is posed in
/// double-double ([`posed_point`]) and the pair moved next to the origin
/// (by `a`'s first posed vertex, rounded) before it is rounded to `f64`, so
/// the rounding is of the pair's own size, not of its distance from the
/// origin. The points come back in the poses' frame.
///
/// Where plain posing rounds each coordinate by up to an ulp or two of the
/// coordinates (and so moves the distance by as much), this answer is the
/// kernel's on the exactly posed pair: for a mesh distance's closest pair,
/// within an ulp of the largest coordinate of the exact distance.
pub fn posed_triangle_distance(
    a: &Triangle,
    pose_a: &MatrixPose,
    b: &Triangle,
    pose_b: &MatrixPose,
) -> TriangleDistance {
    let posed_a = a.map(|p| posed_point(&pose_a.rotation, &pose_a.translation, &p));
    let posed_b = b.map(|p| posed_point(&pose_b.rotation, &pose_b.translation, &p));
    let origin = Vector::from_fn(|k, _| posed_a[0][k].high);
    let near_origin = |p: [DoubleDouble; 3]| {
        Point::from_slice(&std::array::from_fn::<_, 3, _>(|k| {
            let moved = p[k] - DoubleDouble::from_real(origin[k]);
            moved.high + moved.low
        }))
    };
    let found = triangle_distance(&posed_a.map(near_origin), &posed_b.map(near_origin));
    TriangleDistance { point_a: found.point_a + origin, point_b: found.point_b + origin, ..found }
}

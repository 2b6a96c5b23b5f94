//! Exact (to rounding) distance between two triangles, with closest points
//! and features.
//!
//! Composed of small queries, as Geometric Tools' `DistTriangle3Triangle3`:
//!
//! 1. **Candidates.** For disjoint triangles the closest pair is attained by a vertex over
//!    the interior of the other face (6 queries, [`point_face_interior`]) or
//!    by two edges (9 queries, [`segment_segment`]); vertex–edge and
//!    vertex–vertex pairs are edge–edge pairs with clamped parameters.
//!    Everything is computed relative to vertex 0 of `a`: the differences of
//!    nearby large coordinates are exact, so a pair at 1e6 from the origin is
//!    as accurate as one at the origin.
//! 2. **Certificate.** If the plane normal to the winning pair's direction
//!    separates the two triangles by more than a rounding margin, they are
//!    certainly disjoint and the minimum is the distance. This holds for every
//!    disjoint pair whose gap exceeds about 1e-14 of its size.
//! 3. **Otherwise** the exact predicate test [`triangles_intersect`] decides:
//!    touching or overlapping triangles get distance exactly 0 and a common
//!    point; disjoint ones keep the minimum of step 1.
//!
//! The separated part has no early returns and is shared, lane by lane, with
//! the batched kernel (`triangle_distance_batch`), which gives bit-identical
//! distances.

use super::dispatch::multiversioned;
use super::feature::Feature;
use super::point_triangle::{point_face_interior, point_triangle, FacePlane};
use super::segment_segment::{point_on_segment, segment_segment};
use super::triangle_intersection::triangles_intersect;
use crate::math::{Point, Real, Triangle, Vector};

/// The distance between two triangles and where it is attained.
#[derive(Copy, Clone, Debug, PartialEq)]
pub struct TriangleDistance {
    /// The distance; exactly 0 when the triangles touch or overlap.
    pub distance: Real,
    /// The closest point on the first triangle (a common point if they meet).
    pub point_a: Point,
    /// The closest point on the second triangle (a common point if they meet).
    pub point_b: Point,
    /// The feature of the first triangle that `point_a` lies on.
    pub feature_a: Feature,
    /// The feature of the second triangle that `point_b` lies on.
    pub feature_b: Feature,
}

multiversioned! {
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
    pub fn triangle_distance / triangle_distance_with(a: &Triangle, b: &Triangle) -> TriangleDistance {
        triangle_distance_kernel(a, b)
    }
}

/// The body of [`triangle_distance`], inlined into each instruction-set
/// version and into the batched kernel's scalar pass.
#[inline(always)]
pub(crate) fn triangle_distance_kernel(a: &Triangle, b: &Triangle) -> TriangleDistance {
    let origin = a[0];
    let local_a = a.map(|v| Point::from(v - origin));
    let local_b = b.map(|v| Point::from(v - origin));
    let closest = closest_separated(&local_a, &local_b);
    if !closest.certified {
        if let Some(common) = triangles_intersect(a, b) {
            return TriangleDistance {
                distance: 0.0,
                point_a: common,
                point_b: common,
                feature_a: point_triangle(&common, a).feature,
                feature_b: point_triangle(&common, b).feature,
            };
        }
    }
    let (point_a, point_b, feature_a, feature_b) = match closest.pair {
        ClosestPair::VertexOverFace { vertex_of_b: true, vertex } => {
            let face = FacePlane::new(&local_a);
            let (_, projection) = point_face_interior(&local_b[vertex as usize], &face);
            (projection + origin.coords, b[vertex as usize], Feature::Face, Feature::Vertex(vertex))
        }
        ClosestPair::VertexOverFace { vertex_of_b: false, vertex } => {
            let face = FacePlane::new(&local_b);
            let (_, projection) = point_face_interior(&local_a[vertex as usize], &face);
            (a[vertex as usize], projection + origin.coords, Feature::Vertex(vertex), Feature::Face)
        }
        ClosestPair::EdgeEdge { edge_a, edge_b, s, t } => {
            let (i, j) = (edge_a as usize, edge_b as usize);
            (
                point_on_segment(&a[i], &a[(i + 1) % 3], s),
                point_on_segment(&b[j], &b[(j + 1) % 3], t),
                Feature::on_edge(edge_a, s),
                Feature::on_edge(edge_b, t),
            )
        }
    };
    TriangleDistance { distance: closest.distance_squared.sqrt(), point_a, point_b, feature_a, feature_b }
}

/// Which of the 15 candidate pairs attains the minimum.
#[derive(Copy, Clone, Debug, PartialEq)]
pub(crate) enum ClosestPair {
    /// A vertex of one triangle over the interior of the other's face.
    VertexOverFace { vertex_of_b: bool, vertex: u8 },
    /// Edge `edge_a` of `a` at parameter `s`, edge `edge_b` of `b` at `t`.
    EdgeEdge { edge_a: u8, edge_b: u8, s: Real, t: Real },
}

/// The minimum over the 15 candidate pairs, and whether the triangles are
/// certainly disjoint.
#[derive(Copy, Clone, Debug, PartialEq)]
pub(crate) struct ClosestSeparated {
    /// The smallest squared candidate distance.
    pub distance_squared: Real,
    /// The candidate pair attaining it.
    pub pair: ClosestPair,
    /// `point_b - point_a` of that pair.
    pub separation: Vector,
    /// Whether the plane normal to `separation` certainly separates the
    /// triangles (then they are disjoint and the minimum is their distance);
    /// `false` means "not certain": the exact test must decide.
    pub certified: bool,
}

/// How many `ε · ‖u‖₁ · S` a separation along `u` must exceed to be certain
/// (S the largest local coordinate). Each projection `u·v` carries at most
/// about `6.2 ε ‖u‖ S` of error: `ε/2` relative from forming the local
/// coordinate, `3ε` from the dot product on `|v| ≤ √3 S`; two of them are
/// compared. 16 covers `2 × 6.2` with room.
const SEPARATION_MARGIN_ULPS: Real = 16.0;

/// The smallest of the 15 candidate squared distances between two
/// triangles (local coordinates), which pair attains it, and whether the
/// direction between that pair certifies that the triangles are disjoint.
/// The first minimum in the fixed candidate order wins ties.
#[inline(always)]
pub(crate) fn closest_separated(a: &Triangle, b: &Triangle) -> ClosestSeparated {
    let face_a = FacePlane::new(a);
    let face_b = FacePlane::new(b);
    let mut best = ClosestSeparated {
        distance_squared: Real::INFINITY,
        pair: ClosestPair::VertexOverFace { vertex_of_b: true, vertex: 0 },
        separation: Vector::zeros(),
        certified: false,
    };
    for vertex in 0..3u8 {
        let (squared, projection) = point_face_interior(&b[vertex as usize], &face_a);
        if squared < best.distance_squared {
            best.distance_squared = squared;
            best.pair = ClosestPair::VertexOverFace { vertex_of_b: true, vertex };
            best.separation = b[vertex as usize] - projection;
        }
        let (squared, projection) = point_face_interior(&a[vertex as usize], &face_b);
        if squared < best.distance_squared {
            best.distance_squared = squared;
            best.pair = ClosestPair::VertexOverFace { vertex_of_b: false, vertex };
            best.separation = projection - a[vertex as usize];
        }
    }
    for edge_a in 0..3u8 {
        let (i, i1) = (edge_a as usize, (edge_a as usize + 1) % 3);
        for edge_b in 0..3u8 {
            let (j, j1) = (edge_b as usize, (edge_b as usize + 1) % 3);
            let c = segment_segment(&a[i], &a[i1], &b[j], &b[j1]);
            if c.distance_squared < best.distance_squared {
                best.distance_squared = c.distance_squared;
                best.pair = ClosestPair::EdgeEdge { edge_a, edge_b, s: c.s, t: c.t };
                best.separation = -c.gap;
            }
        }
    }
    // Separating-axis certificate along the closest direction.
    let u = best.separation;
    let highest_a = a.iter().map(|v| u.dot(&v.coords)).fold(Real::NEG_INFINITY, Real::max);
    let lowest_b = b.iter().map(|v| u.dot(&v.coords)).fold(Real::INFINITY, Real::min);
    let extent = a.iter().chain(b).flat_map(|v| v.coords.iter()).fold(0.0, |m: Real, c| m.max(c.abs()));
    let margin = SEPARATION_MARGIN_ULPS * Real::EPSILON * u.lp_norm(1) * extent;
    best.certified = lowest_b - highest_a > margin;
    best
}

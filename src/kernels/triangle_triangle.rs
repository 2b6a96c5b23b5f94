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
use super::lanes::{Lane, V3};
use super::point_triangle::{point_face_interior, point_triangle, FacePlane};
use super::segment_segment::{point_on_segment, segment_segment_lanes, Edge};
use super::triangle_intersection::triangles_intersect;
use crate::math::{Point, Real, Triangle};

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
    let origin = V3::from(&a[0]);
    let local_a = [V3::from(&a[0]) - origin, V3::from(&a[1]) - origin, V3::from(&a[2]) - origin];
    let local_b = [V3::from(&b[0]) - origin, V3::from(&b[1]) - origin, V3::from(&b[2]) - origin];
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
    let to_world = |v: V3<Real>| (v + origin).to_point();
    // Candidate codes, in the order `closest_separated` considers them.
    let code = closest.candidate as usize;
    let (point_a, point_b, feature_a, feature_b) = if code < VERTEX_OF_A_OVER_FACE_OF_B {
        let vertex = code - VERTEX_OF_B_OVER_FACE_OF_A;
        let (_, projection) = point_face_interior(&local_b[vertex], &FacePlane::new(&local_a));
        (to_world(projection), b[vertex], Feature::Face, Feature::Vertex(vertex as u8))
    } else if code < EDGE_OF_A_AND_EDGE_OF_B {
        let vertex = code - VERTEX_OF_A_OVER_FACE_OF_B;
        let (_, projection) = point_face_interior(&local_a[vertex], &FacePlane::new(&local_b));
        (a[vertex], to_world(projection), Feature::Vertex(vertex as u8), Feature::Face)
    } else {
        let (i, j) = ((code - EDGE_OF_A_AND_EDGE_OF_B) / 3, (code - EDGE_OF_A_AND_EDGE_OF_B) % 3);
        (
            point_on_segment(&a[i], &a[(i + 1) % 3], closest.s),
            point_on_segment(&b[j], &b[(j + 1) % 3], closest.t),
            Feature::on_edge(i as u8, closest.s),
            Feature::on_edge(j as u8, closest.t),
        )
    };
    TriangleDistance { distance: closest.distance_squared.sqrt(), point_a, point_b, feature_a, feature_b }
}

/// Candidate codes 0..3: vertex `code` of b over the face of a.
const VERTEX_OF_B_OVER_FACE_OF_A: usize = 0;
/// Candidate codes 3..6: vertex `code - 3` of a over the face of b.
const VERTEX_OF_A_OVER_FACE_OF_B: usize = 3;
/// Candidate codes 6..15: edge `(code - 6) / 3` of a and `(code - 6) % 3` of b.
const EDGE_OF_A_AND_EDGE_OF_B: usize = 6;

/// The minimum over the 15 candidate pairs, and whether the triangles are
/// certainly disjoint.
#[derive(Copy, Clone, Debug)]
pub(crate) struct ClosestSeparated<L: Lane> {
    /// The smallest squared candidate distance.
    pub distance_squared: L,
    /// Which candidate attains it (a code, see the constants above).
    pub candidate: L,
    /// Edge parameters of an edge–edge candidate.
    pub s: L,
    /// Edge parameters of an edge–edge candidate.
    pub t: L,
    /// Whether the plane normal to the direction between the winning pair
    /// certainly separates the triangles (then they are disjoint and the
    /// minimum is their distance); false means "not certain": the exact test
    /// must decide.
    pub certified: L::Mask,
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
/// The first minimum in the fixed candidate order wins ties. Branch-free:
/// runs on one pair or a batch of lanes with the same result.
#[inline(always)]
#[allow(clippy::needless_range_loop)] // index loops: see the first comment
pub(crate) fn closest_separated<L: Lane>(a: &[V3<L>; 3], b: &[V3<L>; 3]) -> ClosestSeparated<L> {
    // No closures or iterator adapters here: inside the dispatched
    // functions they would not be inlined, and run without the vector
    // instruction set.
    let zero = L::splat(0.0);
    let face_a = FacePlane::new(a);
    let face_b = FacePlane::new(b);
    let mut best = Best {
        distance_squared: L::splat(Real::INFINITY),
        candidate: zero,
        s: zero,
        t: zero,
        separation: V3::zeros(),
    };
    for vertex in 0..3 {
        let (squared, projection) = point_face_interior(&b[vertex], &face_a);
        best.consider(squared, VERTEX_OF_B_OVER_FACE_OF_A + vertex, zero, zero, b[vertex] - projection);
        let (squared, projection) = point_face_interior(&a[vertex], &face_b);
        best.consider(squared, VERTEX_OF_A_OVER_FACE_OF_B + vertex, zero, zero, projection - a[vertex]);
    }
    let edges_a = [Edge::new(&a[0], &a[1]), Edge::new(&a[1], &a[2]), Edge::new(&a[2], &a[0])];
    let edges_b = [Edge::new(&b[0], &b[1]), Edge::new(&b[1], &b[2]), Edge::new(&b[2], &b[0])];
    for i in 0..3 {
        for j in 0..3 {
            let c = segment_segment_lanes(&edges_a[i], &edges_b[j]);
            best.consider(c.distance_squared, EDGE_OF_A_AND_EDGE_OF_B + 3 * i + j, c.s, c.t, -c.gap);
        }
    }
    // Separating-axis certificate along the closest direction.
    let u = best.separation;
    let highest_a = u.dot(&a[0]).max(u.dot(&a[1])).max(u.dot(&a[2]));
    let lowest_b = u.dot(&b[0]).min(u.dot(&b[1])).min(u.dot(&b[2]));
    let extent_a = a[0].max_abs().max(a[1].max_abs()).max(a[2].max_abs());
    let extent = extent_a.max(b[0].max_abs()).max(b[1].max_abs()).max(b[2].max_abs());
    let margin = L::splat(SEPARATION_MARGIN_ULPS * Real::EPSILON) * u.norm_l1() * extent;
    ClosestSeparated {
        distance_squared: best.distance_squared,
        candidate: best.candidate,
        s: best.s,
        t: best.t,
        certified: margin.lt(lowest_b - highest_a),
    }
}

/// The running minimum of [`closest_separated`].
struct Best<L: Lane> {
    distance_squared: L,
    candidate: L,
    s: L,
    t: L,
    separation: V3<L>,
}

impl<L: Lane> Best<L> {
    /// Keeps candidate `code` where it is strictly closer.
    #[inline(always)]
    fn consider(&mut self, squared: L, code: usize, s: L, t: L, separation: V3<L>) {
        let better = squared.lt(self.distance_squared);
        self.distance_squared = L::select(better, squared, self.distance_squared);
        self.candidate = L::select(better, L::splat(code as Real), self.candidate);
        self.s = L::select(better, s, self.s);
        self.t = L::select(better, t, self.t);
        self.separation = V3::select(better, separation, self.separation);
    }
}

//! Exact (to rounding) distance between two triangles, with closest points
//! and features.
//!
//! Composed of small queries, as Geometric Tools' `DistTriangle3Triangle3`:
//!
//! 1. **Candidates** (`separated.rs`). For disjoint triangles the closest
//!    pair is attained by a vertex over the interior of the other face
//!    (6 queries, [`point_face_interior`]) or by two edges (9 queries,
//!    [`segment_segment`](super::segment_segment)); vertex–edge and
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
//! 4. **Refinement** (`refine.rs`). When the distance is below
//!    [`REFINE_BELOW_EXTENT`](super::REFINE_BELOW_EXTENT) of the pair's size,
//!    the winning pair's distance is recomputed from exact differences in
//!    double-double arithmetic, so that even a 1e-12 gap between unit
//!    triangles comes out with a relative error of a few ulps.
//!
//! Steps 1 and 2 have no branches and are shared, lane by lane, with the
//! batched kernel ([`super::batch::triangle_distances`]), which gives
//! bit-identical distances. On one pair, from AVX2 on, they run with the
//! pair's 15 candidates side by side in vector lanes (`pair_lanes.rs`),
//! again bit for bit the same.

use super::feature::Feature;
use super::lanes::V3;
use super::point_triangle::point_triangle;
use super::refine::refined_distance_kernel;
use super::scale::{
    largest_magnitude_of_pair, normalising_exponent, scale_by_power_of_two, scale_point, triangle_extent,
    MIN_RELATIVE_SIZE,
};
use super::segment_segment::point_on_segment;
use super::separated::{closest_separated, local_frame, triangle_lanes, Candidate, ClosestSeparated};
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
    /// Whether the stated accuracy holds: each triangle's extent and the
    /// distance (unless zero) are at least [`MIN_RELATIVE_SIZE`](super::MIN_RELATIVE_SIZE)
    /// (about 6e-61) of the largest coordinate magnitude. Any uniform scale
    /// is fine (inputs are normalised by a power of two); `false` means a
    /// size ratio beyond that, where products of the small lengths leave the
    /// normal range and the distance may have lost its digits.
    pub within_range: bool,
}

/// A pair's sizes, for the normalisation and the range check.
#[derive(Copy, Clone, Debug)]
pub(super) struct PairSizes {
    /// The largest coordinate magnitude of the six vertices (NaN passed over).
    pub largest: Real,
    /// Each triangle's extent (`scale.rs`'s `triangle_extent`).
    pub extents: [Real; 2],
}

/// How an instruction set runs the parts of [`triangle_distance`](super::triangle_distance) that
/// differ between them. Static methods, always inlined: a closure or a
/// function item passed instead is compiled on its own, without the
/// caller's target features, and its intrinsics (and `mul_add`) become calls.
pub(crate) trait PairPass {
    /// What the candidate pass leaves for the refinement (nothing, or every
    /// candidate's values).
    type Kept: Default;

    /// The candidate pass on local coordinates ([`closest_separated`]'s
    /// result), keeping what the refinement may need in `kept`.
    fn closest(a: &[V3<Real>; 3], b: &[V3<Real>; 3], kept: &mut Self::Kept) -> ClosestSeparated<Real>;

    /// The pair's sizes.
    fn sizes(a: &Triangle, b: &Triangle) -> PairSizes;

    /// The refined distance (`refine.rs`) of `a`, `b` (world coordinates),
    /// given their pass and what it kept.
    fn refined(a: &Triangle, b: &Triangle, closest: &ClosestSeparated<Real>, kept: &Self::Kept) -> Real;
}

/// The candidates one after another, the sizes one coordinate at a time:
/// the baseline, and the batch's scalar pass.
pub(crate) struct Sequential;

impl PairPass for Sequential {
    type Kept = ();

    #[inline(always)]
    fn closest(a: &[V3<Real>; 3], b: &[V3<Real>; 3], _: &mut ()) -> ClosestSeparated<Real> {
        closest_separated(a, b)
    }

    /// The tie path recomputes the candidates one after another: the
    /// baseline single pair is the sequential reference from end to end
    /// (the tests compare every level with it).
    #[inline(always)]
    fn refined(a: &Triangle, b: &Triangle, closest: &ClosestSeparated<Real>, _: &()) -> Real {
        refined_distance_kernel(a, b, closest)
    }

    #[inline(always)]
    fn sizes(a: &Triangle, b: &Triangle) -> PairSizes {
        PairSizes {
            largest: largest_magnitude_of_pair(a, b),
            extents: [triangle_extent(a), triangle_extent(b)],
        }
    }
}

/// [`triangle_distance_kernel`] behind the power-of-two normalisation of
/// `scale.rs`, with the range check.
#[inline(always)]
pub(super) fn normalised_triangle_distance<P: PairPass>(a: &Triangle, b: &Triangle) -> TriangleDistance {
    let measured = P::sizes(a, b);
    let Some(exponent) = normalising_exponent(measured.largest) else {
        let mut found = triangle_distance_kernel::<P>(a, b);
        found.within_range &= within_range(&measured, found.distance);
        return found;
    };
    let (a, b) = (a.map(|p| scale_point(&p, -exponent)), b.map(|p| scale_point(&p, -exponent)));
    let mut found = triangle_distance_kernel::<P>(&a, &b);
    found.within_range &= within_range(&P::sizes(&a, &b), found.distance);
    found.distance = scale_by_power_of_two(found.distance, exponent);
    found.point_a = scale_point(&found.point_a, exponent);
    found.point_b = scale_point(&found.point_b, exponent);
    found
}

/// Whether each triangle's extent and the distance (unless zero: touching,
/// decided exactly) are at least `MIN_RELATIVE_SIZE` of the largest
/// coordinate magnitude.
#[inline(always)]
fn within_range(sizes: &PairSizes, distance: Real) -> bool {
    let limit = MIN_RELATIVE_SIZE * sizes.largest;
    let fine = |size: Real| size == 0.0 || size >= limit;
    fine(sizes.extents[0]) && fine(sizes.extents[1]) && fine(distance)
}

/// The body of [`triangle_distance`](super::triangle_distance), inlined into each instruction-set
/// version and into the batched kernel's scalar pass.
#[inline(always)]
pub(crate) fn triangle_distance_kernel<P: PairPass>(a: &Triangle, b: &Triangle) -> TriangleDistance {
    let origin = V3::from(&a[0]);
    let (local_a, local_b) = local_frame(&triangle_lanes(a), &triangle_lanes(b));
    let mut kept = P::Kept::default();
    let closest = P::closest(&local_a, &local_b, &mut kept);
    if !closest.certified {
        if let Some(common) = triangles_intersect(a, b) {
            return TriangleDistance {
                distance: 0.0,
                point_a: common,
                point_b: common,
                feature_a: point_triangle(&common, a).feature,
                feature_b: point_triangle(&common, b).feature,
                within_range: true,
            };
        }
    }
    let to_world = |v: V3<Real>| (v + origin).to_point();
    let (point_a, point_b, feature_a, feature_b) = match closest.winner() {
        // The separation runs from the vertex's projection to the vertex
        // (b over a) or from the vertex to its projection (a over b).
        Candidate::VertexOfBOverFaceOfA(vertex) => (
            to_world(local_b[vertex] - closest.best.separation),
            b[vertex],
            Feature::Face,
            Feature::Vertex(vertex as u8),
        ),
        Candidate::VertexOfAOverFaceOfB(vertex) => (
            a[vertex],
            to_world(local_a[vertex] + closest.best.separation),
            Feature::Vertex(vertex as u8),
            Feature::Face,
        ),
        Candidate::Edges(i, j) => (
            point_on_segment(&a[i], &a[(i + 1) % 3], closest.best.s),
            point_on_segment(&b[j], &b[(j + 1) % 3], closest.best.t),
            Feature::on_edge(i as u8, closest.best.s),
            Feature::on_edge(j as u8, closest.best.t),
        ),
    };
    let distance = if closest.needs_refinement() {
        P::refined(a, b, &closest, &kept)
    } else {
        closest.best.distance_squared.sqrt()
    };
    // Separated triangles at distance 0: the distance underflowed (the
    // exact intersection test said they do not meet).
    TriangleDistance { distance, point_a, point_b, feature_a, feature_b, within_range: distance > 0.0 }
}

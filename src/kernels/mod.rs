//! Pure distance kernels: no allocation, no I/O, never a panic, never NaN on
//! finite input.
//!
//! **Domain of the stated accuracy.** Any uniform scale of the f64 range:
//! the public kernels ([`triangle_distance`], [`point_segment_distance`],
//! [`dyop_distance`], and the linear-vertex CCD queries) normalise inputs
//! whose largest coordinate lies beyond `2^±SAFE_EXPONENT` by an exact power
//! of two, compute there and scale the answer back (`scale.rs`;
//! `tests/kernels/scale_invariance.rs` checks 2^-900 to 2^1000 against the exact
//! reference). What no scaling fixes is a size *ratio*: the bounds hold
//! while each triangle's (segment's) extent and the distance are at least
//! [`MIN_RELATIVE_SIZE`] (2^-200, about 6e-61) of the largest coordinate
//! magnitude; [`TriangleDistance::within_range`] says whether they are, and
//! [`point_segment_distance_checked`] and [`dyop_distance_checked`] return
//! `None` outside. (The linear-vertex CCD stays conservative there: its
//! tolerance never drops below 64 ulps of the largest coordinate, and the
//! contact distance it used is in its result.)
//! Beyond it products of the small lengths leave the normal range (the
//! answer is never NaN, and a separated pair whose distance underflows to 0
//! is marked out of range). The batched kernels compute inputs as they
//! are: use them within `2^±SAFE_EXPONENT`.
//!
//! - [`point_segment_distance`] with the three [`PointEdgeFormula`]s of the
//!   seed paper and its critics (plus the plain cross product).
//! - [`triangle_distance`]: exact (to rounding) triangle–triangle distance with
//!   closest points and features, built from [`point_face_interior`],
//!   [`segment_segment`] and the exact [`triangles_intersect`].
//! - [`triangle_intersection`] and [`triangle_penetration`]: past contact,
//!   the set two triangles share and the shortest translation that
//!   separates them.
//! - [`dyop_distance`]: the seed's approximate DyOP kernel.
//! - [`batch`]: the same kernels over structure-of-arrays batches, vectorized
//!   with runtime CPU-feature dispatch, bit-identical to the scalar ones.
//!   A single triangle pair runs its own candidates in vector lanes
//!   (AVX2), with the same result.

pub mod batch;
mod compensated;
mod dispatch;
mod double_double;
mod dyop;
mod feature;
pub(crate) mod lanes;
#[cfg(target_arch = "x86_64")]
mod pair_lanes;
mod point_segment;
mod point_triangle;
mod refine;
mod scale;
mod segment_segment;
mod separated;
mod triangle_distance;
mod triangle_intersection;
mod triangle_overlap;
mod triangle_penetration;
mod triangle_triangle;
#[cfg(target_arch = "x86_64")]
mod ymm;

pub use compensated::difference_of_products;
pub use dispatch::SimdLevel;
pub use double_double::{height_over_plane, posed_point, vector_difference, DoubleDouble};
pub use dyop::{dynamic_origin_point, dyop_distance, dyop_distance_checked};
pub use feature::Feature;
pub use point_segment::{
    heron_height, point_segment_distance, point_segment_distance_checked, point_segment_distance_with,
    stable_heron_height, PointEdgeFormula,
};
pub(crate) use point_triangle::nearest_of_four;
pub use point_triangle::{point_face_interior, point_triangle, FacePlane, PointTriangle};
#[cfg(test)]
pub(crate) use refine::{REFINE_BELOW_EXTENT, REFINE_TIE_BAND_ULPS};
pub use scale::MIN_RELATIVE_SIZE;
pub(crate) use scale::{largest_magnitude, normalising_exponent, scale_by_power_of_two, scale_point};
pub use segment_segment::{segment_segment, segment_segment_lanes, Edge, SegmentSegment};
pub use triangle_distance::{posed_triangle_distance, triangle_distance, triangle_distance_with};
pub use triangle_intersection::triangles_intersect;
pub use triangle_overlap::{triangle_intersection, OverlapPolygon, TriangleIntersection};
pub use triangle_penetration::{triangle_penetration, TrianglePenetration};
pub use triangle_triangle::TriangleDistance;

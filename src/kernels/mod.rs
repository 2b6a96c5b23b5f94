//! Pure distance kernels: no allocation, no I/O, never a panic, never NaN on
//! finite input.
//!
//! **Domain of the stated accuracy.** The error bounds hold for coordinates,
//! sizes and distances between about 1e-45 and 1e45 in magnitude
//! (`tests/scale_invariance.rs`): the kernels square and multiply lengths up
//! to the fourth power. Beyond that an intermediate value may underflow to 0
//! or overflow to infinity, and the answer may be 0 or infinite, but never NaN.
//!
//! - [`point_segment_distance`] with the three [`PointEdgeFormula`]s of the
//!   seed paper and its critics (plus the plain cross product).
//! - [`triangle_distance`]: exact (to rounding) triangle–triangle distance with
//!   closest points and features, built from [`point_face_interior`],
//!   [`segment_segment`] and the exact [`triangles_intersect`].
//! - [`dyop_distance`]: the seed's approximate DyOP kernel.
//! - [`batch`]: the same kernels over structure-of-arrays batches, vectorized
//!   with runtime CPU-feature dispatch, bit-identical to the scalar ones.

pub mod batch;
mod compensated;
mod dispatch;
mod double_double;
mod dyop;
mod feature;
pub mod lanes;
mod point_segment;
mod point_triangle;
mod refine;
mod segment_segment;
mod separated;
mod triangle_intersection;
mod triangle_triangle;

pub use compensated::difference_of_products;
pub use dispatch::SimdLevel;
pub use double_double::{height_over_plane, vector_difference, DoubleDouble};
pub use dyop::{dynamic_origin_point, dyop_distance};
pub use feature::Feature;
pub use point_segment::{
    heron_height, point_segment_distance, point_segment_distance_with, stable_heron_height, PointEdgeFormula,
};
pub use point_triangle::{point_face_interior, point_triangle, FacePlane, PointTriangle};
pub use refine::{REFINE_BELOW_EXTENT, REFINE_TIE_BAND_ULPS};
pub use segment_segment::{segment_segment, segment_segment_lanes, Edge, SegmentSegment};
pub use triangle_intersection::triangles_intersect;
pub use triangle_triangle::{triangle_distance, triangle_distance_with, TriangleDistance};

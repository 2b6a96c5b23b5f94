//! The distance kernels: triangle–triangle, point–segment (every formula),
//! the seed's DyOP and the batched SIMD versions, against the exact rational
//! reference, parry and each other, at every scale the docs promise.

#[path = "../support/bounds.rs"]
mod bounds;

mod batch_matches_scalar;
mod dyop_kernel;
mod mesh_overlap;
mod point_segment_vs_exact;
mod scale_invariance;
mod triangle_distance_vs_exact;
mod triangle_distance_vs_parry;
mod triangle_overlap_vs_exact;

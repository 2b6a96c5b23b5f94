//! Triangle-mesh assets: validated vertices and triangles, built once and
//! shared by every body that uses them, each with its bounding volume
//! hierarchy ([`MeshBvh`]) and, for closed meshes, its mass properties.
//!
//! A mesh is a surface (a triangle soup): two meshes are in contact when
//! their surfaces touch. A mesh entirely inside another does not touch it.
//! Past contact, [`mesh_intersection`] gives where two surfaces cross, and
//! [`convex_penetration`] how deep two convex meshes overlap as solids (a
//! mesh inside another overlaps it there).

mod bvh;
mod convex_features;
pub(crate) mod distance;
mod files;
mod gltf;
mod intersection;
mod local_depth;
mod mass;
mod obj;
mod penetration;
mod ply;
mod point_query;
mod primitives;
mod signed_distance;
mod stl;
mod support;
mod trimesh;

pub use bvh::{BvhNode, MeshBvh};

pub(crate) use bvh::BVH_LEAF_SIZE;
#[cfg(test)]
pub(crate) use bvh::PRINCIPAL_BOX_GAIN;
#[cfg(test)]
pub(crate) use convex_features::FLAT_EDGE_TOLERANCE;
pub use distance::{
    mesh_distance, mesh_distance_brute_force, mesh_distance_relative, DistanceKernel, DistanceSearch,
    MeshDistance, MeshDistanceScratch,
};
pub(crate) use distance::{triangle_pair_distance, walk_to_closer_pair};
pub use files::{load_mesh, read_mesh, weld, MeshFileError, MeshFormat};
pub use intersection::{
    mesh_intersection, mesh_intersection_brute_force, CrossingPair, MeshIntersection, MeshIntersectionScratch,
};
pub use local_depth::{local_depths, LocalDepth, Side};
pub use mass::MassProperties;
pub use obj::{load_obj, parse_obj, ObjError};
#[cfg(test)]
pub(crate) use penetration::PARALLEL_EDGE_SINE;
pub use penetration::{convex_penetration, MeshPenetration, NotConvex};
#[cfg(feature = "rapier")]
pub(crate) use penetration::{convex_penetration_with, PenetrationScratch};
pub use point_query::{point_signed_distance, PointQueryScratch, PointSignedDistance};
pub use primitives::{
    box_mesh, icosphere, needle, single_triangle, tetrahedron, torus, MAX_ICOSPHERE_SUBDIVISIONS,
};
pub(crate) use signed_distance::overlap_beyond;
pub use signed_distance::{overlap_of, signed_distance, Overlap, SignedDistance, SignedDistanceScratch};
pub use trimesh::{MeshError, TriMesh, MAX_COORDINATE};

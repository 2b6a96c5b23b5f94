//! Between nearmiss's triangle meshes and rapier's collider shapes: the
//! mesh the guard sweeps for a rapier body, and the collider rapier sees
//! for a scene's mesh.

use rapier3d_f64::prelude::{Collider, ColliderBuilder, ColliderSet, RigidBody};

use super::GuardError;
use crate::math::{from_parry, to_parry, Point, Real, Vector};
use crate::mesh::TriMesh;

/// The shape rapier is given for a nearmiss mesh.
#[derive(Copy, Clone, Debug, PartialEq, Eq)]
pub enum ColliderShape {
    /// The convex hull of the mesh's vertices: the mesh is convex (boxes,
    /// icospheres, tetrahedra, a convex OBJ), so this is the same solid.
    ConvexHull,
    /// The triangle mesh itself (a non-convex or open mesh).
    TriMesh,
}

impl ColliderShape {
    /// Its name in reports.
    pub fn name(self) -> &'static str {
        match self {
            ColliderShape::ConvexHull => "convex hull",
            ColliderShape::TriMesh => "triangle mesh",
        }
    }
}

/// How far a vertex may lie outside a face's plane, relative to the mesh's
/// radius, for the mesh to count as convex: rounding of the vertices, not
/// shape.
pub const CONVEXITY_TOLERANCE: Real = 1e-9;

/// Whether a closed mesh is convex: every vertex on the same side of every
/// face's plane (within [`CONVEXITY_TOLERANCE`] of the radius;
/// [`TriMesh::convex_within`]). An open mesh (a plate of triangles, a single
/// triangle) is not a solid: `false`.
pub fn is_convex(mesh: &TriMesh) -> bool {
    mesh.convex_within(CONVEXITY_TOLERANCE)
}

/// The collider rapier is given for `mesh` (vertices in the body frame):
/// its convex hull where the mesh is convex (unless `triangle_mesh`),
/// otherwise the triangle mesh.
pub fn collider_for(
    mesh: &TriMesh,
    triangle_mesh: bool,
) -> Result<(ColliderBuilder, ColliderShape), GuardError> {
    let points: Vec<_> = mesh.vertices().iter().map(to_parry).collect();
    if !triangle_mesh && is_convex(mesh) {
        if let Some(hull) = ColliderBuilder::convex_hull(&points) {
            return Ok((hull, ColliderShape::ConvexHull));
        }
    }
    ColliderBuilder::trimesh(points, mesh.triangles().to_vec())
        .map(|builder| (builder, ColliderShape::TriMesh))
        .map_err(|error| GuardError::Shape { body: String::new(), message: error.to_string() })
}

/// The triangles of one collider in its body's frame, appended to
/// `vertices` and `triangles`, or why it has none.
fn append_collider(
    collider: &Collider,
    vertices: &mut Vec<Point>,
    triangles: &mut Vec<[u32; 3]>,
) -> Result<(), String> {
    let shape = collider.shape();
    let (points, indices) = if let Some(mesh) = shape.as_trimesh() {
        (mesh.vertices().to_vec(), mesh.indices().to_vec())
    } else if let Some(polyhedron) = shape.as_convex_polyhedron() {
        polyhedron.to_trimesh()
    } else if let Some(cuboid) = shape.as_cuboid() {
        cuboid.to_trimesh()
    } else {
        return Err(format!(
            "a collider's shape ({:?}) is not a mesh: the guard sweeps triangle meshes, convex polyhedra and cuboids",
            shape.shape_type()
        ));
    };
    let frame = collider.position_wrt_parent().copied().unwrap_or_default();
    let first = u32::try_from(vertices.len()).map_err(|_| "too many vertices".to_string())?;
    vertices.extend(points.into_iter().map(|p| from_parry(frame.transform_point(p))));
    triangles.extend(indices.into_iter().map(|t| t.map(|i| i + first)));
    Ok(())
}

/// The mesh the guard sweeps for `body`: the triangles of all its
/// colliders, relative to its centre of mass (returned too, body frame).
pub fn mesh_of_body(
    body: &RigidBody,
    colliders: &ColliderSet,
    name: &str,
) -> Result<(TriMesh, Vector), GuardError> {
    let shape_error = |message: String| GuardError::Shape { body: name.to_string(), message };
    let mut vertices = Vec::new();
    let mut triangles = Vec::new();
    for &handle in body.colliders() {
        let Some(collider) = colliders.get(handle) else { continue };
        append_collider(collider, &mut vertices, &mut triangles).map_err(shape_error)?;
    }
    if triangles.is_empty() {
        return Err(shape_error("the body has no collider".into()));
    }
    let center = from_parry(body.local_center_of_mass()).coords;
    for v in &mut vertices {
        *v -= center;
    }
    let mesh = TriMesh::new(vertices, triangles).map_err(|error| shape_error(error.to_string()))?;
    Ok((mesh, center))
}

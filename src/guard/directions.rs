//! A contact's directions: the closest points', the hulls' axis and the
//! triangles' normals, and the overlap of two posed meshes along one.

use crate::ccd::MeshCcdResult;
use crate::math::{Pose, Real, Vector};
use crate::mesh::{MeshDistance, TriMesh};
use crate::stepper::respond::StepContext;

/// The directions pair `k`'s contact at `time` into the sweep may be along
/// ([`contact_directions`]), each with the meshes' overlap along it ([`overlap_along`]) at the
/// contact and at the sweep's end. Computed once a contact: the overshoot
/// bound, the end check and the guard's normal read them.
pub(crate) struct Directions {
    list: [(Vector, Real, Real); 4],
    len: usize,
}

impl Directions {
    /// The directions of `result`'s contact (none without closest points).
    pub(crate) fn of(step: &StepContext<'_>, k: usize, time: Real, result: &MeshCcdResult) -> Directions {
        let mut directions = Directions { list: [(Vector::zeros(), 0.0, 0.0); 4], len: 0 };
        let Some(closest) = result.closest else { return directions };
        let pair = &step.world.pairs[k];
        let (mesh_a, mesh_b) = (&step.model.bodies[pair.a].mesh, &step.model.bodies[pair.b].mesh);
        let (ma, mb) = (&step.world.motions[pair.a], &step.world.motions[pair.b]);
        let (contact_a, contact_b) = (ma.pose_at(time), mb.pose_at(time));
        let dt = step.model.dt;
        let (end_a, end_b) = (ma.pose_at(dt), mb.pose_at(dt));
        for n in contact_directions(mesh_a, &contact_a, mesh_b, &contact_b, &closest, result.axis) {
            let at_contact = overlap_along(mesh_a, &contact_a, mesh_b, &contact_b, &n);
            let at_end = overlap_along(mesh_a, &end_a, mesh_b, &end_b, &n);
            directions.list[directions.len] = (n, at_contact, at_end);
            directions.len += 1;
        }
        directions
    }

    /// Each direction, its overlap at the contact and at the sweep's end.
    pub(crate) fn iter(&self) -> impl Iterator<Item = &(Vector, Real, Real)> {
        self.list[..self.len].iter()
    }

    /// The contact's normal: the direction the meshes are farthest apart
    /// along at the contact (for two convex meshes, the separating one).
    pub(crate) fn normal(&self) -> Option<Vector> {
        self.iter().min_by(|x, y| x.1.total_cmp(&y.1)).map(|&(n, ..)| n)
    }
}

/// The unit directions (from `a` towards `b`, world frame) a contact of
/// meshes `a` and `b` at these poses (its closest points `closest`) may be
/// along: its closest points' (which say nothing once within rounding of
/// each other), the hulls' separating `axis` of its query if known, and its
/// two triangles' outward normals.
pub(crate) fn contact_directions(
    mesh_a: &TriMesh,
    pose_a: &Pose,
    mesh_b: &TriMesh,
    pose_b: &Pose,
    closest: &MeshDistance,
    axis: Option<Vector>,
) -> impl Iterator<Item = Vector> {
    let face = |mesh: &TriMesh, pose: &Pose, t: usize| {
        let [p, q, r] = mesh.triangle(t);
        pose.rotation * ((q - p).cross(&(r - p)) * mesh.orientation())
    };
    [
        closest.point_b - closest.point_a,
        axis.unwrap_or_else(Vector::zeros),
        face(mesh_a, pose_a, closest.triangle_a),
        -face(mesh_b, pose_b, closest.triangle_b),
    ]
    .into_iter()
    .filter_map(|n| n.try_normalize(0.0))
}

/// How far convex meshes `a` and `b` overlap along the unit direction `u`
/// (from `a` towards `b`): `a`'s reach along `u` past `b`'s reach against
/// it. At least the depth of their overlap; negative when apart along `u`.
pub(crate) fn overlap_along(a: &TriMesh, pose_a: &Pose, b: &TriMesh, pose_b: &Pose, u: &Vector) -> Real {
    let reach = |mesh: &TriMesh, pose: &Pose, u: &Vector| {
        let local = pose.rotation.inverse_transform_vector(u);
        let vertex = mesh.vertices()[mesh.farthest_vertex(&local)];
        u.dot(&(pose * vertex).coords)
    };
    reach(a, pose_a, u) + reach(b, pose_b, &-u)
}

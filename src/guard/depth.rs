//! The guard's depth watch: how deep rapier's contacts let touching pairs
//! overlap at a step's end.
//!
//! A pair overlapping is rapier's: its soft contact holds it within
//! rapier's allowed error, and the guard's sweep leaves it be (it cannot
//! sweep a pair already inside another). The watch checks that rapier held
//! it: after each step, every touching pair whose overlap could exceed the
//! tolerated depth is measured, and one found deeper is handed back to the
//! guard, which pushes its dynamic bodies apart (rapier's contact failed to
//! hold it: a body squeezed by a kinematic one, a pile under a load rapier's
//! solver cannot carry).
//!
//! - **Two convex meshes**: the overlap along any direction (two support
//!   lookups) bounds the depth. The pair keeps its *side*: the direction
//!   from `a` towards `b` it came into contact along (of the contact's
//!   directions, the one the meshes were farthest apart along), then its
//!   last direction of penetration. Within the tolerated depth along it, the pair is fine.
//!   Otherwise the exact depth is measured ([`convex_penetration_with`]:
//!   separating axes): if the shortest way out points to the pair's side,
//!   it is the depth (and the new side); if it points the other way, one
//!   body went through the other within the step (a blade's turn past a
//!   ball), and the depth is the overlap along its side, which it is
//!   pushed back out along. A box resting or sliding on a floor costs two
//!   support lookups a step. (A side is trusted across a turn of under a
//!   quarter turn between measures.)
//! - **Other meshes**: a bound of how far the pair can have closed since it
//!   was last measured (the relative speed of any point, as in the guard's
//!   arrival test, over each step) grows step by step; once it exceeds the
//!   tolerated depth the pair is measured ([`local_depths`] of the curve
//!   where the surfaces cross: the deepest vertex) and the bound starts
//!   again from that depth. A resting pair is measured rarely, a sliding one
//!   every step. The measure is the deepest vertex (a point at least that
//!   deep exists): between vertices of coarse triangles the true depth may
//!   be a little larger.

use std::collections::HashMap;

use super::directions::{contact_directions, overlap_along};
use crate::math::{Point, Pose, Real, Vector};
use crate::mesh::{
    convex_penetration_with, local_depths, mesh_intersection, MeshIntersection, MeshIntersectionScratch,
    PenetrationScratch, Side, TriMesh,
};
use crate::scene::Model;
use crate::stepper::{Contact, World};

/// A touching pair found deeper than the tolerated depth at a step's end.
#[derive(Copy, Clone, Debug, PartialEq)]
pub(crate) struct Deep {
    /// The pair's bodies (guard indices).
    pub a: usize,
    pub b: usize,
    /// How deep it overlaps.
    pub depth: Real,
    /// The unit direction that moves `b` out of `a` (world frame).
    pub direction: Vector,
    /// Where the two meet (world frame): the push's point.
    pub point: Point,
}

/// What the watch keeps of a touching pair between steps.
#[derive(Copy, Clone, Debug, Default)]
struct PairDepth {
    /// Convex pairs: the pair's side, the direction from `a` towards `b`
    /// it touched along or last overlapped along (world frame).
    axis: Option<Vector>,
    /// Other pairs: a bound of the depth at the step's end.
    bound: Real,
}

/// The depth watch's memory and scratch (see the module).
#[derive(Default)]
pub(crate) struct DepthWatch {
    pairs: HashMap<(usize, usize), PairDepth>,
    penetration: PenetrationScratch,
    crossing: MeshIntersection,
    intersection: MeshIntersectionScratch,
}

impl DepthWatch {
    /// The touching pairs of `world` (those `solved` keeps) deeper than
    /// their `tolerated` depth at the end of the step just swept, into
    /// `deep`. `new`: the contacts the step found (their sides are kept).
    pub fn measure(
        &mut self,
        model: &Model,
        world: &World,
        new: &[Contact],
        tolerated: &dyn Fn(usize, usize) -> Real,
        solved: &dyn Fn(usize, usize) -> bool,
        deep: &mut Vec<Deep>,
    ) {
        let dt = model.dt;
        for contact in new {
            let (mesh_a, mesh_b) = (&model.bodies[contact.body_a].mesh, &model.bodies[contact.body_b].mesh);
            if let Some(side) = contact_side(contact, mesh_a, mesh_b) {
                self.pairs.entry((contact.body_a, contact.body_b)).or_default().axis = Some(side);
            }
        }
        // Pairs no longer touching are forgotten.
        self.pairs.retain(|&(a, b), _| {
            world
                .pairs
                .binary_search_by_key(&(a, b), |p| (p.a, p.b))
                .is_ok_and(|k| world.pairs[k].touching.is_some())
        });
        for pair in world.pairs.iter().filter(|p| p.touching.is_some() && solved(p.a, p.b)) {
            let (a, b) = (pair.a, pair.b);
            let tolerated = tolerated(a, b);
            let (mesh_a, mesh_b) = (&model.bodies[a].mesh, &model.bodies[b].mesh);
            let (ma, mb) = (&world.motions[a], &world.motions[b]);
            let (pose_a, pose_b) = (ma.pose_at(dt), mb.pose_at(dt));
            let memory = self.pairs.entry((a, b)).or_default();
            let found = if mesh_a.is_convex() && mesh_b.is_convex() {
                let along = |u: &Vector| overlap_along(mesh_a, &pose_a, mesh_b, &pose_b, u);
                let side = memory.axis;
                let fine = match side {
                    Some(u) => along(&u) <= tolerated,
                    // No side yet: any direction within settles it.
                    None => {
                        let centres = pose_b.translation.vector - pose_a.translation.vector;
                        [pair.axis, centres.try_normalize(0.0)]
                            .iter()
                            .flatten()
                            .any(|u| along(u) <= tolerated)
                    }
                };
                if fine {
                    continue;
                }
                match convex_penetration_with(mesh_a, &pose_a, mesh_b, &pose_b, &mut self.penetration) {
                    Ok(Some(found)) => {
                        let point = Point::from((found.point_a.coords + found.point_b.coords) / 2.0);
                        match side {
                            // Through: back along its side.
                            Some(u) if found.direction.dot(&u) <= 0.0 => Some((along(&u), u, point)),
                            _ => {
                                memory.axis = Some(found.direction);
                                Some((found.depth, found.direction, point))
                            }
                        }
                    }
                    _ => None,
                }
            } else {
                // How far any point of one can have gone into the other
                // over the step.
                let speed = (mb.velocity - ma.velocity).norm()
                    + mesh_a.radius() * ma.angular_velocity.norm()
                    + mesh_b.radius() * mb.angular_velocity.norm();
                memory.bound += speed * dt;
                if memory.bound <= tolerated {
                    continue;
                }
                let found = deepest_vertex(
                    mesh_a,
                    &pose_a,
                    mesh_b,
                    &pose_b,
                    &mut self.crossing,
                    &mut self.intersection,
                );
                memory.bound = found.map_or(0.0, |(depth, ..)| depth);
                found
            };
            if let Some((depth, direction, point)) = found.filter(|&(depth, ..)| depth > tolerated) {
                deep.push(Deep { a, b, depth, direction, point });
            }
        }
    }
}

/// The side of a contact of two convex meshes: of the directions it may be
/// along ([`contact_directions`]), the one the meshes are farthest apart
/// along at the contact (from `a` towards `b`).
fn contact_side(contact: &Contact, mesh_a: &TriMesh, mesh_b: &TriMesh) -> Option<Vector> {
    if !(mesh_a.is_convex() && mesh_b.is_convex()) {
        return None;
    }
    let (pose_a, pose_b) = (&contact.pose_a, &contact.pose_b);
    contact_directions(mesh_a, pose_a, mesh_b, pose_b, &contact.closest, None)
        .map(|n| (overlap_along(mesh_a, pose_a, mesh_b, pose_b, &n), n))
        .min_by(|x, y| x.0.total_cmp(&y.0))
        .map(|(_, n)| n)
}

/// The depth of the deepest vertex of either closed mesh inside the other
/// where their surfaces cross, the direction that moves `b` out of `a`
/// (from the vertex to the nearest point of the other surface), and the
/// vertex's nearest point; `None` when the surfaces do not cross or a mesh
/// is not closed.
fn deepest_vertex(
    a: &TriMesh,
    pose_a: &Pose,
    b: &TriMesh,
    pose_b: &Pose,
    crossing: &mut MeshIntersection,
    scratch: &mut MeshIntersectionScratch,
) -> Option<(Real, Vector, Point)> {
    if !(a.is_closed() && b.is_closed()) {
        return None;
    }
    mesh_intersection(a, pose_a, b, pose_b, crossing, scratch);
    if crossing.is_empty() {
        return None;
    }
    let deepest = local_depths(a, pose_a, b, pose_b, crossing).ok()?.into_iter().next()?;
    // The vertex goes to the nearest point of the other surface: a vertex
    // of `b` moves `b` that way, a vertex of `a` moves `b` the other way.
    let out: Vector = deepest.nearest - deepest.deepest;
    let direction = match deepest.side {
        Side::B => out,
        Side::A => -out,
    };
    // A vertex exactly on the other surface has no way out of its own: the
    // line between the centres (or, with the centres together, up).
    let direction = direction.try_normalize(0.0).unwrap_or_else(|| {
        let centres = pose_b.translation.vector - pose_a.translation.vector;
        centres.try_normalize(0.0).unwrap_or_else(Vector::z)
    });
    Some((deepest.lower, direction, deepest.nearest))
}

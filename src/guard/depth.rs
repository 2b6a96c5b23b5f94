//! The guard's depth watch: how deep rapier's contacts let touching pairs
//! overlap at a step's end.
//!
//! A pair in contact is rapier's: its soft contact holds it within rapier's
//! allowed error, and the guard does not sweep it. The watch checks that it
//! did: after each step, every touching pair whose overlap could exceed the
//! tolerated depth is measured, and one found deeper is handed back to the
//! guard, which pushes its dynamic bodies apart (rapier's contact failed to
//! hold it: a body squeezed by a kinematic one, a pile under a load rapier's
//! solver cannot carry).
//!
//! - **Two convex meshes**: the overlap along the pair's last direction of
//!   penetration (two support lookups) bounds the depth; only where that
//!   exceeds the tolerated depth is the exact depth measured
//!   ([`convex_penetration_with`]: separating axes), and its direction kept
//!   for the next step. A box resting or sliding on a floor costs two
//!   support lookups a step.
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

use super::watch::overlap_along;
use crate::math::{Point, Pose, Real, Vector};
use crate::mesh::{
    convex_penetration_with, local_depths, mesh_intersection, MeshIntersection, MeshIntersectionScratch,
    PenetrationScratch, Side, TriMesh,
};
use crate::scene::Model;
use crate::stepper::World;

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
}

/// What the watch keeps of a touching pair between steps.
#[derive(Copy, Clone, Debug, Default)]
struct PairDepth {
    /// Convex pairs: the last direction of penetration (world frame).
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
    /// `deep`.
    pub fn measure(
        &mut self,
        model: &Model,
        world: &World,
        tolerated: &dyn Fn(usize, usize) -> Real,
        solved: &dyn Fn(usize, usize) -> bool,
        deep: &mut Vec<Deep>,
    ) {
        let dt = model.dt;
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
                if let Some(axis) = memory.axis {
                    if overlap_along(mesh_a, &pose_a, mesh_b, &pose_b, &axis) <= tolerated {
                        continue;
                    }
                }
                match convex_penetration_with(mesh_a, &pose_a, mesh_b, &pose_b, &mut self.penetration) {
                    Ok(Some(found)) => {
                        memory.axis = Some(found.direction);
                        Some((found.depth, found.direction))
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
                memory.bound = found.map_or(0.0, |(depth, _)| depth);
                found
            };
            if let Some((depth, direction)) = found.filter(|&(depth, _)| depth > tolerated) {
                deep.push(Deep { a, b, depth, direction });
            }
        }
    }
}

/// The depth of the deepest vertex of either closed mesh inside the other
/// where their surfaces cross, and the direction that moves `b` out of `a`
/// (from the vertex to the nearest point of the other surface); `None`
/// when the surfaces do not cross or a mesh is not closed.
fn deepest_vertex(
    a: &TriMesh,
    pose_a: &Pose,
    b: &TriMesh,
    pose_b: &Pose,
    crossing: &mut MeshIntersection,
    scratch: &mut MeshIntersectionScratch,
) -> Option<(Real, Vector)> {
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
    let direction = direction.try_normalize(0.0).unwrap_or_else(|| {
        let centres: Point = Point::from(pose_b.translation.vector - pose_a.translation.vector);
        centres.coords.try_normalize(0.0).unwrap_or_else(Vector::z)
    });
    Some((deepest.lower, direction))
}

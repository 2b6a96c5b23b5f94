//! Bodies that overlap at time 0: where their surfaces cross and, for
//! convex pairs, how deep their solids overlap.
//!
//! A run starting with bodies overlapping reports a contact at `t = 0`
//! (distance 0) and says nothing of how deep; this says it, and a scene can
//! refuse to start so (`initial_overlap: Refuse`). Pairs of bodies that
//! never move (walls meeting at a corner) are not overlaps of interest and
//! are left out. Candidates are the pairs whose world boxes overlap
//! (through a uniform grid, `GridBroadPhase`); each gets
//! [`mesh_intersection`] and, when both meshes are convex,
//! [`convex_penetration`] (so a convex mesh wholly inside another,
//! surfaces apart, overlaps it too). A non-convex mesh wholly inside
//! another is not detected (its surfaces do not cross).

use super::{Body, BodyMotion};
use crate::broad_phase::{GridBroadPhase, SweptBox};
use crate::math::{Point, Real};
use crate::mesh::{
    convex_penetration, local_depths, mesh_intersection, MeshIntersection, MeshIntersectionScratch,
    MeshPenetration,
};

/// Two bodies that overlap at time 0.
#[derive(Clone, Debug, PartialEq)]
pub struct InitialOverlap {
    /// The first body (index into the scene's bodies).
    pub body_a: usize,
    /// The second body (`body_a < body_b`).
    pub body_b: usize,
    /// The penetration depth of the two solids (both meshes convex);
    /// `None` for pairs with a non-convex mesh.
    pub depth: Option<MeshPenetration>,
    /// For closed meshes that are not both convex: the deepest local depth
    /// at a component of the intersection curve, as `(lower, upper)` (see
    /// [`crate::mesh::local_depths`]); `None` otherwise.
    pub local_depth: Option<(Real, Real)>,
    /// Where the surfaces cross (empty for a convex mesh wholly inside
    /// another).
    pub intersection: MeshIntersection,
}

impl InitialOverlap {
    /// A one-line description for messages: the depth (or the curve where
    /// no depth is known).
    pub fn describe(&self, bodies: &[Body]) -> String {
        let names = format!("\"{}\" and \"{}\"", bodies[self.body_a].name, bodies[self.body_b].name);
        let curve = if self.intersection.is_empty() {
            "one inside the other, surfaces apart".to_string()
        } else {
            format!(
                "surfaces crossing at {} triangle pair{}, along a curve {} long",
                self.intersection.pairs.len(),
                if self.intersection.pairs.len() == 1 { "" } else { "s" },
                short(self.intersection.length())
            )
        };
        match (&self.depth, self.local_depth) {
            (Some(depth), _) => format!(
                "{names} overlap by {} (the shortest move that separates them: \"{}\" by {} along ({}, {}, {})); {curve}",
                short(depth.depth),
                bodies[self.body_b].name,
                short(depth.depth),
                short(depth.direction.x),
                short(depth.direction.y),
                short(depth.direction.z)
            ),
            (None, Some((lower, upper))) => format!(
                "{names} overlap by at least {} and at most {} (the deepest place where their surfaces cross, a local depth: a mesh is not convex); {curve}",
                short(lower),
                short(upper)
            ),
            (None, None) => format!("{names} overlap (no depth: a mesh is not closed); {curve}"),
        }
    }
}

/// Every pair of bodies overlapping at time 0 (at least one of the two
/// moves), in order of `(body_a, body_b)`.
pub fn initial_overlaps(bodies: &[Body]) -> Vec<InitialOverlap> {
    let boxes: Vec<SweptBox> = bodies.iter().map(world_box).collect();
    let mut candidates = Vec::new();
    GridBroadPhase::default().pairs_into(&boxes, &mut candidates);
    let fixed = |i: usize| matches!(bodies[i].motion, BodyMotion::Fixed);
    candidates.retain(|&(i, j)| !(fixed(i) && fixed(j)));
    let mut scratch = MeshIntersectionScratch::default();
    candidates
        .into_iter()
        .filter_map(|(i, j)| {
            let (a, b) = (&bodies[i], &bodies[j]);
            let mut intersection = MeshIntersection::default();
            mesh_intersection(&a.mesh, &a.pose, &b.mesh, &b.pose, &mut intersection, &mut scratch);
            let depth = convex_penetration(&a.mesh, &a.pose, &b.mesh, &b.pose).ok().flatten();
            // Touching only (depth 0, or surfaces meeting without a
            // crossing curve) is contact, not overlap.
            let deep = depth.is_some_and(|d| d.depth > 0.0);
            let crossing = depth.is_none() && intersection.length() > 0.0;
            let local_depth = if crossing {
                local_depths(&a.mesh, &a.pose, &b.mesh, &b.pose, &intersection)
                    .ok()
                    .and_then(|depths| depths.first().map(|d| (d.lower, d.upper)))
            } else {
                None
            };
            (deep || crossing).then_some(InitialOverlap {
                body_a: i,
                body_b: j,
                depth,
                local_depth,
                intersection,
            })
        })
        .collect()
}

/// A body's box in the world at time 0: its mesh's box, turned.
fn world_box(body: &Body) -> (Point, Point) {
    let (low, high) = body.mesh.bounds();
    let center = body.pose * nalgebra::center(&low, &high);
    let half = (high - low) / 2.0;
    let turned = body.pose.rotation.to_rotation_matrix().into_inner().abs() * half;
    (center - turned, center + turned)
}

/// A number in at most 6 significant digits, as messages write them.
fn short(x: Real) -> String {
    if x == 0.0 {
        return "0".into();
    }
    let rounded: Real = format!("{x:.5e}").parse().unwrap_or(x);
    let plain = format!("{rounded}");
    if plain.len() <= 12 {
        plain
    } else {
        format!("{rounded:e}")
    }
}

//! Stage 5, re-arm: a pair in contact is not reported again until it
//! separates; at the step's end, a touching pair farther apart than
//! [`StepParameters::rearm_distance_factor`](crate::scene::StepParameters) times
//! its contact distance is armed again.

use std::sync::Arc;
use std::time::Instant;

use super::world::{Touching, World};
use super::Stepper;
use crate::ccd::hull_gap_from;
use crate::math::Real;
use crate::mesh::{mesh_distance_relative, DistanceSearch};
use crate::motion::StepMotion;

impl Stepper {
    /// Re-arms the touching pairs that separated by the step's end.
    pub(super) fn rearm(&mut self, world: &mut World) {
        let clock = Instant::now();
        let model = Arc::clone(&self.model);
        let model = &*model;
        for pair in &mut world.pairs {
            let Some(Touching { contact_distance, .. }) = pair.touching else { continue };
            let pos_ab = StepMotion::relative_pose(&world.motions[pair.a], &world.motions[pair.b], model.dt);
            let (mesh_a, mesh_b) = (&model.bodies[pair.a].mesh, &model.bodies[pair.b].mesh);
            let rearm_distance =
                self.response.rearm_distance(contact_distance, self.model.parameters.rearm_distance_factor);
            // The hulls' gap first (GJK from the pair's last simplex, or its
            // last axis turned into a's frame at the step's end): a pair
            // whose hulls are beyond the re-arm distance is separated
            // without a search, its bound carried.
            let rotation_a = world.motions[pair.a].rotation_at(model.dt);
            let gap = hull_gap_from(
                mesh_a,
                mesh_b,
                &pos_ab,
                pair.axis.map(|axis| rotation_a.inverse_transform_vector(&axis)),
                (rearm_distance, Real::INFINITY),
                &mut pair.simplex,
            );
            if gap.lower > rearm_distance {
                pair.touching = None;
                world.separated.push((pair.a, pair.b));
                pair.lower_bound = Some(gap.lower);
                continue;
            }
            // Only "beyond the re-arm distance?" is asked: the search may
            // stop at the first pair within it.
            let search = DistanceSearch { kernel: model.kernel, hint: pair.hint, enough: rearm_distance };
            let d = mesh_distance_relative(mesh_a, mesh_b, &pos_ab, &search, &mut self.scratch.ccd.distance);
            self.counters.work.distance_queries += 1;
            if d.distance > rearm_distance {
                pair.touching = None;
                world.separated.push((pair.a, pair.b));
                pair.lower_bound = Some(d.distance);
            }
        }
        self.counters.seconds.rearm += clock.elapsed().as_secs_f64();
    }
}

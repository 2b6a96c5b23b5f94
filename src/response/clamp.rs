//! The guard's clamp (`on_contact: Simulate`, and [`crate::guard`] for
//! rapier applications): an outside engine (rapier) moved the bodies over
//! the step; a pair that would come into contact within it is recorded
//! once, and each of its bodies that the engine can stop (dynamic bodies)
//! is held at its pose at the contact for the rest of the step, the other
//! pairs of a held body checked again (`stop.rs`). Velocities are the
//! engine's: the guard only moves poses back.
//!
//! Pairs in contact are not queried (the engine's contact solver holds
//! them); such a pair is armed again once its distance at a step's end
//! exceeds the larger of the stepper's re-arm distance and the engine's
//! contact distance (`separation`: rapier's prediction distance, within
//! which rapier treats the pair as in contact).

use super::stop::{hold_stopped_bodies, stop_in_time_order, Stops};
use super::{Response, StepContext};
use crate::ccd::ContactRule;
use crate::math::Real;
use crate::stepper::Found;

/// The clamp, with what the engine can stop.
pub(crate) struct Clamp {
    /// Per body: whether contacts stop it (dynamic bodies; fixed and
    /// kinematic ones keep the motion the engine gave them).
    pub stoppable: Vec<bool>,
    /// The distance within which the engine holds a pair in contact.
    pub separation: Real,
}

impl Response for Clamp {
    fn rearm_distance(&self, contact_distance: Real, factor: Real) -> Real {
        (factor * contact_distance).max(self.separation)
    }

    fn respond(&self, step: &mut StepContext<'_>, found: &mut Vec<Found>) -> bool {
        let can_stop = |i: usize| self.stoppable[i];
        let Stops { committed, stopped } =
            stop_in_time_order(step, found, &|_| ContactRule::ScaleRelative, &can_stop);
        for (body, at) in stopped.iter().enumerate() {
            if let Some(at) = *at {
                step.world.held.push((body, at));
            }
        }
        hold_stopped_bodies(step, &stopped);
        !committed.is_empty()
    }
}

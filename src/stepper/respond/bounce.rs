//! `on_contact: Bounce(restitution: e)`: bodies bounce off each other and
//! off fixed walls.
//!
//! The step's contacts are taken in time order. A contact is committed only
//! if neither body has stopped before it; both bodies then stop there for
//! the rest of the step, and every other pair of theirs is queried again
//! from that time with the stopped body held still (its earlier candidates
//! become stale), so no body moves past a contact with a body that stopped.
//! At the end, the committed contacts' impulses ([`super::apply_impulse`])
//! are applied in time order and each body's state moves to where it
//! stopped (or to the step's end).
//!
//! A pair that bounced stays "touching" until it separates; meanwhile it is
//! queried for coming within
//! [`bounce_redetect_fraction`](crate::scene::StepParameters) of its
//! distance at the bounce (an absolute contact distance,
//! [`ContactRule::Absolute`]), which is a new contact of the same episode.
//! The episode keeps its largest contact distance: a pair pressed together
//! (a body lying on another under gravity) bounces at every step at the
//! same re-detection distance, instead of halving it at each bounce down to
//! the rounding floor, where conservative advancement would crawl.

use super::stop::{hold_stopped_bodies, stop_in_time_order};
use super::{apply_impulse, approach_speed, contact_frame, Response, StepContext};
use crate::ccd::{ContactRule, MeshCcdResult};
use crate::math::Real;
use crate::scene::BodyMotion;
use crate::stepper::{Found, PairState};

/// The bounce response with its coefficient of restitution.
pub(crate) struct Bounce {
    pub restitution: Real,
    /// The stepper's re-detection fraction (copied at construction).
    pub redetect_fraction: Real,
}

impl Response for Bounce {
    fn sweeps(&self, _pair: &PairState) -> bool {
        true
    }

    fn contact_rule(&self, pair: &PairState) -> ContactRule {
        match pair.touching {
            // Moving apart: coming closer again is a new contact.
            Some(touching) => ContactRule::Absolute(self.redetect_fraction * touching.distance),
            None => ContactRule::ScaleRelative,
        }
    }

    fn stops_kinematic_bodies(&self) -> bool {
        true
    }

    fn exchanges_momentum(&self) -> bool {
        true
    }

    fn respond(&self, step: &mut StepContext<'_>, found: &mut Vec<Found>) -> bool {
        found.retain(|Found { pair: k, result }| {
            // A pair that bounced and is moving apart, still within the
            // tolerance floor of that contact at the step's start: not a
            // new contact (taking it would hold both bodies still at every
            // step). Approaching, it bounces again.
            let moving_apart = result.time_of_impact == Some(0.0)
                && step.world.pairs[*k].touching.is_some()
                && !approaching(step, *k, result);
            !moving_apart
        });
        let model = step.model;
        // Kinematic bodies stop too (for the rest of the step); fixed ones never move.
        let can_stop = |i: usize| model.bodies[i].motion != BodyMotion::Fixed;
        // The stepper's buffers, lent for the step (taking them allocates nothing).
        let mut stops = std::mem::take(&mut *step.stops);
        stop_in_time_order(step, found, &|pair| self.contact_rule(pair), &can_stop, &mut stops);
        self.apply_impulses(step, &stops.committed, &stops.stopped);
        hold_stopped_bodies(step, &mut stops);
        let any = !stops.committed.is_empty();
        *step.stops = stops;
        any
    }
}

impl Bounce {
    /// The committed contacts' impulses in time order, at the bodies' poses
    /// at contact; the pushed bodies' states take the new velocities.
    fn apply_impulses(&self, step: &mut StepContext<'_>, committed: &[usize], stopped: &[Option<Real>]) {
        let (model, world) = (step.model, &mut *step.world);
        for &c in committed {
            let contact = world.contacts[c].clone();
            let time = contact.time - step.t0;
            let (a, b) = (contact.body_a, contact.body_b);
            let mut sides = [a, b].map(|i| world.impact_body(model, i, stopped[i].unwrap_or(time).min(time)));
            let (point, normal) =
                contact_frame(&contact.closest.point_a, &contact.closest.point_b, &sides[0], &sides[1]);
            let [side_a, side_b] = &mut sides;
            apply_impulse(side_a, side_b, &point, &normal, self.restitution);
            for (i, side) in [(a, sides[0]), (b, sides[1])] {
                if let Some(state) = world.states[i].as_mut() {
                    if side.inverse_mass > 0.0 {
                        state.velocity = side.velocity;
                        state.angular_velocity = side.angular_velocity;
                    }
                }
            }
        }
    }
}

/// Whether the closest points of pair `k`'s contact at the step's start
/// approach each other.
fn approaching(step: &StepContext<'_>, k: usize, contact: &MeshCcdResult) -> bool {
    let Some(closest) = contact.closest else { return true };
    let pair = &step.world.pairs[k];
    let a = step.world.impact_body(step.model, pair.a, 0.0);
    let b = step.world.impact_body(step.model, pair.b, 0.0);
    let (point, normal) = contact_frame(&closest.point_a, &closest.point_b, &a, &b);
    approach_speed(&a, &b, &point, &normal) < 0.0
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::stepper::Touching;

    #[test]
    fn a_bounced_pair_is_redetected_at_an_absolute_fraction_of_its_distance() {
        let bounce = Bounce { restitution: 1.0, redetect_fraction: 0.5 };
        let mut pair = PairState::new(0, 1);
        assert_eq!(bounce.contact_rule(&pair), ContactRule::ScaleRelative);
        pair.touching = Some(Touching { contact_distance: 4e-6, distance: 3e-6 });
        assert_eq!(bounce.contact_rule(&pair), ContactRule::Absolute(1.5e-6));
    }
}

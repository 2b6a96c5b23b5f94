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
//! [`bounce_redetect_fraction`](crate::stepper::StepParameters) of its
//! distance at the bounce (an absolute contact distance,
//! [`ContactRule::Absolute`]), which is a new contact.

use std::cmp::Ordering;
use std::collections::{BinaryHeap, HashMap};

use super::{apply_impulse, approach_speed, contact_frame, Response, StepContext};
use crate::ccd::{mesh_time_of_impact, CcdStatus, ContactRule, MeshCcdResult};
use crate::math::{Point, Real};
use crate::motion::StepMotion;
use crate::scene::BodyMotion;
use crate::stepper::{pair_query, Found, PairState};

/// The bounce response with its coefficient of restitution.
pub(crate) struct Bounce {
    pub restitution: Real,
    /// The stepper's re-detection fraction (copied at construction).
    pub redetect_fraction: Real,
}

/// A candidate contact within a step.
#[derive(Copy, Clone, Debug)]
struct Candidate {
    /// Time into the step.
    time: Real,
    /// The pair (index into `world.pairs`).
    pair: usize,
    /// The pair's recheck count when found (stale once it changed).
    version: u32,
}

impl PartialEq for Candidate {
    fn eq(&self, other: &Self) -> bool {
        self.cmp(other) == Ordering::Equal
    }
}
impl Eq for Candidate {}
impl PartialOrd for Candidate {
    fn partial_cmp(&self, other: &Self) -> Option<Ordering> {
        Some(self.cmp(other))
    }
}
impl Ord for Candidate {
    /// Reversed (the heap's top is the earliest; ties: the lower pair).
    fn cmp(&self, other: &Self) -> Ordering {
        other.time.total_cmp(&self.time).then(other.pair.cmp(&self.pair))
    }
}

impl Response for Bounce {
    fn queries_touching_pairs(&self) -> bool {
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
        let mut candidates = BinaryHeap::new();
        let mut results = HashMap::new();
        for Found { pair: k, result } in found.drain(..) {
            let Some(time) = result.time_of_impact else { continue };
            if time == 0.0 && step.world.pairs[k].touching.is_some() && !approaching(step, k, &result) {
                // A pair that bounced and is moving apart, still within the
                // tolerance floor of that contact at the step's start: not a
                // new contact (taking it would hold both bodies still at
                // every step). Approaching, it bounces again.
                continue;
            }
            candidates.push(Candidate { time, pair: k, version: 0 });
            results.insert(k, result);
        }
        let (committed, stopped) = self.commit_in_time_order(step, candidates, results);
        self.apply_impulses(step, &committed, &stopped);
        move_to_step_end(step, &stopped);
        !committed.is_empty()
    }
}

impl Bounce {
    /// Takes the candidates in time order (see the module). Returns the
    /// committed contacts (indices into `world.contacts`) and when each body
    /// stopped (time into the step).
    fn commit_in_time_order(
        &self,
        step: &mut StepContext<'_>,
        mut candidates: BinaryHeap<Candidate>,
        mut results: HashMap<usize, MeshCcdResult>,
    ) -> (Vec<usize>, Vec<Option<Real>>) {
        let scene = step.scene;
        let dt = scene.dt;
        let fixed = |i: usize| scene.bodies[i].motion == BodyMotion::Fixed;
        let mut stopped: Vec<Option<Real>> = vec![None; scene.bodies.len()];
        let mut versions = vec![0u32; step.world.pairs.len()];
        let mut committed = Vec::new();
        while let Some(candidate) = candidates.pop() {
            let k = candidate.pair;
            if candidate.version != versions[k] {
                continue;
            }
            let Some(result) = results.remove(&k) else { continue };
            let time = candidate.time;
            step.world.record_contact(k, step.t0, time, &result);
            committed.push(step.world.contacts.len() - 1);
            let (a, b) = (step.world.pairs[k].a, step.world.pairs[k].b);
            for body in [a, b] {
                if fixed(body) || stopped[body].is_some() {
                    continue;
                }
                stopped[body] = Some(time);
                // Every other pair of this body: again from `time`.
                let partners: Vec<usize> = (step.world.pairs.iter().enumerate())
                    .filter(|&(other, pair)| other != k && (pair.a == body || pair.b == body))
                    .map(|(other, _)| other)
                    .collect();
                for other in partners {
                    let pair = step.world.pairs[other].clone();
                    versions[other] += 1;
                    results.remove(&other);
                    step.world.pairs[other].lower_bound = None;
                    if stopped[pair.a].is_some() && stopped[pair.b].is_some() {
                        continue;
                    }
                    let motions = &step.world.motions;
                    let held = |i: usize| match stopped[i] {
                        Some(at) => StepMotion::fixed(motions[i].pose_at(at)),
                        None => StepMotion { elapsed: motions[i].elapsed + time, ..motions[i] },
                    };
                    let (ma, mb) = (held(pair.a), held(pair.b));
                    let query = pair_query(scene, &pair, [&ma, &mb], dt - time, self.contact_rule(&pair));
                    let warm = crate::ccd::WarmStart { lower_bound: None, hint: pair.hint };
                    let result = mesh_time_of_impact(&query, warm, step.scratch);
                    step.counters.distance_queries += result.iterations;
                    step.counters.triangle_pairs += result.triangle_pairs;
                    if result.status == CcdStatus::OutOfIterations {
                        let undecided = MeshCcdResult {
                            time_of_impact: result.time_of_impact.map(|t| time + t),
                            ..result
                        };
                        step.world.note_undecided(other, &undecided);
                    } else if let Some(after) = result.time_of_impact {
                        candidates.push(Candidate {
                            time: time + after,
                            pair: other,
                            version: versions[other],
                        });
                        results.insert(other, result);
                    }
                }
            }
        }
        (committed, stopped)
    }

    /// The committed contacts' impulses in time order, at the bodies' poses
    /// at contact; the pushed bodies' states take the new velocities.
    fn apply_impulses(&self, step: &mut StepContext<'_>, committed: &[usize], stopped: &[Option<Real>]) {
        let (scene, world) = (step.scene, &mut *step.world);
        for &c in committed {
            let contact = world.contacts[c].clone();
            let time = contact.time - step.t0;
            let (a, b) = (contact.body_a, contact.body_b);
            let mut sides = [a, b].map(|i| world.impact_body(scene, i, stopped[i].unwrap_or(time).min(time)));
            let (point, normal) = contact_frame(&contact.point_a, &contact.point_b, &sides[0], &sides[1]);
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

/// Stopped bodies stay where they stopped; kinematic bodies that did not
/// stop reach the step's end.
fn move_to_step_end(step: &mut StepContext<'_>, stopped: &[Option<Real>]) {
    let (scene, world) = (step.scene, &mut *step.world);
    for (i, at) in stopped.iter().enumerate() {
        let Some(at) = *at else { continue };
        let pose = world.motions[i].pose_at(at);
        if let Some(state) = world.states[i].as_mut() {
            state.position = Point::from(pose.translation.vector);
            state.orientation = pose.rotation;
        }
        world.motions[i] = StepMotion::fixed(pose);
    }
    for (i, body) in scene.bodies.iter().enumerate() {
        if body.motion == BodyMotion::Free && stopped[i].is_none() {
            if let Some(state) = world.states[i].as_mut() {
                let pose = world.motions[i].pose_at(scene.dt);
                state.position = Point::from(pose.translation.vector);
                state.orientation = pose.rotation;
            }
        }
    }
}

/// Whether the closest points of pair `k`'s contact at the step's start
/// approach each other.
fn approaching(step: &StepContext<'_>, k: usize, contact: &MeshCcdResult) -> bool {
    let Some(closest) = contact.closest else { return true };
    let pair = &step.world.pairs[k];
    let a = step.world.impact_body(step.scene, pair.a, 0.0);
    let b = step.world.impact_body(step.scene, pair.b, 0.0);
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

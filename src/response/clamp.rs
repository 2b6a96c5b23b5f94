//! The guard's response (`on_contact: Simulate`, and [`crate::guard`] for
//! rapier applications): an outside engine (rapier) moved the bodies over
//! the step (or the rest of it); this response decides what the guard does
//! about the contacts the sweep found.
//!
//! Two levels, one per pair state (see [`crate::guard`] for the design):
//! - a pair **apart** is swept for coming within the contact skin
//!   (`skin_separation`, the colliders' two skins above the scene's
//!   `minimum_separation`): that is where rapier's contact starts, and it is
//!   reported (recorded once, the pair then "touching");
//! - a pair **touching** is swept against the wall: the scene's own contact
//!   contract, the meshes themselves (not their skins). rapier holds such a
//!   pair inside the skin; reaching the wall means rapier let it through.
//!
//! When rewinds are allowed (`World::may_rewind`), the earliest contact that
//! needs the guard (a pair reaching the wall, or a pair coming within the
//! skin that would reach the wall later in the step) sets `World::rewind`:
//! the guard moves the world back to that time and lets rapier solve from
//! there. Contacts after it are dropped (the rest of the step is stepped
//! again). When the guard's substeps are spent, such contacts are clamped
//! instead: their stoppable (dynamic) bodies are held at their poses at the
//! contact for the rest of the step (`stop.rs`), velocities left to rapier.
//!
//! A touching pair is armed again once its distance at a step's end exceeds
//! the larger of the stepper's re-arm distance and `separation` (the skins
//! and rapier's prediction distance, within which rapier treats the pair as
//! in contact).

use super::stop::{hold_stopped_bodies, stop_in_time_order, Stops};
use super::{approach_speed, contact_frame, Response, StepContext};
use crate::ccd::{mesh_time_of_impact, CcdStatus, ContactRule, MeshCcdResult, WarmStart};
use crate::math::Real;
use crate::motion::StepMotion;
use crate::stepper::{pair_query, Found, PairState, Rewind};

/// A pair at the wall at a sweep's start and moving apart is a hit again
/// only once it comes within this fraction of its distance there (the
/// `Bounce` response's re-detection, for the guard). `0.5`.
pub(crate) const WALL_REDETECT_FRACTION: Real = 0.5;

/// The guard's response, with what the engine can stop.
pub(crate) struct Clamp {
    /// Per body: whether contacts stop it (dynamic bodies; fixed and
    /// kinematic ones keep the motion the engine gave them).
    pub stoppable: Vec<bool>,
    /// The distance within which the engine holds a pair in contact.
    pub separation: Real,
    /// The minimum separation of a pair apart: the scene's own plus the two
    /// colliders' contact skins.
    pub skin_separation: Real,
    /// Whether touching pairs are swept against the wall (a guard whose
    /// colliders have a skin). Without a skin rapier's contacts overlap, so
    /// the guard only watches pairs apart (`--compare rapier`'s watcher).
    pub guards_touching_pairs: bool,
}

impl Response for Clamp {
    fn queries_touching_pairs(&self) -> bool {
        self.guards_touching_pairs
    }

    fn contact_rule(&self, pair: &PairState) -> ContactRule {
        match pair.touching {
            Some(_) => ContactRule::ScaleRelative,
            None if self.skin_separation > 0.0 => ContactRule::Separation(self.skin_separation),
            None => ContactRule::ScaleRelative,
        }
    }

    fn rearm_distance(&self, contact_distance: Real, factor: Real) -> Real {
        (factor * contact_distance).max(self.separation)
    }

    fn respond(&self, step: &mut StepContext<'_>, found: &mut Vec<Found>) -> bool {
        for entry in found.iter_mut() {
            let k = entry.pair;
            if step.world.pairs[k].touching.is_some() && entry.result.time_of_impact == Some(0.0) {
                entry.result = self.past_the_start(step, k, 0.0, entry.result);
            }
        }
        found.retain(|entry| entry.result.time_of_impact.is_some());

        found.sort_by(|x, y| time_of(x).total_cmp(&time_of(y)).then(x.pair.cmp(&y.pair)));
        if step.world.may_rewind {
            self.rewind_at_first_hit(step, found)
        } else {
            self.clamp(step, found)
        }
    }
}

impl Clamp {
    /// Records the contacts of pairs apart in time order up to the first
    /// that needs the guard, and asks for a rewind to it.
    fn rewind_at_first_hit(&self, step: &mut StepContext<'_>, found: &mut Vec<Found>) -> bool {
        let mut recorded = false;
        for Found { pair: k, result } in found.drain(..) {
            let Some(time) = result.time_of_impact else { continue };
            let pair = &step.world.pairs[k];
            let (a, b) = (pair.a, pair.b);
            let rewind = Rewind { time, a, b, points: result.closest.map(|c| (c.point_a, c.point_b)) };
            if pair.touching.is_some() {
                // rapier let a touching pair through its skin to the wall.
                step.world.rewind = Some(rewind);
                break;
            }
            step.world.record_contact(k, step.t0, time, &result);
            recorded = true;
            if self.guards_touching_pairs && self.reaches_wall(step, k, time) {
                step.world.rewind = Some(rewind);
                break;
            }
        }
        found.clear();
        recorded
    }

    /// Whether pair `k`, from `time` into the step to its end, would come
    /// within the wall (the scene's contact contract); an undecided query
    /// counts as reaching it.
    fn reaches_wall(&self, step: &mut StepContext<'_>, k: usize, time: Real) -> bool {
        let result = self.query_pair(step, k, time, ContactRule::ScaleRelative);
        let result = if result.time_of_impact == Some(time) {
            self.past_the_start(step, k, time, result)
        } else {
            result
        };
        result.time_of_impact.is_some()
    }

    /// A wall query of pair `k` from `time` that stopped at once (the pair
    /// is at the wall there: it started the run touching, or the world was
    /// moved back to its wall contact). Approaching, it is a hit then;
    /// moving apart, the query is asked again whether the pair comes within
    /// [`WALL_REDETECT_FRACTION`] of its distance there later in the sweep
    /// (a turning body can catch up with one pushed straight), and at once
    /// again means apart at the rounding floor: no hit.
    fn past_the_start(
        &self,
        step: &mut StepContext<'_>,
        k: usize,
        time: Real,
        result: MeshCcdResult,
    ) -> MeshCcdResult {
        if result.status == CcdStatus::OutOfIterations || approaching(step, k, &result, time) {
            return result;
        }
        let distance = result.closest.map_or(0.0, |c| c.distance);
        let mut again =
            self.query_pair(step, k, time, ContactRule::Absolute(WALL_REDETECT_FRACTION * distance));
        if again.time_of_impact == Some(time) && again.status != CcdStatus::OutOfIterations {
            again.time_of_impact = None;
        }
        again
    }

    /// The CCD of pair `k` from `time` into the step to its end under `rule`
    /// (its time of impact counted from the step's start).
    fn query_pair(
        &self,
        step: &mut StepContext<'_>,
        k: usize,
        time: Real,
        rule: ContactRule,
    ) -> MeshCcdResult {
        let model = step.model;
        let pair = step.world.pairs[k].clone();
        let from = |i: usize| {
            let motion = &step.world.motions[i];
            StepMotion { elapsed: motion.elapsed + time, ..*motion }
        };
        let (ma, mb) = (from(pair.a), from(pair.b));
        let query = pair_query(model, &pair, [&ma, &mb], model.dt - time, rule);
        let warm = WarmStart { lower_bound: None, ..pair.warm_start() };
        let mut result = mesh_time_of_impact(&query, warm, step.scratch);
        step.counters.work.distance_queries += result.iterations;
        step.counters.work.hull_steps += result.hull_steps;
        step.counters.work.triangle_pairs += result.triangle_pairs;
        if result.status == CcdStatus::OutOfIterations {
            // Undecided is never apart: a hit where it stopped knowing.
            result.time_of_impact = Some(result.time_of_impact.unwrap_or(0.0));
        }
        result.time_of_impact = result.time_of_impact.map(|t| t + time);
        result
    }

    /// The substeps are spent: contacts of pairs apart are recorded, and
    /// those that need the guard hold their stoppable bodies at the contact
    /// (in time order, `stop.rs`).
    fn clamp(&self, step: &mut StepContext<'_>, found: &mut Vec<Found>) -> bool {
        let mut stops = Vec::with_capacity(found.len());
        let mut recorded = false;
        for entry in found.drain(..) {
            let Some(time) = entry.result.time_of_impact else { continue };
            let k = entry.pair;
            if step.world.pairs[k].touching.is_some() {
                stops.push(entry);
            } else if self.guards_touching_pairs && !self.reaches_wall(step, k, time) {
                step.world.record_contact(k, step.t0, time, &entry.result);
                recorded = true;
            } else {
                stops.push(entry);
            }
        }
        let was_touching: Vec<bool> = step.world.pairs.iter().map(|p| p.touching.is_some()).collect();
        let pairs_of_contacts = step.world.contacts.len();
        let can_stop = |i: usize| self.stoppable[i];
        let Stops { committed, stopped } =
            stop_in_time_order(step, &mut stops, &|pair| self.contact_rule(pair), &can_stop);
        for (body, at) in stopped.iter().enumerate() {
            if let Some(at) = *at {
                step.world.held.push((body, at));
            }
        }
        hold_stopped_bodies(step, &stopped);
        // A wall hit of a pair already touching is not a new contact.
        let committed_contacts = step.world.contacts.split_off(pairs_of_contacts);
        let touching_before = |contact: &crate::stepper::Contact| {
            let pair = step.world.pairs.iter().position(|p| (p.a, p.b) == (contact.body_a, contact.body_b));
            pair.is_some_and(|k| was_touching[k])
        };
        let new: Vec<_> = committed_contacts.into_iter().filter(|c| !touching_before(c)).collect();
        let new_contacts = new.len();
        step.world.contacts.extend(new);
        debug_assert!(committed.len() >= new_contacts);
        recorded || new_contacts > 0
    }
}

/// A found contact's time (every entry has one).
fn time_of(found: &Found) -> Real {
    found.result.time_of_impact.unwrap_or(Real::INFINITY)
}

/// Whether the closest points of pair `k`'s contact at `time` into the
/// sweep approach each other.
fn approaching(step: &StepContext<'_>, k: usize, contact: &MeshCcdResult, time: Real) -> bool {
    let Some(closest) = contact.closest else { return true };
    let pair = &step.world.pairs[k];
    let a = step.world.impact_body(step.model, pair.a, time);
    let b = step.world.impact_body(step.model, pair.b, time);
    let (point, normal) = contact_frame(&closest.point_a, &closest.point_b, &a, &b);
    approach_speed(&a, &b, &point, &normal) < 0.0
}

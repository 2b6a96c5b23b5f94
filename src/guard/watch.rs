//! The guard's response to the contacts its sweep finds: rapier moved the
//! bodies over the step (or the rest of it), and the guard decides, pair by
//! pair, whether rapier's step stands, the world goes back to a contact, or
//! a body stops at one.
//!
//! Every pair rapier solves is swept from where it starts the sweep.
//! - A pair **overlapping** at the sweep's start (rapier's soft contact
//!   holds it a little inside) is rapier's: the guard's depth watch
//!   measures it at the step's end (`depth.rs`).
//! - Any other pair is swept for coming within the contact distance
//!   (without skins: the CCD's contract; with them, a pair apart: the two
//!   skins above the scene's `minimum_separation`, where rapier's contact
//!   starts; a pair touching: the wall, the meshes themselves). A new
//!   contact is recorded (a [`GuardEvent::Started`](super::GuardEvent)).
//!   The guard steps in only where rapier's step takes the pair past its
//!   tolerated depth after that time, or to the far side
//!   ([`Watch::needs_guard`]: a bound of how much closer it can come first,
//!   then rapier's end poses, exactly for convex meshes). A pair that
//!   rapier's own contact stops (it saw it within its prediction distance)
//!   arrives at the step's end and closes no farther; a bullet, a blade or
//!   a body falling from beyond rapier's prediction distance arrives early
//!   in the step with the rest of its motion ahead.
//!
//! What the guard does there: when rewinds are allowed (`World::may_rewind`)
//! and the contact is after the sweep's start, the earliest such contact
//! sets `World::rewind` (the guard moves the world back to that time and
//! lets rapier solve from there; contacts after it are swept again). A
//! contact at the sweep's start (rapier began its step there already), a
//! pair's second in a step (rapier's solve at the first did not hold it),
//! or any once the rewinds are spent **stops** the pair there instead
//! (`World::stops`): its dynamic bodies stay at their poses then for the
//! rest of the step, their approach along the contact normal removed, as
//! rapier's own CCD clamps a body at its time of impact. A body is stopped
//! only where it could otherwise go on too deep, after moving to the
//! contact: resting, sliding and rolling bodies never are.
//!
//! With skins, a touching pair already at the wall at the sweep's start is
//! left to rapier's skin contact, which pushes it out (stopping it there
//! would hold it still).
//!
//! A touching pair is apart again once its distance at a step's end exceeds
//! the larger of the stepper's re-arm distance and `separation` (rapier's
//! prediction distance and the skins, within which rapier holds the pair).

use std::cell::RefCell;
use std::sync::Arc;

use super::directions::Directions;
use super::rules::PairRules;
use super::thickness::pair_tolerance;
use crate::ccd::{hull_gap, mesh_time_of_impact, CcdStatus, ContactRule, MeshCcdResult, WarmStart};
use crate::math::{Point, Real, Vector};
use crate::mesh::{convex_penetration_with, PenetrationScratch};
use crate::motion::StepMotion;
use crate::stepper::respond::{approach_speed, contact_frame, Response, StepContext};
use crate::stepper::{pair_query, Found, GuardHit, PairState};

/// A pair at the wall at a sweep's start and moving apart is a hit again
/// only once it comes within this fraction of its distance there (the
/// `Bounce` response's re-detection, for the guard's skins). `0.5`.
pub(crate) const WALL_REDETECT_FRACTION: Real = 0.5;

/// The guard's response, with what it may stop and how deep it lets rapier
/// go.
pub(crate) struct Watch {
    /// Per body: whether it is dynamic (a pair without one is never acted
    /// on: nothing of it can be stopped or moved back).
    pub dynamic: Vec<bool>,
    /// The distance within which rapier holds a pair in contact (its
    /// prediction distance and the two skins).
    pub separation: Real,
    /// The minimum separation of a pair apart with skins: the scene's own
    /// plus the two colliders' contact skins; 0 without skins.
    pub skin_separation: Real,
    /// The deepest overlap rapier's step may take a pair to without the
    /// guard (without skins), before the bodies' thickness is counted.
    pub tolerated_depth: Real,
    /// Each body's thickness ([`thickness`]).
    pub thickness: Arc<[Real]>,
    /// Which pairs rapier solves (the others are not guarded).
    pub solved: Arc<PairRules>,
}

impl Watch {
    /// Whether the colliders have contact skins (then touching pairs are
    /// swept against the wall).
    fn has_skins(&self) -> bool {
        self.skin_separation > 0.0
    }

    /// The tolerated depth of the pair `(a, b)` ([`pair_tolerance`]).
    fn tolerated(&self, a: usize, b: usize) -> Real {
        pair_tolerance(self.tolerated_depth, &self.thickness, a, b)
    }
}

impl Response for Watch {
    fn sweeps(&self, pair: &PairState) -> bool {
        self.solved.solves(pair.a, pair.b)
    }

    fn contact_rule(&self, pair: &PairState) -> ContactRule {
        match pair.touching {
            None if self.has_skins() => ContactRule::Separation(self.skin_separation),
            _ => ContactRule::ScaleRelative,
        }
    }

    fn rearm_distance(&self, contact_distance: Real, factor: Real) -> Real {
        (factor * contact_distance).max(self.separation)
    }

    fn respond(&self, step: &mut StepContext<'_>, found: &mut Vec<Found>) -> bool {
        let mut recorded = false;
        for entry in found.iter_mut() {
            if entry.result.time_of_impact == Some(0.0) && self.rapiers_at_start(step, entry) {
                // rapier's, and a contact all the same if the pair was apart.
                if step.world.pairs[entry.pair].touching.is_none() {
                    step.world.record_contact(entry.pair, step.t0, 0.0, &entry.result);
                    recorded = true;
                }
                entry.result.time_of_impact = None;
            }
        }
        found.retain(|entry| entry.result.time_of_impact.is_some());
        if found.is_empty() {
            return recorded;
        }
        found.sort_by(|x, y| time_of(x).total_cmp(&time_of(y)).then(x.pair.cmp(&y.pair)));
        for entry in found.drain(..) {
            let (k, time) = (entry.pair, time_of(&entry));
            let pair = &step.world.pairs[k];
            let (a, b, touching) = (pair.a, pair.b, pair.touching.is_some());
            let directions = Directions::of(step, k, time, &entry.result);
            if !self.needs_guard(step, k, time, &entry.result, &directions) {
                if !touching {
                    step.world.record_contact(k, step.t0, time, &entry.result);
                    recorded = true;
                }
                continue;
            }
            let rewound = step.world.rewound.contains(&(a, b));
            let rewinds = step.world.may_rewind && time > 0.0 && !rewound;
            if rewinds && !step.world.stops.is_empty() {
                // The stops first: this contact is swept again after them.
                break;
            }
            if !touching {
                step.world.record_contact(k, step.t0, time, &entry.result);
                recorded = true;
            }
            let normal = directions.normal();
            let point =
                entry.result.closest.map(|c| Point::from((c.point_a.coords + c.point_b.coords) / 2.0));
            let hit = GuardHit { time, a, b, point, normal };
            if rewinds {
                step.world.rewind = Some(hit);
                // What comes after is swept again from the rewind.
                break;
            }
            step.world.stops.push(hit);
        }
        recorded
    }
}

impl Watch {
    /// Whether a contact of `entry`'s pair at the sweep's start is left to
    /// rapier (then `entry` is dropped): rapier's step began with the pair
    /// there, within its prediction distance. So it is where the meshes
    /// overlap (rapier's soft contact holds them). With skins, a touching
    /// pair at the wall is left to rapier's skin contact, which pushes it
    /// out, unless it moves apart and comes back within
    /// [`WALL_REDETECT_FRACTION`] of its distance later in the sweep
    /// (`entry` then takes that contact). Any other contact at the start
    /// goes on to [`needs_guard`](Watch::needs_guard), which judges rapier's
    /// end poses.
    fn rapiers_at_start(&self, step: &mut StepContext<'_>, entry: &mut Found) -> bool {
        let distance = entry.result.closest.map_or(0.0, |c| c.distance);
        if distance <= 0.0 {
            return true;
        }
        let touching = step.world.pairs[entry.pair].touching.is_some();
        if !(touching && self.has_skins()) || entry.result.status == CcdStatus::OutOfIterations {
            return false;
        }
        if approaching(step, entry.pair, &entry.result, 0.0) {
            return true;
        }
        match self.comes_back(step, entry.pair, 0.0, distance) {
            Some(again) => {
                entry.result = again;
                false
            }
            None => true,
        }
    }

    /// Pair `k`, at `distance` at `time` into the sweep and moving apart
    /// there: its contact when it comes back within
    /// [`WALL_REDETECT_FRACTION`] of that distance later in the sweep (a
    /// turning body can catch up with one pushed straight), or an undecided
    /// query (never apart); `None` when it does not, or only at once (apart
    /// at the rounding floor).
    fn comes_back(
        &self,
        step: &mut StepContext<'_>,
        k: usize,
        time: Real,
        distance: Real,
    ) -> Option<MeshCcdResult> {
        let again = self.query_pair(step, k, time, ContactRule::Absolute(WALL_REDETECT_FRACTION * distance));
        let later = again.time_of_impact.is_some_and(|t| t > time);
        (later || again.status == CcdStatus::OutOfIterations).then_some(again)
    }

    /// Whether pair `k`'s contact at `time` into the sweep (`result`, along
    /// `directions`) needs the guard. Without skins: whether it could go
    /// past the contact by more than the pair's tolerated depth by the
    /// sweep's end ([`overshoot_bound`]), and rapier's end poses say it did
    /// ([`rapier_end_fails`]). With skins: a touching pair's (at the wall)
    /// always; a pair apart's (at the skins) if it would go on to the wall.
    fn needs_guard(
        &self,
        step: &mut StepContext<'_>,
        k: usize,
        time: Real,
        result: &MeshCcdResult,
        directions: &Directions,
    ) -> bool {
        let pair = &step.world.pairs[k];
        let (a, b, touching) = (pair.a, pair.b, pair.touching.is_some());
        if !(self.dynamic[a] || self.dynamic[b]) {
            return false;
        }
        let closing = overshoot_bound(step, k, time, directions);
        if !self.has_skins() {
            let tolerated = self.tolerated(a, b);
            return closing > tolerated && rapier_end_fails(step, k, directions.normal(), tolerated);
        }
        if touching {
            return true;
        }
        // The meshes are the skins apart at the contact: only a pair that
        // can close that far can reach the wall.
        let skins = self.skin_separation - step.model.ccd.minimum_separation;
        closing > skins - result.contact_distance && self.reaches_wall(step, k, time)
    }

    /// Whether pair `k`, from `time` into the step to its end, would come
    /// within the wall (the scene's contact contract); an undecided query
    /// counts as reaching it.
    fn reaches_wall(&self, step: &mut StepContext<'_>, k: usize, time: Real) -> bool {
        let result = self.query_pair(step, k, time, ContactRule::ScaleRelative);
        if result.time_of_impact != Some(time) || result.status == CcdStatus::OutOfIterations {
            return result.time_of_impact.is_some();
        }
        // At the wall at once: a hit if approaching; moving apart, only if
        // it comes back within a fraction of its distance.
        let distance = result.closest.map_or(0.0, |c| c.distance);
        approaching(step, k, &result, time) || self.comes_back(step, k, time, distance).is_some()
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
        step.counters.work.add_query(result.iterations, result.triangle_pairs, result.hull_steps);
        if result.status == CcdStatus::OutOfIterations {
            // Undecided is never apart: a hit where it stopped knowing.
            result.time_of_impact = Some(result.time_of_impact.unwrap_or(0.0));
        }
        result.time_of_impact = result.time_of_impact.map(|t| t + time);
        result
    }
}

/// A bound of how far pair `k` goes past its contact at `time` into the
/// sweep (along `directions`) by the sweep's end: how deep it could overlap
/// had nothing stopped it.
///
/// - Two convex meshes: their overlap along any direction `n` bounds their
///   depth. It is measured exactly (two support lookups) at the contact and
///   at the sweep's end (rapier's end poses). Over the sweep each vertex's
///   height along `n` moves with its body's centre (a straight line) and
///   turn, whose curvature is at most `|ω|² r`, so the overlap never
///   exceeds the larger of its ends by more than
///   `(r_a |ω_a|² + r_b |ω_b|²) τ² / 8` (`τ` the time left). The
///   directions tried are the contact's ([`Directions`]); the least bound
///   is kept. A pair rapier's contact holds
///   ends the sweep at its depth, whatever its slide or spin; one passing
///   through a plate ends far along the contact's normal.
/// - Any pair: a point of one mesh inside the other entered it after
///   `time`, and has since moved, in the other's frame, at most the
///   relative speed of the centres plus each body's turn times its radius.
///
/// The smaller of the two.
pub(crate) fn overshoot_bound(step: &StepContext<'_>, k: usize, time: Real, directions: &Directions) -> Real {
    let pair = &step.world.pairs[k];
    let (ma, mb) = (&step.world.motions[pair.a], &step.world.motions[pair.b]);
    let (mesh_a, mesh_b) = (&step.model.bodies[pair.a].mesh, &step.model.bodies[pair.b].mesh);
    let (ra, rb) = (mesh_a.radius(), mesh_b.radius());
    let (wa, wb) = (ma.angular_velocity.norm(), mb.angular_velocity.norm());
    let rest = (step.model.dt - time).max(0.0);
    let any_point = rest * ((mb.velocity - ma.velocity).norm() + ra * wa + rb * wb);
    if !(mesh_a.is_convex() && mesh_b.is_convex()) {
        return any_point;
    }
    let curvature = (ra * wa * wa + rb * wb * wb) * rest * rest / 8.0;
    directions
        .iter()
        .map(|&(_, at_contact, at_end)| at_contact.max(at_end).max(0.0) + curvature)
        .fold(any_point, Real::min)
}

/// Whether rapier's end poses of pair `k` (the sweep's end), after its
/// contact along `normal`, are past what the guard lets through:
/// overlapping deeper than `tolerated`, or with one mesh on the far side of
/// the other (the direction that separates them at the end points against
/// the contact's normal: it went through). Exact for two convex meshes
/// (separating axes, or the hulls' separating axis when apart); any other
/// pair counts as failing (the guard cannot tell, so it stops it). A body
/// turning more than a quarter turn within the sweep could cross and turn
/// back unseen by the side test; the overshoot bound lets such a pair
/// through here only where its depth stays within the tolerated one.
fn rapier_end_fails(step: &StepContext<'_>, k: usize, normal: Option<Vector>, tolerated: Real) -> bool {
    let pair = &step.world.pairs[k];
    let (ma, mb) = (&step.world.motions[pair.a], &step.world.motions[pair.b]);
    let (mesh_a, mesh_b) = (&step.model.bodies[pair.a].mesh, &step.model.bodies[pair.b].mesh);
    let (Some(normal), true) = (normal, mesh_a.is_convex() && mesh_b.is_convex()) else { return true };
    let dt = step.model.dt;
    let (end_a, end_b) = (ma.pose_at(dt), mb.pose_at(dt));
    let penetration = PENETRATION_SCRATCH
        .with(|scratch| convex_penetration_with(mesh_a, &end_a, mesh_b, &end_b, &mut scratch.borrow_mut()));
    match penetration {
        Ok(Some(found)) => found.depth > tolerated || found.direction.dot(&normal) < 0.0,
        Ok(None) => {
            let pos_ab = end_a.inv_mul(&end_b);
            let local = end_a.rotation.inverse_transform_vector(&normal);
            let gap = hull_gap(mesh_a, mesh_b, &pos_ab, Some(local), (0.0, Real::INFINITY));
            gap.axis.is_some_and(|axis| (end_a.rotation * axis).dot(&normal) < 0.0)
        }
        Err(_) => true,
    }
}

thread_local! {
    /// Each thread's scratch for the end poses' penetration depth.
    static PENETRATION_SCRATCH: RefCell<PenetrationScratch> = RefCell::new(PenetrationScratch::default());
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

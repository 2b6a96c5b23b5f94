//! Bodies stopped at their contacts, in time order: the part that `Bounce`
//! and `Simulate`'s clamp share.
//!
//! The step's contacts are taken in time order. A contact is committed only
//! if neither body has stopped before it; each of its bodies that can stop
//! then stops there for the rest of the step, and every other pair of theirs
//! is queried again from that time with the stopped body held still (its
//! earlier candidates become stale), so no body moves past a contact with a
//! body that stopped.

use std::cmp::Ordering;
use std::collections::{BinaryHeap, HashMap};

use super::StepContext;
use crate::ccd::{mesh_time_of_impact, ContactRule, MeshCcdResult, WarmStart};
use crate::math::{Point, Real};
use crate::motion::StepMotion;
use crate::scene::BodyMotion;
use crate::stepper::{pair_query, CcdVerdict, Found, PairState};

/// What [`stop_in_time_order`] committed, and its buffers: kept between
/// steps (in the stepper's scratch), so that a step allocates nothing once
/// they have grown.
#[derive(Default)]
pub(crate) struct Stops {
    /// The committed contacts (indices into `world.contacts`), in time order.
    pub(super) committed: Vec<usize>,
    /// When each body stopped (time into the step), if it did.
    pub(super) stopped: Vec<Option<Real>>,
    /// The bodies that stopped (the entries of `stopped` that are set, so
    /// that a step touches only them).
    stopped_bodies: Vec<usize>,
    /// The kinematic bodies with a state (found at the first step: the
    /// bodies' kinds do not change).
    kinematic_with_state: Option<Vec<usize>>,
    /// The candidates, earliest on top.
    candidates: BinaryHeap<Candidate>,
    /// Each candidate pair's CCD result.
    results: HashMap<usize, MeshCcdResult>,
    /// Each pair's recheck count.
    versions: Vec<u32>,
    /// Every pair under each of its two bodies, as `(body, pair)` sorted:
    /// a body's pairs are a run of it, in ascending order. Made at a step's
    /// first stop (scanning every pair for each stopped body made the
    /// response quadratic in a crowd: 14 ms a step at 100,000 bodies).
    pairs_of_bodies: Vec<(usize, usize)>,
}

/// Fills `index` with every pair of `pairs` (their bodies `(a, b)`) under
/// each of its bodies, sorted (see [`Stops::pairs_of_bodies`]).
fn index_pairs_of_bodies(index: &mut Vec<(usize, usize)>, pairs: impl Iterator<Item = (usize, usize)>) {
    index.clear();
    index.extend(pairs.enumerate().flat_map(|(k, (a, b))| [(a, k), (b, k)]));
    index.sort_unstable();
}

/// The pairs of `body` in `index` (made by [`index_pairs_of_bodies`]), in
/// ascending order.
fn pairs_of(index: &[(usize, usize)], body: usize) -> impl Iterator<Item = usize> + '_ {
    let start = index.partition_point(|&(b, _)| b < body);
    index[start..].iter().take_while(move |&&(b, _)| b == body).map(|&(_, k)| k)
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

/// Commits the step's contacts `found` (drained) in time order (see the
/// module) into `stops`; bodies for which `can_stop` holds stop at their
/// contacts, and their other pairs are queried again under `rule`.
pub(super) fn stop_in_time_order(
    step: &mut StepContext<'_>,
    found: &mut Vec<Found>,
    rule: &dyn Fn(&PairState) -> ContactRule,
    can_stop: &dyn Fn(usize) -> bool,
    stops: &mut Stops,
) {
    let model = step.model;
    let dt = model.dt;
    let Stops { committed, stopped, stopped_bodies, candidates, results, versions, pairs_of_bodies, .. } =
        stops;
    committed.clear();
    // Only the last step's stopped bodies are cleared: a step of many bodies
    // and few contacts touches few.
    for &i in stopped_bodies.iter() {
        stopped[i] = None;
    }
    stopped_bodies.clear();
    stopped.resize(model.bodies.len(), None);
    candidates.clear();
    results.clear();
    if found.is_empty() {
        return;
    }
    for Found { pair, result } in found.drain(..) {
        let Some(time) = result.time_of_impact else { continue };
        candidates.push(Candidate { time, pair, version: 0 });
        results.insert(pair, result);
    }
    versions.clear();
    versions.resize(step.world.pairs.len(), 0);
    // The pairs do not change within the step (only what they carry).
    let mut indexed = false;
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
            if !can_stop(body) || stopped[body].is_some() {
                continue;
            }
            stopped[body] = Some(time);
            stopped_bodies.push(body);
            // Every other pair of this body: again from `time`.
            if !indexed {
                index_pairs_of_bodies(pairs_of_bodies, step.world.pairs.iter().map(|pair| (pair.a, pair.b)));
                indexed = true;
            }
            for other in pairs_of(pairs_of_bodies, body).filter(|&other| other != k) {
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
                let query = pair_query(model, &pair, [&ma, &mb], dt - time, rule(&pair));
                let warm = WarmStart { lower_bound: None, ..pair.warm_start() };
                let result = mesh_time_of_impact(&query, warm, step.scratch);
                step.counters.work.add_query(result.iterations, result.triangle_pairs, result.hull_steps);
                match CcdVerdict::of(&result) {
                    CcdVerdict::Undecided => {
                        let undecided = MeshCcdResult {
                            time_of_impact: result.time_of_impact.map(|t| time + t),
                            ..result
                        };
                        step.world.note_undecided(other, &undecided);
                    }
                    CcdVerdict::Contact(after) => {
                        candidates.push(Candidate {
                            time: time + after,
                            pair: other,
                            version: versions[other],
                        });
                        results.insert(other, result);
                    }
                    CcdVerdict::Apart => {}
                }
            }
        }
    }
}

/// Stopped bodies stay where they stopped for the rest of the step (their
/// motion and, where the stepper keeps one, their state); kinematic bodies
/// with a state that did not stop reach the step's end.
pub(super) fn hold_stopped_bodies(step: &mut StepContext<'_>, stops: &mut Stops) {
    let (model, world) = (step.model, &mut *step.world);
    let Stops { stopped, stopped_bodies, kinematic_with_state, .. } = stops;
    for &i in stopped_bodies.iter() {
        let Some(at) = stopped[i] else { continue };
        let pose = world.motions[i].pose_at(at);
        if let Some(state) = world.states[i].as_mut() {
            state.position = Point::from(pose.translation.vector);
            state.orientation = pose.rotation;
        }
        world.motions[i] = StepMotion::fixed(pose);
    }
    let kinematic = kinematic_with_state.get_or_insert_with(|| {
        // (A body at rest stays where its state has it.)
        let with_state = |&(i, body): &(usize, &crate::scene::Body)| {
            body.motion == BodyMotion::Free && !body.stays_put() && world.states[i].is_some()
        };
        model.bodies.iter().enumerate().filter(with_state).map(|(i, _)| i).collect()
    });
    for &i in kinematic.iter().filter(|&&i| stopped[i].is_none()) {
        if let Some(state) = world.states[i].as_mut() {
            let pose = world.motions[i].pose_at(model.dt);
            state.position = Point::from(pose.translation.vector);
            state.orientation = pose.rotation;
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A body's pairs from the index are those a scan of every pair finds,
    /// in the same (ascending) order.
    #[test]
    fn a_bodys_pairs_are_those_a_scan_finds() {
        let pairs = [(0, 1), (0, 4), (1, 2), (1, 4), (2, 3), (3, 4), (5, 7)];
        let mut index = Vec::new();
        index_pairs_of_bodies(&mut index, pairs.iter().copied());
        for body in 0..9 {
            let scanned: Vec<usize> =
                (0..pairs.len()).filter(|&k| pairs[k].0 == body || pairs[k].1 == body).collect();
            assert_eq!(pairs_of(&index, body).collect::<Vec<_>>(), scanned, "body {body}");
        }
        assert_eq!(pairs_of(&index, 4).collect::<Vec<_>>(), [1, 3, 5]);
    }
}

//! Near misses: the certified closest approach of every pair over a run
//! (a scene's `near_misses: (within: D)`), each pair that came within `D`
//! listed with its bracket.
//!
//! Each step, every candidate pair (the broad phase's, its boxes grown by
//! `D / 2` each, so that a pair it leaves out stays farther than `D` over
//! the step) gets a [`closest_approach`] over the step, asking only for
//! approaches closer than both `D` and the pair's best so far: a pair that
//! does not come nearer costs one CCD run, usually one bounding-sphere or
//! hull check. A pair's motion is taken up to the first contact of either
//! body in the step (what follows a contact is the response's, not the
//! integrated motion), and a pair that touches is a contact (`contacts`),
//! never a near miss.
//!
//! The bracket of the run: `distance` is reached (at `time`, between the
//! listed points), and the pair is never closer than `lower`, which is the
//! smallest certified bound of the steps since it first came within `D`
//! (every earlier step, and every step the broad phase left it out, kept
//! it farther than `D`). What is not looked at: the rest of a step after
//! either body's contact in it (under `Bounce` a body that hit holds still
//! there; under `Record` it moves on), where a pair's approach is not
//! bracketed.

use std::collections::{HashMap, HashSet};

use crate::ccd::{closest_approach, ApproachStatus, ClosestApproachQuery, MeshCcdScratch, MovingMesh};
use crate::math::Real;
use crate::mesh::MeshDistance;
use crate::motion::StepMotion;
use crate::scene::{Model, NearMissSpec};
use crate::stepper::PairState;

/// A pair's closest approach over a run.
#[derive(Clone, Debug, PartialEq)]
pub struct NearMiss {
    /// The first body (index, smaller).
    pub body_a: usize,
    /// The second body.
    pub body_b: usize,
    /// The smallest distance found, reached at `time` (the bracket's upper
    /// end).
    pub distance: Real,
    /// The pair is never closer than this over the run (certified; but for
    /// the rest of a step after either body's contact, see the module).
    pub lower: Real,
    /// When `distance` is reached.
    pub time: Real,
    /// The closest points (world frame), triangles and features at `time`.
    pub closest: MeshDistance,
    /// Every step's bracket closed; `false` if a step's CCD ran out of
    /// iterations (the bracket holds, perhaps wider than the tolerance).
    pub decided: bool,
}

/// The near-miss observer of a run.
#[derive(Debug)]
pub(crate) struct NearMissObserver {
    within: Real,
    /// The pairs asked for, sorted (`None`: every pair).
    only: Option<Vec<(usize, usize)>>,
    best: HashMap<(usize, usize), NearMiss>,
    touched: HashSet<(usize, usize)>,
    /// Each body's horizon in the current step (buffer).
    horizons: Vec<Real>,
    scratch: MeshCcdScratch,
}

impl NearMissObserver {
    pub(crate) fn new(spec: &NearMissSpec) -> NearMissObserver {
        let only = spec.pairs.clone().map(|mut pairs| {
            pairs.sort_unstable();
            pairs
        });
        NearMissObserver {
            within: spec.within,
            only,
            best: HashMap::new(),
            touched: HashSet::new(),
            horizons: Vec::new(),
            scratch: MeshCcdScratch::default(),
        }
    }

    /// The closest approaches of step starting at `t0`, for the candidate
    /// `pairs`, before the response; `contacts` are the step's contacts
    /// (pair, time into the step).
    pub(crate) fn observe_step(
        &mut self,
        model: &Model,
        t0: Real,
        pairs: &[PairState],
        motions: &[StepMotion],
        contacts: impl Iterator<Item = ((usize, usize), Real)>,
    ) {
        self.horizons.clear();
        self.horizons.resize(motions.len(), model.dt);
        for ((a, b), time) in contacts {
            self.horizons[a] = self.horizons[a].min(time);
            self.horizons[b] = self.horizons[b].min(time);
            self.touched.insert((a, b));
            self.best.remove(&(a, b));
        }
        for pair in pairs {
            let key = (pair.a.min(pair.b), pair.a.max(pair.b));
            if self.touched.contains(&key)
                || self.only.as_ref().is_some_and(|only| only.binary_search(&key).is_err())
            {
                continue;
            }
            let duration = self.horizons[key.0].min(self.horizons[key.1]);
            if duration <= 0.0 {
                continue;
            }
            let best = self.best.get(&key);
            let mut query = ClosestApproachQuery::new(
                MovingMesh { mesh: &model.bodies[key.0].mesh, motion: &motions[key.0] },
                MovingMesh { mesh: &model.bodies[key.1].mesh, motion: &motions[key.1] },
                duration,
            );
            query.within = best.map_or(self.within, |b| b.distance.min(self.within));
            query.options.max_iterations = model.ccd.max_iterations;
            query.kernel = model.kernel;
            let approach = closest_approach(&query, &mut self.scratch);
            match (approach.status, approach.closest) {
                (ApproachStatus::Contact, _) => {
                    self.touched.insert(key);
                    self.best.remove(&key);
                }
                (ApproachStatus::Beyond, _) | (_, None) => {
                    if let Some(record) = self.best.get_mut(&key) {
                        record.lower = record.lower.min(approach.lower);
                    }
                }
                (status, Some(closest)) => {
                    let decided = status == ApproachStatus::Bracketed;
                    let record = self.best.entry(key).or_insert_with(|| NearMiss {
                        body_a: key.0,
                        body_b: key.1,
                        distance: Real::INFINITY,
                        lower: Real::INFINITY,
                        time: 0.0,
                        closest,
                        decided: true,
                    });
                    record.lower = record.lower.min(approach.lower);
                    record.decided &= decided;
                    if approach.upper < record.distance {
                        (record.distance, record.time, record.closest) =
                            (approach.upper, t0 + approach.time, closest);
                    }
                }
            }
        }
    }

    /// Every pair that came within the distance, nearest first.
    pub(crate) fn finish(self) -> Vec<NearMiss> {
        let within = self.within;
        let mut list: Vec<NearMiss> = self.best.into_values().filter(|m| m.distance <= within).collect();
        list.sort_by(|x, y| {
            x.distance.total_cmp(&y.distance).then((x.body_a, x.body_b).cmp(&(y.body_a, y.body_b)))
        });
        list
    }
}

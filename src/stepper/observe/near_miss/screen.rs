//! A screen of one pair's step, and what the observer keeps of its answer.

use std::collections::hash_map::Entry;

use super::pair::{approach_query, beats, HeldStep, PairRecord};
use super::NearMissObserver;
use crate::ccd::{
    distance_at, screen_approach, ApproachRun, MeshCcdResult, MeshCcdScratch, MovingMesh, WarmStart,
};
use crate::math::Real;
use crate::scene::Model;

/// A screen of one pair's step: the step and what it asks (anything closer
/// than `within`?), started from `warm`.
#[derive(Copy, Clone, Debug)]
pub(super) struct ScreenJob {
    /// The pair's index among the step's candidates.
    pub(super) index: usize,
    pub(super) key: (usize, usize),
    pub(super) step: HeldStep,
    /// The run's distance `D`, and the pair's best so far if it has one.
    pub(super) within: Real,
    pub(super) best: Option<Real>,
    pub(super) warm: WarmStart,
}

impl ScreenJob {
    /// The pair's two moving meshes over the step.
    fn bodies<'j>(&'j self, model: &'j Model) -> (MovingMesh<'j>, MovingMesh<'j>) {
        let (a, b) = self.key;
        (
            MovingMesh { mesh: &model.bodies[a].mesh, motion: &self.step.a },
            MovingMesh { mesh: &model.bodies[b].mesh, motion: &self.step.b },
        )
    }

    /// The screen: one CCD run, brackets `tolerance` wide (`None`: the
    /// closest approach's default).
    pub(super) fn screen(
        &self,
        model: &Model,
        tolerance: Option<Real>,
        scratch: &mut MeshCcdScratch,
    ) -> (ApproachRun, MeshCcdResult) {
        let (a, b) = self.bodies(model);
        let mut query = approach_query(model, (&a, &b), self.step.duration, tolerance);
        query.within = self.best.map_or(self.within, |best| self.within.min(beats(best, &query)));
        screen_approach(&query, self.warm, scratch)
    }
}

impl NearMissObserver {
    /// What a pair's screen found: its warm start for the next step, and
    /// its record (a held step, a bound, or a contact that ends it).
    pub(super) fn keep_screen(
        &mut self,
        model: &Model,
        job: &ScreenJob,
        run: ApproachRun,
        result: &MeshCcdResult,
    ) {
        let ScreenJob { key, step, .. } = *job;
        let whole_step = step.duration == model.dt;
        let bound = matches!(run, ApproachRun::Beyond { .. }) && whole_step;
        self.screens.insert(
            key,
            (
                self.steps,
                WarmStart {
                    lower_bound: bound.then_some(result.end_lower_bound),
                    hint: result.hint,
                    axis: result.axis,
                    simplex: result.simplex,
                },
            ),
        );
        let hint = result.hint;
        match run {
            // (A pair holding steps is not screened: its held steps wait
            // for it to leave the candidates.)
            ApproachRun::Beyond { lower } => {
                if let Some(record) = self.pairs.get_mut(&key) {
                    record.miss.lower = record.miss.lower.min(lower);
                }
            }
            ApproachRun::Closer { time } => {
                let record = match self.pairs.entry(key) {
                    Entry::Occupied(entry) => entry.into_mut(),
                    Entry::Vacant(entry) => {
                        // A new near miss: a first distance reached, for the
                        // record (the bracket at the flush finds the best):
                        // the triangle pair that stopped the screen there.
                        let found = result.closest.unwrap_or_else(|| {
                            let (a, b) = job.bodies(model);
                            distance_at(&a, &b, time, hint, &mut self.scratch)
                        });
                        entry.insert(PairRecord::new(key, &step, time, found))
                    }
                };
                if record.held.is_empty() {
                    self.with_held.push(key);
                }
                record.seen = self.steps;
                record.held.push(step);
            }
            ApproachRun::Touching { .. } => {
                self.touched.insert(key);
                self.pairs.remove(&key);
            }
            // Undecided: the CCD could not tell how close the pair comes in
            // this step; it is listed (undecided, certified no farther than
            // 0) if the step's end is within the distance.
            ApproachRun::Undecided => {
                let (a, b) = job.bodies(model);
                let end = distance_at(&a, &b, step.duration, hint, &mut self.scratch);
                if self.pairs.contains_key(&key) || end.distance <= self.within {
                    let record = self
                        .pairs
                        .entry(key)
                        .or_insert_with(|| PairRecord::new(key, &step, step.duration, end));
                    record.miss.lower = 0.0;
                    record.miss.decided = false;
                    if end.distance < record.miss.distance {
                        record.miss.reach(&step, step.duration, end);
                    }
                }
            }
        }
    }
}

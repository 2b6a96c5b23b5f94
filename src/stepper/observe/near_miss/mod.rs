//! Near misses: the certified closest approach of every pair over a run
//! (a scene's `near_misses: (within: D)`), each pair that came within `D`
//! listed with its bracket.
//!
//! Each step, every candidate pair (the broad phase's, its boxes grown by
//! `D / 2` each, so that a pair it leaves out stays farther than `D` over
//! the step) is screened by one CCD run: does it come closer than both `D`
//! and its best so far? A pair that does not costs that run, usually one
//! bounding-sphere or hull check, and its certified bound is kept. A step
//! that does is held (its motions copied), and so is every later step of
//! the pair, unscreened, until the pair leaves the candidates, for at most
//! [`MAX_HELD_STEPS`] steps, or to the run's end: most approaches end in a
//! contact, which drops them, so screening each step of an approach bought
//! little (the measurements: `docs/benchmarks-history.md`).
//! Then the held steps are bracketed with [`closest_approach`]: the step
//! whose end is nearest first (a golden-section search over the held
//! steps' ends), then its neighbours outwards, each asking only for what
//! beats the best so far, so that one bracket finds the approach and the
//! others are proved farther by one CCD run each. (Bracketing every step
//! as it came made a pair that approaches over many steps improve its
//! best, and pay a whole bracket, every step.)
//!
//! The screens run before the narrow phase, which takes a screen that
//! proves its pair farther than the contact distance as its own answer: a
//! far pair costs one CCD run, not two. A pair whose body touches anything
//! in the step is screened again after the response, up to that contact.
//!
//! What a step's brackets find is kept when the next step's screens start:
//! in a parallel run of many bodies the brackets run on another thread
//! meanwhile, while the next step's bodies move and its broad phase runs
//! (the run without near misses leaves the second core mostly idle), with
//! the same answers as on one thread.
//!
//! A pair's motion is taken up to the first contact of either body in the
//! step (what follows a contact is the response's, not the integrated
//! motion), and a pair that touches is a contact (`contacts`), never a
//! near miss.
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
use std::sync::mpsc::Receiver;
use std::sync::{Arc, Mutex};

use crate::ccd::{ApproachRun, MeshCcdResult, MeshCcdScratch, WarmStart};
use crate::math::Real;
use crate::motion::StepMotion;
use crate::scene::{Model, NearMissSpec};
use crate::stepper::threads::Batches;
use crate::stepper::world::PairState;
use hash::PairHash;
use pair::{HeldStep, PairRecord};
use screen::ScreenJob;

mod flush;
mod hash;
mod pair;
pub(crate) mod record;
mod screen;
mod search;

pub use record::NearMiss;

pub(crate) use record::MAX_HELD_STEPS;

/// The near-miss observer of a run.
#[derive(Debug)]
pub(crate) struct NearMissObserver {
    within: Real,
    /// The brackets' width (`None`: the closest approach's default).
    tolerance: Option<Real>,
    /// The pairs asked for, sorted (`None`: every pair).
    only: Option<Vec<(usize, usize)>>,
    pairs: HashMap<(usize, usize), PairRecord, PairHash>,
    touched: HashSet<(usize, usize), PairHash>,
    /// Each body's horizon in the current step (buffer).
    horizons: Vec<Real>,
    /// Steps observed.
    steps: u64,
    /// Where each pair's last screen left off, and in which step: its
    /// closest triangles, hull axis and simplex, and (where nothing cut
    /// that step short) its certified bound at the step's end, which is the
    /// next step's start.
    screens: HashMap<(usize, usize), (u64, WarmStart), PairHash>,
    /// Whether the screens, and the brackets, go on rayon's threads.
    screens_parallel: Batches,
    brackets_parallel: Batches,
    scratch: MeshCcdScratch,
    /// Buffers of a step, kept between steps: the screens asked and their
    /// answers, the pairs to bracket, the records being bracketed and
    /// whether each stays apart.
    jobs: Vec<ScreenJob>,
    screened: Vec<(ApproachRun, MeshCcdResult)>,
    /// The step of each candidate pair whose record holds steps already
    /// (in the middle of an approach): held again with no screen.
    holding: Vec<((usize, usize), HeldStep)>,
    /// The pairs whose records hold steps (or held them until the pair
    /// touched), each once.
    with_held: Vec<(usize, usize)>,
    /// For each candidate pair of the step (by index), where its screen
    /// proved it apart over the whole step: the certified distance and the
    /// screen (its index in `screened`).
    beyond: Vec<Option<(Real, usize)>>,
    flushing: Vec<(usize, usize)>,
    batch: Vec<((usize, usize), PairRecord)>,
    apart: Vec<bool>,
    /// Whether a step's brackets run on another thread while the run steps
    /// on (a parallel run of many bodies with several threads; see
    /// [`NearMissObserver::flush_pending`]).
    background: bool,
    /// The brackets on another thread: each pair's record as bracketed,
    /// and whether it stays apart, and the seconds they took (behind a
    /// lock only so that the observer can be shared with the narrow
    /// phase's threads, which read the screens).
    in_flight: Mutex<Option<Receiver<FlushedBatch>>>,
}

/// A pair's record after its held steps were bracketed, and whether the
/// pair stays apart (`false`: it touches).
type Flushed = ((usize, usize), PairRecord, bool);

/// A batch of brackets done on another thread, and the seconds it took.
type FlushedBatch = (Vec<Flushed>, Real);

impl NearMissObserver {
    /// The observer of a run of `bodies` bodies, `parallel` or not; batches
    /// go on rayon's threads where they outlast `handing_over` seconds, and
    /// the brackets beside the stepping where the run has at least
    /// `many_bodies` bodies (under that, a step is too short to hide them
    /// behind).
    pub(crate) fn new(
        spec: &NearMissSpec,
        parallel: bool,
        handing_over: Real,
        (bodies, many_bodies): (usize, usize),
    ) -> NearMissObserver {
        let only = spec.pairs.clone().map(|mut pairs| {
            pairs.sort_unstable();
            pairs
        });
        NearMissObserver {
            within: spec.within,
            tolerance: spec.tolerance,
            only,
            pairs: HashMap::default(),
            touched: HashSet::default(),
            horizons: Vec::new(),
            steps: 0,
            screens: HashMap::default(),
            screens_parallel: Batches::new(parallel, handing_over),
            brackets_parallel: Batches::new(parallel, handing_over),
            scratch: MeshCcdScratch::default(),
            jobs: Vec::new(),
            screened: Vec::new(),
            holding: Vec::new(),
            with_held: Vec::new(),
            beyond: Vec::new(),
            flushing: Vec::new(),
            batch: Vec::new(),
            apart: Vec::new(),
            background: parallel && rayon::current_num_threads() > 1 && bodies >= many_bodies,
            in_flight: Mutex::new(None),
        }
    }

    /// The first half of a step's near misses, before the narrow phase:
    /// each candidate pair of the step starting at `t0` is screened over
    /// the whole step, its bodies moving by `motions` (one CCD run: does it
    /// come closer than both the distance and its best so far?). A pair
    /// screened farther is one the narrow phase need not ask again
    /// ([`NearMissObserver::screened_apart`]); the rest of the step is
    /// [`NearMissObserver::observe_step`]'s, once the step's contacts are
    /// known.
    ///
    /// The screens are independent from pair to pair: on rayon's threads
    /// when the run is parallel and there are enough of them, their results
    /// kept in pair order (the same answers whatever the threads).
    pub(crate) fn screen_step(
        &mut self,
        model: &Model,
        t0: Real,
        pairs: &[PairState],
        motions: &[StepMotion],
    ) {
        self.steps += 1;
        // The last step's brackets, before anything asks for a best.
        self.join();
        // 1. What each pair's screen asks, in pair order.
        let mut jobs = std::mem::take(&mut self.jobs);
        jobs.clear();
        self.holding.clear();
        for (index, pair) in pairs.iter().enumerate() {
            let key = (pair.a.min(pair.b), pair.a.max(pair.b));
            if self.touched.contains(&key)
                || self.only.as_ref().is_some_and(|only| only.binary_search(&key).is_err())
            {
                continue;
            }
            let step = HeldStep { t0, duration: model.dt, a: motions[key.0], b: motions[key.1] };
            // A pair in the middle of an approach (its last step came
            // closer and is held) holds this one too, unscreened: most
            // approaches end in a contact, which drops them, and the rest
            // are bracketed together once the pair leaves the candidates
            // (or after MAX_HELD_STEPS), a step farther than the best
            // proved so by one CCD run.
            let best = match self.pairs.get_mut(&key) {
                Some(record) if !record.held.is_empty() => {
                    record.seen = self.steps;
                    self.holding.push((key, step));
                    continue;
                }
                record => record.map(|record| record.miss.distance),
            };
            // From the pair's last screen: its bound only if that screen was
            // of the step before (a bound at this step's start, less what
            // the motion closes over the step, bounds the whole step).
            let warm = match self.screens.get(&key) {
                Some(&(screened, warm)) => {
                    WarmStart { lower_bound: warm.lower_bound.filter(|_| screened + 1 == self.steps), ..warm }
                }
                None => WarmStart::default(),
            };
            jobs.push(ScreenJob { index, key, step, within: self.within, best, warm });
        }
        // 2. The screens.
        let tolerance = self.tolerance;
        let mut screened = std::mem::take(&mut self.screened);
        self.screens_parallel.run(&mut jobs, &mut screened, &mut self.scratch, |job, scratch| {
            job.screen(model, tolerance, scratch)
        });
        self.beyond.clear();
        self.beyond.resize(pairs.len(), None);
        for (k, (job, (run, _))) in jobs.iter().zip(&screened).enumerate() {
            if let ApproachRun::Beyond { lower } = *run {
                self.beyond[job.index] = Some((lower, k));
            }
        }
        (self.jobs, self.screened) = (jobs, screened);
    }

    /// Pair `index` of the step's candidates (as [`Self::screen_step`]
    /// had them), if its screen proved it never closer than a distance
    /// over the whole step: that distance, and the screen's CCD result.
    pub(crate) fn screened_apart(&self, index: usize) -> Option<(Real, &MeshCcdResult)> {
        let (lower, k) = self.beyond.get(index).copied().flatten()?;
        Some((lower, &self.screened[k].1))
    }

    /// The second half of a step's near misses, after the response:
    /// `contacts` are the step's contacts (pair, time into the step). A
    /// pair whose body touched anything in the step is screened again up
    /// to that contact (what follows is the response's motion); a pair
    /// that touched is a contact, never a near miss.
    ///
    /// A step that comes closer is held, with the distance measured where
    /// it first came closer, and so is each later step of the pair (up to
    /// either body's contact in it). The held steps are bracketed when the
    /// pair leaves the candidates, every [`MAX_HELD_STEPS`], and at the
    /// run's end, nearest first, so that most of them are settled by one
    /// run that proves them farther than the best. The brackets are
    /// independent from pair to pair, on rayon's threads as the screens.
    pub(crate) fn observe_step(
        &mut self,
        model: &Arc<Model>,
        contacts: impl Iterator<Item = ((usize, usize), Real)>,
    ) {
        self.horizons.clear();
        self.horizons.resize(model.bodies.len(), model.dt);
        for ((a, b), time) in contacts {
            self.horizons[a] = self.horizons[a].min(time);
            self.horizons[b] = self.horizons[b].min(time);
            self.touched.insert((a, b));
            self.pairs.remove(&(a, b));
        }
        // 3. The screens' outcomes, in pair order; the pairs to bracket.
        let (jobs, screened) = (std::mem::take(&mut self.jobs), std::mem::take(&mut self.screened));
        self.flushing.clear();
        for (job, (run, result)) in jobs.iter().zip(&screened) {
            let key = job.key;
            if self.touched.contains(&key) {
                continue;
            }
            let duration = self.horizons[key.0].min(self.horizons[key.1]);
            if duration <= 0.0 {
                continue;
            }
            if duration < job.step.duration {
                let mut job = *job;
                job.step.duration = duration;
                let (run, result) = job.screen(model, self.tolerance, &mut self.scratch);
                self.keep_screen(model, &job, run, &result);
            } else {
                self.keep_screen(model, job, *run, result);
            }
        }
        (self.jobs, self.screened) = (jobs, screened);
        self.beyond.clear();
        // The steps held unscreened, up to either body's contact.
        for &(key, step) in &self.holding {
            let duration = self.horizons[key.0].min(self.horizons[key.1]);
            let Some(record) = self.pairs.get_mut(&key).filter(|_| duration > 0.0) else { continue };
            record.held.push(HeldStep { duration, ..step });
        }
        // Pairs holding steps are bracketed once they leave the candidates
        // (or hold MAX_HELD_STEPS), and leave the list (a record touched
        // meanwhile is gone).
        let (pairs, flushing, steps) = (&self.pairs, &mut self.flushing, self.steps);
        self.with_held.retain(|key| {
            let Some(record) = pairs.get(key) else { return false };
            let flush = record.seen != steps || record.held.len() >= MAX_HELD_STEPS;
            if flush {
                flushing.push(*key);
            }
            !flush
        });
        // 4. The brackets.
        self.flush_pending(model, self.background);
    }

    /// Every pair that came within the distance, nearest first (the steps
    /// still held bracketed first).
    pub(crate) fn finish(mut self, model: &Arc<Model>) -> Vec<NearMiss> {
        self.join();
        self.flushing.clear();
        self.flushing
            .extend(self.pairs.iter().filter(|(_, record)| !record.held.is_empty()).map(|(&key, _)| key));
        self.flush_pending(model, false);
        let within = self.within;
        let mut list: Vec<NearMiss> = self
            .pairs
            .into_values()
            .map(|record| record.miss)
            .filter(|miss| miss.distance <= within)
            .collect();
        list.sort_by(|x, y| {
            x.distance.total_cmp(&y.distance).then((x.body_a, x.body_b).cmp(&(y.body_a, y.body_b)))
        });
        list
    }
}

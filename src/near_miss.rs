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
//! contact, which drops them, so screening each step of an approach (over
//! a quarter of the near misses' work on the 1,000-body box) bought little.
//! Then the held steps are bracketed with [`closest_approach`]: the step
//! whose end is nearest first (a golden-section search over the held
//! steps' ends), then its neighbours outwards, each asking only for what
//! beats the best so far, so that one bracket finds the approach and the
//! others are proved farther by one CCD run each. (Bracketing every step
//! as it came cost 35× the run without near misses on the 1,000-body box:
//! a pair that approaches over many steps improved its best, and paid a
//! whole bracket, every step.)
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

use std::collections::hash_map::Entry;
use std::collections::{HashMap, HashSet};
use std::sync::mpsc::{channel, Receiver};
use std::sync::{Arc, Mutex, PoisonError};
use std::time::Instant;

use rayon::prelude::*;

use crate::ccd::{
    closest_approach, distance_at, hull_gap_from, screen_approach, ApproachRun, ApproachStatus,
    ClosestApproach, ClosestApproachQuery, MeshCcdResult, MeshCcdScratch, MovingMesh, WarmSimplex, WarmStart,
    PROOF_MARGIN_FRACTION,
};
use crate::math::{Pose, Real};
use crate::mesh::MeshDistance;
use crate::motion::StepMotion;
use crate::scene::{Model, NearMissSpec};
use crate::stepper::{gains_from_threads, one_thread_seconds, PairState, THREAD_SCRATCH};

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
    /// The pose of `body_a`'s frame (its mesh's frame) at `time`.
    pub pose_a: Pose,
    /// The pose of `body_b`'s frame at `time`.
    pub pose_b: Pose,
    /// Every step's bracket closed; `false` if a step's CCD ran out of
    /// iterations (the bracket holds, perhaps wider than the tolerance).
    pub decided: bool,
}

/// The most steps of one pair held before they are bracketed: `64` (a
/// pair that keeps approaching is bracketed once per this many steps).
pub const MAX_HELD_STEPS: usize = 64;

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
    screens_parallel: Threads,
    brackets_parallel: Threads,
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

/// The observer's maps hash their pairs of body indices by one multiply
/// and rotate per index (the standard library's SipHash, made to resist
/// crafted keys, cost a tenth of the near misses' time on the 1,000-body
/// box; these keys are the run's own).
type PairHash = std::hash::BuildHasherDefault<PairHasher>;

/// See [`PairHash`].
#[derive(Default)]
struct PairHasher(u64);

impl std::hash::Hasher for PairHasher {
    fn finish(&self) -> u64 {
        self.0
    }

    fn write(&mut self, bytes: &[u8]) {
        for &byte in bytes {
            self.write_u64(u64::from(byte));
        }
    }

    fn write_u64(&mut self, value: u64) {
        self.0 = (self.0.rotate_left(5) ^ value).wrapping_mul(0x517c_c1b7_2722_0a95);
    }

    fn write_usize(&mut self, value: usize) {
        self.write_u64(value as u64);
    }
}

/// A screen of one pair's step: the step and what it asks (anything closer
/// than `within`?), started from `warm`.
#[derive(Copy, Clone, Debug)]
struct ScreenJob {
    /// The pair's index among the step's candidates.
    index: usize,
    key: (usize, usize),
    step: HeldStep,
    /// The run's distance `D`, and the pair's best so far if it has one.
    within: Real,
    best: Option<Real>,
    warm: WarmStart,
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
    fn screen(
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

/// Whether a batch of independent jobs (a step's screens, or its
/// brackets) goes on rayon's threads: when the run is parallel, there are
/// several threads, and the batch, at the mean time per job seen so far,
/// takes longer on one thread than handing it over costs (the narrow
/// phase's rule, with its [`parallel_narrow_phase_seconds`]: a batch of a
/// tenth of a millisecond gains nothing on two threads).
///
/// [`parallel_narrow_phase_seconds`]: crate::stepper::StepParameters::parallel_narrow_phase_seconds
#[derive(Copy, Clone, Debug)]
struct Threads {
    /// `false`: never (the run is not parallel, or one thread).
    allowed: bool,
    threads: Real,
    handing_over: Real,
    /// Seconds on one thread and jobs, over the batches so far.
    seconds: Real,
    jobs: usize,
}

impl Threads {
    fn new(parallel: bool, handing_over: Real) -> Threads {
        let threads = rayon::current_num_threads() as Real;
        Threads { allowed: parallel && threads > 1.0, threads, handing_over, seconds: 0.0, jobs: 0 }
    }

    /// Whether a batch of `jobs` goes on the threads (the first batches,
    /// with nothing seen yet, do not).
    fn choose(&self, jobs: usize) -> bool {
        self.allowed
            && jobs > 1
            && gains_from_threads(self.on_one_thread(jobs), self.threads, self.handing_over)
    }

    /// Whether a batch of `jobs`, at the mean time per job seen so far,
    /// takes longer on one thread than handing it to another costs (the
    /// first batches, with nothing seen yet, do not).
    fn outlasts_hand_over(&self, jobs: usize) -> bool {
        self.allowed && self.on_one_thread(jobs) > self.handing_over
    }

    /// A batch of `jobs` on one thread, at the mean time per job seen so
    /// far (0 before any).
    fn on_one_thread(&self, jobs: usize) -> Real {
        self.seconds / self.jobs.max(1) as Real * jobs as Real
    }

    /// Counts a batch of `jobs` that took `seconds` on one thread.
    fn account(&mut self, seconds: Real, jobs: usize) {
        self.seconds += seconds;
        self.jobs += jobs;
    }

    /// `f` of each of `jobs`, in order, into `out`: on rayon's threads
    /// (each with its own scratch) where [`Threads::choose`] says so,
    /// otherwise on this one with `scratch`.
    fn run<J: Send, R: Send>(
        &mut self,
        jobs: &mut [J],
        out: &mut Vec<R>,
        scratch: &mut MeshCcdScratch,
        f: impl Fn(&mut J, &mut MeshCcdScratch) -> R + Sync,
    ) {
        let clock = Instant::now();
        let parallel = self.choose(jobs.len());
        if parallel {
            jobs.par_iter_mut()
                .map(|job| THREAD_SCRATCH.with(|scratch| f(job, &mut scratch.borrow_mut())))
                .collect_into_vec(out);
        } else {
            out.clear();
            out.extend(jobs.iter_mut().map(|job| f(job, scratch)));
        }
        let seconds = clock.elapsed().as_secs_f64();
        self.account(one_thread_seconds(seconds, parallel, self.threads, self.handing_over), jobs.len());
    }
}

/// A pair that came within the distance: its closest approach so far, and
/// the steps held for bracketing.
#[derive(Debug)]
struct PairRecord {
    /// The smallest distance reached so far (`distance`, `time`, `closest`),
    /// and the smallest certified bound of the steps bracketed or screened
    /// (`lower`; the held steps' are not in it yet).
    miss: NearMiss,
    /// The steps held since one was screened closer than the pair's best
    /// (that step and each later one while the pair stays a candidate):
    /// each is bracketed at the next flush, nearest first, asking only for
    /// what beats the best.
    held: Vec<HeldStep>,
    /// The last step (count) in which the pair was a candidate.
    seen: u64,
}

/// One step of a pair, kept for bracketing.
#[derive(Copy, Clone, Debug)]
struct HeldStep {
    t0: Real,
    duration: Real,
    a: StepMotion,
    b: StepMotion,
}

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
            screens_parallel: Threads::new(parallel, handing_over),
            brackets_parallel: Threads::new(parallel, handing_over),
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

    /// What a pair's screen found: its warm start for the next step, and
    /// its record (a held step, a bound, or a contact that ends it).
    fn keep_screen(&mut self, model: &Model, job: &ScreenJob, run: ApproachRun, result: &MeshCcdResult) {
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

    /// Brackets the held steps of the pairs in `flushing` (see
    /// [`PairRecord::flush`]); a pair found touching is dropped.
    ///
    /// What the brackets found is kept at the next step's
    /// [`NearMissObserver::join`], before its screens, so that they can
    /// run in the `background`, on another of rayon's threads while the
    /// next step's bodies move and its broad phase runs, where a batch
    /// outlasts the hand-over. Their records are out of the map meanwhile
    /// (nothing asks for them before the join). On this thread or
    /// another, the answers are the same.
    fn flush_pending(&mut self, model: &Arc<Model>, background: bool) {
        if self.flushing.is_empty() {
            return;
        }
        let mut batch = std::mem::take(&mut self.batch);
        batch.clear();
        batch.extend(self.flushing.iter().filter_map(|key| self.pairs.remove_entry(key)));
        let tolerance = self.tolerance;
        if background && self.brackets_parallel.outlasts_hand_over(batch.len()) {
            let (sender, receiver) = channel();
            let model = Arc::clone(model);
            rayon::spawn(move || {
                let clock = Instant::now();
                let flushed: Vec<Flushed> = THREAD_SCRATCH.with(|scratch| {
                    let scratch = &mut scratch.borrow_mut();
                    batch
                        .into_iter()
                        .map(|(key, mut record)| {
                            let apart = record.flush(&model, tolerance, scratch);
                            (key, record, apart)
                        })
                        .collect()
                });
                // The observer is gone only if the run is (a panic).
                let _ = sender.send((flushed, clock.elapsed().as_secs_f64()));
            });
            *self.in_flight.get_mut().unwrap_or_else(PoisonError::into_inner) = Some(receiver);
            return;
        }
        let mut apart = std::mem::take(&mut self.apart);
        self.brackets_parallel.run(&mut batch, &mut apart, &mut self.scratch, |(_, record), scratch| {
            record.flush(model, tolerance, scratch)
        });
        for ((key, record), &apart) in batch.drain(..).zip(&apart) {
            self.keep_flushed(key, record, apart);
        }
        (self.batch, self.apart) = (batch, apart);
    }

    /// Waits for the brackets on another thread, if any, and keeps what
    /// they found.
    fn join(&mut self) {
        let in_flight = self.in_flight.get_mut().unwrap_or_else(PoisonError::into_inner);
        if let Some(receiver) = in_flight.take() {
            // The channel closes unsent only if the thread panicked, and
            // rayon aborts the process on a panic in a spawned job.
            let (flushed, seconds) = receiver.recv().unwrap_or_default();
            self.brackets_parallel.account(seconds, flushed.len());
            for (key, record, apart) in flushed {
                self.keep_flushed(key, record, apart);
            }
        }
    }

    /// A pair's record as its brackets left it, back in the map, or the
    /// pair dropped if it touches.
    fn keep_flushed(&mut self, key: (usize, usize), record: PairRecord, apart: bool) {
        if apart {
            self.pairs.insert(key, record);
        } else {
            self.touched.insert(key);
        }
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

/// The closest-approach query of a pair's step, as the run's CCD asks.
fn approach_query<'a>(
    model: &Model,
    (a, b): (&MovingMesh<'a>, &MovingMesh<'a>),
    duration: Real,
    tolerance: Option<Real>,
) -> ClosestApproachQuery<'a> {
    let mut query = ClosestApproachQuery::new(*a, *b, duration);
    query.tolerance = tolerance;
    query.options.max_iterations = model.ccd.max_iterations;
    query.kernel = model.kernel;
    query
}

/// What a step of a pair must come closer than to matter, where its best
/// so far is `best`: that less [`PROOF_MARGIN_FRACTION`] of the bracket's
/// width. A step proved no closer is within that of the best, so the
/// pair's bracket stays within its width however close the step comes.
fn beats(best: Real, query: &ClosestApproachQuery<'_>) -> Real {
    best - PROOF_MARGIN_FRACTION * query.width()
}

impl NearMiss {
    /// The pair is `found.distance` apart (reached) at `s` into `step`.
    fn reach(&mut self, step: &HeldStep, s: Real, found: MeshDistance) {
        (self.distance, self.time, self.closest) = (found.distance, step.t0 + s, found);
        (self.pose_a, self.pose_b) = (step.a.pose_at(s), step.b.pose_at(s));
    }
}

impl PairRecord {
    /// A pair first found `found` apart at `s` into `step`.
    fn new(key: (usize, usize), step: &HeldStep, s: Real, found: MeshDistance) -> PairRecord {
        let mut miss = NearMiss {
            body_a: key.0,
            body_b: key.1,
            distance: Real::INFINITY,
            lower: Real::INFINITY,
            time: 0.0,
            closest: found,
            pose_a: Pose::identity(),
            pose_b: Pose::identity(),
            decided: true,
        };
        miss.reach(step, s, found);
        PairRecord { miss, held: Vec::new(), seen: 0 }
    }

    /// Brackets the held steps, each asking only for what comes closer than
    /// the best so far: first the step whose end is nearest (found by a
    /// golden-section search over the steps' ends, the distance usually
    /// falling and then rising across them), then its neighbours outwards,
    /// so that the first bracket finds the best and the others are proved
    /// farther by one CCD run each. `false` if the pair touches.
    fn flush(&mut self, model: &Model, tolerance: Option<Real>, scratch: &mut MeshCcdScratch) -> bool {
        if self.held.is_empty() {
            return true;
        }
        let mut held = std::mem::take(&mut self.held);
        let (mesh_a, mesh_b) = (&model.bodies[self.miss.body_a].mesh, &model.bodies[self.miss.body_b].mesh);
        // The step whose end is nearest, ranked by the vertex hulls' gap at
        // the ends (GJK, warm from end to end; exact for convex meshes, a
        // lower bound otherwise, the exact distance where the hulls
        // overlap): the order only decides which step is bracketed first,
        // every step is bracketed or proved farther all the same.
        let hint = Some((self.miss.closest.triangle_a, self.miss.closest.triangle_b));
        let (mut warm, mut axis) = (WarmSimplex::default(), None);
        let mut end_gap = |k: usize| {
            let step = &held[k];
            let pos_ab = StepMotion::relative_pose(&step.a, &step.b, step.duration);
            let gap = hull_gap_from(mesh_a, mesh_b, &pos_ab, axis, (0.0, Real::INFINITY), &mut warm);
            axis = gap.axis.or(axis);
            if gap.lower > 0.0 {
                return gap.lower;
            }
            let a = MovingMesh { mesh: mesh_a, motion: &step.a };
            let b = MovingMesh { mesh: mesh_b, motion: &step.b };
            distance_at(&a, &b, step.duration, hint, scratch).distance
        };
        let nearest = nearest_index(held.len(), &mut end_gap);
        // Its end, measured: that step's bracket starts from it (a steady
        // approach's minimum is there, and one run then closes it).
        let end = {
            let step = &held[nearest];
            let a = MovingMesh { mesh: mesh_a, motion: &step.a };
            let b = MovingMesh { mesh: mesh_b, motion: &step.b };
            distance_at(&a, &b, step.duration, hint, scratch)
        };
        let mut apart = true;
        for k in outwards(nearest, held.len()) {
            let step = &held[k];
            let a = MovingMesh { mesh: mesh_a, motion: &step.a };
            let b = MovingMesh { mesh: mesh_b, motion: &step.b };
            let mut query = approach_query(model, (&a, &b), step.duration, tolerance);
            query.within = beats(self.miss.distance, &query);
            query.reached = (k == nearest).then_some((step.duration, end));
            let approach = closest_approach(&query, scratch);
            if !self.keep(step, &approach) {
                apart = false;
                break;
            }
        }
        held.clear();
        self.held = held;
        apart
    }

    /// Keeps what a bracket of `step` found. `false` if the pair touches.
    fn keep(&mut self, step: &HeldStep, approach: &ClosestApproach) -> bool {
        let miss = &mut self.miss;
        miss.lower = miss.lower.min(approach.lower);
        match (approach.status, approach.closest) {
            (ApproachStatus::Contact, _) => return false,
            (ApproachStatus::Beyond, _) => {}
            (status, closest) => {
                miss.decided &= status == ApproachStatus::Bracketed;
                if let Some(closest) = closest.filter(|_| approach.upper < miss.distance) {
                    miss.reach(step, approach.time, closest);
                }
            }
        }
        true
    }
}

/// The index in `0..n` (`n` at most [`MAX_HELD_STEPS`]) where `f` is
/// least, by a golden-section search over the indices (for `f` falling and
/// then rising; otherwise some local minimum): `f` is called about
/// `1.44 log2(n) + 3` times, once per index.
fn nearest_index(n: usize, f: &mut impl FnMut(usize) -> Real) -> usize {
    let mut known = [Real::NAN; MAX_HELD_STEPS];
    let mut at = |k: usize| {
        if known[k].is_nan() {
            known[k] = f(k);
        }
        known[k]
    };
    let (mut lo, mut hi) = (0usize, n.saturating_sub(1));
    let inner = |lo: usize, hi: usize| {
        let long = (((hi - lo) as Real * 0.381_966_011_250_105_1).round() as usize).max(1);
        let left = lo + long;
        (left, (hi - long).max(left + 1))
    };
    while hi - lo > 3 {
        let (left, right) = inner(lo, hi);
        if at(left) <= at(right) {
            hi = right;
        } else {
            lo = left;
        }
    }
    (lo..=hi).min_by(|&x, &y| at(x).total_cmp(&at(y))).unwrap_or(lo)
}

/// `0..n` from `start` outwards: `start`, `start + 1`, `start − 1`,
/// `start + 2`, ... (the step after the nearest end first: the minimum may
/// be just past it).
fn outwards(start: usize, n: usize) -> impl Iterator<Item = usize> {
    (0..2 * n).filter_map(move |i| {
        let offset = i.div_ceil(2);
        let k = if i % 2 == 1 { start.checked_add(offset) } else { start.checked_sub(offset) };
        k.filter(|&k| k < n)
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_nearest_of_a_falling_then_rising_sequence_is_found_with_few_calls() {
        for n in 1..=MAX_HELD_STEPS {
            for least in 0..n {
                let mut calls = 0;
                let mut f = |k: usize| {
                    calls += 1;
                    (k as Real - least as Real).abs()
                };
                assert_eq!(nearest_index(n, &mut f), least, "n {n}");
                assert!(calls <= n.min(14), "n {n}: {calls} calls");
            }
        }
    }

    #[test]
    fn outwards_visits_every_index_once_from_the_start() {
        for n in 1..10 {
            for start in 0..n {
                let order: Vec<usize> = outwards(start, n).collect();
                assert_eq!(order[0], start);
                let mut sorted = order.clone();
                sorted.sort_unstable();
                assert_eq!(sorted, (0..n).collect::<Vec<_>>());
                if start + 1 < n {
                    assert_eq!(order[1], start + 1);
                }
            }
        }
    }
}

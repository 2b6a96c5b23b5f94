//! The time-stepper: for each fixed step, integrate the bodies, find
//! contacts by conservative advancement over every pair that can touch,
//! record events and traces.
//!
//! It assembles only what a scene uses: fixed bodies are never integrated
//! and a pair of fixed bodies never queried; free bodies (nothing acting on
//! them) move exactly; a far pair is skipped by the bound carried from the
//! previous step without any mesh query; no distance is computed for a
//! trace the scene did not ask for.
//!
//! With two bodies the one pair is queried directly (no tree). With more,
//! a broad phase ([`crate::broad_phase`]) keeps the pairs whose swept boxes
//! overlap in the step; each pair is then culled by its bounding spheres
//! and the distance bound carried from its previous step. The pairs' CCD
//! runs on rayon's threads, results applied in pair order, so a run gives
//! the same result whatever the threads.
//!
//! With `on_contact: Bounce` the step's contacts are taken in time order:
//! both bodies of a contact stop there for the rest of the step, every other
//! pair of theirs is queried again from that time with the stopped body held
//! still (so no body moves past a contact with a body that stopped), and
//! the committed contacts' impulses ([`crate::response`]) set the velocities
//! the bodies move on with from the next step.

use std::cell::RefCell;
use std::collections::HashMap;
use std::time::Instant;

use rayon::prelude::*;

use crate::broad_phase::{swept_box, BroadPhase, SweptBox};
use crate::ccd::{mesh_time_of_impact, CcdOptions, CcdStatus, MeshCcdResult, MovingMesh};
use crate::kernels::Feature;
use crate::math::{Point, Real};
use crate::mesh::{mesh_distance_relative, DistanceKernel, MeshDistanceScratch};
use crate::motion::{integrate, Dynamics, Integrator, RigidState, StepMotion, MAX_TURN_PER_STEP};
use crate::response::{apply_impulse, approach_speed, contact_frame, ImpactBody};
use crate::scene::{BodyMotion, OnContact, Scene};
use crate::trace::TraceRecord;

/// A contact event.
#[derive(Clone, Debug, PartialEq)]
pub struct Contact {
    /// The time of first contact (never later than the true one).
    pub time: Real,
    /// The first body (index into the scene's bodies; the lower index).
    pub body_a: usize,
    /// The second body.
    pub body_b: usize,
    /// The distance at `time` (at most the contact distance).
    pub distance: Real,
    /// The closest point of `body_a`, world frame.
    pub point_a: Point,
    /// The closest point of `body_b`, world frame.
    pub point_b: Point,
    /// The triangle of `body_a` (in its mesh's triangle order).
    pub triangle_a: usize,
    /// The triangle of `body_b`.
    pub triangle_b: usize,
    /// The feature of `triangle_a` that `point_a` lies on.
    pub feature_a: Feature,
    /// The feature of `triangle_b` that `point_b` lies on.
    pub feature_b: Feature,
    /// How the CCD iteration ended.
    pub status: CcdStatus,
    /// The contact distance of the pair (`minimum_separation + tolerance`).
    pub contact_distance: Real,
}

/// Why a run ended.
#[derive(Clone, Debug, PartialEq)]
pub enum Termination {
    /// All steps ran.
    Completed,
    /// Stopped at the first contact (`on_contact: Stop`).
    FirstContact,
    /// A body's state stopped being usable: not finite, or turning too far
    /// in one step for the in-step motion to be defined.
    Diverged {
        /// The body.
        body: usize,
        /// The step at which it happened (0-based).
        step: u64,
        /// What happened.
        reason: String,
    },
}

/// Work and time per stage.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Counters {
    /// Mesh queries: CCD advancement searches and trace distances.
    pub distance_queries: usize,
    /// Triangle pairs evaluated.
    pub triangle_pairs: usize,
    /// Pair-steps skipped without a mesh query (spheres or carried bound).
    pub pairs_culled: usize,
    /// Steps where the implicit gyroscopic solve did not converge.
    pub gyroscopic_unconverged: usize,
    /// The largest drift of an integrated body's mechanical energy,
    /// `|E − E0|` over its initial energy scale (0 without integrated bodies).
    pub max_energy_drift: Real,
    /// Seconds spent integrating.
    pub integrate_s: Real,
    /// Seconds spent in CCD.
    pub ccd_s: Real,
    /// Seconds spent in the broad phase.
    pub broad_phase_s: Real,
    /// Pairs handed to CCD, summed over steps.
    pub candidate_pairs: usize,
    /// Seconds spent tracing.
    pub trace_s: Real,
}

/// The outcome of a run.
#[derive(Clone, Debug, PartialEq)]
pub struct RunResult {
    /// The scene's name.
    pub scene: String,
    /// The body names (for the indices in contacts and traces).
    pub bodies: Vec<String>,
    /// Steps taken (the last one possibly cut short by a contact).
    pub steps: u64,
    /// The time reached.
    pub end_time: Real,
    /// Wall-clock time of the run, in seconds.
    pub wall_time_s: Real,
    /// The earliest contact, if any.
    pub first_contact: Option<Contact>,
    /// Every contact in time order (only the first with `on_contact: Stop`).
    pub contacts: Vec<Contact>,
    /// The distance trace (empty unless the scene asks for one).
    pub trace: Vec<TraceRecord>,
    /// Why the run ended.
    pub termination: Termination,
    /// Work and time per stage.
    pub counters: Counters,
    /// Each body at `end_time`.
    pub final_states: Vec<RigidState>,
}

/// Runs a scene.
pub fn run(scene: &Scene) -> RunResult {
    run_observed(scene, &mut |_| {})
}

/// How a run is carried out (not what it computes: results are the same
/// whatever the options).
#[derive(Copy, Clone, Debug, PartialEq, Eq)]
pub struct RunOptions {
    /// Run the pairs' CCD on several threads (rayon's pool). Default: true.
    pub parallel: bool,
    /// Select pairs with the broad phase when there are more than two
    /// bodies (otherwise every pair not both fixed is queried). Default: true.
    pub broad_phase: bool,
}

impl Default for RunOptions {
    fn default() -> Self {
        RunOptions { parallel: true, broad_phase: true }
    }
}

/// Runs a scene, calling `observer` with the number of steps done after
/// each step (for progress display).
pub fn run_observed(scene: &Scene, observer: &mut dyn FnMut(u64)) -> RunResult {
    run_with(scene, RunOptions::default(), observer)
}

/// Runs a scene with options.
pub fn run_with(scene: &Scene, options: RunOptions, observer: &mut dyn FnMut(u64)) -> RunResult {
    let start = Instant::now();
    let mut stepper = Stepper::new(scene, options);
    stepper.record_trace(0, 0.0, 0.0);
    let mut termination = Termination::Completed;
    let mut steps = 0;
    for step in 0..scene.steps {
        let t0 = step as Real * scene.dt;
        steps = step + 1;
        if let Err(diverged) = stepper.integrate(step, t0) {
            termination = diverged;
            break;
        }
        if stepper.collide(t0) && scene.on_contact == OnContact::Stop {
            termination = Termination::FirstContact;
            break;
        }
        stepper.end_step(step, t0);
        observer(steps);
    }
    let end_time = match (&termination, &stepper.contacts.first()) {
        (Termination::FirstContact, Some(contact)) => contact.time,
        _ => steps as Real * scene.dt,
    };
    if termination == Termination::FirstContact {
        let step_start = (steps - 1) as Real * scene.dt;
        stepper.record_trace(steps, end_time, end_time - step_start);
    }
    let last_step_start = steps.saturating_sub(1) as Real * scene.dt;
    let final_states =
        (0..scene.bodies.len()).map(|i| stepper.state_at(i, end_time - last_step_start)).collect();
    let mut contacts = stepper.contacts;
    contacts.sort_by(|a, b| a.time.total_cmp(&b.time).then((a.body_a, a.body_b).cmp(&(b.body_a, b.body_b))));
    RunResult {
        scene: scene.name.clone(),
        bodies: scene.bodies.iter().map(|b| b.name.clone()).collect(),
        steps,
        end_time,
        wall_time_s: start.elapsed().as_secs_f64(),
        first_contact: contacts.first().cloned(),
        contacts,
        trace: stepper.trace,
        termination,
        counters: stepper.counters,
        final_states,
    }
}

/// A pair in contact (`Record`, `Bounce`) is re-armed once its distance at
/// a step's end exceeds this many times its contact distance.
pub const REARM_DISTANCE_FACTOR: Real = 2.0;

/// Under `Bounce`, a pair that bounced and is not yet re-armed is a new
/// contact when it comes within this fraction of its distance at the bounce.
pub const BOUNCE_REDETECT_FRACTION: Real = 0.5;

/// Bodies are integrated on several threads from this many on.
const PARALLEL_INTEGRATION_BODIES: usize = 64;

thread_local! {
    /// Each rayon thread's CCD scratch, kept between steps and runs.
    static THREAD_SCRATCH: RefCell<MeshDistanceScratch> = RefCell::new(MeshDistanceScratch::default());
}

/// A run is declared diverged when an integrated body's mechanical energy
/// exceeds its initial value by this many times its initial energy scale
/// (the sum of the magnitudes of its kinetic and potential terms). Gravity,
/// springs and free spin conserve energy and damping only removes it, so
/// such growth is the integrator's, not the physics'.
pub const DIVERGENCE_ENERGY_GROWTH: Real = 10.0;

/// The swept boxes grow by this many ulps of a body's reach (largest
/// coordinate plus travel plus radius) beyond its share of the contact
/// distance, so that box rounding never drops a pair that the CCD's
/// tolerance floor would count as touching.
pub const BROAD_PHASE_ROUNDING_ULPS: Real = 1e3;

/// What to do about a diverging body: the largest stable step of its springs.
fn stability_advice(dynamics: &Dynamics, integrator: Integrator, dt: Real) -> String {
    let limit = |i: Integrator| dynamics.stable_step_limit(i).unwrap_or(0.0);
    match dynamics.stable_step_limit(integrator) {
        None => format!("Lower `dt` (now {dt})."),
        Some(_) if integrator == Integrator::ExplicitEuler => format!(
            "Explicit Euler gains energy at every step on an undamped spring, whatever `dt`: use SymplecticEuler \
             (stable for dt < {:.4e}) or Rk4 (dt < {:.4e}); `dt` is now {dt}.",
            limit(Integrator::SymplecticEuler),
            limit(Integrator::Rk4)
        ),
        Some(largest) => format!(
            "The largest stable dt for its springs with {integrator:?} is {largest:.4e} ({} / ω, ω = sqrt(Σk / m)); `dt` is now {dt}.",
            if integrator == Integrator::Rk4 { "2√2" } else { "2" }
        ),
    }
}

/// What the CCD keeps per pair between steps.
#[derive(Clone, Debug)]
struct PairState {
    a: usize,
    b: usize,
    /// A lower bound on the distance at the start of the next step.
    lower_bound: Option<Real>,
    /// The last closest triangle pair.
    hint: Option<(usize, usize)>,
    /// In contact (`on_contact: Record` or `Bounce`): not re-reported until
    /// it separates (`Bounce`: until it comes within half this distance).
    touching: Option<Touching>,
}

/// A pair in contact.
#[derive(Copy, Clone, Debug)]
struct Touching {
    /// The contact distance of its contact (re-armed beyond twice this).
    contact_distance: Real,
    /// The distance at its contact.
    distance: Real,
}

impl PairState {
    fn new(a: usize, b: usize) -> PairState {
        PairState { a, b, lower_bound: None, hint: None, touching: None }
    }
}

/// What the stepper keeps of a pair's CCD result: the counters and what
/// carries to the next step, and the full result only at a contact (a few
/// pairs a step), so that thousands of pairs cost little memory.
#[derive(Clone, Debug)]
struct PairOutcome {
    summary: OutcomeSummary,
    contact: Option<Box<MeshCcdResult>>,
}

/// The part of every pair's result that the stepper reads.
#[derive(Copy, Clone, Debug)]
struct OutcomeSummary {
    iterations: usize,
    triangle_pairs: usize,
    hint: Option<(usize, usize)>,
    end_lower_bound: Real,
}

impl From<MeshCcdResult> for PairOutcome {
    fn from(result: MeshCcdResult) -> PairOutcome {
        PairOutcome {
            summary: OutcomeSummary {
                iterations: result.iterations,
                triangle_pairs: result.triangle_pairs,
                hint: result.hint,
                end_lower_bound: result.end_lower_bound,
            },
            contact: result.time_of_impact.is_some().then(|| Box::new(result)),
        }
    }
}

/// A candidate contact of `on_contact: Bounce` within a step.
#[derive(Copy, Clone, Debug)]
struct Candidate {
    /// Time into the step.
    time: Real,
    /// The pair (index into `pairs`).
    pair: usize,
    /// The pair's recheck count when found (stale once it changed).
    version: u32,
}

impl PartialEq for Candidate {
    fn eq(&self, other: &Self) -> bool {
        self.cmp(other) == std::cmp::Ordering::Equal
    }
}
impl Eq for Candidate {}
impl PartialOrd for Candidate {
    fn partial_cmp(&self, other: &Self) -> Option<std::cmp::Ordering> {
        Some(self.cmp(other))
    }
}
impl Ord for Candidate {
    /// Reversed (the heap's top is the earliest; ties: the lower pair).
    fn cmp(&self, other: &Self) -> std::cmp::Ordering {
        other.time.total_cmp(&self.time).then(other.pair.cmp(&self.pair))
    }
}

/// The run's state and scratch buffers.
struct Stepper<'s> {
    scene: &'s Scene,
    /// Integrated bodies' states (others: `None`).
    states: Vec<Option<RigidState>>,
    /// Integrated bodies' initial energy and energy scale.
    energies: Vec<(Real, Real)>,
    /// Each body's motion over the current step.
    motions: Vec<StepMotion>,
    /// The pairs in play, sorted by `(a, b)`: all pairs not both fixed,
    /// or with a broad phase the pairs whose swept boxes overlap.
    pairs: Vec<PairState>,
    /// The broad phase, for scenes of more than two bodies.
    broad: Option<BroadPhase>,
    /// The swept boxes of the current step.
    boxes: Vec<SweptBox>,
    /// Run the pairs' CCD on several threads.
    parallel: bool,
    /// `on_contact: Bounce`'s coefficient of restitution.
    restitution: Option<Real>,
    scratch: MeshDistanceScratch,
    /// The CCD results of a step (a buffer kept between steps).
    results: Vec<PairOutcome>,
    /// The previous step's pairs (a buffer kept between steps).
    spare_pairs: Vec<PairState>,
    /// The integrated states of a step and whether their solve converged
    /// (a buffer kept between steps).
    advanced: Vec<Option<(RigidState, bool)>>,
    contacts: Vec<Contact>,
    trace: Vec<TraceRecord>,
    counters: Counters,
}

impl<'s> Stepper<'s> {
    fn new(scene: &'s Scene, options: RunOptions) -> Stepper<'s> {
        let bouncing = matches!(scene.on_contact, OnContact::Bounce { .. });
        let states = scene
            .bodies
            .iter()
            .map(|body| {
                // A bounce can stop a kinematic body: it needs a state too.
                let needs_state = match body.motion {
                    BodyMotion::Integrated(_) => true,
                    BodyMotion::Free => bouncing,
                    BodyMotion::Fixed => false,
                };
                needs_state.then(|| RigidState {
                    position: Point::from(body.pose.translation.vector),
                    orientation: body.pose.rotation,
                    velocity: body.velocity,
                    angular_velocity: body.angular_velocity,
                })
            })
            .collect();
        let energies = scene
            .bodies
            .iter()
            .zip(&states)
            .map(|(body, state): (&crate::scene::Body, &Option<RigidState>)| {
                match (&body.motion, state.as_ref()) {
                    (BodyMotion::Integrated(dynamics), Some(state)) => {
                        (dynamics.energy(state), dynamics.energy_scale(state).max(Real::MIN_POSITIVE))
                    }
                    _ => (0.0, 0.0),
                }
            })
            .collect();
        let broad = (options.broad_phase && scene.bodies.len() > 2).then(BroadPhase::default);
        // With a broad phase the pairs come from it, step by step.
        let pairs = if broad.is_some() {
            Vec::new()
        } else {
            scene.movable_pairs().into_iter().map(|(a, b)| PairState::new(a, b)).collect()
        };
        Stepper {
            scene,
            states,
            energies,
            motions: scene.bodies.iter().map(|b| StepMotion::fixed(b.pose)).collect(),
            pairs,
            broad,
            boxes: Vec::new(),
            parallel: options.parallel,
            restitution: match scene.on_contact {
                OnContact::Bounce { restitution } => Some(restitution),
                _ => None,
            },
            scratch: MeshDistanceScratch::default(),
            results: Vec::new(),
            spare_pairs: Vec::new(),
            advanced: Vec::new(),
            contacts: Vec::new(),
            trace: Vec::new(),
            counters: Counters::default(),
        }
    }

    /// Stage 1: each body's motion over the step starting at `t0`.
    fn integrate(&mut self, step: u64, t0: Real) -> Result<(), Termination> {
        let clock = Instant::now();
        let scene = self.scene;
        // The integrations are independent: on the threads when there are
        // many (each body's step is the same whatever the threads).
        let advance = |(body, state): (&crate::scene::Body, &Option<RigidState>)| match (&body.motion, state)
        {
            (BodyMotion::Integrated(dynamics), Some(state)) => {
                Some(integrate(state, dynamics, scene.integrator, scene.gyroscopic, scene.dt))
            }
            _ => None,
        };
        let mut advanced = std::mem::take(&mut self.advanced);
        if self.parallel && scene.bodies.len() >= PARALLEL_INTEGRATION_BODIES {
            scene.bodies.par_iter().zip(&self.states).map(advance).collect_into_vec(&mut advanced);
        } else {
            advanced.clear();
            advanced.extend(scene.bodies.iter().zip(&self.states).map(advance));
        }
        let result = self.take_integrated(step, t0, &advanced);
        self.advanced = advanced;
        self.counters.integrate_s += clock.elapsed().as_secs_f64();
        result
    }

    /// Stage 1's second half: the bodies' motions from their integrated
    /// states (`advanced`), checked for divergence.
    fn take_integrated(
        &mut self,
        step: u64,
        t0: Real,
        advanced: &[Option<(RigidState, bool)>],
    ) -> Result<(), Termination> {
        let scene = self.scene;
        for (i, body) in scene.bodies.iter().enumerate() {
            self.motions[i] = match &body.motion {
                BodyMotion::Fixed => StepMotion::fixed(body.pose),
                BodyMotion::Free => match &self.states[i] {
                    // Kinematic under `Bounce`: from where the last step left it.
                    Some(state) => StepMotion::new(state.pose(), state.velocity, state.angular_velocity),
                    None => StepMotion::free(&body.pose, body.velocity, body.angular_velocity, t0),
                },
                BodyMotion::Integrated(dynamics) => {
                    let (Some(state), Some((next, converged))) = (self.states[i], advanced[i]) else {
                        continue;
                    };
                    self.counters.gyroscopic_unconverged += usize::from(!converged);
                    let diverged = |reason: String| Termination::Diverged { body: i, step, reason };
                    if !next.is_finite() {
                        return Err(diverged(format!("the state of `{}` is no longer finite (the integration diverged): lower `dt` or pick a more stable integrator", body.name)));
                    }
                    let motion = StepMotion::between(&state.pose(), &next.pose(), scene.dt);
                    let turn = motion.angular_velocity.norm() * scene.dt;
                    if turn >= MAX_TURN_PER_STEP {
                        return Err(diverged(format!("`{}` turned {turn:.3} rad in one step (at most π/2 is allowed, so that the motion within a step is defined): lower `dt`", body.name)));
                    }
                    // Bounces move energy between bodies: the check is
                    // per body, so it is off under `Bounce`.
                    if self.restitution.is_none() {
                        let (initial, scale) = self.energies[i];
                        let energy = dynamics.energy(&next);
                        self.counters.max_energy_drift =
                            self.counters.max_energy_drift.max((energy - initial).abs() / scale);
                        if energy - initial > DIVERGENCE_ENERGY_GROWTH * scale {
                            let time = (step + 1) as Real * scene.dt;
                            let advice = stability_advice(dynamics, scene.integrator, scene.dt);
                            return Err(diverged(format!(
                                "the mechanical energy of `{}` grew from {initial:.3e} to {energy:.3e} by t = {time}: the integration is unstable (or, near its stability limit, far too inaccurate to use). {advice}",
                                body.name
                            )));
                        }
                    }
                    self.states[i] = Some(next);
                    motion
                }
            };
        }
        Ok(())
    }

    /// Stage 2: CCD over every pair for the step starting at `t0`. Returns
    /// whether a new contact was found.
    fn collide(&mut self, t0: Real) -> bool {
        let clock = Instant::now();
        let scene = self.scene;
        if self.broad.is_some() {
            self.select_pairs();
        }
        let broad_s = clock.elapsed().as_secs_f64();
        self.counters.broad_phase_s += broad_s;
        self.counters.candidate_pairs += self.pairs.len();
        // CCD of every pair not already in contact: independent queries, in
        // parallel when there are several, results applied in pair order
        // (so the outcome does not depend on the threads).
        // Under `Bounce` a touching pair is queried too, for coming within
        // half its distance (`pair_options`).
        let bouncing = self.restitution.is_some();
        let work: Vec<usize> =
            (0..self.pairs.len()).filter(|&k| bouncing || self.pairs[k].touching.is_none()).collect();
        let motions = &self.motions;
        let pairs = &self.pairs;
        let query = |k: usize, scratch: &mut MeshDistanceScratch| {
            let pair = &pairs[k];
            let moving = |i: usize| MovingMesh { mesh: &scene.bodies[i].mesh, motion: &motions[i] };
            let mut result = mesh_time_of_impact(
                moving(pair.a),
                moving(pair.b),
                scene.dt,
                &pair_options(scene, pair),
                scene.kernel,
                pair.lower_bound,
                pair.hint,
                scratch,
            );
            if result.status == CcdStatus::InitiallyTouching && t0 > 0.0 {
                // A pair new to the broad phase, touching at the step's start.
                result.status = CcdStatus::Converged;
            }
            PairOutcome::from(result)
        };
        // Results go into a buffer kept between steps, and each thread keeps
        // its own scratch: a step allocates nothing once they have grown.
        let mut results = std::mem::take(&mut self.results);
        if self.parallel && work.len() > 1 {
            work.par_iter()
                .map(|&k| THREAD_SCRATCH.with(|scratch| query(k, &mut scratch.borrow_mut())))
                .collect_into_vec(&mut results);
        } else {
            results.clear();
            let scratch = &mut self.scratch;
            results.extend(work.iter().map(|&k| query(k, scratch)));
        }
        let mut found = false;
        let mut candidates = std::collections::BinaryHeap::new();
        let mut found_results = HashMap::new();
        for (&k, outcome) in work.iter().zip(&mut results) {
            let pair = &mut self.pairs[k];
            let result = outcome.summary;
            self.counters.distance_queries += result.iterations;
            self.counters.triangle_pairs += result.triangle_pairs;
            self.counters.pairs_culled += usize::from(result.iterations == 0);
            pair.hint = result.hint;
            pair.lower_bound = Some(result.end_lower_bound);
            let Some(contact) = outcome.contact.take() else { continue };
            let Some(time) = contact.time_of_impact else { continue };
            if bouncing && time == 0.0 && self.pairs[k].touching.is_some() && !self.approaching(k, &contact) {
                // A pair that bounced and is moving apart, still within the
                // tolerance floor of that contact at the step's start: not a
                // new contact (taking it would hold both bodies still at
                // every step). Approaching, it bounces again.
                continue;
            }
            if bouncing {
                candidates.push(Candidate { time, pair: k, version: 0 });
                found_results.insert(k, *contact);
                continue;
            }
            found = true;
            self.record_contact(k, t0, time, &contact);
        }
        self.results = results;
        if bouncing {
            found = self.bounce(t0, candidates, found_results);
        }
        if found && scene.on_contact == OnContact::Stop {
            // Keep only the earliest contact (ties: the first pair).
            let first = self.contacts.iter().cloned().min_by(|a, b| a.time.total_cmp(&b.time));
            self.contacts = first.into_iter().collect();
        }
        self.counters.ccd_s += clock.elapsed().as_secs_f64() - broad_s;
        found
    }

    /// Records the contact of pair `k` at `time` into the step starting at
    /// `t0` and marks the pair touching.
    fn record_contact(&mut self, k: usize, t0: Real, time: Real, result: &MeshCcdResult) {
        let Some(closest) = result.closest else { return };
        let pair = &mut self.pairs[k];
        pair.touching =
            Some(Touching { contact_distance: result.contact_distance, distance: closest.distance });
        pair.lower_bound = None;
        self.contacts.push(Contact {
            time: t0 + time,
            body_a: pair.a,
            body_b: pair.b,
            distance: closest.distance,
            point_a: closest.point_a,
            point_b: closest.point_b,
            triangle_a: closest.triangle_a,
            triangle_b: closest.triangle_b,
            feature_a: closest.feature_a,
            feature_b: closest.feature_b,
            status: result.status,
            contact_distance: result.contact_distance,
        });
    }

    /// `on_contact: Bounce`: takes the step's candidate contacts in time
    /// order. A contact is committed only if neither body has stopped
    /// before it; both bodies then stop there for the rest of the step, and
    /// every other pair of theirs is queried again from that time with the
    /// stopped body held still (its earlier candidates become stale), so no
    /// body moves past a contact with a body that stopped. At the end, the
    /// committed contacts' impulses are applied in time order and each
    /// body's state moves to where it stopped (or to the step's end).
    /// Returns whether a contact was committed.
    fn bounce(
        &mut self,
        t0: Real,
        mut candidates: std::collections::BinaryHeap<Candidate>,
        mut results: HashMap<usize, MeshCcdResult>,
    ) -> bool {
        let scene = self.scene;
        let dt = scene.dt;
        let fixed = |i: usize| scene.bodies[i].motion == BodyMotion::Fixed;
        let mut stopped: Vec<Option<Real>> = vec![None; scene.bodies.len()];
        let mut versions = vec![0u32; self.pairs.len()];
        let mut committed = Vec::new();
        while let Some(candidate) = candidates.pop() {
            let k = candidate.pair;
            if candidate.version != versions[k] {
                continue;
            }
            let Some(result) = results.remove(&k) else { continue };
            let time = candidate.time;
            self.record_contact(k, t0, time, &result);
            committed.push(self.contacts.len() - 1);
            let (a, b) = (self.pairs[k].a, self.pairs[k].b);
            for body in [a, b] {
                if fixed(body) || stopped[body].is_some() {
                    continue;
                }
                stopped[body] = Some(time);
                // Every other pair of this body: again from `time`.
                let partners: Vec<usize> = (self.pairs.iter().enumerate())
                    .filter(|&(other, pair)| other != k && (pair.a == body || pair.b == body))
                    .map(|(other, _)| other)
                    .collect();
                for other in partners {
                    let pair = self.pairs[other].clone();
                    versions[other] += 1;
                    results.remove(&other);
                    self.pairs[other].lower_bound = None;
                    let held = |i: usize| match stopped[i] {
                        Some(at) => StepMotion::fixed(self.motions[i].pose_at(at)),
                        None => StepMotion { elapsed: self.motions[i].elapsed + time, ..self.motions[i] },
                    };
                    let (ma, mb) = (held(pair.a), held(pair.b));
                    if stopped[pair.a].is_some() && stopped[pair.b].is_some() {
                        continue;
                    }
                    let result = mesh_time_of_impact(
                        MovingMesh { mesh: &scene.bodies[pair.a].mesh, motion: &ma },
                        MovingMesh { mesh: &scene.bodies[pair.b].mesh, motion: &mb },
                        dt - time,
                        &pair_options(scene, &pair),
                        scene.kernel,
                        None,
                        pair.hint,
                        &mut self.scratch,
                    );
                    self.counters.distance_queries += result.iterations;
                    self.counters.triangle_pairs += result.triangle_pairs;
                    if let Some(after) = result.time_of_impact {
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
        // Impulses in time order, at the bodies' poses at contact.
        let restitution = self.restitution.unwrap_or(1.0);
        for &c in &committed {
            let contact = self.contacts[c].clone();
            let time = contact.time - t0;
            let (a, b) = (contact.body_a, contact.body_b);
            let mut sides = [a, b].map(|i| self.impact_body(i, stopped[i].unwrap_or(time).min(time)));
            let (point, normal) = contact_frame(&contact.point_a, &contact.point_b, &sides[0], &sides[1]);
            let [side_a, side_b] = &mut sides;
            apply_impulse(side_a, side_b, &point, &normal, restitution);
            for (i, side) in [(a, sides[0]), (b, sides[1])] {
                if let Some(state) = self.states[i].as_mut() {
                    if side.inverse_mass > 0.0 {
                        state.velocity = side.velocity;
                        state.angular_velocity = side.angular_velocity;
                    }
                }
            }
        }
        // Stopped bodies stay where they stopped.
        for (i, at) in stopped.iter().enumerate() {
            let Some(at) = *at else { continue };
            let pose = self.motions[i].pose_at(at);
            if let Some(state) = self.states[i].as_mut() {
                state.position = Point::from(pose.translation.vector);
                state.orientation = pose.rotation;
            }
            self.motions[i] = StepMotion::fixed(pose);
        }
        // Kinematic bodies that did not stop reach the step's end.
        for (i, body) in scene.bodies.iter().enumerate() {
            if body.motion == BodyMotion::Free && stopped[i].is_none() {
                if let Some(state) = self.states[i].as_mut() {
                    let pose = self.motions[i].pose_at(dt);
                    state.position = Point::from(pose.translation.vector);
                    state.orientation = pose.rotation;
                }
            }
        }
        !committed.is_empty()
    }

    /// Whether the closest points of pair `k`'s contact at the step's start
    /// approach each other.
    fn approaching(&self, k: usize, contact: &MeshCcdResult) -> bool {
        let Some(closest) = contact.closest else { return true };
        let pair = &self.pairs[k];
        let (a, b) = (self.impact_body(pair.a, 0.0), self.impact_body(pair.b, 0.0));
        let (point, normal) = contact_frame(&closest.point_a, &closest.point_b, &a, &b);
        approach_speed(&a, &b, &point, &normal) < 0.0
    }

    /// Body `i` at time `s` into the current step.
    fn state_at(&self, i: usize, s: Real) -> RigidState {
        let motion = &self.motions[i];
        let pose = motion.pose_at(s);
        let (velocity, angular_velocity) = match &self.states[i] {
            Some(state) => (state.velocity, state.angular_velocity),
            None => (motion.velocity, motion.angular_velocity),
        };
        RigidState {
            position: Point::from(pose.translation.vector),
            orientation: pose.rotation,
            velocity,
            angular_velocity,
        }
    }

    /// Body `i` at time `s` into the step, for an impulse.
    fn impact_body(&self, i: usize, s: Real) -> ImpactBody {
        let body = &self.scene.bodies[i];
        let state = self.state_at(i, s);
        let pushable = matches!(body.motion, BodyMotion::Integrated(_));
        let rotation = state.orientation.to_rotation_matrix().into_inner();
        let inverse_inertia = match body.inertia.and_then(|inertia| inertia.try_inverse()) {
            Some(inverse) if pushable => rotation * inverse * rotation.transpose(),
            _ => nalgebra::Matrix3::zeros(),
        };
        ImpactBody {
            center: state.position,
            inverse_mass: if pushable { body.mass.map_or(0.0, |m| 1.0 / m) } else { 0.0 },
            inverse_inertia,
            velocity: state.velocity,
            angular_velocity: state.angular_velocity,
        }
    }

    /// The broad phase: keeps the states of the pairs whose swept boxes
    /// overlap this step (new pairs start fresh; a pair that left the set
    /// was apart for a whole step, so it is re-armed).
    fn select_pairs(&mut self) {
        let scene = self.scene;
        let (tolerance, separation) = (scene.ccd.distance_tolerance, scene.ccd.minimum_separation);
        self.boxes.clear();
        for (body, motion) in scene.bodies.iter().zip(&self.motions) {
            let radius = body.mesh.radius();
            // Each box grows by at least its share of any pair's contact
            // distance (and a rounding margin).
            let reach = motion.center_at(0.0).coords.amax() + motion.travel(scene.dt) + radius;
            let margin =
                separation + 2.0 * tolerance * radius + BROAD_PHASE_ROUNDING_ULPS * Real::EPSILON * reach;
            self.boxes.push(swept_box(motion, radius, scene.dt, margin));
        }
        let Some(broad) = self.broad.as_mut() else { return };
        let candidates = broad.pairs(&self.boxes);
        let fixed = |i: usize| scene.bodies[i].motion == BodyMotion::Fixed;
        // The new pairs go into the previous step's spare buffer.
        let mut old = std::mem::replace(&mut self.pairs, std::mem::take(&mut self.spare_pairs));
        self.pairs.clear();
        self.pairs.reserve(candidates.len());
        let mut next_old = 0;
        for (a, b) in candidates.into_iter().filter(|&(a, b)| !(fixed(a) && fixed(b))) {
            while old.get(next_old).is_some_and(|p| (p.a, p.b) < (a, b)) {
                next_old += 1;
            }
            match old.get(next_old) {
                Some(p) if (p.a, p.b) == (a, b) => {
                    self.pairs.push(p.clone());
                    next_old += 1;
                }
                _ => self.pairs.push(PairState::new(a, b)),
            }
        }
        old.clear();
        self.spare_pairs = old;
    }

    /// Stage 3: re-arm pairs that separated, and sample the trace.
    fn end_step(&mut self, step: u64, t0: Real) {
        let scene = self.scene;
        let dt = scene.dt;
        for pair in &mut self.pairs {
            let Some(Touching { contact_distance, .. }) = pair.touching else { continue };
            let pos_ab = StepMotion::relative_pose(&self.motions[pair.a], &self.motions[pair.b], dt);
            let (mesh_a, mesh_b) = (&scene.bodies[pair.a].mesh, &scene.bodies[pair.b].mesh);
            let d = mesh_distance_relative(
                mesh_a,
                mesh_b,
                &pos_ab,
                scene.kernel,
                pair.hint,
                // Only "beyond twice the contact distance?" is asked: the
                // search may stop at the first pair within it.
                REARM_DISTANCE_FACTOR * contact_distance,
                &mut self.scratch,
            );
            self.counters.distance_queries += 1;
            if d.distance > REARM_DISTANCE_FACTOR * contact_distance {
                pair.touching = None;
                pair.lower_bound = Some(d.distance);
            }
        }
        let Some(trace) = &scene.trace else { return };
        let done = step + 1;
        if done % trace.every == 0 || done == scene.steps {
            self.record_trace(done, t0 + dt, dt);
        }
    }

    /// Appends one trace sample per traced pair, at time `s` into the
    /// current step (`time` in all).
    fn record_trace(&mut self, step: u64, time: Real, s: Real) {
        let Some(trace) = &self.scene.trace else { return };
        let clock = Instant::now();
        let scene = self.scene;
        for &(a, b) in &trace.pairs {
            let pos_ab = StepMotion::relative_pose(&self.motions[a], &self.motions[b], s);
            let (mesh_a, mesh_b) = (&scene.bodies[a].mesh, &scene.bodies[b].mesh);
            let d =
                mesh_distance_relative(mesh_a, mesh_b, &pos_ab, scene.kernel, None, 0.0, &mut self.scratch);
            self.counters.distance_queries += 1;
            let reference = trace.reference.then(|| {
                let exact = mesh_distance_relative(
                    mesh_a,
                    mesh_b,
                    &pos_ab,
                    DistanceKernel::Exact,
                    None,
                    0.0,
                    &mut self.scratch,
                );
                // The closest pair as the kernels see it: b in a's frame.
                let tb = mesh_b.triangle(exact.triangle_b).map(|p| pos_ab * p);
                crate::exact::triangle_distance_f64(&mesh_a.triangle(exact.triangle_a), &tb)
            });
            self.trace.push(TraceRecord { step, time, pair: (a, b), distance: d.distance, reference });
        }
        self.counters.trace_s += clock.elapsed().as_secs_f64();
    }
}

/// The CCD options of a pair: the scene's, or for a pair touching under
/// `on_contact: Bounce`, a contact distance of half its distance at contact
/// (it is moving apart; coming closer again is a new contact).
fn pair_options(scene: &Scene, pair: &PairState) -> CcdOptions {
    match (scene.on_contact, pair.touching) {
        (OnContact::Bounce { .. }, Some(touching)) => {
            let size = scene.bodies[pair.a].mesh.radius() + scene.bodies[pair.b].mesh.radius();
            CcdOptions {
                distance_tolerance: BOUNCE_REDETECT_FRACTION * touching.distance / size,
                minimum_separation: 0.0,
                ..scene.ccd
            }
        }
        _ => scene.ccd,
    }
}

//! The time-stepper: each fixed step runs the stages below in order, one
//! file or folder each, each timed by its counter ([`Counters`]):
//!
//! 1. **integrate** (`integrate.rs`): each body's motion over the step (or,
//!    under `Simulate`, rapier's step read back as motions: `crate::guard`);
//! 2. **broad phase** (`broad.rs`): the pairs whose swept boxes overlap
//!    (scenes of more than two bodies; with two, the one pair is queried);
//! 3. **narrow phase** (`narrow.rs`): the CCD of every pair in play, on
//!    rayon's threads when it is long enough to gain from them
//!    (`threads.rs`), results in pair order (a run is the same whatever the
//!    threads); with `near_misses`, each pair's screen runs first, and a
//!    pair it proves farther than the contact distance over the step is not
//!    asked again;
//! 4. **respond** (`respond/`): what the scene's `on_contact` does with the
//!    contacts found (stop, record, bounce), then the near misses' screens
//!    up to the contacts and their brackets;
//! 5. **re-arm** (`rearm.rs`): touching pairs that separated are armed again;
//! 6. **observe** (`observe/`): the distance trace, the poses and the near
//!    misses, each when the scene asks for it.
//!
//! A run's steps are made by a driver (`driver.rs`): the stepper's own
//! integration (`Stop`, `Record`, `Bounce`) or rapier guarded by nearmiss
//! (`Simulate`: rapier steps, the guard runs stages 2 to 5 on its motions,
//! rewinding to a contact where rapier would let a pair through, then
//! stage 6). The loop around it is [`crate::run`](mod@crate::run), on top.
//!
//! The world state (bodies' states and motions, pairs, contacts:
//! `world.rs`) is passed to each stage; the `Stepper` owns only the run's
//! set-up and scratch buffers. A scene gets only the stages it needs: fixed
//! bodies are never integrated and a pair of fixed bodies never queried;
//! free bodies (nothing acting on them) move exactly; there is no tree for
//! two bodies and no trace unless asked for.

mod broad;
mod driver;
mod found;
mod integrate;
mod kept;
mod narrow;
pub(crate) mod observe;
mod options;
mod rearm;
pub(crate) mod respond;
mod result;
mod threads;
mod world;

use std::sync::Arc;
use std::time::Instant;

pub(crate) use driver::{Driver, StepEnd};
pub(crate) use found::{pair_query, CcdVerdict, Found};
pub use observe::near_miss::NearMiss;
pub use observe::poses::{write_poses_csv, PoseRecord};
pub use observe::trace::{write_trace_csv, TraceRecord};
pub use options::RunOptions;
pub use result::{Contact, Counters, RunResult, Solver, StageSeconds, Termination, Work};
#[cfg(feature = "rapier")]
pub(crate) use world::GuardHit;
#[cfg(test)]
pub(crate) use world::Touching;
pub(crate) use world::{PairState, World};

use crate::broad_phase::{BroadPhase, SweptBox};
use crate::ccd::MeshCcdScratch;
use crate::math::Real;
use crate::mesh::TriMesh;
use crate::scene::{Body, BodyMotion, Model, RunSpec, Scene};
use observe::near_miss::NearMissObserver;
use observe::poses::PoseObserver;
use observe::trace::TraceObserver;
use respond::{Response, StepContext};
use threads::Batches;

/// The stepper integrating the scene's bodies itself (`Stop`, `Record`,
/// `Bounce`).
pub(crate) struct Integrated {
    stepper: Stepper,
    world: World,
    /// The scene's name.
    name: String,
}

impl Driver for Integrated {
    fn start(&mut self) {
        self.stepper.observe_start(&self.world);
    }

    fn step(&mut self, step: u64) -> Result<StepEnd, Termination> {
        let Integrated { stepper, world, .. } = self;
        if stepper.options.parallel && rayon::current_thread_index().is_none() {
            // The step is handed to rayon's threads once: made from here,
            // each of its parallel stages would hand its work over and
            // wait for it (a wake-up and a sleep of two threads each). A
            // step of many bodies keeps the other threads awake as well;
            // a caller stepping from rayon's own threads schedules them.
            let awake = stepper.model.bodies.len() >= threads::AWAKE_STEP_BODIES;
            rayon::scope(|_| stepper.step(world, step, awake))
        } else {
            stepper.step(world, step, false)
        }
    }

    fn finish(self: Box<Self>, steps: u64, termination: Termination, start: Instant) -> RunResult {
        let Integrated { stepper, world, name } = *self;
        stepper.finish(world, name, steps, termination, start)
    }
}

impl Integrated {
    /// The stepper's own integration of `scene` (`Stop`, `Record`,
    /// `Bounce`); `None` under `Simulate`, whose steps rapier makes.
    pub(crate) fn of(scene: &Scene, options: RunOptions) -> Option<Integrated> {
        let response = respond::for_model(&scene.model)?;
        let mut stepper =
            Stepper::with_response(Arc::new(scene.model.clone()), Some(&scene.run), options, response);
        // Its own integration never moves a body that stays put (fixed, or
        // free at rest): passed over in the integration, boxed once.
        stepper.still = scene.model.bodies.iter().map(Body::stays_put).collect();
        stepper.fixed_apart = stepper.broad.as_ref().and_then(|_| broad::FixedApart::of(&scene.model));
        let world = stepper.new_world(stepper.response.stops_kinematic_bodies());
        Some(Integrated { stepper, world, name: scene.run.name.clone() })
    }
}

/// Each body's mesh as an index into the run's distinct meshes, for the
/// broad phase: a body's mesh found from its 4-byte index rather than from
/// the body itself (296 bytes, read at random for the bodies a crowded
/// step boxes again).
pub(crate) struct BodyMeshes {
    ids: Vec<u32>,
    meshes: Vec<Arc<TriMesh>>,
}

impl BodyMeshes {
    /// The meshes of `model`'s bodies, each distinct mesh's farthest-vertex
    /// table built now: the CCD's hull steps read it, and the first of them
    /// near the mesh otherwise builds it (in a scene of many bodies nearly
    /// every mesh comes near another, and the step in which they first did
    /// took up to a millisecond longer, on one thread, in the middle of a
    /// run). On rayon's threads when `parallel`, a mesh each.
    fn of(model: &Model, parallel: bool) -> BodyMeshes {
        let mut meshes: Vec<&Arc<TriMesh>> = model.bodies.iter().map(|b| &b.mesh).collect();
        meshes.sort_unstable_by_key(|mesh| Arc::as_ptr(mesh));
        meshes.dedup_by_key(|mesh| Arc::as_ptr(mesh));
        let place = |mesh: &Arc<TriMesh>| {
            meshes.binary_search_by_key(&Arc::as_ptr(mesh), |m| Arc::as_ptr(m)).expect("a body's mesh") as u32
        };
        let ids = model.bodies.iter().map(|b| place(&b.mesh)).collect();
        let meshes: Vec<Arc<TriMesh>> = meshes.into_iter().cloned().collect();
        let prepare = |mesh: &Arc<TriMesh>| mesh.prepare_farthest_vertex();
        if parallel {
            use rayon::prelude::*;
            meshes.par_iter().for_each(prepare);
        } else {
            meshes.iter().for_each(prepare);
        }
        BodyMeshes { ids, meshes }
    }

    /// Body `i`'s mesh.
    #[inline]
    pub(crate) fn of_body(&self, i: usize) -> &TriMesh {
        &self.meshes[self.ids[i] as usize]
    }
}

/// A run's set-up and scratch buffers (the world state is passed in).
pub(crate) struct Stepper {
    /// What is simulated.
    model: Arc<Model>,
    options: RunOptions,
    /// What happens at contact.
    response: Box<dyn Response>,
    /// The broad phase, for scenes of more than two bodies.
    broad: Option<BroadPhase>,
    /// The bodies' meshes, with the broad phase.
    body_meshes: Option<BodyMeshes>,
    /// The fixed bodies' boxes, made once, in the stepper's own
    /// integration of a scene with many fixed bodies (under a guard, an
    /// engine may move a fixed body: every box is made each step).
    fixed_apart: Option<broad::FixedApart>,
    /// The bodies' kept boxes, in a run of many bodies (`kept.rs`).
    kept: Option<kept::KeptBoxes>,
    /// Whether each body is still: fixed (under a guard), or one that stays
    /// put (in the stepper's own integration: fixed, or free at rest). The
    /// integration passes over them without reading them.
    still: Vec<bool>,
    /// The bodies that move in the stepper's own integration without being
    /// integrated (free, not still), found at its first step.
    movers: Option<Vec<usize>>,
    /// Whether each body's step is a steady spin's, found at the first
    /// step (`integrate.rs`).
    steady: Option<Vec<bool>>,
    /// The trace, when the scene asks for one.
    trace: Option<TraceObserver>,
    /// The pose record, when the scene asks for one.
    poses: Option<PoseObserver>,
    /// The near misses, when the scene asks for them.
    near_misses: Option<NearMissObserver>,
    scratch: Scratch,
    counters: Counters,
    /// Added to every swept box's margin: half the smallest separation any
    /// pair's query asks for beyond the scene's (the guard's contact skins,
    /// the near misses' distance).
    extra_box_margin: Real,
}

/// Buffers kept between steps, so that a step allocates nothing once they
/// have grown.
#[derive(Default)]
struct Scratch {
    /// The CCD's scratch (also lent to the re-arm stage's distances).
    ccd: MeshCcdScratch,
    /// The swept boxes of the current step.
    boxes: Vec<SweptBox>,
    /// The broad phase's candidate pairs of the current step.
    candidates: Vec<(usize, usize)>,
    /// The previous step's pairs.
    spare_pairs: Vec<PairState>,
    /// The pairs queried in the narrow phase (indices into the pairs).
    work: Vec<usize>,
    /// Whether the narrow phase's queries go on rayon's threads.
    batches: Batches,
    /// The narrow phase's results.
    results: Vec<narrow::PairOutcome>,
    /// The contacts found in a step.
    found: Vec<Found>,
    /// The buffers of a response that stops bodies in time order.
    stops: respond::Stops,
    /// The integrated bodies' velocities at the step's start.
    saved: integrate::SavedVelocities,
}

impl Stepper {
    /// A stepper of `model` whose contacts go to `response` (the scene's,
    /// or the guard's clamp), with the observers `run` asks for (none
    /// without a run: a guard of rapier bodies).
    pub(crate) fn with_response(
        model: Arc<Model>,
        run: Option<&RunSpec>,
        options: RunOptions,
        response: Box<dyn Response>,
    ) -> Stepper {
        let broad = (options.broad_phase && model.bodies.len() > 2).then(BroadPhase::default);
        Stepper {
            options,
            response,
            body_meshes: broad.as_ref().map(|_| BodyMeshes::of(&model, options.parallel)),
            broad,
            fixed_apart: None,
            kept: None,
            still: model.bodies.iter().map(|b| b.motion == BodyMotion::Fixed).collect(),
            movers: None,
            steady: None,
            trace: run.and_then(|run| {
                TraceObserver::of(&model, run, options.parallel.then_some(options.parallel_trace_pairs))
            }),
            poses: run
                .and_then(|run| run.poses.as_ref().map(|spec| PoseObserver::new(spec.every, run.steps))),
            near_misses: run.and_then(|run| {
                run.near_misses.as_ref().map(|spec| {
                    NearMissObserver::new(
                        spec,
                        options.parallel,
                        options.parallel_narrow_phase_seconds,
                        (model.bodies.len(), options.parallel_integration_bodies),
                    )
                })
            }),
            scratch: Scratch {
                batches: Batches::new(options.parallel, options.parallel_narrow_phase_seconds),
                ..Scratch::default()
            },
            counters: Counters::default(),
            // The near misses' pairs must be candidates: boxes grown by half
            // their distance.
            extra_box_margin: run
                .and_then(|run| run.near_misses.as_ref())
                .map_or(0.0, |spec| 0.5 * spec.within),
            model,
        }
    }

    /// One step (0-based `step`) of the stepper's own integration: the
    /// stages in order. (Under a guard, rapier makes the motions and the
    /// guard calls [`Stepper::sweep`] and [`Stepper::observe_step_end`].)
    /// With `awake`, rayon's other threads keep looking for work during
    /// stages 1 to 5 ([`threads::awake_while`]); the observers (whose
    /// near-miss brackets may run on another thread while the next step
    /// does) come after.
    fn step(&mut self, world: &mut World, step: u64, awake: bool) -> Result<StepEnd, Termination> {
        let t0 = step as Real * self.model.dt;
        let mut stages = || {
            self.integrate(world, step, t0)?;
            self.sweep(world, step)
        };
        let end = if awake { threads::awake_while(stages)? } else { stages()? };
        if let StepEnd::Continue = end {
            self.observe_step_end(world, step);
        }
        Ok(end)
    }

    /// Stages 2 to 5 of step `step` (no observers): the guard sweeps a step
    /// in several parts when it rewinds, and observes its end once.
    pub(crate) fn sweep(&mut self, world: &mut World, step: u64) -> Result<StepEnd, Termination> {
        let t0 = step as Real * self.model.dt;
        world.separated.clear();
        world.stops.clear();
        world.rewind = None;
        self.broad_phase(world);
        // The near misses screen the integrated motions first: a pair they
        // prove apart over the step the narrow phase need not ask again.
        // Their stage is timed by one clock across the step, less the
        // stages in between (reading a clock is not free: on a two-body
        // scene, whose steps are short, a second one would show).
        let seconds_between = |s: &StageSeconds| s.ccd + s.respond;
        let near_clock =
            self.near_misses.is_some().then(|| (Instant::now(), seconds_between(&self.counters.seconds)));
        if let Some(near_misses) = self.near_misses.as_mut() {
            near_misses.screen_step(&self.model, t0, &world.pairs, &world.motions);
        }
        let mut found = std::mem::take(&mut self.scratch.found);
        self.narrow_phase(world, t0, &mut found);
        // The rest of their step goes up to the step's contacts (known
        // after the response, which may find more).
        let contacts_before = world.contacts.len();
        let contact = self.respond(world, t0, &mut found);
        self.scratch.found = found;
        if let Some(near_misses) = self.near_misses.as_mut() {
            let contacts =
                world.contacts[contacts_before..].iter().map(|c| ((c.body_a, c.body_b), c.time - t0));
            near_misses.observe_step(&self.model, contacts);
        }
        if let Some((clock, before)) = near_clock {
            let between = seconds_between(&self.counters.seconds) - before;
            self.counters.seconds.near_misses += (clock.elapsed().as_secs_f64() - between).max(0.0);
        }
        if let Some(undecided) = world.undecided {
            let (a, b) = undecided.pair;
            return Err(Termination::Undecided {
                pair: (a, b),
                time: t0 + undecided.time,
                step,
                iterations: undecided.iterations,
            });
        }
        if contact && self.response.ends_run() {
            return Ok(StepEnd::FirstContact);
        }
        // A sweep the guard will step again from a contact, or sweep again
        // with bodies stopped: its end poses are not where the step ends.
        if world.rewind.is_none() && world.stops.is_empty() {
            self.rearm(world);
        }
        Ok(StepEnd::Continue)
    }

    /// Stage 6 after step `step` (0-based).
    pub(crate) fn observe_step_end(&mut self, world: &World, step: u64) {
        let dt = self.model.dt;
        self.observe(world, step + 1, step as Real * dt + dt);
    }

    /// Stage 4: the response to the contacts found. Returns whether one
    /// was recorded.
    fn respond(&mut self, world: &mut World, t0: Real, found: &mut Vec<Found>) -> bool {
        let clock = Instant::now();
        let mut context = StepContext {
            model: &self.model,
            world,
            scratch: &mut self.scratch.ccd,
            stops: &mut self.scratch.stops,
            counters: &mut self.counters,
            t0,
        };
        let contact = self.response.respond(&mut context, found);
        self.counters.seconds.respond += clock.elapsed().as_secs_f64();
        contact
    }

    /// Stage 6: the trace and the poses after `done` steps, at `time`.
    fn observe(&mut self, world: &World, done: u64, time: Real) {
        if let Some(trace) = self.trace.as_mut() {
            trace.step_done(done, time, &world.motions);
        }
        if let Some(poses) = self.poses.as_mut() {
            poses.step_done(done, time, self.model.dt, &world.motions);
        }
    }

    /// The trace and the poses at the run's start.
    pub(crate) fn observe_start(&mut self, world: &World) {
        if let Some(trace) = self.trace.as_mut() {
            trace.sample(0, 0.0, 0.0, &world.motions);
        }
        if let Some(poses) = self.poses.as_mut() {
            poses.sample(0, 0.0, 0.0, &world.motions);
        }
    }

    /// The world at the scene's start, for this stepper: without a broad
    /// phase, its pairs are every movable pair, once and for all (with one,
    /// the broad phase sets them each step). `kinematic_states`: see
    /// [`World::new`].
    pub(crate) fn new_world(&self, kinematic_states: bool) -> World {
        let mut world = World::new(&self.model, kinematic_states, self.checks_energy());
        if self.broad.is_none() {
            world.pairs = self.model.movable_pairs().into_iter().map(|(a, b)| PairState::new(a, b)).collect();
        }
        world
    }

    /// Whether each integrated body's energy is checked for divergence:
    /// bounces move energy between bodies, so a response that exchanges
    /// momentum turns the (per body) check off.
    pub(crate) fn checks_energy(&self) -> bool {
        !self.response.exchanges_momentum()
    }

    /// Whether pairs come from a broad phase (otherwise [`Stepper::new_world`]
    /// set every movable pair once).
    #[cfg(feature = "rapier")]
    pub(crate) fn has_broad_phase(&self) -> bool {
        self.broad.is_some()
    }

    /// What is simulated.
    #[cfg(feature = "rapier")]
    pub(crate) fn model(&self) -> &Model {
        &self.model
    }

    /// Grows every swept box by `margin` (each body's contact skin).
    #[cfg(feature = "rapier")]
    pub(crate) fn set_extra_box_margin(&mut self, margin: Real) {
        self.extra_box_margin = margin;
    }

    /// The work done so far.
    #[cfg(feature = "rapier")]
    pub(crate) fn counters(&self) -> &Counters {
        &self.counters
    }

    /// The work counters, for an outside engine's stage times.
    #[cfg(feature = "rapier")]
    pub(crate) fn counters_mut(&mut self) -> &mut Counters {
        &mut self.counters
    }

    /// The run's result after `steps` steps.
    pub(crate) fn finish(
        mut self,
        mut world: World,
        name: String,
        steps: u64,
        termination: Termination,
        start: Instant,
    ) -> RunResult {
        let model = Arc::clone(&self.model);
        let model = &*model;
        let end_time = match (&termination, world.contacts.first()) {
            (Termination::FirstContact, Some(contact)) => contact.time,
            // Nothing after an undecided query is known.
            (Termination::Undecided { time, .. }, _) => *time,
            // A diverging step moved no body: the run ends at its start.
            (Termination::Diverged { step, .. }, _) => *step as Real * model.dt,
            _ => steps as Real * model.dt,
        };
        world.contacts.retain(|c| c.time <= end_time);
        let last_step_start = steps.saturating_sub(1) as Real * model.dt;
        let trace = match self.trace.take() {
            Some(mut trace) => {
                if termination == Termination::FirstContact {
                    trace.sample(steps, end_time, end_time - last_step_start, &world.motions);
                }
                self.counters.work.distance_queries += trace.distance_queries;
                self.counters.seconds.trace += trace.seconds;
                self.counters.work.trace_certified += trace.certified;
                trace.into_records()
            }
            None => Vec::new(),
        };
        let poses = match self.poses.take() {
            Some(mut poses) => {
                if termination == Termination::FirstContact {
                    poses.sample(steps, end_time, end_time - last_step_start, &world.motions);
                }
                poses.into_records()
            }
            None => Vec::new(),
        };
        // The motions are those of the last step taken (after a divergence,
        // the step before the one that failed: the bodies are at its end;
        // an integrated body, whose motion was the failed step's, is its
        // state, undone to the failed step's start).
        let diverged = matches!(termination, Termination::Diverged { .. });
        let at = if diverged { model.dt } else { end_time - last_step_start };
        let final_states = (0..model.bodies.len())
            .map(|i| match &world.states[i] {
                Some(state) if diverged && model.bodies[i].is_integrated() => *state,
                _ => world.state_at(i, at),
            })
            .collect();
        // The step's buffers go before the result is built beside them (a
        // third of the run's peak at 100,000 bodies).
        (self.broad, self.body_meshes, self.kept, self.scratch) = (None, None, None, Scratch::default());
        world.release_buffers();
        let near_misses = match self.near_misses.take() {
            Some(observer) => {
                // The steps still held are bracketed now.
                let clock = Instant::now();
                let list = observer.finish(&self.model);
                self.counters.seconds.near_misses += clock.elapsed().as_secs_f64();
                list
            }
            None => Vec::new(),
        };
        let mut contacts = world.contacts;
        contacts
            .sort_by(|a, b| a.time.total_cmp(&b.time).then((a.body_a, a.body_b).cmp(&(b.body_a, b.body_b))));
        RunResult {
            scene: name,
            bodies: model.bodies.iter().map(|b| b.name.clone()).collect(),
            steps,
            end_time,
            wall_time_s: start.elapsed().as_secs_f64(),
            first_contact: contacts.first().cloned(),
            contacts,
            trace,
            poses,
            solver: None,
            termination,
            counters: self.counters,
            final_states,
            near_misses,
            initial_overlaps: Vec::new(),
        }
    }
}

//! Tunnel-free rapier bodies: nearmiss's conservative CCD guarding a rapier
//! simulation (the `rapier` feature, on by default).
//!
//! rapier never sweeps a moving triangle mesh (a mesh bullet passes a thin
//! plate even with CCD on), and it sees a contact only where a pair starts
//! a step within its prediction distance: a body arriving from farther in
//! one step (a bullet, a blade's tip, a fast fall) goes into the other, or
//! through it. A [`Guard`] sweeps every step rapier takes and steps in
//! there, and nowhere else.
//!
//! # What is guaranteed
//!
//! - **Invisible where rapier holds.** Where rapier's own contacts hold a
//!   pair (it rests, slides, rolls, is stacked or pushed, or arrives from
//!   within rapier's prediction distance), the guard only reads: the poses
//!   and velocities are rapier's, step for step, bit for bit. It adds no
//!   contact skin unless asked ([`GuardOptions::skin`]).
//! - **Decisive where rapier would not.** A pair that arrives within a
//!   step, and that rapier's step takes deeper than the pair's tolerated
//!   depth ([`GuardOptions::tolerated_depth`], rapier's allowed linear error
//!   by default, never more than `THIN_BODY_FRACTION` of the thinner
//!   body) or to the far side, is stopped at its contact: the world goes
//!   back to the contact's time and rapier solves the rest of the step from
//!   there (its masses, friction and restitution at the contact; forces act
//!   once; no velocity thrown away). So no mesh passes through another, and
//!   no pair ends a step deeper than its tolerated depth, whatever its speed
//!   or spin (a body turns less than a quarter turn a step: the side tests'
//!   one assumption). A touching pair that rapier's contact lets sink deeper
//!   (a body pushed by a kinematic one) is pushed apart to
//!   `PUSHED_DEPTH_FRACTION` of it at the step's end, back along its own
//!   side if it went through ([`GuardEvent::Overlap`]).
//! - **Never frozen** (the liveness rule beside that safety rule). No body
//!   is held still while rapier moves it: a pair overlapping at a sweep's
//!   start is rapier's, and where the guard must stop a pair (a contact at
//!   the sweep's start, which rapier already stepped from; a pair's second
//!   in a step; the rewinds spent) its dynamic bodies stay at the contact
//!   for the rest of the step with an inelastic impulse there, so their
//!   approach is gone and they move on at the next step, as rapier's own
//!   CCD clamps a body at its time of impact. A body touching a kinematic
//!   one is carried along.
//! - **rapier's own rules.** A pair rapier would not solve is not guarded:
//!   sensors, disabled colliders, collision and solver groups, the bodies'
//!   types (`ActiveCollisionTypes`: two fixed or kinematic bodies), pairs
//!   joined with contacts disabled ([`Guard::honour_joints`]), the
//!   application's pair filter ([`Guard::step_with_hooks`]); a body whose
//!   colliders modify their solver contacts is left to rapier.
//! - Contacts are reported never late ([`GuardEvent::Started`], with
//!   nearmiss's time of impact, points and features). A pair the CCD cannot
//!   decide ends the step with [`GuardError::Undecided`], never a guess.
//!
//! # How
//!
//! [`Guard::step`] steps rapier, then sweeps every guarded pair from the
//! step's start poses to rapier's end poses (a body's motion over a step is
//! the constant linear and angular velocity that takes its start pose to
//! its end pose, the turn nearest rapier's angular velocity) for its first
//! contact (`watch.rs`).
//! - A pair overlapping at the sweep's start is rapier's.
//! - Where another pair touches, a cheap bound decides first whether it
//!   could end the step past its tolerated depth (the overlap along the
//!   contact's directions at the contact and at rapier's end poses, plus
//!   each body's turn; or any point's travel after the contact); only then
//!   are rapier's end poses judged exactly (two convex meshes: the depth by
//!   separating axes, and the side the pair ends on; others count as
//!   failing). If rapier's step stands, the contact is only reported (a
//!   pair rapier saw coming arrives at the step's end and closes no
//!   farther). If not, the world is moved back to the contact (every moving
//!   body to its pose then, velocities interpolated between the step's ends
//!   so that forces act once, the pair woken) and rapier steps the rest of
//!   the step, which is swept again; up to [`GuardOptions::max_substeps`]
//!   times a step; where that cannot help, the pair stops there (above),
//!   and the step is swept again with it stopped.
//! - A pair **touching** stays so until its distance at a step's end
//!   exceeds rapier's prediction distance ([`GuardEvent::Stopped`]). At
//!   each step's end the guard checks its depth (`depth.rs`): convex pairs
//!   along their side (two support lookups; exactly by separating axes only
//!   where that is over the tolerated depth), others by the deepest vertex
//!   where their surfaces cross, once they can have closed that far.
//! - **A kinematic body has infinite mass**: after a rewind to its contact
//!   with a dynamic body, the dynamic body takes an inelastic impulse
//!   there, leaving at least as fast as the kinematic body's point along
//!   the normal.
//! - **Skins, when asked for** ([`GuardOptions::skin`] > 0): each guarded
//!   collider gets a contact skin, rapier rests pairs the two skins apart,
//!   and the guard's wall is the meshes themselves: pairs apart are swept
//!   for coming within the skins, touching pairs for reaching the wall
//!   after a sweep's start. The meshes then never overlap, at the price of
//!   the visible gap (a box on a floor floats the two skins, less what
//!   rapier lets it sink, above it).
//!
//! ```no_run
//! use nearmiss::guard::{Guard, GuardOptions};
//! use rapier3d_f64::prelude::*;
//!
//! let (mut bodies, mut colliders) = (RigidBodySet::new(), ColliderSet::new());
//! // ... insert bodies and mesh colliders ...
//! # let guarded: Vec<RigidBodyHandle> = Vec::new();
//! let parameters = IntegrationParameters::default();
//! let mut guard = Guard::new(&bodies, &mut colliders, &guarded, &parameters, GuardOptions::default())?;
//! # let (mut pipeline, mut islands, mut broad_phase, mut narrow_phase) =
//! #     (PhysicsPipeline::new(), IslandManager::new(), DefaultBroadPhase::default(), NarrowPhase::new());
//! # let (mut impulse_joints, mut multibody_joints, mut soft_bodies, mut ccd) =
//! #     (ImpulseJointSet::new(), MultibodyJointSet::new(), SoftBodySet::new(), CCDSolver::new());
//! for _ in 0..100 {
//!     // rapier's step by `dt`: once per step, again after a rewind.
//!     let events = guard.step(&mut bodies, |bodies, dt| {
//!         pipeline.step(Vector::new(0.0, -9.81, 0.0), &IntegrationParameters { dt, ..parameters },
//!             &mut islands, &mut broad_phase, &mut narrow_phase, bodies, &mut colliders,
//!             &mut impulse_joints, &mut multibody_joints, &mut soft_bodies, &mut ccd, &(), &());
//!     })?;
//!     for event in events {
//!         println!("{event:?} ({} rewinds so far)", guard.rewinds());
//!     }
//! }
//! # Ok::<(), nearmiss::guard::GuardError>(())
//! ```
//!
//! The guard works on the bodies' centres of mass: the mesh it sweeps is the
//! triangles of a body's solid colliders relative to the body's centre of
//! mass (triangle meshes, convex polyhedra, cuboids and heightfields as they
//! are; balls, capsules and cylinders as polyhedra drawn around them, at
//! most `BALL_EXCESS_OF_SKIN` of the skin, or of rapier's allowed error
//! without one, outside, so that the shapes themselves are guarded too; a
//! half-space as a box `HALF_SPACE_EXTENT` length units wide and deep
//! under its plane; compounds part by part). The scene runner's
//! `on_contact: Simulate` is built on the same type.
//!
//! # f32 rapier
//!
//! With the `rapier-f32` feature, `Guard<rapier3d::prelude::RigidBodySet>`
//! guards an f32 rapier3d 0.36 pipeline (bevy_rapier's) with the same
//! logic: every pose and velocity crosses into f64 for the sweep
//! ([`RapierBodies`]), and the step closure takes rapier's `f32` `dt`. The
//! guarantee above then holds for the poses the guard proved; what rapier
//! stores is each rounded to f32, at most half an ulp of its coordinates
//! away (2⁻²⁴ of their size: 6e-5 at 1,000 units), well inside the
//! tolerated depth (0.005) within about 10⁴ units of the origin.

mod act;
mod bodies;
mod build;
mod compare;
mod depth;
mod directions;
mod events;
mod options;
mod parts;
mod rules;
mod shapes;
pub(crate) mod simulate;
mod sweep;
mod thickness;
mod views;
mod watch;

pub use compare::{
    compare_with_rapier, rapier_markdown, run_rapier_alone, RapierAlone, RapierBody, RapierComparison,
    RapierPair,
};

use std::sync::Arc;
use std::time::Instant;

use rapier3d_f64::prelude::RigidBodySet;

pub use bodies::RapierBodies;
pub use parts::{ColliderPart, ContactHooks};
pub use views::{BodyKind, BodyView, ShapePart};

#[cfg(test)]
pub(crate) use shapes::HALF_SPACE_EXTENT;
pub use shapes::{
    circumscribed_ball, collider_for, is_convex, mesh_of_body, ColliderShape, MAX_BALL_SEGMENTS,
};

use crate::math::{Pose, Real, Vector};
use crate::stepper::{Contact, Stepper, Termination, World};
pub(crate) use build::{solved_pairs, GuardSetup};
use depth::{Deep, DepthWatch};
pub use events::{GuardError, GuardEvent};
pub use options::GuardOptions;
pub(crate) use options::{simulate_contact_limit, DEFAULT_MAX_SUBSTEPS, PUSHED_DEPTH_FRACTION};
#[cfg(test)]
pub(crate) use options::{
    BALL_EXCESS_OF_SKIN, DEFAULT_SKIN, DEFAULT_TOLERATED_DEPTH, PARALLEL_NARROW_PHASE_SECONDS,
};
use rules::PairRules;
#[cfg(test)]
pub(crate) use thickness::THIN_BODY_FRACTION;
use views::center_pose;

/// rapier's step by a given `dt` (in f64; [`Guard::step`] hands rapier's
/// own real to the application's closure).
type RapierStep<'a, B> = dyn FnMut(&mut B, Real) + 'a;

/// Guards rapier bodies against tunnelling (see the module). `B`: rapier's
/// body set, `rapier3d_f64`'s or (the `rapier-f32` feature) `rapier3d`'s.
pub struct Guard<B: RapierBodies = RigidBodySet> {
    /// The guarded bodies, in the guard's order.
    handles: Vec<B::Handle>,
    /// Each body's centre of mass in its body frame.
    centers: Vec<Vector>,
    /// Per body: whether the guard may stop it at a contact (dynamic bodies;
    /// none for `--compare rapier`'s watcher).
    stoppable: Vec<bool>,
    /// The poses of the centres of mass at the sweep's start.
    start: Vec<Pose>,
    /// The dynamic bodies' velocities at the sweep's start (linear,
    /// angular).
    velocities: Vec<(Vector, Vector)>,
    started: bool,
    pub(crate) stepper: Stepper,
    pub(crate) world: World,
    /// Steps guarded since the guard's bodies or `dt` were last set.
    step: u64,
    /// Steps guarded before that, and the time they took.
    steps_before: u64,
    time_before: Real,
    dt: Real,
    max_substeps: usize,
    /// The deepest overlap the guard lets rapier take pairs to.
    tolerated_depth: Real,
    /// Each body's thickness (a pair's tolerated depth is at most
    /// [`THIN_BODY_FRACTION`] of its thinner body's).
    thickness: Arc<[Real]>,
    /// Which pairs rapier solves (the guard's response has the same).
    solved: Arc<PairRules>,
    /// The depth watch of touching pairs (`None`: a watcher that moves
    /// nothing, `--compare rapier`'s).
    depth: Option<DepthWatch>,
    /// The pairs the depth watch found too deep in the step.
    deep: Vec<Deep>,
    /// The options [`Guard::new`] was given (for
    /// [`set_bodies`](Guard::set_bodies)); `None` for the scene runner's.
    options: Option<GuardOptions>,
    /// Rewinds so far (rapier solving again from a contact).
    rewinds: u64,
    events: Vec<GuardEvent<B::Handle>>,
    /// The last step's undecided query, as the stepper reported it.
    pub(crate) undecided: Option<Termination>,
}

impl<B: RapierBodies> Guard<B> {
    /// The time guarded so far (the steps' `dt`s added up).
    pub fn time(&self) -> Real {
        self.time_before + self.step as Real * self.dt
    }

    /// One guarded step: `rapier_step(bodies, dt)` steps rapier by `dt`
    /// (your `PhysicsPipeline::step` with `IntegrationParameters::dt` set to
    /// it; `dt` in rapier's real, `f32` for rapier3d). The guard sweeps the
    /// step; where a pair arrives that rapier would let too deep or through
    /// (see the module), it moves the world back to the contact's time and
    /// calls `rapier_step` again for the rest of the step, so that rapier
    /// solves the contact where it happens (up to
    /// [`GuardOptions::max_substeps`] times; then the arrival's dynamic
    /// bodies are held at it). Returns the step's events, which borrow
    /// nothing: the guard's counters can be read beside them.
    pub fn step<F>(
        &mut self,
        bodies: &mut B,
        mut rapier_step: F,
    ) -> Result<Vec<GuardEvent<B::Handle>>, GuardError<B::Handle>>
    where
        F: FnMut(&mut B, B::Scalar),
    {
        let clock = Instant::now();
        self.before_step(bodies);
        let engine = Instant::now();
        rapier_step(bodies, B::scalar(self.dt));
        let seconds = &mut self.stepper.counters_mut().seconds;
        seconds.engine += engine.elapsed().as_secs_f64();
        seconds.engine_sync += (engine - clock).as_secs_f64();
        let mut engine = |bodies: &mut B, dt: Real| rapier_step(bodies, B::scalar(dt));
        self.finish_step(bodies, Some(&mut engine))
    }

    /// [`step`](Guard::step) for an application with contact hooks (rapier's
    /// `PhysicsHooks`): before the step the guard asks `hooks` whether each
    /// pair with a body whose colliders filter their contacts
    /// (`ActiveHooks::FILTER_CONTACT_PAIRS`) is solved, and guards it only
    /// if so, as rapier will. `rapier_step` is handed the colliders back
    /// beside the bodies. (Bodies whose colliders modify their solver
    /// contacts, `MODIFY_SOLVER_CONTACTS`, are left to rapier with or
    /// without hooks: the guard cannot know which contacts the hook keeps.)
    pub fn step_with_hooks<F>(
        &mut self,
        bodies: &mut B,
        colliders: &mut B::Colliders,
        hooks: &B::Hooks,
        mut rapier_step: F,
    ) -> Result<Vec<GuardEvent<B::Handle>>, GuardError<B::Handle>>
    where
        F: FnMut(&mut B, &mut B::Colliders, B::Scalar),
    {
        if self.solved.has_filters() {
            let handles = &self.handles;
            let refused =
                self.solved.filtered_pairs(|a, b| bodies.filter(colliders, hooks, handles[a], handles[b]));
            self.solved.refuse(refused);
        }
        self.step(bodies, |bodies, dt| rapier_step(bodies, colliders, dt))
    }

    /// Leaves to rapier, from the next step on, the pairs of guarded bodies
    /// that a joint of `joints` (rapier's `ImpulseJointSet`) joins with its
    /// contacts disabled: rapier never solves their contacts (a robot's
    /// links overlapping at their joint), so neither does the guard. Call
    /// it again after changing the joints.
    pub fn honour_joints(&mut self, joints: &B::Joints) {
        let index = |handle: &B::Handle| self.handles.iter().position(|h| h == handle);
        let jointed = B::without_contacts(joints)
            .iter()
            .filter_map(|(a, b)| Some((index(a)?, index(b)?)))
            .filter(|(a, b)| a != b)
            .map(|(a, b)| (a.min(b), a.max(b)))
            .collect();
        self.solved.set_jointed(jointed);
    }

    /// Notes the guarded bodies' poses before rapier's step (with
    /// [`after_step`](Guard::after_step), for a loop that steps rapier
    /// itself; [`step`](Guard::step) rewinds to contacts, this pair of
    /// calls only clamps).
    pub fn before_step(&mut self, bodies: &B) {
        for (i, handle) in self.handles.iter().enumerate() {
            if let Some(body) = bodies.view(*handle) {
                self.start[i] = center_pose(&body.pose, &self.centers[i]);
                self.velocities[i] = (body.linvel, body.angvel);
            }
        }
        self.started = true;
    }

    /// Sweeps the guarded bodies from their poses at
    /// [`before_step`](Guard::before_step) to where rapier's step left
    /// them; holds the dynamic bodies of arrivals that need the guard at
    /// their poses at contact (it cannot step rapier again). Returns the
    /// step's events.
    pub fn after_step(
        &mut self,
        bodies: &mut B,
    ) -> Result<Vec<GuardEvent<B::Handle>>, GuardError<B::Handle>> {
        self.finish_step(bodies, None)
    }

    /// The sweeps of one step after rapier's first step (see
    /// [`step`](Guard::step)); `engine` steps rapier again after a rewind.
    fn finish_step(
        &mut self,
        bodies: &mut B,
        engine: Option<&mut RapierStep<'_, B>>,
    ) -> Result<Vec<GuardEvent<B::Handle>>, GuardError<B::Handle>> {
        // The time outside rapier, the sweeps and the observers is the
        // guard's own (`engine_sync`).
        let clock = Instant::now();
        let sweeps = self.stepper.counters().seconds.sweep();
        let mut engine_seconds = 0.0;
        let outcome = match engine {
            Some(engine) => {
                let mut timed = |bodies: &mut B, dt: Real| {
                    let clock = Instant::now();
                    engine(bodies, dt);
                    engine_seconds += clock.elapsed().as_secs_f64();
                };
                self.sweep_step(bodies, Some(&mut timed))
            }
            None => self.sweep_step(bodies, None),
        };
        let seconds = &mut self.stepper.counters_mut().seconds;
        seconds.engine += engine_seconds;
        seconds.engine_sync += clock.elapsed().as_secs_f64() - engine_seconds - (seconds.sweep() - sweeps);
        outcome?;
        // After the accounting: the trace times itself (its stage).
        self.stepper.observe_step_end(&self.world, self.step - 1);
        Ok(std::mem::take(&mut self.events))
    }

    /// Every contact reported so far, in the order found (body indices are
    /// positions in the guarded list).
    pub fn contacts(&self) -> &[Contact] {
        &self.world.contacts
    }

    /// The guarded bodies, in the guard's order.
    pub fn handles(&self) -> &[B::Handle] {
        &self.handles
    }

    /// The guard's work so far (CCD queries, stage times).
    pub fn counters(&self) -> &crate::stepper::Counters {
        self.stepper.counters()
    }

    /// The steps guarded so far.
    pub fn steps(&self) -> u64 {
        self.steps_before + self.step
    }

    /// The times the guard moved the world back to a contact so far.
    pub fn rewinds(&self) -> u64 {
        self.rewinds
    }

    /// The guard's world and stepper, for the scene runner.
    pub(crate) fn into_parts(self) -> (Stepper, World) {
        (self.stepper, self.world)
    }
}

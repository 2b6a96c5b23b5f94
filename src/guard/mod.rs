//! Tunnel-free rapier bodies: nearmiss's conservative CCD guarding a rapier
//! simulation (the `rapier` feature, on by default).
//!
//! rapier never sweeps a moving triangle mesh (a mesh bullet passes a thin
//! plate even with CCD on), and its soft contacts let a pair it holds sink
//! into each other (by its allowed linear error and more under load: a plate
//! thinner than that is no wall). A [`Guard`] makes rapier's bodies keep
//! nearmiss's contact contract.
//!
//! # What is guaranteed
//!
//! **No two guarded meshes come closer than the CCD's contact distance (the
//! wall) at any pose the guard hands back**, in contact or not: a mesh never
//! overlaps another, so it never passes through one. Contacts are reported
//! never late. Exceptions, each reported and never silent: a pair the CCD
//! cannot decide ends the step with [`GuardError::Undecided`]; when a step
//! needs more than [`GuardOptions::max_substeps`] rewinds, the rest of its
//! contacts are clamped (below), which keeps dynamic bodies off each other
//! and off fixed ones, and a dynamic body touching a kinematic one is
//! carried along by it, but a body squeezed between a kinematic body and
//! another can then overlap the other (nothing can hold it).
//!
//! # How
//!
//! - **A contact skin.** Each guarded collider gets a contact skin
//!   ([`GuardOptions::skin`], rapier's allowed linear error by default):
//!   rapier's contacts start when two colliders are their two skins apart and
//!   its soft contacts sink into the skins, not into the meshes. A pair
//!   resting on another is the skins apart, less what rapier lets it sink.
//! - **Every pair is swept every step.** A pair apart is swept for coming
//!   within the two skins (a contact: [`GuardEvent::Started`], with
//!   nearmiss's time of impact, points and features). A pair in contact is
//!   swept against the wall: the meshes themselves, at the scene's contact
//!   contract. Once farther apart than the skins and rapier's prediction
//!   distance at a step's end it is apart again ([`GuardEvent::Stopped`]).
//! - **Rewind to the time of impact, then let rapier solve there.**
//!   [`Guard::step`] steps rapier, then sweeps every pair from the step's
//!   start poses to rapier's end poses. Where a pair would reach the wall
//!   (rapier let a touching pair through its skins, or a pair coming within
//!   the skins would go on to the wall: a bullet, a blade), the world is
//!   moved back to the earliest such time (every moving body to its pose
//!   then, velocities interpolated between the step's ends so that forces
//!   act once, the pair woken) and rapier steps the rest of the step from
//!   there, where its solver sees the contact with both bodies' masses,
//!   friction and restitution. The rest of the step is swept again; up to
//!   [`GuardOptions::max_substeps`] times per step.
//! - **Clamp, when the rewinds are spent** (and under
//!   [`before_step`](Guard::before_step) / [`after_step`](Guard::after_step),
//!   which cannot step rapier again, or when the contact is at the sweep's
//!   start, where rapier would only repeat itself): the dynamic bodies of
//!   such a contact are held at their poses at contact for the rest of the
//!   step (rapier's own CCD does the same), velocities left to rapier; one
//!   touching a kinematic body is carried along by it (their relative pose
//!   kept, the kinematic body's velocities), since that body goes on.
//! - **A kinematic body has infinite mass**: after a rewind to its contact
//!   with a dynamic body, the dynamic body leaves at least as fast as the
//!   kinematic body's contact point along the normal (rapier's soft contact
//!   alone lets it sink in).
//! - Fixed and kinematic bodies are never moved by the guard beyond the
//!   rewind (rapier drives them; a kinematic body rewound is still bound for
//!   its pose at the step's end).
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
//!         println!("{event:?}");
//!     }
//! }
//! # Ok::<(), nearmiss::guard::GuardError>(())
//! ```
//!
//! The guard works on the bodies' centres of mass: the mesh it sweeps is the
//! triangles of a body's colliders relative to the body's centre of mass
//! (triangle meshes, convex polyhedra and cuboids as they are; balls,
//! capsules and cylinders as polyhedra drawn around them, at most
//! [`BALL_EXCESS_OF_SKIN`] of the skin outside, so that the shapes
//! themselves never overlap either; compounds part by part), and a body's motion over
//! a step is the constant linear and angular velocity that takes its start
//! pose to its end pose (the turn nearest rapier's angular velocity). The
//! scene runner's `on_contact: Simulate` is built on the same type.
//!
//! # f32 rapier
//!
//! With the `rapier-f32` feature, `Guard<rapier3d::prelude::RigidBodySet>`
//! guards an f32 rapier3d 0.36 pipeline (bevy_rapier's) with the same
//! logic: every pose and velocity crosses into f64 for the sweep
//! ([`RapierBodies`]). The guarantee above then holds for the poses the guard
//! proved; what rapier stores is each rounded to f32, at most half an ulp of
//! its coordinates away (2⁻²⁴ of their size: 6e-5 at 1,000 units), inside
//! the contact skins as long as that stays well below them (bodies within
//! about 10⁴ units of the origin under the default skin of 0.005).

mod bodies;
mod compare;
mod shapes;
pub(crate) mod simulate;

pub use compare::{
    compare_with_rapier, rapier_markdown, run_rapier_alone, RapierAlone, RapierBody, RapierComparison,
    RapierPair, PENETRATION_LIMIT_FACTOR,
};

use std::sync::Arc;
use std::time::Instant;

use rapier3d_f64::prelude::{IntegrationParameters, RigidBodyHandle, RigidBodySet};

pub use bodies::{BodyKind, BodyView, RapierBodies, ShapePart};

pub use shapes::{
    circumscribed_ball, collider_for, is_convex, mesh_of_body, ColliderShape, CONVEXITY_TOLERANCE,
    MAX_BALL_SEGMENTS,
};

use crate::ccd::{CcdOptions, ContactContract, ContactRule};
use crate::math::{Point, Pose, Real, Vector};
use crate::mesh::DistanceKernel;
use crate::motion::StepMotion;
use crate::response::Clamp;
use crate::scene::{Body, BodyMotion, Model, OnContact, RunSpec};
use crate::stepper::{Contact, PairState, RunOptions, Stepper, Termination, World};
use bodies::{body_pose, center_pose};

/// How a [`Guard`] sweeps.
#[derive(Copy, Clone, Debug, PartialEq)]
pub struct GuardOptions {
    /// The CCD's tolerances and limits (the contact distance is relative to
    /// the smaller body of a pair, see [`CcdOptions`]). This is the wall: no
    /// two guarded meshes come closer. It must stay below the two
    /// colliders' skins ([`Guard::new`] checks it for the largest pair).
    /// Default: [`CcdOptions::default`].
    pub ccd: CcdOptions,
    /// The CCD's distance kernel. Default: exact.
    pub kernel: DistanceKernel,
    /// Sweep pairs on rayon's threads. Default: true.
    pub parallel: bool,
    /// The contact skin [`Guard::new`] gives each guarded collider, as a
    /// multiple of rapier's allowed linear error
    /// (`IntegrationParameters::allowed_linear_error`, 0.005 × `length_unit`
    /// by default): rapier then holds touching pairs that far apart, and its
    /// soft contacts sink into the skins, not into the meshes. A collider
    /// with a larger skin keeps it. `0`: no skin, and pairs in contact are
    /// rapier's alone (only pairs apart are swept; rapier's overlaps go
    /// unchecked). Finite and at least 0 ([`Guard::new`] checks it).
    /// Default: `1.0`.
    pub skin: Real,
    /// How many times per step [`Guard::step`] may move the world back to a
    /// contact and let rapier solve from there; after that, contacts clamp
    /// their dynamic bodies (held at their poses at contact for the rest of
    /// the step). Default: `4`.
    pub max_substeps: usize,
}

/// How far outside a ball, capsule or cylinder collider its swept
/// polyhedron may stand, as a fraction of the contact skin (of rapier's
/// allowed linear error when the skin is 0): `0.25`.
pub const BALL_EXCESS_OF_SKIN: Real = 0.25;

/// [`GuardOptions::skin`]'s default.
pub const DEFAULT_SKIN: Real = 1.0;

/// [`GuardOptions::max_substeps`]'s default.
pub const DEFAULT_MAX_SUBSTEPS: usize = 4;

/// [`StepParameters::parallel_narrow_phase_seconds`](crate::stepper::StepParameters::parallel_narrow_phase_seconds) under a guard: between
/// two of its sweeps rapier steps on one thread and rayon's threads fall
/// asleep, and waking them cost 1.3e-4 to 1.6e-4 s a step on the 1,000-body
/// box (2 cores), more than a narrow phase of 0.25 ms gained from the
/// second thread (and their spinning afterwards slowed rapier's step).
/// Seconds.
pub const PARALLEL_NARROW_PHASE_SECONDS: Real = 3e-4;

impl Default for GuardOptions {
    fn default() -> Self {
        GuardOptions {
            ccd: CcdOptions::default(),
            kernel: DistanceKernel::Exact,
            parallel: true,
            skin: DEFAULT_SKIN,
            max_substeps: DEFAULT_MAX_SUBSTEPS,
        }
    }
}

impl GuardOptions {
    /// The contact skin of each guarded collider under `parameters`
    /// (rapier3d-f64's; under an f32 rapier it is the same product,
    /// `skin × parameters.allowed_linear_error()`).
    pub fn skin_under(&self, parameters: &IntegrationParameters) -> Real {
        self.skin * parameters.allowed_linear_error()
    }
}

/// The largest contact distance the CCD may have under a guard whose
/// colliders have the contact skin `skin` (each): the two skins, within
/// which rapier holds a pair, or without skins rapier's
/// `prediction_distance`.
pub(crate) fn contact_distance_limit(prediction_distance: Real, skin: Real) -> Real {
    if skin > 0.0 {
        two_skins(skin)
    } else {
        prediction_distance
    }
}

/// How far apart rapier holds two touching colliders of contact skin
/// `skin` each: the guard reports a contact there.
fn two_skins(skin: Real) -> Real {
    2.0 * skin
}

/// Whether a `Simulate` scene's bodies fit the guard under rapier's default
/// parameters and the default skin: `Err((body, contact distance, limit))`
/// when the largest pair's contact distance is not below the skins (`body`
/// is the one whose radius sets it).
pub(crate) fn simulate_contact_limit(ccd: &CcdOptions, bodies: &[Body]) -> Result<(), (String, Real, Real)> {
    let parameters = IntegrationParameters::default();
    let limit = contact_distance_limit(
        parameters.prediction_distance(),
        GuardOptions::default().skin_under(&parameters),
    );
    contact_within(ccd, bodies.iter(), limit)
}

/// [`simulate_contact_limit`] for any bodies and limit.
fn contact_within<'a>(
    ccd: &CcdOptions,
    bodies: impl Iterator<Item = &'a Body> + Clone,
    limit: Real,
) -> Result<(), (String, Real, Real)> {
    let radius =
        largest_pair_radius(bodies.clone().map(|b| (b.mesh.radius(), b.motion == BodyMotion::Fixed)));
    let contract = ContactContract::of(ccd, ContactRule::ScaleRelative, radius, 0.0);
    if contract.contact_distance < limit {
        return Ok(());
    }
    let mut bodies = bodies;
    let body = bodies.find(|b| b.mesh.radius() == radius).map_or(String::new(), |b| b.name.clone());
    Err((body, contract.contact_distance, limit))
}

/// The largest radius that sets a pair's contact distance: over the pairs
/// not both fixed, the larger of their smaller radii (`(radius, fixed)` per
/// body). 0 without such a pair.
pub(crate) fn largest_pair_radius(bodies: impl Iterator<Item = (Real, bool)>) -> Real {
    // The two largest radii of all bodies, and the largest of a movable one.
    let (mut first, mut second, mut movable) = (0.0, 0.0, None::<Real>);
    for (radius, fixed) in bodies {
        if radius > first {
            second = first;
            first = radius;
        } else if radius > second {
            second = radius;
        }
        if !fixed {
            movable = Some(movable.map_or(radius, |m: Real| m.max(radius)));
        }
    }
    // A movable body pairs with every other: its smaller radius against the
    // largest other body is min(r, first) when it is not the largest, and
    // min(r, second) when it is.
    match movable {
        None => 0.0,
        Some(m) if m >= first => second.min(m),
        Some(m) => m,
    }
}

/// What the guard saw in a step (`H`: rapier's body handle).
#[non_exhaustive]
#[derive(Clone, Debug, PartialEq)]
pub enum GuardEvent<H = RigidBodyHandle> {
    /// Two guarded bodies came into contact within the step (and the
    /// dynamic ones among them were moved back to their poses at that
    /// time).
    Started {
        /// The first body.
        a: H,
        /// The second body.
        b: H,
        /// The contact: time (since the guard's first step), distance,
        /// points (world frame), features and the contact contract.
        contact: Box<Contact>,
    },
    /// Two bodies in contact separated by the step's end (farther apart
    /// than the two skins and rapier's prediction distance): apart again,
    /// swept for coming within the skins.
    Stopped {
        /// The first body.
        a: H,
        /// The second body.
        b: H,
    },
}

/// What can go wrong (`H`: rapier's body handle).
#[non_exhaustive]
#[derive(Debug, thiserror::Error)]
pub enum GuardError<H: std::fmt::Debug = RigidBodyHandle> {
    /// A guarded handle is not in the body set.
    #[error("rigid body {0:?} is not in the body set")]
    UnknownBody(H),
    /// A body's colliders give no mesh the guard can sweep.
    #[error("body {body}: {message}")]
    Shape {
        /// The body.
        body: String,
        /// What is wrong.
        message: String,
    },
    /// The CCD's contact distance (the wall) is not below the two
    /// colliders' contact skins (without skins: rapier's prediction
    /// distance).
    #[error("the CCD's contact distance ({contact_distance:e}, for a pair with body {body}) is not below the two colliders' contact skins ({limit:e}): the wall would lie outside rapier's contact; lower `GuardOptions::ccd.distance_tolerance` or raise `GuardOptions::skin`")]
    ContactDistance {
        /// The body whose radius sets the largest pair's contact distance.
        body: String,
        /// That contact distance.
        contact_distance: Real,
        /// The skins' sum (or rapier's prediction distance).
        limit: Real,
    },
    /// [`GuardOptions::skin`] is negative or not finite.
    #[error("GuardOptions::skin must be a finite multiple of rapier's allowed linear error, at least 0; found {0}")]
    Skin(Real),
    /// [`Guard::set_bodies`] on a guard not made by [`Guard::new`].
    #[error("set_bodies needs a guard made by Guard::new")]
    NotFromRapier,
    /// `after_step` without `before_step`.
    #[error("after_step was called without before_step")]
    NoStartPoses,
    /// A pair's CCD ran out of iterations: it is proven apart only up to
    /// `time`, and the guard cannot say what happened after.
    #[error("the CCD of bodies {a:?} and {b:?} could not decide after {iterations} iterations (proven apart up to t = {time}): raise `GuardOptions::ccd.max_iterations`")]
    Undecided {
        /// The first body.
        a: H,
        /// The second body.
        b: H,
        /// Proven apart up to this time (since the guard's first step).
        time: Real,
        /// The CCD iterations made.
        iterations: usize,
    },
}

/// rapier's step by a given `dt`, as [`Guard::step`] calls it.
type RapierStep<'a, B> = dyn FnMut(&mut B, Real) + 'a;

/// Guards rapier bodies against tunnelling (see the module). `B`: rapier's
/// body set, `rapier3d_f64`'s or (the `rapier-f32` feature) `rapier3d`'s.
pub struct Guard<B: RapierBodies = RigidBodySet> {
    /// The guarded bodies, in the guard's order.
    handles: Vec<B::Handle>,
    /// Each body's centre of mass in its body frame.
    centers: Vec<Vector>,
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
    /// The options [`Guard::new`] was given (for
    /// [`set_bodies`](Guard::set_bodies)); `None` for the scene runner's.
    options: Option<GuardOptions>,
    /// Rewinds so far (rapier solving again from a contact).
    rewinds: u64,
    events: Vec<GuardEvent<B::Handle>>,
    /// The last step's undecided query, as the stepper reported it.
    pub(crate) undecided: Option<Termination>,
}

/// How the guard's scene was made: what the guard needs beside it.
pub(crate) struct GuardSetup<H> {
    /// The rapier handle of each scene body.
    pub handles: Vec<H>,
    /// Each body's centre of mass in its body frame.
    pub centers: Vec<Vector>,
    /// Per body: whether contacts may hold it (dynamic bodies).
    pub stoppable: Vec<bool>,
    /// Each collider's contact skin (0: touching pairs are rapier's alone).
    pub skin: Real,
    /// Rewinds allowed per step.
    pub max_substeps: usize,
    /// Sweep pairs on rayon's threads.
    pub parallel: bool,
}

impl<B: RapierBodies> Guard<B> {
    /// A guard of the bodies `guarded` (their colliders' triangles) for
    /// steps of `parameters.dt` (for other bodies or another `dt`,
    /// [`set_bodies`](Guard::set_bodies)). Gives each of their colliders the contact skin
    /// [`GuardOptions::skin`] (a larger skin is kept).
    pub fn new(
        bodies: &B,
        colliders: &mut B::Colliders,
        guarded: &[B::Handle],
        parameters: &B::Parameters,
        options: GuardOptions,
    ) -> Result<Guard<B>, GuardError<B::Handle>> {
        if !(options.skin.is_finite() && options.skin >= 0.0) {
            return Err(GuardError::Skin(options.skin));
        }
        let allowed_error = B::allowed_linear_error(parameters);
        let skin = options.skin * allowed_error;
        // A round shape's polyhedron stands at most a quarter skin outside
        // it, inside the skins rapier rests a pair at.
        let excess = BALL_EXCESS_OF_SKIN * if skin > 0.0 { skin } else { allowed_error };
        let mut scene_bodies = Vec::with_capacity(guarded.len());
        let mut centers = Vec::with_capacity(guarded.len());
        let mut stoppable = Vec::with_capacity(guarded.len());
        for &handle in guarded {
            let body = bodies.view(handle).ok_or(GuardError::UnknownBody(handle))?;
            let name = format!("{handle:?}");
            let (mesh, center) = mesh_of_body(bodies, colliders, handle, &name, excess)?;
            bodies.give_skin(colliders, handle, skin);
            scene_bodies.push(Body {
                name,
                mesh: Arc::new(mesh),
                pose: body.center_pose(),
                velocity: Vector::zeros(),
                angular_velocity: Vector::zeros(),
                mass: None,
                inertia: None,
                motion: if body.kind == BodyKind::Fixed { BodyMotion::Fixed } else { BodyMotion::Free },
                kinematic: matches!(body.kind, BodyKind::Kinematic { .. }),
                material: None,
            });
            centers.push(center);
            stoppable.push(matches!(body.kind, BodyKind::Dynamic { .. }));
        }
        // What the guard sweeps: rapier's bodies as meshes, rapier's step
        // (no run to write: no trace, no poses, no name).
        let model = Model {
            dt: B::dt(parameters),
            integrator: Default::default(),
            gyroscopic: Default::default(),
            ccd: options.ccd,
            kernel: options.kernel,
            // Rapier solves (its colliders carry their own materials): the
            // response is `Simulate`, and these values are not read.
            on_contact: OnContact::Simulate {
                restitution: 0.0,
                friction: crate::scene::file::DEFAULT_FRICTION,
                solver_iterations: crate::scene::file::DEFAULT_SOLVER_ITERATIONS,
            },
            bodies: Arc::new(scene_bodies),
            parameters: Default::default(),
        };
        let setup = GuardSetup {
            handles: guarded.to_vec(),
            centers,
            stoppable,
            skin,
            max_substeps: options.max_substeps,
            parallel: options.parallel,
        };
        let mut guard = Guard::with_model(Arc::new(model), None, setup, parameters)?;
        guard.options = Some(options);
        Ok(guard)
    }

    /// Guards `guarded` from the next step on, under `parameters` (whose
    /// `dt` may differ from before): bodies new to the list are guarded
    /// (their colliders given the skin), bodies left out no longer are. A
    /// pair in contact stays in contact (not reported again). Times go on
    /// from the steps so far; [`contacts`](Guard::contacts) and
    /// [`counters`](Guard::counters) start afresh. Only for a guard made
    /// by [`Guard::new`] (otherwise [`GuardError::NotFromRapier`]).
    pub fn set_bodies(
        &mut self,
        bodies: &B,
        colliders: &mut B::Colliders,
        guarded: &[B::Handle],
        parameters: &B::Parameters,
    ) -> Result<(), GuardError<B::Handle>> {
        let options = self.options.ok_or(GuardError::NotFromRapier)?;
        let mut next = Guard::new(bodies, colliders, guarded, parameters, options)?;
        next.steps_before = self.steps();
        next.time_before = self.time();
        // The pairs in contact, carried over by their bodies' handles.
        let index = |handle: &B::Handle| next.handles.iter().position(|h| h == handle);
        let mut carried: Vec<PairState> = self
            .world
            .pairs
            .iter()
            .filter_map(|p| {
                let t = p.touching.as_ref()?;
                let (i, j) = (index(&self.handles[p.a])?, index(&self.handles[p.b])?);
                let mut pair = PairState::new(i.min(j), i.max(j));
                pair.touching = Some(*t);
                Some(pair)
            })
            .collect();
        if next.stepper.has_broad_phase() {
            // The broad phase keeps pairs in contact from one step to the next.
            carried.sort_by_key(|p| (p.a, p.b));
            next.world.pairs = carried;
        } else {
            for pair in &mut next.world.pairs {
                pair.touching =
                    carried.iter().find(|c| (c.a, c.b) == (pair.a, pair.b)).and_then(|c| c.touching);
            }
        }
        *self = next;
        Ok(())
    }

    /// The time guarded so far (the steps' `dt`s added up).
    pub fn time(&self) -> Real {
        self.time_before + self.step as Real * self.dt
    }

    /// The guard of `model` (the scene runner's, with the observers of its
    /// `run`; or [`Guard::new`]'s, of rapier's bodies: its bodies are
    /// `setup.handles`, its meshes relative to their bodies' frames, which
    /// are their centres of mass).
    pub(crate) fn with_model(
        model: Arc<Model>,
        run: Option<&RunSpec>,
        setup: GuardSetup<B::Handle>,
        parameters: &B::Parameters,
    ) -> Result<Guard<B>, GuardError<B::Handle>> {
        let limit = contact_distance_limit(B::prediction_distance(parameters), setup.skin);
        if let Err((body, contact_distance, limit)) = contact_within(&model.ccd, model.bodies.iter(), limit) {
            return Err(GuardError::ContactDistance { body, contact_distance, limit });
        }
        let options = RunOptions { parallel: setup.parallel, broad_phase: true };
        let response = Box::new(Clamp {
            stoppable: setup.stoppable,
            separation: two_skins(setup.skin) + B::prediction_distance(parameters),
            skin_separation: if setup.skin > 0.0 {
                model.ccd.minimum_separation + two_skins(setup.skin)
            } else {
                0.0
            },
            guards_touching_pairs: setup.skin > 0.0,
        });
        let mut stepper = Stepper::with_response(Arc::clone(&model), run, options, response);
        stepper.set_extra_box_margin(setup.skin);
        stepper.set_parallel_narrow_phase_seconds(PARALLEL_NARROW_PHASE_SECONDS);
        let world = stepper.new_world(false);
        Ok(Guard {
            start: model.bodies.iter().map(|b| b.pose).collect(),
            velocities: model.bodies.iter().map(|b| (b.velocity, b.angular_velocity)).collect(),
            handles: setup.handles,
            centers: setup.centers,
            started: false,
            stepper,
            world,
            step: 0,
            steps_before: 0,
            time_before: 0.0,
            dt: B::dt(parameters),
            max_substeps: setup.max_substeps,
            options: None,
            rewinds: 0,
            events: Vec::new(),
            undecided: None,
        })
    }

    /// One guarded step: `rapier_step(bodies, dt)` steps rapier by `dt`
    /// (your `PhysicsPipeline::step` with `IntegrationParameters::dt` set to
    /// it). The guard sweeps the step; where a pair would come into contact
    /// and rapier would not hold it (it reaches the wall), the guard moves
    /// the world back to the contact's time and calls `rapier_step` again
    /// for the rest of the step, so that rapier solves the contact where it
    /// happens (up to [`GuardOptions::max_substeps`] times; then the
    /// contact's dynamic bodies are held at it). Returns the step's events.
    pub fn step<F>(
        &mut self,
        bodies: &mut B,
        mut rapier_step: F,
    ) -> Result<&[GuardEvent<B::Handle>], GuardError<B::Handle>>
    where
        F: FnMut(&mut B, Real),
    {
        let clock = Instant::now();
        self.before_step(bodies);
        let engine = Instant::now();
        rapier_step(bodies, self.dt);
        let seconds = &mut self.stepper.counters_mut().seconds;
        seconds.engine += engine.elapsed().as_secs_f64();
        seconds.engine_sync += (engine - clock).as_secs_f64();
        self.finish_step(bodies, Some(&mut rapier_step))
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
    /// them; holds dynamic bodies that would reach the wall at their poses
    /// at contact. Returns the step's events.
    pub fn after_step(&mut self, bodies: &mut B) -> Result<&[GuardEvent<B::Handle>], GuardError<B::Handle>> {
        self.finish_step(bodies, None)
    }

    /// The sweeps of one step after rapier's first step (see
    /// [`step`](Guard::step)); `engine` steps rapier again after a rewind.
    fn finish_step(
        &mut self,
        bodies: &mut B,
        engine: Option<&mut RapierStep<'_, B>>,
    ) -> Result<&[GuardEvent<B::Handle>], GuardError<B::Handle>> {
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
        Ok(&self.events)
    }

    /// [`finish_step`](Guard::finish_step)'s sweeps and rewinds; the events
    /// go to `self.events`.
    fn sweep_step(
        &mut self,
        bodies: &mut B,
        mut engine: Option<&mut RapierStep<'_, B>>,
    ) -> Result<(), GuardError<B::Handle>> {
        if !std::mem::take(&mut self.started) {
            return Err(GuardError::NoStartPoses);
        }
        self.events.clear();
        let contacts_before = self.world.contacts.len();
        let t0 = self.step as Real * self.dt;
        // Time into the step at the current sweep's start; each sweep runs
        // over the rest of the step, its motions stretched over `dt`.
        let mut elapsed: Real = 0.0;
        let mut substeps = 0;
        // Set when the next sweep must clamp: a rewind to a sweep's start
        // would step rapier again from the same state, to the same end.
        let mut clamp = false;
        loop {
            self.set_motions(bodies, elapsed);
            self.world.may_rewind = engine.is_some() && substeps < self.max_substeps && !clamp;
            let mark = self.world.contacts.len();
            let result = self.stepper.sweep(&mut self.world, self.step);
            let scale = (self.dt - elapsed) / self.dt;
            let time_before = self.time_before;
            let real = |time: Real| {
                let time = if elapsed > 0.0 { t0 + elapsed + (time - t0) * scale } else { time };
                if time_before > 0.0 {
                    time_before + time
                } else {
                    time
                }
            };
            for contact in &mut self.world.contacts[mark..] {
                contact.time = real(contact.time);
            }
            let handles = &self.handles;
            self.events.extend(
                self.world
                    .separated
                    .iter()
                    .map(|&(a, b)| GuardEvent::Stopped { a: handles[a], b: handles[b] }),
            );
            // Held bodies go back to their poses at contact (also when a
            // pair was undecided: the contacts before it stand).
            let held = std::mem::take(&mut self.world.held);
            for &(i, at) in &held {
                self.hold_or_carry(bodies, i, at.min(self.dt), scale);
            }
            self.world.held = held;
            if let Err(Termination::Undecided { pair: (a, b), time, step, iterations }) = result {
                let time = real(time);
                self.undecided = Some(Termination::Undecided { pair: (a, b), time, step, iterations });
                self.step += 1;
                return Err(GuardError::Undecided {
                    a: self.handles[a],
                    b: self.handles[b],
                    time,
                    iterations,
                });
            }
            let (Some(rewind), Some(engine)) = (self.world.rewind.take(), engine.as_mut()) else { break };
            if rewind.time == 0.0 {
                clamp = true;
                continue;
            }
            let at = rewind.time;
            self.rewind(bodies, at, [rewind.a, rewind.b]);
            if let Some((point_a, point_b)) = rewind.points {
                self.push_off_kinematic(bodies, [rewind.a, rewind.b], &point_a, &point_b, at);
            }
            elapsed += at * scale;
            substeps += 1;
            self.rewinds += 1;
            engine(bodies, self.dt - elapsed);
        }
        self.step += 1;
        let handles = &self.handles;
        self.events.extend(self.world.contacts[contacts_before..].iter().map(|contact| {
            GuardEvent::Started {
                a: handles[contact.body_a],
                b: handles[contact.body_b],
                contact: Box::new(contact.clone()),
            }
        }));
        Ok(())
    }

    /// Each body's motion over the rest of the step from `elapsed`: from its
    /// pose at the sweep's start to where rapier left it, stretched over
    /// `dt` (the CCD's path is the same; its times map back linearly).
    fn set_motions(&mut self, bodies: &B, elapsed: Real) {
        let scale = (self.dt - elapsed) / self.dt;
        for (i, handle) in self.handles.iter().enumerate() {
            let Some(body) = bodies.view(*handle) else { continue };
            let end = center_pose(&body.pose, &self.centers[i]);
            self.world.motions[i] = if body.kind == BodyKind::Fixed {
                StepMotion::fixed(end)
            } else {
                let spin = body.angvel * scale;
                StepMotion::between_near(&self.start[i], &end, self.dt, &spin)
            };
        }
    }

    /// Moves every moving body back to its pose at `at` into the current
    /// sweep (velocities interpolated between the sweep's ends, so that the
    /// forces of the step are applied once), kinematic bodies still bound
    /// for the step's end, and wakes the pair `hit`.
    fn rewind(&mut self, bodies: &mut B, at: Real, hit: [usize; 2]) {
        let fraction = at / self.dt;
        for (i, &handle) in self.handles.iter().enumerate() {
            let Some(body) = bodies.view(handle) else { continue };
            let woken = hit.contains(&i);
            let pose = self.world.motions[i].pose_at(at);
            match body.kind {
                BodyKind::Fixed => continue,
                BodyKind::Kinematic { position_based } => {
                    bodies.set_pose(handle, &body_pose(&pose, &self.centers[i]), woken);
                    if position_based {
                        bodies.set_next_kinematic_pose(handle, &body.pose);
                    }
                }
                BodyKind::Dynamic { sleeping } => {
                    if sleeping && !woken {
                        continue;
                    }
                    let (v0, w0) = self.velocities[i];
                    let (v1, w1) = (body.linvel, body.angvel);
                    let (v, w) = (v0 + (v1 - v0) * fraction, w0 + (w1 - w0) * fraction);
                    bodies.set_pose(handle, &body_pose(&pose, &self.centers[i]), false);
                    bodies.set_velocities(handle, &v, &w, false);
                    if woken {
                        bodies.wake_up(handle);
                    }
                    self.velocities[i] = (v, w);
                }
            }
            self.start[i] = pose;
        }
        // What the pairs carried was about the sweep's end.
        for pair in &mut self.world.pairs {
            pair.lower_bound = None;
        }
    }

    /// Body `i`, clamped at `at` into the sweep: held at its pose then, or,
    /// when it touches a kinematic body (which has infinite mass and goes
    /// on), carried by it from then to the step's end (their relative pose
    /// kept, velocities the kinematic body's), so it is pushed, not passed
    /// through. `scale`: the sweep's real length over `dt`.
    fn hold_or_carry(&mut self, bodies: &mut B, i: usize, at: Real, scale: Real) {
        let held = self.world.motions[i].pose_at(at);
        // A kinematic body in contact with it, and that body's view.
        let carrier = self.world.pairs.iter().filter(|p| p.touching.is_some()).find_map(|p| {
            let other = if p.a == i {
                p.b
            } else if p.b == i {
                p.a
            } else {
                return None;
            };
            let body = bodies.view(self.handles[other])?;
            matches!(body.kind, BodyKind::Kinematic { .. }).then_some((other, body))
        });
        let Some((k, carrier)) = carrier else {
            bodies.set_pose(self.handles[i], &body_pose(&held, &self.centers[i]), true);
            return;
        };
        let (k_at, k_end) = (self.world.motions[k].pose_at(at), self.world.motions[k].pose_at(self.dt));
        let carried = k_end * k_at.inverse() * held;
        let (v_k, w_k) = (carrier.linvel, carrier.angvel);
        let velocity = v_k + w_k.cross(&(carried.translation.vector - k_end.translation.vector));
        self.world.motions[i] = StepMotion::between_near(&self.start[i], &carried, self.dt, &(w_k * scale));
        bodies.set_pose(self.handles[i], &body_pose(&carried, &self.centers[i]), true);
        bodies.set_velocities(self.handles[i], &velocity, &w_k, true);
    }

    /// A dynamic body moved back to its contact with a kinematic one leaves
    /// at least as fast as the kinematic body's contact point along the
    /// contact normal (the kinematic body has infinite mass, and rapier's
    /// soft contact alone lets it sink in): its velocity gains the missing
    /// normal speed, through its centre (no spin is added).
    fn push_off_kinematic(
        &self,
        bodies: &mut B,
        pair: [usize; 2],
        point_a: &Point,
        point_b: &Point,
        at: Real,
    ) {
        let [a, b] = pair;
        let kinematic = |i: usize| is_kinematic(bodies, self.handles[i]);
        let dynamic = |i: usize| {
            bodies.view(self.handles[i]).is_some_and(|body| matches!(body.kind, BodyKind::Dynamic { .. }))
        };
        let (k, d, towards_d) = if kinematic(a) && dynamic(b) {
            (a, b, point_b - point_a)
        } else if kinematic(b) && dynamic(a) {
            (b, a, point_a - point_b)
        } else {
            return;
        };
        let center = |i: usize| self.world.motions[i].center_at(at);
        let Some(normal) =
            towards_d.try_normalize(0.0).or_else(|| (center(d) - center(k)).try_normalize(0.0))
        else {
            return;
        };
        let contact = Point::from((point_a.coords + point_b.coords) / 2.0);
        let (Some(body_k), Some(body_d)) = (bodies.view(self.handles[k]), bodies.view(self.handles[d]))
        else {
            return;
        };
        let point_velocity =
            |i: usize, body: &BodyView| body.linvel + body.angvel.cross(&(contact - center(i)));
        let deficit = (point_velocity(k, &body_k) - point_velocity(d, &body_d)).dot(&normal);
        if deficit > 0.0 {
            bodies.set_velocities(self.handles[d], &(body_d.linvel + normal * deficit), &body_d.angvel, true);
        }
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

/// Whether the body `handle` is kinematic.
fn is_kinematic<B: RapierBodies>(bodies: &B, handle: B::Handle) -> bool {
    bodies.view(handle).is_some_and(|body| matches!(body.kind, BodyKind::Kinematic { .. }))
}

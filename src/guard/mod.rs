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
mod compare;
mod depth;
mod shapes;
pub(crate) mod simulate;
mod watch;

pub use compare::{
    compare_with_rapier, rapier_markdown, run_rapier_alone, RapierAlone, RapierBody, RapierComparison,
    RapierPair,
};

use std::sync::Arc;
use std::time::Instant;

use rapier3d_f64::prelude::{IntegrationParameters, RigidBodyHandle, RigidBodySet};

pub use bodies::{BodyKind, BodyView, ColliderPart, ContactHooks, RapierBodies, ShapePart};

#[cfg(test)]
pub(crate) use shapes::HALF_SPACE_EXTENT;
pub use shapes::{
    circumscribed_ball, collider_for, is_convex, mesh_of_body, ColliderShape, MAX_BALL_SEGMENTS,
};

use crate::ccd::{CcdOptions, ContactContract, ContactRule};
use crate::math::{Pose, Real, Vector};
use crate::mesh::DistanceKernel;
use crate::scene::{Body, BodyMotion, Model, OnContact, RunSpec};
use crate::stepper::{Contact, PairState, RunOptions, Stepper, Termination, World};
use act::is_kinematic;
use bodies::center_pose;
use depth::{Deep, DepthWatch};
#[cfg(test)]
pub(crate) use watch::THIN_BODY_FRACTION;
use watch::{thickness, PairRules, Watch};

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
    /// by default). `0` (the default): no skin; rapier's contact model is
    /// untouched (its soft contacts overlap resting pairs by up to about its
    /// allowed error) and the guard only reads where rapier holds. Above
    /// `0`: rapier holds touching pairs the two skins apart and its soft
    /// contacts sink into the skins, and the guard keeps the meshes
    /// themselves from ever overlapping (a resting box floats the two
    /// skins, less what rapier lets it sink, above its floor). A collider
    /// with a larger skin keeps it. Finite and at least 0 ([`Guard::new`]
    /// checks it). Default: `DEFAULT_SKIN`.
    pub skin: Real,
    /// The deepest overlap the guard lets rapier's step take two meshes to,
    /// as a multiple of rapier's allowed linear error (without skins): an
    /// arriving pair that could close farther after its contact is stopped
    /// there, and a touching pair found deeper at a step's end is pushed
    /// apart. A body thinner than twice this depth can be crossed by a slow
    /// arrival: lower it, or ask for a skin. Finite and above 0
    /// ([`Guard::new`] checks it). Default: `DEFAULT_TOLERATED_DEPTH`.
    pub tolerated_depth: Real,
    /// How many times per step [`Guard::step`] may move the world back to a
    /// contact and let rapier solve from there; after that, arrivals hold
    /// their dynamic bodies at their contacts for the rest of the step.
    /// Default: `DEFAULT_MAX_SUBSTEPS`.
    pub max_substeps: usize,
}

/// How far outside a ball, capsule or cylinder collider its swept
/// polyhedron may stand, as a fraction of the contact skin (of rapier's
/// allowed linear error when the skin is 0): `0.25`.
pub(crate) const BALL_EXCESS_OF_SKIN: Real = 0.25;

/// [`GuardOptions::skin`]'s default: `0`, no skin (rapier's contacts as they
/// are).
pub(crate) const DEFAULT_SKIN: Real = 0.0;

/// [`GuardOptions::tolerated_depth`]'s default: `1.0`, rapier's allowed
/// linear error (0.005 × `length_unit`), which its soft contacts keep
/// resting pairs within.
pub(crate) const DEFAULT_TOLERATED_DEPTH: Real = 1.0;

/// What a touching pair found deeper than the tolerated depth is pushed
/// back to, as a fraction of it: `0.5` (room for rapier's next step).
pub(crate) const PUSHED_DEPTH_FRACTION: Real = 0.5;

/// [`GuardOptions::max_substeps`]'s default.
pub(crate) const DEFAULT_MAX_SUBSTEPS: usize = 4;

/// [`RunOptions::parallel_narrow_phase_seconds`](crate::stepper::RunOptions::parallel_narrow_phase_seconds) under a guard: between
/// two of its sweeps rapier steps on one thread and rayon's threads fall
/// asleep, so waking them costs more than under the stepper's own loop,
/// and their spinning afterwards slows rapier's step (measured on the
/// 1,000-body box: `docs/benchmarks-history.md`). Seconds.
pub(crate) const PARALLEL_NARROW_PHASE_SECONDS: Real = 3e-4;

impl Default for GuardOptions {
    fn default() -> Self {
        GuardOptions {
            ccd: CcdOptions::default(),
            kernel: DistanceKernel::Exact,
            parallel: true,
            skin: DEFAULT_SKIN,
            tolerated_depth: DEFAULT_TOLERATED_DEPTH,
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

    /// The tolerated depth under `parameters` (rapier3d-f64's; under an f32
    /// rapier the same product).
    pub fn tolerated_depth_under(&self, parameters: &IntegrationParameters) -> Real {
        self.tolerated_depth * parameters.allowed_linear_error()
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
/// parameters and the scene's `skin` (a multiple of rapier's allowed linear
/// error): `Err((body, contact distance, limit))` when the largest pair's
/// contact distance is not below the skins, or without skins rapier's
/// prediction distance (`body` is the one whose radius sets it).
pub(crate) fn simulate_contact_limit(
    ccd: &CcdOptions,
    bodies: &[Body],
    skin: Real,
) -> Result<(), (String, Real, Real)> {
    let parameters = IntegrationParameters::default();
    let options = GuardOptions { skin, ..GuardOptions::default() };
    let limit = contact_distance_limit(parameters.prediction_distance(), options.skin_under(&parameters));
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
    /// swept for their next contact.
    Stopped {
        /// The first body.
        a: H,
        /// The second body.
        b: H,
    },
    /// Two touching bodies that rapier's contact let sink deeper than the
    /// tolerated depth by the step's end (a body squeezed by a kinematic
    /// one, a load rapier's solver could not carry).
    Overlap {
        /// The first body.
        a: H,
        /// The second body.
        b: H,
        /// How deep they overlapped (convex meshes: exactly; others: the
        /// deepest vertex where their surfaces cross).
        depth: Real,
        /// Whether the guard pushed them apart to half the tolerated depth
        /// (their dynamic bodies, by their inverse masses, and their
        /// approach along the push removed); `false` when neither is
        /// dynamic.
        pushed_apart: bool,
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
    #[error("{body}: {message}")]
    Shape {
        /// The body, as messages name it (`rigid body #3`; under a scene,
        /// ``body `name` ``).
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
    /// [`GuardOptions::tolerated_depth`] is not above 0 or not finite.
    #[error("GuardOptions::tolerated_depth must be a finite multiple of rapier's allowed linear error, above 0; found {0}")]
    ToleratedDepth(Real),
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
    /// The deepest overlap the guard lets rapier take pairs to.
    pub tolerated_depth: Real,
    /// Which pairs rapier solves.
    pub solved: Arc<PairRules>,
    /// Whether the guard may move bodies (`false`: a watcher of rapier's
    /// motion that never rewinds, holds or pushes).
    pub acts: bool,
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
        if !(options.tolerated_depth.is_finite() && options.tolerated_depth > 0.0) {
            return Err(GuardError::ToleratedDepth(options.tolerated_depth));
        }
        let allowed_error = B::allowed_linear_error(parameters);
        let skin = options.skin * allowed_error;
        // A round shape's polyhedron stands at most a quarter skin (or of
        // rapier's allowed error) outside it.
        let excess = BALL_EXCESS_OF_SKIN * if skin > 0.0 { skin } else { allowed_error };
        let length_unit = B::length_unit(parameters);
        let mut scene_bodies = Vec::with_capacity(guarded.len());
        let mut centers = Vec::with_capacity(guarded.len());
        let mut stoppable = Vec::with_capacity(guarded.len());
        let mut rules = Vec::with_capacity(guarded.len());
        let mut hooks = Vec::with_capacity(guarded.len());
        for &handle in guarded {
            let body = bodies.view(handle).ok_or(GuardError::UnknownBody(handle))?;
            let name = B::describe(handle);
            let (mesh, center) = mesh_of_body(bodies, colliders, handle, &name, (excess, length_unit))?;
            if skin > 0.0 {
                // Without a skin rapier's colliders are left as they are.
                bodies.give_skin(colliders, handle, skin);
            }
            rules.push(bodies.rules(colliders, handle));
            hooks.push(bodies.contact_hooks(colliders, handle));
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
                skin: options.skin,
            },
            bodies: Arc::new(scene_bodies),
            parameters: Default::default(),
        };
        let solved = solved_pairs::<B>(rules, hooks);
        let setup = GuardSetup {
            handles: guarded.to_vec(),
            centers,
            stoppable,
            skin,
            tolerated_depth: options.tolerated_depth * allowed_error,
            solved,
            acts: true,
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
        let options = RunOptions {
            parallel: setup.parallel,
            parallel_narrow_phase_seconds: PARALLEL_NARROW_PHASE_SECONDS,
            ..RunOptions::default()
        };
        let thickness: Arc<[Real]> = model.bodies.iter().map(|b| thickness(&b.mesh)).collect();
        let response = Box::new(Watch {
            dynamic: setup.stoppable.clone(),
            thickness: Arc::clone(&thickness),
            separation: two_skins(setup.skin) + B::prediction_distance(parameters),
            skin_separation: if setup.skin > 0.0 {
                model.ccd.minimum_separation + two_skins(setup.skin)
            } else {
                0.0
            },
            tolerated_depth: setup.tolerated_depth,
            solved: Arc::clone(&setup.solved),
        });
        let mut stepper = Stepper::with_response(Arc::clone(&model), run, options, response);
        stepper.set_extra_box_margin(setup.skin);
        let world = stepper.new_world(false);
        Ok(Guard {
            start: model.bodies.iter().map(|b| b.pose).collect(),
            velocities: model.bodies.iter().map(|b| (b.velocity, b.angular_velocity)).collect(),
            handles: setup.handles,
            centers: setup.centers,
            stoppable: setup.stoppable,
            started: false,
            stepper,
            world,
            step: 0,
            steps_before: 0,
            time_before: 0.0,
            dt: B::dt(parameters),
            max_substeps: setup.max_substeps,
            tolerated_depth: setup.tolerated_depth,
            thickness,
            solved: setup.solved,
            depth: setup.acts.then(DepthWatch::default),
            deep: Vec::new(),
            options: None,
            rewinds: 0,
            events: Vec::new(),
            undecided: None,
        })
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
        self.world.rewound.clear();
        let contacts_before = self.world.contacts.len();
        let t0 = self.step as Real * self.dt;
        // Time into the step at the current sweep's start; each sweep runs
        // over the rest of the step, its motions stretched over `dt`.
        let mut elapsed: Real = 0.0;
        let mut substeps = 0;
        // Sweeps after stops (no rapier step between): each stops more
        // bodies, so there are at most as many as bodies.
        let mut restops = 0;
        loop {
            self.set_motions(bodies, elapsed);
            self.world.may_rewind = engine.is_some() && substeps < self.max_substeps;
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
            // Stopped bodies stay at their contacts (also when a pair was
            // undecided: the contacts before it stand).
            let stops = std::mem::take(&mut self.world.stops);
            let stopped = self.stop_bodies(bodies, &stops, scale);
            self.world.stops = stops;
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
            if let (Some(rewind), Some(engine)) = (self.world.rewind.take(), engine.as_mut()) {
                // The response never asks for the sweep's start (rapier's
                // step began there already).
                debug_assert!(rewind.time > 0.0);
                let at = rewind.time;
                self.rewind(bodies, at, [rewind.a, rewind.b]);
                // A kinematic body has infinite mass: the dynamic body it
                // meets leaves at least as fast as its point at the contact.
                let kinematic = |i: usize| is_kinematic(bodies, self.handles[i]);
                if let (Some(point), Some(normal), true) =
                    (rewind.point, rewind.normal, kinematic(rewind.a) != kinematic(rewind.b))
                {
                    self.inelastic_impulse(bodies, [rewind.a, rewind.b], &point, &normal);
                }
                self.world.rewound.push((rewind.a, rewind.b));
                elapsed += at * scale;
                substeps += 1;
                self.rewinds += 1;
                engine(bodies, self.dt - elapsed);
                continue;
            }
            if stopped && restops < self.handles.len() {
                // Swept again: a body that stopped may now be in another's way.
                restops += 1;
                continue;
            }
            self.watch_depths(bodies, scale, contacts_before);
            break;
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

/// Which pairs of bodies rapier solves, from each body's solid colliders'
/// rules (`rules[i]`, the guard's order: those with a pair of colliders
/// that meet, [`RapierBodies::solves`]) and contact hooks.
pub(crate) fn solved_pairs<B: RapierBodies>(
    rules: Vec<Vec<B::Rule>>,
    hooks: Vec<ContactHooks>,
) -> Arc<PairRules> {
    Arc::new(PairRules::new(
        Box::new(move |a, b| rules[a].iter().any(|ra| rules[b].iter().any(|rb| B::solves(ra, rb)))),
        hooks,
    ))
}

//! Tunnel-free rapier bodies: nearmiss's conservative CCD guarding a rapier
//! simulation (the `rapier` feature, on by default).
//!
//! rapier never sweeps a moving triangle mesh (a mesh bullet passes a thin
//! plate even with CCD on). A [`Guard`] sweeps the bodies it guards over
//! each step, from their poses before `PhysicsPipeline::step` to rapier's
//! poses after it, with nearmiss's mesh CCD; a pair that would come into
//! contact within the step is reported once ([`GuardEvent::Started`], with
//! nearmiss's time of impact, points and features) and each of its dynamic
//! bodies is moved back to its pose at that time (the motion clamping rapier
//! applies for its own CCD: poses clamped, velocities left to rapier's
//! contact solver on the next step). Pairs in contact are rapier's to hold:
//! the guard does not query them until they separate
//! ([`GuardEvent::Stopped`]: farther apart than rapier's prediction
//! distance), so resting contact costs nothing and is reported once.
//! Fixed and kinematic bodies are never moved (rapier drives them); their
//! contacts are reported.
//!
//! ```no_run
//! use nearmiss::guard::{Guard, GuardOptions};
//! use rapier3d_f64::prelude::*;
//!
//! let (mut bodies, mut colliders) = (RigidBodySet::new(), ColliderSet::new());
//! // ... insert bodies and mesh colliders ...
//! # let guarded: Vec<RigidBodyHandle> = Vec::new();
//! let parameters = IntegrationParameters::default();
//! let mut guard = Guard::new(&bodies, &colliders, &guarded, &parameters, GuardOptions::default())?;
//! # let (mut pipeline, mut islands, mut broad_phase, mut narrow_phase) =
//! #     (PhysicsPipeline::new(), IslandManager::new(), DefaultBroadPhase::default(), NarrowPhase::new());
//! # let (mut impulse_joints, mut multibody_joints, mut soft_bodies, mut ccd) =
//! #     (ImpulseJointSet::new(), MultibodyJointSet::new(), SoftBodySet::new(), CCDSolver::new());
//! for _ in 0..100 {
//!     guard.before_step(&bodies);
//!     pipeline.step(Vector::new(0.0, -9.81, 0.0), &parameters, &mut islands, &mut broad_phase,
//!         &mut narrow_phase, &mut bodies, &mut colliders, &mut impulse_joints,
//!         &mut multibody_joints, &mut soft_bodies, &mut ccd, &(), &());
//!     for event in guard.after_step(&mut bodies)? {
//!         println!("{event:?}");
//!     }
//! }
//! # Ok::<(), nearmiss::guard::GuardError>(())
//! ```
//!
//! The guard works on the bodies' centres of mass: the mesh it sweeps is the
//! triangles of a body's colliders (triangle meshes, convex polyhedra,
//! cuboids) relative to the body's centre of mass, and a body's motion over
//! a step is the constant linear and angular velocity that takes its start
//! pose to its end pose (the turn nearest rapier's angular velocity). The
//! scene runner's `on_contact: Simulate` is built on the same type.

mod compare;
mod shapes;
pub(crate) mod simulate;

pub use compare::{
    compare_with_rapier, rapier_markdown, run_rapier_alone, RapierAlone, RapierPair, PENETRATION_LIMIT_FACTOR,
};

use std::sync::Arc;

use nalgebra::Translation3;
use rapier3d_f64::prelude::{IntegrationParameters, RigidBody, RigidBodyHandle, RigidBodySet};

pub use shapes::{collider_for, is_convex, mesh_of_body, ColliderShape, CONVEXITY_TOLERANCE};

use crate::ccd::CcdOptions;
use crate::math::{from_parry, pose_from_parry, pose_to_parry, Pose, Real, Vector};
use crate::mesh::DistanceKernel;
use crate::motion::StepMotion;
use crate::response::Clamp;
use crate::scene::{Body, BodyMotion, OnContact, Scene};
use crate::stepper::{Contact, RunOptions, Stepper, Termination, World};

/// How a [`Guard`] sweeps.
#[derive(Copy, Clone, Debug, PartialEq)]
pub struct GuardOptions {
    /// The CCD's tolerances and limits (the contact distance is relative to
    /// the smaller body of a pair, see [`CcdOptions`]). It must stay below
    /// rapier's prediction distance so that rapier's solver sees the pairs
    /// the guard stops ([`Guard::new`] checks it for bodies up to the
    /// largest guarded). Default: [`CcdOptions::default`].
    pub ccd: CcdOptions,
    /// The CCD's distance kernel. Default: exact.
    pub kernel: DistanceKernel,
    /// Sweep pairs on rayon's threads. Default: true.
    pub parallel: bool,
}

impl Default for GuardOptions {
    fn default() -> Self {
        GuardOptions { ccd: CcdOptions::default(), kernel: DistanceKernel::Exact, parallel: true }
    }
}

/// What the guard saw in a step.
#[derive(Clone, Debug, PartialEq)]
pub enum GuardEvent {
    /// Two guarded bodies came into contact within the step (and the
    /// dynamic ones among them were moved back to their poses at that
    /// time).
    Started {
        /// The first body.
        a: RigidBodyHandle,
        /// The second body.
        b: RigidBodyHandle,
        /// The contact: time (since the guard's first step), distance,
        /// points (world frame), features and the contact contract.
        contact: Box<Contact>,
    },
    /// Two bodies in contact separated by the step's end (farther apart
    /// than rapier's prediction distance, or apart for the whole step): the
    /// guard sweeps them again.
    Stopped {
        /// The first body.
        a: RigidBodyHandle,
        /// The second body.
        b: RigidBodyHandle,
    },
}

/// What can go wrong.
#[derive(Debug, thiserror::Error)]
pub enum GuardError {
    /// A guarded handle is not in the body set.
    #[error("rigid body {0:?} is not in the body set")]
    UnknownBody(RigidBodyHandle),
    /// A body's colliders give no mesh the guard can sweep.
    #[error("body {body}: {message}")]
    Shape {
        /// The body.
        body: String,
        /// What is wrong.
        message: String,
    },
    /// The CCD's contact distance is not below rapier's prediction distance.
    #[error("the CCD's contact distance ({contact_distance:e}, for body {body}) is not below rapier's prediction distance ({prediction:e}): rapier would not see the contacts the guard stops; lower `GuardOptions::ccd.distance_tolerance`")]
    ContactDistance {
        /// The body.
        body: String,
        /// Its contact distance.
        contact_distance: Real,
        /// rapier's prediction distance.
        prediction: Real,
    },
    /// `after_step` without `before_step`.
    #[error("after_step was called without before_step")]
    NoStartPoses,
    /// A pair's CCD ran out of iterations: it is proven apart only up to
    /// `time`, and the guard cannot say what happened after.
    #[error("the CCD of bodies {a:?} and {b:?} could not decide after {iterations} iterations (proven apart up to t = {time}): raise `GuardOptions::ccd.max_iterations`")]
    Undecided {
        /// The first body.
        a: RigidBodyHandle,
        /// The second body.
        b: RigidBodyHandle,
        /// Proven apart up to this time (since the guard's first step).
        time: Real,
        /// The CCD iterations made.
        iterations: usize,
    },
}

/// Guards rapier bodies against tunnelling (see the module).
pub struct Guard {
    /// The guarded bodies, in the guard's order.
    handles: Vec<RigidBodyHandle>,
    /// Each body's centre of mass in its body frame.
    centers: Vec<Vector>,
    /// The poses of the centres of mass at the step's start.
    start: Vec<Pose>,
    started: bool,
    pub(crate) stepper: Stepper,
    pub(crate) world: World,
    /// Steps guarded.
    step: u64,
    dt: Real,
    events: Vec<GuardEvent>,
    /// The last step's undecided query, as the stepper reported it.
    pub(crate) undecided: Option<Termination>,
}

impl Guard {
    /// A guard of the bodies `guarded` (their colliders' triangles) for
    /// steps of `parameters.dt` (every step: for another dt, make another
    /// guard).
    pub fn new(
        bodies: &RigidBodySet,
        colliders: &rapier3d_f64::prelude::ColliderSet,
        guarded: &[RigidBodyHandle],
        parameters: &IntegrationParameters,
        options: GuardOptions,
    ) -> Result<Guard, GuardError> {
        let mut scene_bodies = Vec::with_capacity(guarded.len());
        let mut centers = Vec::with_capacity(guarded.len());
        let mut stoppable = Vec::with_capacity(guarded.len());
        for &handle in guarded {
            let body = bodies.get(handle).ok_or(GuardError::UnknownBody(handle))?;
            let name = format!("{handle:?}");
            let (mesh, center) = mesh_of_body(body, colliders, &name)?;
            scene_bodies.push(Body {
                name,
                mesh: Arc::new(mesh),
                pose: center_pose(body, &center),
                velocity: Vector::zeros(),
                angular_velocity: Vector::zeros(),
                mass: None,
                inertia: None,
                motion: if body.is_fixed() { BodyMotion::Fixed } else { BodyMotion::Free },
                kinematic: body.is_kinematic(),
                material: None,
            });
            centers.push(center);
            stoppable.push(body.is_dynamic());
        }
        let scene = Scene {
            name: "guard".into(),
            source: "nearmiss::guard".into(),
            dt: parameters.dt,
            steps: u64::MAX,
            duration: Real::INFINITY,
            integrator: Default::default(),
            gyroscopic: Default::default(),
            ccd: options.ccd,
            kernel: options.kernel,
            on_contact: OnContact::Simulate {
                restitution: 0.0,
                friction: crate::scene::file::DEFAULT_FRICTION,
                solver_iterations: crate::scene::file::DEFAULT_SOLVER_ITERATIONS,
            },
            trace: None,
            plot: None,
            bodies: Arc::new(scene_bodies),
            expect: None,
            poses: None,
            parameters: Default::default(),
        };
        Guard::with_scene(Arc::new(scene), guarded.to_vec(), centers, stoppable, parameters, options.parallel)
    }

    /// The guard of a scene already built (the scene runner's: its bodies
    /// are `handles`, its meshes relative to their bodies' frames, which are
    /// their centres of mass).
    pub(crate) fn with_scene(
        scene: Arc<Scene>,
        handles: Vec<RigidBodyHandle>,
        centers: Vec<Vector>,
        stoppable: Vec<bool>,
        parameters: &IntegrationParameters,
        parallel: bool,
    ) -> Result<Guard, GuardError> {
        let prediction = parameters.prediction_distance();
        for body in scene.bodies.iter() {
            let contract = crate::ccd::ContactContract::of(
                &scene.ccd,
                crate::ccd::ContactRule::ScaleRelative,
                body.mesh.radius(),
                0.0,
            );
            if contract.contact_distance >= prediction {
                return Err(GuardError::ContactDistance {
                    body: body.name.clone(),
                    contact_distance: contract.contact_distance,
                    prediction,
                });
            }
        }
        let options = RunOptions { parallel, broad_phase: true };
        let response = Box::new(Clamp { stoppable, separation: prediction });
        let stepper = Stepper::with_response(Arc::clone(&scene), options, response);
        let mut world = World::new(&scene, false);
        if !stepper.has_broad_phase() {
            world.pairs = scene
                .movable_pairs()
                .into_iter()
                .map(|(a, b)| crate::stepper::PairState::new(a, b))
                .collect();
        }
        Ok(Guard {
            start: scene.bodies.iter().map(|b| b.pose).collect(),
            handles,
            centers,
            started: false,
            stepper,
            world,
            step: 0,
            dt: parameters.dt,
            events: Vec::new(),
            undecided: None,
        })
    }

    /// Notes the guarded bodies' poses before rapier's step.
    pub fn before_step(&mut self, bodies: &RigidBodySet) {
        for (i, handle) in self.handles.iter().enumerate() {
            if let Some(body) = bodies.get(*handle) {
                self.start[i] = center_pose(body, &self.centers[i]);
            }
        }
        self.started = true;
    }

    /// Sweeps the guarded bodies from their poses at
    /// [`before_step`](Guard::before_step) to where rapier's step left
    /// them; moves dynamic bodies that would come into contact back to
    /// their poses at contact. Returns the step's events.
    pub fn after_step(&mut self, bodies: &mut RigidBodySet) -> Result<&[GuardEvent], GuardError> {
        if !std::mem::take(&mut self.started) {
            return Err(GuardError::NoStartPoses);
        }
        self.events.clear();
        for (i, handle) in self.handles.iter().enumerate() {
            let Some(body) = bodies.get(*handle) else { continue };
            let end = center_pose(body, &self.centers[i]);
            self.world.motions[i] = if body.is_fixed() {
                StepMotion::fixed(end)
            } else {
                StepMotion::between_near(&self.start[i], &end, self.dt, &from_parry(body.angvel()).coords)
            };
        }
        let contacts_before = self.world.contacts.len();
        let result = self.stepper.after_motion(&mut self.world, self.step);
        self.step += 1;
        // Held bodies go back to their poses at contact (also when a pair
        // was undecided: the contacts before it stand).
        for &(i, at) in &self.world.held {
            let Some(body) = bodies.get_mut(self.handles[i]) else { continue };
            let held = self.world.motions[i].pose_at(at.min(self.dt));
            body.set_position(pose_to_parry(&body_pose(&held, &self.centers[i])), true);
        }
        if let Err(undecided @ Termination::Undecided { pair: (a, b), time, iterations, .. }) = result {
            self.undecided = Some(undecided);
            return Err(GuardError::Undecided { a: self.handles[a], b: self.handles[b], time, iterations });
        }
        let handles = &self.handles;
        self.events.extend(self.world.contacts[contacts_before..].iter().map(|contact| {
            GuardEvent::Started {
                a: handles[contact.body_a],
                b: handles[contact.body_b],
                contact: Box::new(contact.clone()),
            }
        }));
        self.events.extend(
            self.world.separated.iter().map(|&(a, b)| GuardEvent::Stopped { a: handles[a], b: handles[b] }),
        );
        Ok(&self.events)
    }

    /// Every contact reported so far, in the order found (body indices are
    /// positions in the guarded list).
    pub fn contacts(&self) -> &[Contact] {
        &self.world.contacts
    }

    /// The guarded bodies, in the guard's order.
    pub fn handles(&self) -> &[RigidBodyHandle] {
        &self.handles
    }

    /// The guard's work so far (CCD queries, stage times).
    pub fn counters(&self) -> &crate::stepper::Counters {
        self.stepper.counters()
    }

    /// The steps guarded so far.
    pub fn steps(&self) -> u64 {
        self.step
    }

    /// The guard's world and stepper, for the scene runner.
    pub(crate) fn into_parts(self) -> (Stepper, World) {
        (self.stepper, self.world)
    }
}

/// The pose of a body's centre of mass (`center`, body frame).
fn center_pose(body: &RigidBody, center: &Vector) -> Pose {
    let pose = pose_from_parry(body.position());
    Pose::from_parts(Translation3::from(pose.translation.vector + pose.rotation * center), pose.rotation)
}

/// The body-frame pose whose centre of mass (`center`) is at `center_pose`.
fn body_pose(center_pose: &Pose, center: &Vector) -> Pose {
    let rotation = center_pose.rotation;
    Pose::from_parts(Translation3::from(center_pose.translation.vector - rotation * center), rotation)
}

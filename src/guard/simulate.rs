//! `on_contact: Simulate`: a scene run by rapier3d and guarded by a
//! [`Guard`], as the run loop's driver ([`crate::stepper::run_with`]).
//! Each fixed step: kinematic bodies' targets and the springs' forces are
//! set from the bodies' states, rapier steps (gravity, forces, contact
//! solving), and the guard sweeps every pair from the step's start poses to
//! rapier's end poses, moving the world back to a contact where rapier
//! would let a pair reach the meshes and letting rapier solve the rest of
//! the step from there. The trace and the poses are the stepper's
//! observers, run by the guard's stepper.

use std::sync::Arc;
use std::time::Instant;

use rapier3d_f64::prelude::{
    CCDSolver, ColliderBuilder, ColliderSet, DefaultBroadPhase, ImpulseJointSet, IntegrationParameters,
    IslandManager, MassProperties, MultibodyJointSet, NarrowPhase, PhysicsPipeline, RigidBodyBuilder,
    RigidBodyHandle, RigidBodySet, SharedShape, SoftBodySet,
};

use super::{collider_for, ColliderShape, Guard, GuardError, GuardSetup};
use crate::math::{
    from_parry, pose_from_parry, pose_to_parry, to_parry, vector_to_parry, Point, Real, Vector,
};
use crate::motion::{RigidState, StepMotion};
use crate::scene::{BodyMotion, OnContact, Scene};
use crate::stepper::{Driver, RunOptions, RunResult, Solver, StepEnd, Termination};

/// The engine named in `summary.json`.
pub const ENGINE: &str = "rapier3d-f64 0.36";

/// A scene's bodies in rapier: the sets, the pipeline, and each scene
/// body's handle.
pub(crate) struct RapierScene {
    pub bodies: RigidBodySet,
    pub colliders: ColliderSet,
    pub handles: Vec<RigidBodyHandle>,
    /// The collider shape each body was given.
    pub shapes: Vec<ColliderShape>,
    pub parameters: IntegrationParameters,
    pub gravity: Vector,
    /// Each collider's contact skin (the guard's; 0 for rapier alone).
    pub skin: Real,
    engine: Engine,
}

/// rapier's pipeline and the sets a step needs besides the bodies and
/// colliders.
struct Engine {
    pipeline: PhysicsPipeline,
    islands: IslandManager,
    broad_phase: DefaultBroadPhase,
    narrow_phase: NarrowPhase,
    impulse_joints: ImpulseJointSet,
    multibody_joints: MultibodyJointSet,
    soft_bodies: SoftBodySet,
    ccd: CCDSolver,
}

impl Engine {
    /// `PhysicsPipeline::step` by `dt`.
    fn step(
        &mut self,
        bodies: &mut RigidBodySet,
        colliders: &mut ColliderSet,
        parameters: &IntegrationParameters,
        gravity: &Vector,
        dt: Real,
    ) {
        let parameters = IntegrationParameters { dt, ..*parameters };
        self.pipeline.step(
            vector_to_parry(gravity),
            &parameters,
            &mut self.islands,
            &mut self.broad_phase,
            &mut self.narrow_phase,
            bodies,
            colliders,
            &mut self.impulse_joints,
            &mut self.multibody_joints,
            &mut self.soft_bodies,
            &mut self.ccd,
            &(),
            &(),
        );
    }
}

impl RapierScene {
    /// The scene's bodies as rapier bodies: fixed, kinematic (velocity
    /// based) or dynamic (with the scene's mass and inertia about the
    /// centre of mass, which is the body frame's origin), each with the
    /// collider [`collider_for`] its mesh, and the scene's materials.
    /// `rapier_ccd`: switch rapier's own CCD on for every moving body
    /// (`--compare rapier`); `guarded`: give every collider the scene's
    /// contact skin (`on_contact: Simulate(skin: ...)`, 0 by default;
    /// rapier alone gets none).
    pub fn build(scene: &Scene, rapier_ccd: bool, guarded: bool) -> Result<RapierScene, GuardError> {
        let (friction, restitution, solver_iterations, skin) = match scene.model.on_contact {
            OnContact::Simulate { friction, restitution, solver_iterations, skin } => {
                (friction, restitution, solver_iterations, skin)
            }
            _ => (
                crate::scene::file::DEFAULT_FRICTION,
                0.0,
                crate::scene::file::DEFAULT_SOLVER_ITERATIONS,
                0.0,
            ),
        };
        let mut parameters = IntegrationParameters { dt: scene.model.dt, ..Default::default() };
        parameters.num_solver_iterations = solver_iterations;
        // A scene's velocities are what it says: no speed cap (rapier's
        // default caps bodies at 400 units per second).
        parameters.normalized_max_linear_velocity = Real::MAX;
        let guard_options = super::GuardOptions { skin, ..super::GuardOptions::default() };
        let skin = if guarded { guard_options.skin_under(&parameters) } else { 0.0 };
        let mut bodies = RigidBodySet::new();
        let mut colliders = ColliderSet::new();
        let mut handles = Vec::with_capacity(scene.model.bodies.len());
        let mut shapes = Vec::with_capacity(scene.model.bodies.len());
        // The scene's gravity where it pulls an integrated body (rapier's
        // dynamic bodies of a scene with none, `--compare rapier` of a scene
        // under another response, keep their velocities).
        let gravity = if scene.model.bodies.iter().any(crate::scene::Body::is_integrated) {
            scene.model.gravity
        } else {
            Vector::zeros()
        };
        // One collider shape per mesh asset (and shape kind): bodies of one
        // mesh share it, as they share the mesh (a thousand icospheres are
        // one convexity check and one hull).
        let mut built: Vec<(*const crate::mesh::TriMesh, bool, SharedShape, ColliderShape)> = Vec::new();
        for body in scene.model.bodies.iter() {
            let rigid = rigid_body_of(body, rapier_ccd);
            let handle = bodies.insert(rigid);
            let material = body.material.unwrap_or(crate::scene::Material {
                friction,
                restitution,
                triangle_mesh: false,
            });
            let asset = (Arc::as_ptr(&body.mesh), material.triangle_mesh);
            let (shared, shape) = match built.iter().find(|(mesh, kind, ..)| (*mesh, *kind) == asset) {
                Some((_, _, shared, shape)) => (shared.clone(), *shape),
                None => {
                    let (collider, shape) =
                        collider_for(&body.mesh, material.triangle_mesh).map_err(|error| {
                            GuardError::Shape {
                                body: format!("body `{}`", body.name),
                                message: error.to_string(),
                            }
                        })?;
                    built.push((asset.0, asset.1, collider.shape.clone(), shape));
                    (collider.shape, shape)
                }
            };
            let mut collider = ColliderBuilder::new(shared)
                .friction(material.friction)
                .restitution(material.restitution)
                .contact_skin(skin);
            if let (Some(mass), Some(inertia)) = (body.mass, body.inertia) {
                let inertia = glam_matrix(&inertia);
                collider = collider.mass_properties(MassProperties::with_inertia_matrix(
                    to_parry(&Point::origin()),
                    mass,
                    inertia,
                ));
            }
            colliders.insert_with_parent(collider.build(), handle, &mut bodies);
            handles.push(handle);
            shapes.push(shape);
        }
        Ok(RapierScene {
            bodies,
            colliders,
            handles,
            shapes,
            parameters,
            gravity,
            skin,
            engine: Engine::new(),
        })
    }

    /// Rapier's step `step` (0-based): [`prepare`](RapierScene::prepare),
    /// then `PhysicsPipeline::step` by the scene's `dt`.
    pub fn step(&mut self, scene: &Scene, step: u64) {
        self.prepare(scene, step);
        self.engine.step(
            &mut self.bodies,
            &mut self.colliders,
            &self.parameters,
            &self.gravity,
            scene.model.dt,
        );
    }

    /// Before rapier's step `step`: kinematic bodies' next poses on their
    /// exact motions, the springs' forces from the bodies' states.
    pub fn prepare(&mut self, scene: &Scene, step: u64) {
        let end = (step + 1) as Real * scene.model.dt;
        for (body, handle) in scene.model.bodies.iter().zip(&self.handles) {
            if body.kinematic {
                if let Some(rigid) = self.bodies.get_mut(*handle) {
                    let motion = StepMotion::free(&body.pose, body.velocity, body.angular_velocity, 0.0);
                    rigid.set_next_kinematic_position(pose_to_parry(&motion.pose_at(end)));
                }
                continue;
            }
            let BodyMotion::Integrated { springs } = &body.motion else { continue };
            if springs.is_empty() {
                continue;
            }
            let Some(rigid) = self.bodies.get_mut(*handle) else { continue };
            let state = rigid_state(rigid);
            rigid.reset_forces(false);
            for spring in springs {
                let (force, arm) = spring.force(
                    &state.position,
                    &state.orientation,
                    &state.velocity,
                    &state.angular_velocity,
                );
                rigid.add_force_at_point(vector_to_parry(&force), to_parry(&(state.position + arm)), true);
            }
        }
    }

    /// Whether rapier has the two bodies' colliders in contact (a contact
    /// point within its prediction distance).
    pub fn in_contact(&self, a: usize, b: usize) -> bool {
        let collider =
            |i: usize| self.bodies.get(self.handles[i]).and_then(|body| body.colliders().first().copied());
        let (Some(ca), Some(cb)) = (collider(a), collider(b)) else { return false };
        self.engine.narrow_phase.contact_pair(ca, cb).is_some_and(|pair| pair.has_any_active_contact())
    }

    /// Which pairs of the scene's bodies rapier solves (by their colliders'
    /// rules, as the guard of an application reads them).
    pub fn solved_pairs(&self) -> std::sync::Arc<super::rules::PairRules> {
        use super::RapierBodies;
        let rules = self.handles.iter().map(|h| self.bodies.rules(&self.colliders, *h)).collect();
        let hooks = self.handles.iter().map(|h| self.bodies.contact_hooks(&self.colliders, *h)).collect();
        super::solved_pairs::<RigidBodySet>(rules, hooks)
    }

    /// Body `i`'s state (its centre of mass is its frame's origin).
    pub fn state(&self, i: usize) -> Option<RigidState> {
        self.bodies.get(self.handles[i]).map(rigid_state)
    }

    /// The depth by which the two bodies' colliders overlap (parry's
    /// contact query, independent of rapier's narrow phase): 0 when apart,
    /// `None` where parry cannot measure the pair of shapes.
    pub fn penetration(&self, a: usize, b: usize) -> Option<Real> {
        let collider = |i: usize| {
            let body = self.bodies.get(self.handles[i])?;
            self.colliders.get(*body.colliders().first()?)
        };
        let (ca, cb) = (collider(a)?, collider(b)?);
        let contact =
            parry3d_f64::query::contact(ca.position(), ca.shape(), cb.position(), cb.shape(), 0.0).ok()?;
        Some(contact.map_or(0.0, |c| (-c.dist).max(0.0)))
    }
}

/// A scene body as rapier's: fixed, kinematic (driven along its exact
/// motion) or dynamic, with rapier's CCD where asked for.
fn rigid_body_of(body: &crate::scene::Body, rapier_ccd: bool) -> rapier3d_f64::prelude::RigidBody {
    let builder = match &body.motion {
        BodyMotion::Fixed => RigidBodyBuilder::fixed(),
        // Driven along its exact motion (`step` sets each next pose).
        _ if body.kinematic => RigidBodyBuilder::kinematic_position_based(),
        BodyMotion::Integrated { .. } => RigidBodyBuilder::dynamic(),
        // Nothing acts on it in the scene (`--compare rapier` of a
        // scene under another response): dynamic, its mass from the
        // scene or rapier's default density.
        BodyMotion::Free => RigidBodyBuilder::dynamic(),
    };
    let moving = body.motion != BodyMotion::Fixed;
    builder
        .pose(pose_to_parry(&body.pose))
        .linvel(vector_to_parry(&body.velocity))
        .angvel(vector_to_parry(&body.angular_velocity))
        .ccd_enabled(rapier_ccd && moving)
        .soft_ccd_prediction(if rapier_ccd && moving { body.mesh.radius() } else { 0.0 })
        // A scene's spin is what it says (rapier caps it at about
        // 45° a step by default).
        .allow_fast_rotation(true)
        .build()
}

impl Engine {
    /// A pipeline and empty sets.
    fn new() -> Engine {
        Engine {
            pipeline: PhysicsPipeline::new(),
            islands: IslandManager::new(),
            broad_phase: DefaultBroadPhase::default(),
            narrow_phase: NarrowPhase::new(),
            impulse_joints: ImpulseJointSet::new(),
            multibody_joints: MultibodyJointSet::new(),
            soft_bodies: SoftBodySet::new(),
            ccd: CCDSolver::new(),
        }
    }
}

/// A rapier body's state.
fn rigid_state(body: &rapier3d_f64::prelude::RigidBody) -> RigidState {
    let pose = pose_from_parry(body.position());
    RigidState {
        position: Point::from(pose.translation.vector),
        orientation: pose.rotation,
        velocity: from_parry(body.linvel()).coords,
        angular_velocity: from_parry(body.angvel()).coords,
    }
}

/// A nalgebra matrix as glam's.
fn glam_matrix(m: &nalgebra::Matrix3<Real>) -> rapier3d_f64::math::Matrix {
    rapier3d_f64::math::Matrix::from_cols(
        to_parry(&Point::from(m.column(0).into_owned())),
        to_parry(&Point::from(m.column(1).into_owned())),
        to_parry(&Point::from(m.column(2).into_owned())),
    )
}

/// A `Simulate` scene's steps (see the module), for the run loop
/// ([`crate::stepper::run_with`]): rapier's bodies and the guard that
/// sweeps them.
pub(crate) struct Guarded {
    scene: Arc<Scene>,
    rapier: RapierScene,
    guard: Guard,
}

/// The driver of a `Simulate` scene: its bodies in rapier, each collider
/// with the guard's skin, and the guard over them.
pub(crate) fn driver(scene: &Scene, options: RunOptions) -> Result<Guarded, GuardError> {
    let rapier = RapierScene::build(scene, false, true)?;
    // The guard's model: rapier moves the bodies, so none is integrated by
    // the stepper; the dynamic ones are those contacts stop.
    let stoppable: Vec<bool> = scene.model.bodies.iter().map(crate::scene::Body::is_integrated).collect();
    let mut guarded = scene.model.clone();
    for body in Arc::make_mut(&mut guarded.bodies) {
        if body.motion != BodyMotion::Fixed {
            body.motion = BodyMotion::Free;
        }
    }
    let setup = GuardSetup {
        handles: rapier.handles.clone(),
        centers: vec![Vector::zeros(); scene.model.bodies.len()],
        stoppable,
        skin: rapier.skin,
        tolerated_depth: super::GuardOptions::default().tolerated_depth_under(&rapier.parameters),
        // A scene's colliders have no groups, sensors or hooks: every pair
        // is swept (a kinematic body's contacts with fixed ones reported).
        solved: std::sync::Arc::new(super::rules::PairRules::all(scene.model.bodies.len())),
        acts: true,
        max_substeps: super::DEFAULT_MAX_SUBSTEPS,
        parallel: options.parallel,
    };
    let guard = Guard::with_model(Arc::new(guarded), Some(&scene.run), setup, &rapier.parameters)?;
    Ok(Guarded { scene: Arc::new(scene.clone()), rapier, guard })
}

impl Driver for Guarded {
    fn start(&mut self) {
        self.guard.stepper.observe_start(&self.guard.world);
    }

    /// rapier's step (kinematic targets and springs' forces first), swept
    /// and rewound by the guard.
    fn step(&mut self, step: u64) -> Result<StepEnd, Termination> {
        self.rapier.prepare(&self.scene, step);
        let RapierScene { bodies, colliders, parameters, gravity, engine, .. } = &mut self.rapier;
        let outcome = self.guard.step(bodies, |bodies, dt| {
            engine.step(bodies, colliders, parameters, gravity, dt);
        });
        match outcome {
            Ok(_) => Ok(StepEnd::Continue),
            Err(error @ GuardError::Undecided { .. }) => {
                Err(self.guard.undecided.take().unwrap_or_else(|| Termination::Failed {
                    step,
                    reason: format!("the guard failed: {error}"),
                }))
            }
            Err(error) => Err(Termination::Failed { step, reason: format!("the guard failed: {error}") }),
        }
    }

    /// The stepper's result, with rapier's final states and who solved.
    fn finish(self: Box<Self>, steps: u64, termination: Termination, start: Instant) -> RunResult {
        let Guarded { scene, rapier, guard } = *self;
        let rewinds = guard.rewinds();
        let (stepper, world) = guard.into_parts();
        let mut result = stepper.finish(world, scene.run.name.clone(), steps, termination, start);
        for (i, state) in result.final_states.iter_mut().enumerate() {
            if let Some(rapier_state) = rapier.state(i) {
                *state = rapier_state;
            }
        }
        result.solver = Some(Solver {
            contact_skin: rapier.skin,
            rewinds,
            engine: ENGINE.into(),
            colliders: rapier.shapes.iter().map(|s| s.name().to_string()).collect(),
        });
        result
    }
}

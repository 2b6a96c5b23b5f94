//! A guard made: from rapier's bodies and colliders, for other bodies, or
//! from a scene's model (the `Simulate` driver's).

use std::sync::Arc;

use super::bodies::RapierBodies;
use super::parts::ContactHooks;
use super::views::BodyKind;

use super::shapes::mesh_of_body;

use super::depth::DepthWatch;
use super::events::GuardError;
use super::options::{
    contact_distance_limit, contact_within, two_skins, GuardOptions, BALL_EXCESS_OF_SKIN,
    PARALLEL_NARROW_PHASE_SECONDS,
};
use super::rules::PairRules;
use super::thickness::thickness;
use super::watch::Watch;
use super::Guard;
use crate::math::{Real, Vector};
use crate::scene::{Body, BodyMotion, Model, OnContact, RunSpec};
use crate::stepper::{PairState, RunOptions, Stepper};

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
    /// [`GuardOptions::skin`](super::GuardOptions::skin) (a larger skin is kept).
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
                path: None,
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
            // Rapier applies its own gravity to its bodies; none here is
            // integrated.
            gravity: Vector::zeros(),
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
    /// by [`Guard::new`](super::Guard::new) (otherwise [`GuardError::NotFromRapier`]).
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

    /// The guard of `model` (the scene runner's, with the observers of its
    /// `run`; or [`Guard::new`](super::Guard::new)'s, of rapier's bodies: its bodies are
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

//! The run loop, on top of the house: it picks a scene's driver (the
//! stepper's own integration, or rapier guarded by nearmiss under
//! `Simulate`), checks what a `Simulate` scene needs, and asks the driver
//! for each step until the scene's end, its first contact or the step
//! that ends it. Everything a caller reads of a run comes from here:
//! [`RunResult`] and the types in it are re-exported.

use std::time::Instant;

pub use crate::stepper::{
    write_poses_csv, write_trace_csv, Contact, Counters, NearMiss, PoseRecord, RunOptions, RunResult, Solver,
    StageSeconds, Termination, TraceRecord, Work,
};

use crate::scene::{OnContact, Scene, SceneError};
use crate::stepper::{Driver, Integrated, StepEnd};

/// Runs a scene: the bodies move step by step, and every contact is found
/// at its time, never late (see [`crate::stepper`] for the stages).
///
/// Two unit cubes 1 apart closing at 2 touch at `t = 0.5`:
///
/// ```
/// use nearmiss::scene::Scene;
/// let scene = Scene::from_ron_str(r#"Scene(name: "meet", dt: 0.1, duration: 1.0, bodies: [
///     (name: "a", mesh: Box(half_extents: (0.5, 0.5, 0.5)), velocity: (1.0, 0.0, 0.0)),
///     (name: "b", mesh: Box(half_extents: (0.5, 0.5, 0.5)), position: (2.0, 0.0, 0.0), velocity: (-1.0, 0.0, 0.0)),
/// ])"#).unwrap();
/// let result = nearmiss::run(&scene);
/// let contact = result.first_contact.unwrap();
/// assert!(contact.time <= 0.5 && contact.time > 0.5 - 1e-6);
/// assert_eq!((result.bodies[contact.body_a].as_str(), result.bodies[contact.body_b].as_str()), ("a", "b"));
/// ```
pub fn run(scene: &Scene) -> RunResult {
    run_observed(scene, &mut |_| {})
}

/// Runs a scene, calling `observer` with the number of steps done after
/// each step (for progress display).
pub fn run_observed(scene: &Scene, observer: &mut dyn FnMut(u64)) -> RunResult {
    run_with(scene, RunOptions::default(), observer)
}

/// Runs a scene with options: the one run loop of every response, its
/// steps made by the scene's driver (the stepper's integration, or rapier
/// guarded by nearmiss under `Simulate`).
pub fn run_with(scene: &Scene, options: RunOptions, observer: &mut dyn FnMut(u64)) -> RunResult {
    let start = Instant::now();
    let mut driver = match driver_for(scene, options) {
        Ok(driver) => driver,
        Err(reason) => return not_started(scene, reason, start),
    };
    let initial_overlaps = crate::scene::initial_overlaps(&scene.model.bodies);
    driver.start();
    let mut termination = Termination::Completed;
    let mut steps = 0;
    for step in 0..scene.run.steps {
        steps = step + 1;
        match driver.step(step) {
            Ok(StepEnd::Continue) => observer(steps),
            Ok(StepEnd::FirstContact) => {
                termination = Termination::FirstContact;
                break;
            }
            Err(ended) => {
                termination = ended;
                break;
            }
        }
    }
    RunResult { initial_overlaps, ..driver.finish(steps, termination, start) }
}

/// What a scene needs of this build to run, beyond what its file says:
/// under `Simulate`, the `rapier` feature, and a contact distance of its
/// largest pair inside the two colliders' contact skins (or, without
/// skins, rapier's prediction distance), so that the guard's wall lies
/// inside rapier's contact. The command line calls it after loading a
/// scene, so that such a scene is refused as bad input; [`run`] reports
/// it as [`Termination::NotStarted`].
pub fn check(scene: &Scene) -> Result<(), SceneError> {
    let OnContact::Simulate { skin, .. } = scene.model.on_contact else { return Ok(()) };
    simulate_fits(scene, skin).map_err(|(field, message)| SceneError::Invalid {
        path: scene.run.source.clone(),
        field: field.into(),
        message,
    })
}

/// Whether this build can run a `Simulate` scene of collider skin `skin`:
/// `Err` names the field at fault and says why.
#[cfg(feature = "rapier")]
fn simulate_fits(scene: &Scene, skin: crate::math::Real) -> Result<(), (&'static str, String)> {
    use crate::math::shortest;
    let (body, contact_distance, limit) =
        match crate::guard::simulate_contact_limit(&scene.model.ccd, &scene.model.bodies, skin) {
            Ok(()) => return Ok(()),
            Err(failed) => failed,
        };
    Err((
        "ccd.distance_tolerance",
        format!(
                "a pair with `{body}` would have a contact distance of {} under `Simulate`, not below {} (the two colliders' contact skins, or without skins rapier's prediction distance): the guard's wall would lie outside rapier's contact; lower `distance_tolerance` or `minimum_separation`",
                shortest(contact_distance),
                shortest(limit)
            ),
    ))
}

/// Without the `rapier` feature no `Simulate` scene can run.
#[cfg(not(feature = "rapier"))]
fn simulate_fits(_scene: &Scene, _skin: crate::math::Real) -> Result<(), (&'static str, String)> {
    Err((
        "on_contact",
        "`Simulate` solves contacts with rapier3d: build nearmiss with the `rapier` feature".into(),
    ))
}

/// The scene's driver: rapier guarded by nearmiss under `Simulate`, the
/// stepper's integration otherwise. `Err`: why it could not be set up.
fn driver_for(scene: &Scene, options: RunOptions) -> Result<Box<dyn Driver>, String> {
    check(scene).map_err(|error| error.to_string())?;
    #[cfg(feature = "rapier")]
    if let OnContact::Simulate { .. } = scene.model.on_contact {
        return crate::guard::simulate::driver(scene, options)
            .map(|driver| Box::new(driver) as Box<dyn Driver>)
            .map_err(|error| format!("rapier could not be set up: {error}"));
    }
    match Integrated::of(scene, options) {
        Some(driver) => Ok(Box::new(driver)),
        None => Err("the scene's response has no driver in this build".into()),
    }
}

/// The result of a run whose driver could not be set up: no step, and why.
fn not_started(scene: &Scene, reason: String, start: Instant) -> RunResult {
    RunResult {
        scene: scene.run.name.clone(),
        bodies: scene.model.bodies.iter().map(|b| b.name.clone()).collect(),
        steps: 0,
        end_time: 0.0,
        wall_time_s: start.elapsed().as_secs_f64(),
        first_contact: None,
        contacts: Vec::new(),
        trace: Vec::new(),
        poses: Vec::new(),
        solver: None,
        termination: Termination::NotStarted { reason },
        counters: Counters::default(),
        final_states: Vec::new(),
        near_misses: Vec::new(),
        initial_overlaps: Vec::new(),
    }
}

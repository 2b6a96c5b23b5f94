//! Stage 1, integrate: each body's motion over the step, from its state
//! (fixed bodies stay, free ones move exactly, integrated ones take one
//! integrator step), checked for divergence.
//!
//! An integrated body's step is committed in the pass that makes it: its
//! state moves to the step's end and its motion over the step is written
//! at once, so that each body is read and written once a step (a second
//! pass over every body's step, kept apart until all were checked, was a
//! good part of this stage's time). A step in which any body fails a check
//! moves no body: it is undone from what the pass kept, each integrated
//! body's velocities at the step's start ([`SavedVelocities`]), and from
//! its new motion, which starts exactly at its pose at the step's start.

use rayon::prelude::*;

use std::time::Instant;

use super::result::{Counters, Termination};
use super::world::World;
use super::Stepper;
use crate::math::{Point, Real, Vector};
use crate::motion::{
    integrate_turning, spins_steadily, steady_spin_step, Dynamics, Integrator, IntegratorStep, RigidState,
    StepMotion, MAX_TURN_PER_STEP,
};
use crate::scene::{Body, BodyMotion, Model};

/// A body's integrator step: its next state, the angular velocity of the
/// motion between the two (the rest of the motion is a subtraction away),
/// and whether the solve converged.
#[derive(Copy, Clone, Debug)]
struct Advance {
    step: IntegratorStep,
}

/// A body's energy check: its mechanical energy at the step's end, its
/// initial energy and scale, and the growth allowed (a multiple of the
/// scale).
#[derive(Copy, Clone, Debug)]
struct EnergyCheck {
    now: Real,
    initial: Real,
    scale: Real,
    limit: Real,
}

impl EnergyCheck {
    /// The energy's drift, relative to the scale.
    fn drift(self) -> Real {
        (self.now - self.initial).abs() / self.scale
    }
}

/// Each integrated body's velocity and angular velocity at the current
/// step's start (a slot per body; the others' unused): with its motion's
/// start, its state there, should the step be undone.
pub(crate) type SavedVelocities = Vec<(Vector, Vector)>;

impl Stepper {
    /// Moves every body's motion to the step starting at `t0` (step number
    /// `step`), checked for divergence.
    pub(super) fn integrate(&mut self, world: &mut World, step: u64, t0: Real) -> Result<(), Termination> {
        let clock = Instant::now();
        let mut saved = std::mem::take(&mut self.scratch.saved);
        let result = self.integrate_into(world, &mut saved, step, t0);
        self.scratch.saved = saved;
        self.counters.seconds.integrate += clock.elapsed().as_secs_f64();
        result
    }

    fn integrate_into(
        &mut self,
        world: &mut World,
        saved: &mut SavedVelocities,
        step: u64,
        t0: Real,
    ) -> Result<(), Termination> {
        let check_energy = self.checks_energy();
        let (model, counters, still) = (&*self.model, &mut self.counters, &self.still);
        let dt = model.dt;
        let World { states, motions, energies, .. } = world;
        let energies = &*energies;
        let parallel =
            self.options.parallel && model.bodies.len() >= self.options.parallel_integration_bodies;
        // An integrated body's step and the checks made with it: whether it
        // fails one, whether its gyroscopic solve converged, its energy's
        // drift. Combined over the bodies by minimum (the earliest body that
        // fails one is the one reported), sum and maximum, so the same
        // whatever the threads.
        let limit = model.parameters.divergence_energy_growth;
        let energy_of = |i: usize, dynamics: &Dynamics, advance: &Advance| {
            check_energy.then(|| {
                let (initial, scale) = energies[i];
                EnergyCheck { now: dynamics.energy(&advance.step.next), initial, scale, limit }
            })
        };
        // (`None` for a steady spin's step, whose run checks no energy.)
        let checked = |i: usize, dynamics: Option<&Dynamics>, advance: &Advance| {
            let energy = dynamics.and_then(|dynamics| energy_of(i, dynamics, advance));
            Checked {
                first_failure: advance.failure(dt, energy).map(|_| i),
                unconverged: usize::from(!advance.step.converged),
                max_drift: energy.map_or(0.0, EnergyCheck::drift),
            }
        };
        // Each integrated body moves to its step's end as soon as its step
        // is made (its velocities kept first). A still body (fixed, or at
        // rest in the stepper's own integration) is not read (in a scene of
        // many fixed bodies, reading them was most of this stage); the other
        // bodies that are not integrated move below.
        saved.resize(model.bodies.len(), (Vector::zeros(), Vector::zeros()));
        // The bodies whose step is a steady spin's, decided once (see
        // `steady_bodies`): their step reads their state and nothing of
        // the body itself.
        let steady = &*self.steady.get_or_insert_with(|| steady_bodies(model, still, check_energy));
        let step_body = |i: usize,
                         body: &Body,
                         state: &mut Option<RigidState>,
                         motion: &mut StepMotion,
                         saved: &mut (Vector, Vector)| {
            if still[i] {
                return Checked::default();
            }
            let Some(current) = state.as_mut() else { return Checked::default() };
            let (advance, checks) = if steady[i] {
                // `integrate_turning`'s own step for such a body.
                let advance = Advance { step: steady_spin_step(current, &model.gravity, dt) };
                let checks = checked(i, None, &advance);
                (advance, checks)
            } else {
                let Some(dynamics) = body.dynamics(model.gravity) else { return Checked::default() };
                // (Made here, not through `advance`: its tuple was copied
                // with `memcpy` and read back with stalled loads, a quarter
                // of this closure's samples under `perf`.)
                let advance = Advance {
                    step: integrate_turning(current, &dynamics, model.integrator, model.gyroscopic, dt),
                };
                let checks = checked(i, Some(&dynamics), &advance);
                (advance, checks)
            };
            *saved = (current.velocity, current.angular_velocity);
            *motion = advance.motion_from(current, dt);
            *current = advance.step.next;
            checks
        };
        let checks = if parallel {
            let bodies = model.bodies.par_iter().zip(states.par_iter_mut()).zip(motions.par_iter_mut());
            let bodies = bodies.zip(saved.par_iter_mut()).enumerate();
            let checks =
                bodies.map(|(i, (((body, state), motion), saved))| step_body(i, body, state, motion, saved));
            checks.reduce(Checked::default, Checked::and)
        } else {
            let bodies = model.bodies.iter().zip(states.iter_mut()).zip(motions.iter_mut());
            let bodies = bodies.zip(saved.iter_mut()).enumerate();
            let checks =
                bodies.map(|(i, (((body, state), motion), saved))| step_body(i, body, state, motion, saved));
            checks.fold(Checked::default(), Checked::and)
        };
        if checks.first_failure.is_some() {
            // The step is undone: each integrated body back at its start.
            for (i, ((body, state), motion)) in
                model.bodies.iter().zip(states.iter_mut()).zip(motions.iter()).enumerate()
            {
                let integrated = !still[i] && body.is_integrated();
                if let Some(current) = state.as_mut().filter(|_| integrated) {
                    let (velocity, angular_velocity) = saved[i];
                    let start = &motion.reference;
                    *current = RigidState {
                        position: Point::from(start.translation.vector),
                        orientation: start.rotation,
                        velocity,
                        angular_velocity,
                    };
                }
            }
            let redo = |i: usize, body: &Body| {
                let state = if still[i] { None } else { states[i].as_ref() }?;
                let (dynamics, advance) = advance(model, body, state)?;
                Some((energy_of(i, &dynamics, &advance), advance))
            };
            return Err(first_divergence(model, counters, &redo, step));
        }
        counters.work.gyroscopic_unconverged += checks.unconverged;
        if check_energy {
            counters.work.max_energy_drift = counters.work.max_energy_drift.max(checks.max_drift);
        }
        // The bodies that move but are not integrated (free ones), each from
        // its state or its own motion.
        let movers = self.movers.get_or_insert_with(|| {
            let moves = |i: &usize| !still[*i] && model.bodies[*i].motion == BodyMotion::Free;
            (0..model.bodies.len()).filter(moves).collect()
        });
        if parallel && movers.len() >= self.options.parallel_integration_bodies {
            let bodies = model.bodies.par_iter().zip(motions.par_iter_mut()).zip(states.par_iter());
            bodies.zip(still.par_iter()).for_each(|(((body, motion), state), &still)| {
                if !still && body.motion == BodyMotion::Free {
                    move_free(body, motion, state, step, t0, dt);
                }
            });
        } else {
            for &i in movers.iter() {
                move_free(&model.bodies[i], &mut motions[i], &states[i], step, t0, dt);
            }
        }
        Ok(())
    }
}

/// Whether each body of `model` takes a steady spin's step in the stepper's
/// integration: integrated, not `still`, under semi-implicit Euler, with
/// no spring and no gyroscopic torque ([`spins_steadily`]: its angular
/// velocity stays), in a run that does not check energies
/// (`check_energy`). `integrate_turning` makes such a body's step from its
/// state and the gravity alone; the stepper makes it so without reading
/// the body, whose 296 bytes were about a third of what the integration
/// moved through memory for each body (with its state, read and written,
/// its motion and its saved velocities, written).
fn steady_bodies(model: &Model, still: &[bool], check_energy: bool) -> Vec<bool> {
    let semi_implicit = model.integrator == Integrator::SymplecticEuler;
    let steady = |(i, body): (usize, &Body)| {
        !check_energy
            && semi_implicit
            && !still[i]
            && body
                .dynamics(model.gravity)
                .is_some_and(|dynamics| spins_steadily(&dynamics, model.gyroscopic))
    };
    model.bodies.iter().enumerate().map(steady).collect()
}

/// Body `body`'s integrator step from `state`, with its dynamics (`None`
/// for a body that is not integrated).
fn advance<'a>(model: &'a Model, body: &'a Body, state: &RigidState) -> Option<(Dynamics<'a>, Advance)> {
    let dynamics = body.dynamics(model.gravity)?;
    let step = integrate_turning(state, &dynamics, model.integrator, model.gyroscopic, model.dt);
    Some((dynamics, Advance { step }))
}

/// What the checks of the bodies' steps found (see `integrate_into`).
#[derive(Copy, Clone, Debug, Default)]
struct Checked {
    /// The first body whose step fails a check.
    first_failure: Option<usize>,
    /// The gyroscopic solves that did not converge.
    unconverged: usize,
    /// The largest energy drift (relative to the body's scale).
    max_drift: Real,
}

impl Checked {
    /// The checks of two sets of bodies together.
    fn and(self, other: Checked) -> Checked {
        Checked {
            first_failure: match (self.first_failure, other.first_failure) {
                (Some(a), Some(b)) => Some(a.min(b)),
                (a, b) => a.or(b),
            },
            unconverged: self.unconverged + other.unconverged,
            max_drift: self.max_drift.max(other.max_drift),
        }
    }
}

/// How a body's step fails the checks.
#[derive(Copy, Clone, Debug)]
enum Failure {
    /// The state is no longer finite.
    NotFinite,
    /// The body turned this angle (at least `MAX_TURN_PER_STEP`).
    Turned(Real),
    /// The mechanical energy grew beyond its limit.
    EnergyGrew,
}

impl Advance {
    /// The motion over the step from state `before` to this step's end.
    fn motion_from(&self, before: &RigidState, dt: Real) -> StepMotion {
        StepMotion::between_turning(&before.pose(), &self.step.next.pose(), dt, self.step.turn)
    }

    /// The first check the step fails, in order: a finite state, a turn
    /// under `MAX_TURN_PER_STEP` (the angle the integrator turned the body
    /// by, not folded to the short way: a turn of nearly 2π is not a small
    /// one), and when `energy` checks it, an energy within its limit.
    fn failure(&self, dt: Real, energy: Option<EnergyCheck>) -> Option<Failure> {
        let turn = self.step.turn.norm() * dt;
        if !self.step.next.is_finite() {
            Some(Failure::NotFinite)
        } else if turn >= MAX_TURN_PER_STEP {
            Some(Failure::Turned(turn))
        } else {
            energy
                .filter(|check| check.now - check.initial > check.limit * check.scale)
                .map(|_| Failure::EnergyGrew)
        }
    }
}

/// A body's step made again, with its energy check when made.
type Redone = (Option<EnergyCheck>, Advance);

/// The divergence of the first body whose step fails a check, told body
/// by body in order (the counters counted up to it, as far as its checks
/// went): a step in which a body diverges moves no body (the run ends at
/// that step's start). `redo(i, body)`: an integrated body's step again
/// from its state at the step's start, and its energy check when made
/// (`None` for a body that is not integrated or is still).
fn first_divergence(
    model: &Model,
    counters: &mut Counters,
    redo: &dyn Fn(usize, &Body) -> Option<Redone>,
    step: u64,
) -> Termination {
    for (i, body) in model.bodies.iter().enumerate() {
        let Some((energy, advance)) = redo(i, body) else { continue };
        counters.work.gyroscopic_unconverged += usize::from(!advance.step.converged);
        let failure = advance.failure(model.dt, energy);
        if let (None | Some(Failure::EnergyGrew), Some(check)) = (failure, energy) {
            counters.work.max_energy_drift = counters.work.max_energy_drift.max(check.drift());
        }
        let name = &body.name;
        let reason = match failure {
            None => continue,
            Some(Failure::NotFinite) => format!("the state of `{name}` is no longer finite (the integration diverged): lower `dt` or pick a more stable integrator"),
            Some(Failure::Turned(turn)) => format!("`{name}` turned {turn:.3} rad in one step (at most π/2 is allowed, so that the motion within a step is defined): lower `dt`"),
            Some(Failure::EnergyGrew) => {
                let (Some(dynamics), Some(check)) = (body.dynamics(model.gravity), energy) else {
                    continue;
                };
                let (initial, energy, time) = (check.initial, check.now, (step + 1) as Real * model.dt);
                let advice = stability_advice(&dynamics, model.integrator, model.dt);
                format!(
                    "the mechanical energy of `{name}` grew from {initial:.3e} to {energy:.3e} by t = {time:?}: the integration is unstable (or, near its stability limit, far too inaccurate to use). {advice}"
                )
            }
        };
        return Termination::Diverged { body: i, step, reason };
    }
    unreachable!("a body's step failed a check")
}

/// A free (not integrated) body's motion over step `step` (starting at
/// `t0`): from its state where it has one (the response can stop it), else
/// from its keyframe path or its constant velocities.
fn move_free(
    body: &Body,
    motion: &mut StepMotion,
    state: &Option<RigidState>,
    step: u64,
    t0: Real,
    dt: Real,
) {
    *motion = match state {
        Some(state) => StepMotion::new(state.pose(), state.velocity, state.angular_velocity),
        None => match &body.path {
            Some(path) => path.motion(step, dt),
            None => StepMotion::free(&body.pose, body.velocity, body.angular_velocity, t0),
        },
    };
}

/// What to do about a diverging body: the largest stable step of its springs.
fn stability_advice(dynamics: &Dynamics, integrator: Integrator, dt: Real) -> String {
    let limit = |i: Integrator| dynamics.stable_step_limit(i).unwrap_or(0.0);
    match dynamics.stable_step_limit(integrator) {
        None => format!("Lower `dt` (now {dt:?})."),
        Some(_) if integrator == Integrator::ExplicitEuler => format!(
            "Explicit Euler gains energy at every step on an undamped spring, whatever `dt`: use SymplecticEuler \
             (stable for dt < {:.4e}) or Rk4 (dt < {:.4e}); `dt` is now {dt:?}.",
            limit(Integrator::SymplecticEuler),
            limit(Integrator::Rk4)
        ),
        Some(largest) => format!(
            "The largest stable dt for its springs with {integrator:?} is {largest:.4e} ({} / ω, ω = sqrt(Σk / m)); `dt` is now {dt:?}.",
            if integrator == Integrator::Rk4 { "2√2" } else { "2" }
        ),
    }
}

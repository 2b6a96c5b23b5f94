//! Stage 1, integrate: each body's motion over the step, from its state
//! (fixed bodies stay, free ones move exactly, integrated ones take one
//! integrator step), checked for divergence.

use rayon::prelude::*;

use std::time::Instant;

use super::result::{Counters, Termination};
use super::world::World;
use super::Stepper;
use crate::math::Real;
use crate::motion::{
    integrate_turning, Dynamics, Integrator, IntegratorStep, RigidState, StepMotion, MAX_TURN_PER_STEP,
};
use crate::scene::{Body, BodyMotion, Model};

/// A body's integrator step, made on rayon's threads when there are many
/// bodies: its next state, the angular velocity of the motion between the
/// two (the rest of the motion is a subtraction away), and whether the
/// solve converged. (Its energy, when checked, is found from its state
/// where it is checked, not kept in every body's slot.)
#[derive(Copy, Clone, Debug)]
pub(crate) struct Advance {
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

/// The integrated bodies' steps (`None` for the others).
pub(crate) type Advanced = Vec<Option<Advance>>;

impl Stepper {
    /// Moves every body's motion to the step starting at `t0` (step number
    /// `step`), checked for divergence.
    pub(super) fn integrate(&mut self, world: &mut World, step: u64, t0: Real) -> Result<(), Termination> {
        let clock = Instant::now();
        let mut advanced = std::mem::take(&mut self.scratch.advanced);
        let result = self.integrate_into(world, &mut advanced, step, t0);
        self.scratch.advanced = advanced;
        self.counters.seconds.integrate += clock.elapsed().as_secs_f64();
        result
    }

    fn integrate_into(
        &mut self,
        world: &mut World,
        advanced: &mut Advanced,
        step: u64,
        t0: Real,
    ) -> Result<(), Termination> {
        let check_energy = self.checks_energy();
        let (model, counters) = (&*self.model, &mut self.counters);
        // The integrations (and the motions between the states) are
        // independent: on the threads when there are many (each body's step
        // is the same whatever the threads). The first body to fail a check
        // is the one reported.
        let advance =
            |(body, state): (&Body, &Option<RigidState>)| match (body.dynamics(model.gravity), state) {
                (Some(dynamics), Some(state)) => {
                    let step =
                        integrate_turning(state, &dynamics, model.integrator, model.gyroscopic, model.dt);
                    Some(Advance { step })
                }
                _ => None,
            };
        let parallel =
            self.options.parallel && model.bodies.len() >= self.options.parallel_integration_bodies;
        // Each body's step, and the checks of it made with it: whether it
        // fails one (the earliest such body), how many gyroscopic solves did
        // not converge, the largest energy drift. Combined by minimum, sum
        // and maximum, so the same whatever the threads.
        let limit = model.parameters.divergence_energy_growth;
        let energy_of = |i: usize, advance: &Advance| {
            if !check_energy {
                return None;
            }
            let dynamics = model.bodies[i].dynamics(model.gravity)?;
            let (initial, scale) = world.energies[i];
            Some(EnergyCheck { now: dynamics.energy(&advance.step.next), initial, scale, limit })
        };
        let checked = |i: usize, step_of: &Option<Advance>| {
            let Some(advance) = step_of else { return Checked::default() };
            let energy = energy_of(i, advance);
            Checked {
                first_failure: advance.failure(model.dt, energy).map(|_| i),
                unconverged: usize::from(!advance.step.converged),
                max_drift: energy.map_or(0.0, EnergyCheck::drift),
            }
        };
        advanced.resize(model.bodies.len(), None);
        // A still body (fixed, or at rest in the stepper's own integration)
        // is not stepped: its slot stays `None`, and neither its body nor its
        // state is read (in a scene of many fixed bodies, reading them was
        // most of this stage).
        let still = &self.still;
        let fill = |i: usize, slot: &mut Option<Advance>, body: &Body, state: &Option<RigidState>| {
            if still[i] {
                return Checked::default();
            }
            *slot = advance((body, state));
            checked(i, slot)
        };
        let checks = if parallel {
            let bodies = advanced.par_iter_mut().zip(model.bodies.par_iter()).zip(&world.states);
            let checks = bodies.enumerate().map(|(i, ((slot, body), state))| fill(i, slot, body, state));
            checks.reduce(Checked::default, Checked::and)
        } else {
            let bodies = advanced.iter_mut().zip(model.bodies.iter()).zip(&world.states);
            let checks = bodies.enumerate().map(|(i, ((slot, body), state))| fill(i, slot, body, state));
            checks.fold(Checked::default(), Checked::and)
        };
        if checks.first_failure.is_some() {
            return Err(first_divergence(model, advanced, counters, &energy_of, step));
        }
        counters.work.gyroscopic_unconverged += checks.unconverged;
        if check_energy {
            counters.work.max_energy_drift = counters.work.max_energy_drift.max(checks.max_drift);
        }
        // Every body's motion over the step (and an integrated body's state
        // at its end), each its own: on the threads with the integrations.
        let dt = model.dt;
        let commit = |((((body, motion), state), step_of), &still): (_, &bool)| {
            if !still {
                commit_step(body, motion, state, step_of, step, t0, dt);
            }
        };
        if parallel {
            let bodies =
                model.bodies.par_iter().zip(world.motions.par_iter_mut()).zip(world.states.par_iter_mut());
            bodies.zip(advanced.par_iter()).zip(self.still.par_iter()).for_each(commit);
        } else {
            let bodies = model.bodies.iter().zip(world.motions.iter_mut()).zip(world.states.iter_mut());
            bodies.zip(advanced.iter()).zip(self.still.iter()).for_each(commit);
        }
        Ok(())
    }
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

/// The divergence of the first body whose step fails a check, told body
/// by body in order (the counters counted up to it, as far as its checks
/// went): a step in which a body diverges moves no body (the run ends at
/// that step's start). `energy_of`: a body's energy check, when made.
fn first_divergence(
    model: &Model,
    advanced: &Advanced,
    counters: &mut Counters,
    energy_of: &dyn Fn(usize, &Advance) -> Option<EnergyCheck>,
    step: u64,
) -> Termination {
    for (i, step_of) in advanced.iter().enumerate() {
        let Some(advance) = step_of else { continue };
        counters.work.gyroscopic_unconverged += usize::from(!advance.step.converged);
        let energy = energy_of(i, advance);
        let failure = advance.failure(model.dt, energy);
        if let (None | Some(Failure::EnergyGrew), Some(check)) = (failure, energy) {
            counters.work.max_energy_drift = counters.work.max_energy_drift.max(check.drift());
        }
        let name = &model.bodies[i].name;
        let reason = match failure {
            None => continue,
            Some(Failure::NotFinite) => format!("the state of `{name}` is no longer finite (the integration diverged): lower `dt` or pick a more stable integrator"),
            Some(Failure::Turned(turn)) => format!("`{name}` turned {turn:.3} rad in one step (at most π/2 is allowed, so that the motion within a step is defined): lower `dt`"),
            Some(Failure::EnergyGrew) => {
                let (Some(dynamics), Some(check)) = (model.bodies[i].dynamics(model.gravity), energy) else {
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

/// Body `body`'s motion over step `step` (starting at `t0`), and an
/// integrated body's state at its end (`step_of`).
fn commit_step(
    body: &Body,
    motion: &mut StepMotion,
    state: &mut Option<RigidState>,
    step_of: &Option<Advance>,
    step: u64,
    t0: Real,
    dt: Real,
) {
    // An integrated body's step (only integrated bodies with a state have
    // one): its body is not read (in a scene of many bodies, reading each
    // body again was a good part of this pass).
    if let Some(Advance { step: IntegratorStep { next, turn, .. } }) = step_of {
        let before = state.replace(*next).map_or_else(|| body.pose, |s| s.pose());
        *motion = StepMotion::between_turning(&before, &next.pose(), dt, *turn);
        return;
    }
    *motion = match &body.motion {
        // A fixed body's motion is the world's from its start (nothing
        // stops or moves a fixed body): nothing to do.
        BodyMotion::Fixed => return,
        BodyMotion::Free => match state {
            // Kinematic with a state (the response can stop it): from where
            // the last step left it.
            Some(state) => StepMotion::new(state.pose(), state.velocity, state.angular_velocity),
            None => match &body.path {
                Some(path) => path.motion(step, dt),
                None => StepMotion::free(&body.pose, body.velocity, body.angular_velocity, t0),
            },
        },
        BodyMotion::Integrated { .. } => return,
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

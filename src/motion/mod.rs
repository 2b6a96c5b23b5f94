//! Rigid motion: the fixed-step integrators, and the motion of a body
//! within one step, which the CCD sweeps.
//!
//! Bodies on which nothing acts move *exactly*: constant linear velocity
//! and constant angular velocity, the rotation being the exponential of
//! `ω t` ([`StepMotion::free`]); their pose at any time is computed from
//! the initial pose directly, so no error accumulates. Bodies with forces,
//! or whose anisotropic inertia makes a torque-free spin precess, are
//! integrated ([`integrate`]) with semi-implicit Euler (default), explicit
//! Euler or RK4.
//!
//! Which bodies are integrated is decided in `classify`.
//!
//! Within a step every body moves with constant linear velocity and
//! constant angular velocity about its centre of mass, from the pose at the
//! start of the step to the integrator's pose at its end ([`StepMotion`]).

pub(crate) mod classify;
mod exponential;
mod gyroscopic;
mod integrator;
mod step_motion;

pub use exponential::turn_exponential;
pub use gyroscopic::{implicit_gyroscopic_step, GyroscopicSolve};

#[cfg(test)]
pub(crate) use gyroscopic::{COFACTOR_UNSCALED_RANGE, GYROSCOPIC_MAX_ITERATIONS};
pub use integrator::{
    integrate, integrate_turning, Dynamics, Gyroscopic, Integrator, IntegratorStep, RigidState, Spring,
};
pub(crate) use integrator::{spins_steadily, steady_spin_step};
pub use step_motion::StepMotion;
pub(crate) use step_motion::MAX_TURN_PER_STEP;
#[cfg(test)]
pub(crate) use step_motion::TURN_ROUNDING_ULPS;

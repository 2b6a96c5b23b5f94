//! Which bodies move exactly and which are integrated.
//!
//! A body that is neither fixed nor kinematic moves exactly (constant
//! velocities, [`StepMotion::free`](super::StepMotion::free)) when nothing
//! acts on it: no gravity, no spring, no contact response that pushes it,
//! and a spin that does not precess. Otherwise it is integrated.

use nalgebra::Matrix3;

use crate::math::{Real, Vector};

/// A torque-free spin is taken as steady (no precession) when `|L × ω|` is
/// at most this many ulps of `|L| |ω|` (`L = I ω`, body frame): a spin
/// about a principal axis, to rounding. `64`.
pub(crate) const STEADY_SPIN_ULPS: Real = 64.0;

/// What acts on a body that is neither fixed nor kinematic.
#[derive(Copy, Clone, Debug, Default, PartialEq, Eq)]
pub struct Influences {
    /// Gravity is not zero.
    pub gravity: bool,
    /// At least one spring holds it.
    pub springs: bool,
    /// The contact response pushes it (its spin then changes at every
    /// contact, so it is integrated and precesses).
    pub pushed_by_contacts: bool,
}

/// Whether the torque-free spin `omega_body` (body frame) of a body with
/// inertia `inertia` precesses (see [`STEADY_SPIN_ULPS`]).
pub fn spin_precesses(inertia: &Matrix3<Real>, omega_body: &Vector) -> bool {
    let momentum = inertia * omega_body;
    momentum.cross(omega_body).norm() > STEADY_SPIN_ULPS * Real::EPSILON * momentum.norm() * omega_body.norm()
}

/// Whether a body under `influences`, whose spin precesses or not, must be
/// integrated (otherwise it moves exactly).
pub fn needs_integration(influences: Influences, precesses: bool) -> bool {
    influences.gravity || influences.springs || influences.pushed_by_contacts || precesses
}

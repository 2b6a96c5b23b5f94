//! The implicit gyroscopic step: Euler's equations of a rotating rigid body,
//! `I ω̇ = τ − ω × I ω` (body frame), advanced by the implicit midpoint rule
//!
//! ```text
//! I (ω' − ω) = dt (τ − ω_m × I ω_m),   ω_m = (ω + ω') / 2,
//! ```
//!
//! solved by Newton's method. The rule preserves every quadratic invariant
//! of the torque-free motion, so the kinetic energy `½ ωᵀ I ω` and the
//! magnitude of the angular momentum `|I ω|` are kept to the solver's
//! tolerance: an intermediate-axis spin (the Dzhanibekov flip) stays
//! bounded, where explicit Euler gains energy every step.

use nalgebra::Matrix3;

use crate::math::{Real, Vector};

/// The most Newton iterations of one implicit gyroscopic step.
pub(crate) const GYROSCOPIC_MAX_ITERATIONS: usize = 20;

/// Newton stops when the update is below this many ulps of `|ω|`.
const GYROSCOPIC_TOLERANCE_ULPS: Real = 4.0;

/// The outcome of one implicit gyroscopic step.
#[derive(Copy, Clone, Debug, PartialEq)]
pub struct GyroscopicSolve {
    /// The angular velocity at the end of the step (body frame).
    pub angular_velocity: Vector,
    /// The midpoint angular velocity `(ω + ω') / 2`, which rotates the body over the step.
    pub midpoint: Vector,
    /// Newton iterations taken.
    pub iterations: usize,
    /// Whether the update fell below the tolerance within
    /// `GYROSCOPIC_MAX_ITERATIONS`.
    pub converged: bool,
}

/// One implicit-midpoint step of Euler's equations (body frame).
pub fn implicit_gyroscopic_step(
    inertia: &Matrix3<Real>,
    angular_velocity: &Vector,
    torque: &Vector,
    dt: Real,
) -> GyroscopicSolve {
    let omega = *angular_velocity;
    let mut next = omega;
    let tolerance = GYROSCOPIC_TOLERANCE_ULPS * Real::EPSILON * omega.norm().max(Real::MIN_POSITIVE);
    for iteration in 1..=GYROSCOPIC_MAX_ITERATIONS {
        let mid = (omega + next) / 2.0;
        let momentum = inertia * mid;
        let residual = inertia * (next - omega) + dt * (mid.cross(&momentum) - torque);
        // d(residual)/d(next) = I + dt/2 (skew(ω_m) I − skew(I ω_m)).
        let jacobian = inertia + (dt / 2.0) * (mid.cross_matrix() * inertia - momentum.cross_matrix());
        let Some(update) = jacobian.lu().solve(&residual) else {
            return GyroscopicSolve {
                angular_velocity: next,
                midpoint: mid,
                iterations: iteration,
                converged: false,
            };
        };
        next -= update;
        let size = update.norm();
        if size <= tolerance || !size.is_finite() {
            let converged = size.is_finite();
            return GyroscopicSolve {
                angular_velocity: next,
                midpoint: (omega + next) / 2.0,
                iterations: iteration,
                converged,
            };
        }
    }
    GyroscopicSolve {
        angular_velocity: next,
        midpoint: (omega + next) / 2.0,
        iterations: GYROSCOPIC_MAX_ITERATIONS,
        converged: false,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn keeps_energy_and_momentum_of_an_intermediate_axis_spin() {
        let inertia = Matrix3::from_diagonal(&Vector::new(1.0, 2.0, 3.0));
        let mut omega = Vector::new(0.01, 5.0, 0.01);
        let energy = |w: &Vector| w.dot(&(inertia * w)) / 2.0;
        let (e0, l0) = (energy(&omega), (inertia * omega).norm());
        let mut flipped = false;
        for _ in 0..20_000 {
            let solve = implicit_gyroscopic_step(&inertia, &omega, &Vector::zeros(), 1e-3);
            assert!(solve.converged);
            omega = solve.angular_velocity;
            flipped |= omega.y < -4.0;
        }
        assert!(flipped, "the intermediate-axis spin should flip within 20 s");
        assert!((energy(&omega) - e0).abs() <= 1e-11 * e0);
        assert!(((inertia * omega).norm() - l0).abs() <= 1e-11 * l0);
    }
}

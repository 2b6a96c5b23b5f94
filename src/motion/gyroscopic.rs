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
        let Some(update) = lu_solve3(jacobian, residual) else {
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

/// `m x = b` by Gaussian elimination with partial pivoting: `None` when
/// `m` is singular. The operations are those of nalgebra's
/// `m.lu().solve(&b)` in the same order (so the result is the same to the
/// bit, as the tests check), written out for 3 × 3: the generic
/// decomposition and its triangular solves took a fifth of a tumbling
/// body's integration.
fn lu_solve3(mut m: Matrix3<Real>, mut b: Vector) -> Option<Vector> {
    for i in 0..3 {
        // The pivot: the first entry of largest magnitude on or below the
        // diagonal (a column of zeros is left as it is).
        let mut pivot = i;
        for r in i + 1..3 {
            if m[(r, i)].abs() > m[(pivot, i)].abs() {
                pivot = r;
            }
        }
        let diagonal = m[(pivot, i)];
        if diagonal == 0.0 {
            continue;
        }
        m.swap_rows(i, pivot);
        b.swap_rows(i, pivot);
        let inverse = 1.0 / diagonal;
        for r in i + 1..3 {
            m[(r, i)] *= inverse;
        }
        for k in i + 1..3 {
            for r in i + 1..3 {
                m[(r, k)] -= m[(i, k)] * m[(r, i)];
            }
        }
    }
    // Forward (unit lower triangle), then back substitution.
    for i in 0..3 {
        for r in i + 1..3 {
            b[r] -= b[i] * m[(r, i)];
        }
    }
    for i in (0..3).rev() {
        if m[(i, i)] == 0.0 {
            return None;
        }
        b[i] /= m[(i, i)];
        for r in 0..i {
            b[r] -= b[i] * m[(r, i)];
        }
    }
    Some(b)
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

    /// The written-out solve is nalgebra's LU solve to the bit, on random
    /// matrices, on the Jacobians of tumbling bodies, and on singular,
    /// tied, tiny, huge and non-finite ones.
    #[test]
    fn lu_solve3_is_nalgebras_to_the_bit() {
        let mut rng = crate::samples::Rng::new(41);
        let mut cases: Vec<(Matrix3<Real>, Vector)> = Vec::new();
        for _ in 0..20_000 {
            let scale = 10f64.powi((rng.uniform() * 40.0 - 20.0) as i32);
            let m = Matrix3::from_fn(|_, _| (rng.uniform() * 2.0 - 1.0) * scale);
            cases.push((m, rng.in_unit_ball()));
        }
        let inertia = Matrix3::new(0.02, 0.001, 0.0, 0.001, 0.03, 0.002, 0.0, 0.002, 0.05);
        for _ in 0..5_000 {
            let mid = rng.in_unit_ball() * 8.0;
            let momentum = inertia * mid;
            let m = inertia + (1.0 / 480.0) * (mid.cross_matrix() * inertia - momentum.cross_matrix());
            cases.push((m, rng.in_unit_ball() * 1e-3));
        }
        let special = [0.0, -0.0, 1.0, -1.0, 2.0, Real::MIN_POSITIVE, 1e300, Real::NAN, Real::INFINITY];
        for _ in 0..20_000 {
            let pick = |rng: &mut crate::samples::Rng| {
                special[(rng.uniform() * special.len() as f64) as usize % special.len()]
            };
            let m = Matrix3::from_fn(|_, _| pick(&mut rng));
            cases.push((m, Vector::new(pick(&mut rng), 1.0, -3.0)));
        }
        cases.push((Matrix3::zeros(), Vector::new(1.0, 2.0, 3.0)));
        cases.push((Matrix3::from_diagonal(&Vector::new(1.0, 0.0, 1.0)), Vector::new(1.0, 2.0, 3.0)));
        // A NaN's sign and payload are not part of any result (nor fixed
        // by Rust's semantics): every NaN is one.
        let bits = |x: Option<Vector>| x.map(|v| v.map(|c| if c.is_nan() { u64::MAX } else { c.to_bits() }));
        for (m, b) in cases {
            assert_eq!(bits(lu_solve3(m, b)), bits(m.lu().solve(&b)), "{m} {b}");
        }
    }
}

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

/// The cofactor inverse of the Newton step's Jacobian scales the matrix to
/// its largest entry first when that entry is outside `1 / x ..= x` for
/// this `x`: `1e100`. The determinant is a cube of the entries, so beyond
/// it the determinant may overflow or underflow a double (whose range is
/// about 1e±308); within it, a zero determinant is a singular matrix.
pub(crate) const COFACTOR_UNSCALED_RANGE: Real = 1e100;

/// The outcome of one implicit gyroscopic step.
#[derive(Copy, Clone, Debug, PartialEq)]
pub struct GyroscopicSolve {
    /// The angular velocity at the end of the step (body frame).
    pub angular_velocity: Vector,
    /// The midpoint angular velocity `(ω + ω') / 2`, which rotates the body over the step.
    pub midpoint: Vector,
    /// Newton iterations taken.
    pub iterations: usize,
    /// Whether an update (Newton's or the chord step's: see
    /// [`implicit_gyroscopic_step`]) fell below the tolerance within
    /// `GYROSCOPIC_MAX_ITERATIONS`.
    pub converged: bool,
}

/// One implicit-midpoint step of Euler's equations (body frame).
///
/// Newton's method on the residual `F(ω') = I (ω' − ω) + dt (ω_m × I ω_m
/// − τ)`. `F` is quadratic in `ω'`: after an update `δ` (the solution of
/// `J δ = F`, `J` the Jacobian) the residual is exactly `dt/4 (δ × I δ)` up
/// to rounding, so the next update is about `J⁻¹ dt/4 (δ × I δ)`, with the
/// same `J⁻¹` (a chord step, no new Jacobian). Each iteration applies both;
/// the solve ends when either is below the tolerance
/// (`GYROSCOPIC_TOLERANCE_ULPS` of `|ω|`). A tumbling body's step takes one
/// or two iterations (three before the chord step: the third only showed
/// the update had vanished), and ends on the same root to the tolerance.
pub fn implicit_gyroscopic_step(
    inertia: &Matrix3<Real>,
    angular_velocity: &Vector,
    torque: &Vector,
    dt: Real,
) -> GyroscopicSolve {
    let omega = *angular_velocity;
    let mut next = omega;
    let tolerance = GYROSCOPIC_TOLERANCE_ULPS * Real::EPSILON * omega.norm().max(Real::MIN_POSITIVE);
    let ended = |next: Vector, iterations: usize, converged: bool| GyroscopicSolve {
        angular_velocity: next,
        midpoint: (omega + next) / 2.0,
        iterations,
        converged,
    };
    for iteration in 1..=GYROSCOPIC_MAX_ITERATIONS {
        let mid = (omega + next) / 2.0;
        let momentum = inertia * mid;
        let residual = inertia * (next - omega) + dt * (mid.cross(&momentum) - torque);
        // d(residual)/d(next) = I + dt/2 (skew(ω_m) I − skew(I ω_m)).
        let jacobian = inertia + (dt / 2.0) * (mid.cross_matrix() * inertia - momentum.cross_matrix());
        let Some(inverse) = inverse3(&jacobian) else {
            return GyroscopicSolve {
                angular_velocity: next,
                midpoint: mid,
                iterations: iteration,
                converged: false,
            };
        };
        let update = inverse * residual;
        next -= update;
        let size = update.norm();
        if size <= tolerance || !size.is_finite() {
            return ended(next, iteration, size.is_finite());
        }
        let following = inverse * ((dt / 4.0) * update.cross(&(inertia * update)));
        next -= following;
        if following.norm() <= tolerance {
            return ended(next, iteration, true);
        }
    }
    ended(next, GYROSCOPIC_MAX_ITERATIONS, false)
}

/// The inverse of a 3 × 3 matrix by its cofactors (the cross products of
/// its rows over its determinant): `None` when the matrix is singular or
/// not finite. One division, where an LU solve divides once per row and
/// twice more in its back substitution, each waiting on the last: the
/// Newton step's Jacobian is close to the inertia, well conditioned, and
/// Newton's iteration corrects a solve's rounding. Where the largest
/// entry is beyond [`COFACTOR_UNSCALED_RANGE`] (the determinant, a cube,
/// may overflow or underflow) the inverse is found again on the matrix
/// scaled to it.
fn inverse3(m: &Matrix3<Real>) -> Option<Matrix3<Real>> {
    let by_cofactors = |m: &Matrix3<Real>| {
        let (r0, r1, r2) = (m.row(0).transpose(), m.row(1).transpose(), m.row(2).transpose());
        let (c0, c1, c2) = (r1.cross(&r2), r2.cross(&r0), r0.cross(&r1));
        let determinant = r0.dot(&c0);
        (determinant != 0.0 && determinant.is_finite())
            .then(|| Matrix3::from_columns(&[c0, c1, c2]) * (1.0 / determinant))
    };
    by_cofactors(m).or_else(|| {
        // Only where the cube of the entries is out of range: a matrix of
        // ordinary entries with no determinant is singular.
        let largest = m.amax();
        let extreme = largest.is_finite()
            && largest > 0.0
            && !(1.0 / COFACTOR_UNSCALED_RANGE..=COFACTOR_UNSCALED_RANGE).contains(&largest);
        let inverse = by_cofactors(&(m / largest)).filter(|_| extreme)? / largest;
        inverse.iter().all(|x| x.is_finite()).then_some(inverse)
    })
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

    /// The cofactor inverse against nalgebra's LU inverse on random and
    /// tumbling bodies' Jacobians; `None` for singular and non-finite ones.
    #[test]
    fn inverse3_inverts() {
        let mut rng = crate::samples::Rng::new(41);
        let inertia = Matrix3::new(0.02, 0.001, 0.0, 0.001, 0.03, 0.002, 0.0, 0.002, 0.05);
        for k in 0..20_000 {
            let m = if k % 2 == 0 {
                let scale = 10f64.powi((rng.uniform() * 40.0 - 20.0) as i32);
                Matrix3::from_fn(|_, _| (rng.uniform() * 2.0 - 1.0) * scale)
            } else {
                let mid = rng.in_unit_ball() * 8.0;
                let momentum = inertia * mid;
                inertia + (1.0 / 480.0) * (mid.cross_matrix() * inertia - momentum.cross_matrix())
            };
            let (ours, theirs) = (inverse3(&m).unwrap(), m.try_inverse().unwrap());
            // Within the conditioning's share of rounding (random matrices
            // can be ill conditioned).
            let condition = m.norm() * theirs.norm();
            let error = (ours - theirs).norm() / theirs.norm();
            assert!(error <= 64.0 * Real::EPSILON * condition, "{m} {error:e} {condition:e}");
        }
        for refused in [
            Matrix3::zeros(),
            Matrix3::from_diagonal(&Vector::new(1.0, 0.0, 1.0)),
            Matrix3::new(1.0, 2.0, 3.0, 2.0, 4.0, 6.0, 0.0, 1.0, 5.0),
            Matrix3::from_diagonal(&Vector::new(1.0, Real::NAN, 1.0)),
            Matrix3::from_diagonal(&Vector::new(1.0, Real::INFINITY, 1.0)),
        ] {
            assert_eq!(inverse3(&refused), None, "{refused}");
        }
        // Determinants out of the doubles' range (a body's inertia in
        // extreme units): inverted all the same.
        for scale in [1e-120, 1e-300, 1e120, 1e300] {
            let m = inertia * scale;
            // (nalgebra's own inverse refuses these: its determinant is
            // out of range too.)
            let (ours, theirs) = (inverse3(&m).unwrap(), inertia.try_inverse().unwrap() / scale);
            assert!((ours - theirs).norm() <= 1e-14 * theirs.norm(), "{scale:e}");
        }
    }

    /// The solve ends on the root of the implicit midpoint rule: within its
    /// tolerance of a reference Newton iteration (nalgebra's LU solves, run
    /// a fixed twelve iterations), in at most two iterations for bodies
    /// turning up to a twelfth of a radian a step, with full inertia
    /// tensors and a torque.
    #[test]
    fn ends_on_the_root_in_two_iterations() {
        let mut rng = crate::samples::Rng::new(7);
        for _ in 0..5_000 {
            let axes = Vector::new(0.5 + rng.uniform(), 0.5 + rng.uniform(), 0.5 + rng.uniform()) * 0.01;
            let turn = nalgebra::Rotation3::new(rng.in_unit_ball() * 3.0);
            let inertia = turn.matrix() * Matrix3::from_diagonal(&axes) * turn.matrix().transpose();
            let omega = rng.in_unit_ball() * 20.0;
            let torque = rng.in_unit_ball() * 0.01;
            let dt = 1.0 / 240.0;
            let solve = implicit_gyroscopic_step(&inertia, &omega, &torque, dt);
            let mut reference = omega;
            for _ in 0..12 {
                let mid = (omega + reference) / 2.0;
                let momentum = inertia * mid;
                let residual = inertia * (reference - omega) + dt * (mid.cross(&momentum) - torque);
                let jacobian =
                    inertia + (dt / 2.0) * (mid.cross_matrix() * inertia - momentum.cross_matrix());
                reference -= jacobian.lu().solve(&residual).unwrap();
            }
            assert!(solve.converged);
            assert!(solve.iterations <= 2, "{} iterations, ω dt = {}", solve.iterations, omega.norm() * dt);
            let error = (solve.angular_velocity - reference).norm();
            assert!(error <= 2.0 * GYROSCOPIC_TOLERANCE_ULPS * Real::EPSILON * omega.norm(), "{error:e}");
            assert_eq!(solve.midpoint, (omega + solve.angular_velocity) / 2.0);
        }
    }
}

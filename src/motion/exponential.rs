//! The exponential of a rotation vector: the unit quaternion that turns by
//! `|v|` about `v`, `(cos(|v|/2), sin(|v|/2) v/|v|)`.
//!
//! Every integrated body turns by one such exponential a step, and every
//! pose the CCD places a body at within a step is one away from the
//! step's start: a step's turn is small (at most `MAX_TURN_PER_STEP`, and
//! a few hundredths of a radian in most scenes). For a turn of at most a
//! quarter radian the sine and cosine of the half angle are summed from
//! their series, where `nalgebra`'s `from_scaled_axis` divides by the angle
//! and calls `sin_cos` (which reduces its argument first): a third of the
//! integrator's time for a body of isotropic inertia, measured.

use nalgebra::{Quaternion, UnitQuaternion};

use crate::math::{Real, Vector};

/// The largest squared angle (rad²) whose exponential [`turn_exponential`]
/// sums from the series: `1/16`, a quarter radian. The half angle `h` is
/// then at most 1/8: the first term left out of the cosine's series,
/// `h¹² / 12!`, is below 3.1e-20 and that of `sin h / h` below 2.4e-21, a
/// thousandth of an ulp of 1; each sum rounds to about an ulp.
pub(crate) const SERIES_SQUARED_ANGLE: Real = 1.0 / 16.0;

/// The rotation by the rotation vector `rotation` (angle `|rotation|`
/// about its direction), as [`UnitQuaternion::from_scaled_axis`] makes it,
/// to an ulp or two of each coordinate: summed from the series up to a
/// quarter radian (a squared angle of 1/16), `from_scaled_axis` beyond
/// (and for a vector that is not finite). The identity for the zero
/// vector. Unlike `from_scaled_axis`, which returns the identity for any
/// turn below 2 ulps of a radian (4.4e-16), a smaller turn is kept: a body
/// spinning at 1e-16 rad/s turns as it says.
#[inline]
pub fn turn_exponential(rotation: &Vector) -> UnitQuaternion<Real> {
    let squared = rotation.norm_squared();
    // (A NaN squared angle goes to `from_scaled_axis` too.)
    let in_series = squared <= SERIES_SQUARED_ANGLE;
    if !in_series {
        return UnitQuaternion::from_scaled_axis(*rotation);
    }
    // h = |v| / 2; the cosine and sin(h) / h from their series, Horner's
    // way on h² with each term's ratio to the last (1 / (2k (2k ± 1))).
    let h2 = 0.25 * squared;
    let cosine = 1.0
        - h2 * (1.0 / 2.0)
            * (1.0
                - h2 * (1.0 / 12.0)
                    * (1.0 - h2 * (1.0 / 30.0) * (1.0 - h2 * (1.0 / 56.0) * (1.0 - h2 * (1.0 / 90.0)))));
    let sinc = 1.0
        - h2 * (1.0 / 6.0)
            * (1.0
                - h2 * (1.0 / 20.0)
                    * (1.0 - h2 * (1.0 / 42.0) * (1.0 - h2 * (1.0 / 72.0) * (1.0 - h2 * (1.0 / 110.0)))));
    // sin(h) v / |v| = (sin h / h) v / 2.
    UnitQuaternion::new_unchecked(Quaternion::from_parts(cosine, rotation * (0.5 * sinc)))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::samples::Rng;

    /// Within two ulps of 1 of `nalgebra`'s exponential (libm's `sin_cos`)
    /// in every coordinate, over turns from 1e-300 rad to the series'
    /// bound and just past it, and of unit norm to rounding; the identity
    /// for no turn, `from_scaled_axis` itself beyond the bound.
    #[test]
    fn agrees_with_nalgebra() {
        let mut rng = Rng::new(7);
        let bound = SERIES_SQUARED_ANGLE.sqrt();
        let mut worst: Real = 0.0;
        for k in 0..200_000 {
            let direction = rng.in_unit_ball().normalize();
            let angle = match k % 4 {
                0 => bound * rng.uniform(),
                1 => bound * (1.0 - 1e-9 * rng.uniform()),
                2 => 10f64.powf(-300.0 * rng.uniform()),
                _ => bound * (1.0 + rng.uniform()),
            };
            let v = direction * angle;
            let (ours, theirs) = (turn_exponential(&v), UnitQuaternion::from_scaled_axis(v));
            let error = (ours.coords - theirs.coords).amax();
            worst = worst.max(error);
            assert!(error <= 2.0 * Real::EPSILON, "{v:?}: {ours:?} against {theirs:?}");
            assert!((ours.coords.norm_squared() - 1.0).abs() <= 4.0 * Real::EPSILON, "{v:?}");
            if v.norm_squared() > SERIES_SQUARED_ANGLE {
                assert_eq!(ours, theirs);
            } else if angle < 1e-20 {
                // nalgebra's identity; here the turn itself, to rounding.
                assert_eq!(ours.w, 1.0);
                assert_eq!(ours.imag(), v * 0.5);
            }
        }
        assert!(worst > 0.0, "the series is used");
        assert_eq!(turn_exponential(&Vector::zeros()), UnitQuaternion::identity());
    }
}

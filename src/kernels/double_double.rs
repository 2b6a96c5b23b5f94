//! Double-double arithmetic (an unevaluated sum of two f64, about 106 bits),
//! for the few values that must be accurate to the last bit when their
//! inputs nearly cancel: the height of a point over a plane, or of one line
//! over another, when that height is tiny next to the coordinates.
//!
//! The operations are the classic error-free transformations (Dekker 1971;
//! Knuth TAOCP vol. 2, §4.2.2): `two_sum`, and `two_product` by FMA. Addition
//! and multiplication here are the "sloppy" forms whose error is about
//! `ε²` of the operands' magnitudes: so a determinant of exact inputs comes
//! out with an absolute error near `ε²·|u||v||w|`, and its leading part is
//! then correct to a few ulps whenever the determinant exceeds about
//! `ε·|u||v||w|` (for unit-size inputs, any height above 1e-16 or so).

use super::compensated::{two_difference, two_sum};
use super::lanes::V3;
use crate::math::{Point, Real, Vector};
use nalgebra::Matrix3;
use std::ops::{Add, Mul, Sub};

/// `high + low`, with `|low| ≤ ulp(high) / 2`.
#[derive(Copy, Clone, Debug, PartialEq)]
pub struct DoubleDouble {
    /// The leading part: the value rounded to f64.
    pub high: Real,
    /// The rest.
    pub low: Real,
}

impl DoubleDouble {
    /// The exact difference `x - y`.
    #[inline(always)]
    pub fn difference(x: Real, y: Real) -> DoubleDouble {
        let (high, low) = two_difference(x, y);
        DoubleDouble { high, low }
    }

    /// The exact product `x · y` (by FMA).
    #[inline(always)]
    pub fn product(x: Real, y: Real) -> DoubleDouble {
        let high = x * y;
        DoubleDouble { high, low: x.mul_add(y, -high) }
    }

    /// `x` itself.
    #[inline(always)]
    pub fn from_real(x: Real) -> DoubleDouble {
        DoubleDouble { high: x, low: 0.0 }
    }
}

/// `rotation · p + translation` in double-double: each product exact, the
/// sums within about `ε²` of the largest term. Posing a mesh's point this
/// way keeps the pose as given to far below an ulp of the result, where
/// plain arithmetic rounds each coordinate by up to an ulp or two.
#[inline]
pub fn posed_point(rotation: &Matrix3<Real>, translation: &Vector, p: &Point) -> [DoubleDouble; 3] {
    std::array::from_fn(|row| {
        DoubleDouble::product(rotation[(row, 0)], p.x)
            + DoubleDouble::product(rotation[(row, 1)], p.y)
            + DoubleDouble::product(rotation[(row, 2)], p.z)
            + DoubleDouble::from_real(translation[row])
    })
}

impl Add for DoubleDouble {
    type Output = DoubleDouble;
    #[inline(always)]
    fn add(self, other: DoubleDouble) -> DoubleDouble {
        let (sum, error) = two_sum(self.high, other.high);
        renormalise(sum, error + (self.low + other.low))
    }
}

impl Sub for DoubleDouble {
    type Output = DoubleDouble;
    #[inline(always)]
    fn sub(self, other: DoubleDouble) -> DoubleDouble {
        self + DoubleDouble { high: -other.high, low: -other.low }
    }
}

impl Mul for DoubleDouble {
    type Output = DoubleDouble;
    #[inline(always)]
    fn mul(self, other: DoubleDouble) -> DoubleDouble {
        let product = self.high * other.high;
        let error = self.high.mul_add(other.high, -product);
        renormalise(product, error + (self.high * other.low + self.low * other.high))
    }
}

/// Dekker's FastTwoSum for `|a| ≥ |b|`, as a double-double.
#[inline(always)]
fn renormalise(a: Real, b: Real) -> DoubleDouble {
    let high = a + b;
    DoubleDouble { high, low: b - (high - a) }
}

/// The exact difference `u - v` of two points, componentwise.
#[inline(always)]
pub fn vector_difference(u: &V3<Real>, v: &V3<Real>) -> [DoubleDouble; 3] {
    [
        DoubleDouble::difference(u.x, v.x),
        DoubleDouble::difference(u.y, v.y),
        DoubleDouble::difference(u.z, v.z),
    ]
}

/// `|det(u, v, w)| / |u × v|`: the distance of `w` from the plane spanned by
/// `u` and `v` (all three given exactly as double-doubles). `None` when
/// `u × v` vanishes.
#[inline(always)]
pub fn height_over_plane(
    u: &[DoubleDouble; 3],
    v: &[DoubleDouble; 3],
    w: &[DoubleDouble; 3],
) -> Option<Real> {
    let normal = [u[1] * v[2] - u[2] * v[1], u[2] * v[0] - u[0] * v[2], u[0] * v[1] - u[1] * v[0]];
    let determinant = normal[0] * w[0] + normal[1] * w[1] + normal[2] * w[2];
    let length =
        (normal[0].high * normal[0].high + normal[1].high * normal[1].high + normal[2].high * normal[2].high)
            .sqrt();
    (length > 0.0).then(|| (determinant.high + determinant.low).abs() / length)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn recovers_a_height_that_plain_arithmetic_loses() {
        // The plane z = 0 tilted by a tiny rotation that f64 cannot hold
        // exactly, and a point 2^-60 above it at coordinates near 1.
        let u = vector_difference(&V3::new(1.0, 0.0, 0.0), &V3::new(0.0, 0.0, 0.0));
        let v = vector_difference(&V3::new(0.0, 1.0, 0.0), &V3::new(0.0, 0.0, 0.0));
        let h = (2.0 as Real).powi(-60);
        let w = vector_difference(&V3::new(0.75, 0.5, h), &V3::new(0.0, 0.0, 0.0));
        assert_eq!(height_over_plane(&u, &v, &w), Some(h));
    }
}

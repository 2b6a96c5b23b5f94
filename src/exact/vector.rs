//! Exact 3-vectors of rationals, converted losslessly from f64.

use crate::math::{Point, Real, Vector};
use nalgebra::Matrix3;
use num_bigint::BigInt;
use num_rational::BigRational;
use num_traits::{FromPrimitive, Signed, Zero};

/// An exact rational number.
pub type Rational = BigRational;

/// A 3-vector of exact rationals.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct RationalVector {
    /// x coordinate.
    pub x: Rational,
    /// y coordinate.
    pub y: Rational,
    /// z coordinate.
    pub z: Rational,
}

/// The exact value of a finite f64.
///
/// # Panics
/// If `value` is NaN or infinite: the exact reference is defined on finite
/// inputs only.
pub fn rational(value: f64) -> Rational {
    match Rational::from_f64(value) {
        Some(r) => r,
        None => panic!("the exact reference takes finite inputs, got {value}"),
    }
}

impl RationalVector {
    /// The exact coordinates of `p`.
    pub fn from_point(p: &Point) -> RationalVector {
        RationalVector { x: rational(p.x), y: rational(p.y), z: rational(p.z) }
    }

    /// `rotation · p + translation`, exactly: the point posed by a rotation
    /// matrix and a translation as given (the matrix need not be exactly
    /// orthogonal; no rounding of the posing enters the reference).
    pub fn posed(p: &Point, rotation: &Matrix3<Real>, translation: &Vector) -> RationalVector {
        let p = [rational(p.x), rational(p.y), rational(p.z)];
        let row = |k: usize| {
            (0..3).fold(rational(translation[k]), |sum, j| sum + rational(rotation[(k, j)]) * &p[j])
        };
        RationalVector { x: row(0), y: row(1), z: row(2) }
    }

    /// `self - other`.
    pub fn sub(&self, other: &RationalVector) -> RationalVector {
        RationalVector { x: &self.x - &other.x, y: &self.y - &other.y, z: &self.z - &other.z }
    }

    /// `self + other * k`.
    pub fn add_scaled(&self, other: &RationalVector, k: &Rational) -> RationalVector {
        RationalVector { x: &self.x + &other.x * k, y: &self.y + &other.y * k, z: &self.z + &other.z * k }
    }

    /// `-self`.
    pub fn negated(&self) -> RationalVector {
        RationalVector { x: -&self.x, y: -&self.y, z: -&self.z }
    }

    /// Dot product.
    pub fn dot(&self, other: &RationalVector) -> Rational {
        &self.x * &other.x + &self.y * &other.y + &self.z * &other.z
    }

    /// Cross product.
    pub fn cross(&self, other: &RationalVector) -> RationalVector {
        RationalVector {
            x: &self.y * &other.z - &self.z * &other.y,
            y: &self.z * &other.x - &self.x * &other.z,
            z: &self.x * &other.y - &self.y * &other.x,
        }
    }

    /// Squared length.
    pub fn norm_squared(&self) -> Rational {
        self.dot(self)
    }

    /// Whether all coordinates are zero.
    pub fn is_zero(&self) -> bool {
        self.x.is_zero() && self.y.is_zero() && self.z.is_zero()
    }
}

/// Whether `0 < x < 1`.
pub(crate) fn strictly_inside_unit(x: &Rational) -> bool {
    x.is_positive() && *x < Rational::from_integer(BigInt::from(1))
}

/// The nearest f64 to an exact rational (for reports and comparisons).
pub fn to_f64(x: &Rational) -> f64 {
    use num_traits::ToPrimitive;
    x.to_f64().unwrap_or(f64::NAN)
}

//! Lanes: one kernel body, run on one `f64` or on `N` of them at once.
//!
//! The triangle kernels are written once against [`Lane`], whose operations
//! are elementwise IEEE operations with selects instead of branches. With
//! `L = f64` they are the scalar kernels; with `L = F64x<8>` each operation
//! is a loop over eight values, which the compiler turns into one vector
//! instruction (AVX-512) or two (AVX2) inside the dispatched functions. The
//! sequence of floating-point operations per lane is the same, so batched
//! results are bit-identical to scalar ones.

use crate::math::{Point, Real, Vector};
use std::ops::{Add, BitAnd, BitOr, Div, Mul, Neg, Not, Sub};

/// A number of `f64` values processed together, elementwise.
pub trait Lane:
    Copy + Add<Output = Self> + Sub<Output = Self> + Mul<Output = Self> + Div<Output = Self> + Neg<Output = Self>
{
    /// The result of a comparison, one truth value per lane.
    type Mask: Copy + BitAnd<Output = Self::Mask> + BitOr<Output = Self::Mask> + Not<Output = Self::Mask>;
    /// The same value in every lane.
    fn splat(x: Real) -> Self;
    /// `self * a + b`, correctly rounded (fused).
    fn mul_add(self, a: Self, b: Self) -> Self;
    /// Square root.
    fn sqrt(self) -> Self;
    /// Absolute value.
    fn abs(self) -> Self;
    /// `self < other`.
    fn lt(self, other: Self) -> Self::Mask;
    /// `self <= other`.
    fn le(self, other: Self) -> Self::Mask;
    /// `self != other`.
    fn ne(self, other: Self) -> Self::Mask;
    /// Per lane, `yes` where `mask` holds, else `no`.
    fn select(mask: Self::Mask, yes: Self, no: Self) -> Self;

    /// The smaller; `other` when either is NaN.
    #[inline(always)]
    fn min(self, other: Self) -> Self {
        Self::select(self.lt(other), self, other)
    }

    /// The larger; `other` when either is NaN.
    #[inline(always)]
    fn max(self, other: Self) -> Self {
        Self::select(other.lt(self), self, other)
    }

    /// Clamped to `[0, 1]`; NaN maps to 0.
    #[inline(always)]
    fn clamp_unit(self) -> Self {
        self.max(Self::splat(0.0)).min(Self::splat(1.0))
    }
}

impl Lane for Real {
    type Mask = bool;
    #[inline(always)]
    fn splat(x: Real) -> Self {
        x
    }
    #[inline(always)]
    fn mul_add(self, a: Self, b: Self) -> Self {
        Real::mul_add(self, a, b)
    }
    #[inline(always)]
    fn sqrt(self) -> Self {
        Real::sqrt(self)
    }
    #[inline(always)]
    fn abs(self) -> Self {
        Real::abs(self)
    }
    #[inline(always)]
    fn lt(self, other: Self) -> bool {
        self < other
    }
    #[inline(always)]
    fn le(self, other: Self) -> bool {
        self <= other
    }
    #[inline(always)]
    fn ne(self, other: Self) -> bool {
        self != other
    }
    #[inline(always)]
    fn select(mask: bool, yes: Self, no: Self) -> Self {
        if mask {
            yes
        } else {
            no
        }
    }
}

/// `N` values of `f64`.
#[derive(Copy, Clone, Debug, PartialEq)]
#[repr(C, align(64))]
pub struct F64x<const N: usize>(pub [Real; N]);

/// `N` truth values, as all-ones or all-zeros 64-bit words (the layout of a
/// vector comparison result).
#[derive(Copy, Clone, Debug, PartialEq)]
#[repr(C, align(64))]
pub struct Mask64x<const N: usize>(pub [u64; N]);

macro_rules! lanewise {
    ($n:ident, |$i:ident| $e:expr) => {{
        let mut out = [Default::default(); $n];
        let mut $i = 0;
        while $i < $n {
            out[$i] = $e;
            $i += 1;
        }
        out
    }};
}

macro_rules! binary_operator {
    ($trait:ident, $method:ident, $op:tt) => {
        impl<const N: usize> $trait for F64x<N> {
            type Output = Self;
            #[inline(always)]
            fn $method(self, other: Self) -> Self {
                F64x(lanewise!(N, |i| self.0[i] $op other.0[i]))
            }
        }
    };
}
binary_operator!(Add, add, +);
binary_operator!(Sub, sub, -);
binary_operator!(Mul, mul, *);
binary_operator!(Div, div, /);

impl<const N: usize> Neg for F64x<N> {
    type Output = Self;
    #[inline(always)]
    fn neg(self) -> Self {
        F64x(lanewise!(N, |i| -self.0[i]))
    }
}

impl<const N: usize> BitAnd for Mask64x<N> {
    type Output = Self;
    #[inline(always)]
    fn bitand(self, other: Self) -> Self {
        Mask64x(lanewise!(N, |i| self.0[i] & other.0[i]))
    }
}

impl<const N: usize> BitOr for Mask64x<N> {
    type Output = Self;
    #[inline(always)]
    fn bitor(self, other: Self) -> Self {
        Mask64x(lanewise!(N, |i| self.0[i] | other.0[i]))
    }
}

impl<const N: usize> Not for Mask64x<N> {
    type Output = Self;
    #[inline(always)]
    fn not(self) -> Self {
        Mask64x(lanewise!(N, |i| !self.0[i]))
    }
}

#[inline(always)]
fn word(b: bool) -> u64 {
    (b as u64).wrapping_neg()
}

impl<const N: usize> Lane for F64x<N> {
    type Mask = Mask64x<N>;
    #[inline(always)]
    fn splat(x: Real) -> Self {
        F64x([x; N])
    }
    #[inline(always)]
    fn mul_add(self, a: Self, b: Self) -> Self {
        F64x(lanewise!(N, |i| self.0[i].mul_add(a.0[i], b.0[i])))
    }
    #[inline(always)]
    fn sqrt(self) -> Self {
        F64x(lanewise!(N, |i| self.0[i].sqrt()))
    }
    #[inline(always)]
    fn abs(self) -> Self {
        F64x(lanewise!(N, |i| self.0[i].abs()))
    }
    #[inline(always)]
    fn lt(self, other: Self) -> Mask64x<N> {
        Mask64x(lanewise!(N, |i| word(self.0[i] < other.0[i])))
    }
    #[inline(always)]
    fn le(self, other: Self) -> Mask64x<N> {
        Mask64x(lanewise!(N, |i| word(self.0[i] <= other.0[i])))
    }
    #[inline(always)]
    fn ne(self, other: Self) -> Mask64x<N> {
        Mask64x(lanewise!(N, |i| word(self.0[i] != other.0[i])))
    }
    #[inline(always)]
    fn select(mask: Mask64x<N>, yes: Self, no: Self) -> Self {
        F64x(lanewise!(N, |i| Real::from_bits(
            (yes.0[i].to_bits() & mask.0[i]) | (no.0[i].to_bits() & !mask.0[i])
        )))
    }
}

/// A 3-vector of lanes.
#[derive(Copy, Clone, Debug, PartialEq)]
pub struct V3<L> {
    /// x.
    pub x: L,
    /// y.
    pub y: L,
    /// z.
    pub z: L,
}

impl<L: Lane> V3<L> {
    /// From components.
    #[inline(always)]
    pub fn new(x: L, y: L, z: L) -> Self {
        V3 { x, y, z }
    }

    /// The zero vector.
    #[inline(always)]
    pub fn zeros() -> Self {
        let zero = L::splat(0.0);
        V3 { x: zero, y: zero, z: zero }
    }

    /// Dot product, `x·x' + y·y' + z·z'` in that order.
    #[inline(always)]
    pub fn dot(&self, other: &Self) -> L {
        self.x * other.x + self.y * other.y + self.z * other.z
    }

    /// Squared length.
    #[inline(always)]
    pub fn norm_squared(&self) -> L {
        self.dot(self)
    }

    /// `|x| + |y| + |z|`.
    #[inline(always)]
    pub fn norm_l1(&self) -> L {
        self.x.abs() + self.y.abs() + self.z.abs()
    }

    /// The largest absolute component.
    #[inline(always)]
    pub fn max_abs(&self) -> L {
        self.x.abs().max(self.y.abs()).max(self.z.abs())
    }

    /// Cross product, plain (see `compensated::cross` for the accurate one).
    #[inline(always)]
    pub fn cross(&self, o: &Self) -> Self {
        V3 { x: self.y * o.z - self.z * o.y, y: self.z * o.x - self.x * o.z, z: self.x * o.y - self.y * o.x }
    }

    /// Per lane, `yes` where `mask` holds, else `no`.
    #[inline(always)]
    pub fn select(mask: L::Mask, yes: Self, no: Self) -> Self {
        V3 {
            x: L::select(mask, yes.x, no.x),
            y: L::select(mask, yes.y, no.y),
            z: L::select(mask, yes.z, no.z),
        }
    }
}

impl<L: Lane> Add for V3<L> {
    type Output = Self;
    #[inline(always)]
    fn add(self, o: Self) -> Self {
        V3 { x: self.x + o.x, y: self.y + o.y, z: self.z + o.z }
    }
}

impl<L: Lane> Sub for V3<L> {
    type Output = Self;
    #[inline(always)]
    fn sub(self, o: Self) -> Self {
        V3 { x: self.x - o.x, y: self.y - o.y, z: self.z - o.z }
    }
}

impl<L: Lane> Neg for V3<L> {
    type Output = Self;
    #[inline(always)]
    fn neg(self) -> Self {
        V3 { x: -self.x, y: -self.y, z: -self.z }
    }
}

impl<L: Lane> Mul<L> for V3<L> {
    type Output = Self;
    #[inline(always)]
    fn mul(self, k: L) -> Self {
        V3 { x: self.x * k, y: self.y * k, z: self.z * k }
    }
}

impl From<&Point> for V3<Real> {
    #[inline(always)]
    fn from(p: &Point) -> Self {
        V3 { x: p.x, y: p.y, z: p.z }
    }
}

impl From<&Vector> for V3<Real> {
    #[inline(always)]
    fn from(v: &Vector) -> Self {
        V3 { x: v.x, y: v.y, z: v.z }
    }
}

impl V3<Real> {
    /// As a nalgebra point.
    #[inline(always)]
    pub fn to_point(self) -> Point {
        Point::new(self.x, self.y, self.z)
    }

    /// As a nalgebra vector.
    #[inline(always)]
    pub fn to_vector(self) -> Vector {
        Vector::new(self.x, self.y, self.z)
    }
}

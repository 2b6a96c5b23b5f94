//! Error-compensated products: the building block that keeps cross products
//! accurate when their terms cancel (a point very near an edge, nearly
//! parallel edges).
//!
//! `a*b - c*d` evaluated naively loses all relative accuracy when the two
//! products nearly cancel. Kahan's algorithm with a fused multiply-add
//! recovers the rounding error of one product exactly and gives a result
//! within 2 ulps (Jeannerod, Louvet, Muller, "Further analysis of Kahan's
//! algorithm for the accurate computation of 2x2 determinants", Math. Comp.
//! 2013). `mul_add` is correctly rounded on every platform (hardware FMA
//! where present, the C library's `fma` otherwise), so results are the same
//! bit for bit everywhere; the price is two extra FMAs per difference.

use super::lanes::{Lane, V3};

/// `a*b - c*d` within 2 ulps, by Kahan's FMA algorithm.
///
/// ```
/// use nearmiss::kernels::difference_of_products;
/// // (1 + 2^-30)^2 - (1 + 2^-29) = 2^-60 exactly; the naive form gives 0.
/// let (x, y) = (1.0 + 2f64.powi(-30), 1.0 + 2f64.powi(-29));
/// assert_eq!(x * x - y, 0.0);
/// assert_eq!(difference_of_products(x, x, y, 1.0), 2f64.powi(-60));
/// ```
#[inline(always)]
pub fn difference_of_products<L: Lane>(a: L, b: L, c: L, d: L) -> L {
    let cd = c * d;
    // The rounding error of c*d, recovered exactly.
    let error = (-c).mul_add(d, cd);
    let difference = a.mul_add(b, -cd);
    difference + error
}

/// The cross product `u × v` with each component from
/// [`difference_of_products`].
#[inline(always)]
pub fn cross<L: Lane>(u: &V3<L>, v: &V3<L>) -> V3<L> {
    V3::new(
        difference_of_products(u.y, v.z, u.z, v.y),
        difference_of_products(u.z, v.x, u.x, v.z),
        difference_of_products(u.x, v.y, u.y, v.x),
    )
}

/// `a + b` exactly, as the unevaluated sum `(sum, error)` (Knuth's TwoSum):
/// `sum` is the rounded sum, `error` its rounding error.
#[inline(always)]
pub fn two_sum<L: Lane>(a: L, b: L) -> (L, L) {
    let sum = a + b;
    let a_part = sum - b;
    let b_part = sum - a_part;
    (sum, (a - a_part) + (b - b_part))
}

/// `x - y` exactly, as `(rounded difference, rounding error)`.
#[inline(always)]
pub fn two_difference<L: Lane>(x: L, y: L) -> (L, L) {
    two_sum(x, -y)
}

/// `u - v` exactly, componentwise, as `(high, low)` vectors.
#[inline(always)]
pub fn exact_difference<L: Lane>(u: &V3<L>, v: &V3<L>) -> (V3<L>, V3<L>) {
    let (x, x_low) = two_difference(u.x, v.x);
    let (y, y_low) = two_difference(u.y, v.y);
    let (z, z_low) = two_difference(u.z, v.z);
    (V3::new(x, y, z), V3::new(x_low, y_low, z_low))
}

/// The cross product of two vectors given as exact `high + low` sums,
/// accurate to a few ulps per component: the compensated product of the
/// high parts plus the first-order terms of the low parts (the low×low term
/// is below the rounding of the result).
#[inline(always)]
pub fn cross_of_sums<L: Lane>(u: &(V3<L>, V3<L>), v: &(V3<L>, V3<L>)) -> V3<L> {
    cross(&u.0, &v.0) + (u.1.cross(&v.0) + u.0.cross(&v.1))
}

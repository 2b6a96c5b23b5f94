//! Exact power-of-two normalisation at the kernels' front doors.
//!
//! Distances, closest points and times of impact are equivariant under a
//! uniform scaling by a power of two, and such a scaling is exact in
//! floating point (short of underflow to subnormal numbers). Inputs whose
//! largest coordinate magnitude `m` lies outside `[2^-SAFE_EXPONENT,
//! 2^SAFE_EXPONENT]` are scaled so that `m ∈ [0.5, 1)`, computed there, and
//! the answer scaled back: the squares and fourth powers the kernels form
//! then neither overflow nor underflow, whatever the scale of the input,
//! from the smallest subnormal to the largest finite number. Inputs inside
//! that range are computed as they are (bit for bit what the batched
//! kernels give).
//!
//! What scaling cannot fix is a *ratio*: a triangle, a segment or a
//! distance far smaller than the coordinates around it. Past
//! [`MIN_RELATIVE_SIZE`] of `m`, products of such lengths leave the normal
//! range and digits are lost; the kernels say so where they can return
//! more than a number ([`TriangleDistance::within_range`](super::TriangleDistance)).

use crate::math::{Point, Real, Triangle, Vector};

/// Inputs whose largest coordinate magnitude is within `2^±SAFE_EXPONENT`
/// are not rescaled. `100`: their fourth powers stay far inside the normal
/// range.
pub(crate) const SAFE_EXPONENT: i32 = 100;

/// `2^e` for an exponent `e` of the normal range, exactly (built from its
/// bits: a constant, not a library call per query).
const fn power_of_two(e: i32) -> Real {
    debug_assert!(-1022 <= e && e <= 1023);
    Real::from_bits(((1023 + e) as u64) << 52)
}

/// The smallest and largest magnitudes not rescaled: `2^∓SAFE_EXPONENT`.
const SAFE_RANGE: (Real, Real) = (power_of_two(-SAFE_EXPONENT), power_of_two(SAFE_EXPONENT));

/// The smallest size (a triangle's or segment's extent, or a distance,
/// unless zero) relative to the largest coordinate magnitude for which the
/// stated accuracy holds: `2^-200` (about 6e-61). A size's fourth power
/// relative to the coordinates' then stays a normal number.
pub const MIN_RELATIVE_SIZE: Real = 6.223015277861142e-61;

/// `x · 2^exponent`, exactly (short of underflow): in two factors, each a
/// normal number, for exponents beyond the normal range (`|exponent|` up
/// to 2,044, which covers every exponent `normalising_exponent` returns).
#[inline]
pub(crate) fn scale_by_power_of_two(x: Real, exponent: i32) -> Real {
    let half = exponent / 2;
    x * power_of_two(half) * power_of_two(exponent - half)
}

/// The point scaled by `2^exponent`.
#[inline]
pub(crate) fn scale_point(p: &Point, exponent: i32) -> Point {
    p.map(|c| scale_by_power_of_two(c, exponent))
}

/// `x` if it exceeds `m`, else `m`: `m.max(x)` for an `m` that is not NaN
/// (a NaN `x` is passed over), in one instruction where `f64::max` takes
/// three.
#[inline(always)]
fn larger(m: Real, x: Real) -> Real {
    if x > m {
        x
    } else {
        m
    }
}

/// The largest coordinate magnitude of `p` (NaN coordinates passed over).
#[inline(always)]
fn point_magnitude(p: &Point) -> Real {
    vector_magnitude(&p.coords)
}

/// The largest coordinate magnitude of `points` (0 if all are zero; NaN
/// coordinates passed over). Always inlined, written without adapters:
/// inside the dispatched kernels a call would run at the baseline
/// instruction set.
#[inline(always)]
pub(crate) fn largest_magnitude<'p>(points: impl IntoIterator<Item = &'p Point>) -> Real {
    let mut largest: Real = 0.0;
    for p in points {
        largest = larger(largest, point_magnitude(p));
    }
    largest
}

/// [`largest_magnitude`] of two triangles' vertices, unrolled: six
/// independent chains, then their maximum.
#[inline(always)]
pub(crate) fn largest_magnitude_of_pair(a: &Triangle, b: &Triangle) -> Real {
    let of_a = larger(larger(point_magnitude(&a[0]), point_magnitude(&a[1])), point_magnitude(&a[2]));
    let of_b = larger(larger(point_magnitude(&b[0]), point_magnitude(&b[1])), point_magnitude(&b[2]));
    larger(of_a, of_b)
}

/// The largest coordinate magnitude of `v` (NaN coordinates passed over).
#[inline(always)]
fn vector_magnitude(v: &Vector) -> Real {
    larger(larger(larger(0.0, v.x.abs()), v.y.abs()), v.z.abs())
}

/// A triangle's extent: its largest edge's largest coordinate difference.
#[inline(always)]
pub(crate) fn triangle_extent(t: &Triangle) -> Real {
    larger(
        larger(vector_magnitude(&(t[1] - t[0])), vector_magnitude(&(t[2] - t[0]))),
        vector_magnitude(&(t[2] - t[1])),
    )
}

/// The exponent `e` that brings `largest` (a positive finite magnitude)
/// into `[0.5, 1)` as `largest · 2^-e`, or `None` if `largest` is 0 or
/// within the safe range.
#[inline]
pub(crate) fn normalising_exponent(largest: Real) -> Option<i32> {
    if largest == 0.0 || !largest.is_finite() || (SAFE_RANGE.0..=SAFE_RANGE.1).contains(&largest) {
        return None;
    }
    // The binary exponent, read from the bits (subnormals: counted by hand).
    let mut exponent = 0;
    let mut m = largest;
    while m >= 1.0 {
        let step = if m >= power_of_two(64) { 64 } else { 1 };
        m = scale_by_power_of_two(m, -step);
        exponent += step;
    }
    while m < 0.5 {
        let step = if m < power_of_two(-64) { 64 } else { 1 };
        m = scale_by_power_of_two(m, step);
        exponent -= step;
    }
    Some(exponent)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_exponent_brings_the_magnitude_to_a_half_or_more() {
        for x in [1e-320, 5e-324, 1e-200, 3e150, 1.7e308, f64::MAX, 2f64.powi(-101), 2f64.powi(101)] {
            let e = normalising_exponent(x).unwrap();
            let m = scale_by_power_of_two(x, -e);
            assert!((0.5..1.0).contains(&m), "{x:e}: {m}");
        }
        assert_eq!(normalising_exponent(1.0), None);
        assert_eq!(normalising_exponent(0.0), None);
        assert_eq!(MIN_RELATIVE_SIZE, 2f64.powi(-200));
    }
}

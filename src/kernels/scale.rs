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

use crate::math::{Point, Real};

/// Inputs whose largest coordinate magnitude is within `2^±SAFE_EXPONENT`
/// are not rescaled. `100`: their fourth powers stay far inside the normal
/// range.
pub const SAFE_EXPONENT: i32 = 100;

/// The smallest size (a triangle's or segment's extent, or a distance,
/// unless zero) relative to the largest coordinate magnitude for which the
/// stated accuracy holds: `2^-200` (about 6e-61). A size's fourth power
/// relative to the coordinates' then stays a normal number.
pub const MIN_RELATIVE_SIZE: Real = 6.223015277861142e-61;

/// `x · 2^exponent`, exactly (short of underflow): in two factors, each a
/// normal number, for exponents beyond the normal range.
#[inline]
pub(crate) fn scale_by_power_of_two(x: Real, exponent: i32) -> Real {
    let half = exponent / 2;
    x * (2.0 as Real).powi(half) * (2.0 as Real).powi(exponent - half)
}

/// The point scaled by `2^exponent`.
#[inline]
pub(crate) fn scale_point(p: &Point, exponent: i32) -> Point {
    p.map(|c| scale_by_power_of_two(c, exponent))
}

/// The largest coordinate magnitude of `points` (0 if all are zero).
#[inline]
pub(crate) fn largest_magnitude<'p>(points: impl IntoIterator<Item = &'p Point>) -> Real {
    points.into_iter().fold(0.0, |m: Real, p| m.max(p.coords.amax()))
}

/// A triangle's extent: its largest edge's largest coordinate difference.
#[inline]
pub(crate) fn triangle_extent(t: &crate::math::Triangle) -> Real {
    (t[1] - t[0]).amax().max((t[2] - t[0]).amax()).max((t[2] - t[1]).amax())
}

/// The exponent `e` that brings `largest` (a positive finite magnitude)
/// into `[0.5, 1)` as `largest · 2^-e`, or `None` if `largest` is 0 or
/// within the safe range.
#[inline]
pub(crate) fn normalising_exponent(largest: Real) -> Option<i32> {
    let safe = (2.0 as Real).powi(-SAFE_EXPONENT)..=(2.0 as Real).powi(SAFE_EXPONENT);
    if largest == 0.0 || !largest.is_finite() || safe.contains(&largest) {
        return None;
    }
    // The binary exponent, read from the bits (subnormals: counted by hand).
    let mut exponent = 0;
    let mut m = largest;
    while m >= 1.0 {
        let step = if m >= (2.0 as Real).powi(64) { 64 } else { 1 };
        m = scale_by_power_of_two(m, -step);
        exponent += step;
    }
    while m < 0.5 {
        let step = if m < (2.0 as Real).powi(-64) { 64 } else { 1 };
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

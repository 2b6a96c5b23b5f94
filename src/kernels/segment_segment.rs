//! Closest points between two segments.
//!
//! Minimises `|p0 + s·d1 - (q0 + t·d2)|²` over `(s, t) ∈ [0, 1]²` with
//! `d1 = p1 - p0`, `d2 = q1 - q0`, `r = p0 - q0`. The unconstrained minimiser
//! solves the 2×2 normal equations; by Lagrange's identity its solution is
//!
//! ```text
//! s* = n·(d2 × r) / |n|²,   t* = n·(d1 × r) / |n|²,   n = d1 × d2,
//! ```
//!
//! which, with FMA-compensated cross products, stays accurate for nearly
//! parallel segments where the textbook `(bf - ce) / (ae - b²)` loses every
//! digit to cancellation. Then (Ericson, *Real-Time Collision Detection*,
//! §5.1.9): clamp `s`, take the best `t` for it, and if that `t` had to be
//! clamped take the best `s` for the clamped `t`. Parallel segments (`n = 0`)
//! start from `s = 0`, which attains the minimum as well; a zero-length
//! segment is a point.
//!
//! The function has no early returns, so that batched callers vectorize.

use super::compensated;
use crate::math::{Point, Real, Vector};

/// Parameters `(s, t)` of the closest points `p0 + s(p1 - p0)` and
/// `q0 + t(q1 - q0)`, and their squared distance.
#[derive(Copy, Clone, Debug, PartialEq)]
pub struct SegmentSegment {
    /// Parameter on the first segment, in `[0, 1]`.
    pub s: Real,
    /// Parameter on the second segment, in `[0, 1]`.
    pub t: Real,
    /// Squared distance between the two closest points.
    pub distance_squared: Real,
    /// `p(s) - q(t)`: from the closest point of the second segment to that of the first.
    pub gap: Vector,
}

/// Closest points between segments `[p0, p1]` and `[q0, q1]`.
///
/// ```
/// use nearmiss::kernels::segment_segment;
/// use nearmiss::math::Point;
/// let c = segment_segment(
///     &Point::new(-1.0, 0.0, 0.0), &Point::new(1.0, 0.0, 0.0),
///     &Point::new(0.5, -1.0, 2.0), &Point::new(0.5, 1.0, 2.0),
/// );
/// assert_eq!((c.s, c.t, c.distance_squared), (0.75, 0.5, 4.0));
/// ```
#[inline(always)]
pub fn segment_segment(p0: &Point, p1: &Point, q0: &Point, q1: &Point) -> SegmentSegment {
    let d1 = p1 - p0;
    let d2 = q1 - q0;
    let r = p0 - q0;
    let a = d1.norm_squared();
    let e = d2.norm_squared();
    let b = d1.dot(&d2);
    let c = d1.dot(&r);
    let f = d2.dot(&r);

    let n = compensated::cross(&d1, &d2);
    let n_squared = n.norm_squared();
    let s_free = n.dot(&compensated::cross(&d2, &r)) / n_squared;
    // Parallel or degenerate segments: any s attains the minimum; take 0.
    let s_first = if n_squared > 0.0 { clamp_unit(s_free) } else { 0.0 };
    let t_free = b.mul_add(s_first, f) / e;
    let t_unclamped = if e > 0.0 { t_free } else { 0.0 };
    let t = clamp_unit(t_unclamped);
    // t was clamped (or the second segment is a point): best s for that t.
    let s_again = clamp_unit(b.mul_add(t, -c) / a);
    let s_recomputed = if a > 0.0 { s_again } else { 0.0 };
    let s = if (t != t_unclamped) | (e <= 0.0) { s_recomputed } else { s_first };

    // r + s·d1 - t·d2, with fused operations.
    let gap = r + d1 * s - d2 * t;
    SegmentSegment { s, t, distance_squared: gap.norm_squared(), gap }
}

/// `x` clamped to `[0, 1]`; NaN maps to 0 (`f64::clamp` would keep NaN).
#[inline(always)]
#[allow(clippy::manual_clamp)]
pub(crate) fn clamp_unit(x: Real) -> Real {
    x.max(0.0).min(1.0)
}

/// The point at parameter `s` on `[p0, p1]`, exactly `p0` or `p1` at the ends.
#[inline(always)]
pub(crate) fn point_on_segment(p0: &Point, p1: &Point, s: Real) -> Point {
    if s >= 1.0 {
        *p1
    } else {
        p0 + (p1 - p0) * s
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use approx::assert_relative_eq;

    fn p(x: Real, y: Real, z: Real) -> Point {
        Point::new(x, y, z)
    }

    #[test]
    fn parallel_overlapping_segments() {
        let c = segment_segment(&p(0.0, 0.0, 0.0), &p(2.0, 0.0, 0.0), &p(1.0, 1.0, 0.0), &p(3.0, 1.0, 0.0));
        assert_relative_eq!(c.distance_squared, 1.0);
    }

    #[test]
    fn parallel_disjoint_segments_meet_at_endpoints() {
        let c = segment_segment(&p(0.0, 0.0, 0.0), &p(1.0, 0.0, 0.0), &p(3.0, 1.0, 0.0), &p(5.0, 1.0, 0.0));
        assert_eq!((c.s, c.t), (1.0, 0.0));
        assert_relative_eq!(c.distance_squared, 5.0);
    }

    #[test]
    fn zero_length_segments() {
        let a = p(1.0, 2.0, 3.0);
        let both = segment_segment(&a, &a, &p(1.0, 2.0, 5.0), &p(1.0, 2.0, 5.0));
        assert_eq!(both.distance_squared, 4.0);
        let first = segment_segment(&a, &a, &p(-1.0, 0.0, 3.0), &p(3.0, 0.0, 3.0));
        assert_eq!((first.s, first.t, first.distance_squared), (0.0, 0.5, 4.0));
        let second = segment_segment(&p(-1.0, 0.0, 3.0), &p(3.0, 0.0, 3.0), &a, &a);
        assert_eq!((second.s, second.t, second.distance_squared), (0.5, 0.0, 4.0));
    }

    #[test]
    fn endpoint_to_interior() {
        // First segment ends above the middle of the second.
        let c = segment_segment(&p(0.0, 0.0, 5.0), &p(0.0, 0.0, 1.0), &p(-1.0, 0.0, 0.0), &p(1.0, 0.0, 0.0));
        assert_eq!((c.s, c.t), (1.0, 0.5));
        assert_relative_eq!(c.distance_squared, 1.0);
    }
}

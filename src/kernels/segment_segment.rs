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
//! Written once for [`Lane`]s: selects, no branches, so it runs on one pair
//! or eight at a time with the same result.

use super::lanes::{Lane, V3};
use crate::math::{Point, Real};

/// Parameters `(s, t)` of the closest points `p0 + s(p1 - p0)` and
/// `q0 + t(q1 - q0)`, and their squared distance.
#[derive(Copy, Clone, Debug, PartialEq)]
pub struct SegmentSegment<L = Real> {
    /// Parameter on the first segment, in `[0, 1]`.
    pub s: L,
    /// Parameter on the second segment, in `[0, 1]`.
    pub t: L,
    /// Squared distance between the two closest points.
    pub distance_squared: L,
    /// `p(s) - q(t)`: from the closest point of the second segment to that of the first.
    pub gap: V3<L>,
}

/// A segment with the data every query against it shares.
#[derive(Copy, Clone, Debug)]
pub struct Edge<L = Real> {
    /// First end point.
    pub start: V3<L>,
    /// `end - start`.
    pub direction: V3<L>,
    /// `|direction|²`.
    pub length_squared: L,
    /// `1 / |direction|²` (infinite for a zero-length segment, never used then).
    pub inverse_length_squared: L,
}

impl<L: Lane> Edge<L> {
    /// The segment `[start, end]`.
    #[inline(always)]
    pub fn new(start: &V3<L>, end: &V3<L>) -> Edge<L> {
        let direction = *end - *start;
        let length_squared = direction.norm_squared();
        Edge {
            start: *start,
            direction,
            length_squared,
            inverse_length_squared: L::splat(1.0) / length_squared,
        }
    }
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
pub fn segment_segment(p0: &Point, p1: &Point, q0: &Point, q1: &Point) -> SegmentSegment {
    segment_segment_lanes(&Edge::new(&p0.into(), &p1.into()), &Edge::new(&q0.into(), &q1.into()))
}

/// [`segment_segment`] on lanes, with the per-edge data precomputed (a
/// triangle pair shares each edge among three queries).
#[inline(always)]
pub fn segment_segment_lanes<L: Lane>(first: &Edge<L>, second: &Edge<L>) -> SegmentSegment<L> {
    let zero = L::splat(0.0);
    let (d1, d2) = (first.direction, second.direction);
    let r = first.start - second.start;
    let (a, e) = (first.length_squared, second.length_squared);
    let b = d1.dot(&d2);
    let c = d1.dot(&r);
    let f = d2.dot(&r);

    // Plain cross products: an error in s moves the distance only at second
    // order (at an interior minimum) or by rounding (at a clamped end), and
    // the clamping sequence is right from any starting s when the segments
    // are parallel. Small distances are refined exactly elsewhere.
    let n = d1.cross(&d2);
    let n_squared = n.norm_squared();
    let s_free = n.dot(&d2.cross(&r)) / n_squared;
    // Parallel or degenerate segments: any s attains the minimum; take 0.
    let s_first = L::select(zero.lt(n_squared), s_free.clamp_unit(), zero);
    let t_free = b.mul_add(s_first, f) * second.inverse_length_squared;
    let t_unclamped = L::select(zero.lt(e), t_free, zero);
    let t = t_unclamped.clamp_unit();
    // t was clamped (or the second segment is a point): best s for that t.
    let s_again = (b.mul_add(t, -c) * first.inverse_length_squared).clamp_unit();
    let s_recomputed = L::select(zero.lt(a), s_again, zero);
    let s = L::select(t.ne(t_unclamped) | e.le(zero), s_recomputed, s_first);

    let gap = r + d1 * s - d2 * t;
    SegmentSegment { s, t, distance_squared: gap.norm_squared(), gap }
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

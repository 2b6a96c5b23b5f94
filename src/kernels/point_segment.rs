//! Distance from a point to a segment, by the three formulas the seed paper
//! and its critics use for the perpendicular distance.
//!
//! Every formula first clamps to the segment with the projection parameter
//! `t = (p - a)·(b - a) / |b - a|²`: for `t ≤ 0` the answer is `|p - a|`, for
//! `t ≥ 1` it is `|p - b|`, and for a zero-length segment it is `|p - a|`.
//! Only the interior (foot of the perpendicular inside the segment) differs:
//!
//! - [`PointEdgeFormula::Vector`]: `|AP × AB| / |AB|` with the differences
//!   `AP`, `AB` kept exact (Knuth's TwoSum: rounded value plus error) and an
//!   FMA-compensated cross product of them ([`super::compensated`]). Relative
//!   error of a few ulps even for a point 1e-12 from a unit edge: the
//!   compensation alone is not enough, because rounding `p - a` already
//!   moves the point by an ulp of its coordinates.
//! - [`PointEdgeFormula::PlainVector`]: the same formula with a plain cross
//!   product, as the seed paper computes it. Loses digits when the point is
//!   close to the edge relative to the edge's length (measured relative error
//!   up to about 1e-5 for a point 1e-12 from a unit edge).
//! - [`PointEdgeFormula::Heron`]: the seed's "virtual triangle": the area from
//!   the three side lengths, `T = sqrt(s(s-a)(s-b)(s-c))`, distance `2T/|AB|`.
//!   For needles (a point near the edge) `s - a` cancels catastrophically:
//!   relative errors of 1e4 and more are measured (the answer can be 0 or
//!   several times too large).
//! - [`PointEdgeFormula::StableHeron`]: Kahan's ordering of Heron's formula
//!   (sides sorted `x ≥ y ≥ z`, parentheses kept). It removes the cancellation
//!   *inside* the formula, but the side lengths were already rounded when
//!   they were computed from coordinates, so needles are still inaccurate
//!   (bounded in the tests; see `tests/kernels/point_segment_vs_exact.rs`).
//!
//! No formula returns NaN on finite input (see the kernels' domain in
//! [`super`]).

use super::compensated;
use super::dispatch::multiversioned;
use super::lanes::V3;
use super::scale::{
    largest_magnitude, normalising_exponent, scale_by_power_of_two, scale_point, MIN_RELATIVE_SIZE,
};
use crate::math::{Point, Real};

/// How the perpendicular distance from a point to an edge is computed.
#[derive(Copy, Clone, Debug, Default, PartialEq, Eq, Hash)]
pub enum PointEdgeFormula {
    /// `|AP × AB| / |AB|` with exact differences and an FMA-compensated
    /// cross product (default; accurate to a few ulps, relative).
    #[default]
    Vector,
    /// `|AP × AB| / |AB|` with a plain cross product (the seed paper's).
    PlainVector,
    /// Heron's formula on the three side lengths (the seed paper's).
    Heron,
    /// Kahan's numerically stable ordering of Heron's formula.
    StableHeron,
}

impl PointEdgeFormula {
    /// All formulas, in a fixed order (for reports and sweeps).
    pub const ALL: [PointEdgeFormula; 4] = [
        PointEdgeFormula::Vector,
        PointEdgeFormula::PlainVector,
        PointEdgeFormula::Heron,
        PointEdgeFormula::StableHeron,
    ];

    /// A short lowercase name, as used in scene files and reports.
    pub fn name(self) -> &'static str {
        match self {
            PointEdgeFormula::Vector => "vector",
            PointEdgeFormula::PlainVector => "plain-vector",
            PointEdgeFormula::Heron => "heron",
            PointEdgeFormula::StableHeron => "stable-heron",
        }
    }
}

multiversioned! {
    /// Distance from point `p` to the segment `[a, b]`.
    ///
    /// The formula only matters when the foot of the perpendicular falls strictly
    /// inside the segment; otherwise the distance to the nearer endpoint is
    /// returned. A zero-length segment is a point.
    ///
    /// ```
    /// use nearmiss::kernels::{point_segment_distance, PointEdgeFormula};
    /// use nearmiss::math::Point;
    /// let (a, b) = (Point::new(0.0, 0.0, 0.0), Point::new(2.0, 0.0, 0.0));
    /// let p = Point::new(1.0, 3.0, 4.0);
    /// for formula in PointEdgeFormula::ALL {
    ///     assert!((point_segment_distance(&p, &a, &b, formula) - 5.0).abs() < 1e-14);
    /// }
    /// // Beyond the end of the segment: the distance to `b`.
    /// let q = Point::new(5.0, 4.0, 0.0);
    /// assert_eq!(point_segment_distance(&q, &a, &b, PointEdgeFormula::Heron), 5.0);
    /// ```
    pub fn point_segment_distance / point_segment_distance_with(p: &Point, a: &Point, b: &Point, formula: PointEdgeFormula) -> Real {
        match normalising_exponent(largest_magnitude([p, a, b])) {
            None => point_segment_distance_kernel(p, a, b, formula),
            // Any scale: computed at a power-of-two normalised one (exact).
            Some(exponent) => {
                let [p, a, b] = [p, a, b].map(|q| scale_point(q, -exponent));
                scale_by_power_of_two(point_segment_distance_kernel(&p, &a, &b, formula), exponent)
            }
        }
    }
}

/// [`point_segment_distance`], or `None` where its accuracy is not stated:
/// the segment's length or the distance (unless zero) below
/// [`MIN_RELATIVE_SIZE`](super::MIN_RELATIVE_SIZE) of the largest
/// coordinate magnitude (any uniform scale is fine). A distance of 0 is
/// trusted only if the point is exactly on the segment's line (a zero cross
/// product): otherwise it underflowed.
///
/// ```
/// use nearmiss::kernels::{point_segment_distance_checked, PointEdgeFormula::Vector};
/// use nearmiss::math::Point;
/// let (a, b) = (Point::new(0.0, 0.0, 0.0), Point::new(2.0, 0.0, 0.0));
/// let d = point_segment_distance_checked(&Point::new(1.0, 1e-50, 0.0), &a, &b, Vector).unwrap();
/// assert!((d - 1e-50).abs() <= 1e-65);
/// // 1e-300 from a segment of length 2: beyond the range (its square underflows).
/// assert_eq!(point_segment_distance_checked(&Point::new(1.0, 1e-300, 0.0), &a, &b, Vector), None);
/// // Exactly on it: 0, trusted.
/// assert_eq!(point_segment_distance_checked(&Point::new(1.0, 0.0, 0.0), &a, &b, Vector), Some(0.0));
/// ```
pub fn point_segment_distance_checked(
    p: &Point,
    a: &Point,
    b: &Point,
    formula: PointEdgeFormula,
) -> Option<Real> {
    let distance = point_segment_distance(p, a, b, formula);
    let limit = MIN_RELATIVE_SIZE * largest_magnitude([p, a, b]);
    let length = (b - a).amax();
    let on_line = (b - a).cross(&(p - a)) == crate::math::Vector::zeros();
    let fine_distance = if distance == 0.0 { on_line } else { distance >= limit };
    ((length == 0.0 || length >= limit) && fine_distance).then_some(distance)
}

/// The body of [`point_segment_distance`], inlined into each instruction-set
/// version and into the batched kernel.
#[inline(always)]
pub(crate) fn point_segment_distance_kernel(
    p: &Point,
    a: &Point,
    b: &Point,
    formula: PointEdgeFormula,
) -> Real {
    // Written without early returns (every candidate computed, then one
    // selected) so that the batched version vectorizes and agrees bit for bit.
    let ab = b - a;
    let ap = p - a;
    let bp = p - b;
    let length_squared = ab.norm_squared();
    let projection = ap.dot(&ab);
    let (to_a_squared, to_b_squared) = (ap.norm_squared(), bp.norm_squared());
    // Regions: "vertex a" (also the zero-length segment), "vertex b", or
    // "edge interior", where the formulas differ.
    let at_a = (projection <= 0.0) | (length_squared <= 0.0);
    let at_b = projection >= length_squared;
    let endpoint_squared = if at_a { to_a_squared } else { to_b_squared };
    let interior = !(at_a | at_b);
    match formula {
        // Squared values selected first, then one square root: the roots
        // and divisions are what a batch pays for.
        PointEdgeFormula::Vector => {
            let (p, a, b) = (V3::from(p), V3::from(a), V3::from(b));
            let ap_exact = compensated::exact_difference(&p, &a);
            let ab_exact = compensated::exact_difference(&b, &a);
            let height_squared =
                compensated::cross_of_sums(&ap_exact, &ab_exact).norm_squared() / length_squared;
            (if interior { height_squared } else { endpoint_squared }).sqrt()
        }
        PointEdgeFormula::PlainVector => {
            let height_squared = ap.cross(&ab).norm_squared() / length_squared;
            (if interior { height_squared } else { endpoint_squared }).sqrt()
        }
        PointEdgeFormula::Heron | PointEdgeFormula::StableHeron => {
            let (length, to_a, to_b) = (length_squared.sqrt(), to_a_squared.sqrt(), to_b_squared.sqrt());
            let height = if formula == PointEdgeFormula::Heron {
                heron_height(length, to_a, to_b)
            } else {
                stable_heron_height(length, to_a, to_b)
            };
            if interior {
                height
            } else if at_a {
                to_a
            } else {
                to_b
            }
        }
    }
}

/// Height over the side `base` of the triangle with sides `base`, `side_1`,
/// `side_2`, by Heron's formula as written: `2 sqrt(s(s-a)(s-b)(s-c)) / base`.
/// A negative radicand (rounding on a needle) is taken as zero area.
#[inline(always)]
pub fn heron_height(base: Real, side_1: Real, side_2: Real) -> Real {
    let s = 0.5 * (base + side_1 + side_2);
    let radicand = s * (s - base) * (s - side_1) * (s - side_2);
    2.0 * radicand.max(0.0).sqrt() / base
}

/// Height over the side `base` by Kahan's stable form of Heron's formula:
/// with the sides sorted `x ≥ y ≥ z`,
/// `area = sqrt((x+(y+z))(z-(x-y))(z+(x-y))(x+(y-z))) / 4`.
/// The parentheses are essential and kept. A negative factor (the sides do not
/// form a triangle after rounding) is taken as zero area.
#[inline(always)]
pub fn stable_heron_height(base: Real, side_1: Real, side_2: Real) -> Real {
    // Sorted with min/max rather than swaps: branch-free, same values.
    let x = base.max(side_1).max(side_2);
    let z = base.min(side_1).min(side_2);
    let y = base.min(side_1).max(base.max(side_1).min(side_2));
    let radicand = (x + (y + z)) * (z - (x - y)) * (z + (x - y)) * (x + (y - z));
    0.5 * radicand.max(0.0).sqrt() / base
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn zero_length_segment_is_a_point() {
        let a = Point::new(1.0, 1.0, 1.0);
        let p = Point::new(1.0, 4.0, 5.0);
        for formula in PointEdgeFormula::ALL {
            assert_eq!(point_segment_distance(&p, &a, &a, formula), 5.0);
        }
    }

    #[test]
    fn point_on_the_segment_is_at_distance_zero_for_vector() {
        let a = Point::new(0.0, 0.0, 0.0);
        let b = Point::new(4.0, 0.0, 0.0);
        let p = Point::new(1.0, 0.0, 0.0);
        assert_eq!(point_segment_distance(&p, &a, &b, PointEdgeFormula::Vector), 0.0);
        assert_eq!(point_segment_distance(&p, &a, &b, PointEdgeFormula::Heron), 0.0);
    }

    #[test]
    fn needle_triangles_never_give_nan() {
        let a = Point::new(0.0, 0.0, 0.0);
        let b = Point::new(1.0, 0.0, 0.0);
        for k in 0..40 {
            let p = Point::new(0.3, (10.0 as Real).powi(-k), 0.0);
            for formula in PointEdgeFormula::ALL {
                let d = point_segment_distance(&p, &a, &b, formula);
                assert!(d.is_finite() && d >= 0.0, "{formula:?} at 1e-{k}: {d}");
            }
        }
    }
}

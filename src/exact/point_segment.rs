//! Exact squared distance from a point to a segment.

use super::vector::{Rational, RationalVector};
use crate::math::Point;
use num_traits::{Signed, Zero};

/// Exact squared distance from `p` to segment `[a, b]`, on the exact values
/// of the f64 inputs. A zero-length segment is a point.
///
/// ```
/// use nearmiss::exact::point_segment_distance_squared;
/// use nearmiss::math::Point;
/// use num_rational::BigRational;
/// let d = point_segment_distance_squared(
///     &Point::new(0.5, 1e-12, 0.0), &Point::new(0.0, 0.0, 0.0), &Point::new(1.0, 0.0, 0.0));
/// assert_eq!(d, BigRational::from_float(1e-12).unwrap().pow(2));
/// ```
pub fn point_segment_distance_squared(p: &Point, a: &Point, b: &Point) -> Rational {
    let [p, a, b] = [p, a, b].map(RationalVector::from_point);
    point_segment_squared(&p, &a, &b)
}

/// [`point_segment_distance_squared`] on exact inputs.
pub(crate) fn point_segment_squared(p: &RationalVector, a: &RationalVector, b: &RationalVector) -> Rational {
    let ab = b.sub(a);
    let ap = p.sub(a);
    let length_squared = ab.norm_squared();
    let projection = ap.dot(&ab);
    if length_squared.is_zero() || !projection.is_positive() {
        return ap.norm_squared();
    }
    if projection >= length_squared {
        return p.sub(b).norm_squared();
    }
    // |ap|² - (ap·ab)²/|ab|²: Pythagoras, exact in rationals.
    ap.norm_squared() - &projection * &projection / length_squared
}

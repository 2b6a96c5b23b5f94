//! Conservative advancement along separating axes, for two convex
//! primitives whose vertices move linearly over `t ∈ [0, 1]`.
//!
//! At time `t` the exact distance kernel gives the closest pair `p ∈ A`,
//! `q ∈ B` and the unit direction `n = (q - p) / |q - p|`. For convex `A` and
//! `B` that direction separates them, and along it the *support gap*
//!
//! ```text
//! G(s) = min_j n·b_j(s) - max_i n·a_i(s)
//! ```
//!
//! equals the distance at `s = t`. Every vertex moves linearly, so each term
//! `n·(b_j(s) - a_i(s))` is linear in `s` and `G` is piecewise linear: its
//! first crossing of a target level is found exactly, and while `G(s)` is
//! positive the plane normal to `n` keeps the primitives apart. So no contact
//! can happen before that crossing: the step is conservative, and it uses the
//! vertices' actual motion along `n` rather than a worst-case speed. It is
//! exact in one step for a pure translation.
//!
//! Every step also has the classic bound: the distance falls no faster
//! than the largest relative speed of any two points, so the step
//! `(d - target) / speed` is safe whatever the axis. (For tiny gaps rounding
//! tilts the closest-pair direction, and the axis step is then refused: see
//! [`LinearPair::gap_crossing`].) A third bound follows the plane spanned
//! by the two edges or by the face as it turns (`swept_plane.rs`): a fixed
//! axis cannot, and when the primitives turn against each other their far
//! ends swing through it. The longest of the three steps is taken.
//!
//! The step aims at `G = minimum_separation + tolerance / 2` and contact is
//! declared at distance `minimum_separation + tolerance` (the contract of
//! `contact.rs`, the tolerance relative to the query's size); the half-tolerance
//! margin, `ε`-sized errors aside, keeps every floating-point step on the
//! safe side (the rounding of `c` and `k` below is about `8 ε S`, and the
//! tolerance is `1e-6 S` by default).

use super::contact::{ContactContract, ContactRule};
use super::options::{CcdOptions, CcdResult, CcdStatus};
use super::swept_plane::SweptPlane;
use crate::kernels::{largest_magnitude, normalising_exponent, scale_by_power_of_two, scale_point};
use crate::math::{Point, Real, Vector};

/// Two primitives (vertex sets `A`, `B`) moving linearly over the step.
pub(crate) struct LinearPair<const NA: usize, const NB: usize> {
    pub a_t0: [Point; NA],
    pub a_t1: [Point; NA],
    pub b_t0: [Point; NB],
    pub b_t1: [Point; NB],
}

impl<const NA: usize, const NB: usize> LinearPair<NA, NB> {
    /// Vertex positions at time `t`.
    #[inline]
    pub fn at(&self, t: Real) -> ([Point; NA], [Point; NB]) {
        let lerp = |p0: &Point, p1: &Point| if t >= 1.0 { *p1 } else { p0 + (p1 - p0) * t };
        (
            std::array::from_fn(|i| lerp(&self.a_t0[i], &self.a_t1[i])),
            std::array::from_fn(|j| lerp(&self.b_t0[j], &self.b_t1[j])),
        )
    }

    /// The diagonal of the bounding box of all vertices at both ends.
    pub fn size(&self) -> Real {
        let (lo, hi) = bounds(self.a_t0.iter().chain(&self.a_t1).chain(&self.b_t0).chain(&self.b_t1));
        (hi - lo).norm()
    }

    /// Whether the swept bounding boxes of `A` and `B`, grown by `margin`,
    /// are disjoint (then there is no contact in the step).
    pub fn swept_boxes_disjoint(&self, margin: Real) -> bool {
        let (a_lo, a_hi) = bounds(self.a_t0.iter().chain(&self.a_t1));
        let (b_lo, b_hi) = bounds(self.b_t0.iter().chain(&self.b_t1));
        (0..3).any(|k| a_lo[k] > b_hi[k] + margin || b_lo[k] > a_hi[k] + margin)
    }

    /// The first `s ≥ t` at which the support gap along `n` falls to
    /// `target`, `+∞` if it stays above for all later times, or `t` itself
    /// if `n` does not separate the primitives by more than `target` at `t`
    /// (when the gap is tiny next to the primitives, rounding tilts the
    /// closest-pair direction enough that far vertices are on the wrong side;
    /// every term is checked).
    pub fn gap_crossing(&self, t: Real, n: &Vector, target: Real) -> Real {
        let (a, b) = self.at(t);
        let mut first = Real::INFINITY;
        for (i, a_i) in a.iter().enumerate() {
            let a_velocity = self.a_t1[i] - self.a_t0[i];
            for (j, b_j) in b.iter().enumerate() {
                let gap = n.dot(&(b_j - a_i));
                if gap <= target {
                    return t;
                }
                let closing = n.dot(&((self.b_t1[j] - self.b_t0[j]) - a_velocity));
                if closing < 0.0 {
                    first = first.min(t + (gap - target) / -closing);
                }
            }
        }
        first
    }

    /// The largest relative speed of any point of `A` against any point of
    /// `B` over the step: `max |Δb_j - Δa_i|` (every point's motion is a
    /// convex combination of its vertices').
    pub fn max_relative_speed(&self) -> Real {
        let mut speed: Real = 0.0;
        for i in 0..NA {
            for j in 0..NB {
                speed = speed.max(((self.b_t1[j] - self.b_t0[j]) - (self.a_t1[i] - self.a_t0[i])).norm());
            }
        }
        speed
    }

    /// Whether the support gap along the fixed unit axis `n` (either way
    /// round) stays above `target` over the whole step. Each term is linear
    /// in time, so checking both ends suffices.
    pub fn separated_all_step(&self, n: &Vector, target: Real) -> bool {
        let apart = |sign: Real| {
            (0..NA).all(|i| {
                (0..NB).all(|j| {
                    sign * n.dot(&(self.b_t0[j] - self.a_t0[i])) > target
                        && sign * n.dot(&(self.b_t1[j] - self.a_t1[i])) > target
                })
            })
        };
        apart(1.0) || apart(-1.0)
    }
}

/// The smallest tolerance, in ulps of the largest coordinate: positions at
/// time `t` and the kernels' distances carry a few ulps of rounding, and half
/// the tolerance must cover it. Default `64`.
pub const ROUNDING_FLOOR_ULPS: Real = 64.0;

/// The componentwise lower and upper bounds of `points`.
fn bounds<'p>(points: impl Iterator<Item = &'p Point>) -> (Vector, Vector) {
    points.fold((Vector::repeat(Real::INFINITY), Vector::repeat(Real::NEG_INFINITY)), |(lo, hi), p| {
        (lo.inf(&p.coords), hi.sup(&p.coords))
    })
}

/// Runs conservative advancement. `axes(pair)` gives fixed directions to try
/// over the whole step first; `plane(pair)` the point and plane whose
/// distance bounds the primitives' from below (`swept_plane.rs`);
/// `closest(a, b)` returns the distance and the closest points
/// `(p on A, q on B)` of the primitives at one time.
///
/// Inputs of any scale: outside the kernels' safe range they are normalised
/// by a power of two (exact; times of impact do not change, distances and
/// the absolute `minimum_separation` scale with it), see `kernels/scale.rs`.
pub(crate) fn advance<const NA: usize, const NB: usize>(
    pair: &LinearPair<NA, NB>,
    options: &CcdOptions,
    axes: impl Fn(&LinearPair<NA, NB>) -> [Vector; 2],
    plane: impl Fn(&LinearPair<NA, NB>) -> SweptPlane,
    closest: impl Fn(&[Point; NA], &[Point; NB]) -> (Real, Point, Point),
) -> CcdResult {
    let points = pair.a_t0.iter().chain(&pair.a_t1).chain(&pair.b_t0).chain(&pair.b_t1);
    let Some(exponent) = normalising_exponent(largest_magnitude(points)) else {
        return advance_normalised(pair, options, &axes(pair), &plane(pair), closest);
    };
    let scale = |p: Point| scale_point(&p, -exponent);
    let scaled = LinearPair {
        a_t0: pair.a_t0.map(scale),
        a_t1: pair.a_t1.map(scale),
        b_t0: pair.b_t0.map(scale),
        b_t1: pair.b_t1.map(scale),
    };
    let options = CcdOptions {
        minimum_separation: scale_by_power_of_two(options.minimum_separation, -exponent),
        ..*options
    };
    let mut result = advance_normalised(&scaled, &options, &axes(&scaled), &plane(&scaled), closest);
    for value in [&mut result.distance, &mut result.contact_distance, &mut result.guaranteed_distance] {
        *value = scale_by_power_of_two(*value, exponent);
    }
    result
}

/// [`advance`] on inputs in the safe range.
fn advance_normalised<const NA: usize, const NB: usize>(
    pair: &LinearPair<NA, NB>,
    options: &CcdOptions,
    axes: &[Vector],
    plane: &SweptPlane,
    closest: impl Fn(&[Point; NA], &[Point; NB]) -> (Real, Point, Point),
) -> CcdResult {
    let all = pair.a_t0.iter().chain(&pair.a_t1).chain(&pair.b_t0).chain(&pair.b_t1);
    if !all.flat_map(|p| p.coords.iter()).all(|c| c.is_finite()) {
        return CcdResult {
            time_of_impact: Some(0.0),
            status: CcdStatus::NonFiniteInput,
            distance: Real::NAN,
            contact_distance: Real::NAN,
            guaranteed_distance: Real::NAN,
            iterations: 0,
        };
    }
    // The half-tolerance margin must exceed the rounding of positions and
    // distances, a few ulps of the largest coordinate `M`: a tiny query far
    // from the origin would otherwise lose it.
    let largest = pair
        .a_t0
        .iter()
        .chain(&pair.a_t1)
        .chain(&pair.b_t0)
        .chain(&pair.b_t1)
        .fold(0.0, |m: Real, p| m.max(p.coords.amax()));
    let contract = ContactContract::of(
        options,
        ContactRule::ScaleRelative,
        pair.size(),
        ROUNDING_FLOOR_ULPS * Real::EPSILON * largest,
    );
    let (contact_distance, target) = (contract.contact_distance, contract.target);
    let no_contact = |status, distance, iterations| CcdResult {
        time_of_impact: None,
        status,
        distance,
        contact_distance,
        guaranteed_distance: target,
        iterations,
    };
    if pair.swept_boxes_disjoint(contact_distance)
        || axes.iter().any(|n| n.norm_squared() > 0.0 && pair.separated_all_step(&n.normalize(), target))
    {
        return no_contact(CcdStatus::Filtered, Real::INFINITY, 0);
    }
    let speed = pair.max_relative_speed();
    let mut t = 0.0;
    for iteration in 0..options.max_iterations.max(1) {
        let (a, b) = pair.at(t);
        let (distance, p, q) = closest(&a, &b);
        if distance <= contact_distance {
            let status = if t == 0.0 { CcdStatus::InitiallyTouching } else { CcdStatus::Converged };
            return CcdResult {
                time_of_impact: Some(t),
                status,
                distance,
                contact_distance,
                guaranteed_distance: target,
                iterations: iteration,
            };
        }
        // Three conservative steps; the longest is taken. Along the
        // separating axis (exact for translations), by the worst-case closing
        // speed (valid whatever the direction's rounding), and by the swept
        // plane (which turns with the primitives).
        let along_axis = pair.gap_crossing(t, &((q - p) / distance), target);
        let worst_case = if speed > 0.0 { t + (distance - target) / speed } else { Real::INFINITY };
        let mut next = along_axis.max(worst_case);
        if next <= 1.0 {
            next = next.max(plane.crossing(t, target, largest));
        }
        if next > 1.0 {
            let (a, b) = pair.at(1.0);
            return no_contact(CcdStatus::Separated, closest(&a, &b).0, iteration + 1);
        }
        t = next;
    }
    let (a, b) = pair.at(t);
    CcdResult {
        time_of_impact: Some(t),
        status: CcdStatus::OutOfIterations,
        distance: closest(&a, &b).0,
        contact_distance,
        guaranteed_distance: target,
        iterations: options.max_iterations,
    }
}

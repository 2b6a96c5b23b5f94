//! A step bound that turns with the primitives: the distance from a point
//! to a plane spanned by two moving edges.
//!
//! Two edges lie on lines `a₀ + σu` and `b₀ + τw`; a vertex and a face on a
//! point `p` and the plane `f₀ + σu + τw`. In both cases the primitives'
//! distance is at least
//!
//! ```text
//! |g| / |c|,   c = u × w,   g = (p − o)·c
//! ```
//!
//! (`o = a₀, p = b₀` for the edges: the lines' distance; `o = f₀` for the
//! face: the point's distance to the face's plane). Every vertex moves
//! linearly, so `c(t + h)` is a quadratic and `g(t + h)` a cubic in `h`, with
//! coefficients computed at `t`. Where the closest points lie inside both
//! primitives this is the distance itself, and it changes at the distance's
//! own pace. The support-gap step of `advance.rs` holds one direction fixed,
//! so when the primitives turn against each other it sees their far ends
//! swing through the plane and takes steps that are orders of magnitude
//! shorter than the distance needs (on the public sample's rod-twist
//! edges, crossing a few 1e-8 apart for a whole step, up to 4,403 steps
//! without this bound and 21 with it).
//!
//! With `σ` the sign of `g(t)` and `|c(t + h)| ≤ |c₀| + c′h + c″h²` (below),
//! the step is safe up to the first `h` at which the lower bound
//!
//! ```text
//! P(h) = σg₀ − E − target·|c₀| + (σg₁ − target·c′) h − (|g₂| + target·c″) h² − |g₃| h³
//! ```
//!
//! reaches zero: `P(h) > 0` gives `σg(t + h) > target·|c(t + h)|`, so the
//! lines are apart by more than `target` (and cannot be parallel). `P` is
//! concave for `h ≥ 0`, so its first root is bracketed from below by chords
//! and from above by Newton steps, and the chord's end is returned. `E`
//! bounds the rounding of `g` (see [`PLANE_ROUNDING_ULPS`]); where it is
//! not small against `g`, as for nearly parallel edges, the bound gives no
//! step and the other two bounds decide.
//!
//! `c′ = ĉ₀·c₁` and `c″ = |c₁|²/2|c₀| + |c₂|` (from `√(a² + x) ≤ a + x/2a`),
//! or `|c₁|` and `|c₂|` where `|c₁| > 2|c₀|`. The first keeps `P`'s slope
//! exact: `g = d|c|`, so a face whose edges shorten as they turn (each end
//! moves on a chord) shrinks `g` while the distance `d` holds still, and
//! with a large `minimum_separation` the plain `|c₁|` read that as closing.
//!
//! The claims are checked in exact rationals on random, nearly parallel
//! and far-from-the-origin draws (the tests below).

use super::advance::LinearPair;
use crate::math::{Point, Real, Vector};

/// The rounding allowance of the swept-plane bound, in units of
/// `ε · M · (|u||w| + |r||u| + |r||w|)` (`M` the query's largest coordinate,
/// `r = p − o`; each length includes its change over the step): rounding
/// the positions by a few ulps of `M` tilts `c` and moves `g` by about that
/// much, and the products add a few ulps more. Default `64`: in the exact
/// tests below, an allowance of 1 held on 40,000 draws and none failed
/// within 600.
pub const PLANE_ROUNDING_ULPS: Real = 64.0;

/// Chord and Newton iterations that bracket the bound's first root.
const ROOT_ITERATIONS: usize = 4;

/// A point and two edges, each given at the step's start and by its change
/// over the step.
pub(crate) struct SweptPlane {
    /// `p − o` at `t = 0`, and its change.
    r: (Vector, Vector),
    u: (Vector, Vector),
    w: (Vector, Vector),
}

impl SweptPlane {
    /// The lines of two edges `a₀a₁` and `b₀b₁`: the plane through `a₀`
    /// spanned by both edges, and the point `b₀`.
    pub fn of_edges(pair: &LinearPair<2, 2>) -> Self {
        let edge = |e0: &[Point; 2], e1: &[Point; 2]| [e0[1] - e0[0], e1[1] - e1[0]];
        Self::new(
            [pair.a_t0[0], pair.a_t1[0]],
            [pair.b_t0[0], pair.b_t1[0]],
            edge(&pair.a_t0, &pair.a_t1),
            edge(&pair.b_t0, &pair.b_t1),
        )
    }

    /// The plane of a face `f₀f₁f₂` (`A`) and a vertex (`B`).
    pub fn of_vertex_face(pair: &LinearPair<3, 1>) -> Self {
        let edge = |k: usize| [pair.a_t0[k] - pair.a_t0[0], pair.a_t1[k] - pair.a_t1[0]];
        Self::new([pair.a_t0[0], pair.a_t1[0]], [pair.b_t0[0], pair.b_t1[0]], edge(1), edge(2))
    }

    /// The plane through `o` spanned by `u` and `w`, and the point `p`, each
    /// as `[at t = 0, at t = 1]`.
    fn new(o: [Point; 2], p: [Point; 2], u: [Vector; 2], w: [Vector; 2]) -> Self {
        let r = [p[0] - o[0], p[1] - o[1]];
        Self { r: (r[0], r[1] - r[0]), u: (u[0], u[1] - u[0]), w: (w[0], w[1] - w[0]) }
    }

    /// The first time after `t` at which the primitives can be `target`
    /// apart by this bound, `+∞` if not before the step's end, or `t` if
    /// the bound gives no step. `largest` is the query's largest coordinate.
    pub fn crossing(&self, t: Real, target: Real, largest: Real) -> Real {
        let at = |(start, change): (Vector, Vector)| start + change * t;
        let (r, u, w) = (at(self.r), at(self.u), at(self.w));
        let (dr, du, dw) = (self.r.1, self.u.1, self.w.1);
        let c = [u.cross(&w), u.cross(&dw) + du.cross(&w), du.cross(&dw)];
        let g = [r.dot(&c[0]), r.dot(&c[1]) + dr.dot(&c[0]), r.dot(&c[2]) + dr.dot(&c[1]), dr.dot(&c[2])];
        let (lr, lu, lw) = (r.norm() + dr.norm() + target, u.norm() + du.norm(), w.norm() + dw.norm());
        let rounding = PLANE_ROUNDING_ULPS * Real::EPSILON * largest * (lu * lw + lr * lu + lr * lw);
        let sign = if g[0] < 0.0 { -1.0 } else { 1.0 };
        let c_norm = c[0].norm();
        let start = sign * g[0] - rounding - target * c_norm;
        if start.is_nan() || start <= 0.0 {
            return t;
        }
        // |c(t + h)| ≤ |c₀| + c′h + c″h² (the module's comment).
        let (first, second) = if c[1].norm() <= 2.0 * c_norm {
            (c[0].dot(&c[1]) / c_norm, c[1].norm_squared() / (2.0 * c_norm) + c[2].norm())
        } else {
            (c[1].norm(), c[2].norm())
        };
        let p = [start, sign * g[1] - target * first, -(g[2].abs() + target * second), -g[3].abs()];
        let value = |h: Real| ((p[3] * h + p[2]) * h + p[1]) * h + p[0];
        let slope = |h: Real| (3.0 * p[3] * h + 2.0 * p[2]) * h + p[1];
        let (mut low, mut high) = (0.0, 1.0 - t);
        let (mut at_low, mut at_high) = (p[0], value(high));
        if at_high > 0.0 {
            return Real::INFINITY;
        }
        for _ in 0..ROOT_ITERATIONS {
            // Concave: the chord lies below P (its root is at most P's),
            // the tangent above it (its root, from the right, at least).
            let chord = low + at_low * (high - low) / (at_low - at_high);
            let at_chord = value(chord);
            if at_chord > 0.0 && chord > low {
                (low, at_low) = (chord, at_chord);
            }
            let newton = high - at_high / slope(high);
            if newton > low && newton < high {
                (high, at_high) = (newton, value(newton));
                if at_high > 0.0 {
                    // Rounding near the root: the point is proven all the same.
                    low = high;
                    break;
                }
            }
        }
        t + low
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::exact::{rational, RationalVector};
    use crate::samples::Rng;

    /// A point at time `s` of its linear motion, exactly.
    fn exact_at(p0: &Point, p1: &Point, s: Real) -> RationalVector {
        let start = RationalVector::from_point(p0);
        start.add_scaled(&RationalVector::from_point(p1).sub(&start), &rational(s))
    }

    /// Whether `|r·c| > target·|c|` exactly, for `c = u × w`: the point is
    /// more than `target` from the plane (and `c` is not zero).
    fn apart(r: &RationalVector, u: &RationalVector, w: &RationalVector, target: Real) -> bool {
        let c = u.cross(w);
        let g = r.dot(&c);
        let target = rational(target);
        &g * &g > &target * &target * c.norm_squared()
    }

    /// A random frame: a point (near the origin or up to 1,000 from it), a
    /// size from 1e-3 to 1, two edges of half to one and a half sizes at an
    /// angle from 1e-10 to 1.5 rad (nearly parallel edges, slivers), and an
    /// offset along their common normal of 1e-12 to 1e-2 sizes.
    fn frame(rng: &mut Rng) -> (Point, Real, Vector, Vector, Vector) {
        let centre = Point::from(rng.in_unit_ball() * [1.0, 10.0, 1e3][rng.index(3)]);
        let size = rng.log_range(1e-3, 1.0);
        let u = rng.unit_vector();
        let side = rng.unit_vector();
        let across = (side - u * side.dot(&u)).normalize();
        let angle = rng.log_range(1e-10, 1.5);
        let w = u * angle.cos() + across * angle.sin();
        let (u, w) = (u * size * rng.range(0.5, 1.5), w * size * rng.range(0.5, 1.5));
        let offset = u.cross(&w).normalize() * size * rng.log_range(1e-12, 1e-2);
        (centre, size, u, w, offset)
    }

    /// Each point's end: moved by up to three sizes, often far less, so the
    /// primitives turn against each other by various amounts.
    fn ends<const N: usize>(rng: &mut Rng, start: [Point; N], size: Real) -> [Point; N] {
        start.map(|p| p + rng.in_unit_ball() * size * rng.log_range(1e-8, 3.0))
    }

    fn largest(points: &[Point]) -> Real {
        points.iter().fold(0.0, |m: Real, p| m.max(p.coords.amax()))
    }

    /// Asks the bound for a step from a random time to a random target,
    /// checks its claim exactly at 12 times of the interval it proves, and
    /// returns whether it proved one.
    fn check(
        rng: &mut Rng,
        plane: &SweptPlane,
        largest: Real,
        size: Real,
        apart_at: impl Fn(Real, Real) -> bool,
    ) -> bool {
        let target = size * rng.log_range(1e-14, 1e-4);
        let t = if rng.index(2) == 0 { 0.0 } else { rng.range(0.0, 0.95) };
        let end = plane.crossing(t, target, largest).min(1.0);
        assert!(end >= t);
        if end == t {
            return false;
        }
        for k in 0..12 {
            let s = if k == 0 { end } else { t + (end - t) * rng.uniform() };
            assert!(apart_at(s, target), "the bound proved [{t}, {end}] at {target:e}, but not {s}");
        }
        true
    }

    #[test]
    fn the_lines_of_two_edges_are_apart_wherever_the_bound_says() {
        let mut rng = Rng::new(71);
        let mut proved = 0;
        for _ in 0..600 {
            let (centre, size, u, w, gap) = frame(&mut rng);
            let (a0, b0) = (centre - u * rng.uniform(), centre + gap - w * rng.uniform());
            let start = [a0, a0 + u, b0, b0 + w];
            let end = ends(&mut rng, start, size);
            let pair = LinearPair {
                a_t0: [start[0], start[1]],
                a_t1: [end[0], end[1]],
                b_t0: [start[2], start[3]],
                b_t1: [end[2], end[3]],
            };
            let apart_at = |s: Real, target: Real| {
                let [a0, a1, b0, b1] = [0, 1, 2, 3].map(|k| exact_at(&start[k], &end[k], s));
                apart(&b0.sub(&a0), &a1.sub(&a0), &b1.sub(&b0), target)
            };
            let largest = largest(&[start, end].concat());
            proved += usize::from(check(&mut rng, &SweptPlane::of_edges(&pair), largest, size, apart_at));
        }
        // Most draws are proved a step: the check above is not idle.
        assert!(proved > 300, "{proved} of 600 proved");
    }

    #[test]
    fn a_vertex_is_off_the_face_plane_wherever_the_bound_says() {
        let mut rng = Rng::new(72);
        let mut proved = 0;
        for _ in 0..600 {
            let (f0, size, u, w, height) = frame(&mut rng);
            let v = f0 + (u * rng.uniform() + w * rng.uniform()) * 0.5 + height;
            let start = [f0, f0 + u, f0 + w, v];
            let end = ends(&mut rng, start, size);
            let pair = LinearPair {
                a_t0: [start[0], start[1], start[2]],
                a_t1: [end[0], end[1], end[2]],
                b_t0: [start[3]],
                b_t1: [end[3]],
            };
            let apart_at = |s: Real, target: Real| {
                let [f0, f1, f2, v] = [0, 1, 2, 3].map(|k| exact_at(&start[k], &end[k], s));
                apart(&v.sub(&f0), &f1.sub(&f0), &f2.sub(&f0), target)
            };
            let largest = largest(&[start, end].concat());
            proved +=
                usize::from(check(&mut rng, &SweptPlane::of_vertex_face(&pair), largest, size, apart_at));
        }
        assert!(proved > 300, "{proved} of 600 proved");
    }
}

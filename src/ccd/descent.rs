//! The descent of one run's bracket: GJK probes, walks over the meshes'
//! triangles or exact distances along the step, stepping down to the
//! nearest time by parabolic steps.

use super::convex_measure::{certificate_slack, in_world, measure, measure_below, pair_at_hulls};
use super::hull_gap::{convex_distance, hull_gap_from, ConvexDistance, WarmSimplex};
use super::query::{MeshCcdScratch, MovingMesh};
use crate::math::Real;
use crate::mesh::{triangle_pair_distance, walk_to_closer_pair, MeshDistance};
use crate::motion::StepMotion;

/// The descent's first step, a fraction of the rest of the interval:
/// `1/256` (then doubling while the distance falls).
pub(crate) const DESCENT_FIRST_STEP_FRACTION: Real = 1.0 / 256.0;

/// A descent's probe of two meshes not both convex is taken from the pair
/// around the hulls' closest vertices where the hulls' gap certifies it to
/// this fraction of the descent's precision ([`pair_at_hulls`]): `0.125`.
/// Where the closest points lie on both hulls (a link beside another),
/// that is one warm GJK and a few triangle pairs, where a walk evaluates
/// every triangle around the pair's corners for up to 16 rounds.
pub(crate) const PROBE_HULL_TOLERANCE_FRACTION: Real = 0.125;

/// The most steps of [`descend`]'s minimisation: `48` (golden-section
/// steps alone would shrink the time bracket to 0.618^48 ≈ 1e-10 of its
/// length).
pub(super) const DESCENT_STEPS: usize = 48;

/// From time `start`, where the meshes are closing, the local minimum of
/// their distance after it, and its time: a march of doubling steps
/// while the distance falls, then Brent's minimisation on the last three
/// points (a parabola's vertex where it falls well inside the bracket, a
/// golden section where not), until the bracket is so short that the
/// distance cannot change by `precision` across it (the distance moves at
/// most at the head-on speed `|v_a − v_b| + |ω_a| r_a + |ω_b| r_b`), a
/// parabola's step finds a closer point by less than `precision`, or
/// [`DESCENT_STEPS`] steps. The probes are [`Probe`]'s: for two convex
/// meshes, GJK on their hulls, warm from probe to probe; otherwise the
/// pair around the hulls' closest vertices where the hulls' gap certifies
/// it, and else a walk from the closest pair of the best time so far to a
/// closer one (a few dozen triangle pairs where an exact distance searches
/// thousands), and, where a walk would end the march, the exact search for
/// a pair closer than the best (over a long step the closest pair may have
/// moved out of a walk's reach, to a gear's next tooth; where the distance
/// has risen, the search below the best prunes at once).
///
/// The answer is the best time's pair, measured: a distance the meshes
/// reach there, so an upper bound of the closest approach, never wrong.
/// Where the walks lost the closest pair it is above the meshes' own
/// distance there, and the proving run that follows finds the closer
/// approach and descends again from it, as it does for any minimum the
/// descent missed. (Measuring the best time exactly after the walks, and
/// descending again on exact distances where that was lower, cost a KUKA
/// link passing `pybullet_data`'s gear ring ten exact distances a query,
/// 6.1 against 2.2 ms, with the same runs and bracket.)
pub(super) fn descend(
    a: &MovingMesh<'_>,
    b: &MovingMesh<'_>,
    interval: (Real, Real),
    precision: Real,
    hint: Option<(usize, usize)>,
    scratch: &mut MeshCcdScratch,
) -> (Real, MeshDistance) {
    descend_with(
        &mut Probe::new(a, b, hint, PROBE_HULL_TOLERANCE_FRACTION * precision),
        interval,
        precision,
        scratch,
    )
}

/// [`descend`] with `probe`: the best time and its pair, measured.
fn descend_with(
    probe: &mut Probe<'_, '_>,
    (start, duration): (Real, Real),
    precision: Real,
    scratch: &mut MeshCcdScratch,
) -> (Real, MeshDistance) {
    let (a, b) = (probe.a, probe.b);
    let speed = (a.motion.velocity - b.motion.velocity).norm()
        + a.motion.angular_velocity.norm() * a.mesh.radius()
        + b.motion.angular_velocity.norm() * b.mesh.radius();
    let mut best = (start, probe.at(start, scratch));
    let mut best_pair = probe.hint;
    // March: (previous, best, next) with the distance falling to best.
    let mut previous = start;
    let mut step = (duration - start) * DESCENT_FIRST_STEP_FRACTION;
    let mut next = start;
    while step > 0.0 {
        next = (best.0 + step).min(duration);
        let mut found = probe.at(next, scratch);
        if found >= best.1 && probe.walks() && !probe.certified {
            // The march would end here: a walk may have lost the closest
            // pair over the long step (a gear's next tooth), so the exact
            // search for a pair closer than the best decides.
            found = probe.below(next, best.1, scratch).map_or(Real::INFINITY, |closer| closer.distance);
        }
        if found >= best.1 {
            break;
        }
        previous = best.0;
        best = (next, found);
        best_pair = probe.hint;
        if next >= duration {
            return (best.0, probe.pair_at(best.0, best_pair, scratch));
        }
        step *= 2.0;
    }
    // Brent's minimisation on [previous, next] around best: a parabola
    // through the three best points where it falls well inside the
    // bracket, a golden section where it does not.
    let (mut lo, mut hi) = (previous, next);
    let ratio = 0.5 * (5.0_f64.sqrt() - 1.0);
    // The two next-best points (time, distance), for the parabola.
    let mut second = (next, Real::INFINITY);
    let mut third = (previous, Real::INFINITY);
    let (mut step_before_last, mut last_step) = (Real::INFINITY, Real::INFINITY);
    for _ in 0..DESCENT_STEPS {
        if hi - lo <= Real::EPSILON * duration.max(hi.abs()) || (hi - lo) * speed <= precision {
            break;
        }
        let golden = if best.0 - lo > hi - best.0 {
            best.0 - (1.0 - ratio) * (best.0 - lo)
        } else {
            best.0 + (1.0 - ratio) * (hi - best.0)
        };
        let parabolic = parabola_vertex(best.0, best.1, second, third)
            .filter(|&x| x > lo && x < hi && (x - best.0).abs() < 0.5 * step_before_last);
        let (probe_time, by_parabola) = match parabolic {
            // Not closer to best than the time can tell apart.
            Some(x) => {
                let least = Real::EPSILON.sqrt() * best.0.abs().max(duration * 1e-6);
                let shift = (x - best.0).abs();
                (if shift < least { best.0 + least.copysign(x - best.0) } else { x }, true)
            }
            None => (golden, false),
        };
        step_before_last = last_step;
        last_step = (probe_time - best.0).abs();
        // A walk starts from the best time's pair, the nearest known one.
        probe.hint = best_pair;
        let found = probe.at(probe_time, scratch);
        let gain = best.1 - found;
        if found < best.1 {
            if probe_time < best.0 {
                hi = best.0;
            } else {
                lo = best.0;
            }
            third = second;
            second = best;
            best = (probe_time, found);
            best_pair = probe.hint;
        } else {
            if probe_time < best.0 {
                lo = probe_time;
            } else {
                hi = probe_time;
            }
            if found <= second.1 {
                third = second;
                second = (probe_time, found);
            } else if found <= third.1 {
                third = (probe_time, found);
            }
        }
        // A parabola's step that gains, but less than the precision: the
        // minimum is found to it (the proving run checks). One that gains
        // nothing only narrows the bracket (the parabola missed: a kink,
        // where the closest features change), and the search goes on.
        if by_parabola && gain > 0.0 && gain < precision {
            break;
        }
    }
    (best.0, probe.pair_at(best.0, best_pair, scratch))
}

/// The distance probes of a descent. For two convex meshes (exact kernel),
/// GJK on their vertex hulls, warm from the last probe (the closest
/// features move little between probes): certified to
/// [`PROBE_CERTIFICATE_ULPS`](super::convex_measure::PROBE_CERTIFICATE_ULPS) ulps of the pair's scale, a few GJK
/// iterations instead of a BVH search. For other meshes, the pair around
/// the hulls' closest vertices where the hulls' gap (GJK, warm from the
/// last probe) certifies it to [`PROBE_HULL_TOLERANCE_FRACTION`] of the
/// precision, until that first fails; then a walk from its pair
/// ([`walk_to_closer_pair`]): an upper bound, the distance where the
/// closest pair lies downhill of the pair. With no pair yet, or where GJK
/// does not certify, the exact mesh distance. [`Probe::measure`] gives the
/// exact distance with its points and features (kept from the last exact
/// probe when it was at that time).
pub(super) struct Probe<'q, 'm> {
    a: &'q MovingMesh<'m>,
    b: &'q MovingMesh<'m>,
    convex: bool,
    warm: WarmSimplex,
    /// Where the meshes are not both convex: the largest error of a probe
    /// certified by the hulls' gap ([`pair_at_hulls`]), and whether to try
    /// that (until it first fails: the closest points then lie inside a
    /// hull, and do so nearby in time).
    hulls: Option<Real>,
    /// Whether the last probe was within `hulls`' tolerance of the meshes'
    /// distance (so no search need check it).
    certified: bool,
    /// Where the next walk or search starts: the last probe's closest pair,
    /// or the one the descent sets.
    hint: Option<(usize, usize)>,
    /// The last exact probe and its time.
    last: Option<(Real, MeshDistance)>,
}

impl<'q, 'm> Probe<'q, 'm> {
    fn new(
        a: &'q MovingMesh<'m>,
        b: &'q MovingMesh<'m>,
        hint: Option<(usize, usize)>,
        tolerance: Real,
    ) -> Probe<'q, 'm> {
        let convex = a.mesh.is_convex() && b.mesh.is_convex();
        let hint = hint.filter(|&(i, j)| i < a.mesh.triangles().len() && j < b.mesh.triangles().len());
        let hulls = (!convex).then_some(tolerance);
        Probe { a, b, convex, warm: WarmSimplex::default(), hulls, certified: false, hint, last: None }
    }

    /// Whether the probes are walks (two meshes not both convex).
    fn walks(&self) -> bool {
        !self.convex
    }

    /// The distance at `s` (a walk's upper bound where [`Probe::walks`]).
    fn at(&mut self, s: Real, scratch: &mut MeshCcdScratch) -> Real {
        self.certified = false;
        if let Some(tolerance) = self.hulls {
            // The hulls' gap, warm from the last probe, and the pair
            // around their closest vertices, where it certifies.
            let relative = StepMotion::relative_pose(self.a.motion, self.b.motion, s);
            let gap = hull_gap_from(
                self.a.mesh,
                self.b.mesh,
                &relative,
                None,
                (0.0, Real::INFINITY),
                &mut self.warm,
            );
            match pair_at_hulls(self.a.mesh, self.b.mesh, &relative, &gap, tolerance) {
                Some(found) => {
                    (self.hint, self.certified) = (Some((found.triangle_a, found.triangle_b)), true);
                    return found.distance;
                }
                None => self.hulls = None,
            }
        }
        if self.convex {
            let relative = StepMotion::relative_pose(self.a.motion, self.b.motion, s);
            let slack = certificate_slack(self.a.mesh, self.b.mesh, &relative);
            if let ConvexDistance::Certified(upper) =
                convex_distance(self.a.mesh, self.b.mesh, &relative, &mut self.warm, slack)
            {
                return upper;
            }
        } else if let Some(start) = self.hint {
            // From the hint, a walk to a closer pair.
            let relative = StepMotion::relative_pose(self.a.motion, self.b.motion, s);
            let (distance, pair) = walk_to_closer_pair(self.a.mesh, self.b.mesh, &relative, start);
            self.hint = Some(pair);
            return distance;
        }
        self.measure(s, scratch).distance
    }

    /// The answer at the best time `s`: where the probes walk, its pair
    /// measured there (or the exact distance, where that was measured
    /// there and is no farther); otherwise the exact distance.
    fn pair_at(
        &mut self,
        s: Real,
        pair: Option<(usize, usize)>,
        scratch: &mut MeshCcdScratch,
    ) -> MeshDistance {
        let Some((i, j)) = pair.filter(|_| self.walks()) else { return self.measure(s, scratch) };
        let relative = StepMotion::relative_pose(self.a.motion, self.b.motion, s);
        let walked = triangle_pair_distance(self.a.mesh, i, self.b.mesh, j, &relative);
        match self.last.filter(|&(at, exact)| at == s && exact.distance <= walked.distance) {
            Some((_, exact)) => exact,
            None => in_world(self.a, s, walked),
        }
    }

    /// The exact distance at `s` where it is below `ceiling` (with its
    /// points and features, kept as [`Probe::measure`]'s), `None` where it
    /// is not.
    fn below(&mut self, s: Real, ceiling: Real, scratch: &mut MeshCcdScratch) -> Option<MeshDistance> {
        let found = measure_below(self.a, self.b, (s, None), ceiling, scratch)?;
        Some(self.keep(s, found))
    }

    /// The exact distance at `s`, with its points and features.
    fn measure(&mut self, s: Real, scratch: &mut MeshCcdScratch) -> MeshDistance {
        if let Some((_, found)) = self.last.filter(|&(at, _)| at == s) {
            return found;
        }
        let found = measure(self.a, self.b, s, self.hint, scratch);
        self.keep(s, found)
    }

    /// Keeps `found`, the exact distance at `s`, as the last exact probe
    /// and its pair as where the next walk or search starts.
    fn keep(&mut self, s: Real, found: MeshDistance) -> MeshDistance {
        self.hint = Some((found.triangle_a, found.triangle_b));
        self.last = Some((s, found));
        found
    }
}

/// The time at the vertex of the parabola through `(x, fx)` and the two
/// other points, if it opens upwards (a minimum).
pub(super) fn parabola_vertex(
    x: Real,
    fx: Real,
    (v, fv): (Real, Real),
    (w, fw): (Real, Real),
) -> Option<Real> {
    if !(fv.is_finite() && fw.is_finite()) || v == w || v == x || w == x {
        return None;
    }
    let slope_vx = (fx - fv) / (x - v);
    let slope_xw = (fw - fx) / (w - x);
    let curvature = (slope_xw - slope_vx) / (w - v);
    if curvature.is_nan() || curvature <= 0.0 {
        return None;
    }
    // f(t) = fx + s (t - x) + c (t - x)^2 with s the slope at x of the
    // parabola: s = slope_vx + c (x - v).
    let slope = slope_vx + curvature * (x - v);
    let t = x - slope / (2.0 * curvature);
    t.is_finite().then_some(t)
}

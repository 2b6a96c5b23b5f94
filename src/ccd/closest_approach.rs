//! The closest approach of two moving meshes over an interval, as a
//! certified bracket: the smallest distance `d*` between them over the
//! interval satisfies `lower ≤ d* ≤ upper`, `upper` is a distance the meshes
//! really reach (at `time`, between the reported closest points), and
//! `upper − lower` is at most the query's tolerance.
//!
//! Built on the CCD's own conservative machinery, nothing else: a
//! [`mesh_time_of_impact`](crate::ccd::mesh_time_of_impact) run with a
//! minimum separation `S` either proves that the meshes stay farther than
//! its guaranteed distance over the whole interval (the contract: every
//! approach closer than `S + τ/2` is reported, so none means
//! `d* ≥ S + τ/2`, a certified lower bound), or stops at a time where the
//! meshes are within `S + τ` (where their exact distance, measured there,
//! is an upper bound that is reached). From such a time the distance is
//! falling; a descent (Brent's; on two convex meshes it probes with GJK on
//! their hulls, warm from probe to probe, on others it walks over their
//! triangles) finds its local minimum after it and the distance of its
//! closest pair there: the best upper bound `u` so far (where the
//! best so far is the interval's start and the distance falls there, as
//! the closest points' velocities say, the descent starts from it without
//! that first run, which would stop a hair later). The next
//! run asks whether anything comes closer than `u` less three
//! quarters of the tolerance: if not, the bracket is closed (one run, the
//! usual case); if so, the descent starts again from there. The first run
//! asks for the query's `within` distance: a pair that never comes that
//! near costs that one run, which for well separated meshes is one
//! bounding-sphere or hull check.
//!
//! Where the meshes come within the CCD's contact distance (touching), the
//! answer is that contact ([`ApproachStatus::Contact`]): its time of first
//! contact is then what a caller wants. A query for every approach (no
//! `within`) asks that first, with one run at separation 0.

use super::contact::{ContactRule, TARGET_FRACTION};
use super::convex_measure::{in_world, measure, measure_below, pair_at_hulls};
use super::descent::descend;
use super::hull_gap::{hull_gap, HullGap};
use super::mesh_pair::mesh_time_of_impact_with;
use super::mesh_search::FrontStart;
use super::options::{CcdOptions, CcdStatus};
use super::pair_motion::PairMotion;
use super::query::{MeshCcdQuery, MeshCcdResult, MeshCcdScratch, MovingMesh, Touching, WarmStart};
use crate::math::{Point, Pose, Real};
use crate::mesh::{DistanceKernel, MeshDistance};
use crate::motion::StepMotion;

/// The bracket's width, relative to the smaller mesh's radius, when the
/// query states none: `1e-6`, the contact contract's default
/// ([`CcdOptions::distance_tolerance`]).
pub const DEFAULT_APPROACH_TOLERANCE: Real = 1e-6;

/// The most CCD runs one closest approach takes: `64`. Each run after the
/// first finds a point closer than the best by at least half the width,
/// or closes the bracket; a query that needs more ends as
/// [`ApproachStatus::OutOfIterations`] with the bracket reached.
pub(crate) const MAX_APPROACH_RUNS: usize = 64;

/// Each CCD run's contract tolerance, as a fraction of the bracket's
/// width: `0.25`. A run that finds nothing certifies the distance stays
/// above its target; one that finds a time stops within this tolerance of
/// the target.
pub(crate) const RUN_TOLERANCE_FRACTION: Real = 0.25;

/// A run that runs out of iterations is run again with this many times
/// the budget: `10`. The budget grows until it reaches the number of
/// advancement steps that decides any run ([`Runs::decided_within`]), so a
/// run of a closest approach is never left undecided by its budget: a
/// grazing pass that needs many small steps gets them.
pub(crate) const BUDGET_GROWTH: usize = 10;

/// After a closer point is found, the next run asks whether anything comes
/// closer than it less this fraction of the width: `0.75`. If nothing
/// does, the bracket is this fraction of the width (within the
/// tolerance); if something does, it is at least `0.75 − 0.25 / 2` of the
/// width closer, so the runs make progress.
pub(crate) const PROOF_MARGIN_FRACTION: Real = 0.75;

/// The contract tolerance of a run that screens an interval for a
/// caller's near misses (does the pair come within a distance?), at least,
/// as a fraction of that distance: `0.25`. Such a run certifies that the
/// pair stays farther than the distance, or stops where it comes within
/// 1.125 times it: it only chooses the intervals to bracket.
pub(crate) const SCREEN_TOLERANCE_FRACTION: Real = 0.25;

/// The descent to a local minimum stops once the distance cannot move by
/// this fraction of the width across its time bracket: `0.125` (the upper
/// bound is then that close to the local minimum).
pub(crate) const DESCENT_PRECISION_FRACTION: Real = 0.125;

/// An end of the interval takes its distance from a triangle pair around
/// the hulls' closest vertices where that is within this fraction of the
/// width of the hulls' gap ([`pair_at_hulls`]): `0.5`. The first run then
/// asks for `0.75` of the width below it, and stops only within `0.125` of
/// the width above that (its own tolerance, `RUN_TOLERANCE_FRACTION / 2`),
/// so at least `0.125` of the width below the end's distance: never at
/// the end itself.
pub(crate) const ENDS_TOLERANCE_FRACTION: Real = 0.5;

/// A closest-approach query: two meshes moving as in
/// [`mesh_time_of_impact`](crate::ccd::mesh_time_of_impact) over `[0, duration]`.
#[derive(Copy, Clone, Debug)]
pub struct ClosestApproachQuery<'a> {
    /// The first body.
    pub a: MovingMesh<'a>,
    /// The second body.
    pub b: MovingMesh<'a>,
    /// The length of the interval.
    pub duration: Real,
    /// Only approaches this close or closer are bracketed; a pair that
    /// stays farther is [`ApproachStatus::Beyond`] after one CCD run.
    /// `Real::INFINITY` brackets every pair.
    pub within: Real,
    /// The bracket's largest width, an absolute distance. `None`:
    /// [`DEFAULT_APPROACH_TOLERANCE`] × the smaller mesh's radius.
    pub tolerance: Option<Real>,
    /// The first iteration budget of each CCD run: a run that runs out of
    /// it is run again with ten times as many, until it decides (the
    /// options' other fields are set by the bisection).
    pub options: CcdOptions,
    /// The kernel of the CCD runs; the upper bound is always measured with
    /// the exact kernel.
    pub kernel: DistanceKernel,
    /// A distance the meshes are known to reach, and when (measured with
    /// the exact kernel at that time of this interval, e.g. at its end):
    /// when it is within `within`, the bracket starts from it, so the first
    /// run asks whether anything comes closer than it less three quarters
    /// of the width; where nothing does (a minimum at that time, as at the
    /// end of a steady approach) that one run closes the bracket with no
    /// descent. Default: none.
    pub reached: Option<(Real, MeshDistance)>,
}

impl ClosestApproachQuery<'_> {
    /// The bracket's largest width, absolute: the query's tolerance, or
    /// [`DEFAULT_APPROACH_TOLERANCE`] × the smaller mesh's radius.
    pub fn width(&self) -> Real {
        self.tolerance.unwrap_or(DEFAULT_APPROACH_TOLERANCE * smaller_radius(self))
    }
}

/// The smaller of the two meshes' radii (at least the smallest positive
/// number).
fn smaller_radius(query: &ClosestApproachQuery<'_>) -> Real {
    query.a.mesh.radius().min(query.b.mesh.radius()).max(Real::MIN_POSITIVE)
}

impl<'a> ClosestApproachQuery<'a> {
    /// Brackets the closest approach over `[0, duration]` to the default
    /// tolerance, whatever the distance.
    pub fn new(a: MovingMesh<'a>, b: MovingMesh<'a>, duration: Real) -> ClosestApproachQuery<'a> {
        ClosestApproachQuery {
            a,
            b,
            duration,
            within: Real::INFINITY,
            tolerance: None,
            options: CcdOptions::default(),
            kernel: DistanceKernel::Exact,
            reached: None,
        }
    }
}

/// How a closest-approach query ended.
#[derive(Copy, Clone, Debug, PartialEq, Eq)]
#[non_exhaustive]
pub enum ApproachStatus {
    /// `upper − lower` is within the tolerance.
    Bracketed,
    /// The meshes come within half the tolerance of each other (they
    /// touch, to the bracket's width): the time is the time of first
    /// contact (never late), `upper` the distance there, and `lower` 0.
    Contact,
    /// The meshes stay farther than `within` over the whole interval:
    /// `lower ≥ within` is certified; nothing closer was looked for.
    Beyond,
    /// `MAX_APPROACH_RUNS` runs did not close the bracket: `lower` and
    /// `upper` still hold, only wider than the tolerance.
    OutOfIterations,
    /// A CCD run could not decide: `upper` holds (it was measured), `lower`
    /// is the last certified one. A run's budget grows tenfold until it
    /// reaches the steps that decide it, so this is left for a run whose
    /// step bound is beyond counting (not a number).
    Undecided,
}

/// The answer of [`closest_approach`].
#[derive(Copy, Clone, Debug, PartialEq)]
pub struct ClosestApproach {
    /// How the query ended.
    pub status: ApproachStatus,
    /// Certified: the meshes are never closer than this over the interval.
    pub lower: Real,
    /// Reached: the reported points are this far apart at `time`, so the
    /// meshes' distance there is at most this, and at least `lower`
    /// (infinite, with `closest` `None`, when the status is
    /// [`ApproachStatus::Beyond`]).
    pub upper: Real,
    /// When `upper` is reached (the time of first contact under
    /// [`ApproachStatus::Contact`]).
    pub time: Real,
    /// The closest points (world frame), triangles and features at `time`:
    /// `upper` apart, the meshes' closest to the bracket's width (on meshes
    /// not both convex, the pair the descent walked to, which another pair
    /// may undercut by at most `upper − lower`).
    pub closest: Option<MeshDistance>,
    /// CCD runs taken.
    pub runs: usize,
}

/// The closest approach of the two meshes of `query` over its interval,
/// as a certified bracket (see the module). `scratch` is reused across
/// runs; nothing is allocated once it has grown.
///
/// ```
/// use nearmiss::ccd::{closest_approach, ApproachStatus, ClosestApproachQuery, MovingMesh};
/// use nearmiss::math::{Pose, Vector};
/// use nearmiss::mesh::box_mesh;
/// use nearmiss::motion::StepMotion;
///
/// // A unit cube passes another at a lateral offset of 1.25: its faces go
/// // by 0.25 apart at t = 1.
/// let cube = box_mesh(&Vector::new(0.5, 0.5, 0.5)).unwrap();
/// let fixed = StepMotion::new(Pose::identity(), Vector::zeros(), Vector::zeros());
/// let moving = StepMotion::new(Pose::translation(-3.0, 1.25, 0.0), Vector::new(3.0, 0.0, 0.0), Vector::zeros());
/// let query = ClosestApproachQuery::new(
///     MovingMesh { mesh: &cube, motion: &fixed },
///     MovingMesh { mesh: &cube, motion: &moving },
///     2.0,
/// );
/// let approach = closest_approach(&query, &mut Default::default());
/// assert_eq!(approach.status, ApproachStatus::Bracketed);
/// assert!(approach.lower <= 0.25 && 0.25 <= approach.upper && approach.upper - approach.lower <= 1e-6);
/// ```
pub fn closest_approach(query: &ClosestApproachQuery<'_>, scratch: &mut MeshCcdScratch) -> ClosestApproach {
    let (a, b) = (query.a, query.b);
    let runs = Runs::of(query);
    let mut answer = ClosestApproach {
        status: ApproachStatus::Beyond,
        lower: 0.0,
        upper: Real::INFINITY,
        time: 0.0,
        closest: None,
        runs: 0,
    };
    let mut warm = WarmStart::default();
    // Every approach is wanted: first, do they touch? That run is the time
    // of impact's own (cheap where the meshes stay apart: its filters settle
    // it), and a pair that touches is answered by it, where the runs from
    // the ends' distance down would each search every triangle pair within
    // that distance (and the ends' distances are not needed).
    // Every front a run keeps is this query's (see `Runs::below`).
    scratch.front.reset();
    let first =
        (!query.within.is_finite()).then(|| runs.below(query, (0.0, 0.0), warm, scratch, FrontStart::Roots));
    if let Some((run, result)) = &first {
        answer.runs += 1;
        warm = WarmStart { lower_bound: None, hint: result.hint, axis: result.axis, simplex: result.simplex };
        if let Run::Touching { time } = *run {
            answer.touch(measure(&a, &b, time, result.hint, scratch), time);
            return answer;
        }
        // The interval's ends are a first upper bound. The end whose hulls
        // are nearer (or, where they touch at both, whose centres are) is
        // measured first, and the other only where it is as near or nearer
        // (a search that starts with that distance as its best: a few node
        // pairs where it is well beyond). On a tie the start is kept. Where
        // the hulls' gap certifies a pair around their closest vertices to
        // `ENDS_TOLERANCE_FRACTION` of the width, that pair's distance is
        // the end's, with no search.
        let at = |s: Real| {
            let pose = StepMotion::relative_pose(a.motion, b.motion, s);
            let gap = hull_gap(a.mesh, b.mesh, &pose, None, (0.0, Real::INFINITY));
            (s, pose, gap)
        };
        let guess =
            |(_, pose, gap): &(Real, Pose, HullGap)| (gap.lower.max(0.0), pose.translation.vector.norm());
        let on_hulls = |(s, pose, gap): &(Real, Pose, HullGap)| {
            let found = pair_at_hulls(a.mesh, b.mesh, pose, gap, ENDS_TOLERANCE_FRACTION * runs.width)?;
            Some(in_world(&a, *s, found))
        };
        let (start, end) = (at(0.0), at(query.duration));
        let (near, far) = if guess(&end) < guess(&start) { (end, start) } else { (start, end) };
        let at_near = on_hulls(&near).unwrap_or_else(|| measure(&a, &b, near.0, None, scratch));
        // The far end where it is nearer, or as near and the start.
        let ceiling = if far.0 == 0.0 { at_near.distance.next_up() } else { at_near.distance };
        let at_far = match on_hulls(&far) {
            Some(found) => Some(found).filter(|found| found.distance < ceiling),
            None => measure_below(&a, &b, (far.0, Some(&far.2)), ceiling, scratch),
        };
        match at_far {
            Some(found) => answer.keep(found, far.0),
            None => answer.keep(at_near, near.0),
        }
    }
    if let Some((s, found)) = query.reached.filter(|(_, found)| found.distance <= query.within) {
        answer.keep(found, s);
    }
    if let Some((run, _)) = first {
        match run {
            Run::Beyond { lower } => answer.lower = lower.min(answer.upper),
            Run::Undecided => {
                answer.status = ApproachStatus::Undecided;
                return answer;
            }
            Run::Closer { .. } | Run::Touching { .. } => {}
        }
        // Closing at the start, where the best is: the first run would
        // stop a hair later (the distance falls below the best at once),
        // so the descent starts from there without it.
        if let Some(found) = answer.closest.filter(|found| answer.time == 0.0 && closing(&a, &b, 0.0, found))
        {
            let (at, found) = descend(
                &a,
                &b,
                (0.0, query.duration),
                DESCENT_PRECISION_FRACTION * runs.width,
                Some((found.triangle_a, found.triangle_b)),
                scratch,
            );
            answer.keep(found, at);
        }
    }
    // Every time before `proven.0` is certified farther than `proven.1`
    // (by a run that stopped there).
    let mut proven = (0.0, Real::NEG_INFINITY);
    while answer.runs < MAX_APPROACH_RUNS {
        // The first run asks for `within`; each later one whether anything
        // comes closer than the best found less three quarters of the
        // width (if not, the bracket is closed).
        let target = if answer.closest.is_none() {
            query.within
        } else {
            answer.upper - PROOF_MARGIN_FRACTION * runs.width
        };
        // A run after one that stopped closer than its target starts where
        // that one stopped: before, the distance stayed above that target,
        // which is above this one (see `Runs::below`).
        let from = if proven.1 >= target { proven.0 } else { 0.0 };
        let (run, result) = runs.below(query, (from, target), warm, scratch, FrontStart::Kept);
        answer.runs += 1;
        warm = WarmStart { lower_bound: None, hint: result.hint, axis: result.axis, simplex: result.simplex };
        match run {
            Run::Undecided => {
                answer.status = ApproachStatus::Undecided;
                return answer;
            }
            Run::Beyond { lower } => {
                answer.lower = answer.lower.max(lower.min(answer.upper));
                answer.status = match answer.closest {
                    None => ApproachStatus::Beyond,
                    Some(_) => ApproachStatus::Bracketed,
                };
                return answer;
            }
            Run::Touching { time } => {
                answer.touch(measure(&a, &b, time, result.hint, scratch), time);
                return answer;
            }
            Run::Closer { time } => {
                proven = (time, result.guaranteed_distance);
                // Closer than asked at `time`, and closing: the distance's
                // local minimum after it is the next best.
                let (at, found) = descend(
                    &a,
                    &b,
                    (time, query.duration),
                    DESCENT_PRECISION_FRACTION * runs.width,
                    result.hint,
                    scratch,
                );
                answer.keep(found, at);
            }
        }
    }
    answer.status = ApproachStatus::OutOfIterations;
    answer
}

/// Whether the distance between the closest points `found` (world frame)
/// of the meshes at time `s` is falling there. The meshes' distance is at
/// most those points', so it falls too (at a tie between closest pairs,
/// the one found is enough).
fn closing(a: &MovingMesh<'_>, b: &MovingMesh<'_>, s: Real, found: &MeshDistance) -> bool {
    let velocity = |m: &MovingMesh<'_>, p: &Point| {
        m.motion.velocity + m.motion.angular_velocity.cross(&(p - m.motion.center_at(s)))
    };
    let apart = found.point_b - found.point_a;
    apart.dot(&(velocity(b, &found.point_b) - velocity(a, &found.point_a))) < 0.0
}

/// What one CCD run of a closest approach found below its target.
#[derive(Copy, Clone, Debug, PartialEq)]
pub(crate) enum Run {
    /// Never closer than `lower` (certified, at least the target) over the
    /// interval.
    Beyond { lower: Real },
    /// Within the target (to the run's tolerance) at `time`, first.
    Closer { time: Real },
    /// The target was within the run's tolerance of 0: touching, first at
    /// `time` (never late).
    Touching { time: Real },
    /// The CCD ran out of iterations.
    Undecided,
}

/// The CCD runs' settings of one query: the bracket's width and the runs'
/// options.
struct Runs {
    width: Real,
    /// Each run's contract tolerance τ (absolute).
    tau: Real,
    options: CcdOptions,
    /// The most any point of one mesh can close on the other over the
    /// interval: the duration times the head-on bound of the closing speed.
    closing: Real,
}

impl Runs {
    fn of(query: &ClosestApproachQuery<'_>) -> Runs {
        let (radius, width) = (smaller_radius(query), query.width());
        // Each run's contract tolerance τ: a quarter of the bracket's width.
        let tau = RUN_TOLERANCE_FRACTION * width;
        let options =
            CcdOptions { distance_tolerance: tau / radius, minimum_separation: 0.0, ..query.options };
        let closing = query.duration * PairMotion::of(&query.a, &query.b, query.duration).speed;
        Runs { width, tau, options, closing }
    }

    /// The advancement steps that decide any run of `result`'s contract:
    /// every step of the BVH search is at least the contact distance less
    /// the target over the closing speed (see `mesh_search.rs`), so the
    /// interval is crossed in at most `closing / (contact − target)` steps
    /// (one more for the last, partial one, and one for rounding).
    fn decided_within(&self, result: &MeshCcdResult) -> usize {
        let least_gain = result.contact_distance - result.guaranteed_distance;
        // A bound beyond `usize` saturates; one that is not a number (a
        // motion that is not) grows nothing, and the run stays undecided.
        let steps = (self.closing / least_gain).ceil();
        if steps.is_nan() {
            0
        } else {
            (steps as usize).saturating_add(2)
        }
    }

    /// One CCD run: does anything come closer than `target` from time
    /// `from` on? Its times are the query's (from 0).
    ///
    /// A run that stops at a time (closer than its target there) has
    /// certified the distance above its guaranteed distance `G` before it,
    /// and the meshes within `G + τ / 2` there: the next target, three
    /// quarters of the width below the next best (at most that distance),
    /// is lower than `G`, so the next run need only start there, and its
    /// search from the front the stopped one left (`FrontStart::Kept`):
    /// every element of it holds for the lower target from there on
    /// ([`Front::begin`](super::mesh_search::Front::begin) checks both), so
    /// the node pairs it opened are not opened again. A run that starts
    /// earlier, or from a higher target, starts from the roots.
    fn below(
        &self,
        query: &ClosestApproachQuery<'_>,
        (from, target): (Real, Real),
        warm: WarmStart,
        scratch: &mut MeshCcdScratch,
        front_start: FrontStart,
    ) -> (Run, MeshCcdResult) {
        // (A start at or past the end would leave no interval to ask about.)
        let from = if from < query.duration { from } else { 0.0 };
        let later = |m: &MovingMesh<'_>| StepMotion { elapsed: m.motion.elapsed + from, ..*m.motion };
        let (motion_a, motion_b) = (later(&query.a), later(&query.b));
        // The run's target (`separation + τ / 2`, the contract's) is `target`.
        let separation = (target - TARGET_FRACTION * self.tau).max(0.0);
        let ccd = MeshCcdQuery {
            a: MovingMesh { motion: &motion_a, ..query.a },
            b: MovingMesh { motion: &motion_b, ..query.b },
            duration: query.duration - from,
            options: self.options,
            contact: ContactRule::Separation(separation),
            kernel: query.kernel,
        };
        let mut result = mesh_time_of_impact_with(&ccd, warm, scratch, (Touching::Named, front_start));
        // Out of iterations: the run again with `BUDGET_GROWTH` times the
        // budget, up to the steps that decide it (a grazing pass can need
        // many small advancement steps).
        let mut budget = self.options.max_iterations.max(1);
        let decided_within = self.decided_within(&result);
        while result.status == CcdStatus::OutOfIterations && budget < decided_within {
            budget = budget.saturating_mul(BUDGET_GROWTH).min(decided_within);
            let ccd = MeshCcdQuery { options: CcdOptions { max_iterations: budget, ..self.options }, ..ccd };
            result = mesh_time_of_impact_with(&ccd, warm, scratch, (Touching::Named, front_start));
        }
        result.time_of_impact = result.time_of_impact.map(|time| time + from);
        let run = match (result.status, result.time_of_impact) {
            (CcdStatus::OutOfIterations, _) => Run::Undecided,
            // Never within the run's guaranteed distance: certified.
            (_, None) => Run::Beyond { lower: result.guaranteed_distance },
            // Within the contact distance of no separation.
            (_, Some(time)) if separation == 0.0 => Run::Touching { time },
            (_, Some(time)) => Run::Closer { time },
        };
        (run, result)
    }
}

/// The first run of [`closest_approach`] alone, coarser: whether the
/// meshes of `query` come within its `within` over the interval, and if so
/// when (and the CCD's closest triangle pair there, a hint). A caller that
/// brackets many intervals of one pair screens them this way and brackets
/// only those that may hold its closest approach.
///
/// The run's contract tolerance is at least [`SCREEN_TOLERANCE_FRACTION`]
/// of `within` (the bracket's own where that is larger): `Beyond` still
/// certifies that the meshes stay farther than `within`, but `Closer` may
/// stop where they are up to `1 + (1 − TARGET_FRACTION) ×` that fraction
/// of `within` apart, before they come within it. A screen only chooses the
/// intervals to bracket, and each bracket then asks at its own width; the
/// advancement that would pin down the moment a pair crosses `within` to
/// the bracket's width (a millionth of the radius) is not spent.
pub(crate) fn screen(
    query: &ClosestApproachQuery<'_>,
    warm: WarmStart,
    scratch: &mut MeshCcdScratch,
) -> (Run, MeshCcdResult) {
    let mut runs = Runs::of(query);
    let coarse = SCREEN_TOLERANCE_FRACTION * query.within;
    if coarse > runs.tau {
        runs.options.distance_tolerance *= coarse / runs.tau;
        runs.tau = coarse;
    }
    runs.below(query, (0.0, query.within), warm, scratch, FrontStart::Roots)
}

impl ClosestApproach {
    /// The meshes touch, first at `time`, `found` apart there.
    fn touch(&mut self, found: MeshDistance, time: Real) {
        (self.status, self.lower, self.upper) = (ApproachStatus::Contact, 0.0, found.distance);
        (self.time, self.closest) = (time, Some(found));
    }

    /// Keeps `found` (at time `s`) if it is the closest yet.
    fn keep(&mut self, found: MeshDistance, s: Real) {
        if self.closest.is_none() || found.distance < self.upper {
            (self.upper, self.time, self.closest) = (found.distance, s, Some(found));
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::math::{Pose, Vector};
    use crate::mesh::{box_mesh, icosphere};
    use crate::motion::StepMotion;
    use crate::samples::Rng;

    #[test]
    fn closing_is_the_sign_of_the_distance_s_change() {
        // Boxes and icospheres near each other, moving and spinning at
        // random: where the exact distance changes clearly over a short
        // time (more than 1e-9 over 1e-6), `closing` at the start says
        // whether it fell, from the closest points' velocities alone.
        let meshes = [box_mesh(&Vector::new(0.3, 0.2, 0.25)).unwrap(), icosphere(0.3, 2).unwrap()];
        let mut rng = Rng::new(41);
        let mut scratch = MeshCcdScratch::default();
        let (mut checked, mut falling) = (0, 0);
        for case in 0..400 {
            let (mesh_a, mesh_b) = (&meshes[case % 2], &meshes[(case / 2) % 2]);
            let ma = StepMotion::new(
                Pose::new(rng.in_unit_ball(), rng.in_unit_ball() * 3.0),
                rng.in_unit_ball() * 2.0,
                rng.in_unit_ball() * 5.0,
            );
            let mb = StepMotion::new(
                Pose::new(Vector::new(1.2, 0.0, 0.0) + rng.in_unit_ball() * 0.3, rng.in_unit_ball() * 3.0),
                rng.in_unit_ball() * 2.0,
                rng.in_unit_ball() * 5.0,
            );
            let (a, b) = (MovingMesh { mesh: mesh_a, motion: &ma }, MovingMesh { mesh: mesh_b, motion: &mb });
            let now = measure(&a, &b, 0.0, None, &mut scratch);
            if now.distance <= 1e-3 {
                continue;
            }
            let change = measure(&a, &b, 1e-6, None, &mut scratch).distance - now.distance;
            if change.abs() <= 1e-9 {
                continue;
            }
            checked += 1;
            falling += usize::from(change < 0.0);
            assert_eq!(
                closing(&a, &b, 0.0, &now),
                change < 0.0,
                "case {case}: the distance changed by {change}"
            );
        }
        assert!(checked > 300 && falling > 100 && checked - falling > 100, "{falling} falling of {checked}");
    }
}

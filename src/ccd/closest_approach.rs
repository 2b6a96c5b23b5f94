//! The closest approach of two moving meshes over an interval, as a
//! certified bracket: the smallest distance `d*` between them over the
//! interval satisfies `lower ≤ d* ≤ upper`, `upper` is a distance the meshes
//! really reach (at `time`, between the reported closest points), and
//! `upper − lower` is at most the query's tolerance.
//!
//! Built on the CCD's own conservative machinery, nothing else: a
//! [`mesh_time_of_impact`] run with a minimum separation `S` either proves
//! that the meshes stay farther than its guaranteed distance over the whole
//! interval (the contract: every approach closer than `S + τ/2` is reported,
//! so none means `d* ≥ S + τ/2`, a certified lower bound), or stops at a
//! time where the meshes are within `S + τ` (where their exact distance,
//! measured there, is an upper bound that is reached). A bisection on `S`
//! closes the bracket. The first run asks for the query's `within`
//! distance: a pair that never comes that near costs that one run, which
//! for well separated meshes is one bounding-sphere or hull check.
//!
//! Where the meshes come within the CCD's contact distance (touching), the
//! answer is that contact ([`ApproachStatus::Contact`]): its time of first
//! contact is then what a caller wants.

use super::contact::ContactRule;
use super::mesh_pair::{mesh_time_of_impact, MeshCcdQuery, MeshCcdScratch, MovingMesh, WarmStart};
use super::options::{CcdOptions, CcdStatus};
use crate::math::Real;
use crate::mesh::{mesh_distance_relative, DistanceKernel, DistanceSearch, MeshDistance};
use crate::motion::StepMotion;

/// The bracket's width, relative to the smaller mesh's radius, when the
/// query states none: `1e-6`, the contact contract's default
/// ([`CcdOptions::distance_tolerance`]).
pub const DEFAULT_APPROACH_TOLERANCE: Real = 1e-6;

/// The most CCD runs one closest approach takes (the first one, then the
/// bisection's): `64`, enough to halve any finite bracket down to the
/// rounding of its coordinates. A query that needs more ends as
/// [`ApproachStatus::OutOfIterations`] with the bracket reached.
pub const MAX_APPROACH_RUNS: usize = 64;

/// A closest-approach query: two meshes moving as in
/// [`mesh_time_of_impact`] over `[0, duration]`.
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
    /// The iteration limit of each CCD run (the options' other fields are
    /// set by the bisection).
    pub options: CcdOptions,
    /// The kernel of the CCD runs; the upper bound is always measured with
    /// the exact kernel.
    pub kernel: DistanceKernel,
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
    /// [`MAX_APPROACH_RUNS`] runs did not close the bracket: `lower` and
    /// `upper` still hold, only wider than the tolerance.
    OutOfIterations,
    /// A CCD run could not decide within its iterations: `upper` holds (it
    /// was measured), `lower` is the last certified one.
    Undecided,
}

/// The answer of [`closest_approach`].
#[derive(Copy, Clone, Debug, PartialEq)]
pub struct ClosestApproach {
    /// How the query ended.
    pub status: ApproachStatus,
    /// Certified: the meshes are never closer than this over the interval.
    pub lower: Real,
    /// Reached: the meshes are this far apart at `time` (infinite, with
    /// `closest` `None`, when the status is [`ApproachStatus::Beyond`]).
    pub upper: Real,
    /// When `upper` is reached (the time of first contact under
    /// [`ApproachStatus::Contact`]).
    pub time: Real,
    /// The closest points (world frame), triangles and features at `time`.
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
    let radius = a.mesh.radius().min(b.mesh.radius()).max(Real::MIN_POSITIVE);
    let width = query.tolerance.unwrap_or(DEFAULT_APPROACH_TOLERANCE * radius);
    // Each run's contract tolerance τ: half the bracket's width, so that
    // the bisection's last bracket (width about τ) fits in it.
    let tau = 0.5 * width;
    let options = CcdOptions { distance_tolerance: tau / radius, minimum_separation: 0.0, ..query.options };
    let run = |separation: Real, warm: WarmStart, scratch: &mut MeshCcdScratch| {
        let ccd = MeshCcdQuery {
            a,
            b,
            duration: query.duration,
            options,
            contact: ContactRule::Separation(separation.max(0.0)),
            kernel: query.kernel,
        };
        mesh_time_of_impact(&ccd, warm, scratch)
    };
    let mut answer = ClosestApproach {
        status: ApproachStatus::Beyond,
        lower: 0.0,
        upper: Real::INFINITY,
        time: 0.0,
        closest: None,
        runs: 0,
    };
    let mut warm = WarmStart::default();
    // The first run: as close as `within`? (Its target is `within`.)
    let mut separation = if query.within.is_finite() { query.within - 0.5 * tau } else { Real::INFINITY };
    if separation.is_infinite() {
        // Every pair is bracketed: start from the distance at the start.
        let at_start = measure(&a, &b, 0.0, None, scratch);
        answer.upper = at_start.distance;
        answer.closest = Some(at_start);
        separation = 0.5 * at_start.distance - 0.5 * tau;
    }
    while answer.runs < MAX_APPROACH_RUNS {
        let result = run(separation, warm, scratch);
        answer.runs += 1;
        warm = WarmStart { lower_bound: None, hint: result.hint, axis: result.axis, simplex: result.simplex };
        match (result.status, result.time_of_impact) {
            (CcdStatus::OutOfIterations, _) => {
                answer.status = ApproachStatus::Undecided;
                return answer;
            }
            (_, None) => {
                // Never within the run's guaranteed distance.
                answer.lower = answer.lower.max(result.guaranteed_distance);
                if answer.closest.is_none() {
                    answer.lower = answer.lower.max(query.within.min(result.guaranteed_distance));
                    answer.status = ApproachStatus::Beyond;
                    return answer;
                }
            }
            (_, Some(time)) => {
                let measured = measure(&a, &b, time, result.hint, scratch);
                if separation <= 0.0 {
                    // Within the contact distance of no separation: touching,
                    // first at `time`.
                    (answer.status, answer.lower, answer.upper) =
                        (ApproachStatus::Contact, 0.0, measured.distance);
                    (answer.time, answer.closest) = (time, Some(measured));
                    return answer;
                }
                if measured.distance < answer.upper || answer.closest.is_none() {
                    (answer.upper, answer.time, answer.closest) = (measured.distance, time, Some(measured));
                }
            }
        }
        if answer.upper - answer.lower <= width || answer.upper <= tau {
            if answer.lower < tau && separation > 0.0 {
                // The bracket reaches down to touching: the run without
                // separation says whether they touch, and first when.
                separation = 0.0;
                continue;
            }
            answer.status = ApproachStatus::Bracketed;
            return answer;
        }
        // The next run's target halves the bracket.
        separation = 0.5 * (answer.lower + answer.upper) - 0.5 * tau;
    }
    answer.status = ApproachStatus::OutOfIterations;
    answer
}

/// The exact distance between the two meshes at time `s`, points in the
/// world frame.
fn measure(
    a: &MovingMesh<'_>,
    b: &MovingMesh<'_>,
    s: Real,
    hint: Option<(usize, usize)>,
    scratch: &mut MeshCcdScratch,
) -> MeshDistance {
    let relative = StepMotion::relative_pose(a.motion, b.motion, s);
    let search = DistanceSearch::new(DistanceKernel::Exact, hint);
    let mut found = mesh_distance_relative(a.mesh, b.mesh, &relative, &search, &mut scratch.distance);
    let pose_a = a.motion.pose_at(s);
    found.point_a = pose_a * found.point_a;
    found.point_b = pose_a * found.point_b;
    found
}

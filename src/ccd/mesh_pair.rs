//! Conservative advancement for two rigid meshes over one step.
//!
//! Each body moves with constant linear velocity `v` and angular velocity
//! `ω` about its centre of mass ([`StepMotion`]). From a time `s`, a search
//! over both BVHs (`mesh_search.rs`, with the bounds of `mesh_bound.rs`)
//! finds a step before which no triangle pair can come within `target`:
//! per pair, a second-order bound of the
//! motion along the pair's own separating direction, backed by the head-on
//! bound of every point's speed,
//!
//! ```text
//! L = |v_a − v_b| + |ω_a| r_a + |ω_b| r_b ,   step ≥ (d − target) / L .
//! ```
//!
//! The loop stops when the search meets a triangle pair within the contact
//! distance `minimum_separation + tolerance` (contact, never late: every
//! step was proven contact-free), or when the step reaches the interval's
//! end (no contact), or after `max_iterations` steps
//! ([`CcdStatus::OutOfIterations`]: undecided; the time reached so far is
//! reported, every step before it having been proven contact-free).
//!
//! ## The contract
//! The target is `minimum_separation + tolerance / 2`, as in the
//! linear-vertex queries (the contract of `contact.rs`), so each step gains
//! at least `tolerance / (2 L)` and rounding (a few ulps of the
//! coordinates, far below the tolerance floor) stays on the safe side.
//! Every approach closer than the target is reported (the
//! `guaranteed_distance` of the result); no contact is reported farther
//! than the contact distance `minimum_separation + tolerance`.
//!
//! The tolerance is `distance_tolerance × min(r_a, r_b)`: relative to the
//! smaller body, the scale where a contact happens (a unit box on a floor of
//! any size gets the box's tolerance). It is never below a rounding floor
//! of 64 ulps ([`ROUNDING_FLOOR_ULPS`]) of the pair's own scale (the centres'
//! distance, their travel and both radii: distances are computed in
//! pair-relative coordinates, [`StepMotion::relative_pose`]) plus 8 ulps
//! (`INTEGRATED_JUMP_ULPS`) of an integrated body's coordinates: far from
//! the origin, or next to a body of 1e8, the coordinates themselves carry
//! that much rounding.
//!
//! Three cheap tests come first: the bounding spheres about the centres of
//! mass (whose distance is exact over the step, the centres moving
//! linearly), a lower bound on the distance carried over from the
//! previous step (`lower_bound`), and the gap between the convex hulls of
//! the two meshes' vertices at the step's start (GJK, `hull_gap.rs`,
//! started from the previous step's axis), less what the motion can close
//! along the gap's direction over the step (the centres' approach along it
//! and each body's turn, at most `|n × ω| r`; or, to second order over a
//! horizon of such steps, the rise of each hull's top alone, from its
//! support along the turning direction, with the direction fixed or turning
//! with either body, [`GapMotion`]). Each lets a pair that stays apart skip
//! the step without any search. Where the hulls' gap does not
//! last the whole step, it still proves a part of it: conservative
//! advancement runs on the hulls' gap alone (one warm-started GJK a step)
//! until the hulls come within the contact distance. There, a triangle
//! pair within the contact distance among the pair's last closest and the
//! triangles around the hulls' closest vertices is the contact (for convex
//! meshes the hulls are the meshes, and the closest pair is among those);
//! only otherwise does the BVH search take over from that time.

use super::contact::ContactContract;
use super::hull_advance::{advance_on_hulls, pair_at_touching_hulls};
use super::mesh_bound::{PairFrame, SPIN_SWEEP_AFTER_ITERATIONS, SPIN_SWEEP_MIN_TURN};
use super::mesh_search::{FrontOrigin, FrontStart, SearchMeshes, StepLimits, StepOutcome, StepWork};
use super::options::{CcdOptions, CcdStatus};
use super::pair_motion::{spheres_apart, PairMotion, Reached};
use super::query::{MeshCcdQuery, MeshCcdResult, MeshCcdScratch, Touching, WarmStart};
use super::spin_sweep::spin_swept_apart;
use crate::math::{Pose, Real};
use crate::mesh::distance::triangle_pair_distance;
use crate::mesh::{mesh_distance_relative, DistanceKernel, DistanceSearch, MeshDistance};

/// The first time in `[0, duration]` at which two moving meshes come within
/// the contact distance, by conservative advancement: never later than the
/// true first contact, early by at most the contact distance over the
/// closing speed; [`CcdStatus::OutOfIterations`] when it could not decide.
///
/// A rod spinning about its long axis flies head-on at a cube: its end cap
/// stays a square whatever the turn, so it meets the cube's face at
/// `t = 0.5`.
///
/// ```
/// use nearmiss::ccd::{mesh_time_of_impact, CcdOptions, CcdStatus, MeshCcdQuery, MeshCcdScratch, MovingMesh, WarmStart};
/// use nearmiss::math::{Pose, Vector};
/// use nearmiss::mesh::box_mesh;
/// use nearmiss::motion::StepMotion;
///
/// let cube = box_mesh(&Vector::new(0.5, 0.5, 0.5)).unwrap();
/// let rod = box_mesh(&Vector::new(0.5, 0.1, 0.1)).unwrap();
/// let at_rest = StepMotion::fixed(Pose::identity());
/// // The rod's near end 1 from the cube's face, closing at 2, spinning at 20 rad/s.
/// let flying = StepMotion::free(&Pose::translation(2.0, 0.0, 0.0), Vector::new(-2.0, 0.0, 0.0), Vector::new(20.0, 0.0, 0.0), 0.0);
/// let query = MeshCcdQuery::new(
///     MovingMesh { mesh: &cube, motion: &at_rest },
///     MovingMesh { mesh: &rod, motion: &flying },
///     1.0,
///     CcdOptions::default(),
/// );
/// let result = mesh_time_of_impact(&query, WarmStart::default(), &mut MeshCcdScratch::default());
/// assert_eq!(result.status, CcdStatus::Converged);
/// let time = result.time_of_impact.unwrap();
/// assert!(time <= 0.5 && time >= 0.5 - result.contact_distance / 2.0);
/// ```
pub fn mesh_time_of_impact(
    query: &MeshCcdQuery<'_>,
    warm: WarmStart,
    scratch: &mut MeshCcdScratch,
) -> MeshCcdResult {
    mesh_time_of_impact_with(query, warm, scratch, (Touching::Searched, FrontStart::Roots))
}

/// [`mesh_time_of_impact`], with the choice of [`Touching`] and where the
/// BVH search starts ([`FrontStart`]: `Kept` only for a query of the meshes
/// and motions of the one that last used `scratch`, at a later time).
pub(crate) fn mesh_time_of_impact_with(
    query: &MeshCcdQuery<'_>,
    warm: WarmStart,
    scratch: &mut MeshCcdScratch,
    (touching_pair, front_start): (Touching, FrontStart),
) -> MeshCcdResult {
    let MeshCcdQuery { a, b, duration, ref options, contact, kernel } = *query;
    let WarmStart { lower_bound, hint, axis, simplex } = warm;
    let pair = PairMotion::of(&a, &b, duration);
    let contract = pair.contract(options, contact);
    let mut result = MeshCcdResult {
        time_of_impact: None,
        status: CcdStatus::Filtered,
        closest: None,
        contact_distance: contract.contact_distance,
        guaranteed_distance: contract.target,
        end_lower_bound: 0.0,
        hint,
        axis,
        simplex,
        iterations: 0,
        hull_steps: 0,
        triangle_pairs: 0,
        node_pairs: 0,
    };
    // 1. The bounding spheres (and a carried bound) over the whole step.
    if let Some(end_lower_bound) = spheres_apart(&pair, lower_bound, contract.target) {
        result.end_lower_bound = end_lower_bound;
        return result;
    }
    // 1b. A fast spin: the solids the bodies sweep turning about their
    // axes, over the whole step.
    if spin_swept_apart(&pair, contract.target) {
        result.status = CcdStatus::Filtered;
        return result;
    }
    // 2. Advancement on the hulls' gap.
    let Some((s, hulls_touch)) = advance_on_hulls(&pair, &contract, &mut result) else { return result };
    let first_touch = if result.hull_steps == 0 && lower_bound.is_none() {
        CcdStatus::InitiallyTouching
    } else {
        CcdStatus::Converged
    };
    let hint = hint.filter(|&(i, j)| i < a.mesh.triangles().len() && j < b.mesh.triangles().len());
    let mut work = StepWork::default();
    // 3. Where the hulls came within the contact distance, a triangle pair
    // that is within it too (the pair's last closest, or one around the
    // hulls' closest vertices: for convex meshes the closest pair is
    // there) is the contact, with no search: every time before was proven
    // safe. Otherwise the BVH search decides from there.
    let touching = match hulls_touch {
        Some(hulls) if kernel == DistanceKernel::Exact => pair_at_touching_hulls(
            &pair,
            (s, hulls),
            (touching_pair == Touching::Named).then_some(&result.simplex),
            hint,
            contract.contact_distance,
            &mut work,
        ),
        _ => None,
    };
    let reached = match touching {
        Some((found, measured)) => Reached { time: s, status: first_touch, pair: Some(found), measured },
        None => match search(
            &Searched { pair: &pair, contract: &contract, kernel, options, first_touch, front_start },
            s,
            hint,
            &mut result,
            scratch,
            &mut work,
        ) {
            Some(found) => found,
            // Apart until the interval's end (`result` says so).
            None => {
                result.triangle_pairs = work.triangle_pairs;
                result.node_pairs = work.node_pairs;
                return result;
            }
        },
    };
    // 4. The contact's closest points and features, in the world.
    finish(&pair, kernel, reached, result, scratch, work)
}

/// The search starts again from the roots after a step at least
/// [`FRONT_RESET_GROWTH`] times the one before whose search evaluated more
/// than this many triangle pairs: `4096`. After a closest approach the
/// front stays cut at the triangle pairs opened there, and on the way out
/// each is bounded again every step (a KUKA base link passing the gear
/// ring of `pybullet_data`: about 50,000 a step, a closest approach of
/// 148 ms, 105 ms with the restart). 1,024 with any growth restarted
/// while pairs still closed (47 → 66 ms on another pair); 4,096, 8,192 and
/// 16,384 (with a growth of 1.2) were no slower beyond noise on the other
/// 13 of the 14 slowest real-mesh pairs tried, and two were faster (44 →
/// 21–23 ms, 21 → 13).
pub(crate) const FRONT_RESET_TRIANGLE_PAIRS: usize = 4096;

/// ... and the step grew by this factor: `1.5` (the distance above the
/// target is widening).
pub(crate) const FRONT_RESET_GROWTH: Real = 1.5;

/// What the BVH search asks of a pair: its motion, contract, kernel and
/// options, the status of a contact found at its first iteration, and
/// where the search starts.
#[derive(Copy, Clone)]
struct Searched<'q, 'p> {
    pair: &'q PairMotion<'p>,
    contract: &'q ContactContract,
    kernel: DistanceKernel,
    options: &'q CcdOptions,
    first_touch: CcdStatus,
    front_start: FrontStart,
}

/// The BVH search from `s` (see the module): the time, status and
/// triangle pair of the contact, or of the time reached when the
/// iterations ran out ([`CcdStatus::OutOfIterations`]). `None`: apart
/// until the interval's end (`result` says so, with its end bound and
/// hint).
fn search(
    query: &Searched<'_, '_>,
    mut s: Real,
    mut hint: Option<(usize, usize)>,
    result: &mut MeshCcdResult,
    scratch: &mut MeshCcdScratch,
    work: &mut StepWork,
) -> Option<Reached> {
    let Searched { pair, contract, kernel, options, first_touch, front_start } = *query;
    let PairMotion { a, b, duration, speed, .. } = *pair;
    let (target, contact_distance) = (contract.target, contract.contact_distance);
    let relative_velocity = b.motion.velocity - a.motion.velocity;
    let (omega_a, omega_b) = (a.motion.angular_velocity, b.motion.angular_velocity);
    let spin = omega_a.norm() + omega_b.norm();
    // A step shorter than this proves nothing a triangle pair outside the
    // contact distance could not (see `mesh_search.rs`).
    let min_step = if speed > 0.0 { (contact_distance - target) / speed } else { Real::INFINITY };
    let meshes = SearchMeshes { a: a.mesh, b: b.mesh, kernel };
    scratch.front.begin(FrontOrigin { elapsed: a.motion.elapsed, target, reached: s }, front_start);
    let mut last_step = Real::INFINITY;
    for iteration in 0..options.max_iterations.max(1) {
        if iteration == SPIN_SWEEP_AFTER_ITERATIONS && spin * (duration - s) >= SPIN_SWEEP_MIN_TURN {
            // The spin-swept bounds start now: from the roots again, so
            // that whole subtrees can be settled by them. (Where the bodies
            // turn too little over the rest of the interval for them, the
            // front is kept: a new one would cost as many node pairs as
            // the front holds, for the same bounds.)
            scratch.front.reset();
        }
        let frame = PairFrame::new(
            pair.relative_pose(s),
            &a.motion.rotation_at(s),
            &relative_velocity,
            &omega_a,
            &omega_b,
        );
        let limits = StepLimits {
            start: s,
            target,
            contact_distance,
            horizon: duration - s,
            min_step,
            spin_sweep: iteration >= SPIN_SWEEP_AFTER_ITERATIONS,
        };
        result.iterations += 1;
        let evaluated_before = work.triangle_pairs;
        match scratch.front.advance(&meshes, &frame, &limits, hint, work) {
            StepOutcome::Contact { pair } => {
                let status = if iteration == 0 { first_touch } else { CcdStatus::Converged };
                return Some(Reached { time: s, status, pair: Some(pair), measured: None });
            }
            StepOutcome::Advance { step, limiting } => {
                hint = limiting.or(hint);
                if s + step >= duration {
                    result.status = CcdStatus::Separated;
                    result.end_lower_bound = target.max(scratch.front.distance_bound_at(duration, speed));
                    result.hint = hint;
                    return None;
                }
                s += step;
                if step > FRONT_RESET_GROWTH * last_step
                    && work.triangle_pairs - evaluated_before > FRONT_RESET_TRIANGLE_PAIRS
                {
                    // Moving away from a close pass: the front is still cut
                    // at the triangle pairs opened there, each bounded again
                    // every step. From the roots, the next search opens
                    // only what the wider distance above the target needs.
                    scratch.front.reset();
                }
                last_step = step;
            }
        }
    }
    Some(Reached { time: s, status: CcdStatus::OutOfIterations, pair: hint, measured: None })
}

/// The result of a contact at `s` (or of the time reached when the
/// iterations ran out): the closest points and features, in the world.
fn finish(
    pair: &PairMotion<'_>,
    kernel: DistanceKernel,
    reached: Reached,
    mut result: MeshCcdResult,
    scratch: &mut MeshCcdScratch,
    mut work: StepWork,
) -> MeshCcdResult {
    let Reached { time: s, status, pair: hint, measured } = reached;
    let (a, b) = (pair.a, pair.b);
    let pos_ab = pair.relative_pose(s);
    let mut closest = match (status, hint) {
        // The triangle pair found within the contact distance.
        (CcdStatus::Converged | CcdStatus::InitiallyTouching, Some((i, j))) => {
            measured.unwrap_or_else(|| triangle_pair_distance(a.mesh, i, b.mesh, j, &pos_ab))
        }
        // Out of iterations (every step so far was safe, so contact is
        // reported, conservatively, at the time reached): the closest pair.
        _ => {
            let closest = mesh_distance_relative(
                a.mesh,
                b.mesh,
                &pos_ab,
                &DistanceSearch::new(kernel, hint),
                &mut scratch.distance,
            );
            work.triangle_pairs += scratch.distance.triangle_pairs();
            closest
        }
    };
    to_world(&mut closest, &a.motion.pose_at(s));
    result.hint = Some((closest.triangle_a, closest.triangle_b));
    result.triangle_pairs = work.triangle_pairs;
    result.node_pairs = work.node_pairs;
    result.time_of_impact = Some(s);
    result.closest = Some(closest);
    result.status = status;
    result
}

/// Moves a distance query's points from `a`'s frame to the world.
fn to_world(closest: &mut MeshDistance, pose_a: &Pose) {
    closest.point_a = pose_a * closest.point_a;
    closest.point_b = pose_a * closest.point_b;
}

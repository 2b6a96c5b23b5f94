//! Conservative advancement for two rigid meshes over one step.
//!
//! Each body moves with constant linear velocity `v` and angular velocity
//! `ω` about its centre of mass ([`StepMotion`]), so no point of mesh `a`
//! moves faster than `|v_a| + |ω_a| r_a` (`r_a`: the mesh's radius about its
//! centre of mass), and the distance between the meshes cannot fall faster
//! than
//!
//! ```text
//! L = |v_a − v_b| + |ω_a| r_a + |ω_b| r_b .
//! ```
//!
//! From a time `s` where the distance is `d`, the meshes therefore stay more
//! than `target` apart until `s + (d − target) / L`: the advancement step.
//! The distance comes from [`mesh_distance_relative`] (the exact kernel unless the
//! scene asks for DyOP). The loop stops when the distance is at most the
//! contact distance `minimum_separation + tolerance` (contact, never late:
//! every step was proven contact-free), or when the next step would leave
//! the interval (no contact), or after `max_iterations` steps
//! ([`CcdStatus::OutOfIterations`]: contact reported where it stopped).
//!
//! The target is `minimum_separation + tolerance / 2`, as in the
//! linear-vertex queries, so each step gains at least `tolerance / (2 L)`
//! and rounding (a few ulps of the coordinates, far below the tolerance
//! floor) stays on the safe side. The tolerance is `distance_tolerance ×
//! (r_a + r_b)`: relative to the pair's size, and never below a rounding
//! floor of 64 ulps of the pair's own scale (distances are computed in
//! pair-relative coordinates: [`StepMotion::relative_pose`]) plus 8 ulps of
//! an integrated body's coordinates.
//!
//! When the global bound stops short of the interval's end, each triangle
//! pair's own directional bound may allow a longer step (`mesh_step.rs`);
//! sliding and grazing motion needs it. It is dropped for the rest of the
//! query once it fails to double the step.
//!
//! Two cheap tests come first: the bounding spheres about the centres of
//! mass (whose distance is exact over the step, the centres moving
//! linearly), and a lower bound on the distance carried over from the
//! previous step (`lower_bound`), which lets a far pair skip the step
//! without any mesh query.

use super::advance::ROUNDING_FLOOR_ULPS;
use super::mesh_step::{directional_step, PairMotion};
use super::options::{CcdOptions, CcdStatus};
use crate::math::{Pose, Real};
use crate::mesh::{mesh_distance_relative, DistanceKernel, MeshDistance, MeshDistanceScratch, TriMesh};
use crate::motion::StepMotion;

/// The directional step is tried again only while it lengthens the global
/// step at least this many times.
const DIRECTIONAL_GAIN: Real = 2.0;

/// The ulps of an integrated body's coordinates by which its path may jump
/// between one step's end and the next step's start (the step's velocity
/// is `(x1 − x0) / dt`, and `x0 + v dt` rounds back to `x1` only to a few
/// ulps); the tolerance never drops below them.
pub const INTEGRATED_JUMP_ULPS: Real = 8.0;

/// One body of a mesh CCD query: its mesh (vertices relative to the centre
/// of mass) and its motion over the step.
#[derive(Copy, Clone, Debug)]
pub struct MovingMesh<'a> {
    /// The mesh.
    pub mesh: &'a TriMesh,
    /// Its motion over the step.
    pub motion: &'a StepMotion,
}

/// The result of [`mesh_time_of_impact`].
#[derive(Copy, Clone, Debug, PartialEq)]
pub struct MeshCcdResult {
    /// Time of first contact after the step's start, within `[0, duration]`,
    /// or `None`.
    pub time_of_impact: Option<Real>,
    /// How the iteration ended.
    pub status: CcdStatus,
    /// At contact: the distance query at the reported time.
    pub closest: Option<MeshDistance>,
    /// The contact distance used (`minimum_separation + tolerance`).
    pub contact_distance: Real,
    /// Without contact: a lower bound on the distance at the step's end,
    /// to pass to the next step as `lower_bound`.
    pub end_lower_bound: Real,
    /// The last closest triangle pair, a good first guess for the next query.
    pub hint: Option<(usize, usize)>,
    /// Mesh distance queries made.
    pub distance_queries: usize,
    /// Triangle pairs evaluated over all queries.
    pub triangle_pairs: usize,
    /// Directional step searches made (`mesh_step.rs`).
    pub directional_steps: usize,
}

/// The first time in `[0, duration]` at which two moving meshes come within
/// the contact distance, by conservative advancement.
///
/// `lower_bound` is a known lower bound on the distance at the step's start
/// (`end_lower_bound` of the previous step), `hint` a triangle pair to seed
/// the distance search.
#[allow(clippy::too_many_arguments)]
pub fn mesh_time_of_impact(
    a: MovingMesh<'_>,
    b: MovingMesh<'_>,
    duration: Real,
    options: &CcdOptions,
    kernel: DistanceKernel,
    lower_bound: Option<Real>,
    hint: Option<(usize, usize)>,
    scratch: &mut MeshDistanceScratch,
) -> MeshCcdResult {
    let (ra, rb) = (a.mesh.radius(), b.mesh.radius());
    let speed = (a.motion.velocity - b.motion.velocity).norm()
        + a.motion.angular_velocity.norm() * ra
        + b.motion.angular_velocity.norm() * rb;
    // Rounding: distances are computed in a's frame from the difference of
    // the reference positions, so they round relative to the pair's own
    // scale; an integrated body's path can also jump by a few ulps of its
    // coordinates between steps.
    let relative_size = StepMotion::center_offset(a.motion, b.motion, 0.0).norm()
        + (a.motion.velocity - b.motion.velocity).norm() * duration
        + a.motion.travel(duration)
        + b.motion.travel(duration)
        + ra
        + rb;
    let jumps = [a.motion, b.motion]
        .iter()
        .filter(|m| m.integrated)
        .map(|m| m.reference.translation.vector.amax() + m.velocity.amax() * duration)
        .sum::<Real>();
    let floor = Real::EPSILON * (ROUNDING_FLOOR_ULPS * relative_size + INTEGRATED_JUMP_ULPS * jumps);
    let tolerance = (options.distance_tolerance * (ra + rb)).max(floor);
    let contact_distance = options.minimum_separation + tolerance;
    let target = options.minimum_separation + 0.5 * tolerance;
    let mut result = MeshCcdResult {
        time_of_impact: None,
        status: CcdStatus::Filtered,
        closest: None,
        contact_distance,
        end_lower_bound: 0.0,
        hint,
        distance_queries: 0,
        triangle_pairs: 0,
        directional_steps: 0,
    };

    // The bounding spheres: their centres move linearly, so the smallest
    // distance between them over the step is exact.
    let spheres_at = |s: Real| StepMotion::center_offset(a.motion, b.motion, s).norm() - ra - rb;
    let offset = StepMotion::center_offset(a.motion, b.motion, 0.0);
    let relative = b.motion.velocity - a.motion.velocity;
    let closest_approach = if relative.norm_squared() > 0.0 {
        (-offset.dot(&relative) / relative.norm_squared()).clamp(0.0, duration)
    } else {
        0.0
    };
    let carried = lower_bound.unwrap_or(Real::NEG_INFINITY).max(spheres_at(0.0));
    if spheres_at(closest_approach) > target || carried - speed * duration > target {
        result.end_lower_bound = (carried - speed * duration).max(spheres_at(duration));
        return result;
    }

    let motion = PairMotion {
        relative_velocity: b.motion.velocity - a.motion.velocity,
        angular_velocity_a: a.motion.angular_velocity,
        angular_velocity_b: b.motion.angular_velocity,
    };
    let mut directional_pays = true;
    let mut s = 0.0;
    let mut hint = hint;
    for iteration in 0..options.max_iterations.max(1) {
        let pos_ab = StepMotion::relative_pose(a.motion, b.motion, s);
        let mut closest =
            mesh_distance_relative(a.mesh, b.mesh, &pos_ab, kernel, hint, contact_distance, scratch);
        result.distance_queries += 1;
        result.triangle_pairs += closest.triangle_pairs;
        hint = Some((closest.triangle_a, closest.triangle_b));
        result.hint = hint;
        let d = closest.distance;
        if d <= contact_distance {
            to_world(&mut closest, &a.motion.pose_at(s));
            result.time_of_impact = Some(s);
            result.closest = Some(closest);
            result.status = if iteration == 0 && lower_bound.is_none() {
                CcdStatus::InitiallyTouching
            } else {
                CcdStatus::Converged
            };
            return result;
        }
        let mut step = if speed > 0.0 { (d - target) / speed } else { Real::INFINITY };
        if s + step < duration && directional_pays {
            // The global bound stops short of the step's end: the
            // per-triangle-pair directional bound may reach further. It
            // costs a scalar kernel call per nearby triangle pair, so once
            // it fails to at least double the step (a tumble, where the
            // spin terms dominate both bounds) it is not tried again in
            // this query.
            let horizon = duration - s;
            let directional = directional_step(
                a.mesh,
                b.mesh,
                &pos_ab,
                &a.motion.rotation_at(s),
                &motion,
                target,
                horizon,
                DIRECTIONAL_GAIN * step,
                &mut scratch.step_stack,
            );
            result.directional_steps += 1;
            directional_pays = directional >= DIRECTIONAL_GAIN * step;
            step = step.max(directional);
        }
        let next = s + step;
        if next >= duration {
            result.status = CcdStatus::Separated;
            result.end_lower_bound = d - speed * (duration - s);
            return result;
        }
        s = next;
    }
    // Out of iterations: every step so far was safe, so contact is reported
    // (conservatively) at the time reached.
    let pos_ab = StepMotion::relative_pose(a.motion, b.motion, s);
    let mut closest = mesh_distance_relative(a.mesh, b.mesh, &pos_ab, kernel, hint, 0.0, scratch);
    to_world(&mut closest, &a.motion.pose_at(s));
    result.distance_queries += 1;
    result.triangle_pairs += closest.triangle_pairs;
    result.time_of_impact = Some(s);
    result.closest = Some(closest);
    result.status = CcdStatus::OutOfIterations;
    result
}

/// Moves a distance query's points from `a`'s frame to the world.
fn to_world(closest: &mut MeshDistance, pose_a: &Pose) {
    closest.point_a = pose_a * closest.point_a;
    closest.point_b = pose_a * closest.point_b;
}

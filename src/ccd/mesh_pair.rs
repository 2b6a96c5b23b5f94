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
//! ([`INTEGRATED_JUMP_ULPS`]) of an integrated body's coordinates: far from
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

use super::advance::ROUNDING_FLOOR_ULPS;
use super::contact::{ContactContract, ContactRule};
use super::convex_measure::convex_measure;
use super::hull_gap::{first_within, hull_gap_from, WarmSimplex};
use super::mesh_bound::{first_root, PairFrame, SPIN_SWEEP_AFTER_ITERATIONS, SPIN_SWEEP_MIN_TURN};
use super::mesh_search::{Front, SearchMeshes, StepLimits, StepOutcome, StepWork};
use super::options::{CcdOptions, CcdStatus};
use crate::math::{Pose, Real, Vector};
use crate::mesh::distance::triangle_pair_distance;
use crate::mesh::{
    mesh_distance_relative, DistanceKernel, DistanceSearch, MeshDistance, MeshDistanceScratch, TriMesh,
};
use crate::motion::StepMotion;

/// The ulps of an integrated body's coordinates by which its path may jump
/// between one step's end and the next step's start (the step's velocity
/// is `(x1 − x0) / dt`, and `x0 + v dt` rounds back to `x1` only to a few
/// ulps); the tolerance never drops below them.
pub(crate) const INTEGRATED_JUMP_ULPS: Real = 8.0;

/// The most advancement steps taken on the hulls' gap alone before the BVH
/// search takes over (see the module). Each costs one warm-started GJK (a
/// microsecond or less), a search tens of them; spinning bodies close far
/// slower than their bound `|n × ω| r` says, so the steps shrink slowly
/// and a few dozen of them still spare most queries the search
/// (`docs/benchmarks-history.md`).
pub(crate) const HULL_ADVANCE_MAX_STEPS: usize = 64;

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
    /// At contact: a triangle pair within the contact distance at the
    /// reported time (the one that stopped the search; not necessarily the
    /// closest), or, out of iterations, the closest pair there.
    pub closest: Option<MeshDistance>,
    /// The contact distance used (`minimum_separation + tolerance`): no
    /// contact is reported farther than this.
    pub contact_distance: Real,
    /// Every approach closer than this (`minimum_separation + tolerance /
    /// 2`, the advancement's target) is reported.
    pub guaranteed_distance: Real,
    /// Without contact: a lower bound on the distance at the step's end,
    /// to pass to the next step as `lower_bound`.
    pub end_lower_bound: Real,
    /// The last closest triangle pair, a good first guess for the next query.
    pub hint: Option<(usize, usize)>,
    /// The direction (world frame, from `a` towards `b`) along which the
    /// hulls' gap was measured at the step's start, a good first guess for
    /// the next query.
    pub axis: Option<Vector>,
    /// The hulls' GJK simplex at the last hulls' gap, a good start for the
    /// next query.
    pub simplex: WarmSimplex,
    /// Advancement steps searched (0 when a filter or the hulls' gap
    /// settled the step).
    pub iterations: usize,
    /// Advancement steps taken on the hulls' gap alone, before any search
    /// (at most `HULL_ADVANCE_MAX_STEPS`).
    pub hull_steps: usize,
    /// Triangle pairs evaluated over all searches.
    pub triangle_pairs: usize,
    /// BVH node pairs bounded over all searches.
    pub node_pairs: usize,
}

/// A mesh CCD query: two moving meshes over `[0, duration]`, and what
/// counts as contact.
#[derive(Copy, Clone, Debug)]
pub struct MeshCcdQuery<'a> {
    /// The first body.
    pub a: MovingMesh<'a>,
    /// The second body.
    pub b: MovingMesh<'a>,
    /// The length of the interval (the motions' time unit).
    pub duration: Real,
    /// Tolerances and the iteration limit.
    pub options: CcdOptions,
    /// How the contact distance is chosen: relative to the pair's size, the
    /// smaller radius `min(r_a, r_b)` (the default), or absolute.
    pub contact: ContactRule,
    /// The triangle distance kernel.
    pub kernel: DistanceKernel,
}

impl<'a> MeshCcdQuery<'a> {
    /// A query with the default contact rule and the exact kernel.
    pub fn new(
        a: MovingMesh<'a>,
        b: MovingMesh<'a>,
        duration: Real,
        options: CcdOptions,
    ) -> MeshCcdQuery<'a> {
        MeshCcdQuery {
            a,
            b,
            duration,
            options,
            contact: ContactRule::default(),
            kernel: DistanceKernel::Exact,
        }
    }

    /// The contract the query is decided under (its contact distance, from
    /// its rule, the smaller radius and the rounding floor of its motions):
    /// a pair certified farther than `contract().contact_distance` over the
    /// interval by any other means is one this query finds apart.
    pub fn contract(&self) -> ContactContract {
        PairMotion::of(&self.a, &self.b, self.duration).contract(&self.options, self.contact)
    }
}

/// What a query may start from, carried over from the pair's previous
/// query (all optional; [`WarmStart::default`] is a cold start).
#[derive(Copy, Clone, Debug, Default, PartialEq)]
pub struct WarmStart {
    /// A known lower bound on the distance at the interval's start (the
    /// previous query's [`MeshCcdResult::end_lower_bound`]).
    pub lower_bound: Option<Real>,
    /// A triangle pair to seed the search (the previous query's
    /// [`MeshCcdResult::hint`]).
    pub hint: Option<(usize, usize)>,
    /// A direction (world frame, from `a` towards `b`) to start the hulls'
    /// gap from (the previous query's [`MeshCcdResult::axis`]).
    pub axis: Option<Vector>,
    /// The hulls' GJK simplex to start from (the previous query's
    /// [`MeshCcdResult::simplex`]).
    pub simplex: WarmSimplex,
}

/// Reusable buffers of [`mesh_time_of_impact`]: queries do not allocate
/// once they have grown. Keep one per thread.
#[derive(Clone, Debug, Default)]
pub struct MeshCcdScratch {
    /// The front of the advancement search (kept between its steps).
    front: Front,
    /// The buffers of the distance queries (also lent to the stepper's).
    pub(crate) distance: MeshDistanceScratch,
}

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
    mesh_time_of_impact_with(query, warm, scratch, Touching::Searched)
}

/// Which triangle pair [`mesh_time_of_impact`] reports where the hulls
/// touch and neither the hint nor a pair around the hulls' closest
/// vertices is within the contact distance.
#[derive(Copy, Clone, Debug, PartialEq, Eq)]
pub(crate) enum Touching {
    /// The BVH search's (a contact: the responses read its features).
    Searched,
    /// Also any pair GJK on the hulls names within the contact distance
    /// (the closest approach's runs, which need only the time, so that
    /// most screens need no search). Among tied pairs, say a box's face on
    /// a face, it may name another than the search would.
    Named,
}

/// [`mesh_time_of_impact`], with the choice of [`Touching`].
pub(crate) fn mesh_time_of_impact_with(
    query: &MeshCcdQuery<'_>,
    warm: WarmStart,
    scratch: &mut MeshCcdScratch,
    touching_pair: Touching,
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
            hulls,
            (touching_pair == Touching::Named).then_some(&result.simplex),
            s,
            hint,
            contract.contact_distance,
            &mut work,
        ),
        _ => None,
    };
    let reached = match touching {
        Some((found, measured)) => Reached { time: s, status: first_touch, pair: Some(found), measured },
        None => match search(
            &pair,
            &contract,
            kernel,
            options,
            s,
            hint,
            first_touch,
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

/// Whether the solids the two bodies sweep over the step stay more than
/// `target` apart (to the pair's rounding floor), checked only when the
/// bodies turn at least [`SPIN_SWEEP_MIN_TURN`] radians over it (where the
/// rate bounds, which grow with the spin, would take tiny steps).
///
/// A body turning with constant `ω` about its centre of mass keeps each
/// vertex's height `h` along the spin axis `k` and its distance `ρ` from
/// it: whatever the turn, the mesh stays inside the cylinder about the axis
/// through the moving centre with the vertices' extreme heights and
/// largest `ρ` (one pass over the vertices), whose support along a unit
/// direction `u` is `(u·k) h_max|min + |u − (u·k) k| ρ_max`. A body that
/// does not turn keeps its own box. The gap between the two along a fixed
/// `u` changes with the centres' relative velocity only, linearly: above
/// `target` at both ends of the step, it is above it over all of it.
/// Directions tried: the centre line at both ends, its part across each
/// spin axis, the spin axes, the world axes.
fn spin_swept_apart(pair: &PairMotion<'_>, target: Real) -> bool {
    let (a, b) = (pair.a, pair.b);
    let (wa, wb) = (a.motion.angular_velocity, b.motion.angular_velocity);
    if (wa.norm() + wb.norm()) * pair.duration < SPIN_SWEEP_MIN_TURN {
        return false;
    }
    let (region_a, region_b) = (SweptRegion::of(&a), SweptRegion::of(&b));
    let ends = [
        StepMotion::center_offset(a.motion, b.motion, 0.0),
        StepMotion::center_offset(a.motion, b.motion, pair.duration),
    ];
    let across = |region: &SweptRegion, d: &Vector| match region {
        SweptRegion::Cylinder { axis, .. } => d - axis * axis.dot(d),
        SweptRegion::Box { .. } => Vector::zeros(),
    };
    let axis = |region: &SweptRegion| match region {
        SweptRegion::Cylinder { axis, .. } => *axis,
        SweptRegion::Box { .. } => Vector::zeros(),
    };
    let mut directions = [Vector::zeros(); 11];
    directions[..2].copy_from_slice(&ends);
    for (k, end) in ends.iter().enumerate() {
        directions[2 + k] = across(&region_a, end);
        directions[4 + k] = across(&region_b, end);
    }
    directions[6] = axis(&region_a);
    directions[7] = axis(&region_b);
    for k in 0..3 {
        directions[8 + k] = Vector::ith(k, 1.0);
    }
    directions.iter().filter(|u| u.norm() > 0.0).any(|u| {
        // From a towards b.
        let u = u.normalize() * if u.dot(&ends[0]) < 0.0 { -1.0 } else { 1.0 };
        let reach = region_a.support(&u) + region_b.support(&-u);
        ends.iter().all(|end| u.dot(end) - reach > target + pair.floor)
    })
}

/// The region a body's mesh stays in over a step, about its centre of
/// mass (see [`spin_swept_apart`]).
enum SweptRegion {
    /// A turning body: the cylinder about its spin axis (unit) holding its
    /// vertices' heights `low..high` along it and distances up to `radius`
    /// from it.
    Cylinder { axis: Vector, low: Real, high: Real, radius: Real },
    /// A body that does not turn: its own box (its frame's `rotation`, the
    /// box's centre and half extents in that frame).
    Box { rotation: nalgebra::UnitQuaternion<Real>, center: Vector, half: Vector },
}

impl SweptRegion {
    fn of(body: &MovingMesh<'_>) -> SweptRegion {
        let rotation = body.motion.pose_at(0.0).rotation;
        let w = body.motion.angular_velocity;
        if w.norm() == 0.0 {
            let (lo, hi) = body.mesh.bounds();
            return SweptRegion::Box {
                rotation,
                center: (lo.coords + hi.coords) / 2.0,
                half: (hi - lo) / 2.0,
            };
        }
        let axis = w.normalize();
        // In the body's frame: the same heights and distances, one rotation.
        let local = rotation.inverse() * axis;
        let (mut low, mut high, mut radius_squared) = (Real::INFINITY, Real::NEG_INFINITY, 0.0 as Real);
        for v in body.mesh.vertices() {
            let h = local.dot(&v.coords);
            (low, high) = (low.min(h), high.max(h));
            radius_squared = radius_squared.max(v.coords.norm_squared() - h * h);
        }
        // A few ulps for the subtraction above.
        let radius = radius_squared.max(0.0).sqrt() * (1.0 + 4.0 * Real::EPSILON)
            + 4.0 * Real::EPSILON * body.mesh.radius();
        SweptRegion::Cylinder { axis, low, high, radius }
    }

    /// The farthest the region reaches along the unit direction `u`, from
    /// the centre of mass.
    fn support(&self, u: &Vector) -> Real {
        match self {
            SweptRegion::Cylinder { axis, low, high, radius } => {
                let along = u.dot(axis);
                along * if along > 0.0 { *high } else { *low } + (u - axis * along).norm() * radius
            }
            SweptRegion::Box { rotation, center, half } => {
                let local = rotation.inverse() * u;
                local.dot(center) + local.abs().dot(half)
            }
        }
    }
}

/// Where the advancement stopped: the time, how, and the triangle pair
/// there (the contact's, or the last limiting one when the iterations ran
/// out).
struct Reached {
    time: Real,
    status: CcdStatus,
    pair: Option<(usize, usize)>,
    /// That pair's distance at `time`, where it was measured there
    /// already (in `a`'s frame).
    measured: Option<MeshDistance>,
}

/// The two bodies of a query and what bounds their motion over the step.
struct PairMotion<'a> {
    a: MovingMesh<'a>,
    b: MovingMesh<'a>,
    /// The interval's length.
    duration: Real,
    /// The meshes' radii about their centres of mass.
    ra: Real,
    rb: Real,
    /// The head-on bound of any point's approach speed
    /// `|v_a − v_b| + |ω_a| r_a + |ω_b| r_b`.
    speed: Real,
    /// The rounding floor of the pair's distances.
    floor: Real,
}

impl<'a> PairMotion<'a> {
    fn of(a: &MovingMesh<'a>, b: &MovingMesh<'a>, duration: Real) -> PairMotion<'a> {
        let (ra, rb) = (a.mesh.radius(), b.mesh.radius());
        let speed = (a.motion.velocity - b.motion.velocity).norm()
            + a.motion.angular_velocity.norm() * ra
            + b.motion.angular_velocity.norm() * rb;
        // Rounding: distances are computed in a's frame from the difference
        // of the reference positions, so they round relative to the pair's
        // own scale; an integrated body's path can also jump by a few ulps
        // of its coordinates between steps.
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
        PairMotion { a: *a, b: *b, duration, ra, rb, speed, floor }
    }

    /// The pair's contact contract under `options` and `rule`: scaled by
    /// the smaller body (where the contact happens), floored by the
    /// rounding of the pair's coordinates.
    fn contract(&self, options: &CcdOptions, rule: ContactRule) -> ContactContract {
        ContactContract::of(options, rule, self.ra.min(self.rb), self.floor)
    }

    /// The distance between the bounding spheres at `s` (negative where
    /// they overlap).
    fn spheres_at(&self, s: Real) -> Real {
        StepMotion::center_offset(self.a.motion, self.b.motion, s).norm() - self.ra - self.rb
    }

    /// `b`'s pose in `a`'s frame at `s`.
    fn relative_pose(&self, s: Real) -> Pose {
        StepMotion::relative_pose(self.a.motion, self.b.motion, s)
    }
}

/// The bounding spheres' centres move linearly, so the smallest distance
/// between them over the step is exact: if it (or the carried
/// `lower_bound` less what the motion can close) stays above `target`, the
/// pair is apart, and this is a lower bound on its distance at the end.
fn spheres_apart(pair: &PairMotion<'_>, lower_bound: Option<Real>, target: Real) -> Option<Real> {
    let offset = StepMotion::center_offset(pair.a.motion, pair.b.motion, 0.0);
    let relative = pair.b.motion.velocity - pair.a.motion.velocity;
    let closest_approach = if relative.norm_squared() > 0.0 {
        (-offset.dot(&relative) / relative.norm_squared()).clamp(0.0, pair.duration)
    } else {
        0.0
    };
    let carried = lower_bound.unwrap_or(Real::NEG_INFINITY).max(pair.spheres_at(0.0));
    let closed = carried - pair.speed * pair.duration;
    (pair.spheres_at(closest_approach) > target || closed > target)
        .then(|| closed.max(pair.spheres_at(pair.duration)))
}

/// Where the hulls came within the contact distance: their closest
/// vertices and the direction between them (in `a`'s frame at that time).
type HullsTouch = ((usize, usize), Vector);

/// Conservative advancement on the hulls' gap: at time s, the gap along a
/// world direction n, less what the motion can close along n (the
/// centres' approach along n and each body's turn, at most |n × ω| r; the
/// rounding of the gap's dot products is within the floor), is safe until
/// it reaches the target. GJK stops early once the head-on bound is
/// beaten, or once the hulls come within the target. The advancement
/// stops where the hulls come within the contact distance (the meshes may
/// touch), or after [`HULL_ADVANCE_MAX_STEPS`] steps: the time reached,
/// and where the hulls touch. `None`: apart over the whole interval
/// (`result` says so, with its end bound). Sets `result`'s axis and hull
/// steps.
fn advance_on_hulls(
    pair: &PairMotion<'_>,
    contract: &ContactContract,
    result: &mut MeshCcdResult,
) -> Option<(Real, Option<HullsTouch>)> {
    let PairMotion { a, b, duration, speed, floor, .. } = *pair;
    let (target, contact_distance) = (contract.target, contract.contact_distance);
    let mut s = 0.0;
    let mut hull_steps = 0;
    let mut hulls_touch = None;
    while hull_steps < HULL_ADVANCE_MAX_STEPS {
        let rotation_a = a.motion.rotation_at(s);
        let rest = duration - s;
        let gap = hull_gap_from(
            a.mesh,
            b.mesh,
            &pair.relative_pose(s),
            result.axis.map(|axis| rotation_a.inverse_transform_vector(&axis)),
            (target + floor, target + floor + speed * rest),
            &mut result.simplex,
        );
        let Some(local) = gap.axis else { break };
        let n = rotation_a * local;
        result.axis = Some(n);
        let margin = gap.lower - floor - target;
        // The gap along n closes at most at the centres' approach along it
        // plus each body's head-on turning rate |n × ω| r; and, to second
        // order, over a horizon of a few such steps, at the centres'
        // approach plus each hull's rise over the horizon (the chord of its
        // support along the turning direction, in the frame that lasts
        // longest, `GapMotion`): the longer step. Where the second-order
        // bound outlasts its horizon, a horizon HULL_HORIZON_STEPS times
        // longer is tried, up to the interval's end: a pair closing far
        // slower than the head-on rate takes steps of its own pace, not of
        // four head-on steps.
        let approach = (a.motion.velocity - b.motion.velocity).dot(&n);
        let head_on =
            |body: &MovingMesh<'_>| n.cross(&body.motion.angular_velocity).norm() * body.mesh.radius();
        let closing = approach + head_on(&a) + head_on(&b);
        let linear = match (margin > 0.0, closing > 0.0) {
            (false, _) => 0.0,
            (true, true) => margin / closing,
            (true, false) => Real::INFINITY,
        };
        let (mut step, mut apart, mut at_end) = (linear, linear > rest, -closing * rest);
        if !apart {
            let mut horizon = rest.min(HULL_HORIZON_STEPS * linear);
            let gap_at = GapMotion::at(pair, s, n);
            loop {
                let mut outlasts = false;
                for frame in gap_at.frames() {
                    let (rate, curvature) = gap_at.bound(frame, horizon);
                    let quadratic = first_root(margin, rate, curvature);
                    step = step.max(quadratic.min(horizon));
                    if horizon == rest && quadratic > rest {
                        apart = true;
                        at_end = at_end.max(rate * rest - curvature * rest * rest / 2.0);
                    }
                    outlasts |= quadratic > horizon;
                }
                if !(outlasts && horizon > 0.0 && horizon < rest) {
                    break;
                }
                horizon = rest.min(HULL_HORIZON_STEPS * horizon);
            }
        }
        if apart {
            // Apart until the interval's end.
            if hull_steps > 0 {
                result.status = CcdStatus::Separated;
            }
            result.hull_steps = hull_steps;
            result.end_lower_bound = (gap.lower - floor + at_end).max(pair.spheres_at(duration));
            return None;
        }
        if margin < contact_distance - target {
            hulls_touch = gap.support.map(|vertices| (vertices, local));
            break;
        }
        s += step;
        hull_steps += 1;
    }
    result.hull_steps = hull_steps;
    Some((s, hulls_touch))
}

/// The gap between the two hulls along a unit direction `n` (from `a`
/// towards `b`) at `s`, as it moves over a horizon, to second order, with
/// the direction fixed in the world or turning with either body: any
/// direction's gap is at most the hulls' distance, so each frame's bound
/// is a lower bound of it, and the advancement takes the frame that lasts
/// longest.
///
/// In a frame turning at `Ω` the direction is `m(t) = exp(Ω t) n`, and
/// the gap `m·(c_b − c_a) − h_a(m) − h_b(−m)`:
/// - The centres' part moves at `(Ω × m)·Δc + m·Δv`, and that rate
///   changes at most at `|Ω × n| (|Ω| |Δc| + 2 |Δv|)`.
/// - A vertex at offset `u` of a body turning at `ω` rises along `m` at
///   `((Ω − ω) × m)·u`, a rate that changes at most at `|Ω − ω| ρ (|Ω × n|
///   + |ω|)` (`|ω × n| |ω| ρ` in the world frame, where `m` stays put; 0
///   in the body's own frame, where its hull stands still). The highest
///   height at `s + t` is at most the hull's support along the direction
///   tilted by `t (Ω − ω) × m`, less its support along `m`, plus that
///   curvature's term: the tilted support's lines have a convex upper
///   envelope `E(t)`, `E(0) = 0`, which stays below its chord over the
///   horizon, so the rate is the chord's slope, from two exact support
///   lookups ([`TriMesh::farthest_vertex`]). Near a round mesh's top that
///   is the top vertex's own rate until a neighbour can overtake it; it
///   never exceeds the head-on `|(Ω − ω) × m| ρ` (ρ the mesh's radius).
///
/// The world frame suits a pair whose closest features both turn; a body's
/// own frame suits a face of that body turning under the other's vertex,
/// where the world's fixed direction sees the face's rising corner and not
/// the point below the vertex.
struct GapMotion<'p> {
    pair: &'p PairMotion<'p>,
    n: Vector,
    /// The centres' offset `c_b − c_a` and relative velocity `v_b − v_a`.
    offset: Vector,
    velocity: Vector,
    /// When `a`'s and `b`'s hulls are wanted: the time, each body's
    /// rotation then and its support along `n` (`a`) or `−n` (`b`), in its
    /// own frame, found at the first need (a body that keeps its place in
    /// every frame, as both do where neither turns, needs none).
    s: Real,
    tops: [std::cell::Cell<Option<HullTop>>; 2],
}

/// A body's rotation at a time, and its hull's support along a direction
/// then (in its own frame).
type HullTop = (nalgebra::UnitQuaternion<Real>, Real);

impl<'p> GapMotion<'p> {
    fn at(pair: &'p PairMotion<'p>, s: Real, n: Vector) -> GapMotion<'p> {
        GapMotion {
            pair,
            n,
            offset: StepMotion::center_offset(pair.a.motion, pair.b.motion, s),
            velocity: pair.b.motion.velocity - pair.a.motion.velocity,
            s,
            tops: Default::default(),
        }
    }

    /// The frames' angular velocities: the world's, and each turning
    /// body's (once).
    fn frames(&self) -> impl Iterator<Item = Vector> {
        let (wa, wb) = (self.pair.a.motion.angular_velocity, self.pair.b.motion.angular_velocity);
        let zero = Vector::zeros();
        [Some(zero), (wa != zero).then_some(wa), (wb != zero && wb != wa).then_some(wb)].into_iter().flatten()
    }

    /// The gap's rate at `s` and the bound of its change over `[s, s +
    /// horizon]` in the frame turning at `frame`: the gap stays above its
    /// value at `s` plus `rate t − curvature t² / 2` (see the type).
    fn bound(&self, frame: Vector, horizon: Real) -> (Real, Real) {
        let n = self.n;
        let turn = frame.cross(&n);
        let centres_rate = turn.dot(&self.offset) + n.dot(&self.velocity);
        let centres_curvature = turn.norm()
            * (frame.norm() * (self.offset.norm() + self.velocity.norm() * horizon)
                + 2.0 * self.velocity.norm());
        let (rise_a, curvature_a) = self.rise(0, &frame, horizon);
        let (rise_b, curvature_b) = self.rise(1, &frame, horizon);
        (centres_rate - rise_a - rise_b, centres_curvature + curvature_a + curvature_b)
    }

    /// How fast the highest point of body `k` (0: `a`, along `n`; 1: `b`,
    /// along `−n`; the direction turning at `frame`) can rise over the
    /// horizon: the chord's rate and the curvature (see the type).
    fn rise(&self, k: usize, frame: &Vector, horizon: Real) -> (Real, Real) {
        let (body, direction) = if k == 0 { (&self.pair.a, self.n) } else { (&self.pair.b, -self.n) };
        let direction = &direction;
        let omega = body.motion.angular_velocity;
        let relative = frame - omega;
        let radius = body.mesh.radius();
        let turning = if *frame == Vector::zeros() { omega.cross(direction).norm() } else { relative.norm() };
        let curvature = radius * (relative.norm() * frame.cross(direction).norm() + turning * omega.norm());
        // Where the vertices' rates are all 0 at `s` (the body keeps its
        // place in the frame, or turns about the direction), only the
        // curvature is left: a turning frame soon tilts the direction.
        let across = relative.cross(direction);
        let sweep = across.norm();
        if !(sweep > 0.0 && horizon > 0.0) {
            return (0.0, curvature);
        }
        let (rotation, top) = self.tops[k].get().unwrap_or_else(|| {
            let rotation = body.motion.rotation_at(self.s);
            let found = (rotation, support(body.mesh, &rotation.inverse_transform_vector(direction)));
            self.tops[k].set(Some(found));
            found
        });
        let tilted = rotation.inverse_transform_vector(&(direction + across * horizon));
        // The rounding of the two lookups' dot products and of the tilted
        // direction: a few ulps of the radius times the directions' lengths.
        let rounding = SUPPORT_ROUNDING_ULPS * Real::EPSILON * radius * (1.0 + sweep * horizon);
        let chord = (support(body.mesh, &tilted) - top + rounding) / horizon;
        (chord.min(sweep * radius), curvature)
    }
}

/// A mesh's support along a direction (its own frame): the largest dot
/// product of a vertex with it, exact (the farthest vertex's).
fn support(mesh: &TriMesh, direction: &Vector) -> Real {
    direction.dot(&mesh.vertices()[mesh.farthest_vertex(direction)].coords)
}

/// The slack of [`GapMotion`]'s support lookups, in ulps of the radius
/// times the lengths of their directions: `16` (a dot product of three
/// terms, and the tilted direction, round by a few).
pub(crate) const SUPPORT_ROUNDING_ULPS: Real = 16.0;

/// The hulls' second-order bound looks this many of the head-on bound's
/// steps ahead first, and then this many times farther each time it
/// outlasts its horizon: `4` (its rates, which must hold over the
/// horizon, grow with it).
pub(crate) const HULL_HORIZON_STEPS: Real = 4.0;

/// At `s`, where the hulls touch: the pair's last closest triangles (the
/// `hint`), or else the first triangle pair around the hulls' closest
/// vertices, if either is within the contact distance; with the hull
/// gap's last `simplex` ([`Touching::Named`]), also the triangles holding
/// it (GJK on the hulls at `s`, stopped once they came within the
/// target) and, for convex meshes, the closest pair by GJK run to its
/// certificate ([`convex_measure`]). The pair, and its distance where it
/// was measured whole (not by [`first_within`]'s kernel).
fn pair_at_touching_hulls(
    pair: &PairMotion<'_>,
    ((va, vb), axis): HullsTouch,
    simplex: Option<&WarmSimplex>,
    s: Real,
    hint: Option<(usize, usize)>,
    contact_distance: Real,
    work: &mut StepWork,
) -> Option<((usize, usize), Option<MeshDistance>)> {
    let (a, b) = (pair.a.mesh, pair.b.mesh);
    let pos_ab = pair.relative_pose(s);
    let within = |found: MeshDistance| {
        (found.distance <= contact_distance).then_some(((found.triangle_a, found.triangle_b), Some(found)))
    };
    let distance_of = |(i, j): (usize, usize)| triangle_pair_distance(a, i, b, j, &pos_ab);
    work.triangle_pairs += usize::from(hint.is_some());
    hint.map(distance_of)
        .and_then(within)
        .or_else(|| {
            let around = first_within((a, va), (b, vb), &pos_ab, Some(axis), contact_distance);
            work.triangle_pairs += around.evaluated;
            around.found.filter(|&(d, _)| d <= contact_distance).map(|(_, found)| (found, None))
        })
        .or_else(|| {
            let named = simplex?.triangles(a, b).filter(|&found| Some(found) != hint);
            work.triangle_pairs += usize::from(named.is_some());
            named.map(distance_of).and_then(within).or_else(|| within(convex_measure(a, b, &pos_ab)?))
        })
}

/// The BVH search from `s` (see the module): the time, status and
/// triangle pair of the contact, or of the time reached when the
/// iterations ran out ([`CcdStatus::OutOfIterations`]). `None`: apart
/// until the interval's end (`result` says so, with its end bound and
/// hint).
#[allow(clippy::too_many_arguments)]
fn search(
    pair: &PairMotion<'_>,
    contract: &ContactContract,
    kernel: DistanceKernel,
    options: &CcdOptions,
    mut s: Real,
    mut hint: Option<(usize, usize)>,
    first_touch: CcdStatus,
    result: &mut MeshCcdResult,
    scratch: &mut MeshCcdScratch,
    work: &mut StepWork,
) -> Option<Reached> {
    let PairMotion { a, b, duration, speed, .. } = *pair;
    let (target, contact_distance) = (contract.target, contract.contact_distance);
    let relative_velocity = b.motion.velocity - a.motion.velocity;
    let (omega_a, omega_b) = (a.motion.angular_velocity, b.motion.angular_velocity);
    // A step shorter than this proves nothing a triangle pair outside the
    // contact distance could not (see `mesh_search.rs`).
    let min_step = if speed > 0.0 { (contact_distance - target) / speed } else { Real::INFINITY };
    let meshes = SearchMeshes { a: a.mesh, b: b.mesh, kernel };
    scratch.front.reset();
    for iteration in 0..options.max_iterations.max(1) {
        if iteration == SPIN_SWEEP_AFTER_ITERATIONS {
            // The spin-swept bounds start now: from the roots again, so
            // that whole subtrees can be settled by them.
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

#[cfg(test)]
mod tests {
    use super::*;
    use crate::math::Point;
    use crate::mesh::{box_mesh, icosphere, torus};
    use crate::samples::Rng;

    #[test]
    fn the_gap_along_a_turning_direction_stays_above_each_frames_bound() {
        // Pairs of boxes, icospheres (12 to 642 vertices), a flat
        // ellipsoid and a torus (642 and 1,024 vertices, far from round;
        // the torus not convex), moving at up to 3 and spinning at up to
        // 30 rad/s (in one pair in three, one body does not turn; in one
        // in eight, a turns about the direction in b's frame), a random
        // direction, horizons of 1e-6 to 0.1: in each frame (the
        // world's, each turning body's), the gap along the direction
        // turning with it, sampled over the horizon, never falls below its
        // value at the start plus the frame's rate and curvature terms.
        // And the world frame's bound is the hulls' own pace, not the
        // head-on one: over horizons up to 1e-3 the rise of a box or an
        // icosphere is below 3/4 of its head-on rate for most cases, and
        // that of the round icospheres (162 and 642 vertices) below 1/4.
        let ellipsoid = {
            let round = icosphere(1.0, 3).unwrap();
            let squashed =
                round.vertices().iter().map(|v| Point::new(0.6 * v.x, 0.3 * v.y, 0.1 * v.z)).collect();
            TriMesh::new(squashed, round.triangles().to_vec()).unwrap()
        };
        let meshes = [
            box_mesh(&Vector::new(0.3, 0.2, 0.25)).unwrap(),
            icosphere(0.3, 0).unwrap(),
            icosphere(0.5, 2).unwrap(),
            icosphere(0.4, 3).unwrap(),
            ellipsoid,
            torus(0.5, 0.15, 32, 32).unwrap(),
        ];
        let (boxes_and_icospheres, round) = (0..4, 2..4);
        let mut rng = Rng::new(23);
        let (mut checked, mut tighter, mut frames) = ([0; 2], [0; 2], 0);
        for case in 0..1200 {
            let kinds = (case % meshes.len(), (case / meshes.len()) % meshes.len());
            let (mesh_a, mesh_b) = (&meshes[kinds.0], &meshes[kinds.1]);
            let spin =
                |still: bool, rng: &mut Rng| if still { Vector::zeros() } else { rng.in_unit_ball() * 30.0 };
            // (One in eight: along an axis, for the case below to be exact.)
            let n = if case % 8 == 5 { Vector::ith(case % 3, 1.0) } else { rng.unit_vector() };
            let mut motion_a = StepMotion::new(
                Pose::new(rng.in_unit_ball(), rng.in_unit_ball() * 3.0),
                rng.in_unit_ball() * 3.0,
                spin(case % 3 == 1, &mut rng),
            );
            let motion_b = StepMotion::new(
                Pose::new(rng.in_unit_ball() * 4.0, rng.in_unit_ball() * 3.0),
                rng.in_unit_ball() * 3.0,
                spin(case % 3 == 2, &mut rng),
            );
            if case % 8 == 5 {
                // In b's frame, a turns about n: its vertices' rates are
                // exactly 0 at the start, not after (the frame tilts n).
                motion_a.angular_velocity = motion_b.angular_velocity + n * 5.0;
            }
            let (a, b) = (
                MovingMesh { mesh: mesh_a, motion: &motion_a },
                MovingMesh { mesh: mesh_b, motion: &motion_b },
            );
            let pair = PairMotion::of(&a, &b, 1.0);
            let (s, horizon) = (rng.uniform() * 0.1, Real::powf(10.0, -6.0 + 5.0 * rng.uniform()));
            let gap_motion = GapMotion::at(&pair, s, n);
            // The gap along m at time u: the lowest of b's vertices along m
            // less the highest of a's.
            let gap = |m: &Vector, u: Real| {
                let heights = |body: &MovingMesh<'_>| {
                    let pose = body.motion.pose_at(u);
                    body.mesh.vertices().iter().map(|v| m.dot(&(pose * v).coords)).collect::<Vec<Real>>()
                };
                let lowest_b = heights(&b).into_iter().fold(Real::INFINITY, Real::min);
                lowest_b - heights(&a).into_iter().fold(Real::NEG_INFINITY, Real::max)
            };
            let start = gap(&n, s);
            for frame in gap_motion.frames() {
                frames += 1;
                let (rate, curvature) = gap_motion.bound(frame, horizon);
                for k in 0..=100 {
                    let t = horizon * k as Real / 100.0;
                    let m = nalgebra::UnitQuaternion::from_scaled_axis(frame * t) * n;
                    let bound = start + rate * t - curvature * t * t / 2.0;
                    let g = gap(&m, s + t);
                    assert!(g >= bound - 1e-12, "case {case}, frame {frame:?}: gap {g} at {t} below {bound}");
                }
                // Each hull's highest point alone (from its centre), along
                // m for a and −m for b.
                for (k, body, sign) in [(0, &a, 1.0), (1, &b, -1.0)] {
                    let direction = n * sign;
                    let (rise, curvature) = gap_motion.rise(k, &frame, horizon);
                    let height = |t: Real| {
                        let m = nalgebra::UnitQuaternion::from_scaled_axis(frame * t) * direction;
                        let pose = body.motion.pose_at(s + t);
                        let centre = pose.translation.vector;
                        body.mesh
                            .vertices()
                            .iter()
                            .map(|v| m.dot(&((pose * v).coords - centre)))
                            .fold(Real::NEG_INFINITY, Real::max)
                    };
                    let top = height(0.0);
                    for j in 0..=100 {
                        let t = horizon * j as Real / 100.0;
                        let bound = top + rise * t + curvature * t * t / 2.0;
                        let h = height(t);
                        assert!(
                            h <= bound + 1e-12,
                            "case {case}, body {k}, frame {frame:?}: {h} at {t} above {bound}"
                        );
                    }
                }
            }
            if horizon <= 1e-3 {
                let (rise, _) = gap_motion.rise(0, &Vector::zeros(), horizon);
                let head_on = n.cross(&motion_a.angular_velocity).norm() * mesh_a.radius();
                for (k, (kinds_checked, fraction)) in
                    [(boxes_and_icospheres.clone(), 0.75), (round.clone(), 0.25)].into_iter().enumerate()
                {
                    if kinds_checked.contains(&kinds.0) && head_on > 0.0 {
                        checked[k] += 1;
                        tighter[k] += usize::from(rise < fraction * head_on);
                    }
                }
            }
        }
        assert!(frames > 2 * 1200, "{frames} frames");
        for k in 0..2 {
            assert!(2 * tighter[k] > checked[k], "tighter {tighter:?} of {checked:?}");
        }
    }
}

//! Conservative advancement on the hulls' gap, before any BVH search, and
//! the triangle pair where the hulls touch.

use super::contact::ContactContract;
use super::convex_measure::convex_measure;
use super::hull_gap::{first_within, hull_gap_from, WarmSimplex};
use super::mesh_bound::first_root;
use super::mesh_search::StepWork;
use super::options::CcdStatus;
use super::pair_motion::PairMotion;
use super::query::{MeshCcdResult, MovingMesh};
use crate::math::{Real, Vector};
use crate::mesh::distance::triangle_pair_distance;
use crate::mesh::{MeshDistance, TriMesh};
use crate::motion::StepMotion;

/// The most advancement steps taken on the hulls' gap alone before the BVH
/// search takes over (see the module). Each costs one warm-started GJK (a
/// microsecond or less), a search tens of them; spinning bodies close far
/// slower than their bound `|n × ω| r` says, so the steps shrink slowly
/// and a few dozen of them still spare most queries the search
/// (`docs/benchmarks-history.md`).
pub(crate) const HULL_ADVANCE_MAX_STEPS: usize = 64;

/// Where the hulls came within the contact distance: their closest
/// vertices and the direction between them (in `a`'s frame at that time).
pub(super) type HullsTouch = ((usize, usize), Vector);

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
pub(super) fn advance_on_hulls(
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
pub(super) struct GapMotion<'p> {
    pub(super) pair: &'p PairMotion<'p>,
    pub(super) n: Vector,
    /// The centres' offset `c_b − c_a` and relative velocity `v_b − v_a`.
    pub(super) offset: Vector,
    pub(super) velocity: Vector,
    /// When `a`'s and `b`'s hulls are wanted: the time, each body's
    /// rotation then and its support along `n` (`a`) or `−n` (`b`), in its
    /// own frame, found at the first need (a body that keeps its place in
    /// every frame, as both do where neither turns, needs none).
    pub(super) s: Real,
    pub(super) tops: [std::cell::Cell<Option<HullTop>>; 2],
}

/// A body's rotation at a time, and its hull's support along a direction
/// then (in its own frame).
pub(super) type HullTop = (nalgebra::UnitQuaternion<Real>, Real);

impl<'p> GapMotion<'p> {
    pub(super) fn at(pair: &'p PairMotion<'p>, s: Real, n: Vector) -> GapMotion<'p> {
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
    pub(super) fn frames(&self) -> impl Iterator<Item = Vector> {
        let (wa, wb) = (self.pair.a.motion.angular_velocity, self.pair.b.motion.angular_velocity);
        let zero = Vector::zeros();
        [Some(zero), (wa != zero).then_some(wa), (wb != zero && wb != wa).then_some(wb)].into_iter().flatten()
    }

    /// The gap's rate at `s` and the bound of its change over `[s, s +
    /// horizon]` in the frame turning at `frame`: the gap stays above its
    /// value at `s` plus `rate t − curvature t² / 2` (see the type).
    pub(super) fn bound(&self, frame: Vector, horizon: Real) -> (Real, Real) {
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
    pub(super) fn rise(&self, k: usize, frame: &Vector, horizon: Real) -> (Real, Real) {
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
pub(super) fn support(mesh: &TriMesh, direction: &Vector) -> Real {
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
pub(super) fn pair_at_touching_hulls(
    pair: &PairMotion<'_>,
    (s, ((va, vb), axis)): (Real, HullsTouch),
    simplex: Option<&WarmSimplex>,
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

#[cfg(test)]
mod tests {
    use super::*;
    use crate::math::Point;
    use crate::math::Pose;
    use crate::mesh::{box_mesh, icosphere, torus};
    use crate::samples::Rng;

    #[test]
    pub(super) fn the_gap_along_a_turning_direction_stays_above_each_frames_bound() {
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

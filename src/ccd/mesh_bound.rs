//! The bounds of a rigid mesh pair's advancement step: for a BVH node pair
//! or a triangle pair, a time before which it cannot come within `target`,
//! from a second-order bound of the motion along a separating direction.
//! The search that combines them is `mesh_search.rs`.
//!
//! ## The bound
//! A body turns with constant `ω` about its centre of mass, which moves with
//! constant `v`. Fix a unit direction `n` (in the world). A point at offset
//! `q(t)` from its body's centre moves along `n` at the rate
//! `n·v + n·(ω × q) = n·v + (n × ω)·q(t)`, and since `q` turns at `|ω|`,
//! `|d/dt (n × ω)·q| = |(n × ω)·(ω × q)| ≤ |n × ω| |ω| |q|`. So
//!
//! ```text
//! n·p(t) ≥ n·p(0) + t [n·v + (n × ω)·q(0)] − t² |n × ω| |ω| |q| / 2
//! ```
//!
//! and the same from above. Over a vertex set (a triangle, whose support
//! along `n` is at a vertex), minimum and maximum separately: the gap
//! between the two sets along `n`, `G(t) = min_b n·p − max_a n·p`, stays above
//!
//! ```text
//! G(0) + g t − M t² / 2,
//! g = n·(v_b − v_a) + min_j (n × ω_b)·q_bj − max_i (n × ω_a)·q_ai,
//! M = |n × ω_a| |ω_a| r_a + |n × ω_b| |ω_b| r_b ,
//! ```
//!
//! and the pair stays farther than `target` until the first root of
//! `G(0) − target + g t − M t²/2`. A separating distance therefore shrinks
//! only at the rate the motion really has along it (a spin about `n`, or a
//! slide across it, costs only second order), instead of the head-on bound
//! `|Δv| + |ω_a| r_a + |ω_b| r_b` of every point: the advancement needs far
//! fewer steps on tumbling bodies.
//!
//! Per triangle pair, `n` is the direction between its closest points (the
//! exact kernel), `G(0)` is taken from the vertices (never from the distance,
//! which rounding may separate from `n`), and the head-on bound
//! `(d − target) / (|Δv| + |ω_a| r_a + |ω_b| r_b)` backs it up; with the DyOP
//! kernel, which gives no direction, the head-on bound alone is used. The
//! full bound takes the gap vertex pair by vertex pair (each pair's own
//! height and rate, the least of the nine roots), so that a vertex that
//! swings fast but lies far above the closest one counts only once it can
//! have come down.
//!
//! ## A turning slab
//! A slab fixed in the world loses at first order to each closest
//! feature's tilt: a face or an edge turning across `n` brings one of its
//! corners down along `n` at `|ω| ℓ` while the distance itself, near a
//! closest approach, hardly changes. Advancing to a target a hair below a
//! closest approach (as the closest-approach proofs do) then takes a step
//! per `hair / (|ω| ℓ)`: thousands. The full bound therefore also takes
//! the slab along `n` in a frame turning at a constant `Ω` about a point
//! `O` moving at a constant velocity (any such frame gives a valid slab:
//! it is the world slab along a direction that turns), with `Ω` chosen so
//! that neither closest feature tilts across `n` in it: the face's body's
//! `ω` where one feature is a face (or an edge against a vertex); for two
//! edges `e_a`, `e_b`, the least `Ω` with `Ω·(e_k × n) = ω_k·(e_k × n)` for
//! both (a 2 × 2 system; none for edges within [`PARALLEL_EDGES`](super::posed_pair::PARALLEL_EDGES) of
//! parallel). Each vertex's height along `n` in that frame then moves at
//! the rate of the distance itself, and its second derivative is bounded
//! by the rotating frame's accelerations,
//!
//! ```text
//! |ω|² |r| + 2 |Ω × n| |u| + |Ω| |Ω × n| (|q| + H |u|),
//! ```
//!
//! with `r` the vertex's offset from its body's centre, `q` its offset from
//! `O`, `u` a bound of its speed relative to `O` (`|v − v_O| + |ω| |r|`) and
//! `H` the horizon (the bound holds up to it). The frame's normal turns
//! about `Ω`, so at the constant rate `|Ω × n|`: only that much of the
//! frame's turning reaches the height. Where the frame turns with a body
//! (`Ω` is its `ω`: a face's, or an edge's against a vertex), each of that
//! body's vertices keeps its height above the body's centre `c` in the
//! frame, and its height moves as the centre's does, which moves in a line:
//!
//! ```text
//! |Ω| |Ω × n| (|c − O| + H |v_c − v_O|) + 2 |Ω × n| |v_c − v_O|,
//! ```
//!
//! the same for every vertex of the body, without the spin's `|ω|² |r|`
//! and `|ω| |r|` of a large body (the gear ring of `pybullet_data`, in
//! millimetres) far from its centre; the lesser of the two is taken. Per
//! vertex pair, the least root as above; the full bound is the longest of
//! the three.
//!
//! Per BVH node pair, the node is bounded both ways: as its bounding sphere
//! along the line joining the two node centres (the sphere only moves with
//! its centre: spread term 0, gap `|ΔC| − ρ_a − ρ_b`), and as its box cut by
//! the sphere (support `min(Σ|e_k n_k|, ρ)`, a larger gap but a spread
//! `|n × ω| ρ` added to the rate, the box turning) along whichever of the
//! centre line and the six box face axes separates the boxes most (a flat
//! node such as a wall is separated along its thin axis, not along an
//! oblique centre line). Where that is still short and one node is a leaf
//! more than [`LOPSIDED_RATIO`] times the other's radius, the box slab is
//! also tried along the direction from the leaf's box's closest point to
//! the small node's centre (a long sliver beside a small node off its
//! edge: neither the centre line nor a face axis sees the gap there). The
//! longer of the times is a lower bound for every triangle pair below the
//! node. Where even that falls short of what the search needs, the search
//! (`mesh_search.rs`) bounds such a pair once more as the small node's ball
//! against each of the leaf's triangles in the frame turning with them
//! ([`PosedPair::ball_time`](super::posed_pair::PosedPair::ball_time)): a
//! box turns with its body, and a long leaf's box sweeps its length times
//! the spin across any slab fixed in the world, where a ball, whose gap is
//! its centre's less its radius, loses only what the distance does.
//!
//! Where a pair of small nodes (up to
//! [`SLAB_TRIANGLES`](crate::mesh::distance::SLAB_TRIANGLES) triangles each)
//! is still short, it is also bounded over its triangles' vertices along
//! the line of its centres ([`vertex_slab_time`]): the bound above,
//! minimum and maximum apart over each vertex set. A box holds a curved
//! patch's empty space and turns with its body; the vertices do not. On
//! the KUKA links 1 and 7 passing 0.06 apart it takes 45% off the node
//! pairs of the closest approach's proof (11,140 → 6,130).
//!
//! A pair of leaves is bounded as a whole before its triangle pairs
//! ([`PosedPair::leaves_time`](super::posed_pair::PosedPair::leaves_time)):
//! the turning slab of the triangle pair whose centroids are nearest, its
//! direction, origin and frame kept, over every vertex of both leaves
//! (vertex pair by vertex pair, as for a triangle pair; the slab between
//! two vertex sets bounds the distance between every triangle spanned by
//! them). Two flat patches facing each other are bounded by it about as
//! tightly as by each triangle pair's own slab.

use crate::math::{Pose, Real, Vector};
use crate::mesh::{BvhNode, TriMesh};
use nalgebra::Matrix3;

/// The motion of `b` relative to `a`, in `a`'s frame at the current time.
#[derive(Copy, Clone, Debug)]
pub(crate) struct PairFrame {
    /// `b`'s pose in `a`'s frame.
    pub pos_ab: Pose,
    /// The rotation part of `pos_ab` as a matrix.
    pub rotation: Matrix3<Real>,
    /// `v_b − v_a`, in `a`'s frame.
    pub velocity: Vector,
    /// `ω_a`, in `a`'s frame.
    pub omega_a: Vector,
    /// `ω_b`, in `a`'s frame.
    pub omega_b: Vector,
    /// `|v_b − v_a|`, `|ω_a|`, `|ω_b|`.
    pub speed: Real,
    pub spin_a: Real,
    pub spin_b: Real,
}

impl PairFrame {
    /// The frame from the pose of `b` in `a`'s frame, `a`'s rotation in the
    /// world, and the world velocities.
    pub fn new(
        pos_ab: Pose,
        rotation_a: &nalgebra::UnitQuaternion<Real>,
        relative_velocity: &Vector,
        omega_a: &Vector,
        omega_b: &Vector,
    ) -> PairFrame {
        let to_a = |v: &Vector| rotation_a.inverse_transform_vector(v);
        PairFrame {
            pos_ab,
            rotation: pos_ab.rotation.to_rotation_matrix().into_inner(),
            velocity: to_a(relative_velocity),
            omega_a: to_a(omega_a),
            omega_b: to_a(omega_b),
            speed: relative_velocity.norm(),
            spin_a: omega_a.norm(),
            spin_b: omega_b.norm(),
        }
    }

    /// The head-on closing speed of points within `ra` and `rb` of the centres.
    #[inline]
    pub fn head_on_speed(&self, ra: Real, rb: Real) -> Real {
        self.speed + self.spin_a * ra + self.spin_b * rb
    }
}

/// The first time `t > 0` at which `gap + rate t − curvature t² / 2`
/// reaches 0 (`gap > 0`; `curvature ≥ 0`), infinite if never; 0 if
/// `gap ≤ 0`.
#[inline]
pub(crate) fn first_root(gap: Real, rate: Real, curvature: Real) -> Real {
    if gap <= 0.0 {
        return 0.0;
    }
    if curvature <= 0.0 {
        return if rate >= 0.0 { Real::INFINITY } else { gap / -rate };
    }
    let root = (rate * rate + 2.0 * curvature * gap).sqrt();
    // The two forms avoid cancellation for either sign of the rate.
    if rate >= 0.0 {
        (rate + root) / curvature
    } else {
        2.0 * gap / (root - rate)
    }
}

/// A node pair's bound is also sought among the spin-swept regions (see
/// `node_pair_time`) once the two bodies together turn at least this many
/// radians over the rest of the interval: then the rate bounds, which grow
/// with the spin, are short. `1.0`.
pub(crate) const SPIN_SWEEP_MIN_TURN: Real = 1.0;

/// ... and only while the rate bounds give less than this fraction of the
/// rest of the interval (a spin-swept region is far larger than the node,
/// so it helps only where the rates leave almost nothing). `1/64`.
pub(crate) const SPIN_SWEEP_MAX_RATE_FRACTION: Real = 1.0 / 64.0;

/// A node pair is bounded also along a box's closest-point direction to
/// the other node's centre only where that box is a leaf's, more than this
/// many times the other node's radius: `2`. Elsewhere a pair that falls
/// short is opened, splitting its larger node, and the bunnies' time of
/// impact took 10–13% longer with the slabs from both boxes tried on every
/// pair.
pub(crate) const LOPSIDED_RATIO: Real = 2.0;

/// ... and only in a query that has already taken this many advancement
/// steps (a query that advances well needs no more; a fast spin takes
/// thousands of tiny steps). `32`: the tumbling benchmark's queries take
/// 9 to 16.
pub(crate) const SPIN_SWEEP_AFTER_ITERATIONS: usize = 32;

/// A lower bound on the time before any triangle pair below nodes `na` and
/// `nb` comes within `target`, and a lower bound on their distance now.
/// The box face axes are tried only when the centre line does not give
/// `needed`; the spin-swept bound only when neither does and the bodies
/// turn far over the `horizon` (the rest of the interval; `0` leaves the
/// spin-swept bound out).
///
/// The spin-swept bound: a body turning with constant `ω` about its centre
/// of mass keeps each point's distance to the spin axis and its coordinate
/// along it, so everything below a node stays, at every time, inside a
/// cylinder about the axis through the moving centre of mass (axial
/// coordinates `k·q ± ρ`, radius `|q − (k·q) k| + ρ`, for a node of centre
/// `q` and radius `ρ`); a body that does not turn keeps its box. The gap
/// between the two regions along a fixed direction changes only with the
/// centres' relative velocity, linearly: if it exceeds `target` at both ends
/// of the horizon, the pair stays apart over all of it, however fast it
/// spins.
#[inline]
pub(crate) fn node_pair_time(
    na: &BvhNode,
    nb: &BvhNode,
    frame: &PairFrame,
    target: Real,
    (needed, horizon): (Real, Real),
) -> (Real, Real) {
    let bounds = node_pair_bounds(na, nb, frame, target, (needed, horizon));
    (bounds.sphere_time.max(bounds.box_time).max(bounds.spin_time), bounds.gap)
}

/// The bounds of a node pair (see [`node_pair_time`]).
#[derive(Copy, Clone, Debug)]
struct NodeBounds {
    /// The spheres' bound, along the line of centres.
    sphere_time: Real,
    /// The boxes' bound, along `box_direction` (a's frame, from a to b).
    box_time: Real,
    #[cfg_attr(not(test), allow(dead_code))]
    box_direction: Vector,
    /// The spin-swept bound: the horizon, or 0.
    spin_time: Real,
    /// A lower bound on the distance now.
    gap: Real,
}

/// The support along the unit `u` of the cylinder swept by a node of
/// centre `q` and radius `radius` turning about the unit axis `k` through
/// its body's centre of mass.
#[inline]
fn swept_support(k: &Vector, q: &Vector, radius: Real, u: &Vector) -> Real {
    let along = k.dot(q);
    let across = (q - k * along).norm() + radius;
    let c = k.dot(u);
    c * along + c.abs() * radius + (1.0 - c * c).max(0.0).sqrt() * across
}

/// A node pair set up for its bounds, in a's frame: the node centres as
/// offsets from their bodies' centres of mass, and the offset between them.
struct NodePair<'n> {
    na: &'n BvhNode,
    nb: &'n BvhNode,
    frame: &'n PairFrame,
    qa: Vector,
    qb: Vector,
    offset: Vector,
    length: Real,
}

impl<'n> NodePair<'n> {
    #[inline]
    fn new(na: &'n BvhNode, nb: &'n BvhNode, frame: &'n PairFrame) -> NodePair<'n> {
        let qa = na.center.coords;
        let qb = frame.rotation * nb.center.coords;
        let offset = qb + frame.pos_ab.translation.vector - qa;
        NodePair { na, nb, frame, qa, qb, offset, length: offset.norm() }
    }

    /// a's box support along the unit `u` of a's frame, cut by its sphere.
    #[inline]
    fn support_a(&self, u: &Vector) -> Real {
        self.na.half_extents.dot(&self.na.axes.tr_mul(u).abs()).min(self.na.radius)
    }

    /// b's box (turned into a's frame) support along `u`, cut by its sphere.
    #[inline]
    fn support_b(&self, u: &Vector) -> Real {
        self.nb
            .half_extents
            .dot(&self.nb.axes.tr_mul(&self.frame.rotation.tr_mul(u)).abs())
            .min(self.nb.radius)
    }

    /// The `k`th axis of a's box and of b's (turned into a's frame).
    #[inline]
    fn box_axes(&self, k: usize) -> (Vector, Vector) {
        (self.na.axes.column(k).into_owned(), self.frame.rotation * self.nb.axes.column(k))
    }

    /// Where one node is a leaf more than [`LOPSIDED_RATIO`] times the
    /// other's radius, the direction (in a's frame, from a towards b) from
    /// that leaf's box's closest point to the small node's centre; `None`
    /// otherwise, or where the centre faces one of the box's faces (the
    /// direction is then that face's axis, already tried) or lies inside
    /// it. Along it the leaf's box lies wholly behind its closest point, so
    /// the slab is the box's distance to the small node's centre less that
    /// node's support: for a long thin leaf (a sliver of a gear's tooth)
    /// beside a small node off its edge, far tighter than the centre line or
    /// any face axis. Opening such a pair splits only the small node, which
    /// leaves the leaf's slack as it is.
    #[inline]
    fn leaf_to_small_node(&self) -> Option<Vector> {
        let (na, nb) = (self.na, self.nb);
        let toward = |axes: &Matrix3<Real>, half: &Vector, from_box_centre: &Vector| {
            let local = axes.tr_mul(from_box_centre);
            let outside = local.zip_map(half, |x, h| x - x.clamp(-h, h));
            let beyond = outside.iter().filter(|&&x| x != 0.0).count();
            (beyond >= 2).then(|| (axes * outside).normalize())
        };
        match lopsided_leaf(na, nb)? {
            Side::A => toward(&na.axes, &na.half_extents, &self.offset),
            Side::B => toward(&(self.frame.rotation * nb.axes), &nb.half_extents, &-self.offset).map(|u| -u),
        }
    }
}

/// One body of a node pair.
#[derive(Copy, Clone, Debug, PartialEq, Eq)]
pub(crate) enum Side {
    A,
    B,
}

/// Which node of the pair is a leaf more than [`LOPSIDED_RATIO`] times the
/// other's radius, if either is (a's where both are).
#[inline]
pub(crate) fn lopsided_leaf(na: &BvhNode, nb: &BvhNode) -> Option<Side> {
    if na.is_leaf() && na.radius > LOPSIDED_RATIO * nb.radius {
        Some(Side::A)
    } else if nb.is_leaf() && nb.radius > LOPSIDED_RATIO * na.radius {
        Some(Side::B)
    } else {
        None
    }
}

#[inline]
fn node_pair_bounds(
    na: &BvhNode,
    nb: &BvhNode,
    frame: &PairFrame,
    target: Real,
    (needed, horizon): (Real, Real),
) -> NodeBounds {
    let pair = NodePair::new(na, nb, frame);
    let (qa, qb, offset, length) = (pair.qa, pair.qb, pair.offset, pair.length);
    let spheres = length - na.radius - nb.radius;
    let box_gap = |u: &Vector| offset.dot(u) - pair.support_a(u) - pair.support_b(u);
    // The boxes' slab: along the line of centres, or along a face axis of
    // either box (the right axis for a flat node, a wall, whose centre line
    // is oblique), whichever separates them most.
    // Along a direction n: the rate and curvature of the centres' gap.
    let motion = |n: &Vector| {
        let (nwa, nwb) = (n.cross(&frame.omega_a), n.cross(&frame.omega_b));
        let (spin_a, spin_b) = (nwa.norm(), nwb.norm());
        let rate = n.dot(&frame.velocity) + nwb.dot(&qb) - nwa.dot(&qa);
        let curvature = spin_a * frame.spin_a * qa.norm() + spin_b * frame.spin_b * qb.norm();
        (rate, curvature, spin_a * na.radius + spin_b * nb.radius)
    };
    let sphere_time = if length > 0.0 {
        let (rate, curvature, _) = motion(&(offset / length));
        first_root(spheres - target, rate, curvature)
    } else {
        0.0
    };
    let box_time = |n: &Vector, gap: Real| {
        let (rate, curvature, spread) = motion(n);
        first_root(gap - target, rate - spread, curvature)
    };
    let consider = |best: (Real, Vector), u: Vector| {
        let u = if offset.dot(&u) < 0.0 { -u } else { u };
        let gap = box_gap(&u);
        if gap > best.0 {
            (gap, u)
        } else {
            best
        }
    };
    let mut best = (Real::NEG_INFINITY, Vector::zeros());
    if length > 0.0 {
        best = consider(best, offset / length);
    }
    if sphere_time.max(box_time(&best.1, best.0)) < needed {
        for k in 0..3 {
            let (axis_a, axis_b) = pair.box_axes(k);
            best = consider(best, axis_a);
            best = consider(best, axis_b);
        }
    }
    let (mut gap, mut box_direction) = best;
    let mut slab_time = box_time(&box_direction, gap);
    if sphere_time.max(slab_time) < needed {
        // Still short: for a large leaf beside a small node, the slab along
        // the leaf's closest-point direction, kept where it lasts longer.
        if let Some(u) = pair.leaf_to_small_node() {
            let along = box_gap(&u);
            gap = gap.max(along);
            let time = box_time(&u, along);
            if time > slab_time {
                (slab_time, box_direction) = (time, u);
            }
        }
    }
    let box_time = slab_time;
    let mut spin_time = 0.0;
    let rate_time = sphere_time.max(box_time);
    if rate_time < needed
        && rate_time < SPIN_SWEEP_MAX_RATE_FRACTION * horizon
        && (frame.spin_a + frame.spin_b) * horizon >= SPIN_SWEEP_MIN_TURN
    {
        let (widest, _) = spin_swept_gap(&pair, horizon);
        if widest > target {
            spin_time = horizon;
        }
    }
    NodeBounds { sphere_time, box_time, box_direction, spin_time, gap: gap.max(spheres) }
}

/// A lower bound on the time before any triangle pair of the triangles
/// under node `na` of `a` and `nb` of `b` comes within `target`, and on
/// their distance now: the slab along the line of the two nodes' centres
/// over the triangles' distinct vertices themselves (`vertices_a`,
/// `vertices_b`: [`TriMesh::small_node_vertices`]) (the bound of the module,
/// minimum and maximum separately over each vertex set). A node's box holds
/// the empty space of a curved patch and turns with its body, so it loses
/// its extent times the spin; each vertex loses only its own rate.
pub(crate) fn vertex_slab_time(
    (a, na, vertices_a): (&TriMesh, &BvhNode, &[u32]),
    (b, nb, vertices_b): (&TriMesh, &BvhNode, &[u32]),
    frame: &PairFrame,
    target: Real,
) -> (Real, Real) {
    let shift = frame.pos_ab.translation.vector;
    let offset = frame.rotation * nb.center.coords + shift - na.center.coords;
    let length = offset.norm();
    if length == 0.0 {
        return (0.0, 0.0);
    }
    let n = offset / length;
    let (turn_a, turn_b) = (n.cross(&frame.omega_a), n.cross(&frame.omega_b));
    // b's vertices in b's frame: the height `n · (R p + shift)` and the rate
    // `(n × ω_b) · R p` as dot products with `p`.
    let (n_b, turn_b_local) = (frame.rotation.tr_mul(&n), frame.rotation.tr_mul(&turn_b));
    let (mut high_a, mut fastest_a, mut reach_a) = (Real::NEG_INFINITY, Real::NEG_INFINITY, 0.0 as Real);
    for &v in vertices_a {
        let p = a.vertices()[v as usize].coords;
        high_a = high_a.max(n.dot(&p));
        fastest_a = fastest_a.max(turn_a.dot(&p));
        reach_a = reach_a.max(p.norm_squared());
    }
    let (mut low_b, mut slowest_b, mut reach_b) = (Real::INFINITY, Real::INFINITY, 0.0 as Real);
    for &v in vertices_b {
        let p = b.vertices()[v as usize].coords;
        low_b = low_b.min(n_b.dot(&p));
        slowest_b = slowest_b.min(turn_b_local.dot(&p));
        reach_b = reach_b.max(p.norm_squared());
    }
    let gap = low_b + n.dot(&shift) - high_a;
    let rate = n.dot(&frame.velocity) + slowest_b - fastest_a;
    let curvature =
        turn_a.norm() * frame.spin_a * reach_a.sqrt() + turn_b.norm() * frame.spin_b * reach_b.sqrt();
    (first_root(gap - target, rate, curvature), gap)
}

/// The widest gap over the `horizon` between the spin-swept regions of
/// the two nodes of `pair` (see [`node_pair_time`]), and its direction (a's
/// frame, from a to b), among the centre line, both spin axes and both
/// boxes' axes.
fn spin_swept_gap(pair: &NodePair<'_>, horizon: Real) -> (Real, Vector) {
    let (na, nb, frame) = (pair.na, pair.nb, pair.frame);
    let (qa, qb, offset, length) = (pair.qa, pair.qb, pair.offset, pair.length);
    let (support_a, support_b) = (|u: &Vector| pair.support_a(u), |u: &Vector| pair.support_b(u));
    // Each body's region along u: its spin cylinder, or its box.
    let axis = |omega: &Vector, spin: Real| (spin > 0.0).then(|| omega / spin);
    let (axis_a, axis_b) = (axis(&frame.omega_a, frame.spin_a), axis(&frame.omega_b, frame.spin_b));
    let high_a = |u: &Vector| match &axis_a {
        Some(k) => swept_support(k, &qa, na.radius, u),
        None => u.dot(&qa) + support_a(u),
    };
    let low_b = |u: &Vector| match &axis_b {
        Some(k) => -swept_support(k, &qb, nb.radius, &-u),
        None => u.dot(&qb) - support_b(u),
    };
    let centres = frame.pos_ab.translation.vector;
    // The smaller of the gaps at the two ends of the horizon.
    let swept_gap = |u: &Vector| {
        let now = u.dot(&centres) + low_b(u) - high_a(u);
        now.min(now + u.dot(&frame.velocity) * horizon)
    };
    let mut directions = [Vector::zeros(); 9];
    directions[0] = if length > 0.0 { offset / length } else { Vector::zeros() };
    directions[1] = axis_a.unwrap_or_else(Vector::zeros);
    directions[2] = axis_b.unwrap_or_else(Vector::zeros);
    for k in 0..3 {
        (directions[3 + k], directions[6 + k]) = pair.box_axes(k);
    }
    let (mut widest, mut spin_direction) = (Real::NEG_INFINITY, Vector::zeros());
    for u in directions.iter().filter(|u| u.norm_squared() > 0.0) {
        let u = if u.dot(&centres) < 0.0 { -u } else { *u };
        let gap = swept_gap(&u);
        if gap > widest {
            (widest, spin_direction) = (gap, u);
        }
    }
    (widest, spin_direction)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::ccd::posed_pair::{PosedPair, TurningSlab};
    use crate::kernels::{triangle_distance, TriangleDistance};
    use crate::mesh::{box_mesh, icosphere};
    use crate::mesh::{DistanceKernel, TriMesh};
    use crate::motion::StepMotion;
    use crate::samples::Rng;

    /// The frame of two bodies at the start of their motions.
    fn frame_at_start(a: &StepMotion, b: &StepMotion) -> PairFrame {
        PairFrame::new(
            StepMotion::relative_pose(a, b, 0.0),
            &a.rotation_at(0.0),
            &(b.velocity - a.velocity),
            &a.angular_velocity,
            &b.angular_velocity,
        )
    }

    /// Random spinning, moving bodies near each other, and the frame at 0.
    fn random_pair(rng: &mut Rng) -> (StepMotion, StepMotion, PairFrame) {
        let a = StepMotion::new(
            Pose::new(rng.in_unit_ball(), rng.in_unit_ball() * 3.0),
            rng.in_unit_ball() * 3.0,
            rng.in_unit_ball() * 20.0,
        );
        let b = StepMotion::new(
            Pose::new(Vector::new(2.5, 0.0, 0.0) + rng.in_unit_ball(), rng.in_unit_ball() * 3.0),
            rng.in_unit_ball() * 3.0,
            rng.in_unit_ball() * 20.0,
        );
        let frame = frame_at_start(&a, &b);
        (a, b, frame)
    }

    /// Two bodies moving (up to 2) and spinning (up to 20 rad/s), `a` at
    /// the origin and `b` at `least` to `least + spread` times the sum of
    /// the meshes' radii from it in a random direction, and the frame at 0.
    fn near_each_other(
        rng: &mut Rng,
        mesh_a: &TriMesh,
        mesh_b: &TriMesh,
        (least, spread): (Real, Real),
    ) -> (StepMotion, StepMotion, PairFrame) {
        let ma = StepMotion::new(
            Pose::new(Vector::zeros(), rng.in_unit_ball() * 3.0),
            rng.in_unit_ball() * 2.0,
            rng.in_unit_ball() * 20.0,
        );
        let reach = mesh_a.radius() + mesh_b.radius();
        let mb = StepMotion::new(
            Pose::new(rng.unit_vector() * reach * (least + spread * rng.uniform()), rng.in_unit_ball() * 3.0),
            rng.in_unit_ball() * 2.0,
            rng.in_unit_ball() * 20.0,
        );
        let frame = frame_at_start(&ma, &mb);
        (ma, mb, frame)
    }

    /// The gap along the world direction `n` between two vertex sets at time `t`.
    fn gap_at(
        n: &Vector,
        a: &[crate::math::Point],
        ma: &StepMotion,
        b: &[crate::math::Point],
        mb: &StepMotion,
        t: Real,
    ) -> Real {
        let (pa, pb) = (ma.pose_at(t), mb.pose_at(t));
        let low_b = b.iter().map(|p| n.dot(&(pb * p).coords)).fold(Real::INFINITY, Real::min);
        let high_a = a.iter().map(|p| n.dot(&(pa * p).coords)).fold(Real::NEG_INFINITY, Real::max);
        low_b - high_a
    }

    /// Rounding allowed to a sampled gap below the target: `1e-12`.
    const SAMPLED_GAP_ROUNDING: Real = 1e-12;

    /// The gap along the world direction `n` between vertex sets `a` and
    /// `b` stays at least `target` (to [`SAMPLED_GAP_ROUNDING`]) at
    /// `samples + 1` evenly spaced times over `[0, until]`.
    fn assert_apart_until(
        n: &Vector,
        (a, ma): (&[crate::math::Point], &StepMotion),
        (b, mb): (&[crate::math::Point], &StepMotion),
        (until, samples): (Real, usize),
        target: Real,
        case: usize,
    ) {
        for k in 0..=samples {
            let t = until * k as Real / samples as Real;
            let g = gap_at(n, a, ma, b, mb, t);
            assert!(
                g >= target - SAMPLED_GAP_ROUNDING,
                "case {case}: gap {g} at {t} < target {target}, until {until}"
            );
        }
    }

    /// The closest triangle pair of two meshes posed by `frame` (every
    /// pair measured with the exact kernel): its triangles, the pair
    /// posed, its closest points and the unit direction from a's to b's.
    /// `None` where they are nearer than 1e-3 (a direction that rounding
    /// would turn).
    fn closest_triangle_pair(
        mesh_a: &TriMesh,
        mesh_b: &TriMesh,
        frame: &PairFrame,
    ) -> Option<((usize, usize), PosedPair, TriangleDistance, Vector)> {
        let (mut best, mut d) = ((0, 0), Real::INFINITY);
        for ta in 0..mesh_a.triangles().len() {
            for tb in 0..mesh_b.triangles().len() {
                let pair = PosedPair::new(mesh_a, ta, mesh_b, tb, frame);
                let found = triangle_distance(&pair.a, &pair.b).distance;
                if found < d {
                    (best, d) = ((ta, tb), found);
                }
            }
        }
        if d < 1e-3 {
            return None;
        }
        let pair = PosedPair::new(mesh_a, best.0, mesh_b, best.1, frame);
        let closest = triangle_distance(&pair.a, &pair.b);
        let n = (closest.point_b - closest.point_a) / closest.distance;
        Some((best, pair, closest, n))
    }

    /// The node tests' meshes: an icosphere, and a flat box or a smaller
    /// icosphere (by the case's parity) to meet it.
    fn node_test_meshes() -> (TriMesh, [TriMesh; 2]) {
        let sphere = icosphere(1.0, 2).unwrap();
        (sphere, [box_mesh(&Vector::new(0.6, 0.05, 0.4)).unwrap(), icosphere(0.6, 2).unwrap()])
    }

    #[test]
    fn triangle_slab_bound_holds_over_its_time() {
        // The true gap along the fixed direction never drops below the target
        // before the bound's time (sampled), and the bound is not vacuous.
        let mesh_a = icosphere(1.0, 1).unwrap();
        let mesh_b = icosphere(0.7, 1).unwrap();
        let mut rng = Rng::new(3);
        let target = 0.01;
        let mut checked = 0;
        for case in 0..2000 {
            let (ma, mb, frame) = random_pair(&mut rng);
            let (ta, tb) = (rng.next_u64() as usize % 80, rng.next_u64() as usize % 80);
            let pair = PosedPair::new(&mesh_a, ta, &mesh_b, tb, &frame);
            let n = rng.in_unit_ball().normalize();
            let (time, gap) = pair.slab_time(&n, &frame, target);
            if gap <= target || !time.is_finite() {
                continue;
            }
            checked += 1;
            let n_world = ma.rotation_at(0.0) * n;
            let (a, b) = (mesh_a.triangle(ta), mesh_b.triangle(tb));
            assert_apart_until(&n_world, (&a, &ma), (&b, &mb), (time, 50), target, case);
        }
        assert!(checked > 300, "{checked} cases with a positive gap");
    }

    /// Every vertex of the triangles below `node`.
    fn vertices_below(mesh: &TriMesh, node: &BvhNode) -> Vec<crate::math::Point> {
        let nodes = mesh.bvh().nodes();
        let mut stack = vec![*node];
        let mut points = Vec::new();
        while let Some(n) = stack.pop() {
            if n.is_leaf() {
                for t in n.first..n.first + n.count {
                    points.extend(mesh.triangle(t as usize));
                }
            } else {
                stack.extend([nodes[n.first as usize], nodes[n.first as usize + 1]]);
            }
        }
        points
    }

    #[test]
    fn full_bounds_hold_over_their_times_near_closest_approaches() {
        // The closest triangle pair of two bodies near each other (boxes and
        // icospheres, spins up to 20 rad/s), the target a little below its
        // distance, as near a closest approach: the full bound (the world
        // slab vertex pair by vertex pair, the turning slab, the head-on
        // bound) holds over its time, sampled against the exact distance
        // of the moved triangles; and the turning slab, whose rate is the
        // distance's own, is the longer one for most pairs.
        let meshes = [box_mesh(&Vector::new(0.3, 0.2, 0.25)).unwrap(), icosphere(0.3, 1).unwrap()];
        let mut rng = Rng::new(17);
        let horizon = 0.05;
        let (mut checked, mut longer) = (0, 0);
        let mut features = std::collections::BTreeMap::new();
        for case in 0..600 {
            let (mesh_a, mesh_b) = (&meshes[case % 2], &meshes[(case / 2) % 2]);
            let (ma, mb, frame) = near_each_other(&mut rng, mesh_a, mesh_b, (0.8, 0.4));
            let Some((best, pair, closest, n)) = closest_triangle_pair(mesh_a, mesh_b, &frame) else {
                continue;
            };
            let d = closest.distance;
            // 1e-6 to 0.1 of the distance below it.
            let target = d * (1.0 - Real::powf(10.0, -6.0 + 5.0 * rng.uniform()));
            let (time, _) = pair.exact_time(&frame, target, DistanceKernel::Exact, horizon);
            let fixed = pair.vertex_slab_time::<3, 3>(&n, &frame, target);
            let turning = pair.turning_slab_time::<3, 3>(&closest, &n, &frame, target, horizon);
            *features.entry(format!("{:?}-{:?}", closest.feature_a, closest.feature_b)).or_insert(0) += 1;
            checked += 1;
            longer += usize::from(turning > fixed);
            let (a, b) = (mesh_a.triangle(best.0), mesh_b.triangle(best.1));
            for bound in [time, turning] {
                for k in 0..=400 {
                    let t = bound * k as Real / 400.0;
                    let (pa, pb) = (ma.pose_at(t), mb.pose_at(t));
                    let distance = triangle_distance(&a.map(|p| pa * p), &b.map(|p| pb * p)).distance;
                    assert!(
                        distance >= target - 1e-12,
                        "case {case}: distance {distance} at {t} < target {target}, bound {bound} ({:?}-{:?})",
                        closest.feature_a,
                        closest.feature_b
                    );
                }
            }
        }
        assert!(checked > 400, "{checked} pairs checked");
        assert!(2 * longer > checked, "the turning slab longer for {longer} of {checked}");
        let edges = features.iter().filter(|(k, _)| k.starts_with("Edge") && k.contains("-Edge")).count();
        assert!(edges > 0 && features.len() >= 4, "feature pairs seen: {features:?}");
    }

    #[test]
    fn each_vertex_s_height_in_a_turning_slab_keeps_to_its_curvature() {
        // The closest triangle pair of two bodies near each other (boxes
        // and icospheres, spins up to 20 rad/s): in the slab along the
        // closest direction turning at the frame's spin about the moving
        // origin, each vertex's height stays within its curvature's
        // parabola about its height and rate now, over the horizon
        // (sampled in the world, the direction turned as the frame turns).
        // That is what the slab's bound rests on, vertex by vertex: the
        // vertices of the body the frame turns with (a face's) by their
        // centre's motion alone, the others by their own.
        let meshes = [box_mesh(&Vector::new(0.3, 0.2, 0.25)).unwrap(), icosphere(0.3, 1).unwrap()];
        let mut rng = Rng::new(29);
        let horizon = 0.05;
        let (mut checked, mut rigid, mut tight) = (0, 0, 0);
        for case in 0..600 {
            let (mesh_a, mesh_b) = (&meshes[case % 2], &meshes[(case / 2) % 2]);
            let (ma, mb, frame) = near_each_other(&mut rng, mesh_a, mesh_b, (0.8, 0.4));
            let Some((best, pair, closest, n)) = closest_triangle_pair(mesh_a, mesh_b, &frame) else {
                continue;
            };
            let Some(spin) = pair.frame_spin(&closest, &n, &frame) else { continue };
            let slab = TurningSlab::new(&closest, &n, spin, &frame, horizon);
            checked += 1;
            rigid += usize::from(spin.body.is_some());
            // Into the world: a's frame at the start is a's pose then, and
            // moves with a's centre.
            let (pose_a, turn_a) = (ma.pose_at(0.0), ma.rotation_at(0.0));
            let (origin, origin_velocity) = slab.origin_motion();
            let (n, omega) = (turn_a * n, turn_a * spin.omega);
            let height_at = |p_local: &crate::math::Point, pose: &dyn Fn(Real) -> Pose, t: Real| {
                let n_t = nalgebra::UnitQuaternion::from_scaled_axis(omega * t) * n;
                let o =
                    pose_a * crate::math::Point::from(origin) + (ma.velocity + turn_a * origin_velocity) * t;
                n_t.dot(&(pose(t) * p_local - o))
            };
            let (a, b) = (mesh_a.triangle(best.0), mesh_b.triangle(best.1));
            let offsets_b = b.map(|p| crate::math::Point::from(frame.rotation * p.coords));
            let heights = a.iter().map(|p| (slab.height_a(p), *p, true)).chain(
                b.iter()
                    .zip(&offsets_b)
                    .map(|(p, q)| (slab.height_b(q, &(q + frame.pos_ab.translation.vector)), *p, false)),
            );
            for ([height, rate, curvature], p, on_a) in heights {
                let pose = |t: Real| if on_a { ma.pose_at(t) } else { mb.pose_at(t) };
                let mut worst: Real = 0.0;
                for k in 0..=200 {
                    let t = horizon * k as Real / 200.0;
                    let off = height_at(&p, &pose, t) - height - rate * t;
                    assert!(
                        off.abs() <= curvature * t * t / 2.0 + SAMPLED_GAP_ROUNDING,
                        "case {case}: a vertex of {} off its parabola by {off} at {t} (curvature {curvature}, frame {:?})",
                        if on_a { "a" } else { "b" },
                        spin.body
                    );
                    if t > 0.0 {
                        worst = worst.max(2.0 * off.abs() / (t * t));
                    }
                }
                tight += usize::from(worst > 0.25 * curvature);
            }
        }
        assert!(checked > 300 && 2 * rigid > checked, "{rigid} rigid of {checked}");
        // Not vacuous: a quarter of the curvature is reached by a vertex in
        // many of the cases.
        assert!(tight > checked, "{tight} vertices reach a quarter of their curvature, of {checked} cases");
    }

    #[test]
    fn a_leaf_pair_bound_holds_over_its_time_near_closest_approaches() {
        // The closest leaf pair of two bodies near each other (a plate, a
        // box and a fine icosphere: flat patches and curved ones; spins up
        // to 20 rad/s), the target 1e-6 to 0.1 of the distance below it,
        // as in a closest approach's proof: wherever the leaves' own bound
        // gives a time, every triangle pair of the two leaves stays
        // farther than the target over it (sampled against the exact
        // distance of the moved triangles), and its gap is below their
        // distance now. Where the leaves are flat patches, it is not
        // vacuous: for most of the pairs it reaches at least a tenth of
        // what the closest triangle pair's own full bound does.
        let meshes = [
            box_mesh(&Vector::new(0.4, 0.4, 0.01)).unwrap(),
            box_mesh(&Vector::new(0.3, 0.2, 0.25)).unwrap(),
            icosphere(0.3, 3).unwrap(),
        ];
        // Leaves as node indices.
        let leaves = |mesh: &TriMesh| -> Vec<u32> {
            (0..mesh.bvh().nodes().len() as u32)
                .filter(|&k| mesh.bvh().nodes()[k as usize].is_leaf())
                .collect()
        };
        let triangles = |mesh: &TriMesh, k: u32| {
            let leaf = mesh.bvh().nodes()[k as usize];
            (leaf.first..leaf.first + leaf.count).map(|t| t as usize)
        };
        let mut rng = Rng::new(23);
        let horizon = 0.05;
        let (mut bounded, mut flat, mut flat_reaching) = (0, 0, 0);
        for case in 0..300 {
            let (mesh_a, mesh_b) = (&meshes[case % 3], &meshes[(case / 3) % 3]);
            let (ma, mb, frame) = near_each_other(&mut rng, mesh_a, mesh_b, (0.6, 0.6));
            // The closest leaf pair, and its closest triangle pair.
            let (mut best, mut d) = ((leaves(mesh_a)[0], leaves(mesh_b)[0], 0, 0), Real::INFINITY);
            for la in leaves(mesh_a) {
                for lb in leaves(mesh_b) {
                    for ta in triangles(mesh_a, la) {
                        for tb in triangles(mesh_b, lb) {
                            let pair = PosedPair::new(mesh_a, ta, mesh_b, tb, &frame);
                            let found = triangle_distance(&pair.a, &pair.b).distance;
                            if found < d {
                                (best, d) = ((la, lb, ta, tb), found);
                            }
                        }
                    }
                }
            }
            if d < 1e-3 {
                continue;
            }
            let (la, lb, ta, tb) = best;
            let target = d * (1.0 - Real::powf(10.0, -6.0 + 5.0 * rng.uniform()));
            let Some((time, gap)) =
                PosedPair::leaves_time((mesh_a, la), (mesh_b, lb), &frame, (target, horizon))
            else {
                continue;
            };
            assert!(gap <= d * (1.0 + 1e-12), "case {case}: gap {gap} above the distance {d}");
            bounded += 1;
            let pair = PosedPair::new(mesh_a, ta, mesh_b, tb, &frame);
            let (own, _) = pair.exact_time(&frame, target, DistanceKernel::Exact, horizon);
            if case % 3 == 0 && (case / 3) % 3 < 2 {
                // The plate against the plate or the box.
                flat += 1;
                flat_reaching += usize::from(time >= 0.1 * own);
            }
            for k in 0..=200 {
                let t = time * k as Real / 200.0;
                let (pa, pb) = (ma.pose_at(t), mb.pose_at(t));
                for ta in triangles(mesh_a, la) {
                    for tb in triangles(mesh_b, lb) {
                        let a = mesh_a.triangle(ta).map(|p| pa * p);
                        let b = mesh_b.triangle(tb).map(|p| pb * p);
                        let distance = triangle_distance(&a, &b).distance;
                        assert!(
                            distance >= target - 1e-12,
                            "case {case}: triangles {ta}, {tb} {distance} apart at {t} < target {target}, bound {time}"
                        );
                    }
                }
            }
        }
        assert!(bounded > 150, "{bounded} leaf pairs bounded");
        assert!(
            2 * flat_reaching > flat,
            "{flat_reaching} of {flat} flat leaf pairs reach a tenth of the pair's own"
        );
    }

    #[test]
    fn spin_swept_bound_holds_over_the_horizon() {
        // Spins up to 20 rad over the horizon (the region does not depend on
        // the rate; slower keeps the sampling fine), one body sometimes
        // not turning at all; wherever the spin-swept bound settles a node
        // pair for the horizon, every vertex below stays on its side of the
        // slab along the chosen (world-fixed) direction at every sampled time.
        let mesh_a = box_mesh(&Vector::new(1.0, 1.0, 0.02)).unwrap();
        let mesh_b = icosphere(0.5, 2).unwrap();
        let mut rng = Rng::new(11);
        let (target, horizon) = (0.01, 1.0);
        let mut checked = 0;
        for case in 0..3000 {
            let spin =
                |rng: &mut Rng, still: bool| if still { Vector::zeros() } else { rng.in_unit_ball() * 20.0 };
            let ma = StepMotion::new(
                Pose::new(rng.in_unit_ball(), rng.in_unit_ball() * 3.0),
                rng.in_unit_ball(),
                spin(&mut rng, case % 3 == 1),
            );
            let mb = StepMotion::new(
                Pose::new(Vector::new(2.2, 0.0, 0.0) + rng.in_unit_ball(), rng.in_unit_ball() * 3.0),
                rng.in_unit_ball(),
                spin(&mut rng, case % 3 == 2),
            );
            let frame = frame_at_start(&ma, &mb);
            let (nodes_a, nodes_b) = (mesh_a.bvh().nodes(), mesh_b.bvh().nodes());
            let na = nodes_a[rng.next_u64() as usize % nodes_a.len()];
            let nb = nodes_b[rng.next_u64() as usize % nodes_b.len()];
            let (gap, direction) = spin_swept_gap(&NodePair::new(&na, &nb, &frame), horizon);
            if gap <= target {
                continue;
            }
            checked += 1;
            let n_world = ma.rotation_at(0.0) * direction;
            let (a, b) = (vertices_below(&mesh_a, &na), vertices_below(&mesh_b, &nb));
            assert_apart_until(&n_world, (&a, &ma), (&b, &mb), (horizon, 1000), target, case);
        }
        assert!(checked > 100, "{checked} node pairs settled by the spin-swept bound");
    }

    #[test]
    fn node_bounds_hold_over_their_times() {
        // Every vertex below a node pair stays on its side of each bound's
        // slab (fixed in the world) until that bound's time: the spheres'
        // along the line of centres, the boxes' along the direction chosen
        // among the centre line and the box axes (a flat box node too).
        let (mesh_a, others) = node_test_meshes();
        let mut rng = Rng::new(5);
        let target = 0.01;
        let (mut spheres, mut boxes) = (0, 0);
        for case in 0..1000 {
            let (ma, mb, frame) = random_pair(&mut rng);
            let mesh_b = &others[case % 2];
            let (nodes_a, nodes_b) = (mesh_a.bvh().nodes(), mesh_b.bvh().nodes());
            let na = nodes_a[rng.next_u64() as usize % nodes_a.len()];
            let nb = nodes_b[rng.next_u64() as usize % nodes_b.len()];
            let bounds = node_pair_bounds(&na, &nb, &frame, target, (Real::INFINITY, 0.0));
            let (pa, pb) = (ma.pose_at(0.0), mb.pose_at(0.0));
            let rotation_a = ma.rotation_at(0.0);
            let centre_line = (pb * nb.center - pa * na.center).normalize();
            let (a, b) = (vertices_below(&mesh_a, &na), vertices_below(mesh_b, &nb));
            for (time, n_world, count) in [
                (bounds.sphere_time, centre_line, &mut spheres),
                (bounds.box_time, rotation_a * bounds.box_direction, &mut boxes),
            ] {
                if time <= 0.0 || !time.is_finite() {
                    continue;
                }
                *count += 1;
                assert_apart_until(&n_world, (&a, &ma), (&b, &mb), (time, 40), target, case);
            }
        }
        assert!(spheres > 100 && boxes > 100, "{spheres} sphere and {boxes} box bounds checked");
    }

    #[test]
    fn a_small_node_pair_s_vertex_slab_holds_over_its_time() {
        // Every vertex below two small nodes (of an icosphere and a flat box
        // or another icosphere, moving and spinning at random) stays on its
        // side of the slab along the line of the nodes' centres, fixed in
        // the world, until the bound's time (sampled); and the bound
        // sometimes lasts longer than the nodes' spheres' and boxes' (126
        // of 2,469 cases: these bodies are 1.5 to 3.5 apart, where the
        // boxes do well; near a closest approach it is the other way).
        let (mesh_a, others) = node_test_meshes();
        let mut rng = Rng::new(61);
        let target = 0.01;
        let (mut checked, mut longer) = (0, 0);
        for case in 0..3000 {
            let (ma, mb, frame) = random_pair(&mut rng);
            let mesh_b = &others[case % 2];
            let (nodes_a, nodes_b) = (mesh_a.bvh().nodes(), mesh_b.bvh().nodes());
            let (i, j) = (rng.index(nodes_a.len()) as u32, rng.index(nodes_b.len()) as u32);
            let (Some(span_a), Some(span_b)) = (mesh_a.small_node_vertices(i), mesh_b.small_node_vertices(j))
            else {
                continue;
            };
            let (na, nb) = (&nodes_a[i as usize], &nodes_b[j as usize]);
            let (_, gap) = vertex_slab_time((&mesh_a, na, span_a), (mesh_b, nb, span_b), &frame, 0.0);
            // Every other case asks for a target just below the gap, where
            // the bound is short and tight.
            let target = if case % 2 == 0 { target } else { 0.98 * gap };
            let (time, _) = vertex_slab_time((&mesh_a, na, span_a), (mesh_b, nb, span_b), &frame, target);
            if time <= 0.0 {
                continue;
            }
            checked += 1;
            let (boxes, _) = node_pair_time(na, nb, &frame, target, (Real::INFINITY, 0.0));
            longer += usize::from(time > boxes);
            let (pa, pb) = (ma.pose_at(0.0), mb.pose_at(0.0));
            let centre_line = (pb * nb.center - pa * na.center).normalize();
            let (a, b) = (vertices_below(&mesh_a, na), vertices_below(mesh_b, nb));
            assert_apart_until(&centre_line, (&a, &ma), (&b, &mb), (time.min(10.0), 100), target, case);
        }
        assert!(checked > 300 && longer > checked / 50, "{longer} longer of {checked} checked");
    }

    #[test]
    fn a_long_leaf_is_bounded_along_its_closest_point_to_a_small_node() {
        // A gear tooth's sliver: a 6 × 0.17 strip of two triangles, one
        // leaf, beside a small icosphere off its edges (outside its box in
        // two or three axes), as the gear ring of `pybullet_data` meets a
        // robot link. The node bound's gap must be the strip's distance to
        // the sphere's centre less its radius (the strip is its own box):
        // the centre line and the face axes give less off a corner. And the
        // bound holds over its time along its direction.
        let strip = TriMesh::new(
            vec![
                crate::math::Point::new(-3.0, -0.085, 0.0),
                crate::math::Point::new(3.0, -0.085, 0.0),
                crate::math::Point::new(3.0, 0.085, 0.0),
                crate::math::Point::new(-3.0, 0.085, 0.0),
            ],
            vec![[0, 1, 2], [0, 2, 3]],
        )
        .unwrap();
        let small = icosphere(0.05, 1).unwrap();
        let (leaf, node) = (strip.bvh().nodes()[0], small.bvh().nodes()[0]);
        assert!(leaf.is_leaf() && leaf.radius > LOPSIDED_RATIO * node.radius);
        let (a_points, b_points) = (vertices_below(&strip, &leaf), vertices_below(&small, &node));
        let mut rng = Rng::new(11);
        let target = 0.01;
        for case in 0..500 {
            // The sphere's centre 0.3–1 from the strip, beyond an end or a
            // long side and above or below it.
            let along = if case % 2 == 0 { 3.0 + rng.range(0.0, 0.7) } else { rng.range(-2.5, 2.5) };
            let side = 0.085 + rng.range(0.2, 0.7);
            let centre = Vector::new(along, side, rng.range(-0.7, 0.7));
            let a = StepMotion::new(Pose::identity(), rng.in_unit_ball() * 0.3, rng.in_unit_ball() * 0.3);
            // Closing on the strip, so that every bound is sought.
            let closing = -centre.normalize() * rng.range(0.5, 2.0) + rng.in_unit_ball() * 0.2;
            let b = StepMotion::new(Pose::new(centre, rng.in_unit_ball()), closing, rng.in_unit_ball());
            let frame = frame_at_start(&a, &b);
            let bounds = node_pair_bounds(&leaf, &node, &frame, target, (Real::INFINITY, 0.0));
            let distance = (0..2)
                .map(|t| {
                    crate::kernels::point_triangle(&crate::math::Point::from(centre), &strip.triangle(t))
                        .distance
                })
                .fold(Real::INFINITY, Real::min);
            assert!(
                bounds.gap >= distance - node.radius - 1e-12,
                "case {case}: gap {} below the strip's distance {distance} less the radius {}",
                bounds.gap,
                node.radius
            );
            let (time, n_world) = (bounds.box_time.min(1.0), a.rotation_at(0.0) * bounds.box_direction);
            assert_apart_until(&n_world, (&a_points, &a), (&b_points, &b), (time, 40), target, case);
        }
    }

    #[test]
    fn a_ball_against_a_spinning_sliver_is_bounded_in_the_sliver_s_turning_frame() {
        // A small node's ball (centre and radius, a point of one body)
        // against a 6 × 0.17 sliver of a body spinning up to 3 rad/s, as a
        // robot link meets the gear ring of `pybullet_data`, the target
        // 1e-6 to 0.1 of the gap below it (a closest approach's proof): the
        // ball's centre stays farther than the target plus the radius from
        // the moving sliver over the bound's time (sampled against the exact
        // point–triangle distance), either body holding the ball. And the
        // bound is the turning frame's: for most cases longer than the
        // world slab's, which the sliver's tilt sweeps at its length times
        // the spin.
        let sliver = [
            crate::math::Point::new(-3.0, -0.085, 0.0),
            crate::math::Point::new(3.0, -0.085, 0.0),
            crate::math::Point::new(3.0, 0.085, 0.1),
        ];
        let mut rng = Rng::new(23);
        let horizon = 0.2;
        let (mut checked, mut longer) = (0, 0);
        for case in 0..1000 {
            let ball_on_a = case % 2 == 0;
            let radius = rng.range(0.001, 0.05);
            // The ball's centre within 0.5 of its body's centre, the
            // bodies' centres 1–6 apart.
            let spin = |rng: &mut Rng, top: Real| rng.in_unit_ball() * top;
            let sliver_motion = StepMotion::new(
                Pose::new(Vector::zeros(), rng.in_unit_ball() * 3.0),
                spin(&mut rng, 0.3),
                spin(&mut rng, 3.0),
            );
            let ball_centre = crate::math::Point::from(rng.unit_vector() * rng.range(0.0, 0.5));
            let place = rng.unit_vector() * rng.range(1.0, 6.0);
            let ball_motion = StepMotion::new(
                Pose::new(place, rng.in_unit_ball() * 3.0),
                spin(&mut rng, 1.0),
                spin(&mut rng, 1.0),
            );
            let (ma, mb) =
                if ball_on_a { (&ball_motion, &sliver_motion) } else { (&sliver_motion, &ball_motion) };
            let frame = frame_at_start(ma, mb);
            let distance_at = |t: Real| {
                let centre = ball_motion.pose_at(t) * ball_centre;
                let posed = sliver_motion.pose_at(t);
                crate::kernels::point_triangle(&centre, &sliver.map(|p| posed * p)).distance - radius
            };
            let gap_now = distance_at(0.0);
            if gap_now < 1e-3 {
                continue;
            }
            let target = gap_now * (1.0 - Real::powf(10.0, -6.0 + 5.0 * rng.uniform()));
            let (time, gap) =
                PosedPair::ball_time(ball_centre, radius, sliver, ball_on_a, &frame, (target, horizon));
            assert!(
                (gap - gap_now).abs() <= 1e-12 * (1.0 + gap_now),
                "case {case}: gap {gap} against {gap_now}"
            );
            checked += 1;
            for k in 0..=400 {
                let t = time.min(horizon) * k as Real / 400.0;
                let d = distance_at(t);
                assert!(d >= target - 1e-12, "case {case}: {d} at {t} < target {target}, bound {time}");
            }
            // The world slab of the same point and sliver along their
            // closest points' direction.
            let point = [ball_centre; 3];
            let pair = if ball_on_a {
                PosedPair::of(point, sliver, &frame)
            } else {
                PosedPair::of(sliver, point, &frame)
            };
            let (p, q) = if ball_on_a { (pair.a[0], &pair.b) } else { (pair.b[0], &pair.a) };
            let closest = crate::kernels::point_triangle(&p, q);
            let n = if ball_on_a { closest.point - p } else { p - closest.point }.normalize();
            longer += usize::from(time > pair.vertex_slab_time::<3, 3>(&n, &frame, target + radius));
        }
        assert!(checked > 800, "{checked} cases");
        assert!(2 * longer > checked, "the turning frame longer for {longer} of {checked}");
    }
}

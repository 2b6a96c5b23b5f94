//! A pair of BVH nodes posed at a time: the bounds of their distance and
//! of its rate over the step.

use super::mesh_bound::{first_root, PairFrame, Side};
use crate::kernels::{dyop_distance, point_triangle, triangle_distance, Feature, TriangleDistance};
use crate::math::{Point, Real, Triangle, Vector};
use crate::mesh::BVH_LEAF_SIZE;
use crate::mesh::{BvhNode, DistanceKernel, TriMesh};

/// Two edges closer to parallel than this (the squared sine of their
/// angle) have no turning frame of their own: `1e-6`.
pub(super) const PARALLEL_EDGES: Real = 1e-6;

/// Triangle `ta` of `a` and `tb` of `b`, set up for the bounds: `a`'s
/// vertices (offsets from its centre), `b`'s as offsets from its centre
/// and as points, both in `a`'s frame, and each one's largest offset.
pub(crate) struct PosedPair {
    pub(super) a: Triangle,
    offsets_b: Triangle,
    pub(super) b: Triangle,
    reach_a: Real,
    reach_b: Real,
}

impl PosedPair {
    #[inline]
    pub(crate) fn new(a: &TriMesh, ta: usize, b: &TriMesh, tb: usize, frame: &PairFrame) -> PosedPair {
        PosedPair::of(a.triangle(ta), b.triangle(tb), frame)
    }

    /// The pair of triangles given in their own meshes' frames.
    #[inline]
    pub(super) fn of(local_a: Triangle, local_b: Triangle, frame: &PairFrame) -> PosedPair {
        let offsets_b: Triangle = local_b.map(|p| (frame.rotation * p.coords).into());
        let moved_b: Triangle = offsets_b.map(|q| q + frame.pos_ab.translation.vector);
        let reach = |t: &Triangle| t.iter().map(|p| p.coords.norm_squared()).fold(0.0, Real::max).sqrt();
        PosedPair { reach_a: reach(&local_a), reach_b: reach(&offsets_b), a: local_a, offsets_b, b: moved_b }
    }

    /// The time before the pair's gap along the unit direction `n` falls to
    /// `target` (the second-order bound of the module), and the gap now.
    #[inline]
    pub(super) fn slab_time(&self, n: &Vector, frame: &PairFrame, target: Real) -> (Real, Real) {
        let (nwa, nwb) = (n.cross(&frame.omega_a), n.cross(&frame.omega_b));
        let slowest_b = self.offsets_b.iter().map(|q| nwb.dot(&q.coords)).fold(Real::INFINITY, Real::min);
        let fastest_a = self.a.iter().map(|p| nwa.dot(&p.coords)).fold(Real::NEG_INFINITY, Real::max);
        let rate = n.dot(&frame.velocity) + slowest_b - fastest_a;
        let curvature = nwa.norm() * frame.spin_a * self.reach_a + nwb.norm() * frame.spin_b * self.reach_b;
        let gap = self.gap(n);
        (first_root(gap - target, rate, curvature), gap)
    }

    /// [`Self::slab_time`], vertex pair by vertex pair: the gap along `n`
    /// is the least of the nine vertex pairs' gaps, each bounded by its own
    /// height and rate, so a vertex that moves fast towards the other
    /// triangle but lies far above the closest one counts only once it can
    /// have come down (a spinning box's corner near a wall: the other
    /// corners of its triangle swing faster, but from higher up). Never
    /// shorter than the slab's time; nine roots instead of one, so kept for
    /// the full bound. Over the first `A` vertices of `a` and `B` of `b`
    /// (1 for a point posed as three equal vertices, 3 otherwise).
    #[inline]
    pub(super) fn vertex_slab_time<const A: usize, const B: usize>(
        &self,
        n: &Vector,
        frame: &PairFrame,
        target: Real,
    ) -> Real {
        let (nwa, nwb) = (n.cross(&frame.omega_a), n.cross(&frame.omega_b));
        let curvature = nwa.norm() * frame.spin_a * self.reach_a + nwb.norm() * frame.spin_b * self.reach_b;
        let along = n.dot(&frame.velocity);
        let mut a = [(0.0, 0.0); A];
        for (h, p) in a.iter_mut().zip(&self.a) {
            *h = (n.dot(&p.coords), nwa.dot(&p.coords));
        }
        let mut time = Real::INFINITY;
        for (q, p) in self.offsets_b[..B].iter().zip(&self.b) {
            let (height, rate) = (n.dot(&p.coords), along + nwb.dot(&q.coords));
            for &(height_a, rate_a) in &a {
                time = time.min(first_root(height - height_a - target, rate - rate_a, curvature));
            }
        }
        time
    }

    /// The gap between the two triangles along the unit direction `n` now:
    /// `b`'s lowest vertex minus `a`'s highest.
    #[inline]
    fn gap(&self, n: &Vector) -> Real {
        let low_b = self.b.iter().map(|p| n.dot(&p.coords)).fold(Real::INFINITY, Real::min);
        let high_a = self.a.iter().map(|p| n.dot(&p.coords)).fold(Real::NEG_INFINITY, Real::max);
        low_b - high_a
    }

    /// A cheap bound: the slab along the line between the centroids.
    #[inline]
    pub(crate) fn quick_time(&self, frame: &PairFrame, target: Real) -> (Real, Real) {
        let centroid = |t: &Triangle| (t[0].coords + t[1].coords + t[2].coords) / 3.0;
        let between = centroid(&self.b) - centroid(&self.a);
        let normal = |t: &Triangle| (t[1] - t[0]).cross(&(t[2] - t[0]));
        // The line between the centroids, or either face normal (the right
        // direction for a large face over a small triangle), whichever
        // separates them most.
        let mut best = (Real::NEG_INFINITY, Vector::zeros());
        for u in [between, normal(&self.a), normal(&self.b)] {
            let length = u.norm();
            if length > 0.0 {
                let u = if u.dot(&between) < 0.0 { -u / length } else { u / length };
                let g = self.gap(&u);
                if g > best.0 {
                    best = (g, u);
                }
            }
        }
        if best.0 > Real::NEG_INFINITY {
            self.slab_time(&best.1, frame, target)
        } else {
            (0.0, Real::NEG_INFINITY)
        }
    }

    /// The full bound (see the module) and the distance.
    #[inline]
    pub(crate) fn exact_time(
        &self,
        frame: &PairFrame,
        target: Real,
        kernel: DistanceKernel,
        horizon: Real,
    ) -> (Real, Real) {
        let closest = match kernel {
            DistanceKernel::Exact => triangle_distance(&self.a, &self.b),
            DistanceKernel::Dyop(formula) => {
                let d = dyop_distance(&self.a, &self.b, formula);
                return (self.head_on_time(d, frame, target), d);
            }
        };
        (self.time_from::<3, 3>(&closest, frame, target, horizon), closest.distance)
    }

    /// The full bound of a ball against a triangle: everything within
    /// `radius` of the point `centre` of one body (a small BVH node's
    /// sphere, `centre` in its mesh's frame) against `triangle` of the
    /// other body (in its mesh's frame); `ball_on_a` says which body the
    /// ball is on. A ball keeps its shape however its body turns, so its
    /// gap is its centre's less `radius`: the bound is the full bound of
    /// the centre as a point (a triangle of three equal vertices) against
    /// the triangle, to `target + radius`. Where the triangle is a long
    /// sliver of a fast spinning body, its turning slab (the frame turning
    /// with the triangle) is far longer than any slab fixed in the world,
    /// which the sliver's tilt sweeps at its length times the spin. The
    /// bound and a lower bound on the distance now.
    #[inline]
    pub(crate) fn ball_time(
        centre: Point,
        radius: Real,
        triangle: Triangle,
        ball_on_a: bool,
        frame: &PairFrame,
        (target, horizon): (Real, Real),
    ) -> (Real, Real) {
        let point = [centre; 3];
        let pair = if ball_on_a {
            PosedPair::of(point, triangle, frame)
        } else {
            PosedPair::of(triangle, point, frame)
        };
        // The point's closest point on the triangle, as a triangle pair's
        // closest points: the point's feature is a vertex.
        let (ball, face) = if ball_on_a { (&pair.a, &pair.b) } else { (&pair.b, &pair.a) };
        let found = point_triangle(&ball[0], face);
        let (point_a, point_b, feature_a, feature_b) = if ball_on_a {
            (ball[0], found.point, Feature::Vertex(0), found.feature)
        } else {
            (found.point, ball[0], found.feature, Feature::Vertex(0))
        };
        let closest = TriangleDistance {
            distance: found.distance,
            point_a,
            point_b,
            feature_a,
            feature_b,
            within_range: true,
        };
        // The point's three equal vertices count once.
        let time = if ball_on_a {
            pair.time_from::<1, 3>(&closest, frame, target + radius, horizon)
        } else {
            pair.time_from::<3, 1>(&closest, frame, target + radius, horizon)
        };
        (time, found.distance - radius)
    }

    /// The full bound of two BVH leaves at once: the turning slab (see
    /// [`TurningSlab`]) of the triangle pair whose centroids are nearest,
    /// its direction and frame taken over every vertex of both leaves, and
    /// the head-on bound of that slab's gap. Where both leaves are flat
    /// patches facing each other (a link's face passing another's nearly
    /// parallel, a small link beside a gear's tooth), this bounds the
    /// leaves' triangle pairs (up to sixteen) about as well as each one's own
    /// bound, for one kernel call. `None` where that pair is within
    /// `target` (the leaves are then bounded pair by pair). The bound and a
    /// lower bound on the leaves' distance now. The leaves are BVH nodes
    /// `i` of `a` and `j` of `b`.
    pub(crate) fn leaves_time(
        (a, i): (&TriMesh, u32),
        (b, j): (&TriMesh, u32),
        frame: &PairFrame,
        (target, horizon): (Real, Real),
    ) -> Option<(Real, Real)> {
        let (leaf_a, leaf_b) = (&a.bvh().nodes()[i as usize], &b.bvh().nodes()[j as usize]);
        let range = |leaf: &BvhNode| leaf.first as usize..(leaf.first + leaf.count) as usize;
        let centroid = |t: &Triangle| (t[0].coords + t[1].coords + t[2].coords) / 3.0;
        let mut nearest = (Real::INFINITY, leaf_a.first as usize, leaf_b.first as usize);
        for tb in range(leaf_b) {
            let cb = frame.rotation * centroid(&b.triangle(tb)) + frame.pos_ab.translation.vector;
            for ta in range(leaf_a) {
                let d2 = (cb - centroid(&a.triangle(ta))).norm_squared();
                if d2 < nearest.0 {
                    nearest = (d2, ta, tb);
                }
            }
        }
        let pair = PosedPair::new(a, nearest.1, b, nearest.2, frame);
        let closest = triangle_distance(&pair.a, &pair.b);
        let d = closest.distance;
        // (Also where the distance is not a number.)
        if d.partial_cmp(&target) != Some(std::cmp::Ordering::Greater) {
            return None;
        }
        let n = (closest.point_b - closest.point_a) / d;
        let spin =
            pair.frame_spin(&closest, &n, frame).unwrap_or(FrameSpin { omega: Vector::zeros(), body: None });
        let turning = TurningSlab::new(&closest, &n, spin, frame, horizon);
        let mut heights_a = [[0.0; 3]; 3 * BVH_LEAF_SIZE];
        let mut reach_a: Real = 0.0;
        let count_a = each_vertex(a, i, |k, p| {
            heights_a[k] = turning.height_a(p);
            reach_a = reach_a.max(p.coords.norm());
        });
        let mut heights_b = [[0.0; 3]; 3 * BVH_LEAF_SIZE];
        let mut reach_b: Real = 0.0;
        let count_b = each_vertex(b, j, |k, p| {
            let offset = Point::from(frame.rotation * p.coords);
            heights_b[k] = turning.height_b(&offset, &(offset + frame.pos_ab.translation.vector));
            reach_b = reach_b.max(offset.coords.norm());
        });
        let (heights_a, heights_b) = (&heights_a[..count_a], &heights_b[..count_b]);
        let high_a = heights_a.iter().map(|h| h[0]).fold(Real::NEG_INFINITY, Real::max);
        let low_b = heights_b.iter().map(|h| h[0]).fold(Real::INFINITY, Real::min);
        let gap = low_b - high_a;
        let speed = frame.head_on_speed(reach_a, reach_b);
        let head_on = if speed > 0.0 { (gap - target) / speed } else { Real::INFINITY };
        Some((turning.time(heights_a, heights_b, target).max(head_on).max(0.0), gap))
    }

    /// The head-on bound: `(d − target)` over the fastest closing of any
    /// two points of the pair.
    #[inline]
    fn head_on_time(&self, d: Real, frame: &PairFrame, target: Real) -> Real {
        let speed = frame.head_on_speed(self.reach_a, self.reach_b);
        if speed > 0.0 {
            (d - target) / speed
        } else {
            Real::INFINITY
        }
    }

    /// The full bound from the pair's closest points: the vertex slab along
    /// their direction, the head-on bound and the turning slab, the longest.
    /// The gaps are the vertices' own (the closest points only choose the
    /// direction and the turning frame), so a rounded closest point costs
    /// tightness, never validity. Over the first `A` vertices of `a` and
    /// `B` of `b`, as [`Self::vertex_slab_time`].
    #[inline]
    fn time_from<const A: usize, const B: usize>(
        &self,
        closest: &TriangleDistance,
        frame: &PairFrame,
        target: Real,
        horizon: Real,
    ) -> Real {
        let d = closest.distance;
        if d <= target {
            return 0.0;
        }
        let n = (closest.point_b - closest.point_a) / d;
        let time = self.vertex_slab_time::<A, B>(&n, frame, target).max(self.head_on_time(d, frame, target));
        if time >= horizon || frame.spin_a + frame.spin_b == 0.0 {
            return time;
        }
        time.max(self.turning_slab_time::<A, B>(closest, &n, frame, target, horizon))
    }

    /// The slab along `n` in a frame that turns with the closest features
    /// (see the module's "A turning slab"): the gap's rate there is the
    /// distance's own, so a pair near its closest approach is bounded to
    /// second order, where a slab fixed in the world loses at first order
    /// to each feature's tilt. At most `horizon`. Over the first `A`
    /// vertices of `a` and `B` of `b`, as [`Self::vertex_slab_time`].
    pub(super) fn turning_slab_time<const A: usize, const B: usize>(
        &self,
        closest: &TriangleDistance,
        n: &Vector,
        frame: &PairFrame,
        target: Real,
        horizon: Real,
    ) -> Real {
        let Some(spin) = self.frame_spin(closest, n, frame) else { return 0.0 };
        let turning = TurningSlab::new(closest, n, spin, frame, horizon);
        let heights_a: [_; A] = std::array::from_fn(|k| turning.height_a(&self.a[k]));
        let heights_b: [_; B] = std::array::from_fn(|k| turning.height_b(&self.offsets_b[k], &self.b[k]));
        turning.time(&heights_a, &heights_b, target)
    }

    /// The turning frame's angular velocity for the closest features:
    /// where one side's feature is a face, or an edge against a vertex,
    /// that side's (the gap's direction then turns with it); for two edges
    /// the least spin that keeps both from tilting across `n` (`None` for
    /// two vertices, or parallel edges: the fixed slab is as good).
    pub(super) fn frame_spin(
        &self,
        closest: &TriangleDistance,
        n: &Vector,
        frame: &PairFrame,
    ) -> Option<FrameSpin> {
        let rank = |feature: Feature| match feature {
            Feature::Vertex(_) => 0,
            Feature::Edge(_) => 1,
            Feature::Face => 2,
        };
        let (fa, fb) = (closest.feature_a, closest.feature_b);
        match (fa, fb) {
            (Feature::Edge(i), Feature::Edge(j)) => {
                let edge = |t: &Triangle, k: u8| {
                    let k = usize::from(k);
                    t[(k + 1) % 3] - t[k]
                };
                let (ua, ub) = (edge(&self.a, i).cross(n), edge(&self.b, j).cross(n));
                // ω·u_a = ω_a·u_a and ω·u_b = ω_b·u_b, ω in their span.
                let (g11, g12, g22) = (ua.dot(&ua), ua.dot(&ub), ub.dot(&ub));
                let det = g11 * g22 - g12 * g12;
                // Parallel edges, or a NaN: no frame of their own.
                if det.is_nan() || det <= PARALLEL_EDGES * g11 * g22 {
                    return None;
                }
                let (ca, cb) = (frame.omega_a.dot(&ua), frame.omega_b.dot(&ub));
                let (alpha, beta) = ((ca * g22 - cb * g12) / det, (cb * g11 - ca * g12) / det);
                Some(FrameSpin { omega: ua * alpha + ub * beta, body: None })
            }
            _ if rank(fa) > rank(fb) => Some(FrameSpin { omega: frame.omega_a, body: Some(Side::A) }),
            _ if rank(fb) > rank(fa) => Some(FrameSpin { omega: frame.omega_b, body: Some(Side::B) }),
            (Feature::Face, Feature::Face) => Some(FrameSpin { omega: frame.omega_a, body: Some(Side::A) }),
            _ => None,
        }
    }
}

/// The angular velocity of a turning slab's frame, and the body it turns
/// with, if it is one body's own (a face's, or an edge's against a vertex).
#[derive(Copy, Clone, Debug)]
pub(super) struct FrameSpin {
    pub omega: Vector,
    pub body: Option<Side>,
}

/// The slab along `n` in a frame turning at `spin` about the midpoint of
/// two closest points (see the module's "A turning slab" in
/// `mesh_bound.rs`): any such frame gives a valid slab, and one that turns
/// with the closest features bounds the distance to second order. Its
/// bound holds for any two vertex sets, a triangle pair's or a leaf
/// pair's: each vertex pair's height difference along `n` stays above
/// `target` until its own first root.
pub(super) struct TurningSlab<'f> {
    frame: &'f PairFrame,
    n: Vector,
    spin: Vector,
    spin_norm: Real,
    /// `|spin × n|`: the frame's normal turns at this rate.
    tilt: Real,
    origin: Vector,
    origin_velocity: Vector,
    /// Each body's centre's speed relative to the origin (a's, b's).
    centre_speeds: (Real, Real),
    /// The curvature of every vertex of a (b) where the frame turns with
    /// a (b), infinite otherwise.
    rigid: (Real, Real),
    horizon: Real,
}

impl<'f> TurningSlab<'f> {
    #[inline]
    pub(super) fn new(
        closest: &TriangleDistance,
        n: &Vector,
        spin: FrameSpin,
        frame: &'f PairFrame,
        horizon: Real,
    ) -> TurningSlab<'f> {
        let origin = (closest.point_a.coords + closest.point_b.coords) / 2.0;
        let origin_velocity =
            (frame.omega_a.cross(&closest.point_a.coords) + velocity_b(frame, &closest.point_b.coords)) / 2.0;
        let centre_speeds = (origin_velocity.norm(), (frame.velocity - origin_velocity).norm());
        let (spin_norm, tilt) = (spin.omega.norm(), spin.omega.cross(n).norm());
        // The body the frame turns with: each of its vertices keeps its
        // height over its centre's, so only the centre's counts.
        let rigid = |centre: Vector, centre_speed: Real| {
            spin_norm * tilt * ((centre - origin).norm() + horizon * centre_speed) + 2.0 * tilt * centre_speed
        };
        let rigid = match spin.body {
            Some(Side::A) => (rigid(Vector::zeros(), centre_speeds.0), Real::INFINITY),
            Some(Side::B) => (Real::INFINITY, rigid(frame.pos_ab.translation.vector, centre_speeds.1)),
            None => (Real::INFINITY, Real::INFINITY),
        };
        TurningSlab {
            frame,
            n: *n,
            spin: spin.omega,
            spin_norm,
            tilt,
            origin,
            origin_velocity,
            centre_speeds,
            rigid,
            horizon,
        }
    }

    /// The origin and its velocity (a's frame, a's centre at rest).
    #[cfg(test)]
    pub(super) fn origin_motion(&self) -> (Vector, Vector) {
        (self.origin, self.origin_velocity)
    }

    /// A vertex's height along `n` in the turning frame, its rate, and the
    /// bound of its second derivative over the horizon: `x` the vertex (a's
    /// frame), `offset` its offset from its body's centre, `velocity` its
    /// velocity, `centre_speed` its body centre's speed relative to the
    /// origin, `omega` its body's spin, `rigid` the bound where the frame
    /// turns with its body (infinite otherwise).
    #[inline]
    fn height(
        &self,
        x: &Vector,
        offset: &Vector,
        velocity: Vector,
        (centre_speed, omega): (Real, Real),
        rigid: Real,
    ) -> [Real; 3] {
        let (q, dq) = (x - self.origin, velocity - self.origin_velocity);
        let reach = offset.norm();
        let speed = centre_speed + omega * reach;
        let (spin_norm, tilt) = (self.spin_norm, self.tilt);
        let curvature =
            omega * omega * reach + 2.0 * tilt * speed + spin_norm * tilt * (q.norm() + self.horizon * speed);
        [self.n.dot(&q), self.n.dot(&(dq - self.spin.cross(&q))), curvature.min(rigid)]
    }

    /// The height, rate and curvature of a vertex of `a` (in a's frame,
    /// its offset from a's centre).
    #[inline]
    pub(super) fn height_a(&self, p: &Point) -> [Real; 3] {
        let frame = self.frame;
        let motion = (self.centre_speeds.0, frame.spin_a);
        self.height(&p.coords, &p.coords, frame.omega_a.cross(&p.coords), motion, self.rigid.0)
    }

    /// ... of a vertex of `b`: `offset` from b's centre and the point, both
    /// in a's frame.
    #[inline]
    pub(super) fn height_b(&self, offset: &Point, p: &Point) -> [Real; 3] {
        let frame = self.frame;
        let motion = (self.centre_speeds.1, frame.spin_b);
        self.height(&p.coords, &offset.coords, velocity_b(frame, &p.coords), motion, self.rigid.1)
    }

    /// The least first root over the vertex pairs, from their heights
    /// ([`Self::height_a`], [`Self::height_b`]), at most the horizon.
    #[inline]
    pub(super) fn time(&self, heights_a: &[[Real; 3]], heights_b: &[[Real; 3]], target: Real) -> Real {
        let mut time = self.horizon;
        for &[height, rate, curvature] in heights_b {
            for &[height_a, rate_a, curvature_a] in heights_a {
                time =
                    time.min(first_root(height - height_a - target, rate - rate_a, curvature + curvature_a));
            }
        }
        time
    }
}

/// The velocity of the point `x` of `b` (a's frame; a's centre is the
/// origin, at rest: a velocity shared by everything changes no distance).
#[inline]
fn velocity_b(frame: &PairFrame, x: &Vector) -> Vector {
    frame.velocity + frame.omega_b.cross(&(x - frame.pos_ab.translation.vector))
}

/// Calls `visit` with each vertex of leaf node `k`'s triangles once (its
/// index among them and the point, in `mesh`'s frame), from the mesh's
/// list of the leaf's distinct vertices; how many there were.
#[inline]
fn each_vertex(mesh: &TriMesh, k: u32, mut visit: impl FnMut(usize, &Point)) -> usize {
    let vertices = mesh.leaf_vertices(k);
    for (count, &v) in vertices.iter().enumerate() {
        visit(count, &mesh.vertices()[v as usize]);
    }
    vertices.len()
}

//! Seeded input classes shared by the tests, the benchmarks and the kernel
//! report, so that all three measure the same inputs.
//!
//! Every generator is deterministic in its seed (a SplitMix64 stream). The
//! expected distances are never taken from here: placement uses the f64
//! kernel only to aim at a gap, and the tests compare against the exact
//! rational reference.

use crate::kernels::triangle_distance;
use crate::math::{max_abs_coordinate, to_parry, triangle_to_parry, Point, Real, Triangle, Vector};
use crate::motion::StepMotion;

/// A small deterministic random stream (SplitMix64, Steele, Lea and Flood,
/// "Fast splittable pseudorandom number generators", OOPSLA 2014).
#[derive(Clone, Debug)]
pub struct Rng {
    state: u64,
}

impl Rng {
    /// A stream from a seed.
    pub fn new(seed: u64) -> Rng {
        Rng { state: seed ^ 0x5DEE_CE66_D1CE_4E5B }
    }

    /// The next 64 random bits.
    pub fn next_u64(&mut self) -> u64 {
        self.state = self.state.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = self.state;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        z ^ (z >> 31)
    }

    /// Uniform in `[0, 1)`, 53 random bits.
    pub fn uniform(&mut self) -> Real {
        (self.next_u64() >> 11) as Real * (1.0 / (1u64 << 53) as Real)
    }

    /// Uniform in `[lo, hi)`.
    pub fn range(&mut self, lo: Real, hi: Real) -> Real {
        lo + (hi - lo) * self.uniform()
    }

    /// Log-uniform in `[lo, hi)` (both positive).
    pub fn log_range(&mut self, lo: Real, hi: Real) -> Real {
        (lo.ln() + (hi.ln() - lo.ln()) * self.uniform()).exp()
    }

    /// Uniform index in `0..n` (`n > 0`).
    pub fn index(&mut self, n: usize) -> usize {
        (self.uniform() * n as Real) as usize % n.max(1)
    }

    /// Uniform in the unit ball.
    pub fn in_unit_ball(&mut self) -> Vector {
        loop {
            let v = Vector::new(self.range(-1.0, 1.0), self.range(-1.0, 1.0), self.range(-1.0, 1.0));
            if v.norm_squared() <= 1.0 {
                return v;
            }
        }
    }

    /// Uniform on the unit sphere.
    pub fn unit_vector(&mut self) -> Vector {
        loop {
            let v = self.in_unit_ball();
            let n = v.norm();
            if n > 0.1 {
                return v / n;
            }
        }
    }
}

/// The input classes on which kernels are tested, benchmarked and reported.
#[derive(Copy, Clone, Debug, PartialEq, Eq, Hash)]
pub enum InputClass {
    /// Random unit-size triangles (no sliver) about 1 to 3 apart; for
    /// point–segment, a point 0.1 to 1 from a unit segment.
    WellConditioned,
    /// Separated pairs at a gap log-uniform in `[1e-12, 1e-1]`.
    NearlyTouching,
    /// Needles: for point–segment a point `1e-12..1e-8` from a unit edge;
    /// for triangles a sliver triangle (height `1e-12..1e-8`) nearly
    /// touching a unit triangle.
    Needle,
    /// Nearly touching pairs (point–segment: needles) offset by about 1e6.
    Offset1e6,
    /// A pair of (nearly) parallel edges, a gap `1e-9..1e-1` apart.
    ParallelEdges,
    /// Coplanar triangles (in `z = 0` exactly, or a rotated plane up to
    /// rounding), separated by `1e-9..1e-1` or overlapping.
    Coplanar,
    /// Triangles that cross each other.
    Intersecting,
    /// Repeated, collinear or coincident vertices, near another triangle.
    Degenerate,
}

impl InputClass {
    /// Every class, in report order.
    pub const ALL: [InputClass; 8] = [
        InputClass::WellConditioned,
        InputClass::NearlyTouching,
        InputClass::Needle,
        InputClass::Offset1e6,
        InputClass::ParallelEdges,
        InputClass::Coplanar,
        InputClass::Intersecting,
        InputClass::Degenerate,
    ];

    /// A short name for reports.
    pub fn name(self) -> &'static str {
        match self {
            InputClass::WellConditioned => "well-conditioned",
            InputClass::NearlyTouching => "nearly-touching",
            InputClass::Needle => "needle",
            InputClass::Offset1e6 => "offset-1e6",
            InputClass::ParallelEdges => "parallel-edges",
            InputClass::Coplanar => "coplanar",
            InputClass::Intersecting => "intersecting",
            InputClass::Degenerate => "degenerate",
        }
    }
}

/// `count` triangle pairs of `class`, deterministic in `seed`.
pub fn triangle_pairs(class: InputClass, count: usize, seed: u64) -> Vec<(Triangle, Triangle)> {
    let mut rng = Rng::new(seed ^ (class as u64) << 32);
    (0..count).map(|_| triangle_pair(class, &mut rng)).collect()
}

/// Pairs where candidates of the triangle kernel tie exactly: coincident
/// and stacked triangles, shared vertices and edges, parallel edges and
/// faces, repeated and collinear vertices; each also scaled by 1e-120 and
/// 1e150 (beyond the range computed unscaled).
pub fn tied_pairs() -> Vec<(Triangle, Triangle)> {
    let p = Point::new;
    let unit = [p(0.0, 0.0, 0.0), p(1.0, 0.0, 0.0), p(0.0, 1.0, 0.0)];
    let pairs = [
        (unit, unit),
        (unit, unit.map(|v| v + Vector::new(0.0, 0.0, 0.25))),
        (unit, [p(0.0, 0.0, 0.0), p(-1.0, 0.0, 0.5), p(0.0, -1.0, 0.5)]),
        (unit, [p(1.0, 0.0, 0.0), p(0.0, 1.0, 0.0), p(1.0, 1.0, 0.0)]),
        (unit, [p(2.0, 0.0, 0.0), p(3.0, 0.0, 0.0), p(2.0, 1.0, 0.0)]),
        (unit, [p(0.0, 0.0, 1.0), p(1.0, 0.0, 1.0), p(0.5, 0.0, 2.0)]),
        (unit, [p(0.5, 0.5, 1.0), p(0.5, 0.5, 1.0), p(0.5, 0.5, 1.0)]),
        (unit, [p(2.0, 0.0, 0.0), p(3.0, 0.0, 0.0), p(4.0, 0.0, 0.0)]),
        ([p(0.0, 0.0, 0.0); 3], [p(0.0, 0.0, 1.0); 3]),
        (unit, [p(0.25, 0.25, 0.5), p(0.25, 0.25, 0.5), p(0.75, 0.75, 0.5)]),
    ];
    let scaled = |k: Real, t: &Triangle| t.map(|v| Point::from(v.coords * k));
    [1.0, 1e-120, 1e150]
        .into_iter()
        .flat_map(|k| pairs.iter().map(move |(a, b)| (scaled(k, a), scaled(k, b))))
        .collect()
}

/// `count` nearly touching pairs with gaps log-uniform in `[gap_lo, gap_hi)`
/// (the benchmark inputs use `1e-3..1e-1`).
pub fn nearly_touching_pairs(
    count: usize,
    gap_lo: Real,
    gap_hi: Real,
    seed: u64,
) -> Vec<(Triangle, Triangle)> {
    let mut rng = Rng::new(seed);
    (0..count)
        .map(|_| {
            let gap = rng.log_range(gap_lo, gap_hi);
            let (a, b) = separated_pair(&mut rng, 1.0);
            at_gap(a, b, gap)
        })
        .collect()
}

/// `count` point–segment queries `(p, a, b)` of `class`. Triangle-only
/// classes fall back to their nearest point–segment meaning (parallel,
/// coplanar, intersecting: a point 0 to 1e-3 from the segment; degenerate: a
/// zero-length or 1e-12-long segment).
pub fn point_segment_queries(class: InputClass, count: usize, seed: u64) -> Vec<(Point, Point, Point)> {
    let mut rng = Rng::new(seed ^ (class as u64) << 40);
    (0..count)
        .map(|_| {
            let a = Point::from(rng.in_unit_ball());
            let direction = rng.unit_vector();
            let perpendicular = direction.cross(&rng.unit_vector()).normalize();
            let along = rng.range(-0.2, 1.2);
            let (length, height, offset) = match class {
                InputClass::WellConditioned => (1.0, rng.range(0.1, 1.0), 0.0),
                InputClass::NearlyTouching => (1.0, rng.log_range(1e-12, 1e-1), 0.0),
                InputClass::Needle => (1.0, rng.log_range(1e-12, 1e-8), 0.0),
                InputClass::Offset1e6 => (1.0, rng.log_range(1e-12, 1e-1), 1e6),
                InputClass::ParallelEdges | InputClass::Coplanar | InputClass::Intersecting => {
                    (1.0, rng.range(0.0, 1e-3), 0.0)
                }
                InputClass::Degenerate => {
                    (if rng.uniform() < 0.5 { 0.0 } else { 1e-12 }, rng.range(0.0, 1.0), 0.0)
                }
            };
            let shift = Vector::new(offset, -offset, offset);
            let b = a + direction * length;
            let p = a + direction * (along * length.max(1.0)) + perpendicular * height;
            (p + shift, a + shift, b + shift)
        })
        .collect()
}

fn triangle_pair(class: InputClass, rng: &mut Rng) -> (Triangle, Triangle) {
    match class {
        InputClass::WellConditioned => separated_pair(rng, 2.0),
        InputClass::NearlyTouching => {
            let gap = rng.log_range(1e-12, 1e-1);
            let (a, b) = separated_pair(rng, 1.0);
            at_gap(a, b, gap)
        }
        InputClass::Needle => {
            let a = unit_triangle(rng, Vector::zeros());
            let height = rng.log_range(1e-12, 1e-8);
            let direction = rng.unit_vector();
            let perpendicular = direction.cross(&rng.unit_vector()).normalize();
            let base = Point::from(rng.in_unit_ball() + rng_offset(rng));
            let sliver =
                [base, base + direction, base + direction * rng.range(0.1, 0.9) + perpendicular * height];
            at_gap(a, sliver, rng.log_range(1e-12, 1e-1))
        }
        InputClass::Offset1e6 => {
            let gap = rng.log_range(1e-12, 1e-1);
            let (a, b) = separated_pair(rng, 1.0);
            let (a, b) = at_gap(a, b, gap);
            let shift = Vector::new(1e6, -1e6, 1e6) + rng.in_unit_ball() * 1e5;
            (a.map(|v| v + shift), b.map(|v| v + shift))
        }
        InputClass::ParallelEdges => {
            let a = unit_triangle(rng, Vector::zeros());
            let edge = a[1] - a[0];
            let inward = a[2] - a[0];
            // Away from a's third vertex, perpendicular to the edge.
            let away = (edge.cross(&inward).cross(&edge) * -1.0).normalize();
            let tilt = edge.cross(&away).normalize() * rng.range(-1.0, 1.0);
            let offset = (away + tilt).normalize() * rng.log_range(1e-9, 1e-1) + edge * rng.range(-0.5, 0.5);
            let third = a[0] + offset + away * rng.range(0.5, 1.0) + edge * rng.range(0.0, 1.0);
            (a, [a[0] + offset, a[1] + offset, third])
        }
        InputClass::Coplanar => {
            let exact_plane = rng.uniform() < 0.5;
            let (u, v) = if exact_plane {
                (Vector::x(), Vector::y())
            } else {
                let u = rng.unit_vector();
                (u, u.cross(&rng.unit_vector()).normalize())
            };
            let flat = |rng: &mut Rng, cx: Real| {
                [0, 1, 2].map(|_| Point::from(u * (cx + rng.range(-0.5, 0.5)) + v * rng.range(-0.5, 0.5)))
            };
            let a = flat(rng, 0.0);
            let cx = rng.range(0.5, 1.5);
            let b = flat(rng, cx);
            if rng.uniform() < 0.3 {
                (a, b)
            } else {
                let (a, b) = at_gap(a, b, rng.log_range(1e-9, 1e-1));
                (a, b)
            }
        }
        InputClass::Intersecting => {
            let a = unit_triangle(rng, Vector::zeros());
            let normal = (a[1] - a[0]).cross(&(a[2] - a[0])).normalize();
            let (w0, w1) = (rng.range(0.05, 0.9), rng.range(0.05, 0.9));
            let (w0, w1) = if w0 + w1 > 0.95 { (1.0 - w0, 1.0 - w1) } else { (w0, w1) };
            let inside = a[0] + (a[1] - a[0]) * w0 + (a[2] - a[0]) * w1;
            let across = normal + rng.in_unit_ball() * 0.5;
            let below = inside - across * rng.range(0.1, 1.0);
            let above = inside + across * rng.range(0.1, 1.0);
            (a, [below, above, above + rng.in_unit_ball()])
        }
        InputClass::Degenerate => {
            let (a, b) = separated_pair(rng, 1.0);
            let b = match rng.index(4) {
                0 => [b[0], b[0], b[2]],
                1 => [b[0], b[1], b[0] + (b[1] - b[0]) * rng.range(-0.5, 1.5)],
                2 => [b[0], b[0], b[0]],
                _ => [b[0], b[1], b[1]],
            };
            let (a, b) = at_gap(a, b, rng.log_range(1e-9, 1e-1));
            if rng.uniform() < 0.5 {
                (b, a)
            } else {
                (a, b)
            }
        }
    }
}

/// A random triangle of unit size about `center`, not a sliver: its area is
/// at least a tenth of its longest edge squared.
fn unit_triangle(rng: &mut Rng, center: Vector) -> Triangle {
    loop {
        let t = [0, 1, 2].map(|_| Point::from(center + rng.in_unit_ball()));
        let longest = (0..3).map(|i| (t[(i + 1) % 3] - t[i]).norm_squared()).fold(0.0, Real::max);
        if (t[1] - t[0]).cross(&(t[2] - t[0])).norm() * 0.5 >= 0.1 * longest {
            return t;
        }
    }
}

fn rng_offset(rng: &mut Rng) -> Vector {
    rng.unit_vector() * rng.range(1.5, 2.5)
}

/// Two unit triangles, the second centred `scale × (1.5..2.5)` away.
fn separated_pair(rng: &mut Rng, scale: Real) -> (Triangle, Triangle) {
    let a = unit_triangle(rng, Vector::zeros());
    let offset = rng_offset(rng) * scale;
    (a, unit_triangle(rng, offset))
}

/// `b` translated along the direction of closest approach so that its
/// distance to `a` is close to `gap` (translation along that direction
/// changes the distance of convex sets by exactly the translation, up to the
/// rounding of the new coordinates).
fn at_gap(a: Triangle, b: Triangle, gap: Real) -> (Triangle, Triangle) {
    let closest = triangle_distance(&a, &b);
    let between = closest.point_b - closest.point_a;
    if closest.distance <= 0.0 {
        return (a, b);
    }
    let shift = between * ((gap - closest.distance) / closest.distance);
    (a, b.map(|v| v + shift))
}

/// Rotating mesh–mesh cases: an icosphere of 320 triangles and one of 1280
/// (radius 1), 5 apart along x, closing at about 4 with random offsets and
/// random spins up to 10 rad/s (both tumbling, offset approach), over
/// `t ∈ [0, 1]`. Shared by the mesh CCD benchmark and the parry comparison.
pub fn tumbling_cases(
    count: usize,
    seed: u64,
) -> (crate::mesh::TriMesh, crate::mesh::TriMesh, Vec<(StepMotion, StepMotion)>) {
    icosphere_cases(count, seed, 10.0)
}

/// [`tumbling_cases`] without the spins: the same meshes, random
/// orientations and offsets, translating only.
pub fn translating_cases(
    count: usize,
    seed: u64,
) -> (crate::mesh::TriMesh, crate::mesh::TriMesh, Vec<(StepMotion, StepMotion)>) {
    icosphere_cases(count, seed, 0.0)
}

/// The cases of [`tumbling_cases`] with spins up to `spin`.
fn icosphere_cases(
    count: usize,
    seed: u64,
    spin: Real,
) -> (crate::mesh::TriMesh, crate::mesh::TriMesh, Vec<(StepMotion, StepMotion)>) {
    let a = crate::mesh::icosphere(1.0, 2).expect("a valid icosphere");
    let b = crate::mesh::icosphere(1.0, 3).expect("a valid icosphere");
    (a, b, approach_cases(count, seed, spin))
}

/// Two bodies of radius about 1 on a head-on course (offset up to 0.8),
/// meeting about halfway through `[0, 1]`, random orientations, spins up
/// to `spin` (the motions of [`tumbling_cases`], for any two meshes).
pub fn approach_cases(count: usize, seed: u64, spin: Real) -> Vec<(StepMotion, StepMotion)> {
    use crate::math::Pose;
    let mut rng = Rng::new(seed);
    (0..count)
        .map(|_| {
            let motion_a = StepMotion::new(
                Pose::new(Vector::new(-2.5, 0.0, 0.0), rng.in_unit_ball() * 3.0),
                Vector::new(2.0, 0.0, 0.0) + rng.in_unit_ball() * 0.3,
                rng.in_unit_ball() * spin,
            );
            let motion_b = StepMotion::new(
                Pose::new(Vector::new(2.5, 0.0, 0.0) + rng.in_unit_ball() * 0.8, rng.in_unit_ball() * 3.0),
                Vector::new(-2.0, 0.0, 0.0),
                rng.in_unit_ball() * spin,
            );
            (motion_a, motion_b)
        })
        .collect()
}

/// parry3d-f64's distance between two triangles given in world coordinates.
/// An unsupported pair (never for triangles) is reported as NaN, not hidden.
pub fn parry_triangle_distance(a: &Triangle, b: &Triangle) -> Real {
    use parry3d_f64::math::Pose;
    let identity = Pose::IDENTITY;
    parry3d_f64::query::distance(&identity, &triangle_to_parry(a), &identity, &triangle_to_parry(b))
        .map(|d| d.distance)
        .unwrap_or(Real::NAN)
}

/// The extent of a pair of triangles about the first vertex of `a`.
pub fn pair_extent(a: &Triangle, b: &Triangle) -> Real {
    let local: Vec<Point> = a.iter().chain(b).map(|v| Point::from(v - a[0])).collect();
    max_abs_coordinate(&local).max(Real::MIN_POSITIVE)
}

/// The extent of a point–segment query about `a`.
pub fn query_extent(p: &Point, a: &Point, b: &Point) -> Real {
    max_abs_coordinate(&[Point::from(p - a), Point::from(b - a)]).max(Real::MIN_POSITIVE)
}

/// parry's point–segment distance (for cross-checks).
pub fn parry_point_segment_distance(p: &Point, a: &Point, b: &Point) -> Real {
    use parry3d_f64::query::PointQuery;
    let segment = parry3d_f64::shape::Segment::new(to_parry(a), to_parry(b));
    segment.distance_to_local_point(to_parry(p), true)
}

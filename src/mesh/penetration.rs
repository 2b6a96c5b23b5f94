//! The penetration depth of two convex meshes: the length and direction of
//! the shortest translation that separates the solids they bound.
//!
//! ## Method: separating axes over the Minkowski difference's facets
//! Two convex solids `A` and `B` overlap iff the origin is inside their
//! Minkowski difference `K = A − B`, and the shortest translation of `B`
//! that separates them is the distance from the origin to `K`'s boundary:
//! the least, over `K`'s facet normals `u` (unit, outward), of how far `K`
//! reaches along `u`. Every facet of `K` is either a face of `A` (normal
//! `n_A`), a face of `B` (normal `−n_B`), or the sum of an edge of `A` and
//! an edge of `B` whose arcs on the Gauss map cross (the edge pair forms a
//! "Minkowski face", normal `±e_A × e_B`). Along a face normal `n` of `A`
//! (outward, through its point `p`) the solids are apart by
//! `s = min_b n·(b − p)` over `B`'s vertices (the support of `B` along
//! `−n`); along an edge pair's axis `u` (oriented out of `A` at its edge),
//! by `s = u·(p_B − p_A)`. The largest `s` over every candidate decides:
//! `s > 0`, the solids are apart (and `s` bounds their distance from
//! below); otherwise the depth is `−s` and `B` moved by `−s` along that
//! axis touches `A`. Exact to the rounding of the dot products (a few
//! ulps of the meshes' extent), with no iteration: the answer is a
//! maximum over finitely many candidates, unlike GJK/EPA's tolerance.
//!
//! Cost: every face of each mesh against the other's support (from its
//! direction table), and the edge pairs whose arcs can cross: each arc on
//! the unit sphere lies in the triangle of its ends and the meeting point
//! of their tangents, so in that triangle's box; `A`'s boxes are sorted
//! once per mesh, `−B`'s each query, and a sweep along x hands only the
//! pairs whose boxes overlap to the exact Gauss-map test (on fine meshes a
//! few percent of `E_A·E_B`). Edges between coplanar triangles (a box
//! face's diagonal) are not edges of the solid and are skipped.

use super::convex_features::FeatureEdge;
use super::trimesh::TriMesh;
use crate::math::{Point, Pose, Real, Vector};

/// Edge pairs whose directions are closer to parallel than this sine are
/// skipped: their cross product has no reliable direction, and the facet
/// they would form is a sliver whose neighbours (the edges' faces) are
/// tested. Default `1e-10`.
pub(crate) const PARALLEL_EDGE_SINE: Real = 1e-10;

/// The shortest translation that separates two convex solids.
#[derive(Copy, Clone, Debug, PartialEq)]
pub struct MeshPenetration {
    /// Its length (0 when the solids only touch).
    pub depth: Real,
    /// Its unit direction, world frame: mesh `b` moved by
    /// `depth * direction` (or `a` by the opposite) touches `a`.
    pub direction: Vector,
    /// The deepest point of `b`'s solid in `a`'s, world frame.
    pub point_b: Point,
    /// Where `point_b` comes to rest on `a`'s surface:
    /// `point_b + depth * direction`.
    pub point_a: Point,
}

/// Reusable buffers of [`convex_penetration_with`]: `b`'s edges in `a`'s
/// frame, so queries do not allocate once it has grown.
#[derive(Clone, Debug, Default)]
pub struct PenetrationScratch {
    edges_b: Vec<FeatureEdge>,
}

/// A mesh is not convex ([`TriMesh::is_convex`]): its solid has no
/// separating-axis depth.
#[derive(Copy, Clone, Debug, PartialEq, Eq, thiserror::Error)]
#[error("mesh {which} is not convex: the separating-axis depth needs convex meshes")]
pub struct NotConvex {
    /// `'a'` or `'b'`.
    pub which: char,
}

/// The penetration of convex meshes `a` at `pose_a` and `b` at `pose_b`
/// as solids: `Ok(None)` when they are apart, an error when either mesh
/// is not convex. See the module for the method.
///
/// ```
/// use nearmiss::math::{Pose, Vector};
/// use nearmiss::mesh::{box_mesh, convex_penetration};
/// let cube = box_mesh(&Vector::new(1.0, 1.0, 1.0)).unwrap();
/// // Two unit cubes 1.75 apart overlap by 0.25 along x.
/// let found = convex_penetration(&cube, &Pose::identity(), &cube, &Pose::translation(1.75, 0.0, 0.0));
/// let found = found.unwrap().unwrap();
/// assert_eq!((found.depth, found.direction), (0.25, Vector::x()));
/// ```
pub fn convex_penetration(
    a: &TriMesh,
    pose_a: &Pose,
    b: &TriMesh,
    pose_b: &Pose,
) -> Result<Option<MeshPenetration>, NotConvex> {
    convex_penetration_with(a, pose_a, b, pose_b, &mut PenetrationScratch::default())
}

/// [`convex_penetration`] with reusable buffers.
pub fn convex_penetration_with(
    a: &TriMesh,
    pose_a: &Pose,
    b: &TriMesh,
    pose_b: &Pose,
    scratch: &mut PenetrationScratch,
) -> Result<Option<MeshPenetration>, NotConvex> {
    for (mesh, which) in [(a, 'a'), (b, 'b')] {
        if !mesh.is_convex() {
            return Err(NotConvex { which });
        }
    }
    Ok(separating_axes(a, pose_a, b, pose_b, scratch))
}

/// The method of [`convex_penetration`] on meshes known to be convex.
fn separating_axes(
    a: &TriMesh,
    pose_a: &Pose,
    b: &TriMesh,
    pose_b: &Pose,
    scratch: &mut PenetrationScratch,
) -> Option<MeshPenetration> {
    let (fa, fb) = (a.convex_features(), b.convex_features());
    // Work in a's frame: b's features moved by pos_ab.
    let pos_ab = pose_a.inv_mul(pose_b);
    let pos_ba = pos_ab.inverse();
    let mut best = Axis { separation: Real::NEG_INFINITY, direction: Vector::z(), point_b: Point::origin() };
    // A's faces: b's support against the normal.
    for (n, p) in &fa.faces {
        let deepest = pos_ab * b.vertices()[b.farthest_vertex(&(pos_ba.rotation * -n))];
        best.offer((deepest - p).dot(n), *n, deepest);
        if best.separation > 0.0 {
            return None;
        }
    }
    // B's faces: a's support against the normal; b moves against it.
    for (m, q) in &fb.faces {
        let (m, q) = (pos_ab.rotation * m, pos_ab * q);
        let deepest_a = a.vertices()[a.farthest_vertex(&-m)];
        let separation = (deepest_a - q).dot(&m);
        // B's point deepest in A: a's vertex moved back onto b's plane.
        best.offer(separation, -m, deepest_a - m * separation);
        if best.separation > 0.0 {
            return None;
        }
    }
    // Edge pairs that form a face of the Minkowski difference: b's edges
    // in a's frame, their arcs those of −B (b's normals negated), swept
    // against a's along x; only pairs whose arc boxes overlap are tested.
    scratch.edges_b.clear();
    scratch.edges_b.extend(fb.edges.iter().map(|e| {
        let normals = e.normals.map(|m| -(pos_ab.rotation * m));
        FeatureEdge::new(pos_ab * e.point, pos_ab.rotation * e.direction, normals)
    }));
    scratch.edges_b.sort_by(|e, f| e.arc_box.low.x.total_cmp(&f.arc_box.low.x));
    let (edges_a, edges_b) = (&fa.edges, &scratch.edges_b);
    let test = |best: &mut Axis, ea: &FeatureEdge, eb: &FeatureEdge| {
        if !ea.arc_box.overlaps_in_y_z(&eb.arc_box) {
            return;
        }
        let ([na, nb], [c, d]) = (ea.normals, eb.normals);
        if !is_minkowski_face(&na, &nb, &ea.normals_cross, &c, &d, &eb.normals_cross) {
            return;
        }
        let axis = ea.direction.cross(&eb.direction);
        let length = axis.norm();
        if length <= PARALLEL_EDGE_SINE * ea.direction.norm() * eb.direction.norm() {
            return;
        }
        let mut u = axis / length;
        if u.dot(&(ea.point - fa.interior)) < 0.0 {
            u = -u;
        }
        let separation = u.dot(&(eb.point - ea.point));
        best.offer(separation, u, closest_on_line(&eb.point, &eb.direction, &ea.point, &ea.direction));
    };
    // Each pair whose boxes overlap along x is met once: by whichever of
    // the two starts first.
    let (mut i, mut j) = (0, 0);
    while i < edges_a.len() && j < edges_b.len() {
        if edges_a[i].arc_box.low.x <= edges_b[j].arc_box.low.x {
            let reach = edges_a[i].arc_box.high.x;
            for eb in edges_b[j..].iter().take_while(|e| e.arc_box.low.x <= reach) {
                test(&mut best, &edges_a[i], eb);
            }
            i += 1;
        } else {
            let reach = edges_b[j].arc_box.high.x;
            for ea in edges_a[i..].iter().take_while(|e| e.arc_box.low.x <= reach) {
                test(&mut best, ea, &edges_b[j]);
            }
            j += 1;
        }
        if best.separation > 0.0 {
            return None;
        }
    }
    let depth = (-best.separation).max(0.0);
    let direction = pose_a.rotation * best.direction;
    let point_b = pose_a * best.point_b;
    Some(MeshPenetration { depth, direction, point_b, point_a: point_b + direction * depth })
}

/// The axis of largest separation so far.
struct Axis {
    separation: Real,
    direction: Vector,
    point_b: Point,
}

impl Axis {
    #[inline]
    fn offer(&mut self, separation: Real, direction: Vector, point_b: Point) {
        if separation > self.separation {
            *self = Axis { separation, direction, point_b };
        }
    }
}

/// Whether the Gauss arc from `a` to `b` (an edge of `A`, `b_x_a = b × a`)
/// crosses the arc from `c` to `d` (an edge of `−B`, `d_x_c = d × c`):
/// then the two edges form a face of `A − B`. The arcs cross iff `c` and
/// `d` lie on opposite sides of the plane of `a, b`, `a` and `b` on
/// opposite sides of the plane of `c, d`, and both on one hemisphere.
#[inline]
fn is_minkowski_face(a: &Vector, b: &Vector, b_x_a: &Vector, c: &Vector, d: &Vector, d_x_c: &Vector) -> bool {
    let cba = c.dot(b_x_a);
    let dba = d.dot(b_x_a);
    let adc = a.dot(d_x_c);
    let bdc = b.dot(d_x_c);
    cba * dba < 0.0 && adc * bdc < 0.0 && cba * bdc > 0.0
}

/// The point of the line through `p` along `u` closest to the line through
/// `q` along `v` (the lines not parallel).
fn closest_on_line(p: &Point, u: &Vector, q: &Point, v: &Vector) -> Point {
    let w = p - q;
    let (uu, uv, vv, uw, vw) = (u.dot(u), u.dot(v), v.dot(v), u.dot(&w), v.dot(&w));
    let denominator = uu * vv - uv * uv;
    if denominator <= 0.0 {
        return *p;
    }
    p + u * ((uv * vw - vv * uw) / denominator)
}

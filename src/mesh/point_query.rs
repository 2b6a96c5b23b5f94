//! The signed distance from a point to a closed mesh: negative inside.
//!
//! The closest point is found by a descent of the mesh's BVH (nearest node
//! first, nodes farther than the best found pruned) with the point–triangle
//! kernel at the leaves. Inside or outside is read from the closest
//! feature's angle-weighted pseudo-normal (Bærentzen and Aanæs, "Signed
//! distance computation using the angle weighted pseudonormal", IEEE TVCG
//! 2005): for a closed, consistently oriented surface, the point is
//! outside iff it lies on the side of the closest point's pseudo-normal:
//! the face's normal in a face's interior, the sum of the two faces'
//! normals on an edge, the sum of the faces' normals weighted by their
//! angles at a vertex. So no ray is cast and no parity can be fooled by a
//! ray grazing an edge.

use super::distance::PRUNE_SLACK_ULPS;
use super::trimesh::TriMesh;
use crate::kernels::{point_triangle, Feature};
use crate::math::{Point, Real, Vector};

/// A point's signed distance to a closed mesh.
#[derive(Copy, Clone, Debug, PartialEq)]
pub struct PointSignedDistance {
    /// The distance to the surface: negative inside the solid, 0 on the
    /// surface.
    pub distance: Real,
    /// The closest point of the surface.
    pub closest: Point,
    /// Its triangle.
    pub triangle: usize,
    /// Its feature on that triangle.
    pub feature: Feature,
}

/// Reusable buffers of [`point_signed_distance`].
#[derive(Clone, Debug, Default)]
pub struct PointQueryScratch {
    stack: Vec<(u32, Real)>,
}

/// The signed distance from `point` (in the mesh's frame) to `mesh`, which
/// must be closed and consistently oriented ([`TriMesh::check_closed`];
/// either orientation: an inside-out mesh, of negative volume, is read the
/// other way round).
pub fn point_signed_distance(
    mesh: &TriMesh,
    point: &Point,
    scratch: &mut PointQueryScratch,
) -> PointSignedDistance {
    let nodes = mesh.bvh().nodes();
    let slack = PRUNE_SLACK_ULPS * Real::EPSILON * (point.coords.norm() + mesh.radius());
    let bound = |i: u32| {
        let node = &nodes[i as usize];
        let offset = point - node.center;
        let boxes = (node.axes.tr_mul(&offset).abs() - node.half_extents).sup(&Vector::zeros()).norm();
        boxes.max(offset.norm() - node.radius) - slack
    };
    let mut best = (Real::INFINITY, Point::origin(), 0usize, Feature::Face);
    scratch.stack.clear();
    scratch.stack.push((0, bound(0)));
    while let Some((i, lower)) = scratch.stack.pop() {
        if lower >= best.0 {
            continue;
        }
        let node = &nodes[i as usize];
        if node.is_leaf() {
            for t in node.first..node.first + node.count {
                let found = point_triangle(point, &mesh.triangle(t as usize));
                if found.distance < best.0 {
                    best = (found.distance, found.point, t as usize, found.feature);
                }
            }
            continue;
        }
        let children = [node.first, node.first + 1].map(|c| (c, bound(c)));
        let order = if children[0].1 <= children[1].1 { [1, 0] } else { [0, 1] };
        for k in order {
            if children[k].1 < best.0 {
                scratch.stack.push(children[k]);
            }
        }
    }
    let (distance, closest, triangle, feature) = best;
    let outside = match pseudo_normal(mesh, triangle, feature) {
        Some(normal) => (point - closest).dot(&(normal * mesh.orientation())) >= 0.0,
        // A zero-area triangle takes part: it has no side, so the winding
        // number decides (its solid angle is zero; the others' sum to ±1
        // inside a closed surface, 0 outside).
        None => winding_number(mesh, point).abs() < 0.5,
    };
    PointSignedDistance { distance: if outside { distance } else { -distance }, closest, triangle, feature }
}

/// The angle-weighted pseudo-normal at `feature` of `triangle` (not
/// normalised; the mesh's own orientation), or `None` where a triangle of
/// zero area is one of those it is made of (it has no normal, and the
/// geometric neighbours across it are not its neighbours by index).
fn pseudo_normal(mesh: &TriMesh, triangle: usize, feature: Feature) -> Option<Vector> {
    let corners = mesh.triangles()[triangle];
    let unit_normal = |t: usize| {
        let [p, q, r] = mesh.triangle(t);
        (q - p).cross(&(r - p)).try_normalize(0.0).filter(|_| !mesh.is_zero_area(t))
    };
    match feature {
        Feature::Face => unit_normal(triangle),
        Feature::Edge(e) => {
            let (u, v) = (corners[e as usize], corners[(e as usize + 1) % 3]);
            // The other triangle along the edge (closed: exactly one).
            let other = mesh
                .triangles_at(u as usize)
                .iter()
                .map(|&t| t as usize)
                .find(|&t| t != triangle && mesh.triangles()[t].contains(&v))?;
            Some(unit_normal(triangle)? + unit_normal(other)?)
        }
        Feature::Vertex(k) => {
            let v = corners[k as usize];
            mesh.triangles_at(v as usize)
                .iter()
                .map(|&t| {
                    let t = t as usize;
                    let ids = mesh.triangles()[t];
                    let at = ids.iter().position(|&i| i == v).unwrap_or(0);
                    let vertices = mesh.vertices();
                    let here = vertices[v as usize];
                    let (next, previous) =
                        (vertices[ids[(at + 1) % 3] as usize], vertices[ids[(at + 2) % 3] as usize]);
                    let angle = (next - here).angle(&(previous - here));
                    Some(unit_normal(t)? * angle)
                })
                .sum()
        }
    }
}

/// The winding number of the mesh's surface about `point` (not on it): the
/// sum of its triangles' signed solid angles over 4π (Van Oosterom and
/// Strackee's formula); ±1 inside a closed surface, 0 outside. Triangles of
/// zero area subtend none and are skipped. Linear in the triangles: the
/// fallback of the rare query whose closest feature touches such a triangle.
fn winding_number(mesh: &TriMesh, point: &Point) -> Real {
    let solid_angle = |t: usize| {
        let [a, b, c] = mesh.triangle(t).map(|q| q - point);
        let (la, lb, lc) = (a.norm(), b.norm(), c.norm());
        let numerator = a.dot(&b.cross(&c));
        let denominator = la * lb * lc + a.dot(&b) * lc + a.dot(&c) * lb + b.dot(&c) * la;
        2.0 * numerator.atan2(denominator)
    };
    let total: Real = (0..mesh.triangles().len()).filter(|&t| !mesh.is_zero_area(t)).map(solid_angle).sum();
    total / (4.0 * std::f64::consts::PI)
}

//! Where two posed meshes' surfaces cross: every triangle pair that meets
//! and what it shares (a segment of the intersection curve, a point, or a
//! coplanar polygon), found by descending the two BVHs wherever the node
//! boxes overlap.
//!
//! Whether a triangle pair meets is decided exactly on the posed
//! coordinates ([`triangle_intersection`]); a node pair is left out only
//! when its boxes are apart by more than the rounding of the relative pose
//! ([`PRUNE_SLACK_ULPS`] ulps), so no meeting pair is lost to rounding.
//! The segments of crossing pairs, taken together, are the intersection
//! curve: closed loops for closed meshes in general position, each segment
//! labelled with the two triangles it lies on.

use super::distance::{node_lower_bound, Relative, PRUNE_SLACK_ULPS};
use super::trimesh::TriMesh;
use super::BVH_LEAF_SIZE;
use crate::kernels::{triangle_intersection, TriangleIntersection};
use crate::math::{Point, Pose, Real};

/// One triangle pair that meets, in world coordinates.
#[derive(Copy, Clone, Debug, PartialEq)]
pub struct CrossingPair {
    /// The triangle of mesh `a` (index into [`TriMesh::triangles`]).
    pub triangle_a: usize,
    /// The triangle of mesh `b`.
    pub triangle_b: usize,
    /// What the two triangles share (never [`TriangleIntersection::Disjoint`]).
    pub shared: TriangleIntersection,
}

/// Every triangle pair of two posed meshes that meets, in the order the
/// search found them.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct MeshIntersection {
    /// The pairs that meet.
    pub pairs: Vec<CrossingPair>,
}

impl MeshIntersection {
    /// Whether the surfaces meet anywhere.
    pub fn is_empty(&self) -> bool {
        self.pairs.is_empty()
    }

    /// The segments of the intersection curve (pairs that share a segment,
    /// crossing or touching along a line).
    pub fn segments(&self) -> impl Iterator<Item = &[Point; 2]> + '_ {
        self.pairs.iter().filter_map(|pair| match &pair.shared {
            TriangleIntersection::Segment(ends) => Some(ends),
            _ => None,
        })
    }

    /// The curve's total length (its segments' lengths summed; a segment
    /// two pairs share, along a mesh edge, counts for each).
    pub fn length(&self) -> Real {
        self.segments().map(|[p, q]| (q - p).norm()).sum()
    }
}

/// Reusable buffers of [`mesh_intersection`].
#[derive(Clone, Debug, Default)]
pub struct MeshIntersectionScratch {
    stack: Vec<(u32, u32)>,
}

/// Every triangle pair of mesh `a` at `pose_a` and mesh `b` at `pose_b`
/// that meets, written into `out` (cleared first), in world coordinates.
pub fn mesh_intersection(
    a: &TriMesh,
    pose_a: &Pose,
    b: &TriMesh,
    pose_b: &Pose,
    out: &mut MeshIntersection,
    scratch: &mut MeshIntersectionScratch,
) {
    out.pairs.clear();
    let pos_ab = pose_a.inv_mul(pose_b);
    let relative = Relative::of(&pos_ab);
    let slack =
        PRUNE_SLACK_ULPS * Real::EPSILON * (pos_ab.translation.vector.norm() + a.radius() + b.radius());
    let (nodes_a, nodes_b) = (a.bvh().nodes(), b.bvh().nodes());
    scratch.stack.clear();
    scratch.stack.push((0, 0));
    while let Some((i, j)) = scratch.stack.pop() {
        let (na, nb) = (&nodes_a[i as usize], &nodes_b[j as usize]);
        if node_lower_bound(na, nb, &relative, slack) > slack {
            continue;
        }
        if na.is_leaf() && nb.is_leaf() {
            // Exact on the world coordinates both meshes are posed to; a
            // leaf's triangles posed once.
            let mut posed_a = [[Point::origin(); 3]; BVH_LEAF_SIZE];
            let mut boxes_a = [(Point::origin(), Point::origin()); BVH_LEAF_SIZE];
            for (k, ta) in (na.first..na.first + na.count).enumerate() {
                posed_a[k] = a.triangle(ta as usize).map(|p| pose_a * p);
                boxes_a[k] = triangle_box(&posed_a[k]);
            }
            for tb in nb.first..nb.first + nb.count {
                let moved_b = b.triangle(tb as usize).map(|p| pose_b * p);
                let box_b = triangle_box(&moved_b);
                for (k, ta) in (na.first..na.first + na.count).enumerate() {
                    // Boxes of exact coordinates: apart boxes, disjoint triangles.
                    let (low, high) = boxes_a[k];
                    if (0..3).any(|i| high[i] < box_b.0[i] || box_b.1[i] < low[i]) {
                        continue;
                    }
                    let shared = triangle_intersection(&posed_a[k], &moved_b);
                    if shared != TriangleIntersection::Disjoint {
                        out.pairs.push(CrossingPair {
                            triangle_a: ta as usize,
                            triangle_b: tb as usize,
                            shared,
                        });
                    }
                }
            }
            continue;
        }
        let split_a = !na.is_leaf() && (nb.is_leaf() || na.radius >= nb.radius);
        if split_a {
            scratch.stack.extend([(na.first, j), (na.first + 1, j)]);
        } else {
            scratch.stack.extend([(i, nb.first), (i, nb.first + 1)]);
        }
    }
}

/// A triangle's axis-aligned box (its smallest and largest coordinates).
fn triangle_box(t: &crate::math::Triangle) -> (Point, Point) {
    (t[0].inf(&t[1]).inf(&t[2]), t[0].sup(&t[1]).sup(&t[2]))
}

/// Every meeting triangle pair by brute force (every pair, posed to the
/// world): the reference [`mesh_intersection`] is tested against.
pub fn mesh_intersection_brute_force(
    a: &TriMesh,
    pose_a: &Pose,
    b: &TriMesh,
    pose_b: &Pose,
) -> Vec<(usize, usize)> {
    let moved_b: Vec<_> = (0..b.triangles().len()).map(|j| b.triangle(j).map(|p| pose_b * p)).collect();
    let mut pairs = Vec::new();
    for i in 0..a.triangles().len() {
        let ta = a.triangle(i).map(|p| pose_a * p);
        for (j, tb) in moved_b.iter().enumerate() {
            if triangle_intersection(&ta, tb) != TriangleIntersection::Disjoint {
                pairs.push((i, j));
            }
        }
    }
    pairs
}

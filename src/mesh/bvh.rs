//! A bounding volume hierarchy over a mesh's triangles: a binary tree of
//! axis-aligned boxes in the mesh's frame, each with a bounding sphere
//! about the box's centre (the sphere bound is unchanged by rotation, the
//! box bound is tighter for elongated nodes; queries use the better one).
//!
//! Built top-down: each node's triangles are split at the median centroid
//! along the longest axis of the centroids' box, down to leaves of at most
//! [`BVH_LEAF_SIZE`] triangles (a 4 × 4 leaf pair fills two 8-lane batches
//! of the triangle kernel).

use crate::math::{Point, Real, Vector};

/// The most triangles in a leaf.
pub(crate) const BVH_LEAF_SIZE: usize = 4;

/// One node of a [`MeshBvh`].
#[derive(Copy, Clone, Debug, PartialEq)]
pub struct BvhNode {
    /// The centre of the node's box.
    pub center: Point,
    /// The half extents of the node's box.
    pub half_extents: Vector,
    /// The largest distance from `center` to a vertex of the node.
    pub radius: Real,
    /// Leaf: the first triangle. Internal: the first child (the second
    /// child is `first + 1`).
    pub first: u32,
    /// Leaf: the number of triangles (at least 1). Internal: 0.
    pub count: u32,
}

impl BvhNode {
    /// Whether the node is a leaf.
    #[inline]
    pub fn is_leaf(&self) -> bool {
        self.count > 0
    }
}

/// The hierarchy; node 0 is the root.
#[derive(Clone, Debug, Default)]
pub struct MeshBvh {
    nodes: Vec<BvhNode>,
}

impl MeshBvh {
    /// Builds the tree over `triangles` (at least one) and returns it with
    /// the triangles reordered so that each leaf holds a contiguous range.
    pub fn build(vertices: &[Point], triangles: Vec<[u32; 3]>) -> (MeshBvh, Vec<[u32; 3]>) {
        let centroids: Vec<Point> = triangles
            .iter()
            .map(|t| Point::from(t.iter().map(|&i| vertices[i as usize].coords).sum::<Vector>() / 3.0))
            .collect();
        let mut order: Vec<usize> = (0..triangles.len()).collect();
        let mut nodes = vec![placeholder()];
        let mut builder =
            Builder { vertices, triangles: &triangles, centroids: &centroids, nodes: &mut nodes };
        builder.build(0, &mut order, 0);
        let reordered = order.iter().map(|&i| triangles[i]).collect();
        (MeshBvh { nodes }, reordered)
    }

    /// The nodes; node 0 is the root, children of an internal node are adjacent.
    pub fn nodes(&self) -> &[BvhNode] {
        &self.nodes
    }
}

fn placeholder() -> BvhNode {
    BvhNode { center: Point::origin(), half_extents: Vector::zeros(), radius: 0.0, first: 0, count: 0 }
}

struct Builder<'a> {
    vertices: &'a [Point],
    triangles: &'a [[u32; 3]],
    centroids: &'a [Point],
    nodes: &'a mut Vec<BvhNode>,
}

impl Builder<'_> {
    /// Fills node `index` with the triangles `order` (which start at
    /// position `offset` of the final order).
    fn build(&mut self, index: usize, order: &mut [usize], offset: usize) {
        let corners =
            || order.iter().flat_map(|&t| self.triangles[t].iter().map(|&v| self.vertices[v as usize]));
        let (low, high) = bounds(corners());
        let center = Point::from((low.coords + high.coords) / 2.0);
        let radius = corners().map(|p| (p - center).norm()).fold(0.0, Real::max);
        let mut node =
            BvhNode { center, half_extents: (high - low) / 2.0, radius, first: offset as u32, count: 0 };
        if order.len() <= BVH_LEAF_SIZE {
            node.count = order.len() as u32;
            self.nodes[index] = node;
            return;
        }
        let (centroid_low, centroid_high) = bounds(order.iter().map(|&t| self.centroids[t]));
        let axis = (centroid_high - centroid_low).imax();
        let middle = order.len() / 2;
        order.select_nth_unstable_by(middle, |&i, &j| {
            self.centroids[i][axis].total_cmp(&self.centroids[j][axis]).then(i.cmp(&j))
        });
        let first_child = self.nodes.len();
        node.first = first_child as u32;
        self.nodes[index] = node;
        self.nodes.extend([placeholder(), placeholder()]);
        let (left, right) = order.split_at_mut(middle);
        self.build(first_child, left, offset);
        self.build(first_child + 1, right, offset + middle);
    }
}

/// The smallest and largest corners of a set of points.
fn bounds(points: impl Iterator<Item = Point>) -> (Point, Point) {
    let start = (Point::from([Real::INFINITY; 3]), Point::from([Real::NEG_INFINITY; 3]));
    points.fold(start, |(low, high), p| (low.inf(&p), high.sup(&p)))
}

#[cfg(test)]
mod tests {
    use super::super::primitives::icosphere;

    #[test]
    fn every_triangle_in_exactly_one_leaf_and_inside_its_bounds() {
        let mesh = icosphere(1.0, 3).unwrap();
        let nodes = mesh.bvh().nodes();
        let mut seen = vec![0; mesh.triangles().len()];
        // Walk from the root, checking that each node's box holds its subtree.
        let mut stack = vec![(0usize, Vec::<usize>::new())];
        while let Some((index, ancestors)) = stack.pop() {
            let node = &nodes[index];
            if node.is_leaf() {
                for t in node.first..node.first + node.count {
                    seen[t as usize] += 1;
                    for p in mesh.triangle(t as usize) {
                        for &a in ancestors.iter().chain([index].iter()) {
                            let n = &nodes[a];
                            assert!(((p - n.center).abs() - n.half_extents).max() <= 1e-15);
                            assert!((p - n.center).norm() <= n.radius * (1.0 + 1e-15));
                        }
                    }
                }
            } else {
                let mut path = ancestors.clone();
                path.push(index);
                stack.push((node.first as usize, path.clone()));
                stack.push((node.first as usize + 1, path));
            }
        }
        assert!(seen.iter().all(|&n| n == 1));
    }
}

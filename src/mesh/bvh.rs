//! A bounding volume hierarchy over a mesh's triangles: a binary tree of
//! oriented boxes in the mesh's frame, each with a bounding sphere about
//! the box's centre (the sphere bound is unchanged by rotation, the box
//! bound is tighter for elongated and flat nodes; queries use the better
//! one).
//!
//! A node's box is the tighter (by volume) of the box along the mesh's own
//! axes and the box along the principal axes of the node's vertices: a
//! strip of a gear's teeth or a slanted wall gets a box along itself, not
//! the much larger one along the mesh's axes (on pybullet_data's meshes,
//! the search's node bounds cut the triangle pairs evaluated many times
//! over; see BENCHMARKS.md). Boxes along the mesh's axes are kept where
//! they are as tight, so an axis-aligned part keeps exact box faces.
//!
//! Split top-down: each node's triangles are split at the median centroid
//! along the longest axis of the centroids' box, down to leaves of at most
//! [`BVH_LEAF_SIZE`] triangles (a 4 × 4 leaf pair fills two 8-lane batches
//! of the triangle kernel). Boxed bottom-up: a node's aligned box, mean and
//! scatter are merged from its children's, so only its principal-axes
//! projections and its radius take a pass over its corners.

use nalgebra::{Matrix3, SymmetricEigen};

use crate::math::{Point, Real, Vector};

/// The most triangles in a leaf.
pub(crate) const BVH_LEAF_SIZE: usize = 4;

/// One node of a [`MeshBvh`].
#[derive(Copy, Clone, Debug, PartialEq)]
pub struct BvhNode {
    /// The centre of the node's box.
    pub center: Point,
    /// The box's axes: orthonormal columns, in the mesh's frame (the
    /// identity for a box along the mesh's axes).
    pub axes: Matrix3<Real>,
    /// The half extents of the node's box along its axes.
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
    ///
    /// Subtrees of `PARALLEL_BUILD_TRIANGLES` (16,384) or more are built on
    /// rayon's threads, each into the slots the one-thread build would give
    /// it (a subtree's node count follows from its triangle count alone), so
    /// the tree is the same whatever the thread count.
    pub fn build(vertices: &[Point], triangles: Vec<[u32; 3]>) -> (MeshBvh, Vec<[u32; 3]>) {
        let centroids: Vec<Point> = triangles
            .iter()
            .map(|t| Point::from(t.iter().map(|&i| vertices[i as usize].coords).sum::<Vector>() / 3.0))
            .collect();
        let mut order: Vec<usize> = (0..triangles.len()).collect();
        let mut nodes = vec![placeholder(); node_count(triangles.len())];
        let builder = Builder { vertices, triangles: &triangles, centroids: &centroids };
        let (root, descendants) = nodes.split_at_mut(1);
        builder.build(&mut root[0], descendants, 1, &mut order, 0);
        let reordered = order.iter().map(|&i| triangles[i]).collect();
        (MeshBvh { nodes }, reordered)
    }

    /// The same tree over vertices moved by `-shift`: each node's centre
    /// moved, its box and sphere widened by the rounding of the move (of the
    /// vertices and of the centre: [`BOX_WIDENING_ULPS`] of the reach of
    /// both), so that they still hold the moved vertices.
    pub(crate) fn translated(&self, shift: &Vector) -> MeshBvh {
        let nodes = self
            .nodes
            .iter()
            .map(|node| {
                let center = node.center - shift;
                let reach = center.coords.norm() + shift.norm() + node.radius;
                let widening = BOX_WIDENING_ULPS * Real::EPSILON * reach;
                BvhNode {
                    center,
                    half_extents: node.half_extents.add_scalar(widening),
                    radius: node.radius + widening,
                    ..*node
                }
            })
            .collect();
        MeshBvh { nodes }
    }

    /// The nodes; node 0 is the root, children of an internal node are adjacent.
    pub fn nodes(&self) -> &[BvhNode] {
        &self.nodes
    }

    /// The triangles under node `k`, a range of the mesh's (each subtree's
    /// triangles are contiguous), where they are at most `most`; `None`
    /// where there are more (found from the subtree's first and last
    /// leaves, so a small node costs a few reads).
    pub(crate) fn small_span(&self, k: u32, most: u32) -> Option<(u32, u32)> {
        let (mut low, mut high) = (&self.nodes[k as usize], &self.nodes[k as usize]);
        while !low.is_leaf() {
            low = &self.nodes[low.first as usize];
        }
        while !high.is_leaf() {
            high = &self.nodes[high.first as usize + 1];
        }
        let span = (low.first, high.first + high.count);
        (span.1 - span.0 <= most).then_some(span)
    }
}

/// The distinct vertices of each small node of a tree: those of the
/// triangles under the node, each once, where the node holds at most a
/// given number of triangles. A node's vertex bounds (its vertices
/// projected on a line, as the distance search's and the CCD's slabs take
/// them) read each vertex once instead of once for each of its triangles,
/// with no triangle read between: the largest such nodes (9 to 16
/// triangles, 11 on average) list about 13 vertices on a KUKA link of
/// `pybullet_data` or a torus, where their triangles have 33 corners (25
/// against 42 on the gear ring's slivers). 4.1 to 6.1 indices a triangle
/// over all the small nodes: 20 to 28 bytes a triangle with the ranges.
#[derive(Clone, Debug, Default, PartialEq)]
pub(crate) struct NodeVertices {
    /// Node `k`'s vertices are `indices[ranges[k][0]..ranges[k][1]]`
    /// (empty for a node with more triangles).
    ranges: Vec<[u32; 2]>,
    indices: Vec<u32>,
}

/// The nodes listed together, on one thread, by [`NodeVertices::of`]:
/// `4096`. A run is about 0.8 ms of work (a million-triangle torus's
/// 524,287 nodes take 100 ms on one thread), far more than handing it to
/// another thread costs, and a million triangles make 128 runs to share.
const NODE_VERTICES_RUN: usize = 4096;

impl NodeVertices {
    /// The table of `bvh` over `triangles` (in its leaf order) for the
    /// nodes of at most `most` triangles. A mesh of
    /// [`PARALLEL_BUILD_TRIANGLES`] or more is listed on rayon's threads,
    /// in runs of nodes joined in order (the same table whatever the
    /// thread count).
    pub(crate) fn of(bvh: &MeshBvh, triangles: &[[u32; 3]], most: u32) -> NodeVertices {
        let nodes = bvh.nodes.len();
        // The nodes `range`, their ranges counted from the run's start.
        let list = |range: std::ops::Range<usize>| {
            let mut run = NodeVertices { ranges: Vec::with_capacity(range.len()), indices: Vec::new() };
            let mut corners = Vec::with_capacity(3 * most as usize);
            for k in range {
                let start = run.indices.len() as u32;
                if let Some((first, end)) = bvh.small_span(k as u32, most) {
                    corners.clear();
                    corners.extend(triangles[first as usize..end as usize].iter().flatten());
                    corners.sort_unstable();
                    corners.dedup();
                    run.indices.extend_from_slice(&corners);
                }
                run.ranges.push([start, run.indices.len() as u32]);
            }
            run
        };
        if triangles.len() < PARALLEL_BUILD_TRIANGLES {
            return list(0..nodes);
        }
        use rayon::prelude::*;
        let runs: Vec<NodeVertices> = (0..nodes.div_ceil(NODE_VERTICES_RUN))
            .into_par_iter()
            .map(|r| list(r * NODE_VERTICES_RUN..((r + 1) * NODE_VERTICES_RUN).min(nodes)))
            .collect();
        let mut table = NodeVertices {
            ranges: Vec::with_capacity(nodes),
            indices: Vec::with_capacity(runs.iter().map(|run| run.indices.len()).sum()),
        };
        for run in runs {
            let offset = table.indices.len() as u32;
            table.ranges.extend(run.ranges.iter().map(|[start, end]| [start + offset, end + offset]));
            table.indices.extend_from_slice(&run.indices);
        }
        table
    }

    /// Bytes the table holds on the heap.
    pub(crate) fn bytes(&self) -> usize {
        std::mem::size_of_val(self.ranges.as_slice()) + std::mem::size_of_val(self.indices.as_slice())
    }

    /// Node `k`'s distinct vertices (indices into the mesh's vertices), or
    /// `None` where it holds more triangles than the table's bound.
    #[inline]
    pub(crate) fn of_node(&self, k: u32) -> Option<&[u32]> {
        let [start, end] = self.ranges[k as usize];
        (end > start).then(|| &self.indices[start as usize..end as usize])
    }
}

/// The fewest triangles of a subtree built on a thread of its own while
/// its sibling is built on another: `16_384` (smaller ones take well under
/// a millisecond, less than the hand-over is worth).
pub(crate) const PARALLEL_BUILD_TRIANGLES: usize = 16_384;

/// The number of nodes of a tree over `triangles` triangles: a node splits
/// at `triangles / 2` until a leaf holds at most [`BVH_LEAF_SIZE`].
fn node_count(triangles: usize) -> usize {
    // Each level holds at most two distinct counts (n and n + 1), so the
    // recursion is walked level by level over those.
    fn count(n: usize, known: &mut Vec<(usize, usize)>) -> usize {
        if n <= BVH_LEAF_SIZE {
            return 1;
        }
        if let Some(&(_, c)) = known.iter().find(|(m, _)| *m == n) {
            return c;
        }
        let c = 1 + count(n / 2, known) + count(n - n / 2, known);
        known.push((n, c));
        c
    }
    count(triangles, &mut Vec::new())
}

fn placeholder() -> BvhNode {
    BvhNode {
        center: Point::origin(),
        axes: Matrix3::identity(),
        half_extents: Vector::zeros(),
        radius: 0.0,
        first: 0,
        count: 0,
    }
}

struct Builder<'a> {
    vertices: &'a [Point],
    triangles: &'a [[u32; 3]],
    centroids: &'a [Point],
}

impl Builder<'_> {
    /// Fills `node` with the triangles `order` (which start at position
    /// `offset` of the final order), and `descendants` (its subtree's other
    /// nodes, the first at index `base` of the tree) with its subtree:
    /// children first, then the first child's subtree, then the second's.
    /// Returns the moments of the node's corners.
    ///
    /// The tree is split top-down and boxed bottom-up: a node's aligned
    /// box, mean and scatter are merged from its children's (exactly for
    /// the box; Chan et al.'s pairwise update for the scatter, as stable
    /// as summing about the mean), so only the principal axes' projections
    /// and the radius take a pass over the node's corners (two passes, not
    /// four: the build is bound by those reads).
    fn build(
        &self,
        node: &mut BvhNode,
        descendants: &mut [BvhNode],
        base: usize,
        order: &mut [usize],
        offset: usize,
    ) -> Moments {
        if order.len() <= BVH_LEAF_SIZE {
            let corners = || self.corners(order);
            let moments = Moments::of(corners);
            *node = fitted_node(corners, &moments, offset as u32);
            node.count = order.len() as u32;
            return moments;
        }
        let (centroid_low, centroid_high) = bounds(order.iter().map(|&t| self.centroids[t]));
        let axis = (centroid_high - centroid_low).imax();
        let middle = order.len() / 2;
        order.select_nth_unstable_by(middle, |&i, &j| {
            self.centroids[i][axis].total_cmp(&self.centroids[j][axis]).then(i.cmp(&j))
        });
        let (children, rest) = descendants.split_at_mut(2);
        let (left_node, right_node) = children.split_at_mut(1);
        let left_size = node_count(middle) - 1;
        let (left_rest, right_rest) = rest.split_at_mut(left_size);
        let (left, right) = order.split_at_mut(middle);
        let parallel = right.len() >= PARALLEL_BUILD_TRIANGLES;
        let mut build_left = || self.build(&mut left_node[0], left_rest, base + 2, left, offset);
        let mut build_right =
            || self.build(&mut right_node[0], right_rest, base + 2 + left_size, right, offset + middle);
        let (left_moments, right_moments) =
            if parallel { rayon::join(build_left, build_right) } else { (build_left(), build_right()) };
        let moments = Moments::merged(&left_moments, &right_moments);
        *node = fitted_node(|| self.corners(order), &moments, base as u32);
        moments
    }

    /// The corners of the triangles `order`.
    fn corners<'s>(&'s self, order: &'s [usize]) -> impl Iterator<Item = Point> + 's {
        order.iter().flat_map(|&t| self.triangles[t].iter().map(|&v| self.vertices[v as usize]))
    }
}

/// What a node's box is fitted from: its points' count, aligned bounds,
/// mean and scatter `Σ (p − mean)(p − mean)ᵀ`.
#[derive(Copy, Clone, Debug)]
struct Moments {
    count: Real,
    low: Point,
    high: Point,
    mean: Vector,
    scatter: Matrix3<Real>,
}

impl Moments {
    /// Of a few points (a leaf's corners): two passes, about the mean.
    fn of<I: Iterator<Item = Point>>(points: impl Fn() -> I) -> Moments {
        let start =
            (Point::from([Real::INFINITY; 3]), Point::from([Real::NEG_INFINITY; 3]), Vector::zeros(), 0.0);
        let (low, high, sum, count) = points()
            .fold(start, |(low, high, sum, n), p| (low.inf(&p), high.sup(&p), sum + p.coords, n + 1.0));
        let mean = sum / count;
        let scatter = points().fold(Matrix3::zeros(), |sum, p| {
            let d = p.coords - mean;
            sum + d * d.transpose()
        });
        Moments { count, low, high, mean, scatter }
    }

    /// Of the union of two point sets.
    fn merged(a: &Moments, b: &Moments) -> Moments {
        let count = a.count + b.count;
        let delta = b.mean - a.mean;
        Moments {
            count,
            low: a.low.inf(&b.low),
            high: a.high.sup(&b.high),
            mean: a.mean + delta * (b.count / count),
            scatter: a.scatter + b.scatter + delta * delta.transpose() * (a.count * b.count / count),
        }
    }
}

/// A node over `points` with these moments (its box by [`fitted_box`],
/// its sphere about the box's centre), `first` its first triangle or child.
fn fitted_node<I: Iterator<Item = Point>>(points: impl Fn() -> I, moments: &Moments, first: u32) -> BvhNode {
    let (center, axes, half_extents) = fitted_box(&points, moments);
    let radius = points().map(|p| (p - center).norm()).fold(0.0, Real::max);
    BvhNode { center, axes, half_extents, radius, first, count: 0 }
}

/// A box that holds `points` (whose `moments` are given): its centre,
/// axes and half extents. The box along the principal axes of the points
/// where its volume is below [`PRINCIPAL_BOX_GAIN`] of the box along the
/// mesh's axes, that box otherwise. Half extents are widened by a few ulps
/// of the box's reach, so that the rounding of the projections never
/// leaves a point outside.
fn fitted_box<I: Iterator<Item = Point>>(
    points: &impl Fn() -> I,
    moments: &Moments,
) -> (Point, Matrix3<Real>, Vector) {
    let (low, high) = (moments.low, moments.high);
    let aligned = (Point::from((low.coords + high.coords) / 2.0), Matrix3::identity(), (high - low) / 2.0);
    let axes = SymmetricEigen::new(moments.scatter).eigenvectors;
    // Only a proper orthonormal frame (the solver's columns are unit and
    // orthogonal to rounding; anything else keeps the mesh's axes).
    let off = (axes.transpose() * axes - Matrix3::identity()).amax();
    if !axes.iter().all(|c| c.is_finite()) || off > PRINCIPAL_AXES_ORTHONORMAL {
        return widened(aligned);
    }
    let (plow, phigh) = bounds(points().map(|p| Point::from(axes.tr_mul(&p.coords))));
    let half = (phigh - plow) / 2.0;
    let volume = |h: &Vector| h.iter().map(|e| e.max(Real::EPSILON * (1.0 + h.amax()))).product::<Real>();
    if volume(&half) < PRINCIPAL_BOX_GAIN * volume(&aligned.2) {
        widened((Point::from(axes * ((plow.coords + phigh.coords) / 2.0)), axes, half))
    } else {
        widened(aligned)
    }
}

/// The share of the axis-aligned box's volume the principal-axes box must
/// stay under to be taken: `0.9` (a box hardly tighter is not worth its
/// rotated projections' rounding and the loss of exact axis-aligned faces).
pub(crate) const PRINCIPAL_BOX_GAIN: Real = 0.9;

/// How far the eigen solver's axes may be from orthonormal (`AᵀA` from the
/// identity) for a node's box to be taken along them: `1e-12` (its
/// rounding is ~1e-15; anything farther keeps the mesh's axes).
const PRINCIPAL_AXES_ORTHONORMAL: Real = 1e-12;

/// How much a principal-axes box is widened, in ulps of its reach from the
/// origin: `8` (each vertex's projection onto an axis and the centre's
/// rotation back round a few times).
const BOX_WIDENING_ULPS: Real = 8.0;

/// The box widened by `BOX_WIDENING_ULPS` of its reach from the origin (the rounding of
/// the projections and of the centre's rotation back).
fn widened((center, axes, half): (Point, Matrix3<Real>, Vector)) -> (Point, Matrix3<Real>, Vector) {
    if axes == Matrix3::identity() {
        return (center, axes, half);
    }
    let reach = center.coords.amax() + half.amax();
    (center, axes, half.add_scalar(BOX_WIDENING_ULPS * Real::EPSILON * reach))
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
        assert_holds_its_triangles(&mesh);
        // Moved far from its pivot, the tree moved with it still holds them
        // (a sphere off the origin, its pivot off the other way).
        let offset = icosphere(1.0, 3).unwrap().pivoted(&crate::math::Point::new(-1e3, 2e3, -5e2)).unwrap();
        assert_eq!(offset.triangles(), mesh.triangles(), "the triangles keep their order");
        assert_holds_its_triangles(&offset);
        assert_holds_its_triangles(&offset.pivoted(&crate::math::Point::new(1e3 + 0.1, -2e3, 5e2)).unwrap());
    }

    fn assert_holds_its_triangles(mesh: &crate::mesh::TriMesh) {
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
                            assert!((n.axes.tr_mul(&(p - n.center)).abs() - n.half_extents).max() <= 1e-15);
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

    /// Each node of at most `SLAB_TRIANGLES` triangles lists the distinct
    /// vertices of its triangles, each once; a larger node lists none.
    /// The triangles under each node are found by walking its subtree.
    #[test]
    fn a_small_node_lists_each_vertex_of_its_triangles_once() {
        use crate::math::Point;
        use crate::mesh::distance::SLAB_TRIANGLES;
        // An icosphere, and a strip with a triangle of a repeated vertex.
        let strip = crate::mesh::TriMesh::new(
            (0..40).map(|k| Point::new(k as f64 * 0.5, (k % 2) as f64, 0.0)).collect(),
            (0..38).map(|k| [k, k + 1, k + 2]).chain([[5, 5, 6]]).collect(),
        )
        .unwrap();
        for mesh in [icosphere(1.0, 3).unwrap(), strip] {
            let nodes = mesh.bvh().nodes();
            let (mut small, mut large) = (0, 0);
            for k in 0..nodes.len() {
                let (mut stack, mut under) = (vec![k], Vec::new());
                while let Some(n) = stack.pop() {
                    let node = &nodes[n];
                    if node.is_leaf() {
                        under.extend(node.first..node.first + node.count);
                    } else {
                        stack.extend([node.first as usize, node.first as usize + 1]);
                    }
                }
                let listed = mesh.small_node_vertices(k as u32);
                if under.len() > SLAB_TRIANGLES as usize {
                    assert_eq!(listed, None, "node {k}: {} triangles", under.len());
                    large += 1;
                    continue;
                }
                let mut expected: Vec<u32> =
                    under.iter().flat_map(|&t| mesh.triangles()[t as usize]).collect();
                expected.sort_unstable();
                expected.dedup();
                let mut listed = listed.expect("a small node's vertices").to_vec();
                listed.sort_unstable();
                assert_eq!(listed, expected, "node {k}");
                small += 1;
            }
            assert!(small > 0 && (large > 0 || mesh.triangles().len() <= SLAB_TRIANGLES as usize));
        }
    }

    /// A tree big enough to be built on several threads is the one a
    /// single thread builds, node for node (and its small nodes' vertices
    /// the same list), and fills exactly the slots `node_count` gives it.
    #[test]
    fn the_tree_does_not_depend_on_the_thread_count() {
        let mesh = super::super::primitives::torus(1.0, 0.3, 300, 150).unwrap();
        let build = |threads: usize| {
            let pool = rayon::ThreadPoolBuilder::new().num_threads(threads).build().unwrap();
            pool.install(|| {
                let (tree, order) = super::MeshBvh::build(mesh.vertices(), mesh.triangles().to_vec());
                let listed = super::NodeVertices::of(&tree, &order, crate::mesh::distance::SLAB_TRIANGLES);
                (tree, order, listed)
            })
        };
        let (one, one_order, one_listed) = build(1);
        let (four, four_order, four_listed) = build(4);
        assert!(mesh.triangles().len() > 4 * super::PARALLEL_BUILD_TRIANGLES);
        assert_eq!(one.nodes(), four.nodes());
        assert_eq!(one_order, four_order);
        // The small nodes' vertices, listed in runs on the threads, too.
        assert_eq!(one_listed, four_listed);
        assert_eq!(one.nodes().len(), super::node_count(mesh.triangles().len()));
        // Every slot filled: no node is left as the placeholder.
        assert!(one.nodes().iter().all(|n| n.radius > 0.0));
    }
}

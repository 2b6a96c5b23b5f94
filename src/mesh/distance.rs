//! The distance between two posed meshes, by branch and bound over their
//! BVHs, with the triangle pairs at the leaves sent to the batched kernel.
//!
//! Mesh `b` is expressed in the frame of mesh `a` (`pos_ab`, parry's `pos12`):
//! `a`'s triangles are used as stored, `b`'s are moved once. Node pairs are
//! visited nearest first (the least lower bound first), or, from a hint's
//! first best, depth first, nearer child first (children whose bounds
//! agree to rounding: the one with the nearer centres, so either argument
//! order visits alike); a node pair whose lower bound is not below the
//! best distance found so far is pruned. The bound is the largest of the
//! sphere–sphere distance, the oriented boxes' gap along each box's axes
//! ([`node_lower_bound`]), where a leaf faces a smaller node, the leaf's
//! triangles' distance to that node's sphere, and for nodes of a few
//! triangles, their vertices' gap along the line of centres
//! ([`vertex_slab`]). Leaf pairs queue
//! their triangle pairs (those whose boxes, in either mesh's frame, may
//! beat the best), and the
//! queue is flushed through [`batch::triangle_distances`] (eight pairs per
//! vector pass) whenever it holds [`FLUSH_PAIRS`] pairs; the best pair is
//! then finished by the scalar kernel for its closest points and features.

use std::cmp::Ordering;
use std::collections::BinaryHeap;

use nalgebra::Matrix3;

use super::bvh::BVH_LEAF_SIZE;
use super::trimesh::TriMesh;
use crate::kernels::{
    batch, dyop_distance, nearest_of_four, posed_triangle_distance, triangle_distance, Feature,
    PointEdgeFormula,
};
use crate::math::{Placement, Point, Pose, Real, Triangle, Vector};

/// Triangle pairs queued before a batched kernel call.
const FLUSH_PAIRS: usize = 16;

/// Rounding slack of the node lower bounds, in ulps of the relative
/// frame's size: a node pair is pruned only if its bound beats the best
/// distance by more than this, so rounding never prunes the true minimum.
pub(crate) const PRUNE_SLACK_ULPS: Real = 32.0;

/// The triangle distance kernel that mesh queries use.
#[derive(Copy, Clone, Debug, Default, PartialEq, Eq)]
pub enum DistanceKernel {
    /// [`crate::kernels::triangle_distance`]: exact to rounding. The default,
    /// and the only kernel that keeps the CCD conservative.
    #[default]
    Exact,
    /// The seed paper's DyOP kernel ([`crate::kernels::dyop_distance`]) with
    /// the given point–edge formula. It ignores vertex–face and interior
    /// edge–edge cases and can over-estimate the distance, so a CCD driven
    /// by it can step past a contact: offered to measure the seed, not to rely on.
    Dyop(PointEdgeFormula),
}

/// The distance between two meshes and where it is attained: the closest
/// points, triangles and features. The one type of closest points from a
/// distance query to a run's contacts ([`crate::stepper::Contact::closest`])
/// and `summary.json` (its serialisation: points as `[x, y, z]`, features
/// by name, `"vertex 0"`, `"edge 2"`, `"face"`).
///
/// With [`DistanceKernel::Dyop`], `distance` is DyOP's value for the
/// winning triangle pair, while the points and features come from the exact
/// kernel on that pair (DyOP gives no points).
#[derive(Copy, Clone, Debug, PartialEq, serde::Serialize)]
pub struct MeshDistance {
    /// The distance (0 when the surfaces touch or cross).
    pub distance: Real,
    /// The closest point on mesh `a`: world coordinates from
    /// [`mesh_distance`], `a`'s frame from [`mesh_distance_relative`].
    #[serde(serialize_with = "crate::math::serialize_point")]
    pub point_a: Point,
    /// The closest point on mesh `b`, in the same frame as `point_a`.
    #[serde(serialize_with = "crate::math::serialize_point")]
    pub point_b: Point,
    /// The triangle of `a` (index into [`TriMesh::triangles`]).
    pub triangle_a: usize,
    /// The triangle of `b`.
    pub triangle_b: usize,
    /// The feature of `triangle_a` that `point_a` lies on.
    #[serde(serialize_with = "crate::math::serialize_display")]
    pub feature_a: Feature,
    /// The feature of `triangle_b` that `point_b` lies on.
    #[serde(serialize_with = "crate::math::serialize_display")]
    pub feature_b: Feature,
}

/// Reusable buffers of [`mesh_distance`], so queries do not allocate once
/// the buffers have grown.
#[derive(Clone, Debug, Default)]
pub struct MeshDistanceScratch {
    /// The node pairs left, nearest first (a search with no first best).
    nearest: BinaryHeap<Pending>,
    /// The node pairs left, last pushed first (a search from a hint).
    stack: Vec<Pending>,
    queue_a: batch::TrianglesSoa,
    queue_b: batch::TrianglesSoa,
    queue_pairs: Vec<(u32, u32)>,
    distances: Vec<Real>,
    /// Triangle pairs the last query evaluated.
    triangle_pairs: usize,
}

impl MeshDistanceScratch {
    /// Triangle pairs the last [`mesh_distance`] query evaluated (a
    /// measure of its work).
    pub fn triangle_pairs(&self) -> usize {
        self.triangle_pairs
    }
}

/// How a mesh distance query searches.
#[derive(Copy, Clone, Debug, Default, PartialEq)]
pub struct DistanceSearch {
    /// The triangle kernel. Default: [`DistanceKernel::Exact`].
    pub kernel: DistanceKernel,
    /// A triangle pair (for example the previous query's closest pair)
    /// that seeds the bound. Default: none.
    pub hint: Option<(usize, usize)>,
    /// The search stops as soon as a pair at this distance or less is
    /// found: a caller that only asks "within this distance?" gets its
    /// answer sooner. Default: `0.0` (the true minimum).
    pub enough: Real,
}

impl DistanceSearch {
    /// The true minimum by `kernel`, from `hint`.
    pub fn new(kernel: DistanceKernel, hint: Option<(usize, usize)>) -> DistanceSearch {
        DistanceSearch { kernel, hint, enough: 0.0 }
    }
}

/// The distance between mesh `a` at `pose_a` and mesh `b` at `pose_b`.
///
/// The poses are a [`Pose`] or a [`MatrixPose`](crate::math::MatrixPose)
/// (a rotation matrix applied as given). The search runs in `a`'s frame;
/// its closest triangle pair is then measured again with each triangle
/// posed exactly in the world ([`posed_triangle_distance`]), so the answer
/// is within about an ulp of the largest coordinate of the exact distance
/// of the poses given, and the points are in world coordinates.
pub fn mesh_distance(
    a: &TriMesh,
    pose_a: &impl Placement,
    b: &TriMesh,
    pose_b: &impl Placement,
    search: &DistanceSearch,
    scratch: &mut MeshDistanceScratch,
) -> MeshDistance {
    let (pose_a, pose_b) = (pose_a.matrix_pose(), pose_b.matrix_pose());
    // b's frame in a's as a matrix product of the two rotations.
    let relative = Relative {
        rotation: pose_a.rotation.tr_mul(&pose_b.rotation),
        shift: pose_a.rotation.tr_mul(&(pose_b.translation - pose_a.translation)),
    };
    let (best, (i, j)) =
        search_relative(a, b, &relative, search, Real::INFINITY, scratch).unwrap_or((Real::INFINITY, (0, 0)));
    let world = posed_triangle_distance(&a.triangle(i), &pose_a, &b.triangle(j), &pose_b);
    MeshDistance {
        // DyOP's value stays DyOP's.
        distance: if search.kernel == DistanceKernel::Exact { world.distance } else { best },
        point_a: world.point_a,
        point_b: world.point_b,
        triangle_a: i,
        triangle_b: j,
        feature_a: world.feature_a,
        feature_b: world.feature_b,
    }
}

/// Mesh `b`'s frame in mesh `a`'s: `p ↦ rotation · p + shift`.
#[derive(Copy, Clone, Debug)]
pub(crate) struct Relative {
    pub(crate) rotation: Matrix3<Real>,
    pub(crate) shift: Vector,
}

impl Relative {
    /// The relative pose `pos_ab` as a matrix and a shift.
    pub(crate) fn of(pos_ab: &Pose) -> Relative {
        Relative {
            rotation: pos_ab.rotation.to_rotation_matrix().into_inner(),
            shift: pos_ab.translation.vector,
        }
    }

    /// `p` of b's frame in a's.
    #[inline]
    pub(crate) fn apply(&self, p: &Point) -> Point {
        Point::from(self.rotation * p.coords + self.shift)
    }

    /// `p` of a's frame in b's (the inverse of [`Relative::apply`]).
    #[inline]
    pub(crate) fn apply_inverse(&self, p: &Point) -> Point {
        Point::from(self.rotation.tr_mul(&(p.coords - self.shift)))
    }
}

/// [`mesh_distance`] with `b` given in the frame of `a` (`pos_ab`, parry's
/// `pos12`); the points are returned in `a`'s frame.
pub fn mesh_distance_relative(
    a: &TriMesh,
    b: &TriMesh,
    pos_ab: &Pose,
    search: &DistanceSearch,
    scratch: &mut MeshDistanceScratch,
) -> MeshDistance {
    let relative = Relative::of(pos_ab);
    let (best, (i, j)) =
        search_relative(a, b, &relative, search, Real::INFINITY, scratch).unwrap_or((Real::INFINITY, (0, 0)));
    // The kernel's value (DyOP's, if chosen), points and features exact.
    MeshDistance { distance: best, ..pair_distance_relative(a, i, b, j, &relative) }
}

/// [`mesh_distance_relative`] where the meshes are closer than `ceiling`;
/// `None` where they are not (the search prunes every node pair bounded at
/// or beyond `ceiling` from the start, so a pair well beyond it costs a
/// few node pairs).
pub(crate) fn mesh_distance_below(
    a: &TriMesh,
    b: &TriMesh,
    pos_ab: &Pose,
    search: &DistanceSearch,
    ceiling: Real,
    scratch: &mut MeshDistanceScratch,
) -> Option<MeshDistance> {
    let relative = Relative::of(pos_ab);
    let (best, (i, j)) = search_relative(a, b, &relative, search, ceiling, scratch)?;
    Some(MeshDistance { distance: best, ..pair_distance_relative(a, i, b, j, &relative) })
}

/// The search of [`mesh_distance_relative`] and [`mesh_distance`], b's
/// frame in a's given as a matrix and a shift: the least distance by the
/// search's kernel and the triangle pair that has it (each caller measures
/// that pair in its own frame). Only pairs closer than `ceiling` are
/// looked for: `None` if there is none (with an infinite ceiling, only if
/// no distance is a number).
fn search_relative(
    a: &TriMesh,
    b: &TriMesh,
    relative: &Relative,
    search: &DistanceSearch,
    ceiling: Real,
    scratch: &mut MeshDistanceScratch,
) -> Option<(Real, (usize, usize))> {
    let DistanceSearch { kernel, hint, enough } = *search;
    let Relative { rotation, shift } = *relative;
    let slack = PRUNE_SLACK_ULPS * Real::EPSILON * (shift.norm() + a.radius() + b.radius());
    let nodes_a = a.bvh().nodes();
    let nodes_b = b.bvh().nodes();
    // b's triangles moved by the rotation matrix (fewer roundings than the
    // quaternion's sandwich, and faster).
    let triangle_b = |j: usize| -> Triangle { b.triangle(j).map(|p| relative.apply(&p)) };
    let pair_distance = |ta: &Triangle, tb: &Triangle| match kernel {
        DistanceKernel::Exact => triangle_distance(ta, tb).distance,
        DistanceKernel::Dyop(formula) => dyop_distance(ta, tb, formula),
    };

    let mut search = Search { best: ceiling, best_pair: None, evaluated: 0 };
    if let Some((i, j)) = hint.filter(|&(i, j)| i < a.triangles().len() && j < b.triangles().len()) {
        search.offer(pair_distance(&a.triangle(i), &triangle_b(j)), (i as u32, j as u32));
    }
    let lower_bound = |i: u32, j: u32, best: Real| {
        let (na, nb) = (&nodes_a[i as usize], &nodes_b[j as usize]);
        let cutoff = best + slack;
        let mut bound = node_lower_bound(na, nb, relative, cutoff);
        // Where the boxes are apart but too loose to prune (a small node
        // far from a leaf of slanted triangles), the leaf's triangles
        // against the other node's sphere, each way round; only where that
        // sphere is smaller than the leaf and than the boxes' gap (elsewhere
        // it seldom prunes more and costs four point–triangle distances).
        if bound < cutoff && nb.is_leaf() && na.radius < bound.min(nb.radius) {
            bound = leaf_sphere_gap(b, j, &relative.apply_inverse(&na.center), na.radius, bound);
        }
        if bound < cutoff && na.is_leaf() && nb.radius < bound.min(na.radius) {
            bound = leaf_sphere_gap(a, i, &relative.apply(&nb.center), nb.radius, bound);
        }
        // Small nodes: their vertices on the line of centres.
        if bound < cutoff {
            if let (Some(vertices_a), Some(vertices_b)) = (a.small_node_vertices(i), b.small_node_vertices(j))
            {
                bound = bound.max(vertex_slab((a, na, vertices_a), (b, nb, vertices_b), relative));
            }
        }
        bound - slack
    };

    scratch.nearest.clear();
    scratch.stack.clear();
    scratch.queue_pairs.clear();
    scratch.queue_a.clear();
    scratch.queue_b.clear();
    // With no first best, nearest first: only node pairs bounded below the
    // distance are opened, where a dive into the wrong region would open
    // every pair bounded below the best it finds there (on the KUKA link_1
    // by link4, three quarters of the pairs). From a hint, depth first (the
    // same pairs, in a stack's order, with its locality).
    let nearest_first = search.best_pair.is_none();
    let push = |scratch: &mut MeshDistanceScratch, pending: Pending| {
        if nearest_first {
            scratch.nearest.push(pending)
        } else {
            scratch.stack.push(pending)
        }
    };
    let mut pushed = 0;
    push(scratch, Pending::new(nearest_first, lower_bound(0, 0, Real::INFINITY), 0, pushed, (0, 0)));
    while let Some(pending) = if nearest_first { scratch.nearest.pop() } else { scratch.stack.pop() } {
        let (i, j, bound, depth) = (pending.i, pending.j, pending.bound, pending.depth());
        if nearest_first && bound >= search.best {
            // Every pair left is bounded at least as far; the queued
            // triangle pairs may still lower the best.
            flush(scratch, kernel, &mut search);
            if bound >= search.best {
                break;
            }
        }
        if search.best <= enough {
            // Near enough: what is left could only find closer pairs.
            break;
        }
        if bound >= search.best {
            continue;
        }
        let (na, nb) = (&nodes_a[i as usize], &nodes_b[j as usize]);
        if na.is_leaf() && nb.is_leaf() {
            // a's triangles with their boxes in a's frame and in b's (the
            // same test both ways round: argument order changes nothing).
            let mut leaf_a = [LeafTriangle::default(); BVH_LEAF_SIZE];
            for (k, ta) in (na.first..na.first + na.count).enumerate() {
                let triangle = a.triangle(ta as usize);
                let in_b = triangle.map(|p| relative.apply_inverse(&p));
                leaf_a[k] = LeafTriangle::of(triangle, triangle_box(&in_b));
            }
            for tb in nb.first..nb.first + nb.count {
                let moved = LeafTriangle::of(triangle_b(tb as usize), triangle_box(&b.triangle(tb as usize)));
                for (k, ta) in (na.first..na.first + na.count).enumerate() {
                    let triangle = &leaf_a[k];
                    // A lower bound of the pair's distance: a pair that
                    // cannot beat the best is skipped.
                    let gap = triangle.gap(&moved);
                    if gap - slack >= search.best {
                        continue;
                    }
                    scratch.queue_a.push(&triangle.points);
                    scratch.queue_b.push(&moved.points);
                    scratch.queue_pairs.push((ta, tb));
                }
            }
            if scratch.queue_pairs.len() >= FLUSH_PAIRS {
                flush(scratch, kernel, &mut search);
            }
            continue;
        }
        // Split the node that is not a leaf, the larger one if both are not.
        let split_a = !na.is_leaf() && (nb.is_leaf() || na.radius >= nb.radius);
        let children =
            if split_a { [(na.first, j), (na.first + 1, j)] } else { [(i, nb.first), (i, nb.first + 1)] };
        let bounds = children.map(|(ci, cj)| lower_bound(ci, cj, search.best));
        // Push the farther child first so the nearer one is searched first;
        // between children whose boxes both reach the other node (bounds
        // alike), the one whose centre is nearer its centre.
        let centres = |(ci, cj): (u32, u32)| {
            let (ca, cb) = (nodes_a[ci as usize].center, nodes_b[cj as usize].center);
            (rotation * cb.coords + shift - ca.coords).norm_squared()
        };
        let first = if (bounds[0] - bounds[1]).abs() <= slack {
            centres(children[0]) <= centres(children[1])
        } else {
            bounds[0] < bounds[1]
        };
        let order = if first { [1, 0] } else { [0, 1] };
        for k in order {
            if bounds[k] < search.best {
                pushed += 1;
                push(scratch, Pending::new(nearest_first, bounds[k], depth + 1, pushed, children[k]));
            }
        }
    }
    flush(scratch, kernel, &mut search);

    scratch.triangle_pairs = search.evaluated;
    let (i, j) = search.best_pair?;
    Some((search.best, (i as usize, j as usize)))
}

/// Triangle `i` of `a` and triangle `j` of `b` (posed by `pos_ab` in `a`'s
/// frame) as a [`MeshDistance`] in `a`'s frame, by the exact kernel.
pub(crate) fn triangle_pair_distance(
    a: &TriMesh,
    i: usize,
    b: &TriMesh,
    j: usize,
    pos_ab: &Pose,
) -> MeshDistance {
    pair_distance_relative(a, i, b, j, &Relative::of(pos_ab))
}

/// [`triangle_pair_distance`] with b's frame in a's given as a matrix.
fn pair_distance_relative(a: &TriMesh, i: usize, b: &TriMesh, j: usize, relative: &Relative) -> MeshDistance {
    let closest = triangle_distance(&a.triangle(i), &b.triangle(j).map(|p| relative.apply(&p)));
    MeshDistance {
        distance: closest.distance,
        point_a: closest.point_a,
        point_b: closest.point_b,
        triangle_a: i,
        triangle_b: j,
        feature_a: closest.feature_a,
        feature_b: closest.feature_b,
    }
}

/// The most rounds of [`walk_to_closer_pair`]: `16`. Each round looks at
/// the triangles around the pair's two triangles (those sharing a corner)
/// and moves to the closest pair among them, and the walk ends at the
/// first round that finds none closer; the cap only bounds a walk's cost.
pub(crate) const WALK_ROUNDS: usize = 16;

/// From triangle pair `start`, a walk over the meshes' triangles to a
/// closer pair: each round, triangle `i` of `a` is paired with each
/// triangle that shares a corner with `j` of `b` (posed by `pos_ab` in
/// `a`'s frame), and `j` with each around `i`; the closest of those
/// replaces the pair while it is closer, for at most [`WALK_ROUNDS`]
/// rounds. The pair's distance (exact kernel) and the pair: a distance the
/// meshes reach, so an upper bound on theirs, found in a few dozen
/// triangle pairs where a search measures thousands. It is the meshes'
/// distance where the closest pair lies downhill of `start` (a closest pair
/// followed over a short time), not in general.
pub(crate) fn walk_to_closer_pair(
    a: &TriMesh,
    b: &TriMesh,
    pos_ab: &Pose,
    start: (usize, usize),
) -> (Real, (usize, usize)) {
    let relative = Relative::of(pos_ab);
    let posed_b = |j: usize| b.triangle(j).map(|p| relative.apply(&p));
    let (mut i, mut j) = start;
    let (mut triangle_a, mut triangle_b) = (a.triangle(i), posed_b(j));
    let mut best = triangle_distance(&triangle_a, &triangle_b).distance;
    for _ in 0..WALK_ROUNDS {
        let mut next = None;
        for &corner in &a.triangles()[i] {
            for &k in a.triangles_at(corner as usize) {
                let candidate = a.triangle(k as usize);
                let distance = triangle_distance(&candidate, &triangle_b).distance;
                if distance < best {
                    (best, next) = (distance, Some((k as usize, j)));
                }
            }
        }
        for &corner in &b.triangles()[j] {
            for &k in b.triangles_at(corner as usize) {
                let distance = triangle_distance(&triangle_a, &posed_b(k as usize)).distance;
                if distance < best {
                    (best, next) = (distance, Some((i, k as usize)));
                }
            }
        }
        let Some(pair) = next else { break };
        (i, j) = pair;
        (triangle_a, triangle_b) = (a.triangle(i), posed_b(j));
    }
    (best, (i, j))
}

/// The distance between two posed meshes by brute force: every triangle
/// pair, both meshes moved to the world, the scalar exact kernel. The
/// reference [`mesh_distance`] is tested against (quadratic: for tests and
/// reports only).
pub fn mesh_distance_brute_force(a: &TriMesh, pose_a: &Pose, b: &TriMesh, pose_b: &Pose) -> Real {
    let moved_b: Vec<Triangle> =
        (0..b.triangles().len()).map(|j| b.triangle(j).map(|p| pose_b * p)).collect();
    let mut best = Real::INFINITY;
    for i in 0..a.triangles().len() {
        let ta = a.triangle(i).map(|p| pose_a * p);
        for tb in &moved_b {
            best = best.min(triangle_distance(&ta, tb).distance);
        }
    }
    best
}

/// A triangle's axis-aligned box: its lowest and highest corners.
#[inline]
fn triangle_box(t: &Triangle) -> [Vector; 2] {
    let [p, q, r] = t;
    [p.coords.inf(&q.coords).inf(&r.coords), p.coords.sup(&q.coords).sup(&r.coords)]
}

/// The distance between two axis-aligned boxes (0 when they overlap).
#[inline]
fn box_gap(a: &[Vector; 2], b: &[Vector; 2]) -> Real {
    let gap = (b[0] - a[1]).sup(&(a[0] - b[1])).sup(&Vector::zeros());
    gap.norm()
}

/// A triangle of a leaf pair, in a's frame, with its boxes: there and in
/// its own mesh's frame (b's, for a triangle of a), for the pair's cheap
/// lower bound.
#[derive(Copy, Clone, Default)]
struct LeafTriangle {
    points: Triangle,
    /// Its box in a's frame.
    box_here: [Vector; 2],
    /// Its box in b's frame.
    box_there: [Vector; 2],
}

impl LeafTriangle {
    #[inline]
    fn of(points: Triangle, box_there: [Vector; 2]) -> LeafTriangle {
        LeafTriangle { points, box_here: triangle_box(&points), box_there }
    }

    /// A lower bound on the distance between the two triangles: the gap
    /// between their boxes in a's frame or in b's, the larger (the same
    /// bound with the meshes in either order). (A face's plane as a
    /// further bound was tried: on pybullet_data's meshes it pruned 0.3%
    /// more pairs and cost more than it saved.)
    #[inline]
    fn gap(&self, other: &LeafTriangle) -> Real {
        box_gap(&self.box_here, &other.box_here).max(box_gap(&self.box_there, &other.box_there))
    }
}

/// A lower bound on the distance between the triangles of leaf node `k`
/// of `mesh` and a sphere (`centre` in `mesh`'s frame, `radius`): the least
/// distance from the centre to a triangle, less the radius. Far tighter
/// than two boxes where the sphere is small beside its distance, as a
/// robot link's node in a gear ring's hole: each ring triangle's box
/// leaves a millimetre of slack where the candidates lie within a tenth
/// of one another.
///
/// Returns the larger of that and `floor`, a bound already known. Where
/// a vertex is within `floor + radius` of the centre the answer is
/// `floor`, found from the leaf's distinct vertices
/// ([`TriMesh::leaf_vertices`]) without its triangles. On pybullet_data's
/// meshes two thirds of the looks near the gear ring end so, and the
/// distance queries take a fifth less time, every search the same node for
/// node. The distances of the others are taken four at once, in vector
/// lanes ([`nearest_of_four`]): the same values as one at a time.
fn leaf_sphere_gap(mesh: &TriMesh, k: u32, centre: &Point, radius: Real, floor: Real) -> Real {
    // A vertex within `floor + radius` of the centre: no triangle can
    // raise the bound (a vertex's distance is at least its triangle's).
    // The leaf's distinct vertices, read before its triangles.
    let reach = floor + radius;
    let reach_squared = if reach > 0.0 { reach * reach } else { -1.0 };
    let points = mesh.vertices();
    if mesh.leaf_vertices(k).iter().any(|&v| (points[v as usize] - centre).norm_squared() <= reach_squared) {
        return floor;
    }
    // The leaf's triangles (at most four: `BVH_LEAF_SIZE`; the first
    // repeated to fill).
    const _: () = assert!(BVH_LEAF_SIZE <= 4);
    let leaf = &mesh.bvh().nodes()[k as usize];
    let (first, count) = (leaf.first as usize, leaf.count as usize);
    let four = [0, 1, 2, 3].map(|j| mesh.triangle(first + if j < count { j } else { 0 }));
    (nearest_of_four(centre, &four) - radius).max(floor)
}

/// A node pair waiting to be searched, with its lower bound. Nearest
/// first, the least bound is taken first; among bounds alike to single
/// precision (overlapping nodes are all bounded at 0), the deeper pair,
/// then the one pushed last, so that the search reaches a leaf pair, and a
/// first best, as a depth-first search would. That order is one integer
/// (`BinaryHeap` pops the greatest); the bound itself decides what is
/// pruned.
#[derive(Copy, Clone, Debug)]
struct Pending {
    order: u64,
    bound: Real,
    i: u32,
    j: u32,
}

impl Pending {
    fn new(nearest_first: bool, bound: Real, depth: u32, pushed: u32, (i, j): (u32, u32)) -> Pending {
        // A non-negative `f32`'s bits grow with it.
        let nearer = if nearest_first { u32::MAX - (bound.max(0.0) as f32).to_bits() } else { 0 };
        let order =
            (u64::from(nearer) << 32) | (u64::from(depth.min(255)) << 24) | u64::from(pushed & 0xff_ffff);
        Pending { order, bound, i, j }
    }

    /// The pair's depth in the search (capped at 255).
    fn depth(&self) -> u32 {
        (self.order >> 24) as u32 & 0xff
    }
}

impl Ord for Pending {
    fn cmp(&self, other: &Pending) -> Ordering {
        self.order.cmp(&other.order)
    }
}

impl PartialOrd for Pending {
    fn partial_cmp(&self, other: &Pending) -> Option<Ordering> {
        Some(self.cmp(other))
    }
}

impl PartialEq for Pending {
    fn eq(&self, other: &Pending) -> bool {
        self.order == other.order
    }
}

impl Eq for Pending {}

/// The most triangles under a node for [`vertex_slab`]: `16` (its
/// distinct vertices read from the mesh's table,
/// [`TriMesh::small_node_vertices`]: on a KUKA link about 13 where a
/// node's triangles have 33 corners). On the KUKA links 7
/// and 1, 0.1 apart, the slab of nodes of up to 16 triangles cut the
/// search's time by 45%; up to 8, by 35%; up to 64, by 55% there, but
/// other pairs' searches took 20–30% longer.
pub(crate) const SLAB_TRIANGLES: u32 = 16;

/// A lower bound on the distance between the triangles under node `na` of
/// `a` (whose distinct vertices are `vertices_a`) and those under `nb` of
/// `b` (`vertices_b`, moved by `relative`): the gap between their vertices
/// projected on the line of the nodes' centres. Where two curved patches
/// face each other, their boxes hold much empty space and the boxes' gap
/// falls well short; the vertices' does not (on the KUKA links 7 and 1,
/// 0.1 apart, 83% of the node pairs the boxes left open lay beyond the
/// distance by this bound). Rounding: the projections err by a few ulps of
/// the coordinates, within the search's prune slack.
fn vertex_slab(
    (a, na, vertices_a): (&TriMesh, &super::BvhNode, &[u32]),
    (b, nb, vertices_b): (&TriMesh, &super::BvhNode, &[u32]),
    relative: &Relative,
) -> Real {
    let offset = relative.apply(&nb.center) - na.center;
    let length = offset.norm();
    if length == 0.0 {
        return 0.0;
    }
    let line = offset / length;
    // b's vertices are projected in b's frame: `line · (R p + shift)`.
    let line_b = relative.rotation.tr_mul(&line);
    let shift = line.dot(&relative.shift);
    let (points_a, points_b) = (a.vertices(), b.vertices());
    let high_a = vertices_a
        .iter()
        .map(|&v| line.dot(&points_a[v as usize].coords))
        .fold(Real::NEG_INFINITY, Real::max);
    let low_b =
        vertices_b.iter().map(|&v| line_b.dot(&points_b[v as usize].coords)).fold(Real::INFINITY, Real::min);
    low_b + shift - high_a
}

/// The best pair so far.
struct Search {
    best: Real,
    best_pair: Option<(u32, u32)>,
    evaluated: usize,
}

impl Search {
    #[inline]
    fn offer(&mut self, distance: Real, pair: (u32, u32)) {
        self.evaluated += 1;
        if distance < self.best {
            self.best = distance;
            self.best_pair = Some(pair);
        }
    }
}

/// Evaluates the queued triangle pairs and empties the queue.
fn flush(scratch: &mut MeshDistanceScratch, kernel: DistanceKernel, search: &mut Search) {
    let n = scratch.queue_pairs.len();
    if n == 0 {
        return;
    }
    scratch.distances.resize(n, 0.0);
    match kernel {
        DistanceKernel::Exact => {
            batch::triangle_distances(&scratch.queue_a, &scratch.queue_b, &mut scratch.distances)
        }
        DistanceKernel::Dyop(formula) => {
            for (k, d) in scratch.distances.iter_mut().enumerate() {
                *d = dyop_distance(&scratch.queue_a.get(k), &scratch.queue_b.get(k), formula);
            }
        }
    }
    for k in 0..n {
        search.offer(scratch.distances[k], scratch.queue_pairs[k]);
    }
    scratch.queue_pairs.clear();
    scratch.queue_a.clear();
    scratch.queue_b.clear();
}

/// A lower bound on the distance between node `na` (frame of `a`) and node
/// `nb` moved into a's frame by `relative`: the largest of the sphere–sphere
/// distance and the distances between each node's box and the box around
/// the other node's box, taken along the first box's axes (each box's
/// three face axes: the bound is the same with the meshes in either
/// order). Pairs whose spheres are `cutoff` or more apart skip the boxes
/// (pruned either way).
#[inline]
pub(crate) fn node_lower_bound(
    na: &super::BvhNode,
    nb: &super::BvhNode,
    relative: &Relative,
    cutoff: Real,
) -> Real {
    let rotation = &relative.rotation;
    let center_b = rotation * nb.center.coords + relative.shift;
    let offset = center_b - na.center.coords;
    let spheres = offset.norm() - na.radius - nb.radius;
    if spheres >= cutoff {
        return spheres;
    }
    let axes_b = rotation * nb.axes;
    // Cosines between a's axes (rows) and b's (columns).
    let cosines = na.axes.tr_mul(&axes_b).abs();
    let zero = nalgebra::Vector3::zeros();
    let along_a = (na.axes.tr_mul(&offset).abs() - na.half_extents - cosines * nb.half_extents).sup(&zero);
    let along_b =
        (axes_b.tr_mul(&offset).abs() - nb.half_extents - cosines.tr_mul(&na.half_extents)).sup(&zero);
    along_a.norm().max(along_b.norm()).max(spheres)
}

#[cfg(test)]
mod tests {
    /// `summary.json` writes a contact's closest points as a
    /// `MeshDistance` serialises: points as arrays, features by their
    /// names (not the variants' Rust names, so a rename changes no file).
    #[test]
    fn a_distance_serialises_with_features_by_name() {
        let d = MeshDistance {
            distance: 0.25,
            point_a: Point::new(1.0, 2.0, 3.0),
            point_b: Point::new(1.0, 2.0, 3.25),
            triangle_a: 4,
            triangle_b: 7,
            feature_a: Feature::Edge(2),
            feature_b: Feature::Vertex(0),
        };
        let json = serde_json::to_string(&d).expect("serialisable");
        assert_eq!(
            json,
            r#"{"distance":0.25,"point_a":[1.0,2.0,3.0],"point_b":[1.0,2.0,3.25],"triangle_a":4,"triangle_b":7,"feature_a":"edge 2","feature_b":"vertex 0"}"#
        );
        let face = MeshDistance { feature_a: Feature::Face, ..d };
        assert!(serde_json::to_string(&face).expect("serialisable").contains(r#""feature_a":"face""#));
    }

    use super::super::primitives::{box_mesh, icosphere};
    use super::*;
    use crate::math::Vector;
    use crate::samples::Rng;

    #[test]
    fn matches_brute_force_on_random_poses() {
        let a = icosphere(1.0, 2).unwrap();
        let b = box_mesh(&Vector::new(0.3, 1.2, 0.5)).unwrap();
        let mut rng = Rng::new(7);
        let mut scratch = MeshDistanceScratch::default();
        for case in 0..60 {
            let random_pose =
                |rng: &mut Rng, reach: Real| Pose::new(rng.in_unit_ball() * reach, rng.in_unit_ball() * 3.0);
            let pose_a = random_pose(&mut rng, 1.0);
            let pose_b = random_pose(&mut rng, 3.0);
            let fast = mesh_distance(&a, &pose_a, &b, &pose_b, &DistanceSearch::default(), &mut scratch);
            let slow = mesh_distance_brute_force(&a, &pose_a, &b, &pose_b);
            // The two move b by different roundings: agree to rounding of the poses.
            assert!((fast.distance - slow).abs() <= 1e-13, "case {case}: {} vs {slow}", fast.distance);
            assert!(((fast.point_a - fast.point_b).norm() - fast.distance).abs() <= 1e-13);
            assert!(scratch.triangle_pairs() < a.triangles().len() * b.triangles().len());
        }
    }

    #[test]
    fn a_vertex_slab_never_exceeds_its_nodes_distance_and_meets_it_face_to_face() {
        // Every pair of small nodes of two icospheres (and of an icosphere
        // and a box) 0.01 to 1 apart, turned at random: the slab is at most
        // the least distance between the nodes' triangles (every pair
        // measured by the exact kernel), to rounding.
        let sphere = icosphere(1.0, 2).unwrap();
        let small = icosphere(0.5, 1).unwrap();
        let slab = box_mesh(&Vector::new(0.6, 0.4, 0.05)).unwrap();
        let mut rng = Rng::new(47);
        let (mut checked, mut positive) = (0, 0);
        for case in 0..12 {
            let b = if case % 2 == 0 { &small } else { &slab };
            let gap = rng.log_range(1e-2, 1.0);
            let pos_ab = Pose::new(rng.unit_vector() * (1.5 + gap), rng.in_unit_ball() * 3.0);
            let relative = Relative::of(&pos_ab);
            let (nodes_a, nodes_b) = (sphere.bvh().nodes(), b.bvh().nodes());
            for i in 0..nodes_a.len() as u32 {
                let Some(span_a) = sphere.bvh().small_span(i, SLAB_TRIANGLES) else { continue };
                for j in 0..nodes_b.len() as u32 {
                    let Some(span_b) = b.bvh().small_span(j, SLAB_TRIANGLES) else { continue };
                    let (na, nb) = (&nodes_a[i as usize], &nodes_b[j as usize]);
                    let (vertices_a, vertices_b) = (
                        sphere.small_node_vertices(i).expect("a small node's vertices"),
                        b.small_node_vertices(j).expect("a small node's vertices"),
                    );
                    let bound = vertex_slab((&sphere, na, vertices_a), (b, nb, vertices_b), &relative);
                    let mut least = Real::INFINITY;
                    for ta in span_a.0..span_a.1 {
                        for tb in span_b.0..span_b.1 {
                            let moved = b.triangle(tb as usize).map(|p| relative.apply(&p));
                            least =
                                least.min(triangle_distance(&sphere.triangle(ta as usize), &moved).distance);
                        }
                    }
                    assert!(
                        bound <= least + 1e-14,
                        "case {case}, nodes {i}, {j}: slab {bound} beyond {least}"
                    );
                    checked += 1;
                    positive += usize::from(bound > 0.0);
                }
            }
        }
        assert!(checked > 10_000 && positive > checked / 4, "{positive} positive of {checked}");
        // Two faces of a box square to each other across the line of
        // centres: the slab is their distance.
        let plate = box_mesh(&Vector::new(0.5, 0.5, 0.1)).unwrap();
        let pos_ab = Pose::translation(0.0, 0.0, 0.7);
        let (nodes, relative) = (plate.bvh().nodes(), Relative::of(&pos_ab));
        let corners = plate.small_node_vertices(0).expect("a box is one small node");
        let bound = vertex_slab((&plate, &nodes[0], corners), (&plate, &nodes[0], corners), &relative);
        assert!((bound - 0.5).abs() <= 1e-15, "{bound}");
    }

    #[test]
    fn a_walk_follows_a_closest_pair_and_never_undercuts_the_distance() {
        // Two icospheres 0.001 to 0.5 apart; b then turns by up to 0.05 rad
        // and moves by up to 0.01. From the closest pair before, the walk
        // reaches the distance after (a scan of every triangle pair is the
        // reference); from any pair, it names a pair at the distance it
        // gives, never below the scan's.
        let a = icosphere(1.0, 2).unwrap();
        let b = icosphere(0.6, 2).unwrap();
        let mut rng = Rng::new(11);
        let mut scratch = MeshDistanceScratch::default();
        for case in 0..60 {
            let pose_a = Pose::new(rng.in_unit_ball(), rng.in_unit_ball() * 3.0);
            let gap = rng.log_range(1e-3, 0.5);
            let centre_b = pose_a.translation.vector + rng.unit_vector() * (1.0 + 0.6 + gap);
            let before = Pose::new(centre_b, rng.in_unit_ball() * 3.0);
            let after = Pose::new(rng.in_unit_ball() * 0.01, rng.in_unit_ball() * 0.05) * before;
            let start = mesh_distance(&a, &pose_a, &b, &before, &DistanceSearch::default(), &mut scratch);
            let pos_ab = pose_a.inverse() * after;
            let scan = mesh_distance_brute_force(&a, &pose_a, &b, &after);
            let (walked, (i, j)) = walk_to_closer_pair(&a, &b, &pos_ab, (start.triangle_a, start.triangle_b));
            assert!((walked - scan).abs() <= 1e-13, "case {case}: walked {walked}, scan {scan}");
            assert_eq!(walked, triangle_pair_distance(&a, i, &b, j, &pos_ab).distance);
            let anywhere = (rng.index(a.triangles().len()), rng.index(b.triangles().len()));
            let (walked, (i, j)) = walk_to_closer_pair(&a, &b, &pos_ab, anywhere);
            assert!(walked >= scan - 1e-13, "case {case}: walked {walked} below the scan's {scan}");
            assert_eq!(walked, triangle_pair_distance(&a, i, &b, j, &pos_ab).distance);
        }
    }

    #[test]
    fn a_search_below_a_ceiling_finds_only_what_is_closer() {
        // An icosphere and a box apart (their centres 2.5 plus 1e-4 to 1
        // apart), the ceiling just above or at or below their distance (the
        // brute-force scan's): above, the distance and pair the plain search
        // gives; at or below, none, for no more triangle pairs than the
        // plain search measures.
        let a = icosphere(1.0, 2).unwrap();
        let b = box_mesh(&Vector::new(0.3, 1.2, 0.5)).unwrap();
        let mut rng = Rng::new(29);
        let mut scratch = MeshDistanceScratch::default();
        let search = DistanceSearch::default();
        for case in 0..60 {
            let gap = rng.log_range(1e-4, 1.0);
            let pos_ab = Pose::new(rng.unit_vector() * (2.5 + gap), rng.in_unit_ball() * 3.0);
            let plain = mesh_distance_relative(&a, &b, &pos_ab, &search, &mut scratch);
            let searched = scratch.triangle_pairs();
            let scan = mesh_distance_brute_force(&a, &Pose::identity(), &b, &pos_ab);
            assert!((plain.distance - scan).abs() <= 1e-13, "case {case}: {} vs {scan}", plain.distance);
            let above = plain.distance * (1.0 + 1e-9);
            let found = mesh_distance_below(&a, &b, &pos_ab, &search, above, &mut scratch);
            assert_eq!(found, Some(plain), "case {case}: below {above}");
            for ceiling in [plain.distance, plain.distance * 0.999, plain.distance * 0.5] {
                let found = mesh_distance_below(&a, &b, &pos_ab, &search, ceiling, &mut scratch);
                assert_eq!(found, None, "case {case}: below {ceiling}");
                assert!(scratch.triangle_pairs() <= searched, "case {case}");
            }
        }
    }
}

//! The broad phase: the pairs of bodies whose swept boxes overlap in a step.
//!
//! A body's swept box covers its whole motion over the step, rotation
//! included. Along each axis `e`, the mesh reaches at most `h(0)` beyond
//! its centre at the step's start (the box of its vertices in its own
//! frame, turned to the world: `(R c)·e + Σ_j |R_ej| s_j` for the box's
//! centre `c` and half sizes `s`), and turning with angular velocity `ω`
//! moves that reach by at most `|e × ω| r` per unit time (`r` the mesh's
//! radius about its centre of mass), never beyond `r`; the centre moves in
//! a straight line. So the box is the centre's box over the step grown, per
//! axis and side, by `min(r, h(0) + |e × ω| r dt)`: the mesh's own box for
//! a body that does not turn with its box's axes along the world's (a
//! fixed wall), and never more than the box of the bounding sphere.
//! The boxes go into parry's `Bvh`, whose self-traversal yields the
//! overlapping pairs. The tree is built once and then refitted to the
//! moved boxes at each step while the number of bodies stays the same
//! (cheaper than a rebuild when they moved little, as between two steps),
//! and incrementally re-optimised at every second refit
//! (`OPTIMIZE_EVERY_REFITS`; parry rebuilds a few subtrees a call): a
//! refitted tree alone degrades as the bodies mix, its boxes growing until
//! a traversal meets most of the tree.
//! Pairs of two fixed bodies are dropped.

use parry3d_f64::bounding_volume::Aabb;
use parry3d_f64::partitioning::{Bvh, BvhBuildStrategy, BvhWorkspace};

use crate::math::{Point, Real, Vector};
use crate::mesh::TriMesh;
use crate::motion::StepMotion;

/// The tree is re-optimised (parry's `optimize_incremental`) at every this
/// many refits: every second refit keeps the traversal as fast as every
/// refit for half the optimisation's cost (measured on the 1,000-body box:
/// `docs/benchmarks-history.md`).
pub(crate) const OPTIMIZE_EVERY_REFITS: u64 = 2;

/// A swept box: smallest and largest corners.
pub type SweptBox = (Point, Point);

/// The box around `mesh` (vertices about its centre of mass) over the step
/// of length `duration` of `motion` (see the module), grown by `margin`.
pub fn swept_box(mesh: &TriMesh, motion: &StepMotion, duration: Real, margin: Real) -> SweptBox {
    let (start, end) = (motion.center_at(0.0), motion.center_at(duration));
    let (mut low, mut high) = (start.inf(&end), start.sup(&end));
    let rotation = motion.rotation_at(0.0).to_rotation_matrix();
    let radius = mesh.radius();
    let (box_low, box_high) = mesh.bounds();
    let centre = rotation * (box_low.coords + box_high.coords) * 0.5;
    let half = (box_high - box_low) * 0.5;
    for k in 0..3 {
        let axis = Vector::ith(k, 1.0);
        let turn = axis.cross(&motion.angular_velocity).norm() * radius * duration;
        let spread = (0..3).map(|j| rotation[(k, j)].abs() * half[j]).sum::<Real>();
        high[k] += (centre[k] + spread + turn).min(radius) + margin;
        low[k] -= (spread - centre[k] + turn).min(radius) + margin;
    }
    (low, high)
}

/// Whether two boxes overlap (touching counts).
#[inline]
pub fn boxes_overlap(a: &SweptBox, b: &SweptBox) -> bool {
    (0..3).all(|k| a.0[k] <= b.1[k] && b.0[k] <= a.1[k])
}

/// The distance between two boxes (0 where they touch or overlap): a
/// lower bound on the distance between anything inside them.
#[inline]
pub fn box_gap(a: &SweptBox, b: &SweptBox) -> Real {
    let separation = Vector::from_fn(|k, _| (a.0[k] - b.1[k]).max(b.0[k] - a.1[k]).max(0.0));
    separation.norm()
}

/// The pairs `(i, j)`, `i < j`, sorted, of boxes apart by at most `within`
/// along every axis (overlapping boxes for `0`; a superset of the pairs
/// whose [`box_gap`] is at most `within`), by a sort and sweep along x:
/// `O(n log n)` and the pairs whose x spans come that near.
pub fn sweep_pairs(boxes: &[SweptBox], within: Real) -> Vec<(usize, usize)> {
    let mut order: Vec<usize> = (0..boxes.len()).collect();
    order.sort_by(|&i, &j| boxes[i].0.x.total_cmp(&boxes[j].0.x).then(i.cmp(&j)));
    let near = |a: &SweptBox, b: &SweptBox, k: usize| a.0[k] - b.1[k] <= within && b.0[k] - a.1[k] <= within;
    let mut pairs = Vec::new();
    for (n, &i) in order.iter().enumerate() {
        for &j in &order[n + 1..] {
            if boxes[j].0.x - boxes[i].1.x > within {
                break;
            }
            if near(&boxes[i], &boxes[j], 1) && near(&boxes[i], &boxes[j], 2) {
                pairs.push((i.min(j), i.max(j)));
            }
        }
    }
    pairs.sort_unstable();
    pairs
}

/// The overlapping pairs `(i, j)`, `i < j`, sorted, by brute force over all
/// pairs (the reference the tree is tested against).
pub fn brute_force_pairs(boxes: &[SweptBox]) -> Vec<(usize, usize)> {
    let mut pairs = Vec::new();
    for i in 0..boxes.len() {
        for j in i + 1..boxes.len() {
            if boxes_overlap(&boxes[i], &boxes[j]) {
                pairs.push((i, j));
            }
        }
    }
    pairs
}

/// The broad phase's reusable state.
#[derive(Default)]
pub struct BroadPhase {
    workspace: BvhWorkspace,
    leaves: Vec<Aabb>,
    /// The tree of the previous call, refitted while the number of boxes
    /// stays the same.
    tree: Option<Bvh>,
    /// Refits since the tree was built.
    refits: u64,
}

impl std::fmt::Debug for BroadPhase {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("BroadPhase").field("leaves", &self.leaves.len()).finish()
    }
}

impl BroadPhase {
    /// The overlapping pairs `(i, j)`, `i < j`, sorted, through parry's BVH.
    pub fn pairs(&mut self, boxes: &[SweptBox]) -> Vec<(usize, usize)> {
        let mut pairs = Vec::new();
        self.pairs_into(boxes, &mut pairs);
        pairs
    }

    /// [`BroadPhase::pairs`] into `pairs` (cleared first): a buffer kept
    /// between steps, so that a step allocates nothing once it has grown.
    pub fn pairs_into(&mut self, boxes: &[SweptBox], pairs: &mut Vec<(usize, usize)>) {
        pairs.clear();
        self.leaves.clear();
        let corner = |p: &Point| parry3d_f64::math::Vector::new(p.x, p.y, p.z);
        self.leaves.extend(boxes.iter().map(|(low, high)| Aabb::new(corner(low), corner(high))));
        if boxes.len() >= 2 {
            let bvh = match self.tree.as_mut() {
                // The same bodies: move the leaves and refit (cheaper than a
                // rebuild when they moved little, as between two steps).
                Some(tree) if tree.leaf_count() as usize == self.leaves.len() => {
                    for (i, leaf) in self.leaves.iter().enumerate() {
                        tree.insert_or_update_partially(*leaf, i as u32, 0.0);
                    }
                    tree.refit(&mut self.workspace);
                    // Bodies that mix (a gas in a box) leave the first
                    // tree's grouping behind: refitted alone, its boxes
                    // grow until a traversal meets most of the tree.
                    // parry's incremental optimisation rebuilds a few
                    // subtrees a call.
                    self.refits += 1;
                    if self.refits.is_multiple_of(OPTIMIZE_EVERY_REFITS) {
                        tree.optimize_incremental(&mut self.workspace);
                    }
                    tree
                }
                _ => {
                    self.refits = 0;
                    self.tree.insert(Bvh::from_leaves(BvhBuildStrategy::Binned, &self.leaves))
                }
            };
            bvh.traverse_bvtt_single_tree::<false>(&mut self.workspace, &mut |i, j| {
                let (i, j) = (i as usize, j as usize);
                pairs.push((i.min(j), i.max(j)));
            });
        }
        pairs.sort_unstable();
        pairs.dedup();
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::samples::Rng;

    #[test]
    fn tree_pairs_equal_brute_force_pairs() {
        let mut rng = Rng::new(17);
        let mut broad = BroadPhase::default();
        for &n in &[0usize, 1, 2, 3, 10, 100, 700] {
            let boxes: Vec<SweptBox> = (0..n)
                .map(|_| {
                    let center = Point::from(rng.in_unit_ball() * 20.0);
                    let half = Vector::new(rng.range(0.05, 2.0), rng.range(0.05, 2.0), rng.range(0.05, 2.0));
                    (center - half, center + half)
                })
                .collect();
            assert_eq!(broad.pairs(&boxes), brute_force_pairs(&boxes), "{n} boxes");
            assert_eq!(sweep_pairs(&boxes, 0.0), brute_force_pairs(&boxes), "{n} boxes");
            // Widened by `within`: every pair whose boxes' gap is that small
            // or smaller, and only pairs near along every axis.
            let within = 1.5;
            let near = sweep_pairs(&boxes, within);
            let grown: Vec<SweptBox> = boxes
                .iter()
                .map(|(l, h)| (l - Vector::repeat(within / 2.0), h + Vector::repeat(within / 2.0)))
                .collect();
            assert_eq!(near, brute_force_pairs(&grown), "{n} boxes");
            for i in 0..n {
                for j in i + 1..n {
                    if box_gap(&boxes[i], &boxes[j]) <= within {
                        assert!(near.binary_search(&(i, j)).is_ok());
                    }
                }
            }
        }
    }

    #[test]
    fn refitted_tree_pairs_equal_brute_force_pairs() {
        // The same 300 boxes moving over 20 calls: the refitted tree's pairs
        // stay those of brute force, including boxes that jump far.
        let mut rng = Rng::new(29);
        let mut broad = BroadPhase::default();
        let mut centers: Vec<Point> = (0..300).map(|_| Point::from(rng.in_unit_ball() * 15.0)).collect();
        for call in 0..20 {
            for (k, c) in centers.iter_mut().enumerate() {
                *c += rng.in_unit_ball() * if k % 50 == call { 20.0 } else { 0.5 };
            }
            let boxes: Vec<SweptBox> = centers
                .iter()
                .map(|c| {
                    let half = Vector::repeat(rng.range(0.2, 1.5));
                    (c - half, c + half)
                })
                .collect();
            assert_eq!(broad.pairs(&boxes), brute_force_pairs(&boxes), "call {call}");
        }
    }

    /// Every vertex of a tumbling mesh, posed at many times of the step,
    /// lies in its swept box; a box that does not turn gets exactly its
    /// vertices' box, and no box is larger than its bounding sphere's.
    /// The box of the bounding sphere over the step.
    fn swept_sphere_box(mesh: &TriMesh, motion: &StepMotion, duration: Real) -> SweptBox {
        let (start, end) = (motion.center_at(0.0), motion.center_at(duration));
        let grow = Vector::repeat(mesh.radius());
        (start.inf(&end) - grow, start.sup(&end) + grow)
    }

    #[test]
    fn the_swept_box_holds_the_mesh_over_the_step() {
        use crate::math::Pose;
        let meshes = [
            crate::mesh::icosphere(0.5, 3).expect("an icosphere"),
            crate::mesh::box_mesh(&Vector::new(1.0, 0.2, 0.4)).expect("a box"),
        ];
        let mut rng = Rng::new(41);
        for case in 0..200 {
            let mesh = &meshes[case % 2];
            let spin = if case % 4 < 2 { 30.0 } else { 0.0 };
            let motion = StepMotion::new(
                Pose::new(rng.in_unit_ball() * 5.0, rng.in_unit_ball() * 3.0),
                rng.in_unit_ball() * 4.0,
                rng.in_unit_ball() * spin,
            );
            let duration = 0.05;
            let (low, high) = swept_box(mesh, &motion, duration, 0.0);
            let slack = 1e-12;
            for k in 0..=100 {
                let pose = motion.pose_at(duration * k as Real / 100.0);
                for v in mesh.vertices() {
                    let p = pose * v;
                    for axis in 0..3 {
                        assert!(
                            p[axis] >= low[axis] - slack && p[axis] <= high[axis] + slack,
                            "case {case}: a vertex leaves the box along axis {axis}"
                        );
                    }
                }
            }
            let sphere = swept_sphere_box(mesh, &motion, duration);
            for axis in 0..3 {
                assert!(
                    low[axis] >= sphere.0[axis] - slack && high[axis] <= sphere.1[axis] + slack,
                    "case {case}"
                );
            }
            if spin == 0.0 && case % 2 == 1 {
                // The box of the posed vertices at the start and the end.
                let posed = [0.0, duration]
                    .iter()
                    .flat_map(|&s| mesh.vertices().iter().map(move |v| motion.pose_at(s) * v))
                    .collect::<Vec<_>>();
                for axis in 0..3 {
                    let lowest = posed.iter().map(|p| p[axis]).fold(Real::INFINITY, Real::min);
                    let highest = posed.iter().map(|p| p[axis]).fold(Real::NEG_INFINITY, Real::max);
                    assert!(
                        (low[axis] - lowest).abs() < 1e-12 && (high[axis] - highest).abs() < 1e-12,
                        "case {case}"
                    );
                }
            }
        }
    }
}

//! The step search of a rigid mesh pair: the longest time before which no
//! triangle pair can come within `target`, found by branch and bound over
//! both BVHs with the bounds of `mesh_bound.rs`.
//!
//! ## A front kept between steps
//! The step is the smallest time over all triangle pairs. The search keeps a
//! *front*: a cut through the tree of node pairs (every triangle pair lies
//! below exactly one element), each element with the absolute time until
//! which nothing below it can come within `target`, in a heap ordered by
//! that time. A bound stays valid after the time it was computed at, so the
//! front is kept across the advancement steps of a query (temporal
//! coherence): an element whose time lies beyond the next step is not
//! looked at again, and a node pair that can never come close during the
//! rest of the interval is settled once for the whole loop.
//!
//! Each step, the earliest element is taken while it limits the step:
//! - a node pair bounded at an earlier time is bounded again now;
//! - a node pair bounded now is opened (its children, or the triangle pairs
//!   of two leaves, enter the front with their own bounds, never shorter
//!   than their parent's, which still holds), unless the radii it would
//!   shrink are small against its distance above the target
//!   ([`OPEN_RATIO`]): then the children would be bounded no better and
//!   the search stops there;
//! - two leaves are first bounded together, with the exact kernel
//!   ([`PosedPair::leaves_time`]: one triangle pair's turning slab over
//!   every vertex of both): where that reaches far enough, the pair of
//!   leaves enters the front instead of its triangle pairs, and is bounded
//!   again the same way when it limits a later step; where it falls short
//!   now, it is opened into its triangle pairs. Two flat patches passing
//!   each other (a closest approach's proof, a hair below their distance)
//!   are then bounded a leaf pair at a time, not a triangle pair;
//! - a triangle pair with only the cheap bound (the slab along the line
//!   between its centroids) or one evaluated earlier is evaluated in full
//!   now, and a triangle pair within the contact distance ends the search
//!   with a contact;
//! - a triangle pair evaluated now ends the search: nothing can do better.
//!
//! The search also stops as soon as the earliest element is within
//! [`STEP_SLACK`] of the shortest triangle pair time found in this search,
//! which is then the step at a fraction of the work. An element below
//! `min_step` is always refined, so a triangle pair within the contact
//! distance is found whenever the meshes can reach `target`, and without
//! one the step is at least `min_step` (each full triangle pair time is, by
//! its head-on bound): the loop advances. A pair that stays between `target`
//! and the contact distance without ever closing to `target` (a resting
//! pair, a receding one) need not be reported.

use super::mesh_bound::{lopsided_leaf, node_pair_time, vertex_slab_time, PairFrame, Side};
use super::posed_pair::PosedPair;
use crate::math::Real;
use crate::mesh::{BvhNode, DistanceKernel, TriMesh};

/// The search stops once the front's earliest time is within this fraction
/// of the shortest triangle pair time found: the step is then at least
/// `1 − STEP_SLACK` of what a full search would give. `0.1`: on the
/// tumbling benchmark, 0.1 to 0.25 all take about 12–14 steps per query,
/// and 0.1 the fewest triangle and node pairs.
pub(crate) const STEP_SLACK: Real = 0.1;

/// A node pair is opened only if the radii opening it can shrink sum to
/// at least this many times its distance above the target (or its time is
/// below `min_step`): smaller nodes, far from the target, are bounded
/// about as well as their children would be. `1.0`: 0.5 and 2 took more
/// steps and pairs on the tumbling benchmark. The radii are both nodes'
/// where neither or both are leaves, otherwise only the inner node's
/// ([`splittable`]): opening a leaf against an inner node splits only the
/// inner one, and a long leaf (a sliver of the gear ring of
/// `pybullet_data`, 3.1 long) beside a small robot link would otherwise
/// open the whole link down to its triangles, a million triangle pairs in
/// one query. The distance is taken above the target, not from 0: a
/// closest approach's proof asks for a target a hair below a distance of
/// several radii, where a node pair's bound falls short by its radii and
/// steps of 1e-9 follow until it is opened (a Panda link passing that gear
/// ring: 14,000 steps, against 15 so). For a time of impact (a target of a
/// millionth of the radius) that part changes nothing.
pub(crate) const OPEN_RATIO: Real = 1.0;

/// What the step search is asked.
#[derive(Copy, Clone, Debug)]
pub(crate) struct StepLimits {
    /// The time the search starts from (from the interval's start).
    pub start: Real,
    /// No pair may come within this distance before the step's end.
    pub target: Real,
    /// A triangle pair this close or closer is a contact.
    pub contact_distance: Real,
    /// The longest step wanted (the rest of the interval).
    pub horizon: Real,
    /// Node bounds below this are always opened (see the module).
    pub min_step: Real,
    /// Whether node pairs may also be bounded by their spin-swept regions
    /// (see [`node_pair_time`]).
    pub spin_sweep: bool,
}

/// The two meshes of a search and the kernel their triangle pairs use.
#[derive(Copy, Clone, Debug)]
pub(crate) struct SearchMeshes<'m> {
    pub a: &'m TriMesh,
    pub b: &'m TriMesh,
    pub kernel: DistanceKernel,
}

/// Makes the front's elements of one search, bounded at `limits.start`.
struct Items<'s> {
    meshes: &'s SearchMeshes<'s>,
    frame: &'s PairFrame,
    limits: &'s StepLimits,
    stamp: u32,
}

impl Items<'_> {
    fn item(&self, (time, gap): (Real, Real), i: u32, j: u32, kind: ItemKind) -> FrontItem {
        let s = self.limits.start;
        FrontItem { safe_until: s + time, gap, evaluated: s, i, j, kind, stamp: self.stamp }
    }

    /// Node pair `(i, j)`; a bound at least `needed` long will not be refined.
    fn nodes(&self, i: u32, j: u32, needed: Real, work: &mut StepWork) -> FrontItem {
        work.node_pairs += 1;
        let (na, nb) = (&self.meshes.a.bvh().nodes()[i as usize], &self.meshes.b.bvh().nodes()[j as usize]);
        let limits = self.limits;
        let sweep_horizon = if limits.spin_sweep { limits.horizon } else { 0.0 };
        let mut bound = node_pair_time(na, nb, self.frame, limits.target, (needed, sweep_horizon));
        if bound.0 < needed {
            if let Some(balls) = self.ball_bound(na, nb, bound) {
                bound = (bound.0.max(balls.0), bound.1.max(balls.1));
            }
        }
        if bound.0 < needed {
            let (a, b) = (self.meshes.a, self.meshes.b);
            if let (Some(vertices_a), Some(vertices_b)) = (a.small_node_vertices(i), b.small_node_vertices(j))
            {
                let slab =
                    vertex_slab_time((a, na, vertices_a), (b, nb, vertices_b), self.frame, limits.target);
                bound = (bound.0.max(slab.0), bound.1.max(slab.1));
            }
        }
        self.item(bound, i, j, ItemKind::Nodes)
    }

    /// Where one node is a leaf more than
    /// [`LOPSIDED_RATIO`](super::mesh_bound::LOPSIDED_RATIO) times the
    /// other's radius: the other node as its bounding ball against each
    /// of the leaf's triangles ([`PosedPair::ball_time`]), the least time
    /// and gap. A node's box turns with its body, and the box of a long
    /// leaf (a sliver of a spinning gear ring) sweeps its length times the
    /// spin in a world slab; a ball against the leaf's own triangles, in
    /// the frame turning with them, loses only what the distance does.
    /// `None` also once it cannot raise `floor`, the time and gap already
    /// known: the least over the triangles is then at or below both.
    fn ball_bound(&self, na: &BvhNode, nb: &BvhNode, floor: (Real, Real)) -> Option<(Real, Real)> {
        let (leaf, ball, ball_on_a, leaf_mesh) = match lopsided_leaf(na, nb)? {
            Side::A => (na, nb, false, self.meshes.a),
            Side::B => (nb, na, true, self.meshes.b),
        };
        let limits = self.limits;
        let mut bound = (Real::INFINITY, Real::INFINITY);
        for t in leaf.first..leaf.first + leaf.count {
            let (time, gap) = PosedPair::ball_time(
                ball.center,
                ball.radius,
                leaf_mesh.triangle(t as usize),
                ball_on_a,
                self.frame,
                (limits.target, limits.horizon),
            );
            bound = (bound.0.min(time), bound.1.min(gap));
            if bound.0 <= floor.0 && bound.1 <= floor.1 {
                return None;
            }
        }
        Some(bound)
    }

    /// Leaf pair `(i, j)` (node indices) with the leaves' own bound
    /// ([`PosedPair::leaves_time`]); `None` where it cannot give one.
    fn leaves(&self, i: u32, j: u32, work: &mut StepWork) -> Option<FrontItem> {
        work.node_pairs += 1;
        let limits = self.limits;
        let bound = PosedPair::leaves_time(
            (self.meshes.a, i),
            (self.meshes.b, j),
            self.frame,
            (limits.target, limits.horizon),
        )?;
        Some(self.item(bound, i, j, ItemKind::Leaves))
    }

    /// Triangle pair `(i, j)` with the cheap bound.
    fn quick(&self, i: u32, j: u32) -> FrontItem {
        let pair = PosedPair::new(self.meshes.a, i as usize, self.meshes.b, j as usize, self.frame);
        self.item(pair.quick_time(self.frame, self.limits.target), i, j, ItemKind::TrianglesQuick)
    }

    /// Triangle pair `(i, j)` with the full bound; its distance as the gap.
    fn exact(&self, i: u32, j: u32, work: &mut StepWork) -> FrontItem {
        work.triangle_pairs += 1;
        let pair = PosedPair::new(self.meshes.a, i as usize, self.meshes.b, j as usize, self.frame);
        let bound = pair.exact_time(self.frame, self.limits.target, self.meshes.kernel, self.limits.horizon);
        self.item(bound, i, j, ItemKind::Triangles)
    }
}

/// The answer of [`Front::advance`].
#[derive(Copy, Clone, Debug, PartialEq)]
pub(crate) enum StepOutcome {
    /// A triangle pair is within the contact distance now.
    Contact {
        /// The pair (triangle of `a`, triangle of `b`).
        pair: (usize, usize),
    },
    /// No pair comes within `target` before `step` (which may exceed the horizon).
    Advance {
        /// The step.
        step: Real,
        /// The triangle pair that limited the step most, if one was evaluated.
        limiting: Option<(usize, usize)>,
    },
}

/// Work counters of a search.
#[derive(Copy, Clone, Debug, Default, PartialEq, Eq)]
pub(crate) struct StepWork {
    /// Triangle pairs evaluated.
    pub triangle_pairs: usize,
    /// Node pairs bounded.
    pub node_pairs: usize,
}

/// One element of the front: a node pair or a triangle pair of the two
/// BVHs, with the time until which it is known to stay farther than the
/// target. The front is a cut through the tree of node pairs: every
/// triangle pair lies below exactly one element.
#[derive(Copy, Clone, Debug)]
pub(crate) struct FrontItem {
    /// Time (from the step's start) before which nothing below it comes
    /// within the target.
    safe_until: Real,
    /// A lower bound on its distance at `evaluated`.
    gap: Real,
    /// When `safe_until` and `gap` were computed.
    evaluated: Real,
    /// Node (or triangle) of `a`, of `b`.
    i: u32,
    j: u32,
    /// What `i`, `j` are.
    kind: ItemKind,
    /// The search that evaluated it (`Front::searches`).
    stamp: u32,
}

impl PartialEq for FrontItem {
    fn eq(&self, other: &Self) -> bool {
        self.cmp(other) == std::cmp::Ordering::Equal
    }
}
impl Eq for FrontItem {}
impl PartialOrd for FrontItem {
    fn partial_cmp(&self, other: &Self) -> Option<std::cmp::Ordering> {
        Some(self.cmp(other))
    }
}
impl Ord for FrontItem {
    /// Reversed on `safe_until`: the binary heap's top is the earliest.
    fn cmp(&self, other: &Self) -> std::cmp::Ordering {
        other.safe_until.total_cmp(&self.safe_until)
    }
}

/// What a front element holds.
#[derive(Copy, Clone, Debug, PartialEq, Eq)]
enum ItemKind {
    /// A pair of BVH nodes.
    Nodes,
    /// A pair of BVH leaves bounded together (`PosedPair::leaves_time`).
    Leaves,
    /// A pair of triangles with the cheap bound only.
    TrianglesQuick,
    /// A pair of triangles with the full bound (and its distance as `gap`).
    Triangles,
}

/// The front of one CCD query, kept between its advancement steps: an
/// element whose time bound still reaches past the next step is not looked
/// at again (temporal coherence), and only the elements that limit the
/// step are re-evaluated at the current time, opened, or both. A run of a
/// closest approach may start from the front of the run before it
/// ([`Front::begin`]).
#[derive(Clone, Debug, Default)]
pub(crate) struct Front {
    heap: std::collections::BinaryHeap<FrontItem>,
    searches: u32,
    /// What the elements' bounds hold for, where there are any.
    origin: FrontOrigin,
}

/// The query a front was bounded for: every element holds that nothing
/// below it comes within `target` from `reached` (the last search's start)
/// until its time, times counted from `elapsed` (the motions' own
/// [`StepMotion::elapsed`](crate::motion::StepMotion) at the query's start).
#[derive(Copy, Clone, Debug, Default, PartialEq)]
pub(crate) struct FrontOrigin {
    pub elapsed: Real,
    pub target: Real,
    pub reached: Real,
}

/// Where a query's BVH search starts.
#[derive(Copy, Clone, Debug, PartialEq, Eq)]
pub(crate) enum FrontStart {
    /// From the pair of roots.
    Roots,
    /// From the front the scratch holds, where it still holds
    /// ([`Front::begin`]): a closest approach's runs, each with the last.
    Kept,
}

/// A front is carried into a later query only where that query starts at
/// or after the time the front reached, to this many ulps of the times
/// (the two count the same instant from different starts, rounded apart):
/// `8`. An instant that close is far below any step the bounds take.
pub(crate) const CARRY_TIME_ULPS: Real = 8.0;

/// The radii that opening a node pair can shrink: both where neither or
/// both are leaves (two leaves open into their triangle pairs), otherwise
/// the inner node's, the only one [`Front::open`] splits.
fn splittable(na: &BvhNode, nb: &BvhNode) -> Real {
    match (na.is_leaf(), nb.is_leaf()) {
        (true, false) => nb.radius,
        (false, true) => na.radius,
        _ => na.radius + nb.radius,
    }
}

impl Front {
    /// Starts a new query: the front is the pair of roots.
    pub fn reset(&mut self) {
        self.heap.clear();
        self.searches = 0;
    }

    /// Starts a query of the same two meshes and motions, bounded for
    /// `origin` (its `reached`: the first search's start): where `start` is
    /// [`FrontStart::Kept`] and the elements held for a target at least
    /// this one's up to a time at or before this start (every element then
    /// still holds, for a lower target, from here until its time), they are
    /// kept, their times moved to the new start; otherwise from the roots. A closest
    /// approach's run after one that stopped starts where it stopped with
    /// a lower target: its search needs none of the node pairs the front
    /// already opened.
    pub fn begin(&mut self, origin: FrontOrigin, start: FrontStart) {
        let shift = origin.elapsed - self.origin.elapsed;
        let slack = CARRY_TIME_ULPS * Real::EPSILON * (origin.elapsed.abs() + origin.reached.abs());
        let holds =
            origin.target <= self.origin.target && shift + origin.reached + slack >= self.origin.reached;
        if start == FrontStart::Kept && holds && !self.heap.is_empty() {
            let mut items = std::mem::take(&mut self.heap).into_vec();
            for item in &mut items {
                item.safe_until -= shift;
                item.evaluated -= shift;
            }
            self.heap = items.into();
        } else {
            self.reset();
        }
        self.origin = origin;
    }

    /// The longest safe step from time `limits.start` (see the module), or
    /// the contact found on the way. `hint`, a triangle pair, is evaluated
    /// first (at the first search) so that the search starts with a good bound.
    pub fn advance(
        &mut self,
        meshes: &SearchMeshes<'_>,
        frame: &PairFrame,
        limits: &StepLimits,
        hint: Option<(usize, usize)>,
        work: &mut StepWork,
    ) -> StepOutcome {
        let (a, b) = (meshes.a, meshes.b);
        let nodes_a = a.bvh().nodes();
        self.searches += 1;
        self.origin.reached = limits.start;
        let items = Items { meshes, frame, limits, stamp: self.searches };
        // The shortest time of a triangle pair evaluated in full in this search.
        let mut best = limits.horizon;
        let mut limiting = None;
        if self.heap.is_empty() {
            self.heap.push(items.nodes(0, 0, limits.horizon, work));
            if let Some((i, j)) = hint.filter(|&(i, j)| i < a.triangles().len() && j < b.triangles().len()) {
                let item = items.exact(i as u32, j as u32, work);
                if item.gap <= limits.contact_distance {
                    return StepOutcome::Contact { pair: (i, j) };
                }
                best = best.min(item.safe_until - limits.start);
            }
        }
        let needed = |best: Real| ((1.0 - STEP_SLACK) * best).max(limits.min_step);
        let long_enough = |time: Real, best: Real| time >= needed(best);
        while let Some(&top) = self.heap.peek() {
            let time = top.safe_until - limits.start;
            if time >= best || long_enough(time, best) {
                break;
            }
            let fresh = top.stamp == items.stamp;
            match top.kind {
                ItemKind::Triangles if fresh => break,
                ItemKind::Triangles | ItemKind::TrianglesQuick => {
                    self.heap.pop();
                    let mut item = items.exact(top.i, top.j, work);
                    if item.gap <= limits.contact_distance {
                        // Kept: the front stays a cut (a later query may
                        // start from it).
                        self.heap.push(item);
                        return StepOutcome::Contact { pair: (top.i as usize, top.j as usize) };
                    }
                    // An earlier bound that reaches further still holds.
                    item.safe_until = item.safe_until.max(top.safe_until);
                    if item.safe_until - limits.start < best {
                        best = item.safe_until - limits.start;
                        limiting = Some((top.i as usize, top.j as usize));
                    }
                    self.heap.push(item);
                }
                ItemKind::Leaves if !fresh => {
                    self.heap.pop();
                    match items.leaves(top.i, top.j, work) {
                        Some(mut item) => {
                            item.safe_until = item.safe_until.max(top.safe_until);
                            self.heap.push(item);
                        }
                        None => self.open_leaves(&items, &top),
                    }
                }
                ItemKind::Leaves => {
                    // Bounded now and still short: pair by pair.
                    self.heap.pop();
                    self.open_leaves(&items, &top);
                }
                ItemKind::Nodes if !fresh => {
                    self.heap.pop();
                    let mut item = items.nodes(top.i, top.j, needed(best), work);
                    item.safe_until = item.safe_until.max(top.safe_until);
                    self.heap.push(item);
                }
                ItemKind::Nodes => {
                    let (na, nb) = (&nodes_a[top.i as usize], &b.bvh().nodes()[top.j as usize]);
                    if time >= limits.min_step && splittable(na, nb) < OPEN_RATIO * (top.gap - limits.target)
                    {
                        // Small against their distance above the target:
                        // the children would not be bounded much better.
                        break;
                    }
                    self.heap.pop();
                    self.open(&items, &top, needed(best), work);
                }
            }
        }
        let step = self.heap.peek().map_or(Real::INFINITY, |top| top.safe_until - limits.start);
        StepOutcome::Advance { step: step.max(0.0), limiting }
    }

    /// Replaces node pair `(i, j)` by its children (node pairs, or the
    /// triangle pairs of two leaves with their cheap bounds).
    fn open(&mut self, items: &Items<'_>, parent: &FrontItem, needed: Real, work: &mut StepWork) {
        let (i, j) = (parent.i, parent.j);
        // The parent's bound holds for everything below it.
        let inherit = |mut item: FrontItem| {
            item.safe_until = item.safe_until.max(parent.safe_until);
            item
        };
        let (na, nb) = (&items.meshes.a.bvh().nodes()[i as usize], &items.meshes.b.bvh().nodes()[j as usize]);
        if na.is_leaf() && nb.is_leaf() {
            // Both leaves at once where that bound is long enough (with
            // the exact kernel only: a DyOP search evaluates its own
            // kernel and nothing else).
            let exact = items.meshes.kernel == DistanceKernel::Exact;
            let leaves = exact.then(|| items.leaves(i, j, work)).flatten();
            let leaves = leaves.filter(|item| item.safe_until - items.limits.start >= needed);
            match leaves {
                Some(item) => self.heap.push(inherit(item)),
                None => self.open_leaves(items, parent),
            }
            return;
        }
        let split_a = !na.is_leaf() && (nb.is_leaf() || na.radius >= nb.radius);
        let children =
            if split_a { [(na.first, j), (na.first + 1, j)] } else { [(i, nb.first), (i, nb.first + 1)] };
        for (ci, cj) in children {
            self.heap.push(inherit(items.nodes(ci, cj, needed, work)));
        }
    }

    /// Replaces leaf pair `parent` by its triangle pairs, with their cheap
    /// bounds (never shorter than the parent's, which still holds).
    fn open_leaves(&mut self, items: &Items<'_>, parent: &FrontItem) {
        let nodes = (items.meshes.a.bvh().nodes(), items.meshes.b.bvh().nodes());
        let (na, nb) = (&nodes.0[parent.i as usize], &nodes.1[parent.j as usize]);
        for tb in nb.first..nb.first + nb.count {
            for ta in na.first..na.first + na.count {
                let mut item = items.quick(ta, tb);
                item.safe_until = item.safe_until.max(parent.safe_until);
                self.heap.push(item);
            }
        }
    }

    /// A lower bound on the distance at time `end`, from every element's
    /// gap at its evaluation and the head-on closing `speed` since.
    pub fn distance_bound_at(&self, end: Real, speed: Real) -> Real {
        self.heap.iter().map(|item| item.gap - speed * (end - item.evaluated)).fold(Real::INFINITY, Real::min)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::math::{Pose, Vector};
    use crate::mesh::icosphere;
    use nalgebra::UnitQuaternion;

    /// The triangle pairs below the front's elements, counted with their
    /// repeats: `n_a × n_b` exactly when the front is a cut.
    fn covered(front: &Front, meshes: &SearchMeshes<'_>) -> usize {
        fn below(nodes: &[BvhNode], k: u32) -> usize {
            let node = &nodes[k as usize];
            if node.is_leaf() {
                node.count as usize
            } else {
                below(nodes, node.first) + below(nodes, node.first + 1)
            }
        }
        let (a, b) = (meshes.a.bvh().nodes(), meshes.b.bvh().nodes());
        front
            .heap
            .iter()
            .map(|item| match item.kind {
                ItemKind::Nodes | ItemKind::Leaves => below(a, item.i) * below(b, item.j),
                ItemKind::Triangles | ItemKind::TrianglesQuick => 1,
            })
            .sum()
    }

    /// A front of one search: two icospheres 0.5 apart, closing at 1,
    /// bounded at time `start` for `target`.
    fn searched(meshes: &SearchMeshes<'_>, start: Real, target: Real) -> Front {
        let frame = PairFrame::new(
            Pose::translation(1.5 - start, 0.0, 0.0),
            &UnitQuaternion::identity(),
            &Vector::new(-1.0, 0.0, 0.0),
            &Vector::zeros(),
            &Vector::new(0.0, 0.0, 2.0),
        );
        let limits = StepLimits {
            start,
            target,
            contact_distance: target + 1e-7,
            horizon: 1.0 - start,
            min_step: 1e-7,
            spin_sweep: false,
        };
        let mut front = Front::default();
        front.begin(FrontOrigin { elapsed: 0.0, target, reached: start }, FrontStart::Roots);
        let outcome = front.advance(meshes, &frame, &limits, None, &mut StepWork::default());
        assert!(matches!(outcome, StepOutcome::Advance { .. }), "{outcome:?}");
        front
    }

    #[test]
    fn a_front_is_kept_only_for_a_lower_target_from_where_it_reached() {
        let ball = icosphere(0.5, 2).unwrap();
        let meshes = SearchMeshes { a: &ball, b: &ball, kernel: DistanceKernel::Exact };
        let (start, target) = (0.1, 0.2);
        let front = searched(&meshes, start, target);
        let pairs = ball.triangles().len() * ball.triangles().len();
        assert_eq!(covered(&front, &meshes), pairs);
        let items = front.heap.len();
        assert!(items > 1, "{items} elements");
        let later = |target: Real, elapsed: Real, reached: Real, start: FrontStart| {
            let mut kept = front.clone();
            kept.begin(FrontOrigin { elapsed, target, reached }, start);
            kept
        };
        // A lower target, from where the search reached (its times counted
        // from 0.05 on): kept, every time moved back by 0.05.
        let kept = later(0.15, 0.05, start - 0.05, FrontStart::Kept);
        assert_eq!(kept.heap.len(), items);
        let earliest = |f: &Front| f.heap.peek().map(|item| (item.safe_until, item.evaluated));
        let (until, evaluated) = earliest(&front).unwrap();
        assert_eq!(earliest(&kept), Some((until - 0.05, evaluated - 0.05)));
        // A higher target, a start before the search's, or from the roots:
        // a new front.
        assert!(later(0.25, 0.05, start - 0.05, FrontStart::Kept).heap.is_empty());
        assert!(later(0.15, 0.0, start - 0.01, FrontStart::Kept).heap.is_empty());
        assert!(later(0.15, 0.05, start - 0.05, FrontStart::Roots).heap.is_empty());
    }

    #[test]
    fn the_front_stays_a_cut_after_a_contact() {
        // The icospheres at time 0.2, asked for a target just below their
        // distance there: the search finds a triangle pair within the
        // contact distance, and the front it leaves (which a later run may
        // start from) still holds every triangle pair below exactly one
        // element.
        let ball = icosphere(0.5, 2).unwrap();
        let meshes = SearchMeshes { a: &ball, b: &ball, kernel: DistanceKernel::Exact };
        let mut front = Front::default();
        let pose = Pose::translation(1.3, 0.0, 0.0);
        let search = crate::mesh::DistanceSearch::default();
        let scratch = &mut crate::mesh::MeshDistanceScratch::default();
        let distance = crate::mesh::mesh_distance_relative(&ball, &ball, &pose, &search, scratch).distance;
        let frame = PairFrame::new(
            pose,
            &UnitQuaternion::identity(),
            &Vector::new(-1.0, 0.0, 0.0),
            &Vector::zeros(),
            &Vector::new(0.0, 0.0, 2.0),
        );
        let limits = StepLimits {
            start: 0.2,
            target: distance - 1e-3,
            contact_distance: distance + 1e-3,
            horizon: 0.8,
            // What the search loop gives (the contact distance less the
            // target over the head-on speed, at most 2 here).
            min_step: 1e-3,
            spin_sweep: false,
        };
        let outcome = front.advance(&meshes, &frame, &limits, None, &mut StepWork::default());
        assert!(matches!(outcome, StepOutcome::Contact { .. }), "{outcome:?}");
        assert_eq!(covered(&front, &meshes), ball.triangles().len() * ball.triangles().len());
    }
}

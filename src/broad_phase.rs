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
//! a traversal meets most of the tree. From `GRID_BROAD_PHASE_BOXES` boxes
//! on, a uniform grid rebuilt at each step ([`GridBroadPhase`]) takes the
//! tree's place: the same pairs, sooner for many bodies. Boxes that never
//! move (a scene's many fixed bodies) go into a grid once
//! ([`StaticBoxes`]), and each step's moving boxes read the cells they
//! can reach. Pairs of two fixed bodies are dropped.

use parry3d_f64::bounding_volume::Aabb;
use parry3d_f64::partitioning::{Bvh, BvhBuildStrategy, BvhWorkspace};

use nalgebra::UnitQuaternion;

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
    let (below, above) = swept_reach(mesh, &motion.rotation_at(0.0), &motion.angular_velocity, duration);
    for k in 0..3 {
        high[k] += above[k] + margin;
        low[k] -= below[k] + margin;
    }
    (low, high)
}

/// How far `mesh` reaches below and above its centre along each world
/// axis over a step of length `duration` that starts turned by `rotation`
/// and turns with `angular_velocity` (see the module: `min(r, h(0) +
/// |e × ω| r dt)` per axis and side). [`swept_box`] is the centre's box
/// over the step grown by these and its margin.
pub fn swept_reach(
    mesh: &TriMesh,
    rotation: &UnitQuaternion<Real>,
    angular_velocity: &Vector,
    duration: Real,
) -> (Vector, Vector) {
    let rotation = rotation.to_rotation_matrix();
    let radius = mesh.radius();
    let (box_low, box_high) = mesh.bounds();
    let centre = rotation * (box_low.coords + box_high.coords) * 0.5;
    let half = (box_high - box_low) * 0.5;
    let (mut below, mut above) = (Vector::zeros(), Vector::zeros());
    for k in 0..3 {
        let axis = Vector::ith(k, 1.0);
        let turn = axis.cross(angular_velocity).norm() * radius * duration;
        let spread = (0..3).map(|j| rotation[(k, j)].abs() * half[j]).sum::<Real>();
        above[k] = (centre[k] + spread + turn).min(radius);
        below[k] = (spread - centre[k] + turn).min(radius);
    }
    (below, above)
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

/// [`GridBroadPhase`]'s cell is at least this many times the largest
/// extent of the boxes it holds (`1 + 1e-9`), so that the rounding of a
/// corner's cell never puts two overlapping boxes two cells apart.
const CELL_SLACK: Real = 1.0 + 1e-9;

/// [`GridBroadPhase`]'s cell is at least this fraction of the span of the
/// boxes' corners: `1e-12` (boxes that are points, or all alike, have no
/// extent to size it by).
const GRID_MIN_CELL_OF_SPAN: Real = 1e-12;

/// [`GridBroadPhase`]'s cell is at least this size, whatever the boxes:
/// `MIN_POSITIVE × 1e20` (its inverse stays finite).
const GRID_MIN_CELL: Real = Real::MIN_POSITIVE * 1e20;

/// [`GridBroadPhase`]: a box is "large" (tested against every other box
/// instead of through the grid) when its extent is over this many times
/// the median extent: `4`.
pub const LARGE_BOX_FACTOR: Real = 4.0;

/// [`GridBroadPhase`]: the grid has at most this many cells a box: `8`
/// (its cell grows where the boxes are sparse, so its memory and the
/// per-step clearing stay proportional to the boxes).
pub const GRID_CELLS_PER_BOX: usize = 8;

/// The overlapping pairs of many boxes through a uniform grid, rebuilt
/// each step by a counting sort (`O(n)`): each box goes into the cell of
/// its smallest corner; the cell is at least as large as every box in the
/// grid, so two overlapping boxes are in the same or adjacent cells, and
/// each pair is found once by looking from each cell into itself and its
/// 13 neighbours ahead of it. The few boxes much larger than the median
/// ([`LARGE_BOX_FACTOR`]: a floor, the walls of a room) stay out of the
/// grid and are tested against every box. The pairs are those of
/// [`brute_force_pairs`], sorted.
#[derive(Debug, Default)]
pub struct GridBroadPhase {
    cells: GridCells,
}

/// Boxes sorted into a uniform grid by the cell of their smallest corner,
/// the cell at least the largest of them (see [`GridBroadPhase`]); the few
/// boxes much larger than the median ([`LARGE_BOX_FACTOR`]) kept apart.
#[derive(Debug, Default)]
struct GridCells {
    /// Each box's cell (`u32::MAX`: large).
    cell_of: Vec<u32>,
    /// Each cell's first entry (a counting sort's starts).
    starts: Vec<u32>,
    /// The grid's boxes by cell: their indices, and the boxes themselves
    /// (so that a cell's neighbours are read in order).
    entries: Vec<u32>,
    sorted: Vec<SweptBox>,
    /// The large boxes: their indices and the boxes.
    large: Vec<u32>,
    large_boxes: Vec<SweptBox>,
    /// A sample of the boxes' extents (for the median).
    extents: Vec<Real>,
    /// The smallest corner of the grid's boxes' smallest corners, the
    /// cell's size and its inverse, the cells along each axis (one of
    /// padding on every side), and whether any box is in the grid.
    low: Point,
    cell: Real,
    inverse: Real,
    shape: nalgebra::Vector3<usize>,
    grid: bool,
}

/// The span of a grid's boxes' smallest corners, the largest extent and
/// the count of its boxes (see [`GridCells::fill`]).
#[derive(Copy, Clone)]
struct GridSpan {
    low: Point,
    high: Point,
    largest: Real,
    count: usize,
}

impl GridSpan {
    /// The span of two sets of boxes together.
    fn join(self, other: GridSpan) -> GridSpan {
        GridSpan {
            low: self.low.inf(&other.low),
            high: self.high.sup(&other.high),
            largest: self.largest.max(other.largest),
            count: self.count + other.count,
        }
    }
}

impl GridCells {
    /// Sorts `boxes` into the grid (the buffers are kept between calls):
    /// each box's cell found on rayon's threads when `threads` (the same
    /// grid either way; the sort itself on the calling thread).
    fn fill(&mut self, n: usize, box_of: impl Fn(usize) -> SweptBox + Sync, threads: bool) {
        use rayon::prelude::*;
        let extent = |(low, high): &SweptBox| (high.x - low.x).max(high.y - low.y).max(high.z - low.z);
        self.extents.clear();
        self.extents.extend((0..n).step_by(EXTENT_SAMPLE_STRIDE).map(|i| extent(&box_of(i))));
        let middle = self.extents.len() / 2;
        let median = *self.extents.select_nth_unstable_by(middle, |a, b| a.total_cmp(b)).1;
        let limit = LARGE_BOX_FACTOR * median;
        let in_grid = |b: &SweptBox| extent(b) <= limit;
        // The grid's boxes: their cell is at least the largest of them (at
        // least a sliver of their spread, for boxes that are points), over
        // the span of their smallest corners. (Least, greatest and count:
        // the same in any order.)
        let none = || GridSpan {
            low: Point::from([Real::INFINITY; 3]),
            high: Point::from([Real::NEG_INFINITY; 3]),
            largest: 0.0,
            count: 0,
        };
        let add = |span: GridSpan, b: &SweptBox| match in_grid(b) {
            true => GridSpan {
                low: span.low.inf(&b.0),
                high: span.high.sup(&b.0),
                largest: span.largest.max(extent(b)),
                count: span.count + 1,
            },
            false => span,
        };
        let add = |span: GridSpan, i: usize| add(span, &box_of(i));
        let GridSpan { low, high, largest, count } = match threads {
            true => (0..n).into_par_iter().fold(none, add).reduce(none, GridSpan::join),
            false => (0..n).fold(none(), add),
        };
        let grid = count > 0;
        let span = if grid { (high - low).max() } else { 0.0 };
        let mut cell = (largest * CELL_SLACK).max(span * GRID_MIN_CELL_OF_SPAN).max(GRID_MIN_CELL);
        // One empty cell of padding on every side: every neighbour exists.
        let dims = |cell: Real| (high - low).map(|d| if grid { (d / cell).floor() as usize + 3 } else { 3 });
        let mut shape = dims(cell);
        while shape.iter().map(|&d| d as Real).product::<Real>() > (GRID_CELLS_PER_BOX * n + 27) as Real {
            cell *= 2.0;
            shape = dims(cell);
        }
        (self.low, self.cell, self.inverse, self.shape, self.grid) = (low, cell, 1.0 / cell, shape, grid);
        let cells = shape.iter().product::<usize>();
        // Each box's cell (`u32::MAX`: large), then a counting sort of the
        // grid's boxes by cell.
        let mut cell_of_box = std::mem::take(&mut self.cell_of);
        let cell_of = |i: usize| {
            let b = box_of(i);
            if in_grid(&b) {
                self.index(&b.0) as u32
            } else {
                u32::MAX
            }
        };
        match threads {
            true => (0..n).into_par_iter().map(cell_of).collect_into_vec(&mut cell_of_box),
            false => {
                cell_of_box.clear();
                cell_of_box.extend((0..n).map(cell_of));
            }
        }
        self.cell_of = cell_of_box;
        self.large.clear();
        self.large_boxes.clear();
        self.starts.clear();
        self.starts.resize(cells + 1, 0);
        for (i, &c) in self.cell_of.iter().enumerate() {
            if c == u32::MAX {
                self.large.push(i as u32);
                self.large_boxes.push(box_of(i));
            } else {
                self.starts[c as usize + 1] += 1;
            }
        }
        for c in 0..cells {
            self.starts[c + 1] += self.starts[c];
        }
        self.entries.clear();
        self.entries.resize(count, 0);
        self.sorted.clear();
        self.sorted.resize(count, (Point::origin(), Point::origin()));
        // Each start is its cell's cursor while filling (the boxes keep
        // their order within a cell), then the starts move back one cell.
        for (i, &c) in self.cell_of.iter().enumerate() {
            if c != u32::MAX {
                let at = self.starts[c as usize] as usize;
                (self.entries[at], self.sorted[at]) = (i as u32, box_of(i));
                self.starts[c as usize] += 1;
            }
        }
        self.starts.copy_within(0..cells, 1);
        self.starts[0] = 0;
    }

    /// The cell coordinates of `p` (from 1: the padding is 0), not clamped above.
    #[inline]
    fn cell_at(&self, p: &Point) -> nalgebra::Vector3<usize> {
        // (Truncation is the floor here: a negative offset is clamped to 0.)
        (p - self.low).map(|d| ((d * self.inverse).max(0.0) as usize).saturating_add(1))
    }

    /// The linear index of the cell of `p`, clamped into the grid.
    #[inline]
    fn index(&self, p: &Point) -> usize {
        let (c, shape) = (self.cell_at(p), self.shape);
        (c.z.min(shape.z - 2) * shape.y + c.y.min(shape.y - 2)) * shape.x + c.x.min(shape.x - 2)
    }

    /// Each grid box whose smallest corner is in a cell that a box `b`
    /// overlapping it can reach (from a cell below `b`'s smallest corner to
    /// the cell of its largest), row by row: `visit(entry)` with its place
    /// in `entries` and `sorted`.
    #[inline]
    fn reach(&self, b: &SweptBox, mut visit: impl FnMut(usize)) {
        if !self.grid {
            return;
        }
        let shape = self.shape;
        let from = self.cell_at(&(b.0 - Vector::repeat(self.cell))).map(|c| c.clamp(1, usize::MAX));
        let to = self.cell_at(&b.1);
        for z in from.z..=to.z.min(shape.z - 2) {
            for y in from.y..=to.y.min(shape.y - 2) {
                let row = (z * shape.y + y) * shape.x;
                let (first, last) = (row + from.x, row + to.x.min(shape.x - 2));
                if first > last {
                    continue;
                }
                (self.starts[first] as usize..self.starts[last + 1] as usize).for_each(&mut visit);
            }
        }
    }
}

/// [`BroadPhase`] finds the pairs of this many boxes or more through a
/// [`GridBroadPhase`] rather than parry's tree: `8192`. On the
/// `many_bodies` box the two are even at 10,000 bodies while they have
/// hardly moved, and once they mix (240 steps) the grid takes 0.7–0.9 of
/// the tree's time and about 0.8 of its memory; at 100,000 it takes
/// 0.75–0.85 of the tree's time on one thread and 0.65 on two (the tree's
/// refit and traversal degrade as the bodies mix; the grid is rebuilt each
/// step in `O(n)`; `docs/benchmarks-history.md`, sessions 31 and 35).
pub const GRID_BROAD_PHASE_BOXES: usize = 8192;

/// [`GridBroadPhase::pairs_into_on`] searches its cells on rayon's threads
/// from this many boxes in the grid: `4096` (a box's search is tens of
/// nanoseconds; fewer are not worth handing out).
pub const PARALLEL_GRID_BOXES: usize = 4096;

/// [`GridBroadPhase`] takes the median extent over every this many boxes:
/// `8` (the cell's size needs no more; it is the largest extent in the
/// grid whatever the sample).
const EXTENT_SAMPLE_STRIDE: usize = 8;

impl GridBroadPhase {
    /// The overlapping pairs `(i, j)`, `i < j`, sorted, into `pairs`
    /// (cleared first); its buffers are kept, so that a step allocates
    /// nothing once they have grown.
    pub fn pairs_into(&mut self, boxes: &[SweptBox], pairs: &mut Vec<(usize, usize)>) {
        self.pairs_into_on(boxes, pairs, false);
    }

    /// [`GridBroadPhase::pairs_into`], its cells searched on rayon's threads
    /// when `threads` (from [`PARALLEL_GRID_BOXES`] boxes): the same pairs.
    pub fn pairs_into_on(&mut self, boxes: &[SweptBox], pairs: &mut Vec<(usize, usize)>, threads: bool) {
        self.pairs_of_into_on(boxes.len(), |i| boxes[i], pairs, threads);
    }

    /// [`GridBroadPhase::pairs_into_on`] of the `n` boxes `box_of(0..n)`
    /// (read a few times each: made on the fly, they need no buffer).
    pub fn pairs_of_into_on(
        &mut self,
        n: usize,
        box_of: impl Fn(usize) -> SweptBox + Sync,
        pairs: &mut Vec<(usize, usize)>,
        threads: bool,
    ) {
        pairs.clear();
        if n < 2 {
            (self.cells.grid, self.cells.large, self.cells.large_boxes) = (false, Vec::new(), Vec::new());
            return;
        }
        let grid = &mut self.cells;
        grid.fill(n, box_of, threads && n >= PARALLEL_GRID_BOXES);
        let grid = &self.cells;
        let shape = grid.shape;
        let cells = shape.iter().product::<usize>();
        let in_grid = grid.sorted.len();
        // Each cell against itself and its 13 neighbours ahead (greater
        // linear index); the padding keeps every neighbour in the grid.
        // Cells x − 1, x and x + 1 of a row are adjacent in the sort, so the
        // neighbours are read as runs: the cell itself with the next one,
        // then the three cells of each of the rows (y + 1, z), (y − 1, z + 1),
        // (y, z + 1) and (y + 1, z + 1) (`FORWARD_ROWS`).
        let (sx, sxy) = (shape.x, shape.x * shape.y);
        let rows = FORWARD_ROWS.map(|(dy, dz)| (dy * sx as isize + dz * sxy as isize) as usize);
        let (starts, entries, sorted) = (&grid.starts, &grid.entries, &grid.sorted);
        let search = |cells: std::ops::Range<usize>, pairs: &mut Vec<(usize, usize)>| {
            for c in cells {
                let (from, to) = (starts[c] as usize, starts[c + 1] as usize);
                if from == to {
                    continue;
                }
                // Each row's run, from the cell before to the cell after.
                let runs = rows.map(|row| starts[c + row - 1] as usize..starts[c + row + 2] as usize);
                let next = starts[c + 2] as usize;
                for a in from..to {
                    let (i, box_i) = (entries[a] as usize, &sorted[a]);
                    let mut meet = |b: usize| {
                        if boxes_overlap(box_i, &sorted[b]) {
                            let j = entries[b] as usize;
                            pairs.push((i.min(j), i.max(j)));
                        }
                    };
                    (a + 1..next).for_each(&mut meet);
                    for run in &runs {
                        run.clone().for_each(&mut meet);
                    }
                }
            }
        };
        in_runs(cells, threads && in_grid >= PARALLEL_GRID_BOXES, pairs, search);
        // The large boxes against the grid's boxes in the cells they reach
        // (a box overlapping one has its smallest corner at most a cell
        // below it), and against each other (each pair once).
        for (k, (&l, large_box)) in grid.large.iter().zip(&grid.large_boxes).enumerate() {
            let l = l as usize;
            grid.reach(large_box, |b| {
                if boxes_overlap(large_box, &sorted[b]) {
                    let j = entries[b] as usize;
                    pairs.push((l.min(j), l.max(j)));
                }
            });
            for (&other, other_box) in grid.large[k + 1..].iter().zip(&grid.large_boxes[k + 1..]) {
                if boxes_overlap(large_box, other_box) {
                    pairs.push((l.min(other as usize), l.max(other as usize)));
                }
            }
        }
        pairs.sort_unstable();
    }

    /// Each box of the last call that overlaps `query`: `visit(i)` with
    /// its index, in no particular order (none for fewer than two boxes).
    pub fn overlapping(&self, query: &SweptBox, mut visit: impl FnMut(usize)) {
        let grid = &self.cells;
        grid.reach(query, |b| {
            if boxes_overlap(query, &grid.sorted[b]) {
                visit(grid.entries[b] as usize);
            }
        });
        for (&l, large_box) in grid.large.iter().zip(&grid.large_boxes) {
            if boxes_overlap(query, large_box) {
                visit(l as usize);
            }
        }
    }
}

/// The length of the runs [`in_runs`] splits `count` items into on rayon's
/// threads: about a quarter of a thread's share (at least one).
pub(crate) fn run_length(count: usize) -> usize {
    count.div_ceil(4 * rayon::current_num_threads()).max(1)
}

/// `find` over `0..count`, appending what it finds (pairs) in order: on
/// rayon's threads when `threads`, as runs of about a quarter of a
/// thread's share each (what they find joined in the runs' order, so the
/// same as on one thread).
pub(crate) fn in_runs<T: Send + Copy>(
    count: usize,
    threads: bool,
    pairs: &mut Vec<T>,
    find: impl Fn(std::ops::Range<usize>, &mut Vec<T>) + Sync,
) {
    if !threads {
        find(0..count, pairs);
        return;
    }
    use rayon::prelude::*;
    let run = run_length(count);
    let found: Vec<Vec<T>> = (0..count.div_ceil(run))
        .into_par_iter()
        .map(|k| {
            let mut found = Vec::new();
            find(k * run..((k + 1) * run).min(count), &mut found);
            found
        })
        .collect();
    found.iter().for_each(|part| pairs.extend_from_slice(part));
}

/// The rows `(dy, dz)` whose cells x − 1, x and x + 1 are ahead of a cell
/// (greater linear index, x fastest): with the next cell in its own row,
/// the 13 of its 26 neighbours that are one of each pair of opposite
/// offsets.
const FORWARD_ROWS: [(isize, isize); 4] = [(1, 0), (-1, 1), (0, 1), (1, 1)];

/// The broad phase's reusable state: parry's tree, or for many boxes the
/// grid.
#[derive(Default)]
pub struct BroadPhase {
    workspace: BvhWorkspace,
    leaves: Vec<Aabb>,
    /// The tree of the previous call, refitted while the number of boxes
    /// stays the same.
    tree: Option<Bvh>,
    /// Refits since the tree was built.
    refits: u64,
    /// The grid, for [`GRID_BROAD_PHASE_BOXES`] boxes or more.
    grid: GridBroadPhase,
}

impl std::fmt::Debug for BroadPhase {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("BroadPhase").field("leaves", &self.leaves.len()).finish()
    }
}

impl BroadPhase {
    /// The overlapping pairs `(i, j)`, `i < j`, sorted, through parry's BVH
    /// (or the grid, from [`GRID_BROAD_PHASE_BOXES`] boxes).
    pub fn pairs(&mut self, boxes: &[SweptBox]) -> Vec<(usize, usize)> {
        let mut pairs = Vec::new();
        self.pairs_into(boxes, &mut pairs);
        pairs
    }

    /// [`BroadPhase::pairs`] into `pairs` (cleared first): a buffer kept
    /// between steps, so that a step allocates nothing once it has grown.
    pub fn pairs_into(&mut self, boxes: &[SweptBox], pairs: &mut Vec<(usize, usize)>) {
        self.pairs_into_on(boxes, pairs, false);
    }

    /// [`BroadPhase::pairs_into`], the tree refitted and traversed on
    /// rayon's threads when `threads` (parry's parallel refit and
    /// traversal: the same tree and the same pairs; the traversal's list
    /// is allocated by parry at each call), or the grid's cells searched on
    /// them.
    pub fn pairs_into_on(&mut self, boxes: &[SweptBox], pairs: &mut Vec<(usize, usize)>, threads: bool) {
        if boxes.len() >= GRID_BROAD_PHASE_BOXES {
            self.grid.pairs_into_on(boxes, pairs, threads);
            return;
        }
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
                    if threads {
                        tree.refit_parallel(&mut self.workspace);
                    } else {
                        tree.refit(&mut self.workspace);
                    }
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
            let mut push = |i: u32, j: u32| {
                let (i, j) = (i as usize, j as usize);
                pairs.push((i.min(j), i.max(j)));
            };
            if threads {
                for (i, j) in bvh.traverse_bvtt_single_tree_parallel::<false>() {
                    push(i, j);
                }
            } else {
                bvh.traverse_bvtt_single_tree::<false>(&mut self.workspace, &mut push);
            }
        }
        pairs.sort_unstable();
        pairs.dedup();
    }
}

/// Boxes that stay put (fixed bodies' boxes), sorted into a grid once
/// (the [`GridBroadPhase`]'s cells: by their smallest corner, the few
/// large ones apart), and the moving boxes that overlap them, each found
/// by reading the cells it can reach: a step then costs nothing per fixed
/// body (no box, no place in the step's grid or tree). The pairs are those
/// of [`brute_force_pairs`] between the two sets (the same inclusive test,
/// [`boxes_overlap`]).
#[derive(Debug)]
pub struct StaticBoxes {
    /// How many boxes.
    count: usize,
    /// The grid of them, and the large ones (index and box).
    cells: GridCells,
    large: Vec<(u32, SweptBox)>,
}

/// [`StaticBoxes::overlaps_into_on`] reads its cells on rayon's threads
/// from this many moving boxes: `4096` (as [`PARALLEL_GRID_BOXES`]).
pub const PARALLEL_STATIC_QUERIES: usize = 4096;

impl StaticBoxes {
    /// The grid of `boxes` (they keep their indices).
    pub fn new(boxes: &[SweptBox]) -> StaticBoxes {
        let mut cells = GridCells::default();
        if !boxes.is_empty() {
            cells.fill(boxes.len(), |i| boxes[i], boxes.len() >= PARALLEL_GRID_BOXES);
        }
        // The grid keeps its own copy of the boxes, in cell order; what only
        // the fill needs is let go.
        let large = cells.large.iter().copied().zip(cells.large_boxes.iter().copied()).collect();
        (cells.cell_of, cells.extents) = (Vec::new(), Vec::new());
        (cells.large, cells.large_boxes) = (Vec::new(), Vec::new());
        StaticBoxes { count: boxes.len(), cells, large }
    }

    /// How many boxes it holds.
    pub fn len(&self) -> usize {
        self.count
    }

    /// Whether it holds none.
    pub fn is_empty(&self) -> bool {
        self.count == 0
    }

    /// The overlapping pairs `(i, j)`, `i < j`, among its own boxes for
    /// which `keep(i, j)` holds, sorted (the pairs of
    /// [`brute_force_pairs`] kept), with no buffer but the pairs.
    pub fn pairs_among(&self, keep: impl Fn(usize, usize) -> bool) -> Vec<(usize, usize)> {
        let grid = &self.cells;
        let mut pairs = Vec::new();
        let mut meet = |i: usize, a: &SweptBox, j: usize, b: &SweptBox| {
            if i < j && boxes_overlap(a, b) && keep(i, j) {
                pairs.push((i, j));
            }
        };
        // Each grid box against the grid boxes it can reach (each pair
        // found from both sides: kept once, from its lower index).
        for (a, box_a) in grid.sorted.iter().enumerate() {
            let i = grid.entries[a] as usize;
            grid.reach(box_a, |b| meet(i, box_a, grid.entries[b] as usize, &grid.sorted[b]));
        }
        // The large ones against every box.
        for (l, large) in &self.large {
            let l = *l as usize;
            for (a, box_a) in grid.sorted.iter().enumerate() {
                let i = grid.entries[a] as usize;
                meet(l.min(i), large, l.max(i), box_a);
            }
            for (other, other_box) in &self.large {
                meet(l, large, *other as usize, other_box);
            }
        }
        pairs.sort_unstable();
        pairs
    }

    /// Every `(k, s)` with `queries[k]` overlapping box `s`, sorted, into
    /// `pairs` (cleared first); the queries on rayon's threads when
    /// `threads` (from [`PARALLEL_STATIC_QUERIES`]): the same pairs.
    pub fn overlaps_into_on(&self, queries: &[SweptBox], pairs: &mut Vec<(usize, usize)>, threads: bool) {
        pairs.clear();
        if self.is_empty() {
            return;
        }
        let grid = &self.cells;
        let query = |range: std::ops::Range<usize>, pairs: &mut Vec<(usize, usize)>| {
            for k in range {
                let moving = &queries[k];
                let first = pairs.len();
                grid.reach(moving, |b| {
                    if boxes_overlap(moving, &grid.sorted[b]) {
                        pairs.push((k, grid.entries[b] as usize));
                    }
                });
                for (l, large) in &self.large {
                    if boxes_overlap(moving, large) {
                        pairs.push((k, *l as usize));
                    }
                }
                pairs[first..].sort_unstable();
            }
        };
        in_runs(queries.len(), threads && queries.len() >= PARALLEL_STATIC_QUERIES, pairs, query);
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::samples::Rng;

    /// The static grid's pairs are the brute force's pairs between the two
    /// sets (and its pairs among its own boxes, the brute force's among
    /// them), on random boxes, boxes touching exactly, and with no static
    /// box or no query, a large box kept out of the grid, queries outside
    /// its span; on one thread and on the threads alike.
    #[test]
    fn static_boxes_pairs_equal_brute_force_pairs() {
        let mut rng = Rng::new(47);
        let random_boxes = |rng: &mut Rng, n: usize| -> Vec<SweptBox> {
            (0..n)
                .map(|_| {
                    let center = Point::from(rng.in_unit_ball() * 20.0);
                    let half = Vector::new(rng.range(0.05, 2.0), rng.range(0.05, 2.0), rng.range(0.05, 2.0));
                    (center - half, center + half)
                })
                .collect()
        };
        for (fixed, moving) in [(0, 10), (10, 0), (1, 1), (7, 300), (300, 7), (500, 5000)] {
            let mut statics = random_boxes(&mut rng, fixed);
            if fixed >= 300 {
                // A floor under them all, kept out of the grid (large).
                statics.push((Point::new(-30.0, -30.0, -1.0), Point::new(30.0, 30.0, 0.0)));
            }
            let mut queries = random_boxes(&mut rng, moving);
            // Queries far outside the static boxes' span, each side.
            if moving >= 7 {
                queries[1] = (Point::new(-90.0, 0.0, 0.0), Point::new(-80.0, 1.0, 1.0));
                queries[2] = (Point::new(80.0, 80.0, 80.0), Point::new(81.0, 81.0, 81.0));
            }
            // A query touching a static box exactly, face to face.
            if let (Some(s), Some(q)) = (statics.first(), queries.first_mut()) {
                let width = q.1.x - q.0.x;
                q.0.x = s.1.x;
                q.1.x = s.1.x + width;
                (q.0.y, q.0.z, q.1.y, q.1.z) = (s.0.y, s.0.z, s.1.y, s.1.z);
            }
            let mut all = queries.clone();
            all.extend_from_slice(&statics);
            let expected: Vec<(usize, usize)> = brute_force_pairs(&all)
                .into_iter()
                .filter(|&(i, j)| i < moving && j >= moving)
                .map(|(i, j)| (i, j - moving))
                .collect();
            let tree = StaticBoxes::new(&statics);
            // Its own pairs (the floor's among them), all or some kept.
            let among = brute_force_pairs(&statics);
            assert_eq!(tree.pairs_among(|_, _| true), among, "{fixed} static: their pairs");
            let odd = |i: usize, j: usize| (i + j) % 2 == 1;
            let kept: Vec<(usize, usize)> = among.iter().copied().filter(|&(i, j)| odd(i, j)).collect();
            assert_eq!(tree.pairs_among(odd), kept, "{fixed} static: their pairs kept");
            for threads in [false, true] {
                let mut pairs = vec![(7, 7)];
                tree.overlaps_into_on(&queries, &mut pairs, threads);
                assert_eq!(pairs, expected, "{fixed} static, {moving} moving, threads {threads}");
            }
            if fixed > 0 && moving > 0 {
                assert!(expected.contains(&(0, 0)), "the boxes touching face to face are a pair");
            }
        }
    }

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
            let mut grid = Vec::new();
            GridBroadPhase::default().pairs_into(&boxes, &mut grid);
            assert_eq!(grid, brute_force_pairs(&boxes), "{n} boxes");
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
    fn grid_pairs_equal_brute_force_pairs_whatever_the_sizes() {
        let mut rng = Rng::new(29);
        let mut grid = GridBroadPhase::default();
        let mut pairs = Vec::new();
        let box_at = |c: Point, h: Vector| (c - h, c + h);
        for case in 0..6 {
            let n = [2, 50, 400, 1000, 300, 64][case];
            let boxes: Vec<SweptBox> = (0..n)
                .map(|k| {
                    let c = Point::from(rng.in_unit_ball() * 15.0);
                    match (case, k % 7) {
                        // Points (zero extent), and boxes touching exactly.
                        (1, _) => box_at(Point::new((k / 2) as Real, 0.0, 0.0), Vector::zeros()),
                        // Walls and floors among small bodies.
                        (2 | 3, 0) => box_at(c, Vector::new(20.0, 20.0, rng.range(0.1, 1.0))),
                        // Far outliers: a grid that would be too fine.
                        (4, 0) => box_at(Point::from(rng.in_unit_ball() * 1e7), Vector::repeat(0.5)),
                        // All the same box.
                        (5, _) => box_at(Point::new(1.0, 2.0, 3.0), Vector::repeat(0.5)),
                        _ => box_at(
                            c,
                            Vector::new(rng.range(0.05, 1.0), rng.range(0.05, 1.0), rng.range(0.05, 1.0)),
                        ),
                    }
                })
                .collect();
            grid.pairs_into(&boxes, &mut pairs);
            assert_eq!(pairs, brute_force_pairs(&boxes), "case {case}");
            assert!(case == 0 || !pairs.is_empty(), "case {case} finds pairs");
        }
    }

    /// Moves each centre by up to `near` (the one in every `every` whose
    /// index is `call` modulo it by up to `far`), then boxes each in a cube
    /// of half side drawn from `half`.
    fn moved_boxes(
        rng: &mut Rng,
        centers: &mut [Point],
        (call, every): (usize, usize),
        (far, near): (Real, Real),
        half: (Real, Real),
    ) -> Vec<SweptBox> {
        for (k, c) in centers.iter_mut().enumerate() {
            *c += rng.in_unit_ball() * if k % every == call { far } else { near };
        }
        centers
            .iter()
            .map(|c| {
                let h = Vector::repeat(rng.range(half.0, half.1));
                (c - h, c + h)
            })
            .collect()
    }

    #[test]
    fn refitted_tree_pairs_equal_brute_force_pairs() {
        // The same 300 boxes moving over 20 calls: the refitted tree's pairs
        // stay those of brute force, including boxes that jump far.
        let mut rng = Rng::new(29);
        let mut broad = BroadPhase::default();
        let mut centers: Vec<Point> = (0..300).map(|_| Point::from(rng.in_unit_ball() * 15.0)).collect();
        for call in 0..20 {
            let boxes = moved_boxes(&mut rng, &mut centers, (call, 50), (20.0, 0.5), (0.2, 1.5));
            assert_eq!(broad.pairs(&boxes), brute_force_pairs(&boxes), "call {call}");
        }
    }

    #[test]
    fn tree_on_threads_gives_the_pairs_of_one_thread() {
        // Enough boxes for parry to split its refit and traversal into
        // tasks (its thresholds are 2,048 and 512 leaves), moving over five
        // calls, some far: the same pairs as brute force.
        let mut rng = Rng::new(53);
        let (mut threaded, mut single) = (BroadPhase::default(), BroadPhase::default());
        let (mut on_threads, mut on_one) = (Vec::new(), Vec::new());
        let mut centers: Vec<Point> = (0..6000).map(|_| Point::from(rng.in_unit_ball() * 30.0)).collect();
        for call in 0..5 {
            let boxes = moved_boxes(&mut rng, &mut centers, (call, 97), (10.0, 0.3), (0.2, 1.2));
            threaded.pairs_into_on(&boxes, &mut on_threads, true);
            single.pairs_into_on(&boxes, &mut on_one, false);
            assert!(on_threads.len() > 1000, "call {call}: {} pairs", on_threads.len());
            assert_eq!(on_threads, on_one, "call {call}");
            assert_eq!(on_threads, brute_force_pairs(&boxes), "call {call}");
        }
    }

    /// The boxes of `n` bodies in a room: jittered on a grid of side 1.2 as
    /// `many_bodies` places them, half sizes 0.3–0.6, and six walls.
    fn room(rng: &mut Rng, n: usize) -> Vec<SweptBox> {
        let side = (n as Real).cbrt().ceil() as usize;
        let half = 0.6 * side as Real;
        let mut boxes: Vec<SweptBox> = (0..n)
            .map(|k| {
                let at = |m: usize| -half + 1.2 * (m as Real + 0.5);
                let c = Point::new(at(k % side), at((k / side) % side), at(k / (side * side)))
                    + rng.in_unit_ball() * 0.2;
                let h = Vector::new(rng.range(0.3, 0.6), rng.range(0.3, 0.6), rng.range(0.3, 0.6));
                (c - h, c + h)
            })
            .collect();
        for axis in 0..3 {
            for side in [-1.0, 1.0] {
                let mut low = Point::from([-half - 0.5; 3]);
                let mut high = Point::from([half + 0.5; 3]);
                (low[axis], high[axis]) = if side < 0.0 { (-half - 0.5, -half) } else { (half, half + 0.5) };
                boxes.push((low, high));
            }
        }
        boxes
    }

    #[test]
    fn grid_on_threads_gives_the_pairs_of_one_thread() {
        let mut rng = Rng::new(61);
        let boxes = room(&mut rng, 6000);
        let (mut threaded, mut single) = (GridBroadPhase::default(), GridBroadPhase::default());
        let (mut on_threads, mut on_one) = (Vec::new(), Vec::new());
        threaded.pairs_into_on(&boxes, &mut on_threads, true);
        single.pairs_into_on(&boxes, &mut on_one, false);
        assert!(on_threads.len() > 1000, "{} pairs", on_threads.len());
        assert_eq!(on_threads, on_one);
        assert_eq!(on_threads, brute_force_pairs(&boxes));
    }

    /// A query box against the grid's last boxes gives the boxes brute
    /// force finds overlapping it, the room's large walls among them, and
    /// queries far outside the grid or as large as it too.
    #[test]
    fn grid_overlapping_a_query_equals_brute_force() {
        let mut rng = Rng::new(71);
        let boxes = room(&mut rng, 3000);
        let mut grid = GridBroadPhase::default();
        let mut pairs = Vec::new();
        grid.pairs_into(&boxes, &mut pairs);
        let mut queries: Vec<SweptBox> = (0..200)
            .map(|_| {
                let c = Point::from(rng.in_unit_ball() * 9.0);
                let h = Vector::repeat(rng.range(0.01, 3.0));
                (c - h, c + h)
            })
            .collect();
        queries.push((Point::new(-200.0, 0.0, 0.0), Point::new(-199.0, 1.0, 1.0)));
        queries.push((Point::from([-100.0; 3]), Point::from([100.0; 3])));
        let mut walls_met = 0;
        for query in &queries {
            let mut found = Vec::new();
            grid.overlapping(query, |i| found.push(i));
            found.sort_unstable();
            let expected: Vec<usize> =
                (0..boxes.len()).filter(|&i| boxes_overlap(query, &boxes[i])).collect();
            assert_eq!(found, expected);
            walls_met += found.iter().filter(|&&i| i >= 3000).count();
        }
        assert!(walls_met > 6, "the walls are met: {walls_met}");
    }

    #[test]
    fn many_boxes_go_through_the_grid_with_the_pairs_of_brute_force() {
        let mut rng = Rng::new(67);
        let boxes = room(&mut rng, GRID_BROAD_PHASE_BOXES + 100);
        let mut broad = BroadPhase::default();
        let mut pairs = Vec::new();
        for threads in [false, true] {
            broad.pairs_into_on(&boxes, &mut pairs, threads);
            assert!(broad.tree.is_none(), "no tree is built for the grid's boxes");
            assert!(pairs.len() > 1000, "{} pairs", pairs.len());
            assert_eq!(pairs, brute_force_pairs(&boxes), "threads: {threads}");
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

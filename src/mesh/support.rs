//! A mesh's farthest vertex along a direction — its support point — from a
//! table of directions built once per mesh, exact for any mesh (convex or
//! not): the same vertex a scan over every vertex finds.
//!
//! ## The table
//! Directions are cut into cells: the six faces of a cube (the direction's
//! largest component and its sign), each in `n × n` squares of the other
//! two components divided by the largest. A cell's directions form a
//! convex cone around its centre direction `c` (unit) of angular radius
//! `ρ`, measured as a chord: `|d − c| ≤ ρ` for every unit `d` in the cell
//! (the largest chord is at a corner, and a cone of directions within a
//! chord of `c` is convex, so the corners bound the whole cell).
//!
//! For each cell the table keeps the vertices that can be farthest along
//! some direction of the cell. With `w` the farthest vertex along `c`, a
//! vertex `v` is farthest along no `d` of the cell when
//!
//! ```text
//! (v − w)·d = (v − w)·c + (v − w)·(d − c) ≤ (v − w)·c + |v − w| ρ < 0
//! ```
//!
//! so only vertices with `(v − w)·c + |v − w| ρ ≥ −margin` are kept. The
//! margin, [`SUPPORT_TABLE_MARGIN`] times the mesh's radius, is a thousand
//! times what the rounding of a dot product (and of the test itself) can
//! move a comparison, so a vertex left out is smaller along `d` also in
//! floating point: the kept list, scanned in index order for the first
//! largest, gives exactly the vertex a whole scan gives, ties included.
//! Cells are filled from coarser cells' lists, level by level, each twice
//! as fine as the one before (a fine cell's directions lie in its coarse
//! cell, so its candidates are among the coarse cell's): a table costs a
//! few passes over the vertices, built once at the first query that needs
//! it.

use crate::math::{Point, Real, Vector};

/// The slack of the table's test, as a fraction of the mesh's radius (see
/// the module): about 1,000 times the rounding of a dot product.
pub(crate) const SUPPORT_TABLE_MARGIN: Real = 1e-12;

/// How much a cell's chord radius is widened (relatively, and absolutely:
/// chords are between unit directions) for the rounding of the cell
/// lookup, which may place a direction on a cell's edge in its neighbour:
/// far above that rounding (a few ulps), far below any cell (0.1 wide).
const CELL_WIDENING: Real = 1e-9;

/// Meshes with fewer vertices than this are scanned whole: a table would
/// not shorten the scan enough to pay for its memory.
pub(crate) const SUPPORT_TABLE_MIN_VERTICES: usize = 32;

/// Meshes with at least this many vertices have their table's cells
/// filled on rayon's threads: `4096` (a few milliseconds of work; below,
/// the hand-over would cost more than it gives).
pub(crate) const PARALLEL_SUPPORT_VERTICES: usize = 4096;

/// The table of one mesh (see the module).
#[derive(Clone, Debug)]
pub(crate) struct SupportTable {
    /// Cells along each side of a cube face.
    side: usize,
    /// The candidates of cell `k` are `candidates[start[k]..start[k + 1]]`.
    start: Vec<u32>,
    candidates: Vec<u32>,
}

/// A cell: cube face (`2 * axis + negative`) and square `(i, j)`.
#[derive(Copy, Clone, Debug)]
struct Cell {
    face: usize,
    i: usize,
    j: usize,
}

/// The two other axes of a face's axis, in a fixed order.
const OTHER_AXES: [(usize, usize); 3] = [(1, 2), (2, 0), (0, 1)];

impl SupportTable {
    /// The table of `vertices`, or `None` when the mesh is small enough to
    /// scan whole ([`SUPPORT_TABLE_MIN_VERTICES`]). The cells grow finer
    /// with the vertex count (16 × 16 a face from 800 vertices).
    pub(crate) fn build(vertices: &[Point]) -> Option<SupportTable> {
        Self::build_on(vertices, vertices.len() >= PARALLEL_SUPPORT_VERTICES)
    }

    /// [`SupportTable::build`], its cells on rayon's threads or not.
    fn build_on(vertices: &[Point], parallel: bool) -> Option<SupportTable> {
        let count = vertices.len();
        if count < SUPPORT_TABLE_MIN_VERTICES {
            return None;
        }
        let side = if count < 200 {
            4
        } else if count < 800 {
            8
        } else {
            16
        };
        let radius = vertices.iter().map(|v| v.coords.norm()).fold(0.0, Real::max);
        let margin = SUPPORT_TABLE_MARGIN * radius;
        // Levels of cells, each twice as fine as the one before: a cube
        // face a cell first, filtered from every vertex; then each cell
        // from its parent's candidates (the cones narrow, and so do the
        // pools).
        let everything: Vec<u32> = (0..count as u32).collect();
        let mut level = 1;
        let mut pools =
            cells(6, parallel, |k| keep(vertices, &cone(Self::cell_at(k, 1), 1), &everything, margin));
        while level < side {
            let finer = 2 * level;
            pools = cells(6 * finer * finer, parallel, |k| {
                let cell = Self::cell_at(k, finer);
                let parent = Cell { face: cell.face, i: cell.i / 2, j: cell.j / 2 };
                keep(vertices, &cone(cell, finer), &pools[Self::index(parent, level)], margin)
            });
            level = finer;
        }
        let mut start = Vec::with_capacity(pools.len() + 1);
        let mut candidates = Vec::with_capacity(pools.iter().map(Vec::len).sum());
        start.push(0);
        for pool in &pools {
            candidates.extend_from_slice(pool);
            start.push(candidates.len() as u32);
        }
        Some(SupportTable { side, start, candidates })
    }

    fn cell_at(k: usize, side: usize) -> Cell {
        Cell { face: k / (side * side), i: (k / side) % side, j: k % side }
    }

    fn index(cell: Cell, side: usize) -> usize {
        (cell.face * side + cell.i) * side + cell.j
    }

    /// The candidates for `direction`, or `None` for a direction that is
    /// zero or not finite (the caller scans every vertex).
    #[inline]
    pub(crate) fn candidates(&self, direction: &Vector) -> Option<&[u32]> {
        let size = direction.map(Real::abs);
        let axis = if size.x >= size.y && size.x >= size.z {
            0
        } else if size.y >= size.z {
            1
        } else {
            2
        };
        let major = size[axis];
        let (a, b) = OTHER_AXES[axis];
        let (u, w) = (direction[a] / major, direction[b] / major);
        if !(major > 0.0 && major.is_finite() && u.is_finite() && w.is_finite()) {
            return None;
        }
        let side = self.side as Real;
        // In [0, side]; `as` saturates, `min` keeps the edge u = 1 inside.
        let square = |x: Real| (((x + 1.0) * 0.5 * side) as usize).min(self.side - 1);
        let face = 2 * axis + usize::from(direction[axis] < 0.0);
        let k = Self::index(Cell { face, i: square(u), j: square(w) }, self.side);
        Some(&self.candidates[self.start[k] as usize..self.start[k + 1] as usize])
    }

    /// Bytes held by the table.
    pub(crate) fn bytes(&self) -> usize {
        4 * (self.start.len() + self.candidates.len())
    }
}

/// A cell's directions as a cone: its unit centre direction and a chord
/// radius `ρ` (see the module), widened for the rounding of the cell
/// lookup (a direction on a cell's edge may be placed in its neighbour).
fn cone(cell: Cell, side: usize) -> (Vector, Real) {
    let axis = cell.face / 2;
    let sign = if cell.face % 2 == 1 { -1.0 } else { 1.0 };
    let (a, b) = OTHER_AXES[axis];
    let direction = |u: Real, w: Real| {
        let mut d = Vector::zeros();
        d[axis] = sign;
        d[a] = u;
        d[b] = w;
        d.normalize()
    };
    let edge = |n: usize| -1.0 + 2.0 * n as Real / side as Real;
    let (u0, u1, w0, w1) = (edge(cell.i), edge(cell.i + 1), edge(cell.j), edge(cell.j + 1));
    let centre = direction(0.5 * (u0 + u1), 0.5 * (w0 + w1));
    let chord = [(u0, w0), (u0, w1), (u1, w0), (u1, w1)]
        .iter()
        .map(|&(u, w)| (direction(u, w) - centre).norm())
        .fold(0.0, Real::max);
    (centre, chord * (1.0 + CELL_WIDENING) + CELL_WIDENING)
}

/// The candidates of `count` cells, `fill(k)` for cell `k`, in order (on
/// rayon's threads when `parallel`).
fn cells(count: usize, parallel: bool, fill: impl Fn(usize) -> Vec<u32> + Sync + Send) -> Vec<Vec<u32>> {
    use rayon::prelude::*;
    if parallel {
        (0..count).into_par_iter().map(fill).collect()
    } else {
        (0..count).map(fill).collect()
    }
}

/// The vertices of `pool` (in its order) that may be farthest along some
/// direction of the cone `(centre, chord)`.
fn keep(vertices: &[Point], &(centre, chord): &(Vector, Real), pool: &[u32], margin: Real) -> Vec<u32> {
    let along = |k: u32| vertices[k as usize].coords.dot(&centre);
    let Some(&farthest) = pool.iter().max_by(|&&x, &&y| along(x).total_cmp(&along(y))) else {
        return Vec::new();
    };
    let w = vertices[farthest as usize];
    pool.iter()
        .copied()
        .filter(|&k| {
            let offset = vertices[k as usize] - w;
            offset.dot(&centre) + offset.norm() * chord >= -margin
        })
        .collect()
}

/// The first vertex of `vertices` farthest along `direction` (the first
/// largest dot product), by a scan over every vertex.
pub(crate) fn farthest_by_scan(vertices: &[Point], direction: &Vector) -> usize {
    const LANES: usize = 4;
    let value = |k: usize| {
        let p = &vertices[k];
        direction.x * p.x + direction.y * p.y + direction.z * p.z
    };
    // Four independent running maxima (each lane keeps its first largest),
    // so the comparisons do not wait on each other; then the largest over
    // the lanes, the lowest index among equals: the first largest vertex,
    // as a plain scan would find it.
    let mut best = [0usize; LANES];
    let mut best_value = [Real::NEG_INFINITY; LANES];
    let whole = vertices.len() / LANES * LANES;
    for start in (0..whole).step_by(LANES) {
        for lane in 0..LANES {
            let v = value(start + lane);
            if v > best_value[lane] {
                best_value[lane] = v;
                best[lane] = start + lane;
            }
        }
    }
    let (mut first, mut first_value) = (0, Real::NEG_INFINITY);
    for lane in 0..LANES {
        if best_value[lane] > first_value || (best_value[lane] == first_value && best[lane] < first) {
            (first, first_value) = (best[lane], best_value[lane]);
        }
    }
    for k in whole..vertices.len() {
        if value(k) > first_value {
            (first, first_value) = (k, value(k));
        }
    }
    first
}

/// The first of `candidates` (in their order) farthest along `direction`,
/// the dot products rounded as in [`farthest_by_scan`].
#[inline]
pub(crate) fn farthest_of(vertices: &[Point], candidates: &[u32], direction: &Vector) -> usize {
    let (mut first, mut first_value) = (candidates[0] as usize, Real::NEG_INFINITY);
    for &k in candidates {
        let p = &vertices[k as usize];
        let value = direction.x * p.x + direction.y * p.y + direction.z * p.z;
        if value > first_value {
            (first, first_value) = (k as usize, value);
        }
    }
    first
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::samples::Rng;

    /// Directions that stress the table: random ones, the axes and cube
    /// diagonals, and directions on cells' edges and corners (where the
    /// lookup's rounding may pick a neighbour), at several scales.
    fn directions(rng: &mut Rng) -> Vec<Vector> {
        let mut out = Vec::new();
        for _ in 0..3000 {
            out.push(rng.in_unit_ball());
        }
        for x in [-1.0, -0.5, -0.25, 0.0, 0.25, 0.5, 1.0] {
            for y in [-1.0, -0.75, -0.125, 0.0, 0.125, 0.375, 1.0] {
                for z in [-1.0, 0.0, 0.0625, 1.0] {
                    let d = Vector::new(x, y, z);
                    if d.norm() > 0.0 {
                        out.extend([d, -d, Vector::new(z, x, y), Vector::new(y, z, x)]);
                        out.push(d + rng.in_unit_ball() * 1e-15);
                    }
                }
            }
        }
        let scaled: Vec<Vector> = out.iter().flat_map(|d| [d * 1e-9, d * 3e7]).collect();
        out.extend(scaled);
        out
    }

    /// The table gives the scan's vertex for every direction; `short`: and
    /// no cell keeps a quarter of the vertices (the table is worth having;
    /// not so for flat or stretched meshes, whose cells keep many).
    fn check(name: &str, vertices: &[Point], short: bool) {
        let table = SupportTable::build(vertices).expect("enough vertices for a table");
        let mut rng = Rng::new(11);
        let mut longest = 0;
        for d in directions(&mut rng) {
            let candidates = table.candidates(&d).expect("a finite non-zero direction");
            longest = longest.max(candidates.len());
            let by_table = farthest_of(vertices, candidates, &d);
            let by_scan = farthest_by_scan(vertices, &d);
            assert_eq!(by_table, by_scan, "{name}: direction {d:?}");
        }
        assert!(!short || longest < vertices.len() / 4, "{name}: a cell keeps {longest}");
    }

    #[test]
    fn the_table_finds_the_scans_vertex() {
        let sphere = crate::mesh::icosphere(1.0, 3).expect("an icosphere");
        check("icosphere", sphere.vertices(), true);
        // Far from its frame's origin: the margin scales with the radius.
        let far: Vec<Point> = sphere.vertices().iter().map(|p| p + Vector::new(1e4, -3e3, 7.0)).collect();
        check("icosphere far from the origin", &far, false);
        let mut rng = Rng::new(5);
        let cloud: Vec<Point> = (0..2000).map(|_| Point::from(rng.in_unit_ball())).collect();
        check("points in a ball", &cloud, true);
        // A cube's surface on a grid: whole faces, edges and corners tie
        // along the axes and diagonals, and the first of equals must win.
        let mut grid = Vec::new();
        for i in 0..9 {
            for j in 0..9 {
                for k in 0..9 {
                    if [i, j, k].iter().any(|&n| n == 0 || n == 8) {
                        grid.push(Point::new(
                            i as Real / 8.0 - 0.5,
                            j as Real / 8.0 - 0.5,
                            k as Real / 8.0 - 0.5,
                        ));
                    }
                }
            }
        }
        check("cube grid", &grid, true);
        // Not convex: a dented, stretched sphere with points inside.
        let dented: Vec<Point> = sphere
            .vertices()
            .iter()
            .enumerate()
            .map(|(k, p)| {
                let dent = if k % 3 == 0 { 0.6 } else { 1.0 };
                Point::new(3.0 * p.x * dent, p.y * dent, 0.2 * p.z)
            })
            .collect();
        check("dented ellipsoid", &dented, false);
    }

    /// A mesh large enough for the threads: the table is the one-thread
    /// table, cell for cell, and gives the scan's vertex.
    #[test]
    fn the_table_built_on_threads_is_the_one_thread_table() {
        let sphere = crate::mesh::icosphere(1.0, 5).expect("an icosphere");
        let mut rng = Rng::new(3);
        // Jittered inward, so that not every vertex is on the hull.
        let vertices: Vec<Point> =
            sphere.vertices().iter().map(|p| p * (1.0 - 0.01 * rng.range(0.0, 1.0))).collect();
        assert!(vertices.len() >= PARALLEL_SUPPORT_VERTICES);
        let (threads, one) =
            (SupportTable::build_on(&vertices, true), SupportTable::build_on(&vertices, false));
        let (threads, one) = (threads.expect("a table"), one.expect("a table"));
        assert_eq!((threads.start, threads.candidates), (one.start, one.candidates));
        check("jittered icosphere", &vertices, true);
    }

    #[test]
    fn small_meshes_and_odd_directions_are_scanned_whole() {
        let cube = crate::mesh::box_mesh(&Vector::new(1.0, 2.0, 3.0)).expect("a box");
        assert!(SupportTable::build(cube.vertices()).is_none());
        let sphere = crate::mesh::icosphere(1.0, 2).expect("an icosphere");
        let table = SupportTable::build(sphere.vertices()).expect("a table");
        for d in [Vector::zeros(), Vector::new(Real::NAN, 0.0, 1.0), Vector::new(Real::INFINITY, 1.0, 0.0)] {
            assert!(table.candidates(&d).is_none(), "{d:?}");
        }
    }
}

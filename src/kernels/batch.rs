//! Batched kernels over structure-of-arrays (SoA) inputs.
//!
//! Each batched kernel runs the *same* branch-free per-query code as its
//! scalar twin, in a plain loop over the SoA columns that the compiler
//! vectorizes, dispatched at run time like the scalar kernels
//! ([`super::SimdLevel`]). Results are bit-identical to the scalar kernels.
//!
//! Kernels never allocate: the caller owns the output slice. Each kernel
//! processes `min` of the input and output lengths.

use super::dispatch::multiversioned;
use super::lanes::{F64x, Lane, V3};
use super::point_segment::{point_segment_distance_kernel, PointEdgeFormula};
use super::refine::{refined_distance_of, CandidateSource, LeastRefined};
use super::separated::{closest_separated_keeping, local_frame, Candidate, CandidateColumns, CandidateSink};
use super::triangle_triangle::{triangle_distance_kernel, Sequential};
use crate::math::{Point, Real, Triangle};

/// Points in structure-of-arrays layout: one column per coordinate.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct PointsSoa {
    /// x coordinates.
    pub x: Vec<Real>,
    /// y coordinates.
    pub y: Vec<Real>,
    /// z coordinates.
    pub z: Vec<Real>,
}

impl PointsSoa {
    /// Columns from a list of points.
    pub fn from_points(points: &[Point]) -> PointsSoa {
        PointsSoa {
            x: points.iter().map(|p| p.x).collect(),
            y: points.iter().map(|p| p.y).collect(),
            z: points.iter().map(|p| p.z).collect(),
        }
    }

    /// Columns for the three points of each query `(p, a, b)`.
    pub fn from_queries(queries: &[(Point, Point, Point)]) -> (PointsSoa, PointsSoa, PointsSoa) {
        let column = |k: usize| {
            PointsSoa::from_points(&queries.iter().map(|q| [q.0, q.1, q.2][k]).collect::<Vec<_>>())
        };
        (column(0), column(1), column(2))
    }

    /// Number of points (the shortest column).
    pub fn len(&self) -> usize {
        self.x.len().min(self.y.len()).min(self.z.len())
    }

    /// Whether there are no points.
    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }

    /// Point `i`. Panics if `i` is out of range.
    #[inline(always)]
    pub fn get(&self, i: usize) -> Point {
        Point::new(self.x[i], self.y[i], self.z[i])
    }
    /// Appends a point.
    #[inline]
    pub fn push(&mut self, p: &Point) {
        self.x.push(p.x);
        self.y.push(p.y);
        self.z.push(p.z);
    }

    /// Removes every point, keeping the allocation.
    pub fn clear(&mut self) {
        self.x.clear();
        self.y.clear();
        self.z.clear();
    }
}

/// Triangles in structure-of-arrays layout: one [`PointsSoa`] per vertex.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct TrianglesSoa {
    /// Vertex columns 0, 1 and 2.
    pub vertices: [PointsSoa; 3],
}

impl TrianglesSoa {
    /// Columns from a list of triangles.
    pub fn from_triangles(triangles: &[Triangle]) -> TrianglesSoa {
        let column = |k: usize| PointsSoa::from_points(&triangles.iter().map(|t| t[k]).collect::<Vec<_>>());
        TrianglesSoa { vertices: [column(0), column(1), column(2)] }
    }

    /// Columns for the first and the second triangle of each pair.
    pub fn from_pairs(pairs: &[(Triangle, Triangle)]) -> (TrianglesSoa, TrianglesSoa) {
        let firsts: Vec<Triangle> = pairs.iter().map(|p| p.0).collect();
        let seconds: Vec<Triangle> = pairs.iter().map(|p| p.1).collect();
        (TrianglesSoa::from_triangles(&firsts), TrianglesSoa::from_triangles(&seconds))
    }

    /// Number of triangles (the shortest column).
    pub fn len(&self) -> usize {
        self.vertices.iter().map(PointsSoa::len).min().unwrap_or(0)
    }

    /// Whether there are no triangles.
    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }

    /// Triangle `i`. Panics if `i` is out of range.
    #[inline(always)]
    pub fn get(&self, i: usize) -> Triangle {
        [self.vertices[0].get(i), self.vertices[1].get(i), self.vertices[2].get(i)]
    }
    /// Appends a triangle.
    #[inline]
    pub fn push(&mut self, t: &Triangle) {
        for (column, p) in self.vertices.iter_mut().zip(t) {
            column.push(p);
        }
    }

    /// Removes every triangle, keeping the allocation.
    pub fn clear(&mut self) {
        self.vertices.iter_mut().for_each(PointsSoa::clear);
    }
}

multiversioned! {
    /// [`point_segment_distance`](super::point_segment_distance) for each `(p[i], a[i], b[i])`, into `out[i]`.
    pub fn point_segment_distances / point_segment_distances_with(
        p: &PointsSoa, a: &PointsSoa, b: &PointsSoa, formula: PointEdgeFormula, out: &mut [Real]
    ) {
        let n = out.len().min(p.len()).min(a.len()).min(b.len());
        let out = &mut out[..n];
        // One monomorphic loop per formula, so the formula is not a per-lane branch.
        macro_rules! run {
            ($formula:expr) => {
                for (i, o) in out.iter_mut().enumerate() {
                    *o = point_segment_distance_kernel(&p.get(i), &a.get(i), &b.get(i), $formula);
                }
            };
        }
        match formula {
            PointEdgeFormula::Vector => run!(PointEdgeFormula::Vector),
            PointEdgeFormula::PlainVector => run!(PointEdgeFormula::PlainVector),
            PointEdgeFormula::Heron => run!(PointEdgeFormula::Heron),
            PointEdgeFormula::StableHeron => run!(PointEdgeFormula::StableHeron),
        }
    }
}

multiversioned! {
    /// [`triangle_distance`](super::triangle_distance)`(a[i], b[i]).distance` for each pair, into
    /// `out[i]`. Eight pairs at a time in vector lanes; pairs whose closest
    /// direction does not certainly separate them (touching, crossing or
    /// nearly so) are finished by the scalar kernel's exact test; small
    /// distances are refined one lane at a time, as in the scalar kernel,
    /// a tie among candidates settled from the candidates the pass kept.
    pub fn triangle_distances / triangle_distances_with(a: &TrianglesSoa, b: &TrianglesSoa, out: &mut [Real]) {
        let n = out.len().min(a.len()).min(b.len());
        let out = &mut out[..n];
        // Vectorized pass: separated pairs get their distance; the others are
        // marked with -1 (distances are never negative).
        let mut chunks = out.chunks_exact_mut(LANES);
        // Every candidate of the eight pairs, for the refinement's tie path.
        let mut kept = [[F64x::splat(0.0); 3]; 15];
        for (chunk, o) in (&mut chunks).enumerate() {
            let start = chunk * LANES;
            let ta = [load(&a.vertices[0], start), load(&a.vertices[1], start), load(&a.vertices[2], start)];
            let tb = [load(&b.vertices[0], start), load(&b.vertices[1], start), load(&b.vertices[2], start)];
            let (local_a, local_b) = local_frame(&ta, &tb);
            let closest = closest_separated_keeping(&local_a, &local_b, &mut kept);
            let plain = closest.best.distance_squared.sqrt();
            let refine = closest.needs_refinement();
            for (k, o) in o.iter_mut().enumerate() {
                *o = if closest.certified.0[k] == 0 {
                    -1.0
                } else if refine.0[k] != 0 {
                    let kept = KeptLane { columns: &kept, lane: k };
                    refined_distance_of(&a.get(start + k), &b.get(start + k), &closest.lane(k), &kept)
                } else {
                    plain.0[k]
                };
            }
        }
        let tail_start = n - chunks.into_remainder().len();
        for (i, o) in out.iter_mut().enumerate().skip(tail_start) {
            *o = triangle_distance_kernel::<Sequential>(&a.get(i), &b.get(i)).distance;
        }
        // Scalar pass over the few marked pairs, with the exact test.
        for (i, o) in out.iter_mut().enumerate() {
            if *o < 0.0 {
                *o = triangle_distance_kernel::<Sequential>(&a.get(i), &b.get(i)).distance;
            }
        }
    }
}

/// One lane of the pass's kept candidates, as the refinement's tie path
/// reads them (instead of computing the pair's candidates again).
struct KeptLane<'k> {
    columns: &'k CandidateColumns<F64x<LANES>>,
    lane: usize,
}

impl CandidateSource for KeptLane<'_> {
    #[inline(always)]
    fn visit(&self, _: &Triangle, _: &Triangle, sink: &mut LeastRefined) {
        for (code, [squared, s, t]) in self.columns.iter().enumerate() {
            let k = self.lane;
            sink.consider(squared.0[k], Candidate::decode(code), s.0[k], t.0[k], V3::zeros());
        }
    }
}

/// Pairs per vector step: eight `f64` fill an AVX-512 register (two AVX2
/// registers).
const LANES: usize = 8;

/// Points `start..start + LANES` of a column set, as lanes.
#[inline(always)]
fn load(points: &PointsSoa, start: usize) -> V3<F64x<LANES>> {
    #[inline(always)]
    fn column(c: &[Real], start: usize) -> F64x<LANES> {
        let mut lanes = [0.0; LANES];
        lanes.copy_from_slice(&c[start..start + LANES]);
        F64x(lanes)
    }
    V3::new(column(&points.x, start), column(&points.y, start), column(&points.z, start))
}

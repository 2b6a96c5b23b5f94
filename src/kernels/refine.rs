//! Refinement of a small triangle–triangle distance to a few ulps.
//!
//! The candidate pass ([`super::separated`]) computes in plain f64 on local
//! coordinates; its absolute error is a few ulps of the pair's extent `S`,
//! which is a large relative error for a gap of 1e-12 between unit
//! triangles. Below [`REFINE_BELOW_EXTENT`]·S the winning candidate's
//! distance is recomputed from exact differences of the input coordinates:
//! vertex–face and edge–edge heights as `|det(u, v, w)| / |u × v|` in
//! double-double ([`super::double_double`]), vertex–edge by the exact
//! `Vector` point–segment formula, vertex–vertex from one rounded difference.
//!
//! When the runner-up candidate is within the plain pass's rounding band of
//! the winner (nearly parallel edges, coplanar faces), which one won is a
//! matter of rounding; then every candidate in the band is refined (each
//! set of features once: a vertex–edge pair is found by both edges at the
//! vertex) and the least is kept.

use super::double_double::{height_over_plane, vector_difference};
use super::lanes::Lane;
use super::lanes::V3;
use super::point_segment::{point_segment_distance_kernel, PointEdgeFormula};
use super::separated::{
    local_frame, triangle_lanes, visit_candidates, Candidate, CandidateSink, ClosestSeparated,
};
use crate::math::{Point, Real, Triangle};

/// Below this fraction of the pair's extent `S` (its largest coordinate
/// relative to `a[0]`), a triangle distance is refined. Above it the plain
/// result's absolute error, about `2ε·S`, is already below `1e-12`
/// relative. Default `1e-3`.
pub(crate) const REFINE_BELOW_EXTENT: Real = 1e-3;

/// The rounding band of the plain candidate pass, in `ε·S`: candidates whose
/// plain distances are within this of the least may be the true least, and
/// are all refined. Each plain distance is within about `2ε·S` of its exact
/// value (measured: at most 1.5); two of them, with room. Default `16`.
pub(crate) const REFINE_TIE_BAND_ULPS: Real = 16.0;

impl<L: Lane> ClosestSeparated<L> {
    /// Whether the distance is small enough next to the pair's extent to be
    /// refined (per lane).
    #[inline(always)]
    pub fn needs_refinement(&self) -> L::Mask {
        let threshold = L::splat(REFINE_BELOW_EXTENT) * self.extent;
        self.best.distance_squared.lt(threshold * threshold)
    }
}

/// The refinement with the sequential tie path (the baseline's, and the
/// sequential single pair's at every level).
#[inline(always)]
pub(crate) fn refined_distance_kernel(a: &Triangle, b: &Triangle, closest: &ClosestSeparated<Real>) -> Real {
    refined_distance_of(a, b, closest, &Sequentially)
}

/// Where the refinement's tie path gets the candidates again.
pub(crate) trait CandidateSource {
    /// Feeds every candidate of `a`, `b` (world coordinates) to `sink`, each
    /// with the squared distance and edge parameters the candidate pass
    /// computes for it (in any order: the sink keeps a minimum).
    fn visit(&self, a: &Triangle, b: &Triangle, sink: &mut LeastRefined);
}

/// The candidates recomputed one after another.
struct Sequentially;

impl CandidateSource for Sequentially {
    #[inline(always)]
    fn visit(&self, a: &Triangle, b: &Triangle, sink: &mut LeastRefined) {
        let (local_a, local_b) = local_frame(&triangle_lanes(a), &triangle_lanes(b));
        visit_candidates(&local_a, &local_b, sink);
    }
}

/// The refined distance of triangles `a`, `b` (world coordinates) given
/// their candidate pass; on a tie, the candidates again from `candidates`.
#[inline(always)]
pub(crate) fn refined_distance_of(
    a: &Triangle,
    b: &Triangle,
    closest: &ClosestSeparated<Real>,
    candidates: &impl CandidateSource,
) -> Real {
    let plain = closest.best.distance_squared.sqrt();
    let band = plain + REFINE_TIE_BAND_ULPS * Real::EPSILON * closest.extent;
    let band_squared = band * band;
    if closest.best.runner_up_squared > band_squared {
        return candidate_distance(a, b, closest.winner(), closest.best.s, closest.best.t).unwrap_or(plain);
    }
    // A tie within rounding: the candidates again (kept by the pass, or
    // recomputed) and every one in the band refined. (Carrying the
    // runner-up's identity through the vector pass instead was measured
    // slower: register pressure.)
    let mut least = LeastRefined { a, b, band_squared, least: Real::INFINITY, refined: [0; 4], count: 0 };
    candidates.visit(a, b, &mut least);
    least.least
}

/// Refines every candidate within the band (each set of features once),
/// keeping the least (in any order of the candidates).
pub(crate) struct LeastRefined<'t> {
    a: &'t Triangle,
    b: &'t Triangle,
    band_squared: Real,
    least: Real,
    /// The first `count` (at most four) refined candidates' features
    /// ([`feature_key`]).
    refined: [u8; 4],
    count: usize,
}

/// Which features a candidate's refinement reads, as `8 · on_a + on_b`,
/// each a vertex (0–2), an edge's interior (3–5) or the face (6). Two
/// candidates with the same key refine to the same value from the same
/// points: a vertex–edge pair is found by both edges at the vertex.
#[inline(always)]
fn feature_key(candidate: Candidate, s: Real, t: Real) -> u8 {
    let on = |edge: usize, x: Real| match on_edge(edge, x) {
        OnEdge::Inside => 3 + edge as u8,
        OnEdge::End(vertex) => vertex as u8,
    };
    let (on_a, on_b) = match candidate {
        Candidate::VertexOfBOverFaceOfA(v) => (6, v as u8),
        Candidate::VertexOfAOverFaceOfB(v) => (v as u8, 6),
        Candidate::Edges(i, j) => (on(i, s), on(j, t)),
    };
    8 * on_a + on_b
}

impl CandidateSink<Real> for LeastRefined<'_> {
    #[inline(always)]
    fn consider(&mut self, squared: Real, candidate: Candidate, s: Real, t: Real, _: V3<Real>) {
        if squared <= self.band_squared {
            // A twin of a candidate refined already: the same value again.
            let key = feature_key(candidate, s, t);
            if self.refined[..self.count].contains(&key) {
                return;
            }
            if self.count < self.refined.len() {
                self.refined[self.count] = key;
                self.count += 1;
            }
            let plain = squared.sqrt();
            let refined = candidate_distance(self.a, self.b, candidate, s, t).unwrap_or(plain);
            self.least = self.least.min(refined);
        }
    }
}

/// One candidate's distance to a few ulps. `None` for a degenerate face.
#[inline(always)]
fn candidate_distance(a: &Triangle, b: &Triangle, candidate: Candidate, s: Real, t: Real) -> Option<Real> {
    let (i, j) = match candidate {
        Candidate::VertexOfBOverFaceOfA(vertex) => return vertex_over_face(&b[vertex], a),
        Candidate::VertexOfAOverFaceOfB(vertex) => return vertex_over_face(&a[vertex], b),
        Candidate::Edges(i, j) => (i, j),
    };
    let (p0, p1, q0, q1) = (&a[i], &a[(i + 1) % 3], &b[j], &b[(j + 1) % 3]);
    Some(match (on_edge(i, s), on_edge(j, t)) {
        (OnEdge::Inside, OnEdge::Inside) => {
            let [v0, v1, w0, w1] = [V3::from(p0), V3::from(p1), V3::from(q0), V3::from(q1)];
            let (d1, d2) = (vector_difference(&v1, &v0), vector_difference(&w1, &w0));
            match height_over_plane(&d1, &d2, &vector_difference(&v0, &w0)) {
                Some(height) => height,
                // Parallel edges span no plane: their distance is then the
                // least of the four vertex–edge distances.
                None => vertex_edge(p0, q0, q1)
                    .min(vertex_edge(p1, q0, q1))
                    .min(vertex_edge(q0, p0, p1))
                    .min(vertex_edge(q1, p0, p1)),
            }
        }
        (OnEdge::End(v), OnEdge::Inside) => vertex_edge(&a[v], q0, q1),
        (OnEdge::Inside, OnEdge::End(w)) => vertex_edge(&b[w], p0, p1),
        (OnEdge::End(v), OnEdge::End(w)) => (a[v] - b[w]).norm(),
    })
}

/// Where a candidate's point lies on edge `edge` (from vertex `edge` to
/// `edge + 1`) at parameter `x`, as the refinement reads it.
#[derive(Copy, Clone, PartialEq, Eq)]
enum OnEdge {
    /// Strictly between the ends.
    Inside,
    /// At this vertex: the first end for `x <= 0`, the second otherwise.
    End(usize),
}

#[inline(always)]
fn on_edge(edge: usize, x: Real) -> OnEdge {
    if 0.0 < x && x < 1.0 {
        OnEdge::Inside
    } else if x <= 0.0 {
        OnEdge::End(edge)
    } else {
        OnEdge::End((edge + 1) % 3)
    }
}

/// Height of `p` over the plane of `face`, from exact differences.
#[inline(always)]
fn vertex_over_face(p: &Point, face: &Triangle) -> Option<Real> {
    let [f0, f1, f2] = [V3::from(&face[0]), V3::from(&face[1]), V3::from(&face[2])];
    let (u, v) = (vector_difference(&f1, &f0), vector_difference(&f2, &f0));
    height_over_plane(&u, &v, &vector_difference(&V3::from(p), &f0))
}

/// Distance from `p` to segment `[e0, e1]` by the exact vector formula.
#[inline(always)]
fn vertex_edge(p: &Point, e0: &Point, e1: &Point) -> Real {
    point_segment_distance_kernel(p, e0, e1, PointEdgeFormula::Vector)
}

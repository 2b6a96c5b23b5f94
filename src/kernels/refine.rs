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
//! matter of rounding; then every candidate in the band is refined and the
//! least is kept.

use super::double_double::{height_over_plane, vector_difference};
use super::lanes::V3;
use super::point_segment::{point_segment_distance_kernel, PointEdgeFormula};
use super::separated::{visit_candidates, Candidate, CandidateSink, ClosestSeparated};
use crate::math::{Point, Real, Triangle};

/// Below this fraction of the pair's extent `S` (its largest coordinate
/// relative to `a[0]`), a triangle distance is refined. Above it the plain
/// result's absolute error, about `2ε·S`, is already below `1e-12`
/// relative. Default `1e-3`.
pub const REFINE_BELOW_EXTENT: Real = 1e-3;

/// The rounding band of the plain candidate pass, in `ε·S`: candidates whose
/// plain distances are within this of the least may be the true least, and
/// are all refined. Each plain distance is within about `2ε·S` of its exact
/// value (measured: at most 1.5); two of them, with room. Default `16`.
pub const REFINE_TIE_BAND_ULPS: Real = 16.0;

impl ClosestSeparated<Real> {
    /// Whether the distance is small enough next to the pair's extent to be
    /// refined.
    #[inline]
    pub fn needs_refinement(&self) -> bool {
        let threshold = REFINE_BELOW_EXTENT * self.extent;
        self.distance_squared < threshold * threshold
    }
}

/// The refined distance of triangles `a`, `b` (world coordinates), given
/// their candidate pass.
pub(crate) fn refined_distance(a: &Triangle, b: &Triangle, closest: &ClosestSeparated<Real>) -> Real {
    let plain = closest.distance_squared.sqrt();
    let band = plain + REFINE_TIE_BAND_ULPS * Real::EPSILON * closest.extent;
    if closest.runner_up_squared > band * band {
        return candidate_distance(a, b, closest.winner(), closest.s, closest.t).unwrap_or(plain);
    }
    // A tie within rounding: refine every candidate in the band.
    let origin = V3::from(&a[0]);
    let local_a = [V3::from(&a[0]) - origin, V3::from(&a[1]) - origin, V3::from(&a[2]) - origin];
    let local_b = [V3::from(&b[0]) - origin, V3::from(&b[1]) - origin, V3::from(&b[2]) - origin];
    let mut least = LeastRefined { a, b, band_squared: band * band, least: Real::INFINITY };
    visit_candidates(&local_a, &local_b, &mut least);
    least.least
}

/// Refines every candidate within the band, keeping the least.
struct LeastRefined<'t> {
    a: &'t Triangle,
    b: &'t Triangle,
    band_squared: Real,
    least: Real,
}

impl CandidateSink<Real> for LeastRefined<'_> {
    fn consider(&mut self, squared: Real, candidate: Candidate, s: Real, t: Real, _: V3<Real>) {
        if squared <= self.band_squared {
            let plain = squared.sqrt();
            let refined = candidate_distance(self.a, self.b, candidate, s, t).unwrap_or(plain);
            self.least = self.least.min(refined);
        }
    }
}

/// One candidate's distance to a few ulps. `None` for a degenerate face.
fn candidate_distance(a: &Triangle, b: &Triangle, candidate: Candidate, s: Real, t: Real) -> Option<Real> {
    let vertex_over_face = |p: &Point, face: &Triangle| {
        let [f0, f1, f2] = face.each_ref().map(V3::from);
        let (u, v) = (vector_difference(&f1, &f0), vector_difference(&f2, &f0));
        height_over_plane(&u, &v, &vector_difference(&V3::from(p), &f0))
    };
    let (i, j) = match candidate {
        Candidate::VertexOfBOverFaceOfA(vertex) => return vertex_over_face(&b[vertex], a),
        Candidate::VertexOfAOverFaceOfB(vertex) => return vertex_over_face(&a[vertex], b),
        Candidate::Edges(i, j) => (i, j),
    };
    let (p0, p1, q0, q1) = (&a[i], &a[(i + 1) % 3], &b[j], &b[(j + 1) % 3]);
    let vertex_edge = |p: &Point, e0: &Point, e1: &Point| {
        point_segment_distance_kernel(p, e0, e1, PointEdgeFormula::Vector)
    };
    let interior = |x: Real| x > 0.0 && x < 1.0;
    let end = |x: Real, start: &Point, finish: &Point| if x <= 0.0 { *start } else { *finish };
    Some(match (interior(s), interior(t)) {
        (true, true) => {
            let [v0, v1, w0, w1] = [p0, p1, q0, q1].map(V3::from);
            let (d1, d2) = (vector_difference(&v1, &v0), vector_difference(&w1, &w0));
            // Parallel edges span no plane: their distance is then the least
            // of the four vertex–edge distances.
            height_over_plane(&d1, &d2, &vector_difference(&v0, &w0)).unwrap_or_else(|| {
                vertex_edge(p0, q0, q1)
                    .min(vertex_edge(p1, q0, q1))
                    .min(vertex_edge(q0, p0, p1))
                    .min(vertex_edge(q1, p0, p1))
            })
        }
        (false, true) => vertex_edge(&end(s, p0, p1), q0, q1),
        (true, false) => vertex_edge(&end(t, q0, q1), p0, p1),
        (false, false) => (end(s, p0, p1) - end(t, q0, q1)).norm(),
    })
}

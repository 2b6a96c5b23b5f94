//! The candidate pass of the triangle–triangle distance: the 15 candidate
//! pairs of two triangles, their minimum, and a certificate that the
//! triangles are disjoint.
//!
//! For disjoint triangles the closest pair is attained by a vertex over the
//! interior of the other face (6 candidates) or by two edges (9 candidates;
//! vertex–edge and vertex–vertex pairs are edge–edge pairs with clamped
//! parameters). The code is written once for [`Lane`]s, with selects and no
//! branches, so it runs on one pair (`f64`) or on eight (`F64x<8>`) with the
//! same result bit for bit. It avoids closures and iterator adapters: inside
//! the dispatched functions those are not inlined and run without the vector
//! instruction set.

use super::lanes::{F64x, Lane, V3};
use super::point_triangle::{point_face_interior, FacePlane};
use super::segment_segment::{segment_segment_lanes, Edge};
use crate::math::{Real, Triangle};

/// One of the 15 candidate pairs, decoded from its code (the order in
/// which [`visit_candidates`] considers them).
#[derive(Copy, Clone, Debug, PartialEq, Eq)]
pub(crate) enum Candidate {
    /// Vertex `i` of b over the interior of a's face (codes 0, 2, 4).
    VertexOfBOverFaceOfA(usize),
    /// Vertex `i` of a over the interior of b's face (codes 1, 3, 5).
    VertexOfAOverFaceOfB(usize),
    /// Edge `i` of a (from vertex `i` to `i + 1`) and edge `j` of b (codes 6..15).
    Edges(usize, usize),
}

impl Candidate {
    /// The code of this candidate.
    #[inline(always)]
    pub fn code(self) -> usize {
        match self {
            Candidate::VertexOfBOverFaceOfA(i) => 2 * i,
            Candidate::VertexOfAOverFaceOfB(i) => 2 * i + 1,
            Candidate::Edges(i, j) => 6 + 3 * i + j,
        }
    }

    /// The candidate with code `code` (codes above 14 read as edges 2, 2).
    #[inline]
    pub fn decode(code: usize) -> Candidate {
        match code {
            0..=5 if code.is_multiple_of(2) => Candidate::VertexOfBOverFaceOfA(code / 2),
            0..=5 => Candidate::VertexOfAOverFaceOfB(code / 2),
            _ => Candidate::Edges(((code - 6) / 3).min(2), (code - 6) % 3),
        }
    }
}

/// Receives every candidate of [`visit_candidates`].
pub(crate) trait CandidateSink<L: Lane> {
    /// Candidate `candidate` at squared distance `squared` (`+∞` where it does
    /// not apply), edge parameters `s`, `t`, and `separation` = point on b
    /// minus point on a.
    fn consider(&mut self, squared: L, candidate: Candidate, s: L, t: L, separation: V3<L>);
}

/// Feeds the 15 candidates of triangles `a`, `b` (local coordinates) to `sink`.
#[inline(always)]
#[allow(clippy::needless_range_loop)] // index loops: see the module docs
pub(crate) fn visit_candidates<L: Lane, S: CandidateSink<L>>(a: &[V3<L>; 3], b: &[V3<L>; 3], sink: &mut S) {
    let zero = L::splat(0.0);
    let face_a = FacePlane::new(a);
    let face_b = FacePlane::new(b);
    for vertex in 0..3 {
        // The separation runs from a to b: the vertex's offset from its
        // projection, or its opposite.
        let (squared, offset) = point_face_interior(&b[vertex], &face_a);
        sink.consider(squared, Candidate::VertexOfBOverFaceOfA(vertex), zero, zero, offset);
        let (squared, offset) = point_face_interior(&a[vertex], &face_b);
        sink.consider(squared, Candidate::VertexOfAOverFaceOfB(vertex), zero, zero, -offset);
    }
    let edges_a = [Edge::new(&a[0], &a[1]), Edge::new(&a[1], &a[2]), Edge::new(&a[2], &a[0])];
    let edges_b = [Edge::new(&b[0], &b[1]), Edge::new(&b[1], &b[2]), Edge::new(&b[2], &b[0])];
    for i in 0..3 {
        for j in 0..3 {
            let c = segment_segment_lanes(&edges_a[i], &edges_b[j]);
            sink.consider(c.distance_squared, Candidate::Edges(i, j), c.s, c.t, -c.gap);
        }
    }
}

/// The minimum over the 15 candidates, the runner-up, and whether the
/// triangles are certainly disjoint.
#[derive(Copy, Clone, Debug)]
pub(crate) struct ClosestSeparated<L: Lane> {
    /// The least candidate: its squared distance, the runner-up (a tie with
    /// the least makes the choice of winner a matter of rounding), which
    /// candidate, its edge parameters and separation.
    pub best: Best<L>,
    /// Whether the plane normal to the direction between the winning pair
    /// certainly separates the triangles (then they are disjoint and the
    /// minimum is their distance); false means "not certain": the exact test
    /// must decide.
    pub certified: L::Mask,
    /// The largest local coordinate of the pair (its scale `S`).
    pub extent: L,
}

impl ClosestSeparated<Real> {
    /// The winning candidate.
    #[inline]
    pub fn winner(&self) -> Candidate {
        Candidate::decode(self.best.candidate as usize)
    }
}

impl<const N: usize> ClosestSeparated<F64x<N>> {
    /// Lane `k` as a scalar result.
    #[inline(always)]
    pub fn lane(&self, k: usize) -> ClosestSeparated<Real> {
        let best = &self.best;
        let separation = &best.separation;
        ClosestSeparated {
            best: Best {
                distance_squared: best.distance_squared.0[k],
                runner_up_squared: best.runner_up_squared.0[k],
                candidate: best.candidate.0[k],
                s: best.s.0[k],
                t: best.t.0[k],
                separation: V3::new(separation.x.0[k], separation.y.0[k], separation.z.0[k]),
            },
            certified: self.certified.0[k] != 0,
            extent: self.extent.0[k],
        }
    }
}

/// How many `ε · ‖u‖₁ · S` a separation along `u` must exceed to be certain
/// (S the largest local coordinate). Each projection `u·v` carries at most
/// about `6.2 ε ‖u‖ S` of error: `ε/2` relative from forming the local
/// coordinate, `3ε` from the dot product on `|v| ≤ √3 S`; two of them are
/// compared. 16 covers `2 × 6.2` with room.
pub(crate) const SEPARATION_MARGIN_ULPS: Real = 16.0;

/// Triangles `a` and `b` relative to `a`'s first vertex, the frame every
/// candidate is computed in: differences of nearby large coordinates are
/// exact, so a pair far from the origin is as accurate as one at it.
#[inline(always)]
pub(crate) fn local_frame<L: Lane>(a: &[V3<L>; 3], b: &[V3<L>; 3]) -> ([V3<L>; 3], [V3<L>; 3]) {
    let origin = a[0];
    ([a[0] - origin, a[1] - origin, a[2] - origin], [b[0] - origin, b[1] - origin, b[2] - origin])
}

/// A triangle's vertices as one-lane vectors.
#[inline(always)]
pub(crate) fn triangle_lanes(t: &Triangle) -> [V3<Real>; 3] {
    [V3::from(&t[0]), V3::from(&t[1]), V3::from(&t[2])]
}

/// The smallest of the 15 candidate squared distances between two
/// triangles (local coordinates), which pair attains it, and whether the
/// direction between that pair certifies that the triangles are disjoint.
/// The first minimum in the fixed candidate order wins ties.
#[inline(always)]
pub(crate) fn closest_separated<L: Lane>(a: &[V3<L>; 3], b: &[V3<L>; 3]) -> ClosestSeparated<L> {
    let mut best = Best::empty();
    visit_candidates(a, b, &mut best);
    certify(a, b, &best)
}

/// Every candidate's squared distance and edge parameters (lanes), by
/// code: what the refinement's tie path needs, kept by the batch's pass
/// so that a refined pair need not run its candidates again.
pub(crate) type CandidateColumns<L> = [[L; 3]; 15];

/// [`closest_separated`], each candidate's squared distance and edge
/// parameters also written to `kept` (by code).
#[inline(always)]
pub(crate) fn closest_separated_keeping<L: Lane>(
    a: &[V3<L>; 3],
    b: &[V3<L>; 3],
    kept: &mut CandidateColumns<L>,
) -> ClosestSeparated<L> {
    let mut keeping = Keeping { best: Best::empty(), kept };
    visit_candidates(a, b, &mut keeping);
    certify(a, b, &keeping.best)
}

/// A [`Best`] that also keeps every candidate.
struct Keeping<'k, L: Lane> {
    best: Best<L>,
    kept: &'k mut CandidateColumns<L>,
}

impl<L: Lane> CandidateSink<L> for Keeping<'_, L> {
    #[inline(always)]
    fn consider(&mut self, squared: L, candidate: Candidate, s: L, t: L, separation: V3<L>) {
        self.kept[candidate.code()] = [squared, s, t];
        self.best.consider(squared, candidate, s, t, separation);
    }
}

/// The pass's result from its minimum: the separating-axis certificate
/// along the winning pair's direction, and the pair's extent.
#[inline(always)]
pub(super) fn certify<L: Lane>(a: &[V3<L>; 3], b: &[V3<L>; 3], best: &Best<L>) -> ClosestSeparated<L> {
    let u = best.separation;
    let highest_a = u.dot(&a[0]).max(u.dot(&a[1])).max(u.dot(&a[2]));
    let lowest_b = u.dot(&b[0]).min(u.dot(&b[1])).min(u.dot(&b[2]));
    let extent_a = a[0].max_abs().max(a[1].max_abs()).max(a[2].max_abs());
    let extent = extent_a.max(b[0].max_abs()).max(b[1].max_abs()).max(b[2].max_abs());
    let margin = L::splat(SEPARATION_MARGIN_ULPS * Real::EPSILON) * u.norm_l1() * extent;
    ClosestSeparated { best: *best, certified: margin.lt(lowest_b - highest_a), extent }
}

/// The running minimum and runner-up of [`closest_separated`].
#[derive(Copy, Clone, Debug)]
pub(crate) struct Best<L: Lane> {
    /// The least squared distance so far.
    pub distance_squared: L,
    /// The least of the others.
    pub runner_up_squared: L,
    /// The code of the candidate attaining the least.
    pub candidate: L,
    /// Its edge parameter on a.
    pub s: L,
    /// Its edge parameter on b.
    pub t: L,
    /// Its separation, from a to b.
    pub separation: V3<L>,
}

impl<L: Lane> Best<L> {
    /// Before any candidate: everything at `+∞`, candidate 0.
    #[inline(always)]
    pub fn empty() -> Best<L> {
        let (zero, infinity) = (L::splat(0.0), L::splat(Real::INFINITY));
        Best {
            distance_squared: infinity,
            runner_up_squared: infinity,
            candidate: zero,
            s: zero,
            t: zero,
            separation: V3::zeros(),
        }
    }
}

impl<L: Lane> CandidateSink<L> for Best<L> {
    /// Keeps the candidate where it is strictly closer.
    #[inline(always)]
    fn consider(&mut self, squared: L, candidate: Candidate, s: L, t: L, separation: V3<L>) {
        let better = squared.lt(self.distance_squared);
        self.runner_up_squared =
            L::select(better, self.distance_squared, squared.min(self.runner_up_squared));
        self.distance_squared = L::select(better, squared, self.distance_squared);
        self.candidate = L::select(better, L::splat(candidate.code() as Real), self.candidate);
        self.s = L::select(better, s, self.s);
        self.t = L::select(better, t, self.t);
        self.separation = V3::select(better, separation, self.separation);
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn candidate_codes_round_trip() {
        for code in 0..15 {
            assert_eq!(Candidate::decode(code).code(), code);
        }
    }
}

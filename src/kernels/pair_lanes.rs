//! The candidate pass of *one* triangle pair with its candidates side by
//! side in the four lanes of an AVX2 register.
//!
//! [`closest_separated`](super::separated::closest_separated) visits the 15
//! candidates one after another; the batch runs it with one pair per lane.
//! A single pair has no other pairs to fill lanes with, so here the lanes
//! hold its candidates:
//!
//! - both face planes are built at once, in lanes `[a, b, a, b]`, and the
//!   six vertex–face candidates are two registers against them: lanes
//!   `[b0, a0, b1, a1]` (codes 0–3) and `[b2, a2, –, –]` (codes 4, 5);
//! - the nine edge–edge candidates are three registers: edge `i` of a in
//!   every lane against b's edges `[0, 1, 2, –]` (codes `6 + 3i + j`).
//!
//! Each lane runs the operations the sequential pass runs for its candidate
//! (the same generic code, [`FacePlane`], [`point_face_interior`],
//! [`segment_segment_lanes`], on the [`Ymm`] lane type), and the reduction
//! takes the least, the first candidate in the sequential order attaining it
//! and the least of the others, as [`Best`] does: the result is the
//! sequential pass's bit for bit (the unit test below compares every field
//! on every input class and on exact ties;
//! `tests/kernels/batch_matches_scalar.rs` compares whole results at every level).
//! On one pair it is about twice as fast as the sequential pass, whose
//! scalar arithmetic leaves three of four lanes idle (`BENCHMARKS.md`).
//!
//! The module also holds the rest of the single pair's AVX2 front door
//! ([`triangle_distance`]: the pair's sizes four coordinates at a time) and
//! the refinement's tie path: the pass keeps every candidate in a
//! [`CandidateTable`] as it goes, which the tie path reads.
//!
//! `Ymm` wraps the AVX2 intrinsics. It is private to this module and only
//! created inside its `#[target_feature(enable = "avx2,fma")]` functions,
//! which are only called where the CPU has both (the caller checks
//! [`SimdLevel`](super::SimdLevel)).

use super::lanes::{Lane, V3};
use super::point_triangle::{point_face_interior, FacePlane};
use super::refine::{refined_distance_of, CandidateSource, LeastRefined};
use super::segment_segment::{segment_segment_lanes, Edge};
use super::separated::{certify, Best, Candidate, CandidateSink, ClosestSeparated};
use super::triangle_triangle::{normalised_triangle_distance, PairPass, PairSizes, TriangleDistance};
use super::ymm::{constants, Ymm, YmmMask};
use crate::math::{Real, Triangle};
use std::arch::x86_64::*;

/// Lanes `[p0, p1, p2, p3]`.
#[inline(always)]
fn gather(p: [&V3<Real>; 4]) -> V3<Ymm> {
    // SAFETY: see above.
    unsafe {
        V3::new(
            Ymm(_mm256_setr_pd(p[0].x, p[1].x, p[2].x, p[3].x)),
            Ymm(_mm256_setr_pd(p[0].y, p[1].y, p[2].y, p[3].y)),
            Ymm(_mm256_setr_pd(p[0].z, p[1].z, p[2].z, p[3].z)),
        )
    }
}

/// Lane `k` of a vector.
#[inline(always)]
fn lane_of(v: &V3<Ymm>, k: usize) -> V3<Real> {
    V3::new(v.x.lanes()[k], v.y.lanes()[k], v.z.lanes()[k])
}

/// Edge lane `K` in every lane (`PERMUTATION = 0x55 · K`).
#[inline(always)]
fn broadcast_edge<const PERMUTATION: i32>(e: &Edge<Ymm>) -> Edge<Ymm> {
    Edge {
        start: broadcast_vector::<PERMUTATION>(&e.start),
        direction: broadcast_vector::<PERMUTATION>(&e.direction),
        length_squared: e.length_squared.broadcast::<PERMUTATION>(),
        inverse_length_squared: e.inverse_length_squared.broadcast::<PERMUTATION>(),
    }
}

/// Vector lane `K` in every lane (`PERMUTATION = 0x55 · K`).
#[inline(always)]
fn broadcast_vector<const PERMUTATION: i32>(v: &V3<Ymm>) -> V3<Ymm> {
    V3::new(v.x.broadcast::<PERMUTATION>(), v.y.broadcast::<PERMUTATION>(), v.z.broadcast::<PERMUTATION>())
}

/// A group of candidates in lanes: lane `k` is candidate `code[k]` where
/// `used[k]` (the other lanes repeat one).
#[derive(Copy, Clone)]
struct LaneGroup {
    /// Which group (0 to 4).
    index: usize,
    /// The squared distances.
    squared: Ymm,
    used: YmmMask,
    code: Ymm,
    /// The edge parameters and the separation (from a to b).
    s: Ymm,
    t: Ymm,
    separation: V3<Ymm>,
}

/// Receives the candidates of [`visit_groups`] a group of lanes at a time.
trait GroupSink {
    /// Takes a group.
    fn group(&mut self, group: LaneGroup);
}

/// Feeds the 15 candidates of triangles `a`, `b` (local coordinates) to
/// `sink` in five groups of lanes, in the sequential order of their codes:
/// codes 0–3, 4–5, 6–8, 9–11, 12–14. Always inlined into this module's
/// AVX2 functions (no closures: one this size is not inlined, and out of
/// line its arguments go through memory).
#[inline(always)]
fn visit_groups(a: &[V3<Real>; 3], b: &[V3<Real>; 3], sink: &mut impl GroupSink) {
    let [a0, a1, a2] = a;
    let [b0, b1, b2] = b;
    let zero = Ymm::splat(0.0);
    // Vertex over face: both planes at once, in lanes [a, b, a, b]. The
    // separation of a vertex of a over b's face (odd lanes, odd codes) is
    // the opposite of its offset.
    let faces =
        FacePlane::new(&[gather([a0, b0, a0, b0]), gather([a1, b1, a1, b1]), gather([a2, b2, a2, b2])]);
    let (squared, offset) = point_face_interior(&gather([b0, a0, b1, a1]), &faces);
    sink.group(LaneGroup {
        index: 0,
        squared,
        used: lane_mask([true; 4]),
        code: constants(0.0, 1.0, 2.0, 3.0),
        s: zero,
        t: zero,
        separation: towards_b(offset),
    });
    let (squared, offset) = point_face_interior(&gather([b2, a2, b2, a2]), &faces);
    sink.group(LaneGroup {
        index: 1,
        squared,
        used: lane_mask([true, true, false, false]),
        code: constants(4.0, 5.0, 4.0, 5.0),
        s: zero,
        t: zero,
        separation: towards_b(offset),
    });
    // Edge against edge: lane j is edge i of a against edge j of b (code 6 + 3i + j).
    let edges_a = Edge::new(&gather([a0, a1, a2, a0]), &gather([a1, a2, a0, a1]));
    let edges_b = Edge::new(&gather([b0, b1, b2, b0]), &gather([b1, b2, b0, b1]));
    edge_group(2, &broadcast_edge::<0x00>(&edges_a), &edges_b, sink);
    edge_group(3, &broadcast_edge::<0x55>(&edges_a), &edges_b, sink);
    edge_group(4, &broadcast_edge::<0xAA>(&edges_a), &edges_b, sink);
}

/// Edge `index - 2` of a (in every lane) against b's edges `[0, 1, 2, –]`:
/// codes `3 · index + j`.
#[inline(always)]
fn edge_group(index: usize, edge_a: &Edge<Ymm>, edges_b: &Edge<Ymm>, sink: &mut impl GroupSink) {
    let found = segment_segment_lanes(edge_a, edges_b);
    let first = (3 * index) as Real;
    sink.group(LaneGroup {
        index,
        squared: found.distance_squared,
        used: lane_mask([true, true, true, false]),
        code: constants(first, first + 1.0, first + 2.0, first + 2.0),
        s: found.s,
        t: found.t,
        separation: -found.gap,
    });
}

/// A vertex's offset from its projection, as the separation from a to b:
/// the opposite in the odd lanes (vertices of a over b's face).
#[inline(always)]
fn towards_b(offset: V3<Ymm>) -> V3<Ymm> {
    let flip = constants(0.0, -0.0, 0.0, -0.0);
    // SAFETY: see above.
    unsafe {
        V3::new(
            Ymm(_mm256_xor_pd(offset.x.0, flip.0)),
            Ymm(_mm256_xor_pd(offset.y.0, flip.0)),
            Ymm(_mm256_xor_pd(offset.z.0, flip.0)),
        )
    }
}

/// The running least of each lane over the groups of candidates it holds
/// (visited in the sequential order), as [`Best`] keeps it for one pair:
/// within a lane the codes grow from group to group, so the lane's least
/// is its first least in the sequential order.
struct LaneBest {
    /// The least squared distance of each lane.
    squared: Ymm,
    /// The least of the lane's other candidates.
    runner_up: Ymm,
    /// The code of the candidate attaining the lane's least.
    code: Ymm,
    /// Its edge parameters and separation (from a to b).
    s: Ymm,
    t: Ymm,
    separation: V3<Ymm>,
}

impl GroupSink for LaneBest {
    /// The sequential pass never takes an infinite (inapplicable)
    /// candidate, nor does this.
    #[inline(always)]
    fn group(&mut self, group: LaneGroup) {
        let LaneGroup { squared, used, code, s, t, separation, .. } = group;
        let infinity = Ymm::splat(Real::INFINITY);
        let squared = Ymm::select(squared.lt(infinity) & used, squared, infinity);
        let better = squared.lt(self.squared);
        self.runner_up = Ymm::select(better, self.squared, squared.min(self.runner_up));
        self.squared = Ymm::select(better, squared, self.squared);
        self.code = Ymm::select(better, code, self.code);
        self.s = Ymm::select(better, s, self.s);
        self.t = Ymm::select(better, t, self.t);
        self.separation = V3::select(better, separation, self.separation);
    }
}

/// Hands each group to two sinks.
struct Both<'s, S: GroupSink, T: GroupSink>(&'s mut S, &'s mut T);

impl<S: GroupSink, T: GroupSink> GroupSink for Both<'_, S, T> {
    #[inline(always)]
    fn group(&mut self, group: LaneGroup) {
        self.1.group(group);
        self.0.group(group);
    }
}

/// Keeps nothing.
impl GroupSink for () {
    #[inline(always)]
    fn group(&mut self, _: LaneGroup) {}
}

/// Lanes `k` with `lanes[k]` set.
#[inline(always)]
fn lane_mask(lanes: [bool; 4]) -> YmmMask {
    let [w, x, y, z] = lanes;
    // SAFETY: see above.
    YmmMask(unsafe {
        _mm256_castsi256_pd(_mm256_setr_epi64x(-(w as i64), -(x as i64), -(y as i64), -(z as i64)))
    })
}

/// [`closest_separated`](super::separated::closest_separated) of one pair
/// (local coordinates), its candidates in lanes; the same result bit for bit.
#[cfg(test)]
#[target_feature(enable = "avx2,fma")]
fn closest_separated_pair(a: &[V3<Real>; 3], b: &[V3<Real>; 3]) -> ClosestSeparated<Real> {
    closest_separated_keeping(a, b, &mut ())
}

/// [`closest_separated_pair`], every group of candidates also handed to
/// `keep` (the single pair keeps them in a [`CandidateTable`] for the
/// refinement's tie path).
#[inline(always)]
fn closest_separated_keeping(
    a: &[V3<Real>; 3],
    b: &[V3<Real>; 3],
    keep: &mut impl GroupSink,
) -> ClosestSeparated<Real> {
    let zero = Ymm::splat(0.0);
    let infinity = Ymm::splat(Real::INFINITY);
    let mut best = LaneBest {
        squared: infinity,
        runner_up: infinity,
        code: zero,
        s: zero,
        t: zero,
        separation: V3::zeros(),
    };
    visit_groups(a, b, &mut Both(&mut best, keep));
    let least = best.squared.least();
    if least == Real::INFINITY {
        // No candidate: the sequential pass's starting state.
        return certify(a, b, &Best::empty());
    }
    // The first candidate in the sequential order attaining the least: the
    // least code among the lanes attaining it (lanes hold distinct codes).
    let attaining = best.squared.equal(Ymm::splat(least));
    let code = Ymm::select(attaining, best.code, infinity).least();
    let lane = Ymm::select(attaining, best.code, infinity).equal_bits(code).trailing_zeros() as usize;
    // The least of the others: the lane's own runner-up and the other lanes' least.
    let others = best.squared.knock_out(lane).least();
    let runner_up_squared = others.min(best.runner_up.lanes()[lane]);
    let winner = Best {
        distance_squared: least,
        runner_up_squared,
        candidate: code,
        s: best.s.lanes()[lane],
        t: best.t.lanes()[lane],
        separation: lane_of(&best.separation, lane),
    };
    certify(a, b, &winner)
}

/// Every candidate's squared distance and edge parameters, by group,
/// column (squared, s, t) and lane: what the refinement's tie path needs.
struct CandidateTable {
    groups: [[[Real; 4]; 3]; 5],
}

impl CandidateTable {
    /// How many lanes of each group hold candidates (`visit_groups`).
    const USED: [usize; 5] = [4, 2, 3, 3, 3];
}

impl Default for CandidateTable {
    #[inline(always)]
    fn default() -> CandidateTable {
        CandidateTable { groups: [[[0.0; 4]; 3]; 5] }
    }
}

impl GroupSink for CandidateTable {
    #[inline(always)]
    fn group(&mut self, group: LaneGroup) {
        for (column, value) in self.groups[group.index].iter_mut().zip([group.squared, group.s, group.t]) {
            // SAFETY: see above; the column holds four f64.
            unsafe { _mm256_storeu_pd(column.as_mut_ptr(), value.0) };
        }
    }
}

/// The table's candidates, in the sequential order of their codes.
impl CandidateSource for CandidateTable {
    #[inline(always)]
    fn visit(&self, _: &Triangle, _: &Triangle, sink: &mut LeastRefined) {
        let mut code = 0;
        for (&[squared, s, t], used) in self.groups.iter().zip(CandidateTable::USED) {
            for lane in 0..used {
                sink.consider(squared[lane], Candidate::decode(code), s[lane], t[lane], V3::zeros());
                code += 1;
            }
        }
    }
}

/// The single pair's refinement, its tie path reading the pass's table.
/// Out of line: about one pair in fifteen of the benchmark's needs it.
#[target_feature(enable = "avx2,fma")]
#[inline(never)]
fn refined_from_table(
    a: &Triangle,
    b: &Triangle,
    closest: &ClosestSeparated<Real>,
    table: &CandidateTable,
) -> Real {
    refined_distance_of(a, b, closest, table)
}

/// [`triangle_distance`](super::triangle_distance) with this module's pass.
#[target_feature(enable = "avx2,fma")]
pub(super) fn triangle_distance(a: &Triangle, b: &Triangle) -> TriangleDistance {
    normalised_triangle_distance::<InLanes>(a, b)
}

/// This module's [`PairPass`]. Private: only [`triangle_distance`], an
/// AVX2 + FMA function, runs it.
struct InLanes;

impl PairPass for InLanes {
    /// Every candidate, for the refinement's tie path: about nine in ten
    /// refined pairs take it (a vertex–edge winner is found again from the
    /// vertex's other edge), and the table costs the pass fifteen stores
    /// where recomputing the candidates cost a second pass.
    type Kept = CandidateTable;

    #[inline(always)]
    fn closest(a: &[V3<Real>; 3], b: &[V3<Real>; 3], table: &mut CandidateTable) -> ClosestSeparated<Real> {
        closest_separated_keeping(a, b, table)
    }

    #[inline(always)]
    fn refined(a: &Triangle, b: &Triangle, closest: &ClosestSeparated<Real>, table: &CandidateTable) -> Real {
        // SAFETY: see above (only run inside `triangle_distance`).
        unsafe { refined_from_table(a, b, closest, table) }
    }

    #[inline(always)]
    fn sizes(a: &Triangle, b: &Triangle) -> PairSizes {
        pair_sizes(a, b)
    }
}

/// A triangle's nine coordinates `c0..c8` (`x0 y0 z0 x1 …`) as four
/// overlapping loads: `c0..c3`, `c3..c6`, `c5..c8`, `c2..c5`.
#[inline(always)]
fn triangle_loads(t: &Triangle) -> [Ymm; 4] {
    const { assert!(std::mem::size_of::<Triangle>() == 9 * std::mem::size_of::<Real>()) };
    let c = t.as_ptr() as *const Real;
    // SAFETY: see above; a triangle is nine contiguous `f64` (nalgebra's
    // points are `repr(C)` arrays, size checked above), and every load
    // reads four of them from offset 0, 3, 5 or 2.
    unsafe {
        [
            Ymm(_mm256_loadu_pd(c)),
            Ymm(_mm256_loadu_pd(c.add(3))),
            Ymm(_mm256_loadu_pd(c.add(5))),
            Ymm(_mm256_loadu_pd(c.add(2))),
        ]
    }
}

/// The largest lane (no lane NaN).
#[inline(always)]
fn largest_lane(v: Ymm) -> Real {
    -(-v).least()
}

/// Lane magnitudes, NaN passed over (`vmaxpd` returns its second operand then).
#[inline(always)]
fn magnitude(v: Ymm) -> Ymm {
    v.abs().max(Ymm::splat(0.0))
}

/// A triangle's extent from its [`triangle_loads`]: `c3..c6 - c0..c3` is
/// edge 0 and x of edge 1; `c5..c8 - c2..c5` is z of edge 0 and edge 1;
/// `c5..c8 - (_, c0, c1, c2)` is edge 2 after a first lane set to 0. NaN
/// differences are passed over, as `triangle_extent` passes them.
#[inline(always)]
fn extent([t0, t1, t2, t3]: [Ymm; 4]) -> Real {
    // SAFETY: see above.
    let shifted = Ymm(unsafe { _mm256_permute4x64_pd::<0b10_01_00_00>(t0.0) });
    let edge_2 = Ymm::select(lane_mask([false, true, true, true]), t2 - shifted, Ymm::splat(0.0));
    largest_lane(magnitude(t1 - t0).max(magnitude(t2 - t3)).max(magnitude(edge_2)))
}

/// [`pair_sizes`](super::triangle_triangle::pair_sizes) four coordinates at
/// a time; the same values (maxima of the same magnitudes and differences).
#[inline(always)]
fn pair_sizes(a: &Triangle, b: &Triangle) -> PairSizes {
    let (of_a, of_b) = (triangle_loads(a), triangle_loads(b));
    let largest_a = magnitude(of_a[0]).max(magnitude(of_a[1])).max(magnitude(of_a[2]));
    let largest_b = magnitude(of_b[0]).max(magnitude(of_b[1])).max(magnitude(of_b[2]));
    PairSizes { largest: largest_lane(largest_a.max(largest_b)), extents: [extent(of_a), extent(of_b)] }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::kernels::lanes::V3;
    use crate::kernels::separated::{closest_separated, local_frame, triangle_lanes};
    use crate::kernels::SimdLevel;
    use crate::samples::{nearly_touching_pairs, tied_pairs, triangle_pairs, InputClass};

    /// Every field, as bits.
    fn bits(c: &ClosestSeparated<Real>) -> ([u64; 9], bool) {
        let fields =
            [c.best.distance_squared, c.best.runner_up_squared, c.best.candidate, c.best.s, c.best.t]
                .into_iter()
                .chain([c.best.separation.x, c.best.separation.y, c.best.separation.z, c.extent]);
        let mut out = [0; 9];
        for (o, f) in out.iter_mut().zip(fields) {
            *o = f.to_bits();
        }
        (out, c.certified)
    }

    /// Counts each group's lanes in use, as its mask says.
    struct UsedLanes([usize; 5]);

    impl GroupSink for UsedLanes {
        fn group(&mut self, group: LaneGroup) {
            // SAFETY: only run where the CPU has AVX2 (checked by the test).
            self.0[group.index] = unsafe { _mm256_movemask_pd(group.used.0) }.count_ones() as usize;
        }
    }

    #[target_feature(enable = "avx2,fma")]
    fn used_lanes(a: &[V3<Real>; 3], b: &[V3<Real>; 3]) -> [usize; 5] {
        let mut used = UsedLanes([0; 5]);
        visit_groups(a, b, &mut used);
        used.0
    }

    #[test]
    fn the_table_reads_the_lanes_the_groups_use() {
        if SimdLevel::detect() < SimdLevel::Avx2 {
            eprintln!("skipped: this CPU has no AVX2 + FMA, the pass in lanes never runs here");
            return;
        }
        let (a, b) = &triangle_pairs(InputClass::WellConditioned, 1, 3)[0];
        let (la, lb) = local_frame(&triangle_lanes(a), &triangle_lanes(b));
        // SAFETY: the CPU has AVX2 and FMA (checked above).
        let used = unsafe { used_lanes(&la, &lb) };
        assert_eq!(used, CandidateTable::USED);
        assert_eq!(used.iter().sum::<usize>(), 15);
    }

    #[test]
    fn the_pass_in_lanes_is_the_sequential_pass_bit_for_bit() {
        if SimdLevel::detect() < SimdLevel::Avx2 {
            eprintln!("skipped: this CPU has no AVX2 + FMA, the pass in lanes never runs here");
            return;
        }
        let mut pairs = tied_pairs();
        for class in InputClass::ALL {
            pairs.extend(triangle_pairs(class, 3000, 41));
        }
        pairs.extend(nearly_touching_pairs(3000, 1e-3, 1e-1, 2024));
        for (i, (a, b)) in pairs.iter().enumerate() {
            for (a, b) in [(a, b), (b, a)] {
                let (la, lb): ([V3<Real>; 3], [V3<Real>; 3]) =
                    local_frame(&triangle_lanes(a), &triangle_lanes(b));
                // SAFETY: the CPU has AVX2 and FMA (checked above).
                let in_lanes = unsafe { closest_separated_pair(&la, &lb) };
                assert_eq!(bits(&in_lanes), bits(&closest_separated(&la, &lb)), "pair {i}: {a:?} {b:?}");
            }
        }
    }
}

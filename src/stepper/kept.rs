//! The broad phase of many bodies, their boxes kept between steps.
//!
//! A grid of every body's swept box, made again at every step, costs about
//! what moving the bodies does, though between two steps a body moves a
//! small part of its size. So each body gets a kept box: a box that holds
//! its swept box as long as its centre stays within a slack of where it was
//! when the box was made ([`KEPT_SLACK_STEPS`] steps of its travel then, at
//! most [`KEPT_SLACK_RADII`] of its radius; a margin grown since, with the
//! body's distance from the origin, takes its share of the slack). A
//! turning body's kept box is the box of its bounding sphere about every
//! such centre; a body that does not turn keeps its own box at its rotation
//! then, and only while that rotation stays the same (bit for bit) and it
//! does not turn. The kept boxes go into a grid once, and their overlapping
//! pairs are kept.
//!
//! At each step, a body whose swept box is still within its kept box is
//! found by a few comparisons (its centre at the step's two ends against
//! its kept box shrunk by its reach and margin: no rotation). The
//! others ("escaped") get their swept box. The step's pairs are:
//!
//! - the kept pairs of two bodies that have not escaped, whose swept boxes
//!   overlap;
//! - each escaped body's swept box against the kept boxes in the grid of
//!   the bodies that have not escaped (then their swept boxes);
//! - the escaped bodies among themselves (a grid of their swept boxes).
//!
//! Two overlapping swept boxes are found whichever of their bodies escaped:
//! the pairs are those of brute force over every swept box, sorted (the
//! same as [`GridBroadPhase`] on them), and so are the same whatever the
//! threads. The kept boxes are made again when more than one body in
//! [`REBUILD_ESCAPED_DIVISOR`] has escaped. Bodies so fast that boxes
//! would not last [`KEPT_MIN_STEPS`] steps get none: the broad phase boxes
//! every body for [`KEPT_PAUSE_STEPS`] steps, then tries again.

use std::ops::Range;

use nalgebra::UnitQuaternion;

use super::broad::{BoxMargin, PARALLEL_BOX_BODIES};
use crate::broad_phase::{
    boxes_overlap, in_runs, run_length, swept_box, swept_reach, GridBroadPhase, SweptBox,
};
use crate::math::{Point, Real, Vector};
use crate::mesh::TriMesh;
use crate::motion::StepMotion;

/// A body's kept box allows its centre this many steps of its travel in
/// the step it was made: `16` (this and the next two constants measured
/// on the `many_bodies` box at 100,000 bodies against 8 and 32, 0.25 and
/// 1, 4 and 16: `docs/benchmarks-history.md`, session 40).
pub(crate) const KEPT_SLACK_STEPS: Real = 16.0;

/// ... and at most this part of its radius: `0.5` (a fast body escapes its
/// box and is boxed at each step rather than widening every cell).
pub(crate) const KEPT_SLACK_RADII: Real = 0.5;

/// The kept boxes are made again when more than one body in this many has
/// escaped its box: `8`.
pub(crate) const REBUILD_ESCAPED_DIVISOR: usize = 8;

/// Kept boxes that last fewer steps than this are not worth keeping: `4`
/// (fast bodies leave them at once; making them costs a little more than
/// boxing every body in a step, measured at 10 and 20 times
/// `many_bodies`' speeds: `docs/benchmarks-history.md`, session 40).
pub(crate) const KEPT_MIN_STEPS: u64 = 4;

/// ... and the broad phase then boxes every body at each step for this
/// many steps before it tries kept boxes again: `32` (not tuned).
pub(crate) const KEPT_PAUSE_STEPS: u64 = 32;

/// `Kept::turn` of a turning body (its kept box is its bounding sphere's).
const TURNING: u32 = u32::MAX;

/// A body's kept box, and whether it holds the body only at one rotation.
#[derive(Copy, Clone, Debug)]
struct Kept {
    fat: SweptBox,
    /// The body's radius (kept here so that the step's check reads nothing
    /// but this and the motion).
    radius: Real,
    /// [`TURNING`], or the index of its rotation in `KeptBoxes::turns`.
    turn: u32,
}

/// The rotation a kept box was made at, for a body that did not turn, and
/// the body's reach below and above its centre at that rotation.
#[derive(Copy, Clone, Debug)]
struct FixedTurn {
    rotation: UnitQuaternion<Real>,
    below: Vector,
    above: Vector,
}

/// How the broad phase sees the bodies: the step's motions, each body's
/// mesh, their boxes' margins and the step's length.
pub(super) struct Bodies<'a, M: Fn(usize) -> &'a TriMesh + Sync> {
    pub motions: &'a [StepMotion],
    pub mesh: M,
    pub margin: BoxMargin<'a>,
    pub dt: Real,
}

impl<'a, M: Fn(usize) -> &'a TriMesh + Sync> Bodies<'a, M> {
    /// Body `i`'s swept box.
    pub(super) fn swept(&self, i: usize) -> SweptBox {
        let (mesh, motion) = ((self.mesh)(i), &self.motions[i]);
        swept_box(mesh, motion, self.dt, self.margin.of(motion, mesh.radius(), self.dt))
    }
}

/// The kept boxes, their grid and pairs, and the step's buffers.
#[derive(Debug, Default)]
pub(crate) struct KeptBoxes {
    kept: Vec<Kept>,
    turns: Vec<FixedTurn>,
    grid: GridBroadPhase,
    /// The bodies in a kept pair, ascending, and the kept pairs as places
    /// in that list (so that a step boxes each of them once, in order).
    paired: Vec<u32>,
    kept_pairs: Vec<(u32, u32)>,
    /// The boxes of the bodies in `paired` at the current step (made
    /// without rotations, then swept where a pair needs them), whether a
    /// pair needs them, and the kept pairs whose first boxes overlap.
    paired_boxes: Vec<SweptBox>,
    needed: Vec<bool>,
    near_pairs: Vec<(usize, usize)>,
    /// Whether each body escaped in the current step (all false between
    /// steps).
    escaped: Vec<bool>,
    escapees: Vec<usize>,
    escapee_boxes: Vec<SweptBox>,
    escapee_grid: GridBroadPhase,
    escapee_pairs: Vec<(usize, usize)>,
    /// How many times the kept boxes were made, and how many bodies had
    /// escaped theirs in the last step (before any new build).
    pub(crate) builds: u64,
    pub(crate) escaped_last: usize,
    /// Steps since the kept boxes were made, and steps left in which they
    /// are not used (see [`KEPT_MIN_STEPS`]).
    lasted: u64,
    paused: u64,
}

impl KeptBoxes {
    /// The pairs `(i, j)`, `i < j`, sorted, of the bodies whose swept boxes
    /// over the step overlap, into `pairs` (cleared first); on rayon's
    /// threads when `threads` (the same pairs). False, and no pairs, when
    /// kept boxes are not worth keeping (see [`KEPT_MIN_STEPS`]): the
    /// caller then boxes every body.
    pub(super) fn pairs_into<'a, M: Fn(usize) -> &'a TriMesh + Sync>(
        &mut self,
        bodies: &Bodies<'a, M>,
        pairs: &mut Vec<(usize, usize)>,
        threads: bool,
    ) -> bool {
        pairs.clear();
        if self.paused > 0 {
            self.paused -= 1;
            return false;
        }
        let n = bodies.motions.len();
        let many = threads && n >= PARALLEL_BOX_BODIES;
        self.escapees.clear();
        // Whether the paired bodies' first boxes were made with the check.
        let mut first_boxes = false;
        if self.kept.len() == n {
            self.check(bodies, many);
            first_boxes = true;
        }
        self.escaped_last = self.escapees.len();
        self.lasted += 1;
        if self.kept.len() != n || self.escapees.len() * REBUILD_ESCAPED_DIVISOR > n {
            // Boxes that lasted too few steps, or bodies so fast that more
            // than one in eight would leave theirs within as few: none.
            let short = self.kept.len() == n && self.lasted < KEPT_MIN_STEPS;
            if short || too_fast(bodies, many) {
                self.paused = KEPT_PAUSE_STEPS;
                return false;
            }
            self.build(bodies, many);
            self.escapees.clear();
            self.lasted = 0;
            first_boxes = false;
        }
        let escaped = &mut self.escaped;
        for &e in &self.escapees {
            escaped[e] = true;
        }
        let escaped = &*escaped;
        // The kept pairs of bodies within their kept boxes: first on the
        // boxes made without rotations, then on the swept boxes of the
        // bodies in a pair that passed (each body boxed once, in order).
        let (kept, turns, paired) = (&self.kept, &self.turns, &self.paired);
        let threads_for = |count: usize| threads && count >= PARALLEL_BOX_BODIES;
        let boxes = &mut self.paired_boxes;
        if !first_boxes {
            // Just made: every body is within its kept box.
            let first = |&i: &u32| bound(&kept[i as usize], turns, &bodies.motions[i as usize], bodies);
            let first = |i: &u32| first(i).unwrap_or_else(outside);
            if threads_for(paired.len()) {
                use rayon::prelude::*;
                paired.par_iter().map(first).collect_into_vec(boxes);
            } else {
                boxes.clear();
                boxes.extend(paired.iter().map(first));
            }
        }
        let (near, kept_pairs, rough_boxes) = (&mut self.near_pairs, &self.kept_pairs, &*boxes);
        near.clear();
        in_runs(kept_pairs.len(), threads_for(kept_pairs.len()), near, |range, out| {
            out.extend(kept_pairs[range].iter().filter_map(|&(a, b)| {
                let (a, b) = (a as usize, b as usize);
                boxes_overlap(&rough_boxes[a], &rough_boxes[b]).then_some((a, b))
            }));
        });
        let needed = &mut self.needed;
        needed.clear();
        needed.resize(paired.len(), false);
        for &(a, b) in near.iter() {
            (needed[a], needed[b]) = (true, true);
        }
        let refine = |(a, swept): (usize, &mut SweptBox)| {
            if needed[a] {
                *swept = bodies.swept(paired[a] as usize);
            }
        };
        if threads_for(paired.len()) {
            use rayon::prelude::*;
            boxes.par_iter_mut().enumerate().for_each(refine);
        } else {
            boxes.iter_mut().enumerate().for_each(refine);
        }
        let boxes = &*boxes;
        in_runs(near.len(), threads_for(near.len()), pairs, |range, out| {
            let meet = near[range].iter().filter(|&&(a, b)| boxes_overlap(&boxes[a], &boxes[b]));
            out.extend(meet.map(|&(a, b)| (paired[a] as usize, paired[b] as usize)));
        });
        if !self.escapees.is_empty() {
            self.escapee_boxes.clear();
            self.escapee_boxes.extend(self.escapees.iter().map(|&e| bodies.swept(e)));
            // Each escaped body against the others' kept boxes (each pair
            // found from its escaped body).
            let (grid, escapees, boxes) = (&self.grid, &self.escapees, &self.escapee_boxes);
            let count = escapees.len();
            in_runs(count, threads_for(count), pairs, |range, out| {
                for k in range {
                    let (e, swept) = (escapees[k], &boxes[k]);
                    grid.overlapping(swept, |j| {
                        if !escaped[j] && boxes_overlap(swept, &bodies.swept(j)) {
                            out.push((e.min(j), e.max(j)));
                        }
                    });
                }
            });
            // The escaped bodies among themselves.
            self.escapee_grid.pairs_into_on(boxes, &mut self.escapee_pairs, many);
            pairs.extend(self.escapee_pairs.iter().map(|&(a, b)| {
                let (i, j) = (escapees[a], escapees[b]);
                (i.min(j), i.max(j))
            }));
            pairs.sort_unstable();
            for &e in escapees {
                self.escaped[e] = false;
            }
        }
        true
    }

    /// Each body's first box (its [`bound`]) against its kept box, in one
    /// pass over the bodies: the bodies that escaped go to `escapees` (in
    /// order), and the first box of each paired body to its place in
    /// `paired_boxes` (an empty box for one that escaped: it meets none).
    /// On rayon's threads when `many`, as runs of bodies, each with the
    /// places of its paired bodies (the same boxes and escapees).
    fn check<'a, M: Fn(usize) -> &'a TriMesh + Sync>(&mut self, bodies: &Bodies<'a, M>, many: bool) {
        let (kept, turns, paired) = (&self.kept, &self.turns, &self.paired);
        let n = kept.len();
        let check = |range: Range<usize>, ids: &[u32], boxes: &mut [SweptBox], escapees: &mut Vec<usize>| {
            let mut place = 0;
            for i in range {
                let first =
                    bound(&kept[i], turns, &bodies.motions[i], bodies).filter(|b| within(b, &kept[i].fat));
                if first.is_none() {
                    escapees.push(i);
                }
                if ids.get(place) == Some(&(i as u32)) {
                    boxes[place] = first.unwrap_or_else(outside);
                    place += 1;
                }
            }
        };
        self.paired_boxes.resize(paired.len(), outside());
        if !many {
            check(0..n, paired, &mut self.paired_boxes, &mut self.escapees);
            return;
        }
        // Runs of bodies as `in_runs` makes them.
        let run = run_length(n);
        let mut runs = Vec::with_capacity(n.div_ceil(run));
        let (mut boxes, mut placed) = (&mut self.paired_boxes[..], 0);
        for start in (0..n).step_by(run) {
            let range = start..(start + run).min(n);
            let end = paired.partition_point(|&p| (p as usize) < range.end);
            let (these, rest) = boxes.split_at_mut(end - placed);
            runs.push((range, &paired[placed..end], these));
            (boxes, placed) = (rest, end);
        }
        use rayon::prelude::*;
        let found: Vec<Vec<usize>> = runs
            .into_par_iter()
            .map(|(range, ids, boxes)| {
                let mut escapees = Vec::new();
                check(range, ids, boxes, &mut escapees);
                escapees
            })
            .collect();
        found.iter().for_each(|part| self.escapees.extend_from_slice(part));
    }

    /// Makes every body's kept box, their grid and their pairs.
    fn build<'a, M: Fn(usize) -> &'a TriMesh + Sync>(&mut self, bodies: &Bodies<'a, M>, many: bool) {
        self.builds += 1;
        let (n, dt) = (bodies.motions.len(), bodies.dt);
        let make = |i: usize| {
            let (mesh, motion) = ((bodies.mesh)(i), &bodies.motions[i]);
            let radius = mesh.radius();
            let margin = bodies.margin.of(motion, radius, dt);
            let (start, end) = (motion.center_at(0.0), motion.center_at(dt));
            let (low, high) = (start.inf(&end), start.sup(&end));
            let slack = (KEPT_SLACK_STEPS * (end - start).norm()).min(KEPT_SLACK_RADII * radius);
            let turning = motion.angular_velocity != Vector::zeros();
            let (below, above) = match turning {
                true => (Vector::repeat(radius), Vector::repeat(radius)),
                false => swept_reach(mesh, &motion.rotation_at(0.0), &motion.angular_velocity, dt),
            };
            let fat_low = Point::from(Vector::from_fn(|k, _| (low[k] - slack) - (below[k] + margin)));
            let fat_high = Point::from(Vector::from_fn(|k, _| (high[k] + slack) + (above[k] + margin)));
            Kept { fat: (fat_low, fat_high), radius, turn: if turning { TURNING } else { 0 } }
        };
        if many {
            use rayon::prelude::*;
            (0..n).into_par_iter().map(make).collect_into_vec(&mut self.kept);
        } else {
            self.kept.clear();
            self.kept.extend((0..n).map(make));
        }
        // Each body that does not turn keeps its rotation and its reach.
        self.turns.clear();
        for (i, kept) in self.kept.iter_mut().enumerate() {
            if kept.turn != TURNING {
                let (mesh, motion) = ((bodies.mesh)(i), &bodies.motions[i]);
                let rotation = motion.rotation_at(0.0);
                let (below, above) = swept_reach(mesh, &rotation, &motion.angular_velocity, dt);
                kept.turn = self.turns.len() as u32;
                self.turns.push(FixedTurn { rotation, below, above });
            }
        }
        let kept = &self.kept;
        let mut pairs = std::mem::take(&mut self.escapee_pairs);
        self.grid.pairs_of_into_on(n, |i| kept[i].fat, &mut pairs, many);
        // The bodies in a pair, and the pairs as places among them (in the
        // same order: the places grow with the bodies).
        self.paired.clear();
        self.paired.extend(pairs.iter().flat_map(|&(i, j)| [i as u32, j as u32]));
        self.paired.sort_unstable();
        self.paired.dedup();
        let paired = &self.paired;
        let place = |i: usize| paired.binary_search(&(i as u32)).expect("a paired body") as u32;
        self.kept_pairs.clear();
        self.kept_pairs.extend(pairs.iter().map(|&(i, j)| (place(i), place(j))));
        self.escapee_pairs = pairs;
        self.escaped.clear();
        self.escaped.resize(n, false);
    }
}

/// A box around the swept box of the body with this motion over the
/// step, made without its rotation: its centre's box over the step grown
/// by its reach (its radius when it turns) and margin, as [`swept_box`]
/// grows it (the same operations, so that it holds the swept box to the
/// last bit). `None` for a body kept at one rotation that has turned.
#[inline]
fn bound<'a, M: Fn(usize) -> &'a TriMesh + Sync>(
    kept: &Kept,
    turns: &[FixedTurn],
    motion: &StepMotion,
    bodies: &Bodies<'a, M>,
) -> Option<SweptBox> {
    let margin = bodies.margin.of(motion, kept.radius, bodies.dt);
    let (start, end) = (motion.center_at(0.0), motion.center_at(bodies.dt));
    let (low, high) = (start.inf(&end), start.sup(&end));
    let grown = |below: &Vector, above: &Vector| {
        let low = Point::from(Vector::from_fn(|k, _| low[k] - (below[k] + margin)));
        let high = Point::from(Vector::from_fn(|k, _| high[k] + (above[k] + margin)));
        Some((low, high))
    };
    match kept.turn {
        TURNING => {
            let radius = Vector::repeat(kept.radius);
            grown(&radius, &radius)
        }
        t => {
            let turn = &turns[t as usize];
            let same = motion.angular_velocity == Vector::zeros()
                && motion.rotation_at(0.0).coords == turn.rotation.coords;
            if same {
                grown(&turn.below, &turn.above)
            } else {
                None
            }
        }
    }
}

/// Whether more than one body in [`REBUILD_ESCAPED_DIVISOR`] would leave
/// its kept box within [`KEPT_MIN_STEPS`] steps at its present speed (its
/// slack, at most [`KEPT_SLACK_RADII`] of its radius, is less than that
/// many steps of its travel).
fn too_fast<'a, M: Fn(usize) -> &'a TriMesh + Sync>(bodies: &Bodies<'a, M>, many: bool) -> bool {
    let n = bodies.motions.len();
    let fast = |i: usize| {
        let travel = (bodies.motions[i].velocity * bodies.dt).norm();
        KEPT_MIN_STEPS as Real * travel > KEPT_SLACK_RADII * (bodies.mesh)(i).radius()
    };
    let count = match many {
        true => {
            use rayon::prelude::*;
            (0..n).into_par_iter().filter(|&i| fast(i)).count()
        }
        false => (0..n).filter(|&i| fast(i)).count(),
    };
    count * REBUILD_ESCAPED_DIVISOR > n
}

/// Whether the first box is within the second.
#[inline]
fn within((low, high): &SweptBox, (outer_low, outer_high): &SweptBox) -> bool {
    (0..3).all(|k| low[k] >= outer_low[k] && high[k] <= outer_high[k])
}

/// The empty box (it meets no box).
fn outside() -> SweptBox {
    (Point::from([Real::INFINITY; 3]), Point::from([Real::NEG_INFINITY; 3]))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::broad_phase::brute_force_pairs;
    use crate::ccd::CcdOptions;
    use crate::math::Pose;
    use crate::samples::Rng;

    /// Bodies moving through a room over many steps, changing their
    /// velocities now and then (a bounce), some turning, some not, some
    /// still, rods that stop turning after a turn (their rotation changed
    /// while they do not turn), a few that jump: at every step the kept
    /// boxes give the pairs of brute force over the step's swept boxes,
    /// on one thread and on the threads alike, through escapes and new
    /// builds.
    #[test]
    fn kept_boxes_give_the_pairs_of_brute_force_at_every_step() {
        let meshes = [
            crate::mesh::icosphere(0.6, 1).expect("an icosphere"),
            crate::mesh::box_mesh(&Vector::new(0.8, 0.05, 0.05)).expect("a rod"),
            crate::mesh::box_mesh(&Vector::new(0.4, 0.5, 0.2)).expect("a box"),
        ];
        let n = 5000;
        let dt = 1.0 / 60.0;
        let side = 14.0;
        let mut rng = Rng::new(83);
        let random_velocity = |rng: &mut Rng| rng.in_unit_ball() * 3.0;
        let mut poses: Vec<Pose> =
            (0..n).map(|_| Pose::new(rng.in_unit_ball() * side, rng.in_unit_ball() * 3.0)).collect();
        // Kind: 0 turning, 1 not turning, 2 still; rods (mesh 1) turn now
        // and then and stop again.
        let kinds: Vec<usize> = (0..n).map(|i| [0, 0, 1, 2][i % 4]).collect();
        let mut velocities: Vec<Vector> =
            (0..n).map(|i| if kinds[i] == 2 { Vector::zeros() } else { random_velocity(&mut rng) }).collect();
        let mut spins: Vec<Vector> =
            (0..n).map(|i| if kinds[i] == 0 { rng.in_unit_ball() * 8.0 } else { Vector::zeros() }).collect();
        let ccd = CcdOptions::default();
        let margin = BoxMargin { ccd: &ccd, extra: 1e-3, rounding: 4.0 * Real::EPSILON };
        let (mut single, mut threaded) = (KeptBoxes::default(), KeptBoxes::default());
        let (mut escapes, mut turned_rods) = (0, 0);
        for step in 0..40 {
            let motions: Vec<StepMotion> =
                (0..n).map(|i| StepMotion::new(poses[i], velocities[i], spins[i])).collect();
            let bodies = Bodies { motions: &motions, mesh: |i: usize| &meshes[i % 3], margin, dt };
            let boxes: Vec<SweptBox> = (0..n).map(|i| bodies.swept(i)).collect();
            let expected = brute_force_pairs(&boxes);
            for (kept, threads) in [(&mut single, false), (&mut threaded, true)] {
                let mut pairs = vec![(7, 7)];
                assert!(kept.pairs_into(&bodies, &mut pairs, threads), "step {step}: kept boxes in use");
                assert_eq!(pairs, expected, "step {step}, threads {threads}");
            }
            escapes += single.escaped_last;
            // The step's end is the next step's start; some bodies bounce,
            // jump or start or stop turning.
            for i in 0..n {
                poses[i] = motions[i].pose_at(dt);
                let roll = rng.range(0.0, 1.0);
                if kinds[i] != 2 && roll < 0.05 {
                    velocities[i] = random_velocity(&mut rng);
                }
                if i % 48 == 10 {
                    // A rod that does not turn (kind 1, mesh 1) turns a
                    // quarter turn in one step in ten (too few at once to
                    // make the boxes again).
                    let turn = step % 10 == 3;
                    let quarter = Vector::new(0.0, 0.0, std::f64::consts::FRAC_PI_2 / dt);
                    spins[i] = if turn { quarter } else { Vector::zeros() };
                    turned_rods += usize::from(turn);
                }
                if roll > 0.999 {
                    poses[i].translation.vector = rng.in_unit_ball() * side;
                }
            }
        }
        assert!(
            single.builds > 2 && escapes > 1000 && turned_rods > 0,
            "{} builds, {escapes} escapes",
            single.builds
        );
        assert!(threaded.builds == single.builds);
    }

    /// A rod that does not turn keeps its box at its rotation; when it has
    /// turned a quarter turn in one step and stopped, its box is made again
    /// (its rotation is not the one kept), and a ball beside its new
    /// length is paired with it at that step and the next.
    #[test]
    fn a_rod_that_turned_and_stopped_is_boxed_at_its_new_rotation() {
        let rod = crate::mesh::box_mesh(&Vector::new(0.8, 0.05, 0.05)).expect("a rod");
        let ball = crate::mesh::icosphere(0.1, 1).expect("a ball");
        let dt = 0.01;
        let ccd = CcdOptions::default();
        let margin = BoxMargin { ccd: &ccd, extra: 0.0, rounding: 4.0 * Real::EPSILON };
        // The rod at the origin along x, the ball above it at y = 0.7, and
        // 98 balls far away in a row.
        let mut poses = vec![Pose::identity(), Pose::new(Vector::new(0.0, 0.7, 0.0), Vector::zeros())];
        poses.extend((0..98).map(|k| Pose::new(Vector::new(10.0 + k as Real, 0.0, 0.0), Vector::zeros())));
        let quarter = Vector::new(0.0, 0.0, std::f64::consts::FRAC_PI_2 / dt);
        let mut kept = KeptBoxes::default();
        for (step, spin) in
            [Vector::zeros(), quarter, Vector::zeros(), Vector::zeros()].into_iter().enumerate()
        {
            let mut motions: Vec<StepMotion> = poses.iter().map(|&pose| StepMotion::fixed(pose)).collect();
            motions[0].angular_velocity = spin;
            let mesh = |i: usize| if i == 0 { &rod } else { &ball };
            let bodies = Bodies { motions: &motions, mesh, margin, dt };
            let mut pairs = Vec::new();
            assert!(kept.pairs_into(&bodies, &mut pairs, false));
            let expected = if step == 0 { vec![] } else { vec![(0, 1)] };
            assert_eq!(pairs, expected, "step {step}");
            poses[0] = motions[0].pose_at(dt);
        }
        assert_eq!(kept.builds, 1, "one body in a hundred escaping makes no new build");
    }

    /// Bodies so fast that they would leave their kept boxes within a few
    /// steps get none: the kept boxes give no pairs (the caller boxes every
    /// body) for `KEPT_PAUSE_STEPS` steps, then try again; slowed down,
    /// they are kept.
    #[test]
    fn fast_bodies_are_boxed_at_every_step_instead() {
        let ball = crate::mesh::icosphere(0.2, 1).expect("a ball");
        let dt = 0.01;
        let ccd = CcdOptions::default();
        let margin = BoxMargin { ccd: &ccd, extra: 0.0, rounding: 4.0 * Real::EPSILON };
        let poses: Vec<Pose> =
            (0..64).map(|k| Pose::new(Vector::new(k as Real, 0.0, 0.0), Vector::zeros())).collect();
        // 4 steps of travel against half the radius: 0.1 / 4 per step.
        let motions = |speed: Real| -> Vec<StepMotion> {
            poses
                .iter()
                .map(|&pose| StepMotion::new(pose, Vector::new(0.0, speed, 0.0), Vector::zeros()))
                .collect()
        };
        let (fast, slow) = (motions(0.026 / dt), motions(0.024 / dt));
        let mut kept = KeptBoxes::default();
        let mut pairs = vec![(7, 7)];
        for step in 0..=KEPT_PAUSE_STEPS {
            let bodies = Bodies { motions: &fast, mesh: |_| &ball, margin, dt };
            assert!(!kept.pairs_into(&bodies, &mut pairs, false), "step {step}");
            assert!(pairs.is_empty() && kept.builds == 0);
        }
        let bodies = Bodies { motions: &fast, mesh: |_| &ball, margin, dt };
        assert!(!kept.pairs_into(&bodies, &mut pairs, false), "still too fast after the pause");
        for _ in 0..KEPT_PAUSE_STEPS {
            assert!(!kept.pairs_into(&bodies, &mut pairs, false));
        }
        let bodies = Bodies { motions: &slow, mesh: |_| &ball, margin, dt };
        assert!(kept.pairs_into(&bodies, &mut pairs, false), "slower, the boxes are kept");
        assert_eq!(kept.builds, 1);
    }
}

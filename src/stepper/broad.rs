//! Stage 2, broad phase: the pairs whose swept boxes overlap in the step
//! (scenes of more than two bodies; with two, the one pair is kept from
//! the start). In a run of many bodies that stay put (fixed, or free and
//! at rest: [`FIXED_APART_BODIES`]), their boxes are made once and kept in
//! a static grid; each step boxes the moving bodies only. Otherwise, from
//! `RunOptions::kept_boxes_bodies` bodies, each body's box is kept between
//! steps and made again only when the body leaves it (`kept.rs`). Each
//! pair keeps its state from the previous step; a new pair starts fresh. A pair in
//! contact stays in the set until the re-arm stage finds it separated
//! (farther apart than its re-arm distance), whether or not its boxes
//! still overlap: boxes that fit the meshes part as soon as the meshes are
//! a contact distance apart, and a resting pair must not be re-armed by
//! that.

use std::sync::Arc;
use std::time::Instant;

use super::kept::{Bodies, KeptBoxes};
use super::world::{PairState, World};
use super::Stepper;
use crate::broad_phase::{StaticBoxes, SweptBox};
use crate::ccd::{box_margin, CcdOptions};
use crate::math::Real;
use crate::motion::StepMotion;
use crate::scene::{BodyMotion, Model};

/// The swept boxes are computed, and parry's tree of them refitted and
/// traversed (or, for many bodies, the grid's cells searched), on rayon's
/// threads from this many bodies (when the run is parallel): `4096` (a box
/// takes tens of nanoseconds, fewer are not worth handing out).
pub(crate) const PARALLEL_BOX_BODIES: usize = 4096;

/// A run keeps its bodies that stay put ([`Body::stays_put`]: fixed, or
/// free and at rest) apart from the broad phase's steps from this many of
/// them: `64`. Their boxes go into a static grid once, and each step boxes
/// and pairs only the moving bodies (against each other, and each against
/// that grid). With a few such bodies (a room's walls) the step's grid or
/// refitted tree handles them as cheaply.
///
/// [`Body::stays_put`]: crate::scene::Body::stays_put
pub(crate) const FIXED_APART_BODIES: usize = 64;

/// The bodies that stay put in a run that keeps them apart (see
/// [`FIXED_APART_BODIES`]): they never move in the stepper's own
/// integration, so their boxes are made once.
pub(crate) struct FixedApart {
    /// The bodies that stay put and the others, by index, ascending.
    still: Vec<usize>,
    moving: Vec<usize>,
    /// Their boxes in a grid, made at the first step.
    statics: Option<StaticBoxes>,
    /// The pairs among them that are queried all the same (not both fixed:
    /// a body at rest touching another is a contact), as body indices,
    /// found in the grid at the first step.
    still_pairs: Option<Vec<(usize, usize)>>,
    /// The moving bodies' pairs (indices into `moving`) and their pairs
    /// with the still ones (into `moving`, into `still`).
    among: Vec<(usize, usize)>,
    across: Vec<(usize, usize)>,
}

impl FixedApart {
    /// For a model with at least [`FIXED_APART_BODIES`] bodies that stay
    /// put.
    pub(crate) fn of(model: &Model) -> Option<FixedApart> {
        let (still, moving): (Vec<usize>, Vec<usize>) =
            (0..model.bodies.len()).partition(|&i| model.bodies[i].stays_put());
        (still.len() >= FIXED_APART_BODIES).then(|| FixedApart {
            still,
            moving,
            statics: None,
            still_pairs: None,
            among: Vec::new(),
            across: Vec::new(),
        })
    }
}

/// The margin of a body's swept box: at least its share of any pair's
/// contact distance (the contract's box margin), the run's `extra` margin,
/// and `rounding` times how far the body reaches from the origin over the
/// step.
#[derive(Copy, Clone)]
pub(super) struct BoxMargin<'a> {
    pub ccd: &'a CcdOptions,
    pub extra: Real,
    pub rounding: Real,
}

impl BoxMargin<'_> {
    /// The margin of a body of this radius with this motion over a step of
    /// length `dt`.
    #[inline]
    pub(super) fn of(&self, motion: &StepMotion, radius: Real, dt: Real) -> Real {
        let reach = motion.center_at(0.0).coords.amax() + motion.travel(dt) + radius;
        box_margin(self.ccd, radius) + self.extra + self.rounding * reach
    }
}

impl Stepper {
    /// Replaces `world.pairs` by the pairs of this step's swept boxes.
    pub(super) fn broad_phase(&mut self, world: &mut World) {
        let clock = Instant::now();
        if let (Some(broad), Some(body_meshes)) = (self.broad.as_mut(), self.body_meshes.as_ref()) {
            let model = Arc::clone(&self.model);
            let model = &*model;
            let boxes = &mut self.scratch.boxes;
            let extra_box_margin = self.extra_box_margin;
            let margin = BoxMargin {
                ccd: &model.ccd,
                extra: extra_box_margin,
                rounding: model.parameters.broad_phase_rounding_ulps * Real::EPSILON,
            };
            let mesh = |i: usize| body_meshes.of_body(i);
            let bodies = Bodies { motions: &world.motions, mesh, margin, dt: model.dt };
            let swept = |i: usize| bodies.swept(i);
            // The boxes of the bodies `only` lists (all of them for `None`),
            // each its own: on the threads when there are many (and the
            // tree's refit and traversal with them).
            let parallel = self.options.parallel;
            let boxes_of = |only: Option<&[usize]>, boxes: &mut Vec<SweptBox>| {
                let count = only.map_or(model.bodies.len(), <[usize]>::len);
                let body = |k: usize| only.map_or(k, |ids| ids[k]);
                let threads = parallel && count >= PARALLEL_BOX_BODIES;
                if threads {
                    use rayon::prelude::*;
                    (0..count).into_par_iter().map(|k| swept(body(k))).collect_into_vec(boxes);
                } else {
                    boxes.clear();
                    boxes.extend((0..count).map(|k| swept(body(k))));
                }
                threads
            };
            let candidates = &mut self.scratch.candidates;
            let fixed = |i: usize| model.bodies[i].motion == BodyMotion::Fixed;
            if let Some(apart) = self.fixed_apart.as_mut() {
                // The still bodies' boxes once, and their pairs that are
                // queried (not both fixed); the moving bodies' boxes each
                // step, paired among themselves and against the still ones.
                let statics = apart.statics.get_or_insert_with(|| {
                    let boxes: Vec<SweptBox> = apart.still.iter().map(|&i| swept(i)).collect();
                    StaticBoxes::new(&boxes)
                });
                if apart.still_pairs.is_none() {
                    let still = &apart.still;
                    let pairs = statics.pairs_among(|i, j| !(fixed(still[i]) && fixed(still[j])));
                    apart.still_pairs = Some(pairs.iter().map(|&(i, j)| (still[i], still[j])).collect());
                }
                let moving = &apart.moving;
                let threads = boxes_of(Some(moving), boxes);
                broad.pairs_into_on(boxes, &mut apart.among, threads);
                statics.overlaps_into_on(boxes, &mut apart.across, threads);
                let still = &apart.still;
                candidates.clear();
                candidates.extend(apart.among.iter().map(|&(i, j)| (moving[i], moving[j])));
                candidates.extend(apart.across.iter().map(|&(k, s)| {
                    let (m, f) = (moving[k], still[s]);
                    (m.min(f), m.max(f))
                }));
                candidates.extend(apart.still_pairs.iter().flatten());
                candidates.sort_unstable();
            } else {
                let kept = (model.bodies.len() >= self.options.kept_boxes_bodies)
                    .then(|| self.kept.get_or_insert_with(KeptBoxes::default));
                if !kept.is_some_and(|kept| kept.pairs_into(&bodies, candidates, parallel)) {
                    let threads = boxes_of(None, boxes);
                    broad.pairs_into_on(boxes, candidates, threads);
                }
            }
            // The new pairs go into the previous step's spare buffer.
            let mut old = std::mem::replace(&mut world.pairs, std::mem::take(&mut self.scratch.spare_pairs));
            world.pairs.clear();
            world.pairs.reserve(candidates.len());
            let mut next_old = 0;
            for &(a, b) in candidates.iter().filter(|&&(a, b)| !(fixed(a) && fixed(b))) {
                while let Some(gone) = old.get(next_old).filter(|p| (p.a, p.b) < (a, b)) {
                    if gone.touching.is_some() {
                        world.pairs.push(gone.clone());
                    }
                    next_old += 1;
                }
                match old.get(next_old) {
                    Some(p) if (p.a, p.b) == (a, b) => {
                        world.pairs.push(p.clone());
                        next_old += 1;
                    }
                    _ => world.pairs.push(PairState::new(a, b)),
                }
            }
            let gone = old[next_old.min(old.len())..].iter().filter(|p| p.touching.is_some());
            world.pairs.extend(gone.cloned());
            old.clear();
            self.scratch.spare_pairs = old;
        }
        self.counters.seconds.broad_phase += clock.elapsed().as_secs_f64();
        self.counters.work.candidate_pairs += world.pairs.len();
    }
}

//! A pair that came within the distance: its record, the steps held for
//! bracketing, and the bracket of those steps.

use super::record::NearMiss;
use super::search::{nearest_index, outwards};
use crate::ccd::{
    closest_approach, distance_at, hull_gap_from, ApproachStatus, ClosestApproach, ClosestApproachQuery,
    MeshCcdScratch, MovingMesh, WarmSimplex, PROOF_MARGIN_FRACTION,
};
use crate::math::{Pose, Real};
use crate::mesh::MeshDistance;
use crate::motion::StepMotion;
use crate::scene::Model;

/// A pair that came within the distance: its closest approach so far, and
/// the steps held for bracketing.
#[derive(Debug)]
pub(super) struct PairRecord {
    /// The smallest distance reached so far (`distance`, `time`, `closest`),
    /// and the smallest certified bound of the steps bracketed or screened
    /// (`lower`; the held steps' are not in it yet).
    pub(super) miss: NearMiss,
    /// The steps held since one was screened closer than the pair's best
    /// (that step and each later one while the pair stays a candidate):
    /// each is bracketed at the next flush, nearest first, asking only for
    /// what beats the best.
    pub(super) held: Vec<HeldStep>,
    /// The last step (count) in which the pair was a candidate.
    pub(super) seen: u64,
}

/// One step of a pair, kept for bracketing.
#[derive(Copy, Clone, Debug)]
pub(super) struct HeldStep {
    pub(super) t0: Real,
    pub(super) duration: Real,
    pub(super) a: StepMotion,
    pub(super) b: StepMotion,
}

/// The closest-approach query of a pair's step, as the run's CCD asks.
pub(super) fn approach_query<'a>(
    model: &Model,
    (a, b): (&MovingMesh<'a>, &MovingMesh<'a>),
    duration: Real,
    tolerance: Option<Real>,
) -> ClosestApproachQuery<'a> {
    let mut query = ClosestApproachQuery::new(*a, *b, duration);
    query.tolerance = tolerance;
    query.options.max_iterations = model.ccd.max_iterations;
    query.kernel = model.kernel;
    query
}

/// What a step of a pair must come closer than to matter, where its best
/// so far is `best`: that less [`PROOF_MARGIN_FRACTION`] of the bracket's
/// width. A step proved no closer is within that of the best, so the
/// pair's bracket stays within its width however close the step comes.
pub(super) fn beats(best: Real, query: &ClosestApproachQuery<'_>) -> Real {
    best - PROOF_MARGIN_FRACTION * query.width()
}

impl NearMiss {
    /// The pair is `found.distance` apart (reached) at `s` into `step`.
    pub(super) fn reach(&mut self, step: &HeldStep, s: Real, found: MeshDistance) {
        (self.distance, self.time, self.closest) = (found.distance, step.t0 + s, found);
        (self.pose_a, self.pose_b) = (step.a.pose_at(s), step.b.pose_at(s));
    }
}

impl PairRecord {
    /// A pair first found `found` apart at `s` into `step`.
    pub(super) fn new(key: (usize, usize), step: &HeldStep, s: Real, found: MeshDistance) -> PairRecord {
        let mut miss = NearMiss {
            body_a: key.0,
            body_b: key.1,
            distance: Real::INFINITY,
            lower: Real::INFINITY,
            time: 0.0,
            closest: found,
            pose_a: Pose::identity(),
            pose_b: Pose::identity(),
            decided: true,
        };
        miss.reach(step, s, found);
        PairRecord { miss, held: Vec::new(), seen: 0 }
    }

    /// Brackets the held steps, each asking only for what comes closer than
    /// the best so far: first the step whose end is nearest (found by a
    /// golden-section search over the steps' ends, the distance usually
    /// falling and then rising across them), then its neighbours outwards,
    /// so that the first bracket finds the best and the others are proved
    /// farther by one CCD run each. `false` if the pair touches.
    pub(super) fn flush(
        &mut self,
        model: &Model,
        tolerance: Option<Real>,
        scratch: &mut MeshCcdScratch,
    ) -> bool {
        if self.held.is_empty() {
            return true;
        }
        let mut held = std::mem::take(&mut self.held);
        let (mesh_a, mesh_b) = (&model.bodies[self.miss.body_a].mesh, &model.bodies[self.miss.body_b].mesh);
        // The step whose end is nearest, ranked by the vertex hulls' gap at
        // the ends (GJK, warm from end to end; exact for convex meshes, a
        // lower bound otherwise, the exact distance where the hulls
        // overlap): the order only decides which step is bracketed first,
        // every step is bracketed or proved farther all the same.
        let hint = Some((self.miss.closest.triangle_a, self.miss.closest.triangle_b));
        let (mut warm, mut axis) = (WarmSimplex::default(), None);
        let mut end_gap = |k: usize| {
            let step = &held[k];
            let pos_ab = StepMotion::relative_pose(&step.a, &step.b, step.duration);
            let gap = hull_gap_from(mesh_a, mesh_b, &pos_ab, axis, (0.0, Real::INFINITY), &mut warm);
            axis = gap.axis.or(axis);
            if gap.lower > 0.0 {
                return gap.lower;
            }
            let a = MovingMesh { mesh: mesh_a, motion: &step.a };
            let b = MovingMesh { mesh: mesh_b, motion: &step.b };
            distance_at(&a, &b, step.duration, hint, scratch).distance
        };
        let nearest = nearest_index(held.len(), &mut end_gap);
        // Its end, measured: that step's bracket starts from it (a steady
        // approach's minimum is there, and one run then closes it).
        let end = {
            let step = &held[nearest];
            let a = MovingMesh { mesh: mesh_a, motion: &step.a };
            let b = MovingMesh { mesh: mesh_b, motion: &step.b };
            distance_at(&a, &b, step.duration, hint, scratch)
        };
        let mut apart = true;
        for k in outwards(nearest, held.len()) {
            let step = &held[k];
            let a = MovingMesh { mesh: mesh_a, motion: &step.a };
            let b = MovingMesh { mesh: mesh_b, motion: &step.b };
            let mut query = approach_query(model, (&a, &b), step.duration, tolerance);
            query.within = beats(self.miss.distance, &query);
            query.reached = (k == nearest).then_some((step.duration, end));
            let approach = closest_approach(&query, scratch);
            if !self.keep(step, &approach) {
                apart = false;
                break;
            }
        }
        held.clear();
        self.held = held;
        apart
    }

    /// Keeps what a bracket of `step` found. `false` if the pair touches.
    pub(super) fn keep(&mut self, step: &HeldStep, approach: &ClosestApproach) -> bool {
        let miss = &mut self.miss;
        miss.lower = miss.lower.min(approach.lower);
        match (approach.status, approach.closest) {
            (ApproachStatus::Contact, _) => return false,
            (ApproachStatus::Beyond, _) => {}
            (status, closest) => {
                miss.decided &= status == ApproachStatus::Bracketed;
                if let Some(closest) = closest.filter(|_| approach.upper < miss.distance) {
                    miss.reach(step, approach.time, closest);
                }
            }
        }
        true
    }
}

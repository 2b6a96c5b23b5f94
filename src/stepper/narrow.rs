//! Stage 3, narrow phase: the CCD of every pair in play over the step. The
//! queries are independent: on rayon's threads when there are several and
//! the narrow phase is long enough to gain from them
//! ([`RunOptions::parallel_narrow_phase_seconds`](super::RunOptions), the
//! rule of `threads.rs`),
//! results applied in pair order, so a run gives the same result whatever
//! the threads. A far pair is settled without a mesh query by its bounding
//! spheres or the distance bound carried from its previous step.

use std::sync::Arc;
use std::time::Instant;

use super::found::{pair_query, CcdVerdict, Found};
use super::world::World;
use super::Stepper;
use crate::ccd::{mesh_time_of_impact, CcdStatus, MeshCcdResult, MeshCcdScratch, WarmSimplex};
use crate::math::Real;

/// What the stepper keeps of a pair's CCD result: the counters and what
/// carries to the next step, and the full result only at a contact. The
/// result is kept in place, not boxed: the outcomes live in a buffer kept
/// between steps, so that a step allocates nothing, also where pairs rest
/// in contact (under `Simulate` every such pair finds one each step).
#[derive(Clone, Debug)]
pub(crate) struct PairOutcome {
    summary: OutcomeSummary,
    contact: Option<MeshCcdResult>,
}

/// The part of every pair's result that the stepper reads.
#[derive(Copy, Clone, Debug)]
struct OutcomeSummary {
    iterations: usize,
    hull_steps: usize,
    triangle_pairs: usize,
    hint: Option<(usize, usize)>,
    axis: Option<crate::math::Vector>,
    simplex: WarmSimplex,
    end_lower_bound: Real,
}

impl From<MeshCcdResult> for PairOutcome {
    fn from(result: MeshCcdResult) -> PairOutcome {
        PairOutcome {
            summary: OutcomeSummary {
                iterations: result.iterations,
                hull_steps: result.hull_steps,
                triangle_pairs: result.triangle_pairs,
                hint: result.hint,
                axis: result.axis,
                simplex: result.simplex,
                end_lower_bound: result.end_lower_bound,
            },
            contact: result.time_of_impact.is_some().then_some(result),
        }
    }
}

impl Stepper {
    /// The CCD of every pair in play over the step starting at `t0`; the
    /// contacts found go to `found`, in pair order.
    pub(super) fn narrow_phase(&mut self, world: &mut World, t0: Real, found: &mut Vec<Found>) {
        let clock = Instant::now();
        let model = Arc::clone(&self.model);
        let model = &*model;
        let response = &*self.response;
        // Pairs already in contact are left alone unless the response asks
        // for them (`Bounce`: for coming closer again).
        let work = &mut self.scratch.work;
        work.clear();
        work.extend((0..world.pairs.len()).filter(|&k| response.sweeps(&world.pairs[k])));
        let (motions, pairs) = (&world.motions, &world.pairs);
        let near_misses = self.near_misses.as_ref();
        let query = |k: usize, scratch: &mut MeshCcdScratch| {
            let pair = &pairs[k];
            let motions = [&motions[pair.a], &motions[pair.b]];
            let query = pair_query(model, pair, motions, model.dt, response.contact_rule(pair));
            // A pair the near misses' screen proved farther than this
            // query's contact distance over the step: that run's answer
            // (apart) is this one's.
            if let Some((lower, screen)) = near_misses.and_then(|near| near.screened_apart(k)) {
                if lower > query.contract().contact_distance {
                    return PairOutcome::from(*screen);
                }
            }
            let mut result = mesh_time_of_impact(&query, pair.warm_start(), scratch);
            if result.status == CcdStatus::InitiallyTouching && t0 > 0.0 {
                // A pair new to the broad phase, touching at the step's start.
                result.status = CcdStatus::Converged;
            }
            PairOutcome::from(result)
        };
        // Results go into a buffer kept between steps, and each thread keeps
        // its own scratch: a step allocates nothing once they have grown.
        let results = &mut self.scratch.results;
        self.scratch.batches.run(work, results, &mut self.scratch.ccd, |&mut k, scratch| query(k, scratch));
        for (&k, outcome) in work.iter().zip(results.iter_mut()) {
            let pair = &mut world.pairs[k];
            let result = outcome.summary;
            self.counters.work.add_query(result.iterations, result.triangle_pairs, result.hull_steps);
            self.counters.work.pairs_culled += usize::from(result.iterations == 0);
            pair.hint = result.hint;
            pair.axis = result.axis;
            pair.simplex = result.simplex;
            pair.lower_bound = Some(result.end_lower_bound);
            let Some(contact) = outcome.contact.take() else { continue };
            match CcdVerdict::of(&contact) {
                CcdVerdict::Undecided => world.note_undecided(k, &contact),
                CcdVerdict::Contact(_) => found.push(Found { pair: k, result: contact }),
                CcdVerdict::Apart => {}
            }
        }
        let seconds = clock.elapsed().as_secs_f64();
        self.counters.seconds.ccd += seconds;
    }
}

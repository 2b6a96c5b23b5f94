//! Stage 3, narrow phase: the CCD of every pair in play over the step. The
//! queries are independent: on rayon's threads when there are several and
//! the narrow phase is long enough to gain from them
//! ([`StepParameters::parallel_narrow_phase_seconds`](super::StepParameters)),
//! results applied in pair order, so a run gives the same result whatever
//! the threads. A far pair is settled without a mesh query by its bounding
//! spheres or the distance bound carried from its previous step.

use std::cell::RefCell;
use std::sync::Arc;
use std::time::Instant;

use rayon::prelude::*;

use super::world::{PairState, World};
use super::Stepper;
use crate::ccd::{
    mesh_time_of_impact, CcdStatus, ContactRule, MeshCcdQuery, MeshCcdResult, MeshCcdScratch, MovingMesh,
    WarmSimplex,
};
use crate::math::Real;
use crate::motion::StepMotion;
use crate::scene::Model;

thread_local! {
    /// Each rayon thread's CCD scratch, kept between steps and runs (the
    /// narrow phase's and the near misses' batches).
    pub(crate) static THREAD_SCRATCH: RefCell<MeshCcdScratch> = RefCell::new(MeshCcdScratch::default());
}

/// What a batch that took `seconds` would have taken on one thread: the
/// time itself, or, where it ran on `threads` threads, what they spent
/// after handing it over (`handing_over` seconds).
pub(crate) fn one_thread_seconds(seconds: Real, parallel: bool, threads: Real, handing_over: Real) -> Real {
    if parallel {
        threads * (seconds - handing_over).max(0.0)
    } else {
        seconds
    }
}

/// Whether a batch of `on_one_thread` seconds gains from `threads`
/// threads, handing it over costing `handing_over` seconds
/// ([`StepParameters::parallel_narrow_phase_seconds`](super::StepParameters)).
pub(crate) fn gains_from_threads(on_one_thread: Real, threads: Real, handing_over: Real) -> bool {
    threads > 1.0 && on_one_thread > handing_over * threads / (threads - 1.0)
}

/// What a pair's CCD result means to the stepper (the narrow phase's and
/// a response's re-checks alike).
#[derive(Copy, Clone, Debug, PartialEq)]
pub(crate) enum CcdVerdict {
    /// The query ran out of iterations: undecided is not a contact; the
    /// run ends after this step ([`World::note_undecided`]).
    Undecided,
    /// A contact at this time (in the query's interval).
    Contact(Real),
    /// No contact within the interval.
    Apart,
}

impl CcdVerdict {
    /// The verdict of `result`.
    pub(crate) fn of(result: &MeshCcdResult) -> CcdVerdict {
        match (result.status, result.time_of_impact) {
            (CcdStatus::OutOfIterations, _) => CcdVerdict::Undecided,
            (_, Some(time)) => CcdVerdict::Contact(time),
            (_, None) => CcdVerdict::Apart,
        }
    }
}

/// A contact the narrow phase found: the pair (index into `world.pairs`)
/// and its CCD result (with a time of impact).
#[derive(Clone, Debug)]
pub(crate) struct Found {
    pub pair: usize,
    pub result: MeshCcdResult,
}

/// What the stepper keeps of a pair's CCD result: the counters and what
/// carries to the next step, and the full result only at a contact (a few
/// pairs a step), so that thousands of pairs cost little memory.
#[derive(Clone, Debug)]
pub(crate) struct PairOutcome {
    summary: OutcomeSummary,
    contact: Option<Box<MeshCcdResult>>,
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
            contact: result.time_of_impact.is_some().then(|| Box::new(result)),
        }
    }
}

/// The mesh CCD query of `pair` over `duration`, its bodies moving by
/// `motions`, under the scene's options and kernel and the rule `contact`.
pub(crate) fn pair_query<'a>(
    model: &'a Model,
    pair: &PairState,
    motions: [&'a StepMotion; 2],
    duration: Real,
    contact: ContactRule,
) -> MeshCcdQuery<'a> {
    MeshCcdQuery {
        a: MovingMesh { mesh: &model.bodies[pair.a].mesh, motion: motions[0] },
        b: MovingMesh { mesh: &model.bodies[pair.b].mesh, motion: motions[1] },
        duration,
        options: model.ccd,
        contact,
        kernel: model.kernel,
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
        let parallel = self.options.parallel && self.scratch.narrow_parallel && work.len() > 1;
        if parallel {
            work.par_iter()
                .map(|&k| THREAD_SCRATCH.with(|scratch| query(k, &mut scratch.borrow_mut())))
                .collect_into_vec(results);
        } else {
            results.clear();
            let scratch = &mut self.scratch.ccd;
            results.extend(work.iter().map(|&k| query(k, scratch)));
        }
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
                CcdVerdict::Contact(_) => found.push(Found { pair: k, result: *contact }),
                CcdVerdict::Apart => {}
            }
        }
        let seconds = clock.elapsed().as_secs_f64();
        let threads = rayon::current_num_threads() as Real;
        let handing_over = self.parameters.parallel_narrow_phase_seconds;
        let on_one_thread = one_thread_seconds(seconds, parallel, threads, handing_over);
        self.scratch.narrow_parallel = gains_from_threads(on_one_thread, threads, handing_over);
        self.counters.seconds.ccd += seconds;
    }
}

//! When work goes to rayon's threads: each thread's CCD scratch, and the
//! rule that hands a batch over only when it gains from the threads (the
//! narrow phase's and the near misses' batches alike).

use std::cell::RefCell;
use std::time::Instant;

use rayon::prelude::*;

use crate::ccd::MeshCcdScratch;
use crate::math::Real;

thread_local! {
    /// Each rayon thread's CCD scratch, kept between steps and runs (the
    /// narrow phase's and the near misses' batches).
    pub(crate) static THREAD_SCRATCH: RefCell<MeshCcdScratch> = RefCell::new(MeshCcdScratch::default());
}

/// What a batch that took `seconds` would have taken on one thread: the
/// time itself, or, where it ran on `threads` threads, what they spent
/// after handing it over (`handing_over` seconds).
fn one_thread_seconds(seconds: Real, parallel: bool, threads: Real, handing_over: Real) -> Real {
    if parallel {
        threads * (seconds - handing_over).max(0.0)
    } else {
        seconds
    }
}

/// Whether a batch of `on_one_thread` seconds gains from `threads`
/// threads, handing it over costing `handing_over` seconds
/// ([`RunOptions::parallel_narrow_phase_seconds`](super::RunOptions)).
fn gains_from_threads(on_one_thread: Real, threads: Real, handing_over: Real) -> bool {
    threads > 1.0 && on_one_thread > handing_over * threads / (threads - 1.0)
}

/// Whether a batch of independent jobs (a step's CCD queries, the near
/// misses' screens or brackets) goes on rayon's threads: when the run is
/// parallel, there are several threads, and the batch, at the mean time
/// per job seen so far, takes longer on one thread than handing it over
/// costs ([`RunOptions::parallel_narrow_phase_seconds`]).
///
/// [`RunOptions::parallel_narrow_phase_seconds`]: super::RunOptions::parallel_narrow_phase_seconds
#[derive(Copy, Clone, Debug, Default)]
pub(crate) struct Batches {
    /// `false`: never (the run is not parallel, or one thread).
    allowed: bool,
    threads: Real,
    handing_over: Real,
    /// Seconds on one thread and jobs, over the batches so far.
    seconds: Real,
    jobs: usize,
}

impl Batches {
    pub(crate) fn new(parallel: bool, handing_over: Real) -> Batches {
        let threads = rayon::current_num_threads() as Real;
        Batches { allowed: parallel && threads > 1.0, threads, handing_over, seconds: 0.0, jobs: 0 }
    }

    /// Whether a batch of `jobs` goes on the threads (the first batches,
    /// with nothing seen yet, do not).
    pub(crate) fn choose(&self, jobs: usize) -> bool {
        self.allowed
            && jobs > 1
            && gains_from_threads(self.on_one_thread(jobs), self.threads, self.handing_over)
    }

    /// Whether a batch of `jobs`, at the mean time per job seen so far,
    /// takes longer on one thread than handing it to another costs (the
    /// first batches, with nothing seen yet, do not).
    pub(crate) fn outlasts_hand_over(&self, jobs: usize) -> bool {
        self.allowed && self.on_one_thread(jobs) > self.handing_over
    }

    /// A batch of `jobs` on one thread, at the mean time per job seen so
    /// far (0 before any).
    fn on_one_thread(&self, jobs: usize) -> Real {
        self.seconds / self.jobs.max(1) as Real * jobs as Real
    }

    /// Counts a batch of `jobs` that took `seconds` on one thread.
    pub(crate) fn account(&mut self, seconds: Real, jobs: usize) {
        self.seconds += seconds;
        self.jobs += jobs;
    }

    /// `f` of each of `jobs`, in order, into `out`: on rayon's threads
    /// (each with its own scratch) where [`Batches::choose`] says so,
    /// otherwise on this one with `scratch`.
    pub(crate) fn run<J: Send, R: Send>(
        &mut self,
        jobs: &mut [J],
        out: &mut Vec<R>,
        scratch: &mut MeshCcdScratch,
        f: impl Fn(&mut J, &mut MeshCcdScratch) -> R + Sync,
    ) {
        let clock = Instant::now();
        let parallel = self.choose(jobs.len());
        if parallel {
            jobs.par_iter_mut()
                .map(|job| THREAD_SCRATCH.with(|scratch| f(job, &mut scratch.borrow_mut())))
                .collect_into_vec(out);
        } else {
            out.clear();
            out.extend(jobs.iter_mut().map(|job| f(job, scratch)));
        }
        let seconds = clock.elapsed().as_secs_f64();
        self.account(one_thread_seconds(seconds, parallel, self.threads, self.handing_over), jobs.len());
    }
}

//! When work goes to rayon's threads: each thread's CCD scratch, the rule
//! that hands a batch over only when it gains from the threads (the narrow
//! phase's and the near misses' batches alike), and the other threads kept
//! looking for work through a step of many bodies.

use std::cell::RefCell;
use std::sync::atomic::{AtomicBool, Ordering};
use std::time::{Duration, Instant};

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

/// A step of this many bodies or more keeps rayon's other threads looking
/// for work while it runs ([`awake_while`]): `4096`, where the broad
/// phase's stages go on the threads too (`PARALLEL_BOX_BODIES`). A
/// shorter step has too few parallel stages to gain from it.
pub(crate) const AWAKE_STEP_BODIES: usize = 4096;

/// A thread kept looking for work goes back to sleep after finding none
/// for this long: `200 µs`, longer than the serial stretches of a step of
/// many bodies (a narrow phase on one thread, the response) and short
/// enough that a thread held by a step of another run (two runs stepping
/// at once from two threads of the caller, each keeping the pool's other
/// thread) is let go soon.
pub(crate) const AWAKE_IDLE_LIMIT: Duration = Duration::from_micros(200);

/// The spin-loop pauses between two looks for work: `16`.
const AWAKE_PAUSES: usize = 16;

/// `f` on this thread of rayon's pool while each of the pool's other
/// threads keeps looking for work instead of going to sleep between the
/// step's parallel stages. A sleeping thread woken by the next stage
/// started 25–45 µs late on this machine's two cores, stage after stage
/// (`BENCHMARKS.md`); a thread that keeps looking burns its core while the
/// step runs serial stages, which is the price. Called from outside the
/// pool, `f` simply runs.
pub(crate) fn awake_while<R: Send>(f: impl FnOnce() -> R + Send) -> R {
    let Some(home) = rayon::current_thread_index() else { return f() };
    if rayon::current_num_threads() < 2 {
        return f();
    }
    let done = AtomicBool::new(false);
    let done = &done;
    rayon::scope(|scope| {
        scope.spawn_broadcast(move |_, context| {
            // This thread's own copy returns at once (it runs `f`).
            if context.index() != home {
                look_for_work(done);
            }
        });
        let result = f();
        done.store(true, Ordering::Release);
        result
    })
}

/// Runs what work this thread finds until `done`, or until it has found
/// none for [`AWAKE_IDLE_LIMIT`].
fn look_for_work(done: &AtomicBool) {
    let mut idle_since = Instant::now();
    while !done.load(Ordering::Acquire) {
        match rayon::yield_now() {
            Some(rayon::Yield::Executed) => idle_since = Instant::now(),
            _ if idle_since.elapsed() > AWAKE_IDLE_LIMIT => return,
            // A pause between looks (under a microsecond), which leaves
            // the core's resources to a sibling thread.
            _ => (0..AWAKE_PAUSES).for_each(|_| std::hint::spin_loop()),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::sync::mpsc::channel;

    /// A sum on the pool's threads, as a step's parallel stage makes one.
    fn stage() -> u64 {
        (0..200_000u64).into_par_iter().map(|k| k % 7).sum()
    }

    /// Stages with serial stretches between them, kept awake: the answers
    /// of the same stages on one thread.
    fn stages() -> u64 {
        awake_while(|| {
            let mut total = 0;
            for _ in 0..20 {
                total += stage();
                let clock = Instant::now();
                while clock.elapsed() < Duration::from_micros(50) {}
            }
            total
        })
    }

    /// Two runs stepping at once from two threads of the caller, in a pool
    /// of two: each keeps the pool's other thread (which the other run's
    /// step holds) looking for work. Both finish, let go after
    /// `AWAKE_IDLE_LIMIT`, with the answers of one thread; and outside
    /// the pool the stages simply run.
    #[test]
    fn two_steps_at_once_each_keeping_the_other_thread_awake_both_finish() {
        let expected: u64 = 20 * (0..200_000u64).map(|k| k % 7).sum::<u64>();
        assert_eq!(stages(), expected, "outside the pool");
        let pool =
            std::sync::Arc::new(rayon::ThreadPoolBuilder::new().num_threads(2).build().expect("a pool"));
        let (sender, receiver) = channel();
        for _ in 0..2 {
            let (pool, sender) = (pool.clone(), sender.clone());
            std::thread::spawn(move || {
                for _ in 0..400 {
                    let sum = pool.install(stages);
                    sender.send(sum).expect("the test waits");
                }
            });
        }
        for k in 0..800 {
            let sum =
                receiver.recv_timeout(Duration::from_secs(20)).unwrap_or_else(|_| panic!("run {k} hangs"));
            assert_eq!(sum, expected);
        }
    }
}

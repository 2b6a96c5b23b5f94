//! How a run is carried out: threads and the broad phase. None of it
//! changes a result (the tests compare runs under each); what shapes
//! results is the scene's [`StepParameters`](crate::scene::StepParameters).

use crate::math::Real;

/// How a run is carried out (not what it computes: results are the same
/// whatever the options).
#[derive(Copy, Clone, Debug, PartialEq)]
pub struct RunOptions {
    /// Run the stages that scale with bodies or pairs on several threads
    /// (rayon's pool). A step of `AWAKE_STEP_BODIES` (4,096) bodies or
    /// more, run from outside the pool, also keeps the pool's other threads
    /// looking for work (spinning) while it runs, so that each parallel
    /// stage starts at once. Default: true.
    pub parallel: bool,
    /// Select pairs with the broad phase when there are more than two
    /// bodies (otherwise every pair not both fixed is queried). Default: true.
    pub broad_phase: bool,
    /// Bodies are integrated on several threads from this many bodies on
    /// (a count). Default: `64`.
    pub parallel_integration_bodies: usize,
    /// What handing a narrow phase to rayon's threads costs in wall time
    /// (waking them and gathering their results; seconds): the next step's
    /// narrow phase runs on `n` threads when this step's, on one thread,
    /// took more than `n / (n − 1)` times it (estimated from a parallel
    /// step as `n` × (its time − this)). Default: `1e-4`, about what two
    /// threads take to wake and gather (measured in `BENCHMARKS.md`). The
    /// guard sets its own, since its narrow phase runs beside rapier's.
    pub parallel_narrow_phase_seconds: Real,
    /// Traces of at least this many pairs are sampled on rayon's threads
    /// (when `parallel`); fewer are sampled in turn (a count). Not tuned: a
    /// sample of two convex meshes is a few hundred nanoseconds, so a
    /// handful of pairs is not worth handing out. Default: `64`.
    pub parallel_trace_pairs: usize,
    /// The broad phase keeps each body's box between steps, making it again
    /// only when the body leaves it, from this many bodies on (a count; see
    /// `src/stepper/kept.rs`): the same pairs as boxing every body at every
    /// step, found in less time when there are many. Default: `8192` (where
    /// the grid takes the tree's place; measured in `BENCHMARKS.md`).
    pub kept_boxes_bodies: usize,
}

impl Default for RunOptions {
    fn default() -> Self {
        RunOptions {
            parallel: true,
            broad_phase: true,
            parallel_integration_bodies: 64,
            parallel_narrow_phase_seconds: 1e-4,
            parallel_trace_pairs: 64,
            kept_boxes_bodies: 8192,
        }
    }
}

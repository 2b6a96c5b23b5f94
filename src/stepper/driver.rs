//! What makes a run's steps: the stepper's own integration, or rapier
//! guarded by nearmiss (`crate::guard`). The run loop on top
//! (`crate::run`) asks a driver for each step.

use std::time::Instant;

use super::result::{RunResult, Termination};

/// What makes a run's steps: the bodies' motions over each step and the
/// sweep of that step (stages 1 to 6). `nearmiss::run` is the loop
/// around it.
pub(crate) trait Driver {
    /// The observers' samples at the run's start.
    fn start(&mut self);
    /// Step `step` (0-based): how it ended, or why the run ends there.
    fn step(&mut self, step: u64) -> Result<StepEnd, Termination>;
    /// The run's result after `steps` steps, ended by `termination`.
    fn finish(self: Box<Self>, steps: u64, termination: Termination, start: Instant) -> RunResult;
}

/// How a step ended, when the run goes on or stops at a contact.
pub(crate) enum StepEnd {
    Continue,
    FirstContact,
}

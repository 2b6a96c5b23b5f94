//! `on_contact: Stop` and `Record`: each contact is recorded once, with the
//! pair marked touching (the stepper re-arms it once it separates); the
//! bodies keep moving. `Stop` keeps only the earliest contact of the step
//! and ends the run.

use super::{Response, StepContext};
use crate::stepper::Found;

/// Records contacts; with `stop`, only the first, ending the run.
pub(crate) struct Record {
    pub stop: bool,
}

impl Response for Record {
    fn ends_run(&self) -> bool {
        self.stop
    }

    fn respond(&self, step: &mut StepContext<'_>, found: &mut Vec<Found>) -> bool {
        let any = !found.is_empty();
        for Found { pair, result } in found.drain(..) {
            if let Some(time) = result.time_of_impact {
                step.world.record_contact(pair, step.t0, time, &result);
            }
        }
        if any && self.stop {
            // Keep only the earliest contact (ties: the first pair).
            let contacts = &mut step.world.contacts;
            let first = contacts.iter().cloned().min_by(|a, b| a.time.total_cmp(&b.time));
            *contacts = first.into_iter().collect();
        }
        any
    }
}

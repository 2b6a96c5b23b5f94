//! The held steps bracketed: on this thread, or on another while the run
//! steps on.

use std::sync::mpsc::channel;
use std::sync::{Arc, PoisonError};
use std::time::Instant;

use super::pair::PairRecord;
use super::{Flushed, NearMissObserver};
use crate::scene::Model;
use crate::stepper::threads::THREAD_SCRATCH;

impl NearMissObserver {
    /// Brackets the held steps of the pairs in `flushing` (see
    /// [`PairRecord::flush`]); a pair found touching is dropped.
    ///
    /// What the brackets found is kept at the next step's
    /// [`NearMissObserver::join`], before its screens, so that they can
    /// run in the `background`, on another of rayon's threads while the
    /// next step's bodies move and its broad phase runs, where a batch
    /// outlasts the hand-over. Their records are out of the map meanwhile
    /// (nothing asks for them before the join). On this thread or
    /// another, the answers are the same.
    pub(super) fn flush_pending(&mut self, model: &Arc<Model>, background: bool) {
        if self.flushing.is_empty() {
            return;
        }
        let mut batch = std::mem::take(&mut self.batch);
        batch.clear();
        batch.extend(self.flushing.iter().filter_map(|key| self.pairs.remove_entry(key)));
        let tolerance = self.tolerance;
        if background && self.brackets_parallel.outlasts_hand_over(batch.len()) {
            let (sender, receiver) = channel();
            let model = Arc::clone(model);
            rayon::spawn(move || {
                let clock = Instant::now();
                let flushed: Vec<Flushed> = THREAD_SCRATCH.with(|scratch| {
                    let scratch = &mut scratch.borrow_mut();
                    batch
                        .into_iter()
                        .map(|(key, mut record)| {
                            let apart = record.flush(&model, tolerance, scratch);
                            (key, record, apart)
                        })
                        .collect()
                });
                // The observer is gone only if the run is (a panic).
                let _ = sender.send((flushed, clock.elapsed().as_secs_f64()));
            });
            *self.in_flight.get_mut().unwrap_or_else(PoisonError::into_inner) = Some(receiver);
            return;
        }
        let mut apart = std::mem::take(&mut self.apart);
        self.brackets_parallel.run(&mut batch, &mut apart, &mut self.scratch, |(_, record), scratch| {
            record.flush(model, tolerance, scratch)
        });
        for ((key, record), &apart) in batch.drain(..).zip(&apart) {
            self.keep_flushed(key, record, apart);
        }
        (self.batch, self.apart) = (batch, apart);
    }

    /// Waits for the brackets on another thread, if any, and keeps what
    /// they found.
    pub(super) fn join(&mut self) {
        let in_flight = self.in_flight.get_mut().unwrap_or_else(PoisonError::into_inner);
        if let Some(receiver) = in_flight.take() {
            // The channel closes unsent only if the thread panicked, and
            // rayon aborts the process on a panic in a spawned job.
            let (flushed, seconds) = receiver.recv().unwrap_or_default();
            self.brackets_parallel.account(seconds, flushed.len());
            for (key, record, apart) in flushed {
                self.keep_flushed(key, record, apart);
            }
        }
    }

    /// A pair's record as its brackets left it, back in the map, or the
    /// pair dropped if it touches.
    pub(super) fn keep_flushed(&mut self, key: (usize, usize), record: PairRecord, apart: bool) {
        if apart {
            self.pairs.insert(key, record);
        } else {
            self.touched.insert(key);
        }
    }
}

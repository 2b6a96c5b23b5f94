//! A step's sweeps and rewinds.

use super::bodies::RapierBodies;

use super::act::is_kinematic;
use super::events::{GuardError, GuardEvent};
use super::{Guard, RapierStep};
use crate::math::Real;
use crate::stepper::Termination;

impl<B: RapierBodies> Guard<B> {
    /// [`finish_step`](Guard::finish_step)'s sweeps and rewinds; the events
    /// go to `self.events`.
    pub(super) fn sweep_step(
        &mut self,
        bodies: &mut B,
        mut engine: Option<&mut RapierStep<'_, B>>,
    ) -> Result<(), GuardError<B::Handle>> {
        if !std::mem::take(&mut self.started) {
            return Err(GuardError::NoStartPoses);
        }
        self.events.clear();
        self.world.rewound.clear();
        let contacts_before = self.world.contacts.len();
        let t0 = self.step as Real * self.dt;
        // Time into the step at the current sweep's start; each sweep runs
        // over the rest of the step, its motions stretched over `dt`.
        let mut elapsed: Real = 0.0;
        let mut substeps = 0;
        // Sweeps after stops (no rapier step between): each stops more
        // bodies, so there are at most as many as bodies.
        let mut restops = 0;
        loop {
            self.set_motions(bodies, elapsed);
            self.world.may_rewind = engine.is_some() && substeps < self.max_substeps;
            let mark = self.world.contacts.len();
            let result = self.stepper.sweep(&mut self.world, self.step);
            let scale = (self.dt - elapsed) / self.dt;
            let time_before = self.time_before;
            let real = |time: Real| {
                let time = if elapsed > 0.0 { t0 + elapsed + (time - t0) * scale } else { time };
                if time_before > 0.0 {
                    time_before + time
                } else {
                    time
                }
            };
            for contact in &mut self.world.contacts[mark..] {
                contact.time = real(contact.time);
            }
            let handles = &self.handles;
            self.events.extend(
                self.world
                    .separated
                    .iter()
                    .map(|&(a, b)| GuardEvent::Stopped { a: handles[a], b: handles[b] }),
            );
            // Stopped bodies stay at their contacts (also when a pair was
            // undecided: the contacts before it stand).
            let stops = std::mem::take(&mut self.world.stops);
            let stopped = self.stop_bodies(bodies, &stops, scale);
            self.world.stops = stops;
            if let Err(Termination::Undecided { pair: (a, b), time, step, iterations }) = result {
                let time = real(time);
                self.undecided = Some(Termination::Undecided { pair: (a, b), time, step, iterations });
                self.step += 1;
                return Err(GuardError::Undecided {
                    a: self.handles[a],
                    b: self.handles[b],
                    time,
                    iterations,
                });
            }
            if let (Some(rewind), Some(engine)) = (self.world.rewind.take(), engine.as_mut()) {
                // The response never asks for the sweep's start (rapier's
                // step began there already).
                debug_assert!(rewind.time > 0.0);
                let at = rewind.time;
                self.rewind(bodies, at, [rewind.a, rewind.b]);
                // A kinematic body has infinite mass: the dynamic body it
                // meets leaves at least as fast as its point at the contact.
                let kinematic = |i: usize| is_kinematic(bodies, self.handles[i]);
                if let (Some(point), Some(normal), true) =
                    (rewind.point, rewind.normal, kinematic(rewind.a) != kinematic(rewind.b))
                {
                    self.inelastic_impulse(bodies, [rewind.a, rewind.b], &point, &normal);
                }
                self.world.rewound.push((rewind.a, rewind.b));
                elapsed += at * scale;
                substeps += 1;
                self.rewinds += 1;
                engine(bodies, self.dt - elapsed);
                continue;
            }
            if stopped && restops < self.handles.len() {
                // Swept again: a body that stopped may now be in another's way.
                restops += 1;
                continue;
            }
            self.watch_depths(bodies, scale, contacts_before);
            break;
        }
        self.step += 1;
        let handles = &self.handles;
        self.events.extend(self.world.contacts[contacts_before..].iter().map(|contact| {
            GuardEvent::Started {
                a: handles[contact.body_a],
                b: handles[contact.body_b],
                contact: Box::new(contact.clone()),
            }
        }));
        Ok(())
    }
}

//! What happens at contact: the seam between the stepper's narrow phase and
//! the bodies' motion.
//!
//! Each step the narrow phase hands the contacts it found (pairs and their
//! CCD results, in pair order) to the scene's `Response`, which records
//! them and may change the bodies' motion before the step ends. The
//! responses:
//! - `Stop` and `Record` (`record.rs`): record each contact once; `Stop`
//!   keeps the earliest and ends the run, `Record` lets bodies move on (a
//!   pair in contact is re-armed once it separates).
//! - `Bounce` (`bounce.rs`): contacts in time order, bodies stopped at their
//!   contacts for the rest of the step and re-checked (`stop.rs`), impulses
//!   along the contact normal (the maths in `impulse.rs`, [`apply_impulse`]).
//! - `Simulate`'s clamp (`clamp.rs`): rapier moved the bodies; contacts in
//!   time order, dynamic bodies held at their contacts (`stop.rs`), the
//!   velocities left to rapier ([`crate::guard`]).
//!
//! A new response is a new file implementing the crate's `Response` trait
//! and one arm of `for_model`; the stepper does not change.

mod bounce;
mod impulse;
mod record;
mod stop;

pub use impulse::{apply_impulse, approach_speed, contact_frame, ImpactBody};
pub(crate) use stop::Stops;

use crate::ccd::{ContactRule, MeshCcdScratch};
use crate::math::Real;
use crate::scene::{Model, OnContact};
use crate::stepper::{Counters, Found, PairState, World};

/// What a response may read and change during a step.
pub(crate) struct StepContext<'a> {
    /// The scene.
    pub model: &'a Model,
    /// The world state.
    pub world: &'a mut World,
    /// CCD scratch, for queries the response makes itself.
    pub scratch: &'a mut MeshCcdScratch,
    /// The buffers of bodies stopped in time order (`stop.rs`).
    pub stops: &'a mut Stops,
    /// The run's counters.
    pub counters: &'a mut Counters,
    /// The time at the step's start.
    pub t0: Real,
}

/// A collision response (see the module).
pub(crate) trait Response: Send + Sync {
    /// Whether the narrow phase sweeps `pair` in this step. Default: pairs
    /// not in contact (`Bounce` sweeps those in contact too, for coming
    /// closer again; the guard every pair rapier solves).
    fn sweeps(&self, pair: &PairState) -> bool {
        pair.touching.is_none()
    }

    /// The contact rule of `pair`'s CCD query. Default: the scene's
    /// options, relative to the pair's size.
    fn contact_rule(&self, _pair: &PairState) -> ContactRule {
        ContactRule::ScaleRelative
    }

    /// Whether the response can stop kinematic bodies (they then keep a
    /// state of their own). Default: no.
    fn stops_kinematic_bodies(&self) -> bool {
        false
    }

    /// Whether it moves momentum (and energy) between bodies: the per-body
    /// energy check of the integration stage is then off. Default: no.
    fn exchanges_momentum(&self) -> bool {
        false
    }

    /// The distance beyond which a touching pair whose contact had
    /// `contact_distance` is armed again. Default: `factor` (the stepper's
    /// [`rearm_distance_factor`](crate::scene::StepParameters)) times it.
    fn rearm_distance(&self, contact_distance: Real, factor: Real) -> Real {
        factor * contact_distance
    }

    /// Whether the run ends at the first contact. Default: no.
    fn ends_run(&self) -> bool {
        false
    }

    /// Responds to the step's contacts (`found`, in pair order, drained).
    /// Called every step, also when nothing was found. Returns whether a
    /// contact was recorded.
    fn respond(&self, step: &mut StepContext<'_>, found: &mut Vec<Found>) -> bool;
}

/// The response a scene asks for, for the stepper's own integration;
/// `None` under `Simulate`, whose steps rapier makes and the guard sweeps
/// with its own response ([`crate::guard`]).
pub(crate) fn for_model(model: &Model) -> Option<Box<dyn Response>> {
    match model.on_contact {
        OnContact::Stop => Some(Box::new(record::Record { stop: true })),
        OnContact::Record => Some(Box::new(record::Record { stop: false })),
        OnContact::Bounce { restitution } => Some(Box::new(bounce::Bounce {
            restitution,
            redetect_fraction: model.parameters.bounce_redetect_fraction,
        })),
        OnContact::Simulate { .. } => None,
    }
}

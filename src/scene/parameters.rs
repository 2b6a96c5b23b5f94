//! The stepper's tunable numbers that shape a run's results, documented
//! and defaulted in one place (like rapier's `IntegrationParameters`). The
//! CCD's own tolerances are [`CcdOptions`](crate::ccd::CcdOptions); how a
//! run is carried out (threads, the broad phase) is the stepper's
//! `RunOptions`, which never changes a result.

use crate::math::Real;

/// The stepper's parameters. Every field is a plain number with its
/// meaning, unit and default; `tests/documented_defaults.rs` checks the
/// defaults stated here.
#[derive(Copy, Clone, Debug, PartialEq)]
pub struct StepParameters {
    /// A pair in contact (`Record`, `Bounce`) is re-armed once its distance
    /// at a step's end exceeds this many times its contact distance
    /// (a ratio). Default: `2.0`.
    pub rearm_distance_factor: Real,
    /// Under `Bounce`, a pair that bounced and is not yet re-armed is a new
    /// contact when it comes within this fraction of its distance at the
    /// bounce (the largest of its episode's contacts until it is re-armed;
    /// a ratio; the absolute re-detection distance of
    /// [`ContactRule::Absolute`](crate::ccd::ContactRule)). Default: `0.5`.
    pub bounce_redetect_fraction: Real,
    /// A run is declared diverged when an integrated body's mechanical
    /// energy exceeds its initial value by this many times its initial
    /// energy scale (the sum of the magnitudes of its kinetic and potential
    /// terms; a ratio). Gravity, springs and free spin conserve energy and
    /// damping only removes it, so such growth is the integrator's, not the
    /// physics'. Default: `10.0`.
    pub divergence_energy_growth: Real,
    /// The swept boxes grow by this many ulps of a body's reach (largest
    /// coordinate plus travel plus radius) beyond its share of the contact
    /// distance, so that box rounding never drops a pair that the CCD's
    /// tolerance floor would count as touching (ulps). Default: `1e3`.
    pub broad_phase_rounding_ulps: Real,
}

impl Default for StepParameters {
    fn default() -> Self {
        StepParameters {
            rearm_distance_factor: 2.0,
            bounce_redetect_fraction: 0.5,
            divergence_energy_growth: 10.0,
            broad_phase_rounding_ulps: 1e3,
        }
    }
}

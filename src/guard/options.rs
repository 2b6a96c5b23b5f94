//! How a guard sweeps: its options, their defaults, and the contact
//! distance they allow beside rapier's contact.

use rapier3d_f64::prelude::IntegrationParameters;

use crate::ccd::{CcdOptions, ContactContract, ContactRule};
use crate::math::Real;
use crate::mesh::DistanceKernel;
use crate::scene::{Body, BodyMotion};

/// How a [`Guard`](super::Guard) sweeps.
#[derive(Copy, Clone, Debug, PartialEq)]
pub struct GuardOptions {
    /// The CCD's tolerances and limits (the contact distance is relative to
    /// the smaller body of a pair, see [`CcdOptions`]). This is the wall: no
    /// two guarded meshes come closer. It must stay below the two
    /// colliders' skins ([`Guard::new`](super::Guard::new) checks it for the largest pair).
    /// Default: [`CcdOptions::default`].
    pub ccd: CcdOptions,
    /// The CCD's distance kernel. Default: exact.
    pub kernel: DistanceKernel,
    /// Sweep pairs on rayon's threads. Default: true.
    pub parallel: bool,
    /// The contact skin [`Guard::new`](super::Guard::new) gives each guarded collider, as a
    /// multiple of rapier's allowed linear error
    /// (`IntegrationParameters::allowed_linear_error`, 0.005 × `length_unit`
    /// by default). `0` (the default): no skin; rapier's contact model is
    /// untouched (its soft contacts overlap resting pairs by up to about its
    /// allowed error) and the guard only reads where rapier holds. Above
    /// `0`: rapier holds touching pairs the two skins apart and its soft
    /// contacts sink into the skins, and the guard keeps the meshes
    /// themselves from ever overlapping (a resting box floats the two
    /// skins, less what rapier lets it sink, above its floor). A collider
    /// with a larger skin keeps it. Finite and at least 0 ([`Guard::new`](super::Guard::new)
    /// checks it). Default: `DEFAULT_SKIN`.
    pub skin: Real,
    /// The deepest overlap the guard lets rapier's step take two meshes to,
    /// as a multiple of rapier's allowed linear error (without skins): an
    /// arriving pair that could close farther after its contact is stopped
    /// there, and a touching pair found deeper at a step's end is pushed
    /// apart. A body thinner than twice this depth can be crossed by a slow
    /// arrival: lower it, or ask for a skin. Finite and above 0
    /// ([`Guard::new`](super::Guard::new) checks it). Default: `DEFAULT_TOLERATED_DEPTH`.
    pub tolerated_depth: Real,
    /// How many times per step [`Guard::step`](super::Guard::step) may move the world back to a
    /// contact and let rapier solve from there; after that, arrivals hold
    /// their dynamic bodies at their contacts for the rest of the step.
    /// Default: `DEFAULT_MAX_SUBSTEPS`.
    pub max_substeps: usize,
}

/// How far outside a ball, capsule or cylinder collider its swept
/// polyhedron may stand, as a fraction of the contact skin (of rapier's
/// allowed linear error when the skin is 0): `0.25`.
pub(crate) const BALL_EXCESS_OF_SKIN: Real = 0.25;

/// [`GuardOptions::skin`](super::GuardOptions::skin)'s default: `0`, no skin (rapier's contacts as they
/// are).
pub(crate) const DEFAULT_SKIN: Real = 0.0;

/// [`GuardOptions::tolerated_depth`](super::GuardOptions::tolerated_depth)'s default: `1.0`, rapier's allowed
/// linear error (0.005 × `length_unit`), which its soft contacts keep
/// resting pairs within.
pub(crate) const DEFAULT_TOLERATED_DEPTH: Real = 1.0;

/// What a touching pair found deeper than the tolerated depth is pushed
/// back to, as a fraction of it: `0.5` (room for rapier's next step).
pub(crate) const PUSHED_DEPTH_FRACTION: Real = 0.5;

/// [`GuardOptions::max_substeps`](super::GuardOptions::max_substeps)'s default.
pub(crate) const DEFAULT_MAX_SUBSTEPS: usize = 4;

/// [`RunOptions::parallel_narrow_phase_seconds`](crate::stepper::RunOptions::parallel_narrow_phase_seconds) under a guard: between
/// two of its sweeps rapier steps on one thread and rayon's threads fall
/// asleep, so waking them costs more than under the stepper's own loop,
/// and their spinning afterwards slows rapier's step (measured on the
/// 1,000-body box: `docs/benchmarks-history.md`). Seconds.
pub(crate) const PARALLEL_NARROW_PHASE_SECONDS: Real = 3e-4;

impl Default for GuardOptions {
    fn default() -> Self {
        GuardOptions {
            ccd: CcdOptions::default(),
            kernel: DistanceKernel::Exact,
            parallel: true,
            skin: DEFAULT_SKIN,
            tolerated_depth: DEFAULT_TOLERATED_DEPTH,
            max_substeps: DEFAULT_MAX_SUBSTEPS,
        }
    }
}

impl GuardOptions {
    /// The contact skin of each guarded collider under `parameters`
    /// (rapier3d-f64's; under an f32 rapier it is the same product,
    /// `skin × parameters.allowed_linear_error()`).
    pub fn skin_under(&self, parameters: &IntegrationParameters) -> Real {
        self.skin * parameters.allowed_linear_error()
    }

    /// The tolerated depth under `parameters` (rapier3d-f64's; under an f32
    /// rapier the same product).
    pub fn tolerated_depth_under(&self, parameters: &IntegrationParameters) -> Real {
        self.tolerated_depth * parameters.allowed_linear_error()
    }
}

/// The largest contact distance the CCD may have under a guard whose
/// colliders have the contact skin `skin` (each): the two skins, within
/// which rapier holds a pair, or without skins rapier's
/// `prediction_distance`.
pub(crate) fn contact_distance_limit(prediction_distance: Real, skin: Real) -> Real {
    if skin > 0.0 {
        two_skins(skin)
    } else {
        prediction_distance
    }
}

/// How far apart rapier holds two touching colliders of contact skin
/// `skin` each: the guard reports a contact there.
pub(super) fn two_skins(skin: Real) -> Real {
    2.0 * skin
}

/// Whether a `Simulate` scene's bodies fit the guard under rapier's default
/// parameters and the scene's `skin` (a multiple of rapier's allowed linear
/// error): `Err((body, contact distance, limit))` when the largest pair's
/// contact distance is not below the skins, or without skins rapier's
/// prediction distance (`body` is the one whose radius sets it).
pub(crate) fn simulate_contact_limit(
    ccd: &CcdOptions,
    bodies: &[Body],
    skin: Real,
) -> Result<(), (String, Real, Real)> {
    let parameters = IntegrationParameters::default();
    let options = GuardOptions { skin, ..GuardOptions::default() };
    let limit = contact_distance_limit(parameters.prediction_distance(), options.skin_under(&parameters));
    contact_within(ccd, bodies.iter(), limit)
}

/// [`simulate_contact_limit`] for any bodies and limit.
pub(super) fn contact_within<'a>(
    ccd: &CcdOptions,
    bodies: impl Iterator<Item = &'a Body> + Clone,
    limit: Real,
) -> Result<(), (String, Real, Real)> {
    let radius =
        largest_pair_radius(bodies.clone().map(|b| (b.mesh.radius(), b.motion == BodyMotion::Fixed)));
    let contract = ContactContract::of(ccd, ContactRule::ScaleRelative, radius, 0.0);
    if contract.contact_distance < limit {
        return Ok(());
    }
    let mut bodies = bodies;
    let body = bodies.find(|b| b.mesh.radius() == radius).map_or(String::new(), |b| b.name.clone());
    Err((body, contract.contact_distance, limit))
}

/// The largest radius that sets a pair's contact distance: over the pairs
/// not both fixed, the larger of their smaller radii (`(radius, fixed)` per
/// body). 0 without such a pair.
pub(crate) fn largest_pair_radius(bodies: impl Iterator<Item = (Real, bool)>) -> Real {
    // The two largest radii of all bodies, and the largest of a movable one.
    let (mut first, mut second, mut movable) = (0.0, 0.0, None::<Real>);
    for (radius, fixed) in bodies {
        if radius > first {
            second = first;
            first = radius;
        } else if radius > second {
            second = radius;
        }
        if !fixed {
            movable = Some(movable.map_or(radius, |m: Real| m.max(radius)));
        }
    }
    // A movable body pairs with every other: its smaller radius against the
    // largest other body is min(r, first) when it is not the largest, and
    // min(r, second) when it is.
    match movable {
        None => 0.0,
        Some(m) if m >= first => second.min(m),
        Some(m) => m,
    }
}

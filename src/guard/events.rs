//! What the guard reports: the events of a step, and its errors.

use rapier3d_f64::prelude::RigidBodyHandle;

use crate::math::Real;
use crate::stepper::Contact;

/// What the guard saw in a step (`H`: rapier's body handle).
#[non_exhaustive]
#[derive(Clone, Debug, PartialEq)]
pub enum GuardEvent<H = RigidBodyHandle> {
    /// Two guarded bodies came into contact within the step (and the
    /// dynamic ones among them were moved back to their poses at that
    /// time).
    Started {
        /// The first body.
        a: H,
        /// The second body.
        b: H,
        /// The contact: time (since the guard's first step), distance,
        /// points (world frame), features and the contact contract.
        contact: Box<Contact>,
    },
    /// Two bodies in contact separated by the step's end (farther apart
    /// than the two skins and rapier's prediction distance): apart again,
    /// swept for their next contact.
    Stopped {
        /// The first body.
        a: H,
        /// The second body.
        b: H,
    },
    /// Two touching bodies that rapier's contact let sink deeper than the
    /// tolerated depth by the step's end (a body squeezed by a kinematic
    /// one, a load rapier's solver could not carry).
    Overlap {
        /// The first body.
        a: H,
        /// The second body.
        b: H,
        /// How deep they overlapped (convex meshes: exactly; others: the
        /// deepest vertex where their surfaces cross).
        depth: Real,
        /// Whether the guard pushed them apart to half the tolerated depth
        /// (their dynamic bodies, by their inverse masses, and their
        /// approach along the push removed); `false` when neither is
        /// dynamic.
        pushed_apart: bool,
    },
}

/// What can go wrong (`H`: rapier's body handle).
#[non_exhaustive]
#[derive(Debug, thiserror::Error)]
pub enum GuardError<H: std::fmt::Debug = RigidBodyHandle> {
    /// A guarded handle is not in the body set.
    #[error("rigid body {0:?} is not in the body set")]
    UnknownBody(H),
    /// A body's colliders give no mesh the guard can sweep.
    #[error("{body}: {message}")]
    Shape {
        /// The body, as messages name it (`rigid body #3`; under a scene,
        /// ``body `name` ``).
        body: String,
        /// What is wrong.
        message: String,
    },
    /// The CCD's contact distance (the wall) is not below the two
    /// colliders' contact skins (without skins: rapier's prediction
    /// distance).
    #[error("the CCD's contact distance ({contact_distance:e}, for a pair with body {body}) is not below the two colliders' contact skins ({limit:e}): the wall would lie outside rapier's contact; lower `GuardOptions::ccd.distance_tolerance` or raise `GuardOptions::skin`")]
    ContactDistance {
        /// The body whose radius sets the largest pair's contact distance.
        body: String,
        /// That contact distance.
        contact_distance: Real,
        /// The skins' sum (or rapier's prediction distance).
        limit: Real,
    },
    /// [`GuardOptions::skin`](super::GuardOptions::skin) is negative or not finite.
    #[error("GuardOptions::skin must be a finite multiple of rapier's allowed linear error, at least 0; found {0}")]
    Skin(Real),
    /// [`GuardOptions::tolerated_depth`](super::GuardOptions::tolerated_depth) is not above 0 or not finite.
    #[error("GuardOptions::tolerated_depth must be a finite multiple of rapier's allowed linear error, above 0; found {0}")]
    ToleratedDepth(Real),
    /// [`Guard::set_bodies`](super::Guard::set_bodies) on a guard not made by [`Guard::new`](super::Guard::new).
    #[error("set_bodies needs a guard made by Guard::new")]
    NotFromRapier,
    /// `after_step` without `before_step`.
    #[error("after_step was called without before_step")]
    NoStartPoses,
    /// A pair's CCD ran out of iterations: it is proven apart only up to
    /// `time`, and the guard cannot say what happened after.
    #[error("the CCD of bodies {a:?} and {b:?} could not decide after {iterations} iterations (proven apart up to t = {time}): raise `GuardOptions::ccd.max_iterations`")]
    Undecided {
        /// The first body.
        a: H,
        /// The second body.
        b: H,
        /// Proven apart up to this time (since the guard's first step).
        time: Real,
        /// The CCD iterations made.
        iterations: usize,
    },
}

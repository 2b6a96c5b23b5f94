//! A body's colliders as the guard reads them, and the contact hooks they
//! let the application run.

use super::views::ShapePart;
use crate::math::Pose;

/// Whether a body's colliders let the application decide their contacts
/// (rapier's `ActiveHooks`), the strongest of its solid colliders'.
#[derive(Copy, Clone, Debug, PartialEq, Eq, PartialOrd, Ord)]
pub enum ContactHooks {
    /// No hook: rapier's rules alone decide.
    None,
    /// `FILTER_CONTACT_PAIRS`: the application's filter keeps or drops
    /// each pair ([`Guard::step_with_hooks`](super::Guard::step_with_hooks)
    /// asks it too).
    Filter,
    /// `MODIFY_SOLVER_CONTACTS`: the application may drop or change the
    /// contacts themselves (a one-way platform): the guard cannot know which
    /// it keeps, and leaves the body's pairs to rapier.
    Modify,
}

/// One collider of a body as the guard reads it.
#[derive(Clone, Debug, PartialEq)]
pub struct ColliderPart {
    /// The collider in messages (`collider #5`).
    pub name: String,
    /// Its pose in the body frame.
    pub frame: Pose,
    /// Its shape.
    pub shape: ShapePart,
    /// Whether rapier's solver meets it: enabled and not a sensor.
    pub solid: bool,
}

//! A pair's closest approach over a run, as the run's result lists it.

use crate::math::{Pose, Real};
use crate::mesh::MeshDistance;

/// A pair's closest approach over a run.
#[derive(Clone, Debug, PartialEq)]
pub struct NearMiss {
    /// The first body (index, smaller).
    pub body_a: usize,
    /// The second body.
    pub body_b: usize,
    /// The smallest distance found, reached at `time` (the bracket's upper
    /// end).
    pub distance: Real,
    /// The pair is never closer than this over the run (certified; but for
    /// the rest of a step after either body's contact, see the module).
    pub lower: Real,
    /// When `distance` is reached.
    pub time: Real,
    /// The closest points (world frame), triangles and features at `time`.
    pub closest: MeshDistance,
    /// The pose of `body_a`'s frame (its mesh's frame) at `time`.
    pub pose_a: Pose,
    /// The pose of `body_b`'s frame at `time`.
    pub pose_b: Pose,
    /// Every step's bracket closed; `false` if a step's CCD ran out of
    /// iterations (the bracket holds, perhaps wider than the tolerance).
    pub decided: bool,
}

/// The most steps of one pair held before they are bracketed: `64` (a
/// pair that keeps approaching is bracketed once per this many steps).
pub(crate) const MAX_HELD_STEPS: usize = 64;

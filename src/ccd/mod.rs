//! Continuous collision detection (CCD).
//!
//! ## What is CCD?
//! Discrete collision detection looks at the world at the end of each step
//! and misses whatever passed through something during it (tunnelling). CCD
//! asks when, during the step, two moving things first touch.
//!
//! ## Linear-vertex queries
//! [`vertex_face_time_of_impact`] and [`edge_edge_time_of_impact`] take
//! primitives whose vertices each move in a straight line over the
//! normalised step `t ∈ [0, 1]` (the standard benchmark model; the triangle
//! may deform). They run conservative advancement along separating axes
//! (`advance.rs`) and along the plane of the two edges or of the face,
//! which turns with them (`swept_plane.rs`): every step is proven
//! contact-free, so `None` always means no contact and a reported time is
//! never late.
//!
//! ## Rigid mesh pairs
//! [`mesh_time_of_impact`] takes two triangle meshes, each moving with
//! constant linear and angular velocity over a step, and advances by a
//! second-order bound of each triangle pair's motion along its own
//! separating direction, in the world and in a frame turning with its
//! closest features (`mesh_bound.rs`), the smallest over all pairs found
//! on a front through both BVHs that is kept between the steps
//! (`mesh_search.rs`); `mesh_pair.rs` is the front door and the loop.
//!
//! ## The contact contract
//! `contact.rs` is the one place that turns options and a query's size into
//! the contact distance (`minimum_separation + tolerance`) and the level
//! every advancement step keeps above (`minimum_separation + tolerance / 2`);
//! the broad phase's box margin and the `Bounce` response use it too.
//!
//! ## Caveats
//! - A reported time may be early by the time the primitives need to close
//!   the contact distance (`minimum_separation` plus the relative
//!   `distance_tolerance` of [`CcdOptions`]); two primitives that pass
//!   within that distance without touching are reported as a contact (a
//!   false positive, within the tolerance).
//! - A linear-vertex query that runs out of iterations reports contact
//!   where it stopped ([`CcdStatus::OutOfIterations`]): conservative,
//!   possibly a false positive. A mesh query reports the same status with
//!   the time reached; the stepper treats it as undecided (never a contact)
//!   and stops the run there.
//! - A NaN or infinite coordinate gives contact at `t = 0`
//!   ([`CcdStatus::NonFiniteInput`]), never a silent "no contact".

mod advance;
mod closest_approach;
mod contact;
mod convex_measure;
mod descent;
mod edge_edge;
mod hull_advance;
mod hull_gap;
mod mesh_bound;
mod mesh_pair;
mod mesh_search;
mod options;
mod pair_motion;
mod posed_pair;
mod query;
mod simplex;
mod spin_sweep;
mod swept_plane;
mod vertex_face;

pub use advance::ROUNDING_FLOOR_ULPS;
#[cfg(test)]
pub(crate) use closest_approach::BUDGET_GROWTH;
pub(crate) use closest_approach::PROOF_MARGIN_FRACTION;
pub use closest_approach::{
    closest_approach, ApproachStatus, ClosestApproach, ClosestApproachQuery, DEFAULT_APPROACH_TOLERANCE,
};
pub(crate) use closest_approach::{screen as screen_approach, Run as ApproachRun};
#[cfg(test)]
pub(crate) use contact::BOX_MARGIN_TOLERANCE_FACTOR;
pub use contact::{box_margin, ContactContract, ContactRule, TARGET_FRACTION};
pub(crate) use convex_measure::measure as distance_at;
pub use edge_edge::{edge_edge_time_of_impact, edge_edge_time_of_impact_detailed};
pub use hull_gap::WarmSimplex;
pub(crate) use hull_gap::{convex_distance, first_within, hull_gap, hull_gap_from, ConvexDistance};
#[cfg(test)]
pub(crate) use mesh_bound::{SPIN_SWEEP_AFTER_ITERATIONS, SPIN_SWEEP_MAX_RATE_FRACTION, SPIN_SWEEP_MIN_TURN};
pub use mesh_pair::mesh_time_of_impact;
#[cfg(test)]
pub(crate) use mesh_search::{OPEN_RATIO, STEP_SLACK};
pub use options::{CcdOptions, CcdResult, CcdStatus};
#[cfg(test)]
pub(crate) use pair_motion::INTEGRATED_JUMP_ULPS;
pub use query::{MeshCcdQuery, MeshCcdResult, MeshCcdScratch, MovingMesh, WarmStart};
#[cfg(test)]
pub(crate) use swept_plane::PLANE_ROUNDING_ULPS;
pub use vertex_face::{vertex_face_time_of_impact, vertex_face_time_of_impact_detailed};

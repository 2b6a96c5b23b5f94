//! Options, statuses and detailed results of the CCD queries.

use crate::math::Real;

/// Tolerances and limits of a CCD query.
#[derive(Copy, Clone, Debug, PartialEq)]
pub struct CcdOptions {
    /// Contact is reported once the distance is at most
    /// `minimum_separation + distance_tolerance × S`, where `S` is the
    /// diagonal of the query's bounding box over the whole step (so the
    /// tolerance is **relative to the query's size**). The reported time is
    /// then never later than the true first contact, and earlier by at most
    /// the time the primitives take to close that distance. The tolerance
    /// used is never below [`ROUNDING_FLOOR_ULPS`](super::ROUNDING_FLOOR_ULPS)
    /// ulps of the largest coordinate: the conservative steps need that much
    /// margin over rounding. For rigid mesh pairs
    /// ([`mesh_time_of_impact`](super::mesh_time_of_impact)) `S` is the
    /// smaller of the meshes' radii about their centres of mass, and the
    /// floor is taken on the pair's own scale (see that function's module).
    /// Every approach closer than `minimum_separation +
    /// distance_tolerance × S / 2` is reported. The
    /// rule is computed in one place: [`ContactContract`](super::ContactContract).
    /// Default: `1e-6`.
    pub distance_tolerance: Real,
    /// An absolute gap that counts as contact (for thickness or a safety
    /// margin): contact is reported when the primitives come within this
    /// distance (plus the tolerance). Default: `0.0` (touching).
    pub minimum_separation: Real,
    /// The most advancement steps before giving up; a query that runs out
    /// reports contact at the time reached so far (conservative: never
    /// late) with status [`CcdStatus::OutOfIterations`]. Default: `10_000`.
    pub max_iterations: usize,
}

impl Default for CcdOptions {
    fn default() -> Self {
        CcdOptions { distance_tolerance: 1e-6, minimum_separation: 0.0, max_iterations: 10_000 }
    }
}

/// How a CCD query ended.
#[non_exhaustive]
#[derive(Copy, Clone, Debug, PartialEq, Eq, Hash)]
pub enum CcdStatus {
    /// Separated over the whole step: no contact in `[0, 1]`.
    Separated,
    /// Came within the contact distance at the reported time.
    Converged,
    /// Within the contact distance already at `t = 0`.
    InitiallyTouching,
    /// Ran out of iterations; contact is reported (conservatively) at the
    /// time reached.
    OutOfIterations,
    /// A filter over the whole step (bounding boxes or a fixed separating
    /// axis) proved there is no contact, before any iteration.
    Filtered,
    /// A coordinate was NaN or infinite: contact is reported at `t = 0`
    /// (conservative: a CCD must not answer "no contact" to what it cannot
    /// measure).
    NonFiniteInput,
}

impl CcdStatus {
    /// Every status, in declaration order.
    pub const ALL: [CcdStatus; 6] = [
        CcdStatus::Separated,
        CcdStatus::Converged,
        CcdStatus::InitiallyTouching,
        CcdStatus::OutOfIterations,
        CcdStatus::Filtered,
        CcdStatus::NonFiniteInput,
    ];

    /// Its name in files (`summary.json`'s `status`) and messages: written
    /// out here, so that renaming a variant does not change the file format.
    pub fn name(self) -> &'static str {
        match self {
            CcdStatus::Separated => "Separated",
            CcdStatus::Converged => "Converged",
            CcdStatus::InitiallyTouching => "InitiallyTouching",
            CcdStatus::OutOfIterations => "OutOfIterations",
            CcdStatus::Filtered => "Filtered",
            CcdStatus::NonFiniteInput => "NonFiniteInput",
        }
    }
}

/// The detailed result of a CCD query.
#[derive(Copy, Clone, Debug, PartialEq)]
pub struct CcdResult {
    /// The time of first contact in `[0, 1]`, or `None` for no contact.
    pub time_of_impact: Option<Real>,
    /// How the iteration ended.
    pub status: CcdStatus,
    /// The distance at the reported time (at `t = 1` without contact).
    pub distance: Real,
    /// The contact distance that was used: `minimum_separation +
    /// distance_tolerance × S`; no contact is reported farther than this.
    pub contact_distance: Real,
    /// Every approach closer than this (`minimum_separation +
    /// distance_tolerance × S / 2`, the advancement's target) is reported.
    pub guaranteed_distance: Real,
    /// Advancement steps taken.
    pub iterations: usize,
}

//! The two bodies of a query moving together: their relative pose, their
//! bounding spheres, their contract.

use super::advance::ROUNDING_FLOOR_ULPS;
use super::contact::{ContactContract, ContactRule};
use super::options::{CcdOptions, CcdStatus};
use super::query::{MeshCcdQuery, MovingMesh};
use crate::math::{Pose, Real};
use crate::mesh::MeshDistance;
use crate::motion::StepMotion;

/// The ulps of an integrated body's coordinates by which its path may jump
/// between one step's end and the next step's start (the step's velocity
/// is `(x1 − x0) / dt`, and `x0 + v dt` rounds back to `x1` only to a few
/// ulps); the tolerance never drops below them.
pub(crate) const INTEGRATED_JUMP_ULPS: Real = 8.0;

/// Where the advancement stopped: the time, how, and the triangle pair
/// there (the contact's, or the last limiting one when the iterations ran
/// out).
pub(super) struct Reached {
    pub(super) time: Real,
    pub(super) status: CcdStatus,
    pub(super) pair: Option<(usize, usize)>,
    /// That pair's distance at `time`, where it was measured there
    /// already (in `a`'s frame).
    pub(super) measured: Option<MeshDistance>,
}

/// The two bodies of a query and what bounds their motion over the step.
pub(super) struct PairMotion<'a> {
    pub(super) a: MovingMesh<'a>,
    pub(super) b: MovingMesh<'a>,
    /// The interval's length.
    pub(super) duration: Real,
    /// The meshes' radii about their centres of mass.
    pub(super) ra: Real,
    pub(super) rb: Real,
    /// The head-on bound of any point's approach speed
    /// `|v_a − v_b| + |ω_a| r_a + |ω_b| r_b`.
    pub(super) speed: Real,
    /// The rounding floor of the pair's distances.
    pub(super) floor: Real,
}

impl<'a> PairMotion<'a> {
    pub(super) fn of(a: &MovingMesh<'a>, b: &MovingMesh<'a>, duration: Real) -> PairMotion<'a> {
        let (ra, rb) = (a.mesh.radius(), b.mesh.radius());
        let speed = (a.motion.velocity - b.motion.velocity).norm()
            + a.motion.angular_velocity.norm() * ra
            + b.motion.angular_velocity.norm() * rb;
        // Rounding: distances are computed in a's frame from the difference
        // of the reference positions, so they round relative to the pair's
        // own scale; an integrated body's path can also jump by a few ulps
        // of its coordinates between steps.
        let relative_size = StepMotion::center_offset(a.motion, b.motion, 0.0).norm()
            + (a.motion.velocity - b.motion.velocity).norm() * duration
            + a.motion.travel(duration)
            + b.motion.travel(duration)
            + ra
            + rb;
        let jumps = [a.motion, b.motion]
            .iter()
            .filter(|m| m.integrated)
            .map(|m| m.reference.translation.vector.amax() + m.velocity.amax() * duration)
            .sum::<Real>();
        let floor = Real::EPSILON * (ROUNDING_FLOOR_ULPS * relative_size + INTEGRATED_JUMP_ULPS * jumps);
        PairMotion { a: *a, b: *b, duration, ra, rb, speed, floor }
    }

    /// The pair's contact contract under `options` and `rule`: scaled by
    /// the smaller body (where the contact happens), floored by the
    /// rounding of the pair's coordinates.
    pub(super) fn contract(&self, options: &CcdOptions, rule: ContactRule) -> ContactContract {
        ContactContract::of(options, rule, self.ra.min(self.rb), self.floor)
    }

    /// The distance between the bounding spheres at `s` (negative where
    /// they overlap).
    pub(super) fn spheres_at(&self, s: Real) -> Real {
        StepMotion::center_offset(self.a.motion, self.b.motion, s).norm() - self.ra - self.rb
    }

    /// `b`'s pose in `a`'s frame at `s`.
    pub(super) fn relative_pose(&self, s: Real) -> Pose {
        StepMotion::relative_pose(self.a.motion, self.b.motion, s)
    }
}

/// The bounding spheres' centres move linearly, so the smallest distance
/// between them over the step is exact: if it (or the carried
/// `lower_bound` less what the motion can close) stays above `target`, the
/// pair is apart, and this is a lower bound on its distance at the end.
pub(super) fn spheres_apart(pair: &PairMotion<'_>, lower_bound: Option<Real>, target: Real) -> Option<Real> {
    let offset = StepMotion::center_offset(pair.a.motion, pair.b.motion, 0.0);
    let relative = pair.b.motion.velocity - pair.a.motion.velocity;
    let closest_approach = if relative.norm_squared() > 0.0 {
        (-offset.dot(&relative) / relative.norm_squared()).clamp(0.0, pair.duration)
    } else {
        0.0
    };
    let carried = lower_bound.unwrap_or(Real::NEG_INFINITY).max(pair.spheres_at(0.0));
    let closed = carried - pair.speed * pair.duration;
    (pair.spheres_at(closest_approach) > target || closed > target)
        .then(|| closed.max(pair.spheres_at(pair.duration)))
}

impl MeshCcdQuery<'_> {
    /// The contract the query is decided under (its contact distance, from
    /// its rule, the smaller radius and the rounding floor of its motions):
    /// a pair certified farther than `contract().contact_distance` over the
    /// interval by any other means is one this query finds apart.
    pub fn contract(&self) -> ContactContract {
        PairMotion::of(&self.a, &self.b, self.duration).contract(&self.options, self.contact)
    }
}

//! A fast spin's first check: the solids the bodies sweep turning about
//! their axes over the whole step.

use super::mesh_bound::SPIN_SWEEP_MIN_TURN;
use super::pair_motion::PairMotion;
use super::query::MovingMesh;
use crate::math::{Real, Vector};
use crate::motion::StepMotion;

/// Whether the solids the two bodies sweep over the step stay more than
/// `target` apart (to the pair's rounding floor), checked only when the
/// bodies turn at least [`SPIN_SWEEP_MIN_TURN`] radians over it (where the
/// rate bounds, which grow with the spin, would take tiny steps).
///
/// A body turning with constant `ω` about its centre of mass keeps each
/// vertex's height `h` along the spin axis `k` and its distance `ρ` from
/// it: whatever the turn, the mesh stays inside the cylinder about the axis
/// through the moving centre with the vertices' extreme heights and
/// largest `ρ` (one pass over the vertices), whose support along a unit
/// direction `u` is `(u·k) h_max|min + |u − (u·k) k| ρ_max`. A body that
/// does not turn keeps its own box. The gap between the two along a fixed
/// `u` changes with the centres' relative velocity only, linearly: above
/// `target` at both ends of the step, it is above it over all of it.
/// Directions tried: the centre line at both ends, its part across each
/// spin axis, the spin axes, the world axes.
pub(super) fn spin_swept_apart(pair: &PairMotion<'_>, target: Real) -> bool {
    let (a, b) = (pair.a, pair.b);
    let (wa, wb) = (a.motion.angular_velocity, b.motion.angular_velocity);
    if (wa.norm() + wb.norm()) * pair.duration < SPIN_SWEEP_MIN_TURN {
        return false;
    }
    let (region_a, region_b) = (SweptRegion::of(&a), SweptRegion::of(&b));
    let ends = [
        StepMotion::center_offset(a.motion, b.motion, 0.0),
        StepMotion::center_offset(a.motion, b.motion, pair.duration),
    ];
    let across = |region: &SweptRegion, d: &Vector| match region {
        SweptRegion::Cylinder { axis, .. } => d - axis * axis.dot(d),
        SweptRegion::Box { .. } => Vector::zeros(),
    };
    let axis = |region: &SweptRegion| match region {
        SweptRegion::Cylinder { axis, .. } => *axis,
        SweptRegion::Box { .. } => Vector::zeros(),
    };
    let mut directions = [Vector::zeros(); 11];
    directions[..2].copy_from_slice(&ends);
    for (k, end) in ends.iter().enumerate() {
        directions[2 + k] = across(&region_a, end);
        directions[4 + k] = across(&region_b, end);
    }
    directions[6] = axis(&region_a);
    directions[7] = axis(&region_b);
    for k in 0..3 {
        directions[8 + k] = Vector::ith(k, 1.0);
    }
    directions.iter().filter(|u| u.norm() > 0.0).any(|u| {
        // From a towards b.
        let u = u.normalize() * if u.dot(&ends[0]) < 0.0 { -1.0 } else { 1.0 };
        let reach = region_a.support(&u) + region_b.support(&-u);
        ends.iter().all(|end| u.dot(end) - reach > target + pair.floor)
    })
}

/// The region a body's mesh stays in over a step, about its centre of
/// mass (see [`spin_swept_apart`]).
pub(super) enum SweptRegion {
    /// A turning body: the cylinder about its spin axis (unit) holding its
    /// vertices' heights `low..high` along it and distances up to `radius`
    /// from it.
    Cylinder { axis: Vector, low: Real, high: Real, radius: Real },
    /// A body that does not turn: its own box (its frame's `rotation`, the
    /// box's centre and half extents in that frame).
    Box { rotation: nalgebra::UnitQuaternion<Real>, center: Vector, half: Vector },
}

impl SweptRegion {
    pub(super) fn of(body: &MovingMesh<'_>) -> SweptRegion {
        let rotation = body.motion.pose_at(0.0).rotation;
        let w = body.motion.angular_velocity;
        if w.norm() == 0.0 {
            let (lo, hi) = body.mesh.bounds();
            return SweptRegion::Box {
                rotation,
                center: (lo.coords + hi.coords) / 2.0,
                half: (hi - lo) / 2.0,
            };
        }
        let axis = w.normalize();
        // In the body's frame: the same heights and distances, one rotation.
        let local = rotation.inverse() * axis;
        let (mut low, mut high, mut radius_squared) = (Real::INFINITY, Real::NEG_INFINITY, 0.0 as Real);
        for v in body.mesh.vertices() {
            let h = local.dot(&v.coords);
            (low, high) = (low.min(h), high.max(h));
            radius_squared = radius_squared.max(v.coords.norm_squared() - h * h);
        }
        // A few ulps for the subtraction above.
        let radius = radius_squared.max(0.0).sqrt() * (1.0 + 4.0 * Real::EPSILON)
            + 4.0 * Real::EPSILON * body.mesh.radius();
        SweptRegion::Cylinder { axis, low, high, radius }
    }

    /// The farthest the region reaches along the unit direction `u`, from
    /// the centre of mass.
    pub(super) fn support(&self, u: &Vector) -> Real {
        match self {
            SweptRegion::Cylinder { axis, low, high, radius } => {
                let along = u.dot(axis);
                along * if along > 0.0 { *high } else { *low } + (u - axis * along).norm() * radius
            }
            SweptRegion::Box { rotation, center, half } => {
                let local = rotation.inverse() * u;
                local.dot(center) + local.abs().dot(half)
            }
        }
    }
}

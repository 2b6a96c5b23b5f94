//! What the guard reads of a rapier body, in nearmiss's f64 types: its
//! view, kind and pose about its centre of mass, and its shapes.

use crate::math::{Point, Pose, Real, Vector};

/// What the guard reads of a rapier body, in nearmiss's f64 types.
#[derive(Copy, Clone, Debug, PartialEq)]
pub struct BodyView {
    /// The body frame's pose.
    pub pose: Pose,
    /// The centre of mass's linear velocity.
    pub linvel: Vector,
    /// The angular velocity.
    pub angvel: Vector,
    /// The centre of mass in the body frame.
    pub center: Vector,
    /// The inverse of its mass (0 for fixed and kinematic bodies, and for a
    /// dynamic body without mass).
    pub inverse_mass: Real,
    /// The inverse of its inertia tensor about its centre of mass, world
    /// frame (0 where `inverse_mass` is).
    pub inverse_inertia: nalgebra::Matrix3<Real>,
    /// How rapier moves it.
    pub kind: BodyKind,
}

/// How rapier moves a body.
#[derive(Copy, Clone, Debug, PartialEq, Eq)]
pub enum BodyKind {
    /// Never moves.
    Fixed,
    /// Moved by forces and contacts.
    Dynamic {
        /// rapier has put it to sleep.
        sleeping: bool,
    },
    /// Moved by the application (infinite mass).
    Kinematic {
        /// Driven by next poses (`KinematicPositionBased`), not velocities.
        position_based: bool,
    },
}

impl BodyView {
    /// The pose of the body's centre of mass.
    pub fn center_pose(&self) -> Pose {
        center_pose(&self.pose, &self.center)
    }
}

/// The pose of a body's centre of mass (`center`, body frame) when the body
/// frame is at `pose`.
pub(crate) fn center_pose(pose: &Pose, center: &Vector) -> Pose {
    if *center == Vector::zeros() {
        // The body frame's origin (a scene body's, by construction).
        return *pose;
    }
    Pose::from_parts((pose.translation.vector + pose.rotation * center).into(), pose.rotation)
}

/// The body-frame pose whose centre of mass (`center`) is at `center_pose`.
pub(crate) fn body_pose(center_pose: &Pose, center: &Vector) -> Pose {
    let rotation = center_pose.rotation;
    Pose::from_parts((center_pose.translation.vector - rotation * center).into(), rotation)
}

/// One collider shape as the guard sweeps it, in f64 whatever rapier's
/// precision.
#[derive(Clone, Debug, PartialEq)]
pub enum ShapePart {
    /// Triangles (a triangle mesh, a convex polyhedron's or a cuboid's
    /// faces).
    Triangles(Vec<Point>, Vec<[u32; 3]>),
    /// A ball about the shape's origin.
    Ball(Real),
    /// A capsule: the points within `radius` of the segment `a`–`b`.
    Capsule {
        /// The segment's first end.
        a: Point,
        /// The segment's second end.
        b: Point,
        /// The radius.
        radius: Real,
    },
    /// A cylinder along y about the origin.
    Cylinder {
        /// Half its height.
        half_height: Real,
        /// The radius.
        radius: Real,
    },
    /// Parts at poses.
    Compound(Vec<(Pose, ShapePart)>),
    /// The solid below a plane through the origin (a half-space).
    HalfSpace {
        /// The plane's outward unit normal.
        normal: Vector,
    },
    /// A shape the guard does not sweep (rapier's name of its type).
    Other(String),
}

/// A rapier quaternion (`[w, x, y, z]`, widened) as a rotation: taken as it
/// is when it is unit to f64's rounding (so an f64 body's pose keeps every
/// bit), renormalised in f64 otherwise (an f32 quaternion is unit only to
/// f32's rounding, which would scale what it turns by up to 1e-7).
pub(crate) fn unit_quaternion([w, x, y, z]: [Real; 4]) -> nalgebra::UnitQuaternion<Real> {
    let q = nalgebra::Quaternion::new(w, x, y, z);
    if (q.norm_squared() - 1.0).abs() <= UNIT_QUATERNION_TOLERANCE {
        nalgebra::UnitQuaternion::new_unchecked(q)
    } else {
        nalgebra::UnitQuaternion::from_quaternion(q)
    }
}

/// How far from 1 a widened quaternion's squared norm may be for
/// [`unit_quaternion`] to take it as it is: 8 f64 epsilons.
pub(crate) const UNIT_QUATERNION_TOLERANCE: Real = 8.0 * Real::EPSILON;

//! Scalar and geometry types used throughout nearmiss, and the conversions to
//! the glam types of parry (the peer), which appear only at that boundary.

/// The scalar type of every computation in nearmiss.
pub type Real = f64;
/// A point in 3-D space.
pub type Point = nalgebra::Point3<Real>;
/// A displacement in 3-D space.
pub type Vector = nalgebra::Vector3<Real>;
/// A rigid pose (rotation then translation).
pub type Pose = nalgebra::Isometry3<Real>;

/// A triangle as its three vertices, in order.
pub type Triangle = [Point; 3];

/// A rigid pose as a rotation matrix and a translation, `p ↦ rotation · p +
/// translation`, with the matrix kept as given: for callers who hold their
/// poses as matrices (a 4 × 4 transform, a robot's forward kinematics), so
/// a query's answer is that of the pose they hold, not of a quaternion
/// rounded from it. The matrix must be a rotation to rounding (`MᵀM` within
/// a few dozen ulps of the identity); it is applied as it is.
#[derive(Copy, Clone, Debug, PartialEq)]
pub struct MatrixPose {
    /// The rotation.
    pub rotation: nalgebra::Matrix3<Real>,
    /// The translation, applied after the rotation.
    pub translation: Vector,
}

/// A pose that a query takes either way: a [`Pose`] (its quaternion's
/// rotation matrix, rounded) or a [`MatrixPose`] (its matrix as given).
pub trait Placement {
    /// The pose as a matrix and a translation.
    fn matrix_pose(&self) -> MatrixPose;

    /// The pose as a [`Pose`] (for the motions, boxes and CCD): a matrix's
    /// quaternion by Shepperd's method, rounded.
    fn pose(&self) -> Pose;
}

impl Placement for Pose {
    #[inline]
    fn matrix_pose(&self) -> MatrixPose {
        MatrixPose {
            rotation: self.rotation.to_rotation_matrix().into_inner(),
            translation: self.translation.vector,
        }
    }

    #[inline]
    fn pose(&self) -> Pose {
        *self
    }
}

impl Placement for MatrixPose {
    #[inline]
    fn matrix_pose(&self) -> MatrixPose {
        *self
    }

    fn pose(&self) -> Pose {
        let rotation = nalgebra::Rotation3::from_matrix_unchecked(self.rotation);
        Pose::from_parts(self.translation.into(), nalgebra::UnitQuaternion::from_rotation_matrix(&rotation))
    }
}

/// Converts a nalgebra point to parry's glam vector.
#[inline]
pub fn to_parry(p: &Point) -> parry3d_f64::math::Vector {
    parry3d_f64::math::Vector::new(p.x, p.y, p.z)
}

/// Converts parry's glam vector back to a nalgebra point.
#[inline]
pub fn from_parry(v: parry3d_f64::math::Vector) -> Point {
    Point::new(v.x, v.y, v.z)
}

/// Converts a triangle to parry's triangle shape.
#[inline]
pub fn triangle_to_parry(t: &Triangle) -> parry3d_f64::shape::Triangle {
    parry3d_f64::shape::Triangle::new(to_parry(&t[0]), to_parry(&t[1]), to_parry(&t[2]))
}

/// Converts a pose to parry's.
#[inline]
pub fn pose_to_parry(pose: &Pose) -> parry3d_f64::math::Pose {
    let q = pose.rotation.quaternion();
    let rotation = parry3d_f64::math::Rotation::from_xyzw(q.i, q.j, q.k, q.w);
    let t = &pose.translation.vector;
    parry3d_f64::math::Pose::from_parts(parry3d_f64::math::Vector::new(t.x, t.y, t.z), rotation)
}

/// Converts parry's pose back to a nalgebra one (the quaternion taken as
/// it is: no renormalisation, so a round trip keeps every bit).
#[inline]
pub fn pose_from_parry(pose: &parry3d_f64::math::Pose) -> Pose {
    let q = pose.rotation;
    let rotation = nalgebra::UnitQuaternion::new_unchecked(nalgebra::Quaternion::new(q.w, q.x, q.y, q.z));
    Pose::from_parts(nalgebra::Translation3::from(from_parry(pose.translation).coords), rotation)
}

/// Converts a vector to parry's.
#[inline]
pub fn vector_to_parry(v: &Vector) -> parry3d_f64::math::Vector {
    parry3d_f64::math::Vector::new(v.x, v.y, v.z)
}

/// parry's constant-velocity rigid motion (about the pose's origin, the
/// centre of mass) for a body at `pose` with these velocities.
#[inline]
pub fn motion_to_parry(
    pose: &Pose,
    velocity: &Vector,
    angular_velocity: &Vector,
) -> parry3d_f64::query::NonlinearRigidMotion {
    parry3d_f64::query::NonlinearRigidMotion::new(
        pose_to_parry(pose),
        parry3d_f64::math::Vector::ZERO,
        vector_to_parry(velocity),
        vector_to_parry(angular_velocity),
    )
}

/// The largest absolute coordinate of a set of points: the scale that
/// absolute error bounds ("a few ulps of the coordinates") refer to.
#[inline]
pub fn max_abs_coordinate(points: &[Point]) -> Real {
    points.iter().flat_map(|p| p.coords.iter()).fold(0.0, |m: Real, c| m.max(c.abs()))
}

/// A number in the shortest form that reads back to the same `f64` (what
/// messages and files quote).
pub fn shortest(value: Real) -> String {
    format!("{value:?}")
}

/// Serialises a point as `[x, y, z]` (serde's `serialize_with`).
pub(crate) fn serialize_point<S: serde::Serializer>(point: &Point, serializer: S) -> Result<S::Ok, S::Error> {
    serde::Serialize::serialize(&[point.x, point.y, point.z], serializer)
}

/// Serialises a value by its `Display` text (serde's `serialize_with`):
/// enums written by name, stable under renames of their variants.
pub(crate) fn serialize_display<T: std::fmt::Display, S: serde::Serializer>(
    value: &T,
    serializer: S,
) -> Result<S::Ok, S::Error> {
    serializer.collect_str(value)
}

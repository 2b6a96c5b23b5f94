//! The rapier builds a [`Guard`](super::Guard) drives: rapier3d-f64 (the
//! `rapier` feature) and rapier3d, whose reals are f32 (the `rapier-f32`
//! feature). Both are the same rapier 0.36 source compiled at two
//! precisions; one macro writes the guard's view of each, so the guard's
//! logic is written once, in f64 (what f32 rounding leaves of the
//! guarantee: the guard module's "f32 rapier").

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
    /// A shape the guard does not sweep (rapier's name of its type).
    Other(String),
}

/// A rapier quaternion (`[w, x, y, z]`, widened) as a rotation: taken as it
/// is when it is unit to f64's rounding (so an f64 body's pose keeps every
/// bit), renormalised in f64 otherwise (an f32 quaternion is unit only to
/// f32's rounding, which would scale what it turns by up to 1e-7).
fn unit_quaternion([w, x, y, z]: [Real; 4]) -> nalgebra::UnitQuaternion<Real> {
    let q = nalgebra::Quaternion::new(w, x, y, z);
    if (q.norm_squared() - 1.0).abs() <= UNIT_QUATERNION_TOLERANCE {
        nalgebra::UnitQuaternion::new_unchecked(q)
    } else {
        nalgebra::UnitQuaternion::from_quaternion(q)
    }
}

/// How far from 1 a widened quaternion's squared norm may be for
/// [`unit_quaternion`] to take it as it is: 8 f64 epsilons.
const UNIT_QUATERNION_TOLERANCE: Real = 8.0 * Real::EPSILON;

mod sealed {
    pub trait Sealed {}
}

/// A rapier body set the guard drives: `rapier3d_f64`'s `RigidBodySet`,
/// and with the `rapier-f32` feature `rapier3d`'s (sealed: these two).
/// Everything crosses in nearmiss's f64 types.
pub trait RapierBodies: sealed::Sealed {
    /// rapier's body handle.
    type Handle: Copy + Eq + std::fmt::Debug + Send + Sync + 'static;
    /// rapier's collider set.
    type Colliders;
    /// rapier's `IntegrationParameters`.
    type Parameters;

    /// `parameters.dt`.
    fn dt(parameters: &Self::Parameters) -> Real;
    /// `parameters.allowed_linear_error()` (0.005 × `length_unit` in rapier 0.36).
    fn allowed_linear_error(parameters: &Self::Parameters) -> Real;
    /// `parameters.prediction_distance()` (0.02 × `length_unit`).
    fn prediction_distance(parameters: &Self::Parameters) -> Real;
    /// The body `handle`, if it is in the set.
    fn view(&self, handle: Self::Handle) -> Option<BodyView>;
    /// The shapes of the body's colliders, each at its pose in the body
    /// frame.
    fn shapes(&self, colliders: &Self::Colliders, handle: Self::Handle) -> Vec<(Pose, ShapePart)>;
    /// Gives each of the body's colliders a contact skin of at least `skin`.
    fn give_skin(&self, colliders: &mut Self::Colliders, handle: Self::Handle, skin: Real);
    /// Moves the body frame to `pose`.
    fn set_pose(&mut self, handle: Self::Handle, pose: &Pose, wake_up: bool);
    /// Sets the body's velocities.
    fn set_velocities(&mut self, handle: Self::Handle, linvel: &Vector, angvel: &Vector, wake_up: bool);
    /// Wakes the body (and its island).
    fn wake_up(&mut self, handle: Self::Handle);
    /// A position-based kinematic body's pose at the step's end.
    fn set_next_kinematic_pose(&mut self, handle: Self::Handle, pose: &Pose);
}

/// The guard's view of one rapier build: `$rapier` the crate, `$real` its
/// real type.
macro_rules! rapier_bodies {
    ($rapier:ident, $real:ty) => {
        impl sealed::Sealed for $rapier::prelude::RigidBodySet {}

        impl RapierBodies for $rapier::prelude::RigidBodySet {
            type Handle = $rapier::prelude::RigidBodyHandle;
            type Colliders = $rapier::prelude::ColliderSet;
            type Parameters = $rapier::prelude::IntegrationParameters;

            fn dt(parameters: &Self::Parameters) -> Real {
                Real::from(parameters.dt)
            }

            fn allowed_linear_error(parameters: &Self::Parameters) -> Real {
                Real::from(parameters.allowed_linear_error())
            }

            fn prediction_distance(parameters: &Self::Parameters) -> Real {
                Real::from(parameters.prediction_distance())
            }

            fn view(&self, handle: Self::Handle) -> Option<BodyView> {
                use $rapier::prelude::RigidBodyType;
                let body = self.get(handle)?;
                let kind = match body.body_type() {
                    RigidBodyType::Fixed => BodyKind::Fixed,
                    // A soft body's cluster proxy moves as a dynamic body.
                    RigidBodyType::Dynamic | RigidBodyType::SoftFrame => {
                        BodyKind::Dynamic { sleeping: body.is_sleeping() }
                    }
                    RigidBodyType::KinematicPositionBased => BodyKind::Kinematic { position_based: true },
                    RigidBodyType::KinematicVelocityBased => BodyKind::Kinematic { position_based: false },
                };
                Some(BodyView {
                    pose: widen_pose(body.position()),
                    linvel: widen(body.linvel()),
                    angvel: widen(body.angvel()),
                    center: widen(body.local_center_of_mass()),
                    kind,
                })
            }

            fn shapes(&self, colliders: &Self::Colliders, handle: Self::Handle) -> Vec<(Pose, ShapePart)> {
                let Some(body) = self.get(handle) else { return Vec::new() };
                body.colliders()
                    .iter()
                    .filter_map(|c| colliders.get(*c))
                    .map(|collider| {
                        let frame = collider.position_wrt_parent().map_or(Pose::identity(), widen_pose);
                        (frame, part(collider.shape()))
                    })
                    .collect()
            }

            fn give_skin(&self, colliders: &mut Self::Colliders, handle: Self::Handle, skin: Real) {
                let Some(body) = self.get(handle) else { return };
                for collider in body.colliders() {
                    if let Some(collider) = colliders.get_mut(*collider) {
                        let skin = skin as $real;
                        collider.set_contact_skin(collider.contact_skin().max(skin));
                    }
                }
            }

            fn set_pose(&mut self, handle: Self::Handle, pose: &Pose, wake_up: bool) {
                if let Some(body) = self.get_mut(handle) {
                    body.set_position(narrow_pose(pose), wake_up);
                }
            }

            fn set_velocities(
                &mut self,
                handle: Self::Handle,
                linvel: &Vector,
                angvel: &Vector,
                wake_up: bool,
            ) {
                if let Some(body) = self.get_mut(handle) {
                    body.set_linvel(narrow(linvel), wake_up);
                    body.set_angvel(narrow(angvel), wake_up);
                }
            }

            fn wake_up(&mut self, handle: Self::Handle) {
                if let Some(body) = self.get_mut(handle) {
                    body.wake_up(true);
                }
            }

            fn set_next_kinematic_pose(&mut self, handle: Self::Handle, pose: &Pose) {
                if let Some(body) = self.get_mut(handle) {
                    body.set_next_kinematic_position(narrow_pose(pose));
                }
            }
        }

        /// A rapier vector in f64.
        fn widen(v: $rapier::math::Vector) -> Vector {
            Vector::new(Real::from(v.x), Real::from(v.y), Real::from(v.z))
        }

        /// A vector in rapier's reals.
        fn narrow(v: &Vector) -> $rapier::math::Vector {
            $rapier::math::Vector::new(v.x as $real, v.y as $real, v.z as $real)
        }

        /// A rapier pose in f64 ([`unit_quaternion`]).
        fn widen_pose(pose: &$rapier::math::Pose) -> Pose {
            let q = pose.rotation;
            let rotation = unit_quaternion([q.w, q.x, q.y, q.z].map(Real::from));
            Pose::from_parts(widen(pose.translation).into(), rotation)
        }

        /// A pose in rapier's reals.
        fn narrow_pose(pose: &Pose) -> $rapier::math::Pose {
            let q = pose.rotation.quaternion();
            let rotation =
                $rapier::math::Rotation::from_xyzw(q.i as $real, q.j as $real, q.k as $real, q.w as $real);
            $rapier::math::Pose::from_parts(narrow(&pose.translation.vector), rotation)
        }

        /// A point in f64.
        fn widen_point(v: &$rapier::math::Vector) -> Point {
            Point::from(widen(*v))
        }

        /// A collider shape in f64.
        fn part(shape: &dyn $rapier::parry::shape::Shape) -> ShapePart {
            if let Some(compound) = shape.as_compound() {
                let parts = compound
                    .shapes()
                    .iter()
                    .map(|(pose, part_shape)| (widen_pose(pose), part(part_shape.as_ref())));
                return ShapePart::Compound(parts.collect());
            }
            let triangles = |(points, indices): (Vec<$rapier::math::Vector>, Vec<[u32; 3]>)| {
                ShapePart::Triangles(points.iter().map(widen_point).collect(), indices)
            };
            if let Some(mesh) = shape.as_trimesh() {
                ShapePart::Triangles(
                    mesh.vertices().iter().map(widen_point).collect(),
                    mesh.indices().to_vec(),
                )
            } else if let Some(polyhedron) = shape.as_convex_polyhedron() {
                triangles(polyhedron.to_trimesh())
            } else if let Some(cuboid) = shape.as_cuboid() {
                triangles(cuboid.to_trimesh())
            } else if let Some(ball) = shape.as_ball() {
                ShapePart::Ball(Real::from(ball.radius))
            } else if let Some(capsule) = shape.as_capsule() {
                ShapePart::Capsule {
                    a: widen_point(&capsule.segment.a),
                    b: widen_point(&capsule.segment.b),
                    radius: Real::from(capsule.radius),
                }
            } else if let Some(cylinder) = shape.as_cylinder() {
                ShapePart::Cylinder {
                    half_height: Real::from(cylinder.half_height),
                    radius: Real::from(cylinder.radius),
                }
            } else {
                ShapePart::Other(format!("{:?}", shape.shape_type()))
            }
        }
    };
}

mod f64_build {
    use super::*;
    rapier_bodies!(rapier3d_f64, f64);
}

#[cfg(feature = "rapier-f32")]
mod f32_build {
    use super::*;
    rapier_bodies!(rapier3d, f32);
}

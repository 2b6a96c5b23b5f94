//! The rapier builds a [`Guard`](super::Guard) drives: rapier3d-f64 (the
//! `rapier` feature) and rapier3d, whose reals are f32 (the `rapier-f32`
//! feature). Both are the same rapier 0.36 source compiled at two
//! precisions; one macro writes the guard's view of each, so the guard's
//! logic is written once, in f64 (what f32 rounding leaves of the
//! guarantee: the guard module's "f32 rapier").

use super::parts::{ColliderPart, ContactHooks};
use super::views::{unit_quaternion, BodyKind, BodyView, ShapePart};
use crate::math::{Point, Pose, Real, Vector};

mod sealed {
    pub trait Sealed {}
}

/// A rapier body set the guard drives: `rapier3d_f64`'s `RigidBodySet`,
/// and with the `rapier-f32` feature `rapier3d`'s (sealed: these two).
/// Everything crosses in nearmiss's f64 types.
pub trait RapierBodies: sealed::Sealed + 'static {
    /// rapier's body handle.
    type Handle: Copy + Eq + std::fmt::Debug + Send + Sync + 'static;
    /// rapier's collider set.
    type Colliders;
    /// rapier's `IntegrationParameters`.
    type Parameters;
    /// rapier's real (`f64`, or `f32` for rapier3d): the `dt` the guard
    /// hands the application's step.
    type Scalar: Copy;
    /// What rapier's narrow phase reads of a solid collider to decide
    /// whether it meets another: its collision and solver groups, its
    /// active collision types and its body's type.
    type Rule: Copy + Send + Sync + 'static;

    /// `parameters.dt`.
    fn dt(parameters: &Self::Parameters) -> Real;
    /// `dt` in rapier's real.
    fn scalar(dt: Real) -> Self::Scalar;
    /// `parameters.allowed_linear_error()` (0.005 × `length_unit` in rapier 0.36).
    fn allowed_linear_error(parameters: &Self::Parameters) -> Real;
    /// `parameters.prediction_distance()` (0.02 × `length_unit`).
    fn prediction_distance(parameters: &Self::Parameters) -> Real;
    /// `parameters.length_unit`.
    fn length_unit(parameters: &Self::Parameters) -> Real;
    /// The body `handle` in messages: `rigid body #3` (its index in the set;
    /// `#3 (generation 1)` once the slot was reused).
    fn describe(handle: Self::Handle) -> String;
    /// The body `handle`, if it is in the set.
    fn view(&self, handle: Self::Handle) -> Option<BodyView>;
    /// The body's colliders, each at its pose in the body frame.
    fn shapes(&self, colliders: &Self::Colliders, handle: Self::Handle) -> Vec<ColliderPart>;
    /// The rules of the body's solid colliders (enabled, not sensors).
    fn rules(&self, colliders: &Self::Colliders, handle: Self::Handle) -> Vec<Self::Rule>;
    /// Whether rapier solves contacts between colliders of these rules
    /// (their bodies' types, collision groups and solver groups allow it).
    fn solves(a: &Self::Rule, b: &Self::Rule) -> bool;
    /// rapier's `PhysicsHooks` trait object.
    type Hooks: ?Sized;
    /// rapier's `ImpulseJointSet`.
    type Joints;
    /// The pairs of bodies joined by a joint of `joints` with contacts
    /// disabled (`GenericJoint::contacts_enabled` false): rapier never
    /// solves their contacts.
    fn without_contacts(joints: &Self::Joints) -> Vec<(Self::Handle, Self::Handle)>;
    /// The contact hooks the body's solid colliders ask for.
    fn contact_hooks(&self, colliders: &Self::Colliders, handle: Self::Handle) -> ContactHooks;
    /// Whether the application's `hooks` let rapier solve some pair of
    /// solid colliders of bodies `a` and `b` that its rules solve (those
    /// without `FILTER_CONTACT_PAIRS` need not ask).
    fn filter(
        &self,
        colliders: &Self::Colliders,
        hooks: &Self::Hooks,
        a: Self::Handle,
        b: Self::Handle,
    ) -> bool;
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
            type Scalar = $real;
            type Rule = (
                $rapier::prelude::InteractionGroups,
                $rapier::prelude::InteractionGroups,
                $rapier::prelude::ActiveCollisionTypes,
                $rapier::prelude::RigidBodyType,
            );

            fn dt(parameters: &Self::Parameters) -> Real {
                Real::from(parameters.dt)
            }

            fn scalar(dt: Real) -> $real {
                dt as $real
            }

            fn length_unit(parameters: &Self::Parameters) -> Real {
                Real::from(parameters.length_unit)
            }

            fn describe(handle: Self::Handle) -> String {
                match handle.into_raw_parts() {
                    (index, 0) => format!("rigid body #{index}"),
                    (index, generation) => format!("rigid body #{index} (generation {generation})"),
                }
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
                let mass = Real::from(body.mass());
                let (inverse_mass, inverse_inertia) = match kind {
                    BodyKind::Dynamic { .. } if mass > 0.0 && mass.is_finite() => {
                        let i = body.mass_properties().effective_world_inv_inertia;
                        let m = nalgebra::Matrix3::new(
                            i.m11, i.m12, i.m13, //
                            i.m12, i.m22, i.m23, //
                            i.m13, i.m23, i.m33,
                        );
                        (1.0 / mass, m.map(Real::from))
                    }
                    _ => (0.0, nalgebra::Matrix3::zeros()),
                };
                Some(BodyView {
                    pose: widen_pose(body.position()),
                    linvel: widen(body.linvel()),
                    angvel: widen(body.angvel()),
                    center: widen(body.local_center_of_mass()),
                    inverse_mass,
                    inverse_inertia,
                    kind,
                })
            }

            fn shapes(&self, colliders: &Self::Colliders, handle: Self::Handle) -> Vec<ColliderPart> {
                let Some(body) = self.get(handle) else { return Vec::new() };
                body.colliders()
                    .iter()
                    .filter_map(|c| Some((c, colliders.get(*c)?)))
                    .map(|(handle, collider)| ColliderPart {
                        name: format!("collider #{}", handle.into_raw_parts().0),
                        frame: collider.position_wrt_parent().map_or(Pose::identity(), widen_pose),
                        shape: part(collider.shape()),
                        solid: collider.is_enabled() && !collider.is_sensor(),
                    })
                    .collect()
            }

            fn rules(&self, colliders: &Self::Colliders, handle: Self::Handle) -> Vec<Self::Rule> {
                let Some(body) = self.get(handle) else { return Vec::new() };
                solid_colliders(body, colliders).map(|(_, collider)| rule_of(collider, body)).collect()
            }

            type Hooks = dyn $rapier::prelude::PhysicsHooks;
            type Joints = $rapier::prelude::ImpulseJointSet;

            fn without_contacts(joints: &Self::Joints) -> Vec<(Self::Handle, Self::Handle)> {
                joints
                    .iter()
                    .filter(|(_, joint)| !joint.data.contacts_enabled)
                    .map(|(_, joint)| (joint.body1(), joint.body2()))
                    .collect()
            }

            fn contact_hooks(&self, colliders: &Self::Colliders, handle: Self::Handle) -> ContactHooks {
                use $rapier::prelude::ActiveHooks;
                let Some(body) = self.get(handle) else { return ContactHooks::None };
                solid_colliders(body, colliders)
                    .map(|(_, collider)| {
                        let hooks = collider.active_hooks();
                        if hooks.contains(ActiveHooks::MODIFY_SOLVER_CONTACTS) {
                            ContactHooks::Modify
                        } else if hooks.contains(ActiveHooks::FILTER_CONTACT_PAIRS) {
                            ContactHooks::Filter
                        } else {
                            ContactHooks::None
                        }
                    })
                    .max()
                    .unwrap_or(ContactHooks::None)
            }

            fn filter(
                &self,
                colliders: &Self::Colliders,
                hooks: &Self::Hooks,
                a: Self::Handle,
                b: Self::Handle,
            ) -> bool {
                use $rapier::prelude::{ActiveHooks, PairFilterContext, SolverFlags};
                let (Some(body_a), Some(body_b)) = (self.get(a), self.get(b)) else { return false };
                for (ca, collider_a) in solid_colliders(body_a, colliders) {
                    for (cb, collider_b) in solid_colliders(body_b, colliders) {
                        if !Self::solves(&rule_of(collider_a, body_a), &rule_of(collider_b, body_b)) {
                            continue;
                        }
                        let asks = (collider_a.active_hooks() | collider_b.active_hooks())
                            .contains(ActiveHooks::FILTER_CONTACT_PAIRS);
                        if !asks {
                            return true;
                        }
                        let context = PairFilterContext {
                            bodies: self,
                            colliders,
                            collider1: ca,
                            collider2: cb,
                            rigid_body1: Some(a),
                            rigid_body2: Some(b),
                        };
                        if hooks
                            .filter_contact_pair(&context)
                            .is_some_and(|flags| flags.contains(SolverFlags::COMPUTE_RIGID_IMPULSES))
                        {
                            return true;
                        }
                    }
                }
                false
            }

            fn solves(a: &Self::Rule, b: &Self::Rule) -> bool {
                // As rapier's narrow phase: either collider's active types
                // take the two bodies' types, the collision groups meet, and
                // the solver groups too (else contacts apply no impulse).
                let types = a.2.test(a.3, b.3) || b.2.test(a.3, b.3);
                types && a.0.test(b.0) && a.1.test(b.1)
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

        /// The body's solid colliders (enabled, not sensors) and their
        /// handles: those rapier's solver meets.
        fn solid_colliders<'a>(
            body: &'a $rapier::prelude::RigidBody,
            colliders: &'a $rapier::prelude::ColliderSet,
        ) -> impl Iterator<Item = ($rapier::prelude::ColliderHandle, &'a $rapier::prelude::Collider)> + 'a {
            body.colliders()
                .iter()
                .filter_map(|c| Some((*c, colliders.get(*c)?)))
                .filter(|(_, collider)| collider.is_enabled() && !collider.is_sensor())
        }

        /// What rapier's narrow phase reads of a collider of `body`.
        fn rule_of(
            collider: &$rapier::prelude::Collider,
            body: &$rapier::prelude::RigidBody,
        ) -> <$rapier::prelude::RigidBodySet as RapierBodies>::Rule {
            (
                collider.collision_groups(),
                collider.solver_groups(),
                collider.active_collision_types(),
                body.body_type(),
            )
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
            } else if let Some(heightfield) = shape.as_heightfield() {
                triangles(heightfield.to_trimesh())
            } else if let Some(halfspace) = shape.as_halfspace() {
                ShapePart::HalfSpace { normal: widen(halfspace.normal) }
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

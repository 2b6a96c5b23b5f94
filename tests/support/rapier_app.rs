//! A rapier application's pipeline, as the guard's tests drive it: one
//! definition for both rapier builds (`rapier_app!(rapier3d_f64)` or
//! `rapier_app!(rapier3d)`), since the two crates' types differ.

/// Defines `Rapier`: the pipeline and the sets a step needs besides the
/// bodies and colliders, and `Rapier::step`, `PhysicsPipeline::step` by a
/// given `dt` (in rapier's real, as the guard hands it); and `sleeping_crate_and_wall`, the
/// world both builds' wake-and-push tests guard.
#[macro_export]
macro_rules! rapier_app {
    ($rapier:ident) => {
        /// A rapier application's pipeline and the sets a step needs
        /// besides the bodies and colliders.
        pub(crate) struct Rapier {
            pipeline: $rapier::prelude::PhysicsPipeline,
            islands: $rapier::prelude::IslandManager,
            broad_phase: $rapier::prelude::DefaultBroadPhase,
            narrow_phase: $rapier::prelude::NarrowPhase,
            impulse_joints: $rapier::prelude::ImpulseJointSet,
            multibody_joints: $rapier::prelude::MultibodyJointSet,
            soft_bodies: $rapier::prelude::SoftBodySet,
            ccd: $rapier::prelude::CCDSolver,
        }

        impl Rapier {
            pub(crate) fn new() -> Rapier {
                Rapier {
                    pipeline: $rapier::prelude::PhysicsPipeline::new(),
                    islands: $rapier::prelude::IslandManager::new(),
                    broad_phase: $rapier::prelude::DefaultBroadPhase::default(),
                    narrow_phase: $rapier::prelude::NarrowPhase::new(),
                    impulse_joints: $rapier::prelude::ImpulseJointSet::new(),
                    multibody_joints: $rapier::prelude::MultibodyJointSet::new(),
                    soft_bodies: $rapier::prelude::SoftBodySet::new(),
                    ccd: $rapier::prelude::CCDSolver::new(),
                }
            }

            /// `PhysicsPipeline::step` by `dt` (what the guard calls, in
            /// rapier's real).
            pub(crate) fn step(
                &mut self,
                bodies: &mut $rapier::prelude::RigidBodySet,
                colliders: &mut $rapier::prelude::ColliderSet,
                gravity: $rapier::prelude::Vector,
                parameters: &$rapier::prelude::IntegrationParameters,
                dt: $rapier::math::Real,
            ) {
                self.step_with_hooks(bodies, colliders, gravity, parameters, dt, &());
            }

            /// [`step`](Self::step) with the application's contact hooks.
            #[allow(dead_code, clippy::too_many_arguments)]
            pub(crate) fn step_with_hooks(
                &mut self,
                bodies: &mut $rapier::prelude::RigidBodySet,
                colliders: &mut $rapier::prelude::ColliderSet,
                gravity: $rapier::prelude::Vector,
                parameters: &$rapier::prelude::IntegrationParameters,
                dt: $rapier::math::Real,
                hooks: &dyn $rapier::prelude::PhysicsHooks,
            ) {
                self.pipeline.step(
                    gravity,
                    &$rapier::prelude::IntegrationParameters { dt, ..*parameters },
                    &mut self.islands,
                    &mut self.broad_phase,
                    &mut self.narrow_phase,
                    bodies,
                    colliders,
                    &mut self.impulse_joints,
                    &mut self.multibody_joints,
                    &mut self.soft_bodies,
                    &mut self.ccd,
                    hooks,
                    &(),
                );
            }

            /// The joints rapier's steps solve.
            #[allow(dead_code)]
            pub(crate) fn joints(&mut self) -> &mut $rapier::prelude::ImpulseJointSet {
                &mut self.impulse_joints
            }
        }

        /// A unit crate asleep on a fixed floor, resting on it face to face,
        /// and a velocity-based kinematic wall (0.2 thick)
        /// at 1.5 units/s that reaches it after 0.5 s: the sets and the
        /// handles `[floor, crate, wall]`.
        fn sleeping_crate_and_wall() -> (
            $rapier::prelude::RigidBodySet,
            $rapier::prelude::ColliderSet,
            [$rapier::prelude::RigidBodyHandle; 3],
        ) {
            use $rapier::prelude::*;
            let (mut bodies, mut colliders) = (RigidBodySet::new(), ColliderSet::new());
            let floor = bodies.insert(RigidBodyBuilder::fixed().translation(Vector::new(0.0, 0.0, -0.5)));
            colliders.insert_with_parent(ColliderBuilder::cuboid(10.0, 10.0, 0.5), floor, &mut bodies);
            let crate_body =
                bodies.insert(RigidBodyBuilder::dynamic().translation(Vector::new(0.0, 0.0, 0.5)));
            colliders.insert_with_parent(ColliderBuilder::cuboid(0.5, 0.5, 0.5), crate_body, &mut bodies);
            let wall = bodies.insert(
                RigidBodyBuilder::kinematic_velocity_based()
                    .translation(Vector::new(-0.5 - 0.1 - 0.75, 0.0, 2.1))
                    .linvel(Vector::new(1.5, 0.0, 0.0)),
            );
            colliders.insert_with_parent(ColliderBuilder::cuboid(0.1, 2.0, 2.0), wall, &mut bodies);
            bodies[crate_body].sleep();
            (bodies, colliders, [floor, crate_body, wall])
        }
    };
}

//! A rapier application's pipeline, as the guard's tests drive it: one
//! definition for both rapier builds (`rapier_app!(rapier3d_f64)` or
//! `rapier_app!(rapier3d)`), since the two crates' types differ.

/// Defines `Rapier`: the pipeline and the sets a step needs besides the
/// bodies and colliders, and `Rapier::step`, `PhysicsPipeline::step` by a
/// given `dt` (the guard's, in f64).
#[macro_export]
macro_rules! rapier_app {
    ($rapier:ident) => {
        /// A rapier application's pipeline and the sets a step needs
        /// besides the bodies and colliders.
        struct Rapier {
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
            fn new() -> Rapier {
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

            /// `PhysicsPipeline::step` by `dt` (what the guard calls; in
            /// rapier's reals).
            fn step(
                &mut self,
                bodies: &mut $rapier::prelude::RigidBodySet,
                colliders: &mut $rapier::prelude::ColliderSet,
                gravity: $rapier::prelude::Vector,
                parameters: &$rapier::prelude::IntegrationParameters,
                dt: f64,
            ) {
                self.pipeline.step(
                    gravity,
                    &$rapier::prelude::IntegrationParameters { dt: dt as _, ..*parameters },
                    &mut self.islands,
                    &mut self.broad_phase,
                    &mut self.narrow_phase,
                    bodies,
                    colliders,
                    &mut self.impulse_joints,
                    &mut self.multibody_joints,
                    &mut self.soft_bodies,
                    &mut self.ccd,
                    &(),
                    &(),
                );
            }
        }
    };
}

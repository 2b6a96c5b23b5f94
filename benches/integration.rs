//! One integrator step of many free bodies (issue 47 §1, §5): 10,000
//! bodies as `many_bodies` makes them (one in five a box of 0.6 × 0.4 ×
//! 0.5, whose anisotropic inertia takes the implicit gyroscopic solve; the
//! others of isotropic inertia, like its icospheres), velocities up to 2
//! and spins up to 8 rad/s, `dt` 1/240, nothing acting on them, through
//! - nearmiss's `integrate_turning` (semi-implicit Euler, the implicit
//!   gyroscopic step; the stepper's own integration of each body, without
//!   the stepper's buffers);
//! - rapier's `PhysicsPipeline::step` on the same bodies with no colliders
//!   (its integration with the pipeline's bookkeeping, nothing to collide),
//!   sleeping off.
//!
//! Times are per step of all bodies: divide by 10,000 for a body.
//! `cargo bench --bench integration` (about a minute).

use criterion::{criterion_group, criterion_main, Criterion};
use nalgebra::{Matrix3, UnitQuaternion};
use nearmiss::math::{Point, Real, Vector};
use nearmiss::motion::{integrate_turning, Dynamics, Gyroscopic, Integrator, RigidState};
use nearmiss::samples::Rng;
use rapier3d_f64::prelude as rapier;
use std::hint::black_box;

const BODIES: usize = 10_000;
const DT: Real = 1.0 / 240.0;

/// A body: its state, mass and principal inertia (body frame).
struct Free {
    state: RigidState,
    mass: Real,
    inertia: Vector,
}

fn bodies(rng: &mut Rng) -> Vec<Free> {
    (0..BODIES)
        .map(|k| {
            let (mass, inertia) = if k % 5 == 0 {
                // A box of density 1 and sides 0.6, 0.4, 0.5.
                let (a, b, c, m) = (0.6, 0.4, 0.5, 0.12);
                (m, Vector::new(b * b + c * c, a * a + c * c, a * a + b * b) * (m / 12.0))
            } else {
                (0.113, Vector::repeat(0.0041))
            };
            let state = RigidState {
                position: Point::from(rng.in_unit_ball() * 50.0),
                orientation: UnitQuaternion::from_scaled_axis(rng.in_unit_ball() * 3.0),
                velocity: rng.in_unit_ball() * 2.0,
                angular_velocity: rng.in_unit_ball() * 8.0,
            };
            Free { state, mass, inertia }
        })
        .collect()
}

fn integration(c: &mut Criterion) {
    let mut rng = Rng::new(47);
    let bodies = bodies(&mut rng);
    let inertias: Vec<Matrix3<Real>> = bodies.iter().map(|b| Matrix3::from_diagonal(&b.inertia)).collect();
    let mut group = c.benchmark_group("integration_10000_bodies");
    group.bench_function("nearmiss integrate_turning", |bench| {
        let mut states: Vec<RigidState> = bodies.iter().map(|b| b.state).collect();
        bench.iter(|| {
            for ((state, body), inertia) in states.iter_mut().zip(&bodies).zip(&inertias) {
                let dynamics = Dynamics {
                    inverse_mass: 1.0 / body.mass,
                    inertia: Some(inertia),
                    gravity: Vector::zeros(),
                    springs: &[],
                };
                let step = integrate_turning(
                    state,
                    &dynamics,
                    Integrator::SymplecticEuler,
                    Gyroscopic::Implicit,
                    DT,
                );
                *state = black_box(step).next;
            }
        })
    });
    group.bench_function("rapier PhysicsPipeline::step, no colliders", |bench| {
        let mut set = rapier::RigidBodySet::new();
        for body in &bodies {
            let (s, q) = (&body.state, body.state.orientation.quaternion());
            let pose = rapier::Pose::from_parts(
                rapier::Vector::new(s.position.x, s.position.y, s.position.z),
                rapier::Rotation::from_xyzw(q.i, q.j, q.k, q.w),
            );
            let (v, w, i) = (s.velocity, s.angular_velocity, body.inertia);
            let mass = rapier::MassProperties::new(
                rapier::Vector::ZERO,
                body.mass,
                rapier::Vector::new(i.x, i.y, i.z),
            );
            set.insert(
                rapier::RigidBodyBuilder::dynamic()
                    .pose(pose)
                    .linvel(rapier::Vector::new(v.x, v.y, v.z))
                    .angvel(rapier::Vector::new(w.x, w.y, w.z))
                    .additional_mass_properties(mass)
                    .can_sleep(false)
                    .allow_fast_rotation(true),
            );
        }
        let parameters = rapier::IntegrationParameters { dt: DT, ..Default::default() };
        let mut colliders = rapier::ColliderSet::new();
        let mut pipeline = rapier::PhysicsPipeline::new();
        let mut islands = rapier::IslandManager::new();
        let mut broad_phase = rapier::DefaultBroadPhase::default();
        let mut narrow_phase = rapier::NarrowPhase::new();
        let mut impulse_joints = rapier::ImpulseJointSet::new();
        let mut multibody_joints = rapier::MultibodyJointSet::new();
        let mut soft_bodies = rapier::SoftBodySet::new();
        let mut ccd = rapier::CCDSolver::new();
        bench.iter(|| {
            pipeline.step(
                rapier::Vector::ZERO,
                &parameters,
                &mut islands,
                &mut broad_phase,
                &mut narrow_phase,
                &mut set,
                &mut colliders,
                &mut impulse_joints,
                &mut multibody_joints,
                &mut soft_bodies,
                &mut ccd,
                &(),
                &(),
            );
        })
    });
    group.finish();
}

criterion_group!(benches, integration);
criterion_main!(benches);

//! A rapier application guarding its mesh bodies with nearmiss.
//!
//! A triangle-mesh bullet flies at 1,000 units/s at a 1 mm plate. rapier
//! alone, with its CCD on, lets it through (rapier never sweeps a moving
//! triangle mesh); with a `nearmiss::guard::Guard` stepping the pipeline
//! (`Guard::step`), the world is moved back to where the bullet touches the
//! plate, and rapier's contact solver takes over from there: the bullet
//! stops on the plate, never deeper into it than half its thickness.
//!
//! Run: `cargo run --release --example guard_rapier`

use nearmiss::guard::{Guard, GuardEvent, GuardOptions};
use rapier3d_f64::prelude::*;

/// A small icosahedron as a triangle mesh (what an application loads from
/// a file).
fn bullet_mesh(radius: f64) -> (Vec<Vector>, Vec<[u32; 3]>) {
    let phi = (1.0 + 5f64.sqrt()) / 2.0;
    let raw = [
        (-1.0, phi, 0.0),
        (1.0, phi, 0.0),
        (-1.0, -phi, 0.0),
        (1.0, -phi, 0.0),
        (0.0, -1.0, phi),
        (0.0, 1.0, phi),
        (0.0, -1.0, -phi),
        (0.0, 1.0, -phi),
        (phi, 0.0, -1.0),
        (phi, 0.0, 1.0),
        (-phi, 0.0, -1.0),
        (-phi, 0.0, 1.0),
    ];
    let scale = radius / (1.0 + phi * phi).sqrt();
    let vertices = raw.iter().map(|&(x, y, z)| Vector::new(x * scale, y * scale, z * scale)).collect();
    let indices = vec![
        [0, 11, 5],
        [0, 5, 1],
        [0, 1, 7],
        [0, 7, 10],
        [0, 10, 11],
        [1, 5, 9],
        [5, 11, 4],
        [11, 10, 2],
        [10, 7, 6],
        [7, 1, 8],
        [3, 9, 4],
        [3, 4, 2],
        [3, 2, 6],
        [3, 6, 8],
        [3, 8, 9],
        [4, 9, 5],
        [2, 4, 11],
        [6, 2, 10],
        [8, 6, 7],
        [9, 8, 1],
    ];
    (vertices, indices)
}

/// The lowest the bullet's lowest vertex gets over 0.1 s (at the steps'
/// ends), with or without the guard; the guard's events and rewinds.
fn shoot(guarded: bool) -> (f64, Vec<GuardEvent>, u64) {
    let mut bodies = RigidBodySet::new();
    let mut colliders = ColliderSet::new();
    let plate = bodies.insert(RigidBodyBuilder::fixed());
    colliders.insert_with_parent(ColliderBuilder::cuboid(1.0, 1.0, 0.0005), plate, &mut bodies);
    let bullet = bodies.insert(
        RigidBodyBuilder::dynamic()
            .translation(Vector::new(0.0, 0.0, 25.0))
            .linvel(Vector::new(0.0, 0.0, -1000.0))
            .ccd_enabled(true),
    );
    let (vertices, indices) = bullet_mesh(0.01);
    let mesh = ColliderBuilder::trimesh(vertices.clone(), indices).expect("a valid mesh").density(7800.0);
    colliders.insert_with_parent(mesh, bullet, &mut bodies);

    let mut parameters = IntegrationParameters { dt: 0.01, ..Default::default() };
    parameters.normalized_max_linear_velocity = f64::MAX;
    let mut pipeline = PhysicsPipeline::new();
    let (mut islands, mut broad_phase, mut narrow_phase) =
        (IslandManager::new(), DefaultBroadPhase::default(), NarrowPhase::new());
    let (mut impulse_joints, mut multibody_joints, mut soft_bodies, mut ccd) =
        (ImpulseJointSet::new(), MultibodyJointSet::new(), SoftBodySet::new(), CCDSolver::new());

    let mut guard = guarded.then(|| {
        Guard::new(&bodies, &mut colliders, &[plate, bullet], &parameters, GuardOptions::default())
            .expect("meshes the guard can sweep")
    });
    let mut events = Vec::new();
    let mut lowest = f64::INFINITY;
    for _ in 0..10 {
        // rapier's step by `dt`: the guard calls it for the step, and again
        // for the rest of a step it moved back to a contact.
        let mut rapier_step = |bodies: &mut RigidBodySet, dt: f64| {
            pipeline.step(
                Vector::ZERO,
                &IntegrationParameters { dt, ..parameters },
                &mut islands,
                &mut broad_phase,
                &mut narrow_phase,
                bodies,
                &mut colliders,
                &mut impulse_joints,
                &mut multibody_joints,
                &mut soft_bodies,
                &mut ccd,
                &(),
                &(),
            );
        };
        match guard.as_mut() {
            Some(guard) => events.extend(guard.step(&mut bodies, rapier_step).expect("decided")),
            None => rapier_step(&mut bodies, parameters.dt),
        }
        let pose = bodies[bullet].position();
        let bottom = vertices.iter().map(|v| (*pose * *v).z).fold(f64::INFINITY, f64::min);
        lowest = lowest.min(bottom);
    }
    (lowest, events, guard.map_or(0, |g| g.rewinds()))
}

fn main() {
    let (z, ..) = shoot(false);
    println!(
        "rapier alone (CCD on): at the steps' ends the bullet's lowest point gets down to z = {z:.4} (through the plate: z = -0.0005 to 0.0005)"
    );
    let (z, events, rewinds) = shoot(true);
    println!(
        "guarded by nearmiss:   at the steps' ends the bullet's lowest point gets down to z = {z:.6} ({rewinds} rewind: rapier solved the impact at the contact)"
    );
    for event in events {
        if let GuardEvent::Started { contact, .. } = event {
            println!(
                "  contact at t = {:.9}, {:.1e} from the plate ({} / {})",
                contact.time, contact.closest.distance, contact.closest.feature_a, contact.closest.feature_b
            );
        }
    }
}

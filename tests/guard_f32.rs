//! Issue 27 §5: the guard drives an f32 rapier3d 0.36 pipeline (the
//! `rapier-f32` feature) as it drives rapier3d-f64: a mesh bullet and a ball
//! stop at a thin plate that rapier alone lets them through, a kinematic
//! wall pushes a sleeping crate. Expected values come from the motions
//! themselves (constant velocity, no gravity: the analytic time at which the
//! bullet's lowest vertex reaches the plate).
#![cfg(feature = "rapier-f32")]

use nearmiss::guard::{Guard, GuardEvent, GuardOptions};
use rapier3d::prelude::*;

#[path = "support/rapier_app.rs"]
mod rapier_app;
rapier_app!(rapier3d);

/// The plate's half thickness (a 2 mm plate, top face at z = 0.001).
const HALF_THICKNESS: f32 = 0.001;

/// The bullet's vertices (a 6 × 30 × 6 mm box) in its body frame.
fn bullet_vertices() -> Vec<Vector> {
    let (hx, hy, hz) = (0.003, 0.015, 0.003);
    let mut vertices = Vec::new();
    for x in [-hx, hx] {
        for y in [-hy, hy] {
            for z in [-hz, hz] {
                vertices.push(Vector::new(x, y, z));
            }
        }
    }
    vertices
}

/// The lowest world z of `vertices` at `pose`, computed in f64.
fn lowest(pose: &Pose, vertices: &[Vector]) -> f64 {
    let q = pose.rotation;
    let rotation = nalgebra::UnitQuaternion::from_quaternion(nalgebra::Quaternion::new(
        f64::from(q.w),
        f64::from(q.x),
        f64::from(q.y),
        f64::from(q.z),
    ));
    let t = nalgebra::Vector3::new(
        f64::from(pose.translation.x),
        f64::from(pose.translation.y),
        f64::from(pose.translation.z),
    );
    vertices
        .iter()
        .map(|v| (t + rotation * nalgebra::Vector3::new(f64::from(v.x), f64::from(v.y), f64::from(v.z))).z)
        .fold(f64::INFINITY, f64::min)
}

/// A plate and a tilted triangle-mesh bullet at `speed` straight down from
/// `height`, at `offset` along x; rapier's CCD off, no gravity.
fn bullet_world(
    speed: f32,
    height: f32,
    offset: f32,
) -> (RigidBodySet, ColliderSet, RigidBodyHandle, RigidBodyHandle) {
    let (mut bodies, mut colliders) = (RigidBodySet::new(), ColliderSet::new());
    let plate = bodies.insert(RigidBodyBuilder::fixed().translation(Vector::new(offset, 0.0, 0.0)));
    colliders.insert_with_parent(ColliderBuilder::cuboid(1.0, 1.0, HALF_THICKNESS), plate, &mut bodies);
    let tilt = Rotation::from_axis_angle(Vector::new(1.0, 0.3, 0.0).normalize(), 40f32.to_radians());
    let bullet = bodies.insert(
        RigidBodyBuilder::dynamic()
            .pose(Pose::from_parts(Vector::new(offset, 0.0, height), tilt))
            .linvel(Vector::new(0.0, 0.0, -speed)),
    );
    let (vertices, triangles) = Cuboid::new(Vector::new(0.003, 0.015, 0.003)).to_trimesh();
    let mesh = ColliderBuilder::trimesh(vertices, triangles).expect("a box's triangles").density(7800.0);
    colliders.insert_with_parent(mesh, bullet, &mut bodies);
    (bodies, colliders, plate, bullet)
}

/// Parameters at `dt` with no speed cap (rapier's default caps bodies at
/// 400 units per second).
fn parameters(dt: f32) -> IntegrationParameters {
    let mut parameters = IntegrationParameters { dt, ..Default::default() };
    parameters.normalized_max_linear_velocity = f32::MAX;
    parameters
}

#[test]
fn rapier_alone_in_f32_lets_the_bullet_through_the_plate() {
    // The case the guard is for: without it, the bullet ends below the plate.
    let (mut bodies, mut colliders, _, bullet) = bullet_world(800.0, 2.0, 0.0);
    let parameters = parameters(1.0 / 240.0);
    let mut rapier = Rapier::new();
    for _ in 0..12 {
        rapier.step(&mut bodies, &mut colliders, Vector::ZERO, &parameters, parameters.dt);
    }
    let below = lowest(bodies[bullet].position(), &bullet_vertices());
    assert!(
        below < -f64::from(HALF_THICKNESS),
        "rapier alone stopped the bullet (lowest vertex z = {below})"
    );
}

#[test]
fn a_guarded_f32_bullet_stops_at_a_thin_plate_at_the_analytic_time() {
    // 800 units/s, 2 m above a 2 mm plate, at the origin and 1,000 units
    // away: the guard reports the contact when the lowest vertex reaches the
    // plate's top face, and no vertex ever goes below the plate's middle
    // (half the plate is the pair's tolerated depth). The step closure takes
    // rapier's f32 `dt`.
    for offset in [0.0, 1000.0] {
        let (speed, height) = (800.0_f32, 2.0_f32);
        let (mut bodies, mut colliders, plate, bullet) = bullet_world(speed, height, offset);
        let parameters = parameters(1.0 / 240.0);
        let options = GuardOptions {
            ccd: nearmiss::ccd::CcdOptions { distance_tolerance: 1e-9, ..Default::default() },
            ..Default::default()
        };
        let mut guard: Guard<RigidBodySet> =
            Guard::new(&bodies, &mut colliders, &[plate, bullet], &parameters, options)
                .expect("cuboid and mesh");
        // The analytic time, from the poses as rapier holds them (f32).
        let gap = lowest(bodies[bullet].position(), &bullet_vertices()) - f64::from(HALF_THICKNESS);
        let expected = gap / f64::from(speed);
        let mut rapier = Rapier::new();
        let mut first = None;
        for step in 0..24 {
            let events = guard
                .step(&mut bodies, |bodies, dt: f32| {
                    rapier.step(bodies, &mut colliders, Vector::ZERO, &parameters, dt)
                })
                .expect("decided");
            // The events are the caller's: the guard's counters can be read
            // beside them.
            assert!(guard.rewinds() <= guard.steps() * 4);
            for event in events {
                if let GuardEvent::Started { contact, .. } = event {
                    first.get_or_insert(contact.time);
                }
            }
            let below = lowest(bodies[bullet].position(), &bullet_vertices());
            // The f32 pose handed back is the proven one rounded: at most
            // half an ulp of 1,000 (3e-5) away.
            let rounding = 4e-5 * f64::from(offset.abs().max(1.0)) / 1000.0;
            assert!(
                below > -rounding,
                "offset {offset}: a vertex at z = {below} after step {step}, past the plate's middle"
            );
        }
        let time = first.expect("the bullet reaches the plate");
        // Never late, to f32's rounding of rapier's own step: the pose rapier
        // ends the step at (z near -1.3, rounded to 1.2e-7) is the motion the
        // guard sweeps, 3.3 units a step: 1e-10 s at most either way. Early
        // at most by the contact distance's travel (1e-9 × 0.015 at 800
        // units/s) beside that.
        let rounding = 1e-10;
        assert!(
            time <= expected + rounding,
            "offset {offset}: contact at {time}, after the analytic {expected}"
        );
        assert!(
            time >= expected - 2.0 * rounding,
            "offset {offset}: contact at {time}, before the analytic {expected}"
        );
    }
}

#[test]
fn a_guarded_f32_ball_stops_at_a_thin_plate() {
    // rapier's balls are swept as polyhedra around them: a ball of radius
    // 0.1 at 300 units/s never reaches past the plate's middle.
    let (mut bodies, mut colliders) = (RigidBodySet::new(), ColliderSet::new());
    let plate = bodies.insert(RigidBodyBuilder::fixed());
    colliders.insert_with_parent(ColliderBuilder::cuboid(10.0, 10.0, HALF_THICKNESS), plate, &mut bodies);
    let ball = bodies.insert(
        RigidBodyBuilder::dynamic()
            .translation(Vector::new(0.0, 0.0, 3.0))
            .linvel(Vector::new(0.0, 0.0, -300.0)),
    );
    colliders.insert_with_parent(ColliderBuilder::ball(0.1), ball, &mut bodies);
    let parameters = parameters(1.0 / 60.0);
    let mut guard: Guard<RigidBodySet> =
        Guard::new(&bodies, &mut colliders, &[plate, ball], &parameters, GuardOptions::default())
            .expect("a ball");
    let mut rapier = Rapier::new();
    let mut started = 0;
    for step in 0..30 {
        let events = guard
            .step(&mut bodies, |bodies, dt| {
                rapier.step(bodies, &mut colliders, Vector::ZERO, &parameters, dt)
            })
            .expect("decided");
        started += events.iter().filter(|e| matches!(e, GuardEvent::Started { .. })).count();
        let bottom = f64::from(bodies[ball].translation().z) - 0.1;
        assert!(bottom > 0.0, "the ball reaches z = {bottom} after step {step}");
    }
    assert!(started >= 1, "the guard saw the ball arrive");
}

#[test]
fn a_guarded_f32_kinematic_wall_wakes_and_pushes_a_sleeping_crate() {
    // A velocity-based kinematic wall at 1.5 units/s reaches a crate asleep
    // on a floor after 0.5 s: the crate is woken and pushed, never entered
    // deeper than rapier's allowed linear error (the tolerated depth).
    let parameters = parameters(1.0 / 60.0);
    let (mut bodies, mut colliders, [floor, crate_body, wall]) = sleeping_crate_and_wall();
    assert!(bodies[crate_body].is_sleeping());
    let mut guard: Guard<RigidBodySet> =
        Guard::new(&bodies, &mut colliders, &[floor, crate_body, wall], &parameters, GuardOptions::default())
            .expect("cuboids");
    let mut rapier = Rapier::new();
    let mut woken = false;
    for step in 0..90 {
        guard
            .step(&mut bodies, |bodies, dt| {
                rapier.step(bodies, &mut colliders, Vector::new(0.0, 0.0, -9.81), &parameters, dt)
            })
            .expect("decided");
        woken |= !bodies[crate_body].is_sleeping();
        // Upright boxes (the crate may tip a little; its back face's lowest x
        // over its corners is what the wall meets).
        let crate_back = lowest_x(bodies[crate_body].position(), 0.5);
        let wall_face = f64::from(bodies[wall].translation().x) + 0.1;
        let tolerated = f64::from(parameters.allowed_linear_error());
        assert!(
            crate_back >= wall_face - tolerated,
            "the wall is {} into the crate after step {step}",
            wall_face - crate_back
        );
    }
    assert!(woken, "the crate was never woken");
    assert!(f64::from(bodies[crate_body].translation().x) > 0.5, "the crate was pushed");
}

/// The smallest world x over the corners of a cube of half extent `half` at
/// `pose`.
fn lowest_x(pose: &Pose, half: f32) -> f64 {
    let mut corners = Vec::new();
    for x in [-half, half] {
        for y in [-half, half] {
            for z in [-half, half] {
                corners.push(pose.transform_point(Vector::new(x, y, z)));
            }
        }
    }
    corners.iter().map(|c| f64::from(c.x)).fold(f64::INFINITY, f64::min)
}

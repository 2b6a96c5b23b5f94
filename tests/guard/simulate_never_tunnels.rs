//! Issues 27 and 43: under `Simulate` no mesh passes through another, in
//! contact or not, at any recorded pose of any step, and no pair overlaps
//! deeper than the guard's tolerated depth (rapier's allowed linear error,
//! at most half the thinner body); kinematic bodies push dynamic ones; a
//! sleeping body is woken; a heavy body keeps its motion; momentum and
//! energy are kept. With a skin asked for, the meshes never overlap at all.
//!
//! The scenes are written from physics, not from the program's output. The
//! independent check is parry's contact query between the bodies' convex
//! hulls at every recorded pose (`poses.csv`'s records).
#![cfg(feature = "rapier")]

use nearmiss::math::{pose_to_parry, to_parry, Pose, Real, Vector};
use nearmiss::run::PoseRecord;
use nearmiss::run::{run, RunResult, Termination};
use nearmiss::scene::Scene;
use parry3d_f64::shape::ConvexPolyhedron;

crate::rapier_app!(rapier3d_f64);

fn simulate(text: &str) -> (Scene, RunResult) {
    let scene = Scene::from_ron_str(text).unwrap_or_else(|e| panic!("{e}\n{text}"));
    let result = run(&scene);
    assert_eq!(result.termination, Termination::Completed, "{:?}", result.termination);
    (scene, result)
}

/// The guard's tolerated depth under rapier's default parameters (0.005).
fn tolerated() -> Real {
    let parameters = rapier3d_f64::prelude::IntegrationParameters::default();
    nearmiss::guard::GuardOptions::default().tolerated_depth_under(&parameters)
}

fn pose_of(record: &PoseRecord) -> Pose {
    Pose::from_parts(nalgebra::Translation3::from(record.position.coords), record.orientation)
}

/// The deepest overlap of bodies `a` and `b` (convex meshes) over the
/// recorded poses, by parry, and the time of the deepest (0 when they never
/// overlap).
fn deepest_overlap(scene: &Scene, result: &RunResult, a: usize, b: usize) -> (Real, Real) {
    let hull = |i: usize| {
        let points: Vec<_> = scene.model().bodies[i].mesh.vertices().iter().map(to_parry).collect();
        ConvexPolyhedron::from_convex_hull(&points).expect("convex hull")
    };
    let (hull_a, hull_b) = (hull(a), hull(b));
    let mut deepest = (0.0, 0.0);
    let records_a = result.poses.iter().filter(|r| r.body == a);
    let records_b = result.poses.iter().filter(|r| r.body == b);
    for (ra, rb) in records_a.zip(records_b) {
        assert_eq!(ra.step, rb.step);
        let contact = parry3d_f64::query::contact(
            &pose_to_parry(&pose_of(ra)),
            &hull_a,
            &pose_to_parry(&pose_of(rb)),
            &hull_b,
            0.0,
        )
        .expect("supported shapes");
        if let Some(contact) = contact {
            if -contact.dist > deepest.0 {
                deepest = (-contact.dist, ra.time);
            }
        }
    }
    deepest
}

/// The lowest world z of `body`'s vertices over the recorded poses at
/// which its centre is within `half` of (x0, 0) across z (over a plate of
/// that half extent there; all poses with an infinite `half`).
fn lowest_vertex_over(scene: &Scene, result: &RunResult, body: usize, (x0, half): (Real, Real)) -> Real {
    let mesh = &scene.model().bodies[body].mesh;
    result
        .poses
        .iter()
        .filter(|r| r.body == body && (r.position.x - x0).abs() <= half && r.position.y.abs() <= half)
        .flat_map(|r| {
            let pose = pose_of(r);
            mesh.vertices().iter().map(move |v| (pose * v).z)
        })
        .fold(Real::INFINITY, Real::min)
}

/// [`lowest_vertex_over`] at every pose.
fn lowest_vertex(scene: &Scene, result: &RunResult, body: usize) -> Real {
    lowest_vertex_over(scene, result, body, (0.0, Real::INFINITY))
}

#[test]
fn a_mesh_bullet_never_comes_out_of_a_thin_plate_behind() {
    // A 6 × 30 × 6 mm triangle-mesh bullet, tilted 40°, at 500 to 2,000
    // units/s onto plates 1 and 2 mm thick, at the origin and 1e6 away: it
    // must never put a vertex past the plate's far face while over it (it
    // may glance off and leave past its edge), and never sink into it
    // deeper than half its thickness (the thin body's tolerated depth);
    // with a skin asked for, never overlap it at all.
    for thickness in [0.001, 0.002] {
        for speed in [500.0, 2000.0] {
            for (offset, skin) in [(0.0, 0.0), (1e6, 0.0), (0.0, 1.0)] {
                let text = format!(
                    r#"Scene(
                        name: "bullet", dt: 0.004166666666666667, duration: 0.05,
                        gravity: (0.0, 0.0, -9.81),
                        ccd: (distance_tolerance: 1e-9),
                        on_contact: Simulate(skin: {skin:?}),
                        poses: (every: 1),
                        bodies: [
                            (name: "plate", mesh: Box(half_extents: (1.0, 1.0, {half})), position: ({offset}, 0.0, 0.0), fixed: true),
                            (name: "bullet", mesh: Box(half_extents: (0.003, 0.015, 0.003)),
                             position: ({offset}, 0.0, {start}),
                             orientation: AxisAngle(axis: (1.0, 0.3, 0.0), degrees: 40.0),
                             velocity: (0.0, 0.0, -{speed}), density: 7800.0, collider: TriMesh),
                        ],
                    )"#,
                    half = thickness / 2.0,
                    start = speed * 0.0125,
                );
                let (scene, result) = simulate(&text);
                let case = format!("{thickness} m plate, {speed} units/s, offset {offset}, skin {skin}");
                assert!(result.first_contact.is_some(), "{case}: the bullet reaches the plate");
                let far_face = -thickness / 2.0;
                let lowest = lowest_vertex_over(&scene, &result, 1, (offset, 1.0));
                assert!(lowest > far_face, "{case}: a vertex at z = {lowest}, past the far face {far_face}");
                let (depth, time) = deepest_overlap(&scene, &result, 0, 1);
                let allowed = if skin > 0.0 { 0.0 } else { thickness / 2.0 };
                assert!(depth <= allowed, "{case}: the bullet overlaps the plate by {depth} at t = {time}");
            }
        }
    }
}

#[test]
fn a_kinematic_blade_pushes_a_ball_out_of_its_way() {
    // A kinematic blade (2 × 0.04 × 0.4) spinning at 60 rad/s about z meets
    // a resting ball of radius 0.05 at radius 0.5 (no gravity): the blade
    // has infinite mass, so the ball must be pushed, never swept through
    // (nor overlapped deeper than rapier's allowed error).
    let (scene, result) = simulate(
        r#"Scene(
            name: "blade", dt: 0.016666666666666666, duration: 0.5,
            on_contact: Simulate(),
            poses: (every: 1),
            bodies: [
                (name: "blade", mesh: Box(half_extents: (1.0, 0.02, 0.2)), angular_velocity: (0.0, 0.0, 60.0), kinematic: true),
                (name: "ball", mesh: Icosphere(radius: 0.05, subdivisions: 2), position: (0.0, 0.5, 0.0), density: 1000.0),
            ],
        )"#,
    );
    assert!(result.first_contact.is_some(), "the blade reaches the ball");
    let (depth, time) = deepest_overlap(&scene, &result, 0, 1);
    assert!(depth <= tolerated(), "the blade overlaps the ball by {depth} at t = {time}");
    let ball = result.final_states[1];
    assert!(ball.velocity.norm() > 1.0, "the ball was pushed away: speed {}", ball.velocity.norm());
}

#[test]
fn a_kinematic_wall_pushes_a_resting_crate() {
    // A crate rests on a floor; a kinematic wall at 1.5 units/s arrives
    // after 1.5 s. rapier's soft contact alone lets the wall 5 cm into the
    // crate: the guard must not let it deeper than rapier's allowed error.
    let (scene, result) = simulate(
        r#"Scene(
            name: "crate", dt: 0.016666666666666666, duration: 2.5,
            gravity: (0.0, 0.0, -9.81),
            on_contact: Simulate(friction: 0.5),
            poses: (every: 1),
            bodies: [
                (name: "floor", mesh: Box(half_extents: (10.0, 10.0, 0.5)), position: (0.0, 0.0, -0.5), fixed: true),
                (name: "crate", mesh: Box(half_extents: (0.5, 0.5, 0.5)), position: (0.0, 0.0, 0.52), density: 100.0),
                (name: "wall", mesh: Box(half_extents: (0.1, 2.0, 2.0)), position: (-2.85, 0.0, 2.1),
                 velocity: (1.5, 0.0, 0.0), kinematic: true),
            ],
        )"#,
    );
    let (depth, time) = deepest_overlap(&scene, &result, 1, 2);
    assert!(depth <= tolerated(), "the wall overlaps the crate by {depth} at t = {time}");
    // Pushed: the crate's back face stays ahead of the wall's front face,
    // which ends at −2.85 + 0.1 + 1.5 × 2.5 = 1.0, to the tolerated depth.
    let crate_x = result.final_states[1].position.x;
    assert!(crate_x - 0.5 >= 1.0 - tolerated(), "the crate at x = {crate_x}, the wall's face at 1.0");
}

#[test]
fn a_heavy_blade_keeps_its_motion_when_it_hits_a_light_ball() {
    // A dynamic 125 kg blade (2 × 0.04 × 0.4, I_z = m (2² + 0.04²) / 12)
    // spinning at 20 rad/s into a 0.5 kg ball at radius 0.8 (no gravity).
    // The ball can take at most (1 + e) m r² ω / I of the blade's spin
    // (e ≤ 1): 1.5%. The guard must not take more: at the first recorded
    // step after the contact, the blade's angle is within 1° of the free
    // spin's, and the angular momentum about z (blade and ball) is kept to
    // 1% at the end.
    let blade_density = 125.0 / (2.0 * 0.04 * 0.4);
    let (scene, result) = simulate(&format!(
        r#"Scene(
            name: "heavy", dt: 0.016666666666666666, duration: 0.3,
            on_contact: Simulate(restitution: 0.0, friction: 0.0),
            poses: (every: 1),
            bodies: [
                (name: "blade", mesh: Box(half_extents: (1.0, 0.02, 0.2)), angular_velocity: (0.0, 0.0, 20.0), density: {blade_density}),
                (name: "ball", mesh: Icosphere(radius: 0.05, subdivisions: 2), position: (0.0, 0.8, 0.0), density: 954.9296585513721),
            ],
        )"#
    ));
    let contact = result.first_contact.as_ref().expect("the blade reaches the ball");
    let after = result
        .poses
        .iter()
        .find(|r| r.body == 0 && r.time > contact.time)
        .expect("a recorded step after the contact");
    let (axis, angle) = after.orientation.axis_angle().expect("the blade turned");
    let turned = angle * axis.z.signum();
    let free = 20.0 * after.time;
    let lost = (free - turned).to_degrees();
    assert!(lost.abs() < 1.0, "the blade lost {lost}° of its turn at t = {}", after.time);
    let blade_inertia = 125.0 * (4.0 + 0.0016) / 12.0;
    let ball_mass = scene.model().bodies[1].mass.expect("density gives a mass");
    let [blade, ball] = [result.final_states[0], result.final_states[1]];
    let ball_inertia = scene.model().bodies[1].inertia.expect("density gives an inertia")[(2, 2)];
    let momentum = blade_inertia * blade.angular_velocity.z
        + ball_mass * ball.position.coords.cross(&ball.velocity).z
        + ball_inertia * ball.angular_velocity.z;
    let initial = blade_inertia * 20.0;
    assert!(((momentum - initial) / initial).abs() < 0.01, "angular momentum {momentum} vs {initial}");
}

#[test]
fn a_guarded_application_wakes_a_sleeping_crate_in_a_kinematic_walls_way() {
    use rapier3d_f64::prelude::*;
    // A rapier application: a crate put to sleep on a floor, a
    // velocity-based kinematic wall at 1.5 units/s arriving after 0.5 s, the
    // guard stepping the pipeline. The crate must be woken (rapier wakes it
    // too once it sees the contact) and pushed, and the wall never gets
    // into it deeper than rapier's allowed error.
    let parameters = IntegrationParameters { dt: 1.0 / 60.0, ..Default::default() };
    let (mut bodies, mut colliders, [floor, crate_body, wall]) = sleeping_crate_and_wall();
    assert!(bodies[crate_body].is_sleeping());
    let options = nearmiss::guard::GuardOptions::default();
    let mut guard = nearmiss::guard::Guard::new(
        &bodies,
        &mut colliders,
        &[floor, crate_body, wall],
        &parameters,
        options,
    )
    .expect("cuboids");
    let mut rapier = Rapier::new();
    let crate_hull = parry3d_f64::shape::Cuboid::new(Vector::new(0.5, 0.5, 0.5));
    let wall_hull = parry3d_f64::shape::Cuboid::new(Vector::new(0.1, 2.0, 2.0));
    let mut woken = false;
    for step in 0..90 {
        guard
            .step(&mut bodies, |bodies, dt| {
                rapier.step(bodies, &mut colliders, Vector::new(0.0, 0.0, -9.81), &parameters, dt)
            })
            .expect("decided");
        woken |= !bodies[crate_body].is_sleeping();
        let contact = parry3d_f64::query::contact(
            bodies[crate_body].position(),
            &crate_hull,
            bodies[wall].position(),
            &wall_hull,
            0.0,
        )
        .expect("cuboids");
        if let Some(contact) = contact {
            assert!(
                contact.dist >= -tolerated(),
                "the wall is {} into the crate after step {step}",
                -contact.dist
            );
        }
    }
    assert!(woken, "the crate was never woken");
    let wall_face = bodies[wall].translation().x + 0.1;
    let crate_back = bodies[crate_body].translation().x - 0.5;
    assert!(
        crate_back >= wall_face - tolerated(),
        "the crate's back {crate_back}, the wall's face {wall_face}"
    );
}

/// Equal unit boxes at +5 and −1 along x, faces parallel, restitution 1,
/// no friction, under Simulate.
fn head_on_boxes() -> (Scene, RunResult) {
    simulate(
        r#"Scene(
            name: "boxes", dt: 0.008333333333333333, duration: 1.0,
            on_contact: Simulate(restitution: 1.0, friction: 0.0),
            bodies: [
                (name: "a", mesh: Box(half_extents: (0.5, 0.5, 0.5)), position: (-2.0, 0.0, 0.0), velocity: (5.0, 0.0, 0.0), density: 1.0),
                (name: "b", mesh: Box(half_extents: (0.5, 0.5, 0.5)), position: (2.0, 0.0, 0.0), velocity: (-1.0, 0.0, 0.0), density: 1.0),
            ],
        )"#,
    )
}

#[test]
fn two_equal_boxes_meeting_head_on_at_restitution_one_exchange_velocities() {
    // Momentum kept to 1%, no kinetic energy gained beyond 1%.
    let (scene, result) = head_on_boxes();
    assert!(result.first_contact.is_some(), "the boxes meet");
    let [a, b] = [result.final_states[0], result.final_states[1]];
    let mass = scene.model().bodies[0].mass.expect("density gives a mass");
    let momentum = mass * (a.velocity + b.velocity);
    let initial = mass * Vector::new(4.0, 0.0, 0.0);
    assert!((momentum - initial).norm() < 0.01 * initial.norm(), "momentum {momentum:?}");
    let energy = 0.5 * mass * (a.velocity.norm_squared() + b.velocity.norm_squared());
    let initial_energy = 0.5 * mass * 26.0;
    assert!(energy <= 1.01 * initial_energy, "kinetic energy {energy} vs {initial_energy}");
}

#[test]
#[ignore = "the ideal exchange, which rapier's solver does not give (issue 27 §3 found it rapier's, not the guard's): the boxes leave at −0.93 / +4.93 spinning at 1.2 rad/s. rapier's own solve of this contact does the same (two touching boxes at +5 / −1 stepped once by rapier alone, with or without skins, at dt 1/120 or 1/600: the same spin, an 8-point face manifold); rapier alone in the whole scene, its CCD clamping first, exchanges exactly (`--compare rapier`). Handing rapier the pair earlier (rewinding 1e-5 to 1e-3 s before the contact, the boxes up to 6e-3 apart) leaves the same spin to 1e-3 rad/s: it is rapier's solve of the face contact, not where the guard hands it over"]
fn two_equal_boxes_meeting_head_on_at_restitution_one_leave_without_spin() {
    // A head-on collision of equal boxes with parallel faces exchanges
    // their velocities (−1 and +5) and adds no spin.
    let (_, result) = head_on_boxes();
    let [a, b] = [result.final_states[0], result.final_states[1]];
    assert!((a.velocity.x + 1.0).abs() < 0.05 && (b.velocity.x - 5.0).abs() < 0.05, "{a:?} {b:?}");
    assert!(a.angular_velocity.norm() < 0.05 && b.angular_velocity.norm() < 0.05, "spin {a:?} {b:?}");
}

#[test]
fn a_crate_on_a_40_km_ground_is_accepted_and_rests() {
    // The contract's contact distance uses the smaller body's radius: a 1 m
    // crate on a 40 km fixed ground has 1e-6 × 0.87, far inside rapier's
    // prediction distance (the ground's own radius, 28 km, would give
    // 0.028, beyond it).
    let (scene, result) = simulate(
        r#"Scene(
            name: "ground", dt: 0.016666666666666666, duration: 1.0,
            gravity: (0.0, 0.0, -9.81),
            on_contact: Simulate(),
            poses: (every: 1),
            bodies: [
                (name: "ground", mesh: Box(half_extents: (20000.0, 20000.0, 0.5)), position: (0.0, 0.0, -0.5), fixed: true),
                (name: "crate", mesh: Box(half_extents: (0.5, 0.5, 0.5)), position: (0.0, 0.0, 0.6), density: 100.0),
            ],
        )"#,
    );
    assert!(result.first_contact.is_some(), "the crate lands");
    let lowest = lowest_vertex(&scene, &result, 1);
    assert!(lowest >= -tolerated(), "the crate sinks to {lowest} into the ground");
}

#[test]
fn guarded_rapier_balls_capsules_cylinders_and_compounds_stop_at_a_thin_plate() {
    use rapier3d_f64::prelude::*;
    // rapier's round shapes and compound colliders are guarded too: a ball
    // of radius 0.1, a body of two cuboids, a capsule and a cylinder, tilted,
    // at 300 units/s, rapier's CCD off, onto a 2 mm plate. The true shapes
    // must never reach past the plate's middle (half its thickness is the
    // pair's tolerated depth): the guard sweeps polyhedra that contain them.
    let (mut bodies, mut colliders) = (RigidBodySet::new(), ColliderSet::new());
    let plate = bodies.insert(RigidBodyBuilder::fixed());
    // Wide: the tilted shapes leave the impact spinning and sliding fast.
    colliders.insert_with_parent(ColliderBuilder::cuboid(100.0, 100.0, 0.001), plate, &mut bodies);
    let ball = bodies.insert(
        RigidBodyBuilder::dynamic()
            .translation(Vector::new(-1.0, 0.0, 3.0))
            .linvel(Vector::new(0.0, 0.0, -300.0)),
    );
    colliders.insert_with_parent(ColliderBuilder::ball(0.1), ball, &mut bodies);
    let parts = vec![
        (Pose::from_translation(Vector::new(-0.2, 0.0, 0.0)), SharedShape::cuboid(0.1, 0.05, 0.05)),
        (Pose::from_translation(Vector::new(0.2, 0.0, 0.0)), SharedShape::cuboid(0.1, 0.05, 0.05)),
    ];
    let compound = bodies.insert(
        RigidBodyBuilder::dynamic()
            .translation(Vector::new(1.0, 0.0, 3.0))
            .linvel(Vector::new(0.0, 0.0, -300.0)),
    );
    colliders.insert_with_parent(ColliderBuilder::compound(parts), compound, &mut bodies);
    let tilt = Rotation::from_axis_angle(Vector::new(1.0, 0.2, 0.0).normalize(), 0.7);
    let capsule = bodies.insert(
        RigidBodyBuilder::dynamic()
            .pose(Pose::from_parts(Vector::new(0.0, 1.0, 3.0), tilt))
            .linvel(Vector::new(0.0, 0.0, -300.0)),
    );
    colliders.insert_with_parent(ColliderBuilder::capsule_y(0.1, 0.05), capsule, &mut bodies);
    let cylinder = bodies.insert(
        RigidBodyBuilder::dynamic()
            .pose(Pose::from_parts(Vector::new(0.0, -1.0, 3.0), tilt))
            .linvel(Vector::new(0.0, 0.0, -300.0)),
    );
    colliders.insert_with_parent(ColliderBuilder::cylinder(0.1, 0.05), cylinder, &mut bodies);
    let mut parameters = IntegrationParameters { dt: 1.0 / 60.0, ..Default::default() };
    parameters.normalized_max_linear_velocity = f64::MAX;
    let mut guard = nearmiss::guard::Guard::new(
        &bodies,
        &mut colliders,
        &[plate, ball, compound, capsule, cylinder],
        &parameters,
        nearmiss::guard::GuardOptions::default(),
    )
    .expect("round shapes and a compound of cuboids");
    let mut rapier = Rapier::new();
    let mut started = 0;
    for step in 0..30 {
        let events = guard
            .step(&mut bodies, |bodies, dt| {
                rapier.step(bodies, &mut colliders, Vector::ZERO, &parameters, dt)
            })
            .expect("decided");
        started += events.iter().filter(|e| matches!(e, nearmiss::guard::GuardEvent::Started { .. })).count();
        let ball_bottom = bodies[ball].translation().z - 0.1;
        assert!(ball_bottom > 0.0, "the ball's sphere reaches z = {ball_bottom} after step {step}");
        let body = &bodies[compound];
        for collider in body.colliders() {
            let shape = colliders[*collider].shape().as_compound().expect("compound");
            for (pose, part) in shape.shapes() {
                let world = *body.position() * *pose;
                let cuboid = part.as_cuboid().expect("cuboid");
                let lowest = cuboid
                    .to_trimesh()
                    .0
                    .iter()
                    .map(|v| world.transform_point(*v).z)
                    .fold(f64::INFINITY, f64::min);
                assert!(lowest > 0.0, "a cuboid reaches z = {lowest} after step {step}");
            }
        }
        // Both along their y axes, half height 0.1, radius 0.05: the lowest
        // point of the capsule is its lower segment end less the radius; of
        // the cylinder, its lower cap centre less the radius times the
        // axis's horizontal part.
        let axis = |body: RigidBodyHandle| bodies[body].rotation() * Vector::Y;
        let (a, c) = (axis(capsule), bodies[capsule].translation());
        let capsule_bottom = c.z - 0.1 * a.z.abs() - 0.05;
        assert!(capsule_bottom > 0.0, "the capsule reaches z = {capsule_bottom} after step {step}");
        let (a, c) = (axis(cylinder), bodies[cylinder].translation());
        let cylinder_bottom = c.z - 0.1 * a.z.abs() - 0.05 * (1.0 - a.z * a.z).max(0.0).sqrt();
        assert!(cylinder_bottom > 0.0, "the cylinder reaches z = {cylinder_bottom} after step {step}");
    }
    assert!(started >= 4, "every body reaches the plate: {started} contacts");
}

#[test]
fn a_guard_takes_new_bodies_drops_old_ones_and_a_new_dt() {
    use nearmiss::guard::{Guard, GuardEvent, GuardOptions};
    use rapier3d_f64::prelude::*;
    // No gravity. A box rests on a plate (face to face); after 10 steps of 1/60 a
    // triangle-mesh bullet is added 2 above the plate at 200 units/s and the step
    // halved; after 20 more the box is dropped from the guard. The resting
    // pair is not reported again, the bullet's contact comes at its
    // analytic time counted from the guard's time (10/60 + (2 − 0.01 −
    // 0.001) / 200, never late), and the bullet never goes past the plate's
    // middle (half its thickness is the pair's tolerated depth).
    let (mut bodies, mut colliders) = (RigidBodySet::new(), ColliderSet::new());
    let mut parameters = IntegrationParameters { dt: 1.0 / 60.0, ..Default::default() };
    parameters.normalized_max_linear_velocity = f64::MAX;
    let plate = bodies.insert(RigidBodyBuilder::fixed());
    colliders.insert_with_parent(ColliderBuilder::cuboid(2.0, 2.0, 0.001), plate, &mut bodies);
    let ball = bodies.insert(RigidBodyBuilder::dynamic().translation(Vector::new(1.0, 0.0, 0.101)));
    colliders.insert_with_parent(ColliderBuilder::cuboid(0.1, 0.1, 0.1), ball, &mut bodies);
    let mut guard = Guard::new(&bodies, &mut colliders, &[plate, ball], &parameters, GuardOptions::default())
        .expect("cuboids");
    let mut rapier = Rapier::new();
    let mut events = Vec::new();
    let mut bullet = None;
    for step in 0..40 {
        if step == 10 {
            let handle = bodies.insert(
                RigidBodyBuilder::dynamic()
                    .translation(Vector::new(-1.0, 0.0, 2.0))
                    .linvel(Vector::new(0.0, 0.0, -200.0)),
            );
            // A triangle mesh, as rapier applications load bullets: rapier
            // does not see it coming (its speculative contacts would slow a
            // cuboid within the step before it touches).
            let (vertices, indices) = parry3d_f64::shape::Cuboid::new(Vector::splat(0.01)).to_trimesh();
            let mesh = ColliderBuilder::trimesh(vertices, indices).expect("a closed box");
            colliders.insert_with_parent(mesh.density(1000.0), handle, &mut bodies);
            parameters.dt = 1.0 / 120.0;
            guard.set_bodies(&bodies, &mut colliders, &[plate, ball, handle], &parameters).expect("cuboids");
            assert!((guard.time() - 10.0 / 60.0).abs() < 1e-15, "{}", guard.time());
            bullet = Some(handle);
        }
        if step == 30 {
            guard
                .set_bodies(&bodies, &mut colliders, &[plate, bullet.expect("added")], &parameters)
                .expect("cuboids");
        }
        let stepped = guard
            .step(&mut bodies, |bodies, dt| {
                rapier.step(bodies, &mut colliders, Vector::ZERO, &parameters, dt)
            })
            .expect("decided");
        events.extend(stepped.iter().cloned());
        if let Some(bullet) = bullet {
            let bottom = bodies[bullet].translation().z - 0.01;
            assert!(bottom > 0.0, "the bullet's bottom at {bottom} after step {step}");
        }
    }
    assert_eq!(guard.steps(), 40);
    let started: Vec<_> = events
        .iter()
        .filter_map(|e| match e {
            GuardEvent::Started { a, b, contact } => Some((*a, *b, contact.time)),
            _ => None,
        })
        .collect();
    let resting = started.iter().filter(|(a, b, _)| [*a, *b].contains(&ball)).count();
    assert_eq!(resting, 1, "the resting pair is reported once: {started:?}");
    let bullet = bullet.expect("added");
    let (_, _, time) =
        *started.iter().find(|(a, b, _)| [*a, *b].contains(&bullet)).expect("the bullet's contact");
    let analytic = 10.0 / 60.0 + (2.0 - 0.01 - 0.001) / 200.0;
    assert!(time <= analytic + 1e-12 && analytic - time < 1e-9, "{time} vs {analytic}");
}

#[test]
fn a_guards_skin_is_checked_and_a_zero_skin_still_takes_balls() {
    use nearmiss::guard::{Guard, GuardError, GuardOptions};
    use rapier3d_f64::prelude::*;
    let (mut bodies, mut colliders) = (RigidBodySet::new(), ColliderSet::new());
    let ball = bodies.insert(RigidBodyBuilder::dynamic());
    colliders.insert_with_parent(ColliderBuilder::ball(0.5), ball, &mut bodies);
    let parameters = IntegrationParameters::default();
    for skin in [-1.0, f64::NAN, f64::INFINITY] {
        let options = GuardOptions { skin, ..GuardOptions::default() };
        let refused = Guard::new(&bodies, &mut colliders, &[ball], &parameters, options);
        assert!(matches!(refused, Err(GuardError::Skin(_))), "skin {skin}");
    }
    for depth in [0.0, -1.0, f64::NAN, f64::INFINITY] {
        let options = GuardOptions { tolerated_depth: depth, ..GuardOptions::default() };
        let refused = Guard::new(&bodies, &mut colliders, &[ball], &parameters, options);
        assert!(matches!(refused, Err(GuardError::ToleratedDepth(_))), "tolerated depth {depth}");
    }
    // No skin: the round shape's polyhedron is drawn to a quarter of
    // rapier's allowed linear error instead.
    let options = GuardOptions { skin: 0.0, ..GuardOptions::default() };
    assert!(Guard::new(&bodies, &mut colliders, &[ball], &parameters, options).is_ok());
}

#[test]
fn turned_boxes_meeting_head_on_far_from_the_origin_bounce_apart() {
    // Issue 43: equal boxes (0.5 × 0.4 × 0.3, 2.5 kg) turned 35° about
    // (1, 1, 0), at z = 120, approaching along their common long axis at 2
    // each, restitution 1, under Simulate at dt 1/60: the guard had frozen
    // both at the contact (momentum 10 → 0). They must bounce apart: moving
    // away from each other along the line of their centres at the end, the
    // total momentum kept (0, to 1% of one box's). (How fast they leave is
    // rapier's solve: `decisive.rs` holds it to rapier alone's.)
    let turn = nalgebra::UnitQuaternion::from_axis_angle(
        &nalgebra::Unit::new_normalize(Vector::new(1.0, 1.0, 0.0)),
        35f64.to_radians(),
    );
    let axis = turn * Vector::x();
    let body = |name: &str, side: Real| {
        let (p, v) = (Vector::new(0.0, 0.0, 120.0) + axis * (0.3 * side), axis * (-2.0 * side));
        format!(
            r#"(name: "{name}", mesh: Box(half_extents: (0.25, 0.2, 0.15)), position: ({:?}, {:?}, {:?}),
                orientation: AxisAngle(axis: (1.0, 1.0, 0.0), degrees: 35.0), velocity: ({:?}, {:?}, {:?}),
                density: {:?}),"#,
            p.x,
            p.y,
            p.z,
            v.x,
            v.y,
            v.z,
            2.5 / (0.5 * 0.4 * 0.3)
        )
    };
    let (scene, result) = simulate(&format!(
        r#"Scene(
            name: "head-on", dt: 0.016666666666666666, duration: 0.5,
            on_contact: Simulate(restitution: 1.0, friction: 0.0),
            bodies: [{}{}],
        )"#,
        body("left", -1.0),
        body("right", 1.0)
    ));
    assert!(result.first_contact.is_some(), "the boxes meet");
    let [a, b] = [result.final_states[0], result.final_states[1]];
    let mass = scene.model().bodies[0].mass.expect("density gives a mass");
    let apart = (b.position - a.position).normalize().dot(&(b.velocity - a.velocity));
    assert!(apart > 1.0, "not bouncing apart: {apart} along the centres' line");
    assert!(
        (a.velocity + b.velocity).norm() * mass < 0.01 * 2.5 * 2.0,
        "momentum {:?}",
        a.velocity + b.velocity
    );
}

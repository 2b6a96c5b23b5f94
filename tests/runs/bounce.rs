//! `on_contact: Bounce`: analytic outcomes of simple collisions, momentum
//! conservation in a crowd, and no body ever inside another.

use crate::ball_rest;
use nearmiss::math::{Real, Vector};
use nearmiss::run::run;
use nearmiss::samples::Rng;
use nearmiss::scene::Scene;

#[test]
fn equal_spheres_head_on_exchange_velocities() {
    // Two equal icospheres (vertices on the axes: the contact is vertex to
    // vertex on the x axis), one at rest: an elastic impact gives all the
    // velocity to the other. Contact at t = (3 - 2) / 2 = 0.5.
    let scene = Scene::from_ron_str(
        r#"Scene(name: "head_on", dt: 0.01, duration: 1.0, on_contact: Bounce(restitution: 1.0),
            trace: (pairs: All, every: 1),
            bodies: [
                (name: "a", mesh: Icosphere(radius: 1.0, subdivisions: 1), density: 1.0, velocity: (2.0, 0.0, 0.0)),
                (name: "b", mesh: Icosphere(radius: 1.0, subdivisions: 1), density: 1.0, position: (3.0, 0.0, 0.0)),
            ])"#,
    )
    .unwrap();
    let result = run(&scene);
    assert_eq!(result.contacts.len(), 1, "{:?}", result.contacts);
    let contact = &result.contacts[0];
    assert!(contact.time <= 0.5 && contact.time > 0.5 - 1e-6, "{}", contact.time);
    // After the step of the impact, a stands still and b moves at 2: the
    // gap grows at 2 per unit time from (near) zero.
    let last = result.trace.last().unwrap();
    let gap_expected = 2.0 * (1.0 - 0.5);
    // a stopped at the contact for the rest of its step (at most dt lost).
    assert!(
        (last.distance - gap_expected).abs() <= 2.0 * scene.model().dt + 1e-6,
        "gap {} at the end, expected about {gap_expected}",
        last.distance
    );
    assert!(result.final_states[0].velocity.norm() <= 1e-9, "{}", result.final_states[0].velocity);
    assert!((result.final_states[1].velocity - Vector::new(2.0, 0.0, 0.0)).norm() <= 1e-9);
    // The gap never shrinks after the contact (a is at rest).
    let after: Vec<Real> = result.trace.iter().filter(|r| r.time > 0.51).map(|r| r.distance).collect();
    assert!(after.windows(2).all(|w| w[1] >= w[0]));
    assert!((after[1] - after[0] - 2.0 * scene.model().dt).abs() <= 1e-9);
}

#[test]
fn a_ball_between_two_walls_keeps_bouncing() {
    // A unit-speed ball of radius 0.5 between walls whose faces are at ±2:
    // contacts near t = 1.5 (right wall), 4.5 (left), 7.5 (right); elastic,
    // so it keeps its speed.
    let scene = Scene::from_ron_str(
        r#"Scene(name: "walls", dt: 0.01, duration: 8.0, on_contact: Bounce(restitution: 1.0),
            bodies: [
                (name: "ball", mesh: Icosphere(radius: 0.5, subdivisions: 2), density: 1.0, velocity: (1.0, 0.0, 0.0)),
                (name: "left", mesh: Box(half_extents: (0.5, 2.0, 2.0)), position: (-2.5, 0.0, 0.0), fixed: true),
                (name: "right", mesh: Box(half_extents: (0.5, 2.0, 2.0)), position: (2.5, 0.0, 0.0), fixed: true),
            ])"#,
    )
    .unwrap();
    let result = run(&scene);
    assert!((result.final_states[0].velocity.norm() - 1.0).abs() <= 1e-9);
    let times: Vec<Real> = result.contacts.iter().map(|c| c.time).collect();
    assert_eq!(times.len(), 3, "{times:?}");
    // Each bounce may lose up to one step (the ball holds still for the rest
    // of the step it hit in), never more, and comes early by at most the
    // contact distance (1e-6 of the pair size, about 3.4e-6) over the speed.
    let expected = [1.5, 4.5, 7.5];
    for (k, (&t, &e)) in times.iter().zip(&expected).enumerate() {
        let lost = k as Real * scene.model().dt;
        assert!(t <= e + lost + 1e-9 && t >= e - 1e-5, "bounce {k} at {t}, expected {e} (+ up to {lost})");
    }
}

#[test]
fn a_crowd_conserves_momentum_and_never_interpenetrates() {
    // 24 tumbling bodies, no walls, elastic: the total momentum is constant
    // (stopping a body for the rest of a step does not change its velocity),
    // and no pair's distance at any step's end is zero.
    let mut rng = Rng::new(17);
    let mut text = String::from(
        "Scene(name: \"crowd\", dt: 0.01, steps: 150, on_contact: Bounce(restitution: 1.0), trace: (pairs: All, every: 1), bodies: [",
    );
    let mut momentum = Vector::zeros();
    for k in 0..24 {
        let position = rng.in_unit_ball() * 2.0;
        let velocity = rng.in_unit_ball() * 2.0 - position * 0.5;
        let spin = rng.in_unit_ball() * 5.0;
        let mesh = if k % 2 == 0 {
            "Box(half_extents: (0.2, 0.15, 0.1))"
        } else {
            "Icosphere(radius: 0.2, subdivisions: 1)"
        };
        text.push_str(&format!(
            "(name: \"b{k}\", mesh: {mesh}, density: 1.0, position: ({:?}, {:?}, {:?}), velocity: ({:?}, {:?}, {:?}), angular_velocity: ({:?}, {:?}, {:?})),",
            position.x, position.y, position.z, velocity.x, velocity.y, velocity.z, spin.x, spin.y, spin.z
        ));
    }
    text.push_str("])");
    let scene = Scene::from_ron_str(&text).unwrap();
    for body in scene.model().bodies.iter() {
        momentum += body.velocity * body.mass.unwrap();
    }
    let result = run(&scene);
    assert!(result.contacts.len() >= 5, "{} contacts", result.contacts.len());
    for record in &result.trace {
        assert!(record.distance > 0.0, "pair {:?} touching at t = {}", record.pair, record.time);
    }
    let end: Vector = result
        .final_states
        .iter()
        .zip(scene.model().bodies.iter())
        .map(|(state, body)| state.velocity * body.mass.unwrap())
        .sum();
    assert!((end - momentum).norm() <= 1e-9 * (1.0 + momentum.norm()), "momentum {momentum} -> {end}");
}

#[test]
fn a_ball_pressed_on_the_floor_keeps_its_redetection_distance() {
    // The shipped ball_rest scene under Bounce(0.5): the ball bounces lower
    // and lower and then lies on the floor, bouncing at every step without
    // leaving it (an episode of contacts that never re-arms). Each contact
    // of an episode is re-detected within `bounce_redetect_fraction` of
    // the episode's distance; the first contact is declared at no less than
    // the CCD's target, `TARGET_FRACTION` of its contact distance `c` (the
    // contract, with no minimum separation), so no contact distance may
    // fall below their product times `c`. (It used to
    // halve at every bounce until conservative advancement crawled at the
    // rounding floor: the 10,000-body box stopped undecided.)
    let scene = Scene::from_ron_str(&ball_rest::under_bounce()).unwrap();
    let result = run(&scene);
    assert!(matches!(result.termination, nearmiss::run::Termination::Completed), "{:?}", result.termination);
    assert!(
        result.contacts.len() > 100,
        "{} contacts: the ball should come to lie on the floor",
        result.contacts.len()
    );
    let first = result.contacts[0].contact_distance;
    let least = result.contacts.iter().map(|c| c.contact_distance).fold(Real::INFINITY, Real::min);
    let floor = scene.model().parameters.bounce_redetect_fraction * nearmiss::ccd::TARGET_FRACTION * first;
    assert!(least >= floor, "a contact distance of {least:e} against {first:e} at the first contact");
    // The ball never goes through the floor: every contact is at a positive distance.
    assert!(result.contacts.iter().all(|c| c.closest.distance > 0.0));
}

/// Bodies far apart under gravity, never meeting: icospheres spinning (a
/// steady spin: under `Bounce`, which checks no energies, the stepper
/// steps them from their states alone), a tumbling box (the gyroscopic
/// solve) and an icosphere on a spring. Under `Bounce` each ends where
/// the same run under `Record` (energies checked: every body through the
/// integrator's general entry) puts it, bit for bit.
#[test]
fn bounce_steps_bodies_as_record_does_where_none_meet() {
    let scene = |on_contact: &str| {
        Scene::from_ron_str(&format!(
            r#"Scene(name: "apart", dt: 0.005, duration: 0.5, on_contact: {on_contact}, gravity: (0.0, 0.0, -9.8),
            springs: [(body: "bob", anchor: (1.0, -20.0, 1.0), stiffness: 40.0)],
            bodies: [
                (name: "ball", mesh: Icosphere(radius: 0.5, subdivisions: 1), density: 1.0,
                 velocity: (0.3, -0.2, 1.0), angular_velocity: (3.0, -7.0, 2.0)),
                (name: "tumbler", mesh: Box(half_extents: (0.1, 0.2, 0.3)), density: 1.0, position: (0.0, 20.0, 0.0),
                 angular_velocity: (0.5, 4.0, 1.0)),
                (name: "bob", mesh: Icosphere(radius: 0.2, subdivisions: 1), density: 1.0, position: (1.0, -20.0, 0.0),
                 angular_velocity: (0.0, 0.0, 5.0)),
                (name: "ball2", mesh: Icosphere(radius: 0.3, subdivisions: 2), density: 2.0, position: (20.0, 0.0, 0.0),
                 velocity: (-1.0, 0.0, 0.0), angular_velocity: (-9.0, 1.0, 0.5)),
            ])"#
        ))
        .unwrap()
    };
    let (record, bounce) = (run(&scene("Record")), run(&scene("Bounce(restitution: 0.5)")));
    assert!(record.contacts.is_empty() && bounce.contacts.is_empty());
    assert_eq!((record.steps, bounce.steps), (100, 100));
    assert_eq!(record.final_states, bounce.final_states);
}

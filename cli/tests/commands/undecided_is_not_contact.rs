//! Symptom: a plate spinning at 1e6 rad/s beside a wall it never reaches
//! was reported as "first contact ... (OutOfIterations)" with exit 0. A
//! query that cannot decide ends the run as undecided, never as a contact;
//! and the spin-swept bound makes this motion decidable.

use nearmiss::run::{run, Termination};
use nearmiss::scene::Scene;

/// The plate (half 1 × 1 × 0.01, spinning about z) reaches at most √2 from
/// the spin axis; the wall's face is at `x = wall − 0.1`.
fn scene(wall: f64, max_iterations: usize, spin: f64) -> Scene {
    Scene::from_ron_str(&format!(
        r#"Scene(name: "spin", dt: 0.01, duration: 0.1, ccd: (max_iterations: {max_iterations}), bodies: [
            (name: "wall", mesh: Box(half_extents: (0.1, 2.0, 2.0)), position: ({wall:?}, 0.0, 0.0), fixed: true),
            (name: "plate", mesh: Box(half_extents: (1.0, 1.0, 0.01)), angular_velocity: (0.0, 0.0, {spin:?}), kinematic: true),
        ])"#
    ))
    .unwrap()
}

#[test]
fn a_fast_spin_that_never_reaches_the_wall_is_no_contact() {
    let result = run(&scene(1.55, 10_000, 1e6));
    assert_eq!(result.termination, Termination::Completed);
    assert!(result.contacts.is_empty(), "{:?}", result.first_contact);
}

#[test]
fn a_fast_spin_that_reaches_the_wall_is_not_late() {
    // The corner at (1, -1, ±0.01), r = √2 from the spin axis, turns towards
    // the wall's face at x = 1.1: x = r cos θ reaches 1.1 after turning
    // π/4 − acos(1.1 / r) at 1e6 rad/s.
    let result = run(&scene(1.2, 10_000, 1e6));
    let contact = result.first_contact.expect("the corner hits the wall");
    let r = 2.0f64.sqrt();
    let analytic = (std::f64::consts::FRAC_PI_4 - (1.1 / r).acos()) / 1e6;
    assert!(contact.time <= analytic && analytic - contact.time < 1e-9, "{} vs {analytic}", contact.time);
}

/// A torus (tube radius 0.2 about a circle of radius 1, 48 segments, its
/// innermost chords 0.798 from its axis) spinning about its axis at 60
/// rad/s around a fixed bar (half 0.55 × 0.55 × 1) through its hole, whose
/// edges (0.778 from the axis) it never reaches. The hulls overlap, so
/// only the search decides, step by rate-bounded step.
fn ring_around_bar(max_iterations: usize) -> Scene {
    Scene::from_ron_str(&format!(
        r#"Scene(name: "spin", dt: 0.01, duration: 0.1, ccd: (max_iterations: {max_iterations}), bodies: [
            (name: "bar", mesh: Box(half_extents: (0.55, 0.55, 1.0)), fixed: true),
            (name: "ring", mesh: Torus(major: 1.0, minor: 0.2), angular_velocity: (0.0, 0.0, 60.0), kinematic: true),
        ])"#
    ))
    .unwrap()
}

#[test]
fn a_query_out_of_iterations_ends_the_run_undecided() {
    // Too few iterations to decide: a spin of 0.6 rad a step (under the
    // radian from which the spin-swept regions are tried) 0.02 from the
    // bar takes many rate-bounded steps; with 10,000 it completes, no
    // contact. (A plate's corner passing 6.4e-6 from a wall face was such
    // a case until the hulls' advancement took steps of its own pace.)
    let decided = run(&ring_around_bar(10_000));
    assert_eq!(decided.termination, Termination::Completed);
    assert!(decided.contacts.is_empty(), "{:?}", decided.first_contact);
    let result = run(&ring_around_bar(5));
    match result.termination {
        Termination::Undecided { pair, time, step, iterations } => {
            assert_eq!((pair, step, iterations), ((0, 1), 0, 5));
            assert!(time > 0.0 && time == result.end_time);
        }
        other => panic!("expected undecided, got {other:?}"),
    }
    assert!(result.contacts.is_empty() && result.first_contact.is_none());
    let summary = nearmiss_cli::output::Summary::of(&result).to_json();
    assert!(summary.contains("\"termination\": \"undecided at step 0: the CCD of `bar` / `ring`"));
    assert!(summary.contains("\"first_contact\": null"));
}

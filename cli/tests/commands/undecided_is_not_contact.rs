//! Symptom: a plate spinning at 1e6 rad/s beside a wall it never reaches
//! was reported as "first contact ... (OutOfIterations)" with exit 0. A
//! query that cannot decide ends the run as undecided, never as a contact;
//! and the spin-swept bound makes this motion decidable.

use nearmiss::scene::Scene;
use nearmiss::stepper::{run, Termination};

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

#[test]
fn a_query_out_of_iterations_ends_the_run_undecided() {
    // Too few iterations to decide: a spin of 0.9 rad a step (under the
    // radian from which the spin-swept cylinder is tried) whose corners
    // (√2 from the axis) pass 6.4e-6 from the wall's face at 1.41422 takes
    // many rate-bounded steps (with 10,000 it completes, no contact).
    let result = run(&scene(1.51422, 5, 90.0));
    match result.termination {
        Termination::Undecided { pair, time, step, iterations } => {
            assert_eq!((pair, step, iterations), ((0, 1), 0, 5));
            assert!(time > 0.0 && time == result.end_time);
        }
        other => panic!("expected undecided, got {other:?}"),
    }
    assert!(result.contacts.is_empty() && result.first_contact.is_none());
    let summary = nearmiss_cli::output::Summary::of(&result).to_json();
    assert!(summary.contains("\"termination\": \"undecided at step 0: the CCD of `wall` / `plate`"));
    assert!(summary.contains("\"first_contact\": null"));
}

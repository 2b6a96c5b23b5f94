//! Issue 43 §1 and §3: where rapier alone holds (no mesh through another,
//! no overlap beyond its allowed linear error), the guarded run is rapier's
//! run, pose for pose and velocity for velocity, bit for bit: the guard only
//! read. And no guarded body is ever held still while rapier moves it.
//!
//! The worlds are `tests/support/guard_worlds.rs`'s, written from physics;
//! each runs twice in the test, rapier alone and guarded. Where a world has
//! an analytic answer (v²/(2µg), an incline's acceleration) the guarded run
//! is held to it too.

use crate::guard_worlds::{box_on_floor, box_on_incline, rapier_holds, GuardWorld, WorldRun};
use nearmiss::guard::{GuardEvent, GuardOptions};
use nearmiss::math::{Real, Vector};

/// rapier 0.36's allowed linear error under its default parameters.
const ALLOWED_ERROR: Real = 0.005;

/// A world run twice: rapier alone and guarded (default options).
fn both(make: impl Fn() -> GuardWorld) -> (WorldRun, WorldRun, Vec<bool>) {
    let world = make();
    let dynamic = world.handles.iter().map(|(_, h)| world.bodies[*h].is_dynamic()).collect();
    let alone = world.run_alone();
    let guarded = make().run_guarded(GuardOptions::default()).expect("the guard decides");
    (alone, guarded, dynamic)
}

#[test]
fn where_rapier_holds_the_guarded_run_is_rapiers_bit_for_bit() {
    let count = rapier_holds().len();
    for k in 0..count {
        let name = rapier_holds().swap_remove(k).name;
        let (alone, guarded, dynamic) = both(|| rapier_holds().swap_remove(k));
        // The world's premise: rapier alone holds it.
        let (deepest, step, i, j) = alone.deepest();
        assert!(
            deepest <= ALLOWED_ERROR,
            "{name}: rapier alone overlaps {i}/{j} by {deepest} after step {step}"
        );
        // The guard only read.
        assert_eq!(guarded.rewinds, 0, "{name}: the guard moved the world back");
        assert!(
            !guarded.events.iter().any(|e| matches!(e, GuardEvent::Overlap { .. })),
            "{name}: the guard pushed a pair apart"
        );
        for (s, (a, g)) in alone.poses.iter().zip(&guarded.poses).enumerate() {
            assert_eq!(a, g, "{name}: the poses differ after step {}", s + 1);
        }
        assert_eq!(alone.velocities, guarded.velocities, "{name}: the velocities differ");
        assert_eq!(guarded.frozen(&dynamic, 1e-9), None, "{name}: a body held still while rapier moves it");
    }
}

#[test]
fn a_box_sliding_from_an_exact_touch_stops_where_v_squared_over_2_mu_g_says() {
    // v0 = |(2.4, 3.2, 0)| = 4, µ = 0.3, g = 9.81: it slows at µg = 2.943
    // (2.528 units/s after 0.5 s), slides v0²/(2µg) = 2.718 and stops
    // (issue 43: the guard had held it still at its start). rapier's
    // friction, solved with its contact, gives both within 1%; from 1e-3
    // above and 1e-4 inside the same.
    let slide = 16.0 / (2.0 * 0.3 * 9.81);
    let half_second = 4.0 - 0.3 * 9.81 * 0.5;
    for height in [0.0, 1e-3, -1e-4] {
        let make = || box_on_floor("slide", [0.0; 3], height, Vector::new(2.4, 3.2, 0.0));
        let (_, guarded, _) = both(make);
        // It starts at the origin; step 60 ends at 0.5 s.
        let travelled = guarded.last_pose(1).translation.vector.xy().norm();
        assert!(
            (travelled - slide).abs() < 0.01 * slide,
            "height {height}: slid {travelled} against {slide}"
        );
        let speed = guarded.velocities[59][1].0.xy().norm();
        assert!((speed - half_second).abs() < 0.01 * half_second, "height {height}: {speed} at 0.5 s");
        let last = guarded.velocities.last().expect("steps")[1].0.norm();
        assert!(last < 1e-3, "height {height}: still moving at {last} after 2.5 s");
    }
}

#[test]
fn a_box_on_a_30_degree_incline_slides_below_tan_theta_and_holds_above() {
    // µ = 0.2 < tan 30°: a = g (sin θ − µ cos θ) = 3.2057, 6.41 units/s
    // after 2 s (the guard had held it still); µ = 0.8 > tan 30°: at rest.
    let (_, guarded, _) = both(|| box_on_incline(0.2));
    let speed = guarded.velocities.last().expect("steps")[1].0.norm();
    let expected = 9.81 * (0.5 - 0.2 * (3.0f64).sqrt() / 2.0) * 2.0;
    assert!((speed - expected).abs() < 0.01 * expected, "µ 0.2: {speed} against {expected}");
    let (_, guarded, _) = both(|| box_on_incline(0.8));
    let speed = guarded.velocities.last().expect("steps")[1].0.norm();
    assert!(speed < 1e-3, "µ 0.8: sliding at {speed}");
}

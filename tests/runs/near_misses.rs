//! `near_misses: (within: D)` (issue 30 §2): a run lists every pair that
//! came within `D` without touching, with a certified bracket holding the
//! analytic closest approach; pairs that stay farther, and pairs that
//! touch, are not listed; the broad phase and the threads change nothing.

use crate::crowd;
use nearmiss::kernels::point_triangle;
use nearmiss::math::Real;
use nearmiss::mesh::{mesh_distance, DistanceKernel, DistanceSearch};
use nearmiss::run::{run, run_with, RunOptions};
use nearmiss::scene::Scene;

/// A cube passes a fixed cube 0.25 from its face (t in [2/3, 4/3]); a ball
/// of radius 0.3 drops towards its top face, its lowest vertex 0.2 above
/// it at the run's end (t = 2); a third cube stays 4 away.
fn pass_by(near_misses: &str, duration: Real) -> Scene {
    Scene::from_ron_str(&format!(
        r#"Scene(name: "pass_by", dt: 0.01, duration: {duration:?}, near_misses: {near_misses},
            bodies: [
                (name: "fixed", mesh: Box(half_extents: (0.5, 0.5, 0.5)), fixed: true),
                (name: "passer", mesh: Box(half_extents: (0.5, 0.5, 0.5)), position: (-3.0, 1.25, 0.2), velocity: (3.0, 0.0, 0.0)),
                (name: "far", mesh: Box(half_extents: (0.5, 0.5, 0.5)), position: (0.0, -5.0, 0.0), velocity: (0.0, 0.0, 1.0)),
                (name: "ball", mesh: Icosphere(radius: 0.3, subdivisions: 1), position: (0.0, 0.0, 3.0), velocity: (0.0, 0.0, -1.0)),
            ])"#
    ))
    .unwrap()
}

/// Every pair, within 0.5.
const ALL: &str = "(within: 0.5)";

/// The bracket's width: the closest-approach tolerance, 1e-6 of the
/// smaller radius (0.3 for the ball, √3/2 for the cubes).
const WIDTH: Real = 1e-6 * 0.87;

#[test]
fn the_pairs_that_come_near_are_listed_with_their_analytic_approach() {
    let scene = pass_by(ALL, 2.0);
    let result = run(&scene);
    let listed: Vec<(&str, &str)> = result
        .near_misses
        .iter()
        .map(|m| (result.bodies[m.body_a].as_str(), result.bodies[m.body_b].as_str()))
        .collect();
    // Nearest first; `far` never within 0.5.
    assert_eq!(listed, [("fixed", "ball"), ("fixed", "passer")]);
    let (ball, passer) = (&result.near_misses[0], &result.near_misses[1]);
    for (miss, analytic) in [(ball, 0.2), (passer, 0.25)] {
        assert!(miss.decided);
        assert!(miss.lower <= analytic && analytic <= miss.distance * (1.0 + 1e-12), "{miss:?}");
        assert!(miss.distance - miss.lower <= WIDTH, "{miss:?}");
        let gap = miss.closest.point_b - miss.closest.point_a;
        assert!((gap.norm() - miss.distance).abs() < 1e-12);
        // The poses are the bodies' at `time`: the meshes there are
        // `distance` apart, between the same points.
        let model = scene.model();
        let (mesh_a, mesh_b) = (&model.bodies[miss.body_a].mesh, &model.bodies[miss.body_b].mesh);
        let search = DistanceSearch::new(DistanceKernel::Exact, None);
        let there =
            mesh_distance(mesh_a, &miss.pose_a, mesh_b, &miss.pose_b, &search, &mut Default::default());
        assert!((there.distance - miss.distance).abs() < 1e-12, "{there:?} {miss:?}");
        // Each closest point lies on its triangle, placed by its pose.
        for (mesh, pose, triangle, point) in [
            (mesh_a, &miss.pose_a, miss.closest.triangle_a, &miss.closest.point_a),
            (mesh_b, &miss.pose_b, miss.closest.triangle_b, &miss.closest.point_b),
        ] {
            let on = point_triangle(point, &mesh.triangle(triangle).map(|p| pose * p));
            assert!(on.distance < 1e-12, "{on:?} {miss:?}");
        }
    }
    // The ball is closest at the run's end; the passer while the faces
    // overlap (within the width's slack of its ends).
    assert!((ball.time - 2.0).abs() < 1e-9, "{ball:?}");
    assert!(passer.time > 2.0 / 3.0 - 1e-3 && passer.time < 4.0 / 3.0 + 1e-3, "{passer:?}");
}

#[test]
fn a_pair_that_touches_is_a_contact_not_a_near_miss() {
    // Longer: the ball reaches the box at t = 2.2 (its vertex at 0.3 below
    // its centre, 2.7 − 0.5 = 2.2 of travel); the run stops there.
    let result = run(&pass_by(ALL, 3.0));
    let contact = result.first_contact.as_ref().expect("the ball lands");
    assert!(contact.time <= 2.2 && 2.2 - contact.time < 1e-6);
    let listed: Vec<&str> = result.near_misses.iter().map(|m| result.bodies[m.body_b].as_str()).collect();
    assert_eq!(listed, ["passer"], "{:?}", result.near_misses);
}

/// The narrow phase takes a near-miss screen's "apart" only where it
/// proves the pair farther than the contact distance: with `within` far
/// inside a 0.3 minimum separation, the passer (0.25 from the fixed cube's
/// face, edges closing) still touches where the analysis says, when its
/// edge comes within 0.3: `√(0.3² − 0.25²)` from the fixed cube's face
/// plane along x, at `t = (2 − √0.0275) / 3`.
#[test]
fn a_distance_inside_the_contact_distance_hides_no_contact() {
    let scene = |near_misses: &str| {
        Scene::from_ron_str(&format!(
            r#"Scene(name: "inside", dt: 0.01, duration: 1.0, near_misses: {near_misses}, ccd: (minimum_separation: 0.3),
                bodies: [
                    (name: "fixed", mesh: Box(half_extents: (0.5, 0.5, 0.5)), fixed: true),
                    (name: "passer", mesh: Box(half_extents: (0.5, 0.5, 0.5)), position: (-3.0, 1.25, 0.2), velocity: (3.0, 0.0, 0.0)),
                ])"#
        ))
        .unwrap()
    };
    let analytic = (2.0 - (0.3_f64 * 0.3 - 0.25 * 0.25).sqrt()) / 3.0;
    for near_misses in ["(within: 0.01)", "(within: 0.29)", "(within: 0.5)"] {
        let result = run(&scene(near_misses));
        let contact = result.first_contact.as_ref().unwrap_or_else(|| panic!("{near_misses}: no contact"));
        assert!(contact.time <= analytic && analytic - contact.time < 1e-4, "{near_misses}: {contact:?}");
        assert!(result.near_misses.is_empty(), "{near_misses}: {:?}", result.near_misses);
    }
}

#[test]
fn only_the_pairs_asked_for_and_nothing_farther_than_asked() {
    let only = run(&pass_by(r#"(within: 0.5, pairs: Only([("passer", "fixed")]))"#, 2.0));
    assert_eq!(only.near_misses.len(), 1);
    assert_eq!((only.near_misses[0].body_a, only.near_misses[0].body_b), (0, 1));
    // Within 0.22: the ball (0.2) only.
    let closer = run(&pass_by("(within: 0.22)", 2.0));
    assert_eq!(closer.near_misses.len(), 1);
    assert_eq!(closer.bodies[closer.near_misses[0].body_b], "ball");
}

/// The broad phase (boxes grown by half the distance) and the all-pairs
/// run give the same near misses.
#[test]
fn the_broad_phase_changes_nothing() {
    let scene = pass_by(ALL, 2.0);
    let broad = run_with(&scene, RunOptions::default(), &mut |_| {});
    let all = run_with(&scene, RunOptions { broad_phase: false, ..RunOptions::default() }, &mut |_| {});
    assert_eq!(broad.near_misses.len(), all.near_misses.len());
    for (x, y) in broad.near_misses.iter().zip(&all.near_misses) {
        assert_eq!((x.body_a, x.body_b), (y.body_a, y.body_b));
        assert!(
            (x.distance - y.distance).abs() <= WIDTH && (x.lower - y.lower).abs() <= WIDTH,
            "{x:?} {y:?}"
        );
    }
}

#[test]
fn near_misses_are_refused_where_rapier_moves_the_bodies() {
    let error = Scene::from_ron_str(
        r#"Scene(name: "s", dt: 0.01, steps: 1, on_contact: Simulate(), near_misses: (within: 0.1), bodies: [
            (name: "a", mesh: Box(half_extents: (0.5, 0.5, 0.5)), fixed: true),
        ])"#,
    )
    .unwrap_err()
    .to_string();
    assert!(error.contains("near_misses") && error.contains("Simulate"), "{error}");
    let error = Scene::from_ron_str(
        r#"Scene(name: "s", dt: 0.01, steps: 1, near_misses: (within: -1.0), bodies: [
            (name: "a", mesh: Box(half_extents: (0.5, 0.5, 0.5)), fixed: true),
        ])"#,
    )
    .unwrap_err()
    .to_string();
    assert!(error.contains("near_misses.within"), "{error}");
}

/// A slow pass: a cube drifts at 0.1 along x past a fixed cube's edge, its
/// own edge 0.25 out in y and in z, so the pair stays 0.25·√2 apart for the
/// 1,500 steps (t in [5, 20]) their x-extents overlap: far more steps than
/// a pair holds before bracketing them (`MAX_HELD_STEPS`), with a flat
/// minimum (no step nearer than the others).
#[test]
fn a_long_flat_approach_is_bracketed_across_many_flushes() {
    let scene = Scene::from_ron_str(
        r#"Scene(name: "drift", dt: 0.01, duration: 20.0, near_misses: (within: 0.5), bodies: [
            (name: "fixed", mesh: Box(half_extents: (0.5, 0.5, 0.5)), fixed: true),
            (name: "drifter", mesh: Box(half_extents: (0.5, 0.5, 0.5)), position: (-1.5, 1.25, 1.25), velocity: (0.1, 0.0, 0.0)),
        ])"#,
    )
    .unwrap();
    let result = run(&scene);
    assert_eq!(result.near_misses.len(), 1, "{:?}", result.near_misses);
    let miss = &result.near_misses[0];
    let analytic = 0.25 * Real::sqrt(2.0);
    assert!(miss.decided);
    assert!(miss.lower <= analytic && analytic <= miss.distance * (1.0 + 1e-12), "{miss:?}");
    assert!(miss.distance - miss.lower <= WIDTH, "{miss:?}");
    assert!(miss.time > 5.0 - 1e-3 && miss.time <= 20.0, "{miss:?}");
}

/// A stated width: each bracket is at most that wide and still holds the
/// analytic approach; a width that is not a positive number is refused.
#[test]
fn a_scene_can_state_the_brackets_width() {
    let result = run(&pass_by("(within: 0.5, tolerance: 1e-3)", 2.0));
    assert_eq!(result.near_misses.len(), 2);
    for (miss, analytic) in result.near_misses.iter().zip([0.2, 0.25]) {
        assert!(miss.lower <= analytic && analytic <= miss.distance * (1.0 + 1e-12), "{miss:?}");
        assert!(miss.distance - miss.lower <= 1e-3, "{miss:?}");
    }
    for bad in ["0.0", "-1.0", "inf"] {
        let error = Scene::from_ron_str(&format!(
            r#"Scene(name: "s", dt: 0.01, steps: 1, near_misses: (within: 0.1, tolerance: {bad}), bodies: [
                (name: "a", mesh: Box(half_extents: (0.5, 0.5, 0.5)), fixed: true),
            ])"#
        ))
        .unwrap_err()
        .to_string();
        assert!(error.contains("near_misses.tolerance"), "{error}");
    }
}

#[test]
fn the_threads_change_no_near_miss() {
    // A crowd of 40 tumbling bodies bouncing off each other, every pair
    // within 0.3: the same list on one thread as on rayon's, whether the
    // brackets run on another thread while the run steps on (every batch,
    // the hand-over taken as free and 40 bodies as many) or not (the
    // default for so few bodies); and every
    // pair's bracket holds, within its width (1e-6 of the smaller radius,
    // at most 0.7 here).
    let scene = crowd::random_crowd(
        40,
        9,
        "on_contact: Bounce(restitution: 1.0), near_misses: (within: 0.3)",
        "density: 1.0",
    );
    let quiet = &mut |_| {};
    let one = run_with(&scene, RunOptions { parallel: false, ..RunOptions::default() }, quiet);
    assert!(one.near_misses.len() >= 10, "{} near misses", one.near_misses.len());
    let handed_over = RunOptions {
        parallel_narrow_phase_seconds: 0.0,
        parallel_integration_bodies: 0,
        parallel_trace_pairs: 0,
        ..RunOptions::default()
    };
    for options in [handed_over, RunOptions::default()] {
        let threads = run_with(&scene, options, quiet);
        assert_eq!(one.near_misses, threads.near_misses);
        assert_eq!(one.contacts, threads.contacts);
    }
    for miss in &one.near_misses {
        assert!(miss.decided && miss.lower <= miss.distance && miss.distance <= 0.3);
        assert!(miss.distance - miss.lower <= 1e-6 * 0.7, "{} {}: {:?}", miss.body_a, miss.body_b, miss);
    }
}

//! The broad phase and the threads change how a run is computed, not what
//! it computes: on a random scene of many tumbling bodies, the contacts and
//! the trace (every pair: sampled on the threads when there are threads)
//! are identical with and without threads, and the same with and without
//! the broad phase. Without it every pair is queried every step, so its CCD
//! starts warm from its last query (GJK's simplex on the hulls); with it a
//! pair new to the broad phase starts cold, and the advancement's steps,
//! hence the contact times, may differ by rounding (each within the
//! contract: never late, early by less than the contact distance allows).

use crate::crowd;
use nearmiss::run::{run_with, RunOptions, RunResult};
use nearmiss::scene::Scene;

/// Tumbling icospheres and boxes in a 6-unit cube, contacts recorded.
fn random_scene(bodies: usize, seed: u64) -> Scene {
    crowd::random_crowd(bodies, seed, "on_contact: Record, trace: (pairs: All)", "")
}

/// The same contacts (pairs, features' triangles aside) at times within
/// `1e-9` (the contact distances here are about 3e-7 at closing speeds of
/// about 1 to 10: a contact found early within the contract is earlier by
/// at most about 3e-7; the two runs agree far more closely), the same
/// trace and ending.
fn same_contacts(a: &RunResult, b: &RunResult) {
    assert_eq!(a.steps, b.steps);
    assert_eq!(a.contacts.len(), b.contacts.len());
    for (x, y) in a.contacts.iter().zip(&b.contacts) {
        assert_eq!((x.body_a, x.body_b, x.status), (y.body_a, y.body_b, y.status));
        assert!((x.time - y.time).abs() <= 1e-9, "{} {}: {} against {}", x.body_a, x.body_b, x.time, y.time);
        assert!(x.closest.distance <= x.contact_distance && y.closest.distance <= y.contact_distance);
    }
    assert_eq!(a.trace, b.trace);
    assert_eq!(a.termination, b.termination);
}

fn same_outcome(a: &RunResult, b: &RunResult) {
    assert_eq!(a.steps, b.steps);
    assert_eq!(a.contacts, b.contacts);
    assert_eq!(a.trace, b.trace);
    assert_eq!(a.termination, b.termination);
}

#[test]
fn threads_and_broad_phase_change_nothing() {
    let scene = random_scene(40, 9);
    let quiet = &mut |_| {};
    let reference =
        run_with(&scene, RunOptions { parallel: false, broad_phase: false, ..RunOptions::default() }, quiet);
    assert!(reference.contacts.len() >= 5, "the scene should have contacts: {}", reference.contacts.len());
    let broad = run_with(&scene, RunOptions { parallel: false, ..RunOptions::default() }, quiet);
    same_contacts(&reference, &broad);
    // The broad phase hands far fewer pairs to CCD than all 780.
    assert!(broad.counters.work.candidate_pairs < reference.counters.work.candidate_pairs / 4);
    let threaded = run_with(&scene, RunOptions::default(), quiet);
    same_outcome(&broad, &threaded);
    let pairs = 40 * 39 / 2;
    assert!(pairs >= RunOptions::default().parallel_trace_pairs && threaded.trace.len() > pairs);
}

/// Boxes kept between steps (`RunOptions::kept_boxes_bodies`, the broad
/// phase of many bodies, here from three): the contacts of the run that
/// queries every pair each step, and the same on the threads as on one.
#[test]
fn kept_boxes_change_nothing() {
    let quiet = &mut |_| {};
    for (bodies, seed) in [(40, 9), (120, 21)] {
        let scene = random_scene(bodies, seed);
        let reference = run_with(
            &scene,
            RunOptions { parallel: false, broad_phase: false, ..RunOptions::default() },
            quiet,
        );
        assert!(reference.contacts.len() >= 5, "{} contacts", reference.contacts.len());
        let kept = RunOptions { kept_boxes_bodies: 3, ..RunOptions::default() };
        let one = run_with(&scene, RunOptions { parallel: false, ..kept }, quiet);
        same_contacts(&reference, &one);
        assert!(one.counters.work.candidate_pairs < reference.counters.work.candidate_pairs / 4);
        same_outcome(&one, &run_with(&scene, kept, quiet));
    }
}

/// A crowd among many fixed bodies (posts on a lattice through the cube):
/// a run keeps the fixed bodies' boxes in a grid made once (from
/// `FIXED_APART_BODIES`, 64, of them) and pairs only the moving bodies each
/// step. The contacts, with the fixed posts among them, are those of the run
/// that queries every pair each step, and the same on the threads.
#[test]
fn many_fixed_bodies_kept_apart_change_nothing() {
    let mut text = String::from(
        "Scene(name: \"posts\", dt: 0.01, duration: 0.6, on_contact: Record, trace: (pairs: All), bodies: [",
    );
    for (k, x) in (0..4).flat_map(|i| (0..4).flat_map(move |j| (0..5).map(move |m| (i, j, m)))).enumerate() {
        let at = |n: i32, count: i32| -3.0 + 6.0 * (n as f64 + 0.5) / count as f64;
        text.push_str(&format!(
            "(name: \"post{k}\", mesh: Box(half_extents: (0.06, 0.06, 0.4)), position: ({:?}, {:?}, {:?}), fixed: true),",
            at(x.0, 4),
            at(x.1, 4),
            at(x.2, 5)
        ));
    }
    text.push_str(&crowd::crowd_bodies(30, 11, ""));
    text.push_str("])");
    let scene = Scene::from_ron_str(&text).unwrap();
    let quiet = &mut |_| {};
    let reference =
        run_with(&scene, RunOptions { parallel: false, broad_phase: false, ..RunOptions::default() }, quiet);
    let posts = |r: &RunResult| r.contacts.iter().filter(|c| c.body_a < 80 || c.body_b < 80).count();
    assert!(posts(&reference) >= 5, "the crowd should meet the posts: {} contacts", posts(&reference));
    let apart = run_with(&scene, RunOptions { parallel: false, ..RunOptions::default() }, quiet);
    same_contacts(&reference, &apart);
    let threaded = run_with(&scene, RunOptions::default(), quiet);
    same_outcome(&apart, &threaded);
}

/// Bodies at rest (free, no velocity) are kept apart like fixed ones: their
/// boxes made once, passed over in the integration. A scene of 80 resting
/// posts (posts 1 and 21 touching posts 0 and 20, a fixed block touching
/// post 40) and a tumbling crowd gives the contacts of the run that queries
/// every pair each step, the resting pairs' contacts among them, under
/// `Record` and under `Bounce` (the posts kinematic: the crowd bounces off
/// them, and each stops at its contacts within a step); and the same on the
/// threads.
#[test]
fn bodies_at_rest_kept_apart_change_nothing() {
    let at = |n: usize, count: usize| -3.0 + 6.0 * (n as f64 + 0.5) / count as f64;
    let mut posts: Vec<[f64; 3]> = (0..4)
        .flat_map(|i| (0..4).flat_map(move |j| (0..5).map(move |m| [at(i, 4), at(j, 4), at(m, 5)])))
        .collect();
    // Boxes of half-width 0.06 side by side, faces touching.
    posts[1] = [posts[0][0] + 0.12, posts[0][1], posts[0][2]];
    posts[21] = [posts[20][0], posts[20][1] + 0.12, posts[20][2]];
    let block = [posts[40][0] + 0.16, posts[40][1], posts[40][2]];
    let bounce = ("Bounce(restitution: 1.0)", ", kinematic: true", "density: 1.0");
    for (on_contact, post, crowd) in [("Record", "", ""), bounce] {
        let mut text =
            format!("Scene(name: \"resting\", dt: 0.01, duration: 0.6, on_contact: {on_contact}, bodies: [");
        for (k, [x, y, z]) in posts.iter().enumerate() {
            text.push_str(&format!(
                "(name: \"post{k}\", mesh: Box(half_extents: (0.06, 0.06, 0.4)), position: ({x:?}, {y:?}, {z:?}){post}),"
            ));
        }
        text.push_str(&crowd::crowd_bodies(30, 11, crowd));
        let [x, y, z] = block;
        text.push_str(&format!(
            "(name: \"block\", mesh: Box(half_extents: (0.1, 0.1, 0.1)), position: ({x:?}, {y:?}, {z:?}), fixed: true)])"
        ));
        let scene = Scene::from_ron_str(&text).unwrap();
        let quiet = &mut |_| {};
        let reference = run_with(
            &scene,
            RunOptions { parallel: false, broad_phase: false, ..RunOptions::default() },
            quiet,
        );
        let met =
            reference.contacts.iter().filter(|c| c.body_a < 80 && (80..110).contains(&c.body_b)).count();
        assert!(met >= 5, "{on_contact}: the crowd should meet the posts: {met} contacts");
        // (Under `Bounce` a resting pair is queried again, and met again,
        // when the crowd stops one of its posts.)
        let mut resting: Vec<(usize, usize)> = (reference.contacts.iter())
            .filter(|c| c.body_b < 80 || (c.body_a < 80 && c.body_b == 110))
            .map(|c| (c.body_a, c.body_b))
            .collect();
        resting.sort_unstable();
        resting.dedup();
        assert_eq!(resting, [(0, 1), (20, 21), (40, 110)], "{on_contact}: the resting pairs met");
        let apart = run_with(&scene, RunOptions { parallel: false, ..RunOptions::default() }, quiet);
        same_contacts(&reference, &apart);
        let threaded = run_with(&scene, RunOptions::default(), quiet);
        same_outcome(&apart, &threaded);
    }
}

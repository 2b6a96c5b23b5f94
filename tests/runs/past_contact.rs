//! Traces past contact: under `Record` bodies pass through each other and
//! the trace reads minus the depth, against analysis.

use nearmiss::run::run;
use nearmiss::scene::Scene;

/// A box (half extent 0.5) moving down at 1 through a fixed floor box
/// (top at z = 0, 0.5 thick, 4 wide): contact at t = 0.5; then both are
/// convex and the trace reads minus the shortest move that separates them.
#[test]
fn a_box_through_a_floor_traces_minus_its_exact_depth() {
    let scene = Scene::from_ron_str(
        r#"Scene(name: "through", dt: 0.01, duration: 1.2, on_contact: Record, trace: (pairs: All), bodies: [
            (name: "floor", mesh: Box(half_extents: (2.0, 2.0, 0.25)), position: (0.0, 0.0, -0.25), fixed: true),
            (name: "box", mesh: Box(half_extents: (0.5, 0.5, 0.5)), position: (0.0, 0.0, 1.0), velocity: (0.0, 0.0, -1.0)),
        ])"#,
    )
    .expect("scene");
    let result = run(&scene);
    assert!((result.contacts[0].time - 0.5).abs() < 1e-6, "{:?}", result.contacts[0].time);
    let mut overlapping = 0;
    for record in &result.trace {
        let t = record.time;
        // Apart: the gap. Overlapping (the box spans z in [0.5 − t,
        // 1.5 − t], the floor [−0.5, 0]): up by t − 0.5, or down by
        // 2 − t (its top below the floor's bottom), whichever is shorter;
        // sideways (2.5) never is.
        let expected = if t <= 0.5 { 0.5 - t } else { -(t - 0.5).min(2.0 - t) };
        assert!((record.distance - expected).abs() < 1e-12, "t = {t}: {} vs {expected}", record.distance);
        overlapping += usize::from(record.distance < 0.0);
    }
    assert!(overlapping > 60, "{overlapping} samples overlap");
}

/// The shipped ring (a torus, not convex) passing through a slab: its
/// lowest circle has vertices, so until the tube's bottom is nearer the
/// slab's bottom face the deepest vertex is exactly t − 0.5 deep; past
/// t = 0.75 the tube's points at the slab's mid-plane are inside, 0.25
/// deep; its vertices, 48 around the tube (7.5° apart, so some vertex is
/// within 0.25 · sin 3.75° of that plane), reach at least 0.25 less that.
#[test]
fn the_ring_through_the_slab_traces_minus_its_local_depth() {
    let scene =
        Scene::load(concat!(env!("CARGO_MANIFEST_DIR"), "/scenes/ring_through_slab.ron")).expect("scene");
    let result = run(&scene);
    let spacing = 0.25 * (3.75f64).to_radians().sin();
    for record in &result.trace {
        let t = record.time;
        if t <= 0.5 {
            assert!((record.distance - (0.5 - t)).abs() < 1e-12, "t = {t}: {}", record.distance);
        } else if t <= 0.745 {
            assert!((record.distance + (t - 0.5)).abs() < 1e-12, "t = {t}: {}", record.distance);
        } else if t >= 0.755 {
            assert!(
                record.distance <= -0.25 + spacing + 1e-12 && record.distance >= -0.25 - 1e-12,
                "t = {t}: {}",
                record.distance
            );
        }
    }
}

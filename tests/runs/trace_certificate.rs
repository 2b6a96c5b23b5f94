//! The trace settles most samples without a search: two convex meshes by
//! GJK warm-started from the last sample (its upper and lower bounds meet),
//! others when the hulls' gap meets the last closest triangle pair's
//! distance. Every sample, certified or searched, must equal a cold full
//! search at the same poses to rounding: checked on tumbling convex meshes
//! (an icosphere, a box) and a non-convex one (the T-handle), near and
//! far, sampled at every step and every seventh (where the closest
//! features have moved on between samples).

use nalgebra::{Isometry3, Translation3};
use nearmiss::mesh::{
    mesh_distance_relative, signed_distance, DistanceKernel, DistanceSearch, MeshDistanceScratch,
    SignedDistanceScratch,
};
use nearmiss::scene::Scene;

#[test]
fn every_sample_equals_a_cold_search() {
    for every in [1, 7] {
        samples_equal_a_cold_search(every);
    }
}

fn samples_equal_a_cold_search(every: u64) {
    let handle = concat!(env!("CARGO_MANIFEST_DIR"), "/scenes/meshes/t_handle.obj");
    let text = format!(
        r#"Scene(name: "certificate", dt: 0.01, steps: 150, on_contact: Record,
        trace: (pairs: All, every: {every}), poses: (every: {every}),
        bodies: [
            (name: "ball", mesh: Icosphere(radius: 0.5, subdivisions: 2), position: (-1.6, 0.0, 0.0),
             velocity: (0.5, 0.05, 0.0), angular_velocity: (3.0, 1.0, -2.0)),
            (name: "box", mesh: Box(half_extents: (0.4, 0.2, 0.3)), position: (0.2, 0.1, 0.0),
             angular_velocity: (-1.0, 4.0, 0.5)),
            (name: "handle", mesh: Obj(path: "{handle}"), position: (0.0, 1.8, 0.3),
             velocity: (0.0, -0.4, 0.0), angular_velocity: (0.3, 0.0, 5.0)),
        ])"#
    );
    let scene = Scene::from_ron_str(&text).unwrap();
    let result = nearmiss::run(&scene);
    assert_eq!(result.trace.len(), 3 * (result.steps as usize).div_ceil(every as usize) + 3);
    let pose = |step: u64, body: usize| {
        let r = result.poses.iter().find(|r| r.step == step && r.body == body).expect("a pose record");
        Isometry3::from_parts(Translation3::from(r.position.coords), r.orientation)
    };
    let mut scratch = MeshDistanceScratch::default();
    let mut near = 0;
    for record in &result.trace {
        let (a, b) = record.pair;
        let pos_ab = pose(record.step, a).inverse() * pose(record.step, b);
        let (mesh_a, mesh_b) = (&scene.model().bodies[a].mesh, &scene.model().bodies[b].mesh);
        let cold = mesh_distance_relative(
            mesh_a,
            mesh_b,
            &pos_ab,
            &DistanceSearch::new(DistanceKernel::Exact, None),
            &mut scratch,
        )
        .distance;
        // Where the surfaces meet (`Record` lets them pass), the trace is
        // signed: minus the depth at the same poses.
        let cold = if cold > 0.0 {
            cold
        } else {
            let identity = Isometry3::identity();
            signed_distance(mesh_a, &identity, mesh_b, &pos_ab, &mut SignedDistanceScratch::default()).value
        };
        let scale = pos_ab.translation.vector.norm() + mesh_a.radius() + mesh_b.radius();
        assert!(
            (record.distance - cold).abs() <= 64.0 * f64::EPSILON * scale,
            "step {} pair {:?}: traced {} against {}",
            record.step,
            record.pair,
            record.distance,
            cold
        );
        near += usize::from(cold < 0.2);
    }
    // The run passes close approaches, not only far pairs, and both ways of
    // sampling were taken.
    assert!(near > 10 / every as usize, "{near} samples nearer than 0.2");
    let certified = result.counters.work.trace_certified;
    assert!(
        certified > 100 / every as usize && certified < result.trace.len(),
        "{certified} of {} certified",
        result.trace.len()
    );
}

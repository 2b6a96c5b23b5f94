//! Traces at the speed of the CCD (issue 15 §4), on a real mesh: the
//! Stanford bunny (3,674 triangles; `scripts/fetch-bunny.sh` fetches it,
//! the bench says so and skips without it) falling 8 units onto a box
//! floor, `benches/scenes/bunny_fall.ron`.
//! - The whole run untraced, and traced at every step (256 samples).
//! - The distance search beside its peer: nearmiss's BVH search
//!   warm-started from the previous sample's closest pair (what the trace
//!   falls back to when its hull certificate does not settle a sample) and
//!   cold, against parry3d-f64's `query::distance` (TriMesh against
//!   Cuboid), at the 256 poses of the fall. The trace's own cost per sample
//!   is the difference of the two runs above over 256.
//!
//! `cargo bench --bench trace` (about a minute).

use criterion::{criterion_group, criterion_main, Criterion};
use nearmiss::math::{pose_to_parry, to_parry, Real, Vector};
use nearmiss::mesh::{mesh_distance_relative, DistanceKernel, DistanceSearch, MeshDistanceScratch};
use nearmiss::scene::Scene;
use nearmiss::stepper::{run_with, RunOptions};
use std::hint::black_box;
use std::time::Duration;

const SCENE: &str = concat!(env!("CARGO_MANIFEST_DIR"), "/benches/scenes/bunny_fall.ron");

fn bunny_fall(c: &mut Criterion) {
    let Ok(traced) = Scene::load(SCENE) else {
        eprintln!("trace bench skipped: no scenes/meshes/bunny.obj (run scripts/fetch-bunny.sh)");
        return;
    };
    let untraced = Scene { trace: None, ..traced.clone() };
    let serial = RunOptions { parallel: false, ..RunOptions::default() };
    let mut group = c.benchmark_group("bunny falls 8 units onto a box floor, 256 steps");
    group.sample_size(20).measurement_time(Duration::from_secs(10));
    group
        .bench_function("untraced", |b| b.iter(|| run_with(black_box(&untraced), serial, &mut |_| {}).steps));
    group.bench_function("traced every step", |b| {
        b.iter(|| run_with(black_box(&traced), serial, &mut |_| {}).trace.len())
    });
    group.finish();

    // The poses of the fall: the bunny's relative to the floor at each step end.
    let result = run_with(&traced, serial, &mut |_| {});
    let (floor, bunny) = (&traced.bodies[0], &traced.bodies[1]);
    let heights: Vec<Real> = result.trace.iter().map(|r| r.distance).collect();
    // The bunny's lowest vertex, in its frame (it falls without turning).
    let lowest = bunny.mesh.vertices().iter().map(|v| v.y).fold(Real::INFINITY, Real::min);
    let poses: Vec<_> = heights
        .iter()
        .map(|h| {
            // The bunny's frame h above its touching height, floor fixed.
            let mut pose = bunny.pose;
            pose.translation.vector += Vector::new(0.0, h - (bunny.pose.translation.vector.y + lowest), 0.0);
            floor.pose.inverse() * pose
        })
        .collect();
    let floor_shape = parry3d_f64::shape::Cuboid::new(to_parry(&nalgebra::Point3::new(10.0, 0.5, 10.0)));
    let bunny_shape = bunny.mesh.to_parry().expect("a parry mesh");
    let mut scratch = MeshDistanceScratch::default();
    let mut group = c.benchmark_group("bunny - floor distance at the 256 poses of the fall");
    group.sample_size(20).measurement_time(Duration::from_secs(10));
    group.bench_function("nearmiss search, warm-started (the trace without its certificate)", |b| {
        b.iter(|| {
            let mut hint = None;
            let mut sum = 0.0;
            for pose in &poses {
                let d = mesh_distance_relative(
                    &floor.mesh,
                    &bunny.mesh,
                    pose,
                    &DistanceSearch::new(DistanceKernel::Exact, hint),
                    &mut scratch,
                );
                hint = Some((d.triangle_a, d.triangle_b));
                sum += d.distance;
            }
            sum
        })
    });
    group.bench_function("nearmiss search, cold", |b| {
        b.iter(|| {
            let search = DistanceSearch::new(DistanceKernel::Exact, None);
            poses
                .iter()
                .map(|pose| {
                    mesh_distance_relative(&floor.mesh, &bunny.mesh, pose, &search, &mut scratch).distance
                })
                .sum::<Real>()
        })
    });
    group.bench_function("parry3d-f64 query::distance", |b| {
        b.iter(|| {
            poses
                .iter()
                .map(|pose| {
                    parry3d_f64::query::distance(
                        &pose_to_parry(&nalgebra::Isometry3::identity()),
                        &floor_shape,
                        &pose_to_parry(pose),
                        &bunny_shape,
                    )
                    .expect("supported")
                    .distance
                })
                .sum::<Real>()
        })
    });
    group.finish();
}

criterion_group!(benches, bunny_fall);
criterion_main!(benches);

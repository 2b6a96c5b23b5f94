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
//! - The same bunny tumbling as it falls (spin (2, 3, 1) rad/s, 211
//!   samples, `benches/scenes/bunny_tumble.ron`): the run untraced and
//!   traced at every step, and parry3d-f64's `query::distance` at the 211
//!   recorded poses (issue 30 §3: a sample at most parry's distance on the
//!   same poses).
//!
//! - Fifty tumbling convex bodies in a closed box
//!   (`benches/scenes/tumbling_convex.ron`), every pair (1,525) traced every
//!   10 steps (25 samples): the run untraced and traced, with one thread
//!   and with rayon's, and parry3d-f64's `query::distance` between the
//!   bodies' convex hulls (`ConvexPolyhedron`) for the same 38,125
//!   pair-samples at the same poses. The trace's cost per pair-sample is
//!   the difference of the one-thread runs over 38,125.
//!
//! `cargo bench --bench trace` (about two minutes).

use criterion::{criterion_group, criterion_main, Criterion};
use nearmiss::math::{pose_to_parry, to_parry, Real, Vector};
use nearmiss::mesh::{mesh_distance_relative, DistanceKernel, DistanceSearch, MeshDistanceScratch};
use nearmiss::run::{run_with, RunOptions};
use nearmiss::scene::Scene;
use std::hint::black_box;
use std::time::Duration;

const SCENE: &str = concat!(env!("CARGO_MANIFEST_DIR"), "/benches/scenes/bunny_fall.ron");

fn bunny_fall(c: &mut Criterion) {
    let Ok(traced) = Scene::load(SCENE) else {
        eprintln!("trace bench skipped: no scenes/meshes/bunny.obj (run scripts/fetch-bunny.sh)");
        return;
    };
    let untraced = traced.with_trace(None).expect("no trace");
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
    let (floor, bunny) = (&traced.model().bodies[0], &traced.model().bodies[1]);
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

const TUMBLE: &str = concat!(env!("CARGO_MANIFEST_DIR"), "/benches/scenes/bunny_tumble.ron");

fn bunny_tumble(c: &mut Criterion) {
    let Ok(traced) = Scene::load(TUMBLE) else {
        eprintln!("trace bench skipped: no scenes/meshes/bunny.obj (run scripts/fetch-bunny.sh)");
        return;
    };
    let untraced = traced.with_trace(None).expect("no trace");
    let serial = RunOptions { parallel: false, ..RunOptions::default() };
    let result = run_with(&traced, serial, &mut |_| {});
    let samples = result.trace.len();
    // The floor's and the bunny's recorded poses at each sample's step.
    let pose_of = |step: u64, body: usize| {
        let r = result.poses.iter().find(|r| r.step == step && r.body == body).expect("a pose record");
        nalgebra::Isometry3::from_parts(nalgebra::Translation3::from(r.position.coords), r.orientation)
    };
    let poses: Vec<_> = result.trace.iter().map(|r| (pose_of(r.step, 0), pose_of(r.step, 1))).collect();
    let bunny = &traced.model().bodies[1];
    let floor_shape = parry3d_f64::shape::Cuboid::new(to_parry(&nalgebra::Point3::new(10.0, 0.5, 10.0)));
    let bunny_shape = bunny.mesh.to_parry().expect("a parry mesh");
    // The two agree on every pose (to parry's rounding).
    let worst = result
        .trace
        .iter()
        .zip(&poses)
        .map(|(r, (pf, pb))| {
            let peer = parry3d_f64::query::distance(
                &pose_to_parry(pf),
                &floor_shape,
                &pose_to_parry(pb),
                &bunny_shape,
            )
            .expect("supported")
            .distance;
            (r.distance - peer).abs()
        })
        .fold(0.0, Real::max);
    println!("tumbling bunny: {samples} samples, largest difference from parry's distance {worst:.1e}");
    let mut group = c.benchmark_group(format!("bunny tumbles onto a box floor, {samples} samples"));
    group.sample_size(20).measurement_time(Duration::from_secs(8));
    group
        .bench_function("untraced", |b| b.iter(|| run_with(black_box(&untraced), serial, &mut |_| {}).steps));
    group.bench_function("traced every step", |b| {
        b.iter(|| run_with(black_box(&traced), serial, &mut |_| {}).trace.len())
    });
    group.bench_function("parry3d-f64 query::distance at the same poses", |b| {
        b.iter(|| {
            poses
                .iter()
                .map(|(pf, pb)| {
                    parry3d_f64::query::distance(
                        &pose_to_parry(pf),
                        &floor_shape,
                        &pose_to_parry(pb),
                        &bunny_shape,
                    )
                    .expect("supported")
                    .distance
                })
                .sum::<Real>()
        })
    });
    // The shapes the other way round, in case parry's dispatch favours it.
    group.bench_function("parry3d-f64 query::distance, the bunny first", |b| {
        b.iter(|| {
            poses
                .iter()
                .map(|(pf, pb)| {
                    parry3d_f64::query::distance(
                        &pose_to_parry(pb),
                        &bunny_shape,
                        &pose_to_parry(pf),
                        &floor_shape,
                    )
                    .expect("supported")
                    .distance
                })
                .sum::<Real>()
        })
    });
    group.finish();
}

const CONVEX: &str = concat!(env!("CARGO_MANIFEST_DIR"), "/benches/scenes/tumbling_convex.ron");

fn tumbling_convex(c: &mut Criterion) {
    let traced = Scene::load(CONVEX).expect("the shipped bench scene").with_poses(None).expect("no poses");
    let untraced = traced.with_trace(None).expect("no trace");
    let serial = RunOptions { parallel: false, ..RunOptions::default() };
    let mut group = c.benchmark_group("50 tumbling convex bodies, every pair traced every 10 steps");
    group.sample_size(10).measurement_time(Duration::from_secs(15));
    for (name, options) in [("one thread", serial), ("rayon", RunOptions::default())] {
        group.bench_function(format!("untraced, {name}"), |b| {
            b.iter(|| run_with(black_box(&untraced), options, &mut |_| {}).steps)
        });
        group.bench_function(format!("traced, {name}"), |b| {
            b.iter(|| run_with(black_box(&traced), options, &mut |_| {}).trace.len())
        });
    }
    // parry on the same pair-samples: the poses at every sampled step.
    let with_poses = Scene::load(CONVEX).expect("the shipped bench scene");
    let result = run_with(&with_poses, serial, &mut |_| {});
    let shapes: Vec<_> = with_poses
        .model()
        .bodies
        .iter()
        .map(|body| {
            let points: Vec<_> = body.mesh.vertices().iter().map(to_parry).collect();
            parry3d_f64::shape::ConvexPolyhedron::from_convex_hull(&points).expect("a hull")
        })
        .collect();
    let poses: Vec<_> = result
        .poses
        .iter()
        .map(|r| pose_to_parry(&nalgebra::Isometry3::from_parts(r.position.coords.into(), r.orientation)))
        .collect();
    let bodies = with_poses.model().bodies.len();
    // Every traced pair at every sample: the records' pairs, and the index
    // of each body's pose at that sample.
    let samples: Vec<(usize, usize)> = result
        .trace
        .iter()
        .map(|r| {
            let first = result.poses.iter().position(|p| p.step == r.step).expect("the sample's poses");
            (first + r.pair.0, first + r.pair.1)
        })
        .collect();
    assert!(result.poses.len().is_multiple_of(bodies) && samples.len() == result.trace.len());
    // The two compute the same distances (parry's GJK to its own tolerance).
    let worst = samples
        .iter()
        .zip(&result.trace)
        .map(|(&(i, j), record)| {
            let d =
                parry3d_f64::query::distance(&poses[i], &shapes[i % bodies], &poses[j], &shapes[j % bodies]);
            (d.expect("supported").distance - record.distance).abs()
        })
        .fold(0.0, Real::max);
    eprintln!("{} pair-samples; largest difference between parry and the trace: {worst:e}", samples.len());
    group.bench_function("parry3d-f64 query::distance, the same pair-samples", |b| {
        b.iter(|| {
            samples
                .iter()
                .map(|&(i, j)| {
                    let (a, b) = (i % bodies, j % bodies);
                    parry3d_f64::query::distance(&poses[i], &shapes[a], &poses[j], &shapes[b])
                        .expect("supported")
                        .distance
                })
                .sum::<Real>()
        })
    });
    group.finish();
}

criterion_group!(benches, bunny_fall, bunny_tumble, tumbling_convex);
criterion_main!(benches);

//! Rotating mesh–mesh time of impact against parry's `cast_shapes_nonlinear`:
//! icosphere 320 vs 1280 triangles, both tumbling, offset approach, the 10
//! seeded cases of `samples::tumbling_cases(10, 5)`, one thread. One
//! iteration runs all 10 cases.
//!
//! `cargo bench --bench mesh_ccd` (about two minutes: parry takes 0.2–0.6 s
//! per case). Correctness of the two side by side: `cargo run --release
//! --example compare_parry_tumble`.

use criterion::{criterion_group, criterion_main, Criterion};
use nearmiss::ccd::{mesh_time_of_impact, CcdOptions, MovingMesh};
use nearmiss::math::motion_to_parry;
use nearmiss::mesh::{DistanceKernel, MeshDistanceScratch};
use nearmiss::motion::StepMotion;
use nearmiss::samples::tumbling_cases;
use std::hint::black_box;
use std::time::Duration;

fn rotating_mesh_ccd(c: &mut Criterion) {
    let (a, b, cases) = tumbling_cases(10, 5);
    let (parry_a, parry_b) = (a.to_parry().expect("parry mesh"), b.to_parry().expect("parry mesh"));
    let options = CcdOptions::default();
    let mut scratch = MeshDistanceScratch::default();
    let parry_motion = |m: &StepMotion| motion_to_parry(&m.pose_t0(), &m.velocity, &m.angular_velocity);
    let parry_motions: Vec<_> = cases.iter().map(|(x, y)| (parry_motion(x), parry_motion(y))).collect();

    let mut group = c.benchmark_group("tumbling icospheres 320 vs 1280, 10 cases");
    group.sample_size(10).measurement_time(Duration::from_secs(20));
    group.bench_function("nearmiss mesh_time_of_impact", |bench| {
        bench.iter(|| {
            let mut found = 0.0;
            for (ma, mb) in &cases {
                let result = mesh_time_of_impact(
                    MovingMesh { mesh: &a, motion: black_box(ma) },
                    MovingMesh { mesh: &b, motion: black_box(mb) },
                    1.0,
                    &options,
                    DistanceKernel::Exact,
                    None,
                    None,
                    &mut scratch,
                );
                found += result.time_of_impact.unwrap_or(2.0);
            }
            found
        })
    });
    group.bench_function("parry3d-f64 cast_shapes_nonlinear", |bench| {
        bench.iter(|| {
            let mut found = 0.0;
            for (ma, mb) in &parry_motions {
                let hit = parry3d_f64::query::cast_shapes_nonlinear(
                    black_box(ma),
                    &parry_a,
                    black_box(mb),
                    &parry_b,
                    0.0,
                    1.0,
                    true,
                );
                found += hit.ok().flatten().map_or(2.0, |h| h.time_of_impact);
            }
            found
        })
    });
    group.finish();
}

criterion_group!(benches, rotating_mesh_ccd);
criterion_main!(benches);

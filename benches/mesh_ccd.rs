//! Mesh–mesh time of impact against parry, icosphere 320 vs 1280 triangles,
//! 10 seeded cases each, one thread; one iteration runs all 10 cases.
//! - Rotating (`samples::tumbling_cases(10, 5)`: both tumbling, offset
//!   approach) against parry's `cast_shapes_nonlinear`.
//! - Translating (`samples::translating_cases(10, 5)`: the same without
//!   the spins) against parry's `cast_shapes`.
//!
//! `cargo bench --bench mesh_ccd` (about two minutes: parry takes 0.2–0.6 s
//! per rotating case). Correctness of the two side by side: `cargo run
//! --release --example compare_parry_tumble`.

use criterion::{criterion_group, criterion_main, Criterion};
use nearmiss::ccd::{mesh_time_of_impact, CcdOptions, MeshCcdQuery, MeshCcdScratch, MovingMesh, WarmStart};
use nearmiss::math::{motion_to_parry, pose_to_parry, vector_to_parry, Real};
use nearmiss::mesh::TriMesh;
use nearmiss::motion::StepMotion;
use nearmiss::samples::{translating_cases, tumbling_cases};
use parry3d_f64::query::{cast_shapes, cast_shapes_nonlinear, ShapeCastOptions};
use std::hint::black_box;
use std::time::Duration;

/// nearmiss over all cases: the sum of the times of impact (2 for none).
fn nearmiss_all(
    a: &TriMesh,
    b: &TriMesh,
    cases: &[(StepMotion, StepMotion)],
    scratch: &mut MeshCcdScratch,
) -> Real {
    let options = CcdOptions::default();
    let mut found = 0.0;
    for (ma, mb) in cases {
        let result = mesh_time_of_impact(
            &MeshCcdQuery::new(
                MovingMesh { mesh: a, motion: black_box(ma) },
                MovingMesh { mesh: b, motion: black_box(mb) },
                1.0,
                options,
            ),
            WarmStart::default(),
            scratch,
        );
        found += result.time_of_impact.unwrap_or(2.0);
    }
    found
}

fn rotating_mesh_ccd(c: &mut Criterion) {
    let (a, b, cases) = tumbling_cases(10, 5);
    let (parry_a, parry_b) = (a.to_parry().expect("parry mesh"), b.to_parry().expect("parry mesh"));
    let mut scratch = MeshCcdScratch::default();
    let parry_motion = |m: &StepMotion| motion_to_parry(&m.pose_t0(), &m.velocity, &m.angular_velocity);
    let parry_motions: Vec<_> = cases.iter().map(|(x, y)| (parry_motion(x), parry_motion(y))).collect();

    let mut group = c.benchmark_group("tumbling icospheres 320 vs 1280, 10 cases");
    group.sample_size(10).measurement_time(Duration::from_secs(20));
    group.bench_function("nearmiss mesh_time_of_impact", |bench| {
        bench.iter(|| nearmiss_all(&a, &b, &cases, &mut scratch))
    });
    group.bench_function("parry3d-f64 cast_shapes_nonlinear", |bench| {
        bench.iter(|| {
            let mut found = 0.0;
            for (ma, mb) in &parry_motions {
                let hit =
                    cast_shapes_nonlinear(black_box(ma), &parry_a, black_box(mb), &parry_b, 0.0, 1.0, true);
                found += hit.ok().flatten().map_or(2.0, |h| h.time_of_impact);
            }
            found
        })
    });
    group.finish();
}

fn translating_mesh_ccd(c: &mut Criterion) {
    let (a, b, cases) = translating_cases(10, 5);
    let (parry_a, parry_b) = (a.to_parry().expect("parry mesh"), b.to_parry().expect("parry mesh"));
    let mut scratch = MeshCcdScratch::default();
    let mut group = c.benchmark_group("translating icospheres 320 vs 1280, 10 cases");
    group.sample_size(20).measurement_time(Duration::from_secs(10));
    group.bench_function("nearmiss mesh_time_of_impact", |bench| {
        bench.iter(|| nearmiss_all(&a, &b, &cases, &mut scratch))
    });
    group.bench_function("parry3d-f64 cast_shapes", |bench| {
        bench.iter(|| {
            let mut found = 0.0;
            for (ma, mb) in &cases {
                let hit = cast_shapes(
                    &pose_to_parry(&ma.pose_t0()),
                    vector_to_parry(black_box(&ma.velocity)),
                    &parry_a,
                    &pose_to_parry(&mb.pose_t0()),
                    vector_to_parry(black_box(&mb.velocity)),
                    &parry_b,
                    ShapeCastOptions::with_max_time_of_impact(1.0),
                );
                found += hit.ok().flatten().map_or(2.0, |h| h.time_of_impact);
            }
            found
        })
    });
    group.finish();
}

criterion_group!(benches, rotating_mesh_ccd, translating_mesh_ccd);
criterion_main!(benches);

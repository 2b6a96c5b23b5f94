//! Point–segment distance per formula, scalar and batched, against parry's
//! segment point query, on the same 10,000 pre-generated queries (a point
//! 1e-12..1e-1 from a unit segment, the nearly touching class).
//!
//! `cargo bench --bench point_segment`.

use criterion::{criterion_group, criterion_main, Criterion, Throughput};
use nearmiss::kernels::batch::{point_segment_distances_with, PointsSoa};
use nearmiss::kernels::{point_segment_distance, PointEdgeFormula, SimdLevel};
use nearmiss::samples::parry_point_segment_distance;
use nearmiss::samples::{point_segment_queries, InputClass};
use std::hint::black_box;

const QUERIES: usize = 10_000;

fn point_segment_kernels(c: &mut Criterion) {
    let queries = point_segment_queries(InputClass::NearlyTouching, QUERIES, 2024);
    let (p, a, b) = PointsSoa::from_queries(&queries);
    let mut out = vec![0.0; QUERIES];

    let mut group = c.benchmark_group("point_segment");
    group.throughput(Throughput::Elements(QUERIES as u64));
    group.bench_function("parry3d-f64 Segment::distance_to_local_point", |bench| {
        bench.iter(|| {
            queries.iter().map(|(p, a, b)| parry_point_segment_distance(black_box(p), a, b)).sum::<f64>()
        })
    });
    for formula in PointEdgeFormula::ALL {
        group.bench_function(format!("scalar {}", formula.name()), |bench| {
            bench.iter(|| {
                queries
                    .iter()
                    .map(|(p, a, b)| point_segment_distance(black_box(p), a, b, formula))
                    .sum::<f64>()
            })
        });
        for level in SimdLevel::available() {
            group.bench_function(format!("batch {} ({})", formula.name(), level.name()), |bench| {
                bench.iter(|| {
                    point_segment_distances_with(level, black_box(&p), &a, &b, formula, &mut out);
                    out[QUERIES - 1]
                })
            });
        }
    }
    group.finish();
}

criterion_group! {
    name = benches;
    config = Criterion::default().sample_size(30).warm_up_time(std::time::Duration::from_millis(500))
        .measurement_time(std::time::Duration::from_secs(2));
    targets = point_segment_kernels
}
criterion_main!(benches);

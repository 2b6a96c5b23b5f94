//! Triangle–triangle distance kernels against parry, on the same 10,000
//! pre-generated nearly touching pairs (gap 1e-3..1e-1, unit size), and on
//! 10,000 nearer ones (1e-6..1e-3: refined).
//!
//! `cargo bench --bench triangle_distance`; criterion reports the time per
//! batch of 10,000 pairs and the throughput in pairs per second.

use criterion::{criterion_group, criterion_main, Criterion, Throughput};
use nearmiss::kernels::batch::{triangle_distances_with, TrianglesSoa};
use nearmiss::kernels::{
    dyop_distance, triangle_distance, triangle_distance_with, PointEdgeFormula, SimdLevel,
};
use nearmiss::math::Triangle;
use nearmiss::samples::nearly_touching_pairs;
use nearmiss::samples::parry_triangle_distance;
use std::hint::black_box;

const PAIRS: usize = 10_000;

/// parry, then the single pair (dispatched, and at every level) and the
/// batch at every level, on `pairs`; with `dyop`, the DyOP kernels too.
fn kernels_on(c: &mut Criterion, name: &str, pairs: &[(Triangle, Triangle)], dyop: bool) {
    let (a, b) = TrianglesSoa::from_pairs(pairs);
    let mut out = vec![0.0; pairs.len()];
    let mut group = c.benchmark_group(name);
    group.throughput(Throughput::Elements(pairs.len() as u64));
    group.bench_function("parry3d-f64 query::distance", |bench| {
        bench.iter(|| {
            pairs.iter().map(|(x, y)| parry_triangle_distance(black_box(x), black_box(y))).sum::<f64>()
        })
    });
    group.bench_function("nearmiss triangle_distance (scalar)", |bench| {
        bench.iter(|| {
            pairs.iter().map(|(x, y)| triangle_distance(black_box(x), black_box(y)).distance).sum::<f64>()
        })
    });
    for level in SimdLevel::available() {
        group.bench_function(format!("nearmiss triangle_distance (scalar, {})", level.name()), |bench| {
            bench.iter(|| {
                pairs
                    .iter()
                    .map(|(x, y)| triangle_distance_with(level, black_box(x), black_box(y)).distance)
                    .sum::<f64>()
            })
        });
        group.bench_function(format!("nearmiss triangle_distances (batch, {})", level.name()), |bench| {
            bench.iter(|| {
                triangle_distances_with(level, black_box(&a), black_box(&b), &mut out);
                out[out.len() - 1]
            })
        });
    }
    if dyop {
        for formula in PointEdgeFormula::ALL {
            group.bench_function(format!("nearmiss dyop_distance ({})", formula.name()), |bench| {
                bench.iter(|| {
                    pairs.iter().map(|(x, y)| dyop_distance(black_box(x), black_box(y), formula)).sum::<f64>()
                })
            });
        }
    }
    group.finish();
}

fn triangle_kernels(c: &mut Criterion) {
    kernels_on(c, "triangle_distance", &nearly_touching_pairs(PAIRS, 1e-3, 1e-1, 2024), true);
    // Nearer pairs, where the CCD works: most are refined in double-double,
    // and most of those take the refinement's tie path.
    kernels_on(
        c,
        "triangle_distance, pairs 1e-6..1e-3 apart",
        &nearly_touching_pairs(PAIRS, 1e-6, 1e-3, 2025),
        false,
    );
}

criterion_group! {
    name = benches;
    config = Criterion::default().sample_size(30).warm_up_time(std::time::Duration::from_millis(500))
        .measurement_time(std::time::Duration::from_secs(2));
    targets = triangle_kernels
}
criterion_main!(benches);

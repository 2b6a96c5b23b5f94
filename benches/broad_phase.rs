//! The broad phase alone (issue 47 §1, §5): the overlapping pairs of the
//! swept boxes of N bodies in a box, the bodies as `many_bodies` places
//! them (a jittered grid of cells of side 1.2, boxes of side 0.6 to 1.2
//! moved a little each step, six walls), through
//! - nearmiss's `GridBroadPhase` (a counting sort into a uniform grid a
//!   step),
//! - parry's `Bvh` refitted to the moved boxes and traversed
//!   (`BroadPhase`, the stepper's),
//! - a sort and sweep along x (`sweep_pairs`, sorting each step).
//!
//! Each step's boxes are the last step's moved by up to 0.01, as between
//! two steps. `cargo bench --bench broad_phase` (about two minutes).

use criterion::{criterion_group, criterion_main, BenchmarkId, Criterion};
use nearmiss::broad_phase::{sweep_pairs, BroadPhase, GridBroadPhase, StaticBoxes, SweptBox};
use nearmiss::math::{Point, Vector};
use nearmiss::samples::Rng;
use std::hint::black_box;

/// `n` bodies' boxes and the six walls of their box.
fn boxes(n: usize, rng: &mut Rng) -> Vec<SweptBox> {
    let per_side = (n as f64).cbrt().ceil() as usize;
    let cell = 1.2;
    let half = cell * per_side as f64 / 2.0;
    let mut boxes = Vec::with_capacity(n + 6);
    for k in 0..n {
        let (i, j, l) = (k % per_side, (k / per_side) % per_side, k / (per_side * per_side));
        let centre = Point::new(i as f64, j as f64, l as f64) * cell
            + Vector::repeat(cell / 2.0 - half)
            + rng.in_unit_ball() * 0.05;
        let h = Vector::repeat(rng.range(0.3, 0.6));
        boxes.push((centre - h, centre + h));
    }
    for axis in 0..3 {
        for side in [-1.0, 1.0] {
            let mut low = Point::from(Vector::repeat(-half - 0.5));
            let mut high = Point::from(Vector::repeat(half + 0.5));
            low[axis] = side * (half + 0.25) - 0.25;
            high[axis] = side * (half + 0.25) + 0.25;
            boxes.push((low, high));
        }
    }
    boxes
}

/// The boxes moved by up to 0.01 (a step's motion).
fn moved(boxes: &[SweptBox], rng: &mut Rng) -> Vec<SweptBox> {
    boxes
        .iter()
        .map(|(low, high)| {
            let shift = rng.in_unit_ball() * 0.01;
            (low + shift, high + shift)
        })
        .collect()
}

fn bench(c: &mut Criterion) {
    let mut group = c.benchmark_group("broad_phase");
    group.sample_size(10);
    for n in [1_000, 10_000, 100_000] {
        let mut rng = Rng::new(7);
        let start = boxes(n, &mut rng);
        let steps: Vec<Vec<SweptBox>> = (0..8).map(|_| moved(&start, &mut rng)).collect();
        let mut pairs = Vec::new();
        let mut grid = GridBroadPhase::default();
        grid.pairs_into(&start, &mut pairs);
        let expected = pairs.len();
        let mut tree = BroadPhase::default();
        tree.pairs_into(&start, &mut pairs);
        assert_eq!(pairs.len(), expected, "the tree's pairs are the grid's");
        println!("{n} bodies: {expected} overlapping pairs at the start");
        let mut k = 0;
        group.bench_with_input(BenchmarkId::new("nearmiss GridBroadPhase", n), &n, |b, _| {
            b.iter(|| {
                k = (k + 1) % steps.len();
                grid.pairs_into(black_box(&steps[k]), &mut pairs);
                pairs.len()
            })
        });
        group.bench_with_input(BenchmarkId::new("parry Bvh refit and traversal", n), &n, |b, _| {
            b.iter(|| {
                k = (k + 1) % steps.len();
                tree.pairs_into(black_box(&steps[k]), &mut pairs);
                pairs.len()
            })
        });
        group.bench_with_input(BenchmarkId::new("sort and sweep along x", n), &n, |b, _| {
            b.iter(|| {
                k = (k + 1) % steps.len();
                sweep_pairs(black_box(&steps[k]), 0.0).len()
            })
        });
    }
    group.finish();
}

/// Nine in ten of the bodies fixed (`many_bodies --fixed 90`): the
/// stepper keeps the fixed boxes in a grid made once (`StaticBoxes`) and
/// each step pairs the moving boxes among themselves (`BroadPhase`) and
/// reads the cells each can reach, where it would otherwise pair every box
/// each step (the grid).
fn bench_fixed(c: &mut Criterion) {
    let mut group = c.benchmark_group("broad_phase_fixed_90");
    group.sample_size(10);
    for n in [10_000, 100_000] {
        let mut rng = Rng::new(7);
        let start = boxes(n, &mut rng);
        let fixed = |k: usize| k >= n || k * 37 % 100 < 90;
        let fixed_boxes: Vec<SweptBox> =
            start.iter().enumerate().filter(|&(k, _)| fixed(k)).map(|(_, b)| *b).collect();
        let statics = StaticBoxes::new(&fixed_boxes);
        let steps: Vec<Vec<SweptBox>> = (0..8)
            .map(|_| {
                moved(&start, &mut rng)
                    .into_iter()
                    .enumerate()
                    .filter(|&(k, _)| !fixed(k))
                    .map(|(_, b)| b)
                    .collect()
            })
            .collect();
        let (mut among, mut across) = (Vec::new(), Vec::new());
        let mut tree = BroadPhase::default();
        let mut k = 0;
        group.bench_with_input(
            BenchmarkId::new("moving boxes paired, fixed ones in a static grid", n),
            &n,
            |b, _| {
                b.iter(|| {
                    k = (k + 1) % steps.len();
                    tree.pairs_into(black_box(&steps[k]), &mut among);
                    statics.overlaps_into_on(black_box(&steps[k]), &mut across, false);
                    among.len() + across.len()
                })
            },
        );
        let every: Vec<Vec<SweptBox>> = (0..8).map(|_| moved(&start, &mut rng)).collect();
        let mut grid = GridBroadPhase::default();
        let mut pairs = Vec::new();
        group.bench_with_input(BenchmarkId::new("every box through the grid", n), &n, |b, _| {
            b.iter(|| {
                k = (k + 1) % every.len();
                grid.pairs_into(black_box(&every[k]), &mut pairs);
                pairs.len()
            })
        });
    }
    group.finish();
}

criterion_group!(benches, bench, bench_fixed);
criterion_main!(benches);

//! Replays the distance queries `python/benchmarks/real_meshes.py --dump
//! DIR` wrote, in Rust: nearmiss's mesh distance at each pose, both
//! argument orders, with the search's work (node and triangle pairs) beside
//! coal's distance and time from the Python run. A development aid for the
//! search's choices (the comparison of record is the Python run, where coal
//! is measured in the same process).
//!
//! `cargo run --release -p nearmiss-tools --bin real_mesh_replay -- DIR`;
//! with `HINTED=1` in the environment it also prints, for queries of more
//! than 5,000 triangle pairs, how many the search takes when started from
//! its own answer (what a perfect first bound would save).

use std::path::Path;
use std::time::Instant;

use nalgebra::{Matrix3, Rotation3, UnitQuaternion};
use nearmiss::math::{Pose, Real, Vector};
use nearmiss::mesh::{load_obj, mesh_distance, DistanceSearch, MeshDistanceScratch, TriMesh};

struct Query {
    a: usize,
    b: usize,
    kind: String,
    pose_a: Pose,
    pose_b: Pose,
    coal: Real,
    coal_seconds: Real,
}

fn pose(v: &[Real]) -> Pose {
    let rotation = Matrix3::from_row_slice(&v[3..12]);
    let rotation = UnitQuaternion::from_rotation_matrix(&Rotation3::from_matrix_unchecked(rotation));
    Pose::from_parts(Vector::new(v[0], v[1], v[2]).into(), rotation)
}

fn main() {
    let dir = std::env::args().nth(1).expect("usage: real_mesh_replay DIR");
    let dir = Path::new(&dir);
    let mut files: Vec<_> = std::fs::read_dir(dir)
        .expect("the dump folder")
        .filter_map(|e| e.ok().map(|e| e.path()))
        .filter(|p| p.extension().is_some_and(|e| e == "obj"))
        .collect();
    files.sort();
    let meshes: Vec<TriMesh> = files.iter().map(|p| load_obj(p).expect("a dumped mesh")).collect();
    let names: Vec<String> =
        files.iter().map(|p| p.file_stem().unwrap().to_string_lossy()[3..].to_string()).collect();
    let text = std::fs::read_to_string(dir.join("queries.txt")).expect("queries.txt");
    let queries: Vec<Query> = text
        .lines()
        .map(|line| {
            let words: Vec<&str> = line.split_whitespace().collect();
            let v: Vec<Real> = words[3..].iter().map(|w| w.parse().unwrap()).collect();
            Query {
                a: words[0].parse().unwrap(),
                b: words[1].parse().unwrap(),
                kind: words[2].to_string(),
                pose_a: pose(&v[0..12]),
                pose_b: pose(&v[12..24]),
                coal: v[24],
                coal_seconds: v[25],
            }
        })
        .collect();
    let mut scratch = MeshDistanceScratch::default();
    let search = DistanceSearch::default();
    let (mut total, mut total_swapped, mut total_coal) = (0.0, 0.0, 0.0);
    let mut rows = Vec::new();
    for q in &queries {
        let (a, b) = (&meshes[q.a], &meshes[q.b]);
        let time = |forward: bool, scratch: &mut MeshDistanceScratch| {
            let mut best = Real::INFINITY;
            let mut found = None;
            for _ in 0..3 {
                let start = Instant::now();
                let d = if forward {
                    mesh_distance(a, &q.pose_a, b, &q.pose_b, &search, scratch)
                } else {
                    mesh_distance(b, &q.pose_b, a, &q.pose_a, &search, scratch)
                };
                best = best.min(start.elapsed().as_secs_f64());
                found = Some((d.distance, scratch.triangle_pairs()));
            }
            (best, found.unwrap())
        };
        let (seconds, (distance, pairs)) = time(true, &mut scratch);
        let (swapped, (_, pairs_swapped)) = time(false, &mut scratch);
        if std::env::var("HINTED").is_ok() {
            let d = mesh_distance(a, &q.pose_a, b, &q.pose_b, &search, &mut scratch);
            let hinted = DistanceSearch { hint: Some((d.triangle_a, d.triangle_b)), ..search };
            mesh_distance(a, &q.pose_a, b, &q.pose_b, &hinted, &mut scratch);
            if pairs > 5000 {
                println!(
                    "{} / {}: {pairs} pairs, {} with the answer as the hint",
                    names[q.a],
                    names[q.b],
                    scratch.triangle_pairs()
                );
            }
        }
        total += seconds;
        total_swapped += swapped;
        total_coal += q.coal_seconds;
        // Ulps of the largest coordinate of the posed meshes (as the Python
        // run measures them).
        let largest =
            |m: &TriMesh, p: &Pose| m.vertices().iter().map(|v| (p * v).coords.amax()).fold(0.0, Real::max);
        let largest = largest(a, &q.pose_a).max(largest(b, &q.pose_b));
        let ulp = (distance - q.coal).abs() / (largest * Real::EPSILON / 2.0);
        rows.push((seconds / q.coal_seconds, seconds, swapped, pairs, pairs_swapped, ulp, q));
    }
    println!(
        "{} queries: nearmiss {:.4} s, swapped {:.4} s, coal (Python run) {:.4} s: nearmiss ÷ coal {:.2}, swapped {:.2}",
        queries.len(),
        total,
        total_swapped,
        total_coal,
        total / total_coal,
        total_swapped / total_coal
    );
    let worst_ulps = rows.iter().map(|r| r.5).fold(0.0, Real::max);
    let mut ulps: Vec<Real> = rows.iter().map(|r| r.5).collect();
    ulps.sort_by(|x, y| x.total_cmp(y));
    println!(
        "|nearmiss − coal|: median {:.2}, worst {worst_ulps:.2} ulps of the largest coordinate",
        ulps[ulps.len() / 2]
    );
    rows.sort_by(|x, y| y.0.total_cmp(&x.0));
    println!(
        "worst ratios (nearmiss ÷ coal; ms; triangle pairs; |nearmiss − coal| in ulps of the larger radius):"
    );
    for (ratio, seconds, swapped, pairs, pairs_swapped, ulp, q) in rows.iter().take(12) {
        println!(
            "  {ratio:7.1}×  {} / {} {:12} d {:10.4e}  {:8.3} ms (swapped {:8.3}) coal {:7.3} ms  pairs {pairs} / {pairs_swapped}  {ulp:.1} ulps",
            names[q.a],
            names[q.b],
            q.kind,
            q.coal,
            seconds * 1e3,
            swapped * 1e3,
            q.coal_seconds * 1e3
        );
    }
    rows.sort_by(|x, y| (y.1.max(y.2) / y.1.min(y.2)).total_cmp(&(x.1.max(x.2) / x.1.min(x.2))));
    println!("worst argument-order ratios:");
    for (_, seconds, swapped, pairs, pairs_swapped, _, q) in rows.iter().take(6) {
        println!(
            "  {:6.2}  {} / {} {:12} d {:10.4e}  {:8.3} ms / {:8.3} ms  pairs {pairs} / {pairs_swapped}",
            seconds.max(*swapped) / seconds.min(*swapped),
            names[q.a],
            names[q.b],
            q.kind,
            q.coal,
            seconds * 1e3,
            swapped * 1e3
        );
    }
}

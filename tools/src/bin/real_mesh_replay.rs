//! Replays the queries `python/benchmarks/real_meshes.py --dump DIR`
//! wrote, in Rust. A development aid for the search's choices (the
//! comparison of record is the Python run, where coal is measured in the
//! same process).
//!
//! - **Distances** (`queries.txt`): nearmiss's mesh distance at each pose,
//!   both argument orders, with the search's work (node and triangle pairs)
//!   beside coal's distance and time from the Python run. With `HINTED=1`
//!   in the environment it also prints, for queries of more than 5,000
//!   triangle pairs, how many the search takes when started from its own
//!   answer (what a perfect first bound would save).
//! - **Tumbling pairs** (`motions.txt`): each pair's time of impact and
//!   closest approach with their defaults, as the Python run calls them (a
//!   still, b tumbling over one unit of time, a new scratch a call), the
//!   least of three calls after a first, a line a pair: the closest
//!   approach's status, runs and bracket, the exact distance at the
//!   interval's ends (what a closest approach over the whole interval
//!   measures first), and the closest approach's time over the time of
//!   impact's, here and in the Python run (a Python call adds about 10 µs,
//!   so a time of impact settled by the spheres, 0.3–5 µs here, is far
//!   shorter here and the ratios far higher); then the median and worst,
//!   and how many pairs are over 100× either way. `PAIRS=3,17`
//!   replays only those pairs (their line numbers from 0); `REPEAT=n` runs
//!   each closest approach `n` more times first (for a profiler).
//!
//! `cargo run --release -p nearmiss-tools --bin real_mesh_replay -- DIR`

use std::path::Path;
use std::time::Instant;

use nalgebra::{Matrix3, Rotation3, UnitQuaternion};
use nearmiss::ccd::{
    closest_approach, mesh_time_of_impact, CcdOptions, ClosestApproachQuery, MeshCcdQuery, MovingMesh,
    WarmStart,
};
use nearmiss::math::{Pose, Real, Vector};
use nearmiss::mesh::{load_obj, mesh_distance, DistanceSearch, MeshDistanceScratch, TriMesh};
use nearmiss::motion::StepMotion;

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
    if dir.join("queries.txt").exists() {
        replay_distances(dir, &meshes, &names);
    }
    if dir.join("motions.txt").exists() {
        replay_motions(dir, &meshes, &names);
    }
}

/// The least of three timed calls of `call` after a first, and its answer.
fn least_of_three<T>(mut call: impl FnMut() -> T) -> (Real, T) {
    let mut answer = call();
    let mut best = Real::INFINITY;
    for _ in 0..3 {
        let start = Instant::now();
        answer = call();
        best = best.min(start.elapsed().as_secs_f64());
    }
    (best, answer)
}

/// The tumbling pairs of `motions.txt` (see the module).
fn replay_motions(dir: &Path, meshes: &[TriMesh], names: &[String]) {
    let text = std::fs::read_to_string(dir.join("motions.txt")).expect("motions.txt");
    let only: Option<Vec<usize>> = std::env::var("PAIRS")
        .ok()
        .map(|v| v.split(',').map(|k| k.trim().parse().expect("PAIRS: numbers")).collect());
    let repeat = std::env::var("REPEAT").map_or(0, |v| v.parse::<usize>().expect("REPEAT: a number"));
    let mut rows = Vec::new();
    for (k, line) in text.lines().enumerate() {
        if only.as_ref().is_some_and(|only| !only.contains(&k)) {
            continue;
        }
        let words: Vec<&str> = line.split_whitespace().collect();
        let v: Vec<Real> = words[2..].iter().map(|w| w.parse().unwrap()).collect();
        let (a, b) =
            (&meshes[words[0].parse::<usize>().unwrap()], &meshes[words[1].parse::<usize>().unwrap()]);
        let still = StepMotion::new(pose(&v[0..12]), Vector::zeros(), Vector::zeros());
        let tumbling = StepMotion::new(
            pose(&v[12..24]),
            Vector::new(v[24], v[25], v[26]),
            Vector::new(v[27], v[28], v[29]),
        );
        let (moving_a, moving_b) =
            (MovingMesh { mesh: a, motion: &still }, MovingMesh { mesh: b, motion: &tumbling });
        let (toi_seconds, toi) = least_of_three(|| {
            mesh_time_of_impact(
                &MeshCcdQuery::new(moving_a, moving_b, 1.0, CcdOptions::default()),
                WarmStart::default(),
                &mut Default::default(),
            )
        });
        for _ in 0..repeat {
            closest_approach(&ClosestApproachQuery::new(moving_a, moving_b, 1.0), &mut Default::default());
        }
        let (ca_seconds, ca) = least_of_three(|| {
            closest_approach(&ClosestApproachQuery::new(moving_a, moving_b, 1.0), &mut Default::default())
        });
        // The exact distance at both ends, as a closest approach over the
        // whole interval measures first: a floor of its time.
        let mut distance_scratch = MeshDistanceScratch::default();
        let (ends_seconds, _) = least_of_three(|| {
            [0.0, 1.0].map(|s| {
                let (pose_a, pose_b) = (still.pose_at(s), tumbling.pose_at(s));
                mesh_distance(a, &pose_a, b, &pose_b, &DistanceSearch::default(), &mut distance_scratch)
                    .distance
            })
        });
        let pair = format!(
            "{} / {}",
            names[words[0].parse::<usize>().unwrap()],
            names[words[1].parse::<usize>().unwrap()]
        );
        println!(
            "{k:3} {pair:32} time of impact {:9.3} ms ({:?}, {} steps, {} triangle pairs; Python {:.3} ms)  closest approach {:9.3} ms ({:?}, {} runs, [{:.6e}, {:.6e}] at {:.4}; Python {:.3} ms; the ends' distances {:.3} ms)  ×{:.0} (Python ×{:.0})",
            toi_seconds * 1e3,
            toi.status,
            toi.iterations,
            toi.triangle_pairs,
            v[30] * 1e3,
            ca_seconds * 1e3,
            ca.status,
            ca.runs,
            ca.lower,
            ca.upper,
            ca.time,
            v[31] * 1e3,
            ends_seconds * 1e3,
            ca_seconds / toi_seconds,
            v[31] / v[30]
        );
        rows.push((ca_seconds / toi_seconds, ca_seconds, v[31] / v[30]));
    }
    let mut ratios: Vec<Real> = rows.iter().map(|r| r.0).collect();
    let mut times: Vec<Real> = rows.iter().map(|r| r.1).collect();
    ratios.sort_by(Real::total_cmp);
    times.sort_by(Real::total_cmp);
    if let (Some(ratio), Some(time)) = (ratios.get(ratios.len() / 2), times.get(times.len() / 2)) {
        println!(
            "{} pairs: closest approach median {:.3} ms, worst {:.3} ms; ÷ time of impact median {ratio:.1}, worst {:.1}; over 100×: {} here, {} in the Python run",
            rows.len(),
            time * 1e3,
            times[times.len() - 1] * 1e3,
            ratios[ratios.len() - 1],
            ratios.iter().filter(|&&r| r > 100.0).count(),
            rows.iter().filter(|r| r.2 > 100.0).count()
        );
    }
}

/// The distance queries of `queries.txt` (see the module).
fn replay_distances(dir: &Path, meshes: &[TriMesh], names: &[String]) {
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

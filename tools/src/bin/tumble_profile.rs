//! Per case of the rotating benchmark (`samples::tumbling_cases(10, 5)`):
//! nearmiss's time of impact, iterations, triangle pairs and wall time
//! (fastest of 20 runs). A profiling aid for `benches/mesh_ccd.rs`;
//! `--translating` for `samples::translating_cases`.
use nearmiss::ccd::{mesh_time_of_impact, CcdOptions, MeshCcdQuery, MeshCcdScratch, MovingMesh, WarmStart};
use nearmiss::samples::{translating_cases, tumbling_cases};
use std::time::Instant;

fn main() {
    let translating = std::env::args().any(|arg| arg == "--translating");
    let (a, b, cases) = if translating { translating_cases(10, 5) } else { tumbling_cases(10, 5) };
    let options = CcdOptions::default();
    let mut scratch = MeshCcdScratch::default();
    let mut total = 0.0;
    println!("| case | toi | status | iterations | triangle pairs | node pairs | µs |\n|---|---|---|---|---|---|---|");
    for (k, (ma, mb)) in cases.iter().enumerate() {
        let mut fastest = f64::INFINITY;
        let mut result = None;
        for _ in 0..20 {
            let start = Instant::now();
            let r = mesh_time_of_impact(
                &MeshCcdQuery::new(
                    MovingMesh { mesh: &a, motion: ma },
                    MovingMesh { mesh: &b, motion: mb },
                    1.0,
                    options,
                ),
                WarmStart::default(),
                &mut scratch,
            );
            fastest = fastest.min(start.elapsed().as_secs_f64() * 1e6);
            result = Some(r);
        }
        let r = result.expect("ran");
        total += fastest;
        println!(
            "| {k} | {:?} | {:?} | {} | {} | {} | {fastest:.0} |",
            r.time_of_impact, r.status, r.iterations, r.triangle_pairs, r.node_pairs
        );
    }
    println!("mean {:.0} µs per query", total / cases.len() as f64);
}

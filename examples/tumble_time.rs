//! Times rotating mesh-mesh CCD (icosphere 320 vs 1280 triangles, both
//! tumbling, offset approach) on seeded cases: a quick look, not a benchmark.
use nearmiss::ccd::{mesh_time_of_impact, CcdOptions, MovingMesh};
use nearmiss::math::{Pose, Vector};
use nearmiss::mesh::{icosphere, DistanceKernel, MeshDistanceScratch};
use nearmiss::motion::StepMotion;
use nearmiss::samples::Rng;
use std::time::Instant;

fn main() {
    let a = icosphere(1.0, 2).unwrap();
    let b = icosphere(1.0, 3).unwrap();
    let tolerance: f64 = std::env::var("TOL").ok().and_then(|t| t.parse().ok()).unwrap_or(1e-6);
    let options = CcdOptions { distance_tolerance: tolerance, ..CcdOptions::default() };
    let mut scratch = MeshDistanceScratch::default();
    let mut rng = Rng::new(5);
    for case in 0..10 {
        let motion_a = StepMotion::new(
            Pose::new(Vector::new(-2.5, 0.0, 0.0), rng.in_unit_ball() * 3.0),
            Vector::new(2.0, 0.0, 0.0) + rng.in_unit_ball() * 0.3,
            rng.in_unit_ball() * 10.0,
        );
        let motion_b = StepMotion::new(
            Pose::new(Vector::new(2.5, 0.0, 0.0) + rng.in_unit_ball() * 0.8, rng.in_unit_ball() * 3.0),
            Vector::new(-2.0, 0.0, 0.0),
            rng.in_unit_ball() * 10.0,
        );
        let start = Instant::now();
        let r = mesh_time_of_impact(
            MovingMesh { mesh: &a, motion: &motion_a },
            MovingMesh { mesh: &b, motion: &motion_b },
            1.0,
            &options,
            DistanceKernel::Exact,
            None,
            None,
            &mut scratch,
        );
        println!(
            "case {case}: toi {:?} status {:?} queries {} directional {} pairs {} time {:.3} ms",
            r.time_of_impact,
            r.status,
            r.distance_queries,
            r.directional_steps,
            r.triangle_pairs,
            start.elapsed().as_secs_f64() * 1e3
        );
    }
}

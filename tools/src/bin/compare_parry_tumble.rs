//! Rotating mesh–mesh time of impact, nearmiss against parry's
//! `cast_shapes_nonlinear`, on the seeded tumbling cases of
//! `benches/mesh_ccd.rs` (icosphere 320 vs 1280 triangles). Where the two
//! disagree by more than the tolerance, a fine scan of the exact distance
//! (brute force over all triangle pairs, no BVH) before the later of the two
//! times tells which one is right.
//!
//! `--translating`: the translating cases (`samples::translating_cases`)
//! against parry's `cast_shapes` instead.
use nearmiss::ccd::{mesh_time_of_impact, CcdOptions, MeshCcdQuery, MeshCcdScratch, MovingMesh, WarmStart};
use nearmiss::math::{motion_to_parry, pose_to_parry, vector_to_parry, Real};
use nearmiss::mesh::{mesh_distance, mesh_distance_brute_force, DistanceSearch, MeshDistanceScratch};
use nearmiss::motion::StepMotion;
use nearmiss::samples::{translating_cases, tumbling_cases};
use std::time::Instant;

fn main() {
    let translating = std::env::args().any(|arg| arg == "--translating");
    let (a, b, cases) = if translating { translating_cases(10, 5) } else { tumbling_cases(10, 5) };
    let (pa_mesh, pb_mesh) = (a.to_parry().unwrap(), b.to_parry().unwrap());
    let options = CcdOptions::default();
    let mut scratch = MeshCcdScratch::default();
    println!("| case | nearmiss toi | µs | parry toi | µs | verdict |\n|---|---|---|---|---|---|");
    for (k, (ma, mb)) in cases.iter().enumerate() {
        let start = Instant::now();
        let ours = mesh_time_of_impact(
            &MeshCcdQuery::new(
                MovingMesh { mesh: &a, motion: ma },
                MovingMesh { mesh: &b, motion: mb },
                1.0,
                options,
            ),
            WarmStart::default(),
            &mut scratch,
        );
        let ours_us = start.elapsed().as_secs_f64() * 1e6;
        let parry_motion = |m: &StepMotion| motion_to_parry(&m.pose_t0(), &m.velocity, &m.angular_velocity);
        let start = Instant::now();
        let hit = if translating {
            parry3d_f64::query::cast_shapes(
                &pose_to_parry(&ma.pose_t0()),
                vector_to_parry(&ma.velocity),
                &pa_mesh,
                &pose_to_parry(&mb.pose_t0()),
                vector_to_parry(&mb.velocity),
                &pb_mesh,
                parry3d_f64::query::ShapeCastOptions::with_max_time_of_impact(1.0),
            )
        } else {
            parry3d_f64::query::cast_shapes_nonlinear(
                &parry_motion(ma),
                &pa_mesh,
                &parry_motion(mb),
                &pb_mesh,
                0.0,
                1.0,
                true,
            )
        };
        let theirs = hit.ok().flatten().map(|hit| hit.time_of_impact);
        let parry_us = start.elapsed().as_secs_f64() * 1e6;
        let t_ours = ours.time_of_impact;
        let tolerance = 1e-6 * 2.0 / 1.0; // twice the contact distance (1e-6 x min(r_a, r_b), unit icospheres) over a closing speed of at least ~1
        let verdict = match (t_ours, theirs) {
            (Some(x), Some(y)) if (x - y).abs() <= tolerance => "agree".to_string(),
            (None, None) => "agree: no contact".to_string(),
            _ => {
                // Scan between the two times (and a little before) for the
                // first sample where the meshes intersect (distance 0).
                let lo = t_ours.unwrap_or(1.0).min(theirs.unwrap_or(1.0)) - 1e-3;
                let hi = t_ours.unwrap_or(1.0).max(theirs.unwrap_or(1.0));
                let samples = 4000;
                // The scan uses the BVH distance (exact kernel); the decisive
                // samples are confirmed by brute force over all triangle pairs.
                let mut distance_scratch = MeshDistanceScratch::default();
                let mut exact = |t: Real| {
                    mesh_distance(
                        &a,
                        &ma.pose_at(t),
                        &b,
                        &mb.pose_at(t),
                        &DistanceSearch::default(),
                        &mut distance_scratch,
                    )
                    .distance
                };
                let first = (0..=samples)
                    .map(|s| lo + (hi - lo) * s as Real / samples as Real)
                    .find(|&t| exact(t) == 0.0);
                if let Some(t) = first {
                    assert_eq!(mesh_distance_brute_force(&a, &ma.pose_at(t), &b, &mb.pose_at(t)), 0.0);
                }
                let at_ours =
                    t_ours.map(|t| mesh_distance_brute_force(&a, &ma.pose_at(t), &b, &mb.pose_at(t)));
                let late = |t: Option<Real>| match (t, first) {
                    (Some(t), Some(f)) => t > f,
                    (None, Some(_)) => true,
                    _ => false,
                };
                format!(
                    "disagree; scan: first intersecting sample {first:?}; distance at nearmiss's time {at_ours:?}; nearmiss late: {}, parry late: {}",
                    late(t_ours),
                    late(theirs)
                )
            }
        };
        println!("| {k} | {t_ours:?} | {ours_us:.0} | {theirs:?} | {parry_us:.0} | {verdict} |");
    }
}

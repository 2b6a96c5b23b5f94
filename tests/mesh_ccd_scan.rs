//! Never late, checked independently: for random tumbling mesh pairs, the
//! brute-force distance (every triangle pair, scalar exact kernel, no BVH)
//! on a fine scan of the motion before the reported contact is never zero,
//! and pairs reported as separated never touch on the scan.

use nearmiss::ccd::{mesh_time_of_impact, CcdOptions, MovingMesh};
use nearmiss::math::{Pose, Real, Vector};
use nearmiss::mesh::{box_mesh, icosphere, mesh_distance_brute_force, DistanceKernel, MeshDistanceScratch};
use nearmiss::motion::StepMotion;
use nearmiss::samples::Rng;

#[test]
fn no_touching_before_the_reported_time_on_a_fine_scan() {
    let a = icosphere(0.6, 1).unwrap();
    let b = box_mesh(&Vector::new(0.7, 0.2, 0.4)).unwrap();
    let mut rng = Rng::new(11);
    let mut scratch = MeshDistanceScratch::default();
    let options = CcdOptions { distance_tolerance: 1e-9, ..CcdOptions::default() };
    let (mut contacts, mut separated) = (0, 0);
    for case in 0..40 {
        let motion_a = StepMotion::new(
            Pose::new(rng.in_unit_ball() * 0.3, rng.in_unit_ball() * 3.0),
            Vector::new(1.5, 0.0, 0.0) + rng.in_unit_ball() * 0.5,
            rng.in_unit_ball() * 12.0,
        );
        let motion_b = StepMotion::new(
            Pose::new(Vector::new(2.2, 0.0, 0.0) + rng.in_unit_ball() * 0.6, rng.in_unit_ball() * 3.0),
            rng.in_unit_ball() * 0.5,
            rng.in_unit_ball() * 12.0,
        );
        let result = mesh_time_of_impact(
            MovingMesh { mesh: &a, motion: &motion_a },
            MovingMesh { mesh: &b, motion: &motion_b },
            1.0,
            &options,
            DistanceKernel::Exact,
            None,
            None,
            &mut scratch,
        );
        let end = result.time_of_impact.unwrap_or(1.0);
        match result.time_of_impact {
            Some(_) => contacts += 1,
            None => separated += 1,
        }
        for k in 0..400 {
            let s = end * k as Real / 400.0;
            let d = mesh_distance_brute_force(&a, &motion_a.pose_at(s), &b, &motion_b.pose_at(s));
            assert!(
                d > 0.0,
                "case {case}: touching at t = {s} before the reported {:?}",
                result.time_of_impact
            );
        }
    }
    // The cases must exercise both outcomes.
    assert!(contacts >= 10 && separated >= 3, "{contacts} contacts, {separated} separated");
}

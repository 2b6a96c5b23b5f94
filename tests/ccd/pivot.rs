//! A motion between two poses turning about a point of the body (issue 46
//! §3): a rod hinged at its end swings a quarter turn about it, its joint
//! fixed, as `StepMotion::between_about` and `TriMesh::pivoted` move it.
//! The first contact with a block in its way and the closest approach to a
//! block beyond its reach are those of the analytic swing, never late.

use std::f64::consts::FRAC_PI_2;

use nalgebra::{Translation3, UnitQuaternion};
use nearmiss::ccd::{
    closest_approach, mesh_time_of_impact, ApproachStatus, CcdOptions, ClosestApproachQuery, ContactRule,
    MeshCcdQuery, MeshCcdScratch, MovingMesh, WarmStart,
};
use nearmiss::math::{Point, Pose, Real, Vector};
use nearmiss::mesh::{box_mesh, DistanceKernel, TriMesh};
use nearmiss::motion::StepMotion;

/// The rod: 2 × 0.1 × 0.1 about its centre, hinged at its end `(-1, 0, 0)`.
fn rod() -> (TriMesh, Point) {
    (box_mesh(&Vector::new(1.0, 0.05, 0.05)).unwrap(), Point::new(-1.0, 0.0, 0.0))
}

/// The rod's poses: along +x with its joint at the origin, then turned a
/// quarter about z, the joint where it was (`p1 = -R1 joint`).
fn swing() -> (Pose, Pose) {
    let turned = UnitQuaternion::from_axis_angle(&Vector::z_axis(), FRAC_PI_2);
    let start = Pose::translation(1.0, 0.0, 0.0);
    let end = Pose::from_parts(Translation3::from(-(turned * Vector::new(-1.0, 0.0, 0.0))), turned);
    (start, end)
}

/// A fixed block `[x0, x1] × [y0, y1] × [-1, 1]`.
fn block(x: (Real, Real), y: (Real, Real)) -> (TriMesh, StepMotion) {
    let half = Vector::new((x.1 - x.0) / 2.0, (y.1 - y.0) / 2.0, 1.0);
    let centre = Pose::translation((x.0 + x.1) / 2.0, (y.0 + y.1) / 2.0, 0.0);
    (box_mesh(&half).unwrap(), StepMotion::fixed(centre))
}

#[test]
fn the_motion_keeps_the_joint_and_meets_both_poses() {
    let (mesh, joint) = rod();
    let (start, end) = swing();
    let motion = StepMotion::between_about(&start, &end, 1.0, &joint);
    let pivoted = mesh.pivoted(&joint).unwrap();
    assert_eq!(motion.velocity, Vector::zeros(), "the joint stays put");
    for (s, pose) in [(0.0, start), (1.0, end)] {
        for (moved, original) in pivoted.vertices().iter().zip(mesh.vertices()) {
            let error = (motion.pose_at(s) * moved - pose * original).norm();
            assert!(error <= 4.0 * Real::EPSILON, "at {s}: {error:e}");
        }
    }
    // Half way, the far end is at 45 degrees, 2 from the joint.
    let far_end = motion.pose_at(0.5) * (Point::new(1.0, 0.0, 0.0) - joint.coords);
    let diagonal = std::f64::consts::SQRT_2;
    assert!((far_end - Point::new(diagonal, diagonal, 0.0)).norm() <= 1e-15);
}

/// The block `[1.5, 2] × [0.5, 1.5]` lies in the swing. The rod's far top
/// edge (2, 0.05) in the rod's frame, at radius r = √4.0025 and angle
/// φ = atan(0.025) ahead of its axis, reaches the block's bottom face
/// y = 0.5 when r sin(θ + φ) = 0.5 (at x ≈ 1.94, on the face); the top
/// face reaches the block's corner (1.5, 0.5) only later (θ ≈ 0.290).
#[test]
fn a_block_in_the_swing_is_hit_at_the_analytic_angle() {
    let (mesh, joint) = rod();
    let (start, end) = swing();
    let motion = StepMotion::between_about(&start, &end, 1.0, &joint);
    let pivoted = mesh.pivoted(&joint).unwrap();
    let (obstacle, fixed) = block((1.5, 2.0), (0.5, 1.5));
    let r = 4.0025_f64.sqrt();
    let angle = (0.5 / r).asin() - 0.025_f64.atan();
    let later = (0.5 * 0.5 + 1.5 * 1.5_f64).sqrt();
    // The corner is on the top face's line when 0.5 cos θ - 1.5 sin θ = 0.05.
    assert!(angle < (0.05 / later).acos() - 1.5_f64.atan2(0.5), "the edge comes first");
    let expected = angle / FRAC_PI_2;
    let options = CcdOptions { distance_tolerance: 1e-9, ..CcdOptions::default() };
    let query = MeshCcdQuery {
        a: MovingMesh { mesh: &pivoted, motion: &motion },
        b: MovingMesh { mesh: &obstacle, motion: &fixed },
        duration: 1.0,
        options,
        contact: ContactRule::ScaleRelative,
        kernel: DistanceKernel::Exact,
    };
    let result = mesh_time_of_impact(&query, WarmStart::default(), &mut MeshCcdScratch::default());
    let time = result.time_of_impact.expect("the rod hits the block");
    assert!(time <= expected, "late: {time} > {expected}");
    // Early by at most the contact distance over the closing speed: the
    // edge moves at r π/2 across its radius, which is θ + φ from the face's
    // plane, so it closes on the face at r π/2 cos(θ + φ) (1% for the arc's
    // curvature over so short a way).
    let speed = r * FRAC_PI_2 * (angle + 0.025_f64.atan()).cos();
    assert!(expected - time <= 1.01 * result.contact_distance / speed, "early by {}", expected - time);
}

/// The block `[-0.5, 0.5] × [2.01, 3]` lies beyond the rod's end at the
/// quarter turn. The far corners reach farthest along y at θ = atan(40)
/// (where 2 sin θ + 0.05 cos θ peaks at √4.0025, x = 0 there): the closest
/// approach is 2.01 - √4.0025, before the end of the swing.
#[test]
fn the_closest_approach_beyond_the_reach_is_the_analytic_one() {
    let (mesh, joint) = rod();
    let (start, end) = swing();
    let motion = StepMotion::between_about(&start, &end, 1.0, &joint);
    let pivoted = mesh.pivoted(&joint).unwrap();
    let (obstacle, fixed) = block((-0.5, 0.5), (2.01, 3.0));
    let gap = 2.01 - 4.0025_f64.sqrt();
    let mut query = ClosestApproachQuery::new(
        MovingMesh { mesh: &pivoted, motion: &motion },
        MovingMesh { mesh: &obstacle, motion: &fixed },
        1.0,
    );
    query.within = Real::INFINITY;
    let approach = closest_approach(&query, &mut MeshCcdScratch::default());
    assert_eq!(approach.status, ApproachStatus::Bracketed, "{approach:?}");
    assert!(approach.lower <= gap && gap <= approach.upper * (1.0 + 1e-12), "{approach:?} against {gap}");
    let at = 40.0_f64.atan() / FRAC_PI_2;
    // The distance is flat at its minimum: the time is near, not exact.
    assert!((approach.time - at).abs() < 0.01, "{approach:?} against t = {at}");
}

//! One mesh–mesh time of impact: a box spinning about its long axis while
//! it flies at a fixed box, the query a user calls directly (no scene, no
//! stepper).
//!
//! The spinning box (half extents 0.5 × 0.1 × 0.1, its long axis along x,
//! turning about x at 20 rad/s) starts 1 away from a unit cube's face and
//! closes at 2 units per second along x. Its end cap stays a 0.2 × 0.2
//! square whatever the turn, so its face meets the cube's at t = 0.5: the
//! CCD reports that time, early by at most the contact distance over the
//! closing speed, and never late.
//!
//! Run: `cargo run --release --example mesh_ccd_query`

use nearmiss::ccd::{mesh_time_of_impact, CcdOptions, MeshCcdQuery, MeshCcdScratch, MovingMesh, WarmStart};
use nearmiss::math::{Pose, Vector};
use nearmiss::mesh::box_mesh;
use nearmiss::motion::StepMotion;

fn main() {
    let cube = box_mesh(&Vector::new(0.5, 0.5, 0.5)).expect("a valid box");
    let rod = box_mesh(&Vector::new(0.5, 0.1, 0.1)).expect("a valid box");
    // The cube at rest at the origin; the rod's near end 1 from the cube's
    // +x face (at x = 0.5), flying towards it and spinning about its axis.
    let cube_motion = StepMotion::fixed(Pose::identity());
    let rod_start = Pose::translation(0.5 + 1.0 + 0.5, 0.0, 0.0);
    let rod_motion =
        StepMotion::free(&rod_start, Vector::new(-2.0, 0.0, 0.0), Vector::new(20.0, 0.0, 0.0), 0.0);
    let query = MeshCcdQuery::new(
        MovingMesh { mesh: &cube, motion: &cube_motion },
        MovingMesh { mesh: &rod, motion: &rod_motion },
        1.0,
        CcdOptions::default(),
    );
    // One scratch per thread: queries reuse its buffers.
    let mut scratch = MeshCcdScratch::default();
    let result = mesh_time_of_impact(&query, WarmStart::default(), &mut scratch);

    println!("status: {:?} after {} iterations", result.status, result.iterations);
    let Some(time) = result.time_of_impact else {
        println!("no contact within the interval");
        return;
    };
    let closest = result.closest.expect("a contact has its closest points");
    println!("time of impact: {time} (analytic: 0.5, early by at most {:e})", result.contact_distance / 2.0);
    println!("distance there: {:e} (contact distance {:e})", closest.distance, result.contact_distance);
    println!("closest points: {:?} on the cube, {:?} on the rod", closest.point_a, closest.point_b);
    println!(
        "features: {:?} of triangle {} / {:?} of triangle {}",
        closest.feature_a, closest.triangle_a, closest.feature_b, closest.triangle_b
    );
}

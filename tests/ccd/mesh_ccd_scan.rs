//! Never late, checked independently: for random tumbling mesh pairs, the
//! brute-force distance (every triangle pair, scalar exact kernel, no BVH)
//! on a fine scan of the motion before the reported contact never comes
//! below the guaranteed distance (every approach closer than it must be
//! reported), a dense scan of the last moment before it neither, pairs
//! reported as separated never come that close on the scan, and at a
//! reported contact the meshes are within the contact distance. The cases
//! take both paths of the query: advancement on the hulls' gap alone, and
//! the BVH search.

use nearmiss::ccd::{
    mesh_time_of_impact, CcdOptions, MeshCcdQuery, MeshCcdResult, MeshCcdScratch, MovingMesh, WarmStart,
};
use nearmiss::math::{Pose, Real, Vector};
use nearmiss::mesh::{box_mesh, icosphere, load_obj, mesh_distance_brute_force, TriMesh};
use nearmiss::motion::StepMotion;
use nearmiss::samples::Rng;
use std::path::Path;

/// Runs one case and checks it against brute force; returns whether contact
/// was reported and whether the hulls' gap advanced before the search.
fn check_case(
    case: usize,
    a: &TriMesh,
    b: &TriMesh,
    motion_a: &StepMotion,
    motion_b: &StepMotion,
) -> (bool, bool) {
    let options = CcdOptions { distance_tolerance: 1e-9, ..CcdOptions::default() };
    let mut scratch = MeshCcdScratch::default();
    let result: MeshCcdResult = mesh_time_of_impact(
        &MeshCcdQuery::new(
            MovingMesh { mesh: a, motion: motion_a },
            MovingMesh { mesh: b, motion: motion_b },
            1.0,
            options,
        ),
        WarmStart::default(),
        &mut scratch,
    );
    let distance_at = |s: Real| mesh_distance_brute_force(a, &motion_a.pose_at(s), b, &motion_b.pose_at(s));
    let end = result.time_of_impact.unwrap_or(1.0);
    // The whole interval before the reported time, then its last 1e-3 densely.
    let coarse = (0..300).map(|k| end * k as Real / 300.0);
    let fine = (0..200).map(|k| (end - 1e-3 * (1.0 - k as Real / 200.0)).max(0.0));
    for s in coarse.chain(fine) {
        let d = distance_at(s);
        assert!(
            d > 0.0 && d >= result.guaranteed_distance - 1e-12,
            "case {case}: distance {d} at t = {s} before the reported {:?} (guaranteed {})",
            result.time_of_impact,
            result.guaranteed_distance
        );
    }
    if let Some(time) = result.time_of_impact {
        // Within the contact distance there (to the rounding of two poses).
        let d = distance_at(time);
        assert!(
            d <= result.contact_distance + 1e-12,
            "case {case}: distance {d} at the reported contact, contact distance {}",
            result.contact_distance
        );
    }
    (result.time_of_impact.is_some(), result.hull_steps > 0)
}

fn random_motion(rng: &mut Rng, center: Vector, velocity: Vector, spin: Real) -> StepMotion {
    StepMotion::new(
        Pose::new(center + rng.in_unit_ball() * 0.3, rng.in_unit_ball() * 3.0),
        velocity + rng.in_unit_ball() * 0.5,
        rng.in_unit_ball() * spin,
    )
}

#[test]
fn no_touching_before_the_reported_time_on_a_fine_scan() {
    let a = icosphere(0.6, 1).unwrap();
    let b = box_mesh(&Vector::new(0.7, 0.2, 0.4)).unwrap();
    let mut rng = Rng::new(11);
    let (mut contacts, mut separated, mut advanced_on_hulls) = (0, 0, 0);
    for case in 0..40 {
        let motion_a = random_motion(&mut rng, Vector::zeros(), Vector::new(1.5, 0.0, 0.0), 12.0);
        let motion_b = random_motion(&mut rng, Vector::new(2.2, 0.0, 0.0), Vector::zeros(), 12.0);
        let (contact, hulls) = check_case(case, &a, &b, &motion_a, &motion_b);
        match contact {
            true => contacts += 1,
            false => separated += 1,
        }
        advanced_on_hulls += usize::from(contact && hulls);
    }
    // The cases must exercise both outcomes, and contacts found after
    // advancing on the hulls' gap.
    assert!(contacts >= 10 && separated >= 3, "{contacts} contacts, {separated} separated");
    assert!(advanced_on_hulls >= 5, "{advanced_on_hulls} contacts after advancing on the hulls");
}

#[test]
fn flat_faces_meet_flat_faces() {
    // Boxes: many contacts are face against face or edge along face, where
    // whole sets of triangle pairs are equally close.
    let a = box_mesh(&Vector::new(0.5, 0.5, 0.5)).unwrap();
    let b = box_mesh(&Vector::new(0.8, 0.1, 0.6)).unwrap();
    let mut rng = Rng::new(23);
    let mut contacts = 0;
    for case in 0..40 {
        let motion_a = random_motion(&mut rng, Vector::zeros(), Vector::new(1.8, 0.0, 0.0), 4.0);
        let motion_b = random_motion(&mut rng, Vector::new(2.6, 0.0, 0.0), Vector::zeros(), 4.0);
        contacts += usize::from(check_case(case, &a, &b, &motion_a, &motion_b).0);
    }
    assert!(contacts >= 20, "{contacts} contacts");
}

#[test]
fn concave_mesh_against_a_sphere() {
    // The T-handle (concave) tumbling into a sphere, which can meet it
    // inside the corner between bar and stem.
    let handle =
        load_obj(Path::new(concat!(env!("CARGO_MANIFEST_DIR"), "/scenes/meshes/t_handle.obj"))).unwrap();
    let centre = handle.mass_properties().expect("a closed mesh").center_of_mass;
    let handle = handle.recentered(&centre);
    let ball = icosphere(0.3, 2).unwrap();
    let mut rng = Rng::new(31);
    let mut contacts = 0;
    for case in 0..20 {
        let motion_a = random_motion(&mut rng, Vector::zeros(), Vector::new(1.5, 0.0, 0.0), 8.0);
        let motion_b = random_motion(&mut rng, Vector::new(2.0, 0.0, 0.0), Vector::zeros(), 8.0);
        contacts += usize::from(check_case(case, &handle, &ball, &motion_a, &motion_b).0);
    }
    assert!(contacts >= 8, "{contacts} contacts");
}

//! The contact contract has one home (`ccd::ContactContract`): the
//! linear-vertex CCD, the mesh CCD (scale-relative and absolute rules) and
//! the stepper's broad phase all agree with it.

use nearmiss::ccd::{
    box_margin, mesh_time_of_impact, vertex_face_time_of_impact_detailed, CcdOptions, CcdStatus,
    ContactContract, ContactRule, MeshCcdQuery, MeshCcdScratch, MovingMesh, WarmStart,
};
use nearmiss::math::{Point, Pose, Real, Vector};
use nearmiss::mesh::{box_mesh, icosphere};
use nearmiss::motion::StepMotion;
use nearmiss::run::{run_with, RunOptions};
use nearmiss::scene::Scene;

/// A tolerance far above every rounding floor, so the contract's value is
/// the scale-relative one exactly.
const TOLERANCE: Real = 1e-3;

#[test]
fn vertex_face_ccd_uses_the_contract() {
    let options =
        CcdOptions { distance_tolerance: TOLERANCE, minimum_separation: 0.01, ..CcdOptions::default() };
    let face = [Point::new(0.0, 0.0, 0.0), Point::new(1.0, 0.0, 0.0), Point::new(0.0, 1.0, 0.0)];
    let (v_t0, v_t1) = (Point::new(0.2, 0.2, 1.0), Point::new(0.2, 0.2, -1.0));
    let result = vertex_face_time_of_impact_detailed(&v_t0, &face, &v_t1, &face, &options);
    // The query's size: the diagonal of the box around all its vertices.
    let (lo, hi) = [v_t0, v_t1]
        .iter()
        .chain(&face)
        .fold((Vector::repeat(Real::INFINITY), Vector::repeat(Real::NEG_INFINITY)), |(lo, hi), p| {
            (lo.inf(&p.coords), hi.sup(&p.coords))
        });
    let contract = ContactContract::of(&options, ContactRule::ScaleRelative, (hi - lo).norm(), 0.0);
    assert_eq!(result.contact_distance, contract.contact_distance);
    let time = result.time_of_impact.expect("the vertex goes through the face");
    // It crosses at t = 0.5; reported no later, and within the contact distance.
    assert!(time <= 0.5 && result.distance <= contract.contact_distance);
}

#[test]
fn mesh_ccd_uses_the_contract_for_both_rules() {
    let (a, b) = (icosphere(1.0, 2).unwrap(), icosphere(0.5, 1).unwrap());
    let ma = StepMotion::new(Pose::identity(), Vector::new(1.0, 0.0, 0.0), Vector::new(0.0, 0.0, 3.0));
    let mb = StepMotion::new(Pose::translation(3.0, 0.0, 0.0), Vector::zeros(), Vector::zeros());
    let options = CcdOptions { distance_tolerance: TOLERANCE, ..CcdOptions::default() };
    let query = MeshCcdQuery::new(
        MovingMesh { mesh: &a, motion: &ma },
        MovingMesh { mesh: &b, motion: &mb },
        2.0,
        options,
    );
    let mut scratch = MeshCcdScratch::default();
    let relative = mesh_time_of_impact(&query, WarmStart::default(), &mut scratch);
    let contract = ContactContract::of(&options, ContactRule::ScaleRelative, a.radius().min(b.radius()), 0.0);
    assert_eq!(relative.contact_distance, contract.contact_distance);
    assert!(relative.closest.expect("they meet").distance <= contract.contact_distance);

    let absolute = MeshCcdQuery { contact: ContactRule::Absolute(0.25), ..query };
    let result = mesh_time_of_impact(&absolute, WarmStart::default(), &mut scratch);
    assert_eq!(result.contact_distance, 0.25);
    assert!(result.closest.expect("they meet").distance <= 0.25);
    // A larger contact distance is reached no later.
    assert!(result.time_of_impact.unwrap() <= relative.time_of_impact.unwrap());
}

#[test]
fn a_pair_within_the_contact_distance_at_the_start_touches_at_the_start_whatever_its_motion() {
    // A cube a hair (a tenth of the contact distance) above a plate: at rest,
    // receding, sliding and spinning about the plate's normal it is in
    // contact at t = 0 (a bound that lets a receding pair skip its step
    // must not skip one that already touches).
    let plate = box_mesh(&Vector::new(2.0, 2.0, 0.1)).unwrap();
    let cube = box_mesh(&Vector::new(0.1, 0.1, 0.1)).unwrap();
    let options = CcdOptions::default();
    let contact =
        ContactContract::of(&options, ContactRule::ScaleRelative, cube.radius(), 0.0).contact_distance;
    let fixed = StepMotion::fixed(Pose::translation(0.0, 0.0, -0.1));
    let at = Pose::translation(0.0, 0.0, 0.1 + contact / 10.0);
    for (velocity, spin) in [
        (Vector::zeros(), Vector::zeros()),
        (Vector::new(0.0, 0.0, 1.0), Vector::zeros()),
        (Vector::new(1.0, 0.0, 0.0), Vector::zeros()),
        (Vector::zeros(), Vector::new(0.0, 0.0, 5.0)),
    ] {
        let moving = StepMotion::new(at, velocity, spin);
        let query = MeshCcdQuery::new(
            MovingMesh { mesh: &plate, motion: &fixed },
            MovingMesh { mesh: &cube, motion: &moving },
            0.01,
            options,
        );
        let result = mesh_time_of_impact(&query, WarmStart::default(), &mut MeshCcdScratch::default());
        assert_eq!(
            (result.time_of_impact, result.status),
            (Some(0.0), CcdStatus::InitiallyTouching),
            "velocity {velocity:?}, spin {spin:?}"
        );
    }
}

/// Body `a` slides past `b` with a closest gap of 1e-4 (below the
/// contract's target, so it must be reported), vertex to vertex along `y`,
/// where the swept boxes are tight: only the contract's box margin makes
/// them overlap. A third, far body makes the stepper use its broad phase.
#[test]
fn broad_phase_margin_keeps_every_pair_the_ccd_reports() {
    let gap = 1e-4;
    let text = format!(
        r#"Scene(name: "pass", dt: 0.01, duration: 4.0, on_contact: Record,
            ccd: (distance_tolerance: {TOLERANCE:e}),
            bodies: [
                (name: "a", mesh: Triangle(a: (0.0, 0.5, 0.0), b: (-0.4, -0.3, 0.0), c: (0.4, -0.3, 0.0)),
                 position: (-2.0, 0.0, 0.0), velocity: (1.0, 0.0, 0.0)),
                (name: "b", mesh: Triangle(a: (0.0, -0.5, 0.0), b: (-0.4, 0.3, 0.0), c: (0.4, 0.3, 0.0)),
                 position: (0.0, {y:?}, 0.0), fixed: true),
                (name: "far", mesh: Box(half_extents: (0.5, 0.5, 0.5)), position: (0.0, 50.0, 0.0), fixed: true),
            ])"#,
        y = 1.0 + gap
    );
    let scene = Scene::from_ron_str(&text).unwrap();
    let (ra, rb) = (scene.model().bodies[0].mesh.radius(), scene.model().bodies[1].mesh.radius());
    let contract = ContactContract::of(&scene.model().ccd, ContactRule::ScaleRelative, ra.min(rb), 0.0);
    assert!(gap < contract.target, "the pass must be one the contract reports");
    // Without the margin the swept boxes would miss each other along y.
    assert!(
        ra + rb < 1.0 + gap
            && ra + rb + box_margin(&scene.model().ccd, ra) + box_margin(&scene.model().ccd, rb) >= 1.0 + gap
    );
    let with_tree = run_with(&scene, RunOptions::default(), &mut |_| {});
    let all_pairs = run_with(&scene, RunOptions { broad_phase: false, ..RunOptions::default() }, &mut |_| {});
    assert_eq!(with_tree.contacts, all_pairs.contacts);
    let contact = with_tree.first_contact.expect("the pass is reported");
    assert_eq!((contact.body_a, contact.body_b), (0, 1));
    assert_eq!(contact.contact_distance, contract.contact_distance);
    assert!(contact.closest.distance <= contract.contact_distance);
}

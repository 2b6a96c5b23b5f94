//! Time of first contact of whole scenes against analytic values, at
//! distance tolerance 1e-9: never later than the true time, and earlier by
//! at most the contact distance over the closing speed.

use nearmiss::run::{run, Contact, RunResult};
use nearmiss::scene::Scene;

fn run_ron(text: &str) -> RunResult {
    let scene = Scene::from_ron_str(text).unwrap_or_else(|e| panic!("{e}\n{text}"));
    run(&scene)
}

/// Asserts the conservative guarantee and the accuracy bound for a contact
/// expected at `expected` with normal closing speed `closing_speed`.
fn assert_contact(result: &RunResult, bodies: (&str, &str), expected: f64, closing_speed: f64) -> Contact {
    let contact =
        result.first_contact.clone().unwrap_or_else(|| panic!("no contact, expected t = {expected}"));
    let names = (result.bodies[contact.body_a].as_str(), result.bodies[contact.body_b].as_str());
    assert_eq!(names, bodies);
    // Never late (4 ulps: the expected value is itself a rounded number).
    assert!(contact.time <= expected * (1.0 + 4.0 * f64::EPSILON), "late: {} > {expected}", contact.time);
    // Early by at most the contact distance over the closing speed.
    let early = expected - contact.time;
    let bound = contact.contact_distance / closing_speed;
    assert!(early <= bound * (1.0 + 1e-6) + 4.0 * f64::EPSILON * expected, "early by {early:e} > {bound:e}");
    assert!(contact.closest.distance <= contact.contact_distance);
    contact
}

fn boxes(dt: f64, extra: &str) -> String {
    format!(
        r#"Scene(name: "t", dt: {dt}, duration: 1.0, ccd: (distance_tolerance: 1e-9), bodies: [
            (name: "a", mesh: Box(half_extents: (0.5, 0.5, 0.5)), fixed: true),
            (name: "b", mesh: Box(half_extents: (0.3, 0.2, 0.4)), {extra}),
        ])"#
    )
}

#[test]
fn pure_translation_hits_at_gap_over_speed_whatever_the_step() {
    // Gap 2 - 0.5 - 0.3 = 1.2 at speed 3: t = 0.4.
    for dt in [0.5, 0.1, 0.013, 1e-3] {
        let result = run_ron(&boxes(dt, "position: (2.0, 0.1, 0.05), velocity: (-3.0, 0.0, 0.0)"));
        assert_contact(&result, ("a", "b"), 0.4, 3.0);
    }
}

#[test]
fn both_bodies_moving() {
    // Gap 1 between the faces; closing speed 0.75 + 1.25 = 2: t = 0.5.
    let result = run_ron(
        r#"Scene(name: "t", dt: 0.01, duration: 1.0, ccd: (distance_tolerance: 1e-9), bodies: [
            (name: "a", mesh: Box(half_extents: (0.5, 0.5, 0.5)), velocity: (0.0, 0.75, 0.0)),
            (name: "b", mesh: Tetrahedron(circumradius: 0.5), position: (0.3, 1.5 + 0.5 / 1.7320508075688772 * 1.0, 0.1),
             orientation: AxisAngle(axis: (1.0, 0.0, -1.0), degrees: 0.0), velocity: (0.0, -1.25, 0.0)),
        ])"#
        .replace("1.5 + 0.5 / 1.7320508075688772 * 1.0", "1.7886751345948129")
        .as_str(),
    );
    // The tetrahedron's vertices are at ±0.5/√3 per axis: its lowest y is
    // 1.7886751345948129 - 0.28867513459481287 = 1.5, the box's top 0.5.
    assert_contact(&result, ("a", "b"), 0.5, 2.0);
}

#[test]
fn rotation_about_a_fixed_axis_until_an_edge_hits_a_vertex() {
    // A triangle with one edge on the radial line from the z axis spins at
    // ω = 5; the probe's vertex P is at radius 0.6, angle 1 rad, z = 0; its
    // other vertices are below z = 0, where the spinning triangle never
    // goes, and further round, so P is the probe's point nearest the arm.
    // The edge reaches P when the angle is 1: t = 1 / 5; the distance closes
    // at ω r = 3.
    let (c, s) = (0.6 * 1f64.cos(), 0.6 * 1f64.sin());
    let (tangent, radial) = ([-(1f64.sin()), 1f64.cos()], [1f64.cos(), 1f64.sin()]);
    let b = [c + 0.1 * tangent[0], s + 0.1 * tangent[1]];
    let text = format!(
        r#"Scene(name: "t", dt: 0.01, duration: 1.0, ccd: (distance_tolerance: 1e-9), bodies: [
            (name: "arm", mesh: Triangle(a: (0.0, 0.0, 0.0), b: (1.0, 0.0, 0.0), c: (0.0, 0.0, 0.5)),
             angular_velocity: (0.0, 0.0, 5.0)),
            (name: "probe", mesh: Triangle(a: ({c:?}, {s:?}, 0.0), b: ({:?}, {:?}, -0.3), c: ({:?}, {:?}, -0.3)), fixed: true),
        ])"#,
        b[0],
        b[1],
        b[0] + 0.1 * radial[0],
        b[1] + 0.1 * radial[1]
    );
    let contact = assert_contact(&run_ron(&text), ("arm", "probe"), 0.2, 5.0 * 0.6);
    // Within the contact distance of the analytic contact point P.
    let p = nearmiss::math::Point::new(c, s, 0.0);
    assert!((contact.closest.point_b - p).norm() <= 1e-8, "{contact:?}");
}

#[test]
fn screw_motion_flag_meets_a_vertex() {
    // A planar flag in the half plane y = 0, x > 0 (radius 0.2..1, z from -1
    // up to the line z = -1 + 2.5 (x - 0.2)) screws about z: ω = 5, moving up
    // at 1. Vertex P of the probe is at radius 0.6, angle 1 rad, z = -0.3;
    // its other vertices are further round. The flag's plane reaches angle 1
    // at t = 0.2, when P sits at z = -0.5 in the flag's frame, inside it
    // (the flag spans z in [-1, 0] at radius 0.6): t = 0.2.
    let at = |r: f64, angle: f64, z: f64| format!("({:?}, {:?}, {z:?})", r * angle.cos(), r * angle.sin());
    let text = format!(
        r#"Scene(name: "t", dt: 0.01, duration: 1.0, ccd: (distance_tolerance: 1e-9), bodies: [
            (name: "flag", mesh: Triangle(a: (0.2, 0.0, -1.0), b: (1.0, 0.0, -1.0), c: (1.0, 0.0, 1.0)),
             velocity: (0.0, 0.0, 1.0), angular_velocity: (0.0, 0.0, 5.0)),
            (name: "probe", mesh: Triangle(a: {}, b: {}, c: {}), fixed: true),
        ])"#,
        at(0.6, 1.0, -0.3),
        at(1.5, 1.2, -0.3),
        at(1.5, 1.4, 0.0)
    );
    let contact = assert_contact(&run_ron(&text), ("flag", "probe"), 0.2, 5.0 * 0.6);
    assert!(matches!(contact.closest.feature_b, nearmiss::kernels::Feature::Vertex(0)));
}

#[test]
fn spinning_box_screwing_onto_a_plate_lands_at_gap_over_speed() {
    // Spin about the direction of travel does not move the bottom face: t = 0.7 / 2.
    let result = run_ron(
        r#"Scene(name: "t", dt: 0.05, duration: 1.0, ccd: (distance_tolerance: 1e-9), bodies: [
            (name: "plate", mesh: Box(half_extents: (3.0, 3.0, 0.1)), fixed: true),
            (name: "nut", mesh: Box(half_extents: (0.4, 0.25, 0.2)), position: (0.5, -0.2, 1.0),
             velocity: (0.0, 0.0, -2.0), angular_velocity: (0.0, 0.0, 40.0)),
        ])"#,
    );
    assert_contact(&result, ("plate", "nut"), 0.35, 2.0);
}

#[test]
fn grazing_pass_does_not_touch_and_comes_as_close_as_expected() {
    // b's bottom face passes 1e-6 over a's top face: no contact (the contact
    // distance is about 1.7e-9), closest approach exactly 1e-6.
    let gap = 1e-6;
    let text = format!(
        r#"Scene(name: "t", dt: 0.01, duration: 3.0, ccd: (distance_tolerance: 1e-9), trace: (pairs: All), bodies: [
            (name: "a", mesh: Box(half_extents: (0.5, 0.5, 0.5)), fixed: true),
            (name: "b", mesh: Box(half_extents: (0.5, 0.5, 0.5)), position: (-3.0, 0.2, {:?}), velocity: (2.0, 0.0, 0.0)),
        ])"#,
        1.0 + gap
    );
    let result = run_ron(&text);
    assert!(result.first_contact.is_none(), "{:?}", result.first_contact);
    let closest = result.trace.iter().map(|r| r.distance).fold(f64::INFINITY, f64::min);
    assert!((closest - gap).abs() <= 1e-15, "closest {closest:e}");
}

#[test]
fn thin_fast_body_does_not_tunnel() {
    // 1000 units/s, dt = 0.01: 10 units per step through a 1 mm plate. The
    // discrete samples at the step ends never see an overlap.
    let result = run_ron(
        r#"Scene(name: "t", dt: 0.01, duration: 0.05, ccd: (distance_tolerance: 1e-9), trace: (pairs: All), bodies: [
            (name: "plate", mesh: Box(half_extents: (1.0, 1.0, 0.0005)), fixed: true),
            (name: "bullet", mesh: Icosphere(radius: 0.01, subdivisions: 2), position: (0.0, 0.0, 25.0),
             velocity: (0.0, 0.0, -1000.0)),
        ])"#,
    );
    assert!(result.trace.iter().filter(|r| r.step > 0 && r.time < 0.024).all(|r| r.distance > 1.0));
    assert_contact(&result, ("plate", "bullet"), 24.9895 / 1000.0, 1000.0);
}

#[test]
fn meshes_of_very_different_sizes() {
    // A grain (icosphere of radius 1e-3, a vertex exactly at its -x tip)
    // against a wall 20 units wide: tip at 5 - 1e-3, wall face at 1.
    let result = run_ron(
        r#"Scene(name: "t", dt: 0.01, duration: 2.0, ccd: (distance_tolerance: 1e-9), bodies: [
            (name: "wall", mesh: Box(half_extents: (1.0, 10.0, 10.0)), fixed: true),
            (name: "grain", mesh: Icosphere(radius: 1e-3, subdivisions: 3), position: (5.0, 3.0, -2.0),
             velocity: (-4.0, 0.0, 0.0), angular_velocity: (30.0, 0.0, 0.0)),
        ])"#,
    );
    assert_contact(&result, ("wall", "grain"), (4.0 - 1e-3) / 4.0, 4.0);
}

#[test]
fn tumbling_icospheres_meet_between_their_inscribed_and_circumscribed_spheres() {
    // With spins about arbitrary axes the contact time has no closed form,
    // but the surface lies between the inscribed sphere (radius r_in, the
    // nearest face plane) and the circumscribed one (R): the centres close at
    // speed 2, so t lies in [(4 - 2R) / 2, (4 - 2 r_in) / 2].
    let mesh = nearmiss::mesh::icosphere(1.0, 2).unwrap();
    let r_in = (0..mesh.triangles().len())
        .map(|i| {
            let [a, b, c] = mesh.triangle(i);
            let n = (b - a).cross(&(c - a)).normalize();
            n.dot(&a.coords).abs()
        })
        .fold(f64::INFINITY, f64::min);
    let mut rng = nearmiss::samples::Rng::new(3);
    for _ in 0..10 {
        let mut w = || {
            format!("({:?}, {:?}, {:?})", rng.range(-9.0, 9.0), rng.range(-9.0, 9.0), rng.range(-9.0, 9.0))
        };
        let text = format!(
            r#"Scene(name: "t", dt: 0.01, duration: 2.0, ccd: (distance_tolerance: 1e-9), bodies: [
                (name: "a", mesh: Icosphere(radius: 1.0, subdivisions: 2), position: (-2.0, 0.0, 0.0),
                 velocity: (1.0, 0.0, 0.0), angular_velocity: {}),
                (name: "b", mesh: Icosphere(radius: 1.0, subdivisions: 2), position: (2.0, 0.0, 0.0),
                 velocity: (-1.0, 0.0, 0.0), angular_velocity: {}),
            ])"#,
            w(),
            w()
        );
        let contact = run_ron(&text).first_contact.expect("the spheres must meet");
        assert!(contact.time >= 1.0 - contact.contact_distance / 2.0 - 1e-12, "{}", contact.time);
        assert!(contact.time <= 2.0 - r_in, "{} later than {}", contact.time, 2.0 - r_in);
    }
}

#[test]
fn record_mode_reports_each_plate_once() {
    // A cube (half 0.1) flies through two thin plates (top faces at z = 0
    // and z = -1, 2 mm thick) at speed 10 from bottom z = 0.5:
    // contacts at 0.05 and 0.15 - 0.002 / 10 ... the second plate's top face
    // is at -1 + 0.001: t = (0.5 + 1 - 0.001) / 10 = 0.1499.
    let result = run_ron(
        r#"Scene(name: "t", dt: 0.001, duration: 0.3, on_contact: Record, ccd: (distance_tolerance: 1e-9), bodies: [
            (name: "upper", mesh: Box(half_extents: (1.0, 1.0, 0.001)), position: (0.0, 0.0, -0.001), fixed: true),
            (name: "lower", mesh: Box(half_extents: (1.0, 1.0, 0.001)), position: (0.0, 0.0, -1.0), fixed: true),
            (name: "cube", mesh: Box(half_extents: (0.1, 0.1, 0.1)), position: (0.0, 0.0, 0.6), velocity: (0.0, 0.0, -10.0)),
        ])"#,
    );
    assert_eq!(result.contacts.len(), 2, "{:?}", result.contacts);
    let upper = Contact { ..result.contacts[0].clone() };
    assert_eq!(result.bodies[upper.body_a], "upper");
    assert!(upper.time <= 0.05 && 0.05 - upper.time <= 1e-9);
    let lower = &result.contacts[1];
    assert_eq!(result.bodies[lower.body_a], "lower");
    assert!(lower.time <= 0.1499 * (1.0 + 1e-15) && 0.1499 - lower.time <= 1e-9, "{}", lower.time);
}

/// Bodies read from mesh files (issue 46): the moving box of
/// [`pure_translation_hits_at_gap_over_speed_whatever_the_step`] written as
/// a binary STL and as an ASCII PLY, given a density (which needs the STL's
/// corners welded into a closed surface), hits at the same analytic time.
#[test]
fn bodies_from_stl_and_ply_files_hit_at_the_analytic_time() {
    let unit = nearmiss::mesh::box_mesh(&nearmiss::math::Vector::new(0.3, 0.2, 0.4)).unwrap();
    let corner = |v: u32| unit.vertices()[v as usize].coords.map(|c| c as f32);
    let mut stl = vec![b' '; 80];
    stl.extend_from_slice(&(unit.triangles().len() as u32).to_le_bytes());
    for t in unit.triangles() {
        stl.extend_from_slice(&[0; 12]);
        for &v in t {
            corner(v).iter().for_each(|c| stl.extend(c.to_le_bytes()));
        }
        stl.extend_from_slice(&[0, 0]);
    }
    let mut ply = format!(
        "ply\nformat ascii 1.0\nelement vertex {}\nproperty double x\nproperty double y\nproperty double z\nelement face {}\nproperty list uchar uint vertex_indices\nend_header\n",
        unit.vertices().len(),
        unit.triangles().len()
    );
    unit.vertices().iter().for_each(|p| ply += &format!("{} {} {}\n", p.x, p.y, p.z));
    unit.triangles().iter().for_each(|[a, b, c]| ply += &format!("3 {a} {b} {c}\n"));
    let folder = std::env::temp_dir().join(format!("nearmiss-scene-files-{}", std::process::id()));
    std::fs::create_dir_all(&folder).unwrap();
    std::fs::write(folder.join("b.stl"), stl).unwrap();
    std::fs::write(folder.join("b.ply"), ply).unwrap();
    // STL holds f32: the box's face at x = -(0.3 as f32), nearer than 0.3
    // by 1.2e-8, so the contact is that over the speed sooner.
    let stl_time = (2.0 - 0.5 - f64::from(0.3f32)) / 3.0;
    for (file, expected) in [("b.stl", stl_time), ("b.ply", 0.4)] {
        let text = r#"Scene(name: "t", dt: 0.013, duration: 1.0, ccd: (distance_tolerance: 1e-9), bodies: [
            (name: "a", mesh: Box(half_extents: (0.5, 0.5, 0.5)), fixed: true),
            (name: "b", mesh: File(path: "FILE"), density: 1000.0,
             position: (2.0, 0.1, 0.05), velocity: (-3.0, 0.0, 0.0)),
        ])"#
        .replace("FILE", file);
        let path = folder.join("scene.ron");
        std::fs::write(&path, text).unwrap();
        let scene = Scene::load(&path).unwrap_or_else(|e| panic!("{file}: {e}"));
        assert_contact(&run(&scene), ("a", "b"), expected, 3.0);
    }
}

/// The root of the increasing `f` on `[low, high]` by bisection (to the
/// last bit).
fn root(f: impl Fn(f64) -> f64, (mut low, mut high): (f64, f64)) -> f64 {
    for _ in 0..200 {
        let mid = 0.5 * (low + high);
        if f(mid) < 0.0 {
            low = mid;
        } else {
            high = mid;
        }
    }
    low
}

/// A rod 2 × 0.1 × 0.1 hinged at its end (`pivot`), its joint at the
/// origin, turning about z at 1 rad/s: its far corner (2, 0.05) reaches a
/// slab whose face is the plane y = 1 when `2 sin θ + 0.05 cos θ = 1`.
/// Turned about its centre instead, it would reach the slab only at
/// `sin θ + 0.05 cos θ = 1` (about 1.52 rad).
#[test]
fn a_rod_hinged_at_its_end_swings_into_a_slab() {
    let result = run_ron(
        r#"Scene(name: "hinge", dt: 0.01, duration: 1.0, ccd: (distance_tolerance: 1e-9),
        bodies: [
            (name: "slab", mesh: Box(half_extents: (2.0, 0.5, 1.0)), position: (1.5, 1.5, 0.0), fixed: true),
            (name: "rod", mesh: Box(half_extents: (1.0, 0.05, 0.05)), position: (1.0, 0.0, 0.0),
             pivot: (-1.0, 0.0, 0.0), angular_velocity: (0.0, 0.0, 1.0), kinematic: true),
        ])"#,
    );
    let theta = root(|t| 2.0 * t.sin() + 0.05 * t.cos() - 1.0, (0.0, 1.0));
    // The corner's speed across the slab's face: 2.0006 cos(θ + φ) ≥ 1.7.
    let contact = assert_contact(&result, ("slab", "rod"), theta, 1.7);
    assert!((contact.closest.point_a.y - 1.0).abs() < 1e-9);
}

/// A unit cube with a path: along +x to (2, 0, 0) over [0, 1], then to
/// (2, 2, 0) over [1, 2] turning a quarter about z. A wall across x = 3.5
/// (where it would go on along x) is never met; one across y = 1.5 is met
/// in the second segment, when `2 (t − 1) + (cos φ + sin φ) / 2 = 1.5`,
/// `φ = π/2 (t − 1)`.
#[test]
fn a_kinematic_body_follows_its_keyframes() {
    let result = run_ron(
        r#"Scene(name: "path", dt: 0.01, duration: 3.0, ccd: (distance_tolerance: 1e-9),
        bodies: [
            (name: "ahead", mesh: Box(half_extents: (0.5, 3.0, 1.0)), position: (4.0, 0.0, 0.0), fixed: true),
            (name: "above", mesh: Box(half_extents: (1.0, 0.5, 1.0)), position: (2.0, 2.0, 0.0), fixed: true),
            (name: "cube", mesh: Box(half_extents: (0.5, 0.5, 0.5)), kinematic: true, path: [
                (time: 1.0, position: (2.0, 0.0, 0.0)),
                (time: 2.0, position: (2.0, 2.0, 0.0), orientation: AxisAngle(axis: (0.0, 0.0, 1.0), degrees: 90.0)),
            ]),
        ])"#,
    );
    let quarter = std::f64::consts::FRAC_PI_2;
    let reach = |t: f64| 2.0 * (t - 1.0) + 0.5 * ((quarter * (t - 1.0)).cos() + (quarter * (t - 1.0)).sin());
    let time = root(|t| reach(t) - 1.5, (1.0, 2.0));
    // The lowest face of "above" closes at 2 m/s plus the corner's turn.
    assert_contact(&result, ("above", "cube"), time, 2.0);
}

/// Before its first keyframe's time the body moves on the first segment,
/// and after the last it stays: a cube that reaches (1, 0, 0) at t = 0.5
/// and rests there never meets a wall whose face is at x = 1.6.
#[test]
fn a_path_body_rests_after_its_last_keyframe() {
    let result = run_ron(
        r#"Scene(name: "rest", dt: 0.01, duration: 2.0,
        bodies: [
            (name: "wall", mesh: Box(half_extents: (0.5, 2.0, 2.0)), position: (2.1, 0.0, 0.0), fixed: true),
            (name: "cube", mesh: Box(half_extents: (0.5, 0.5, 0.5)), kinematic: true,
             path: [(time: 0.5, position: (1.0, 0.0, 0.0))]),
        ])"#,
    );
    assert!(result.first_contact.is_none());
}

/// A step in which one body diverges moves no body: the run ends at that
/// step's start, every body where the step found it (a drifting body
/// listed before the diverging one included: it is at `x0 + v t` of the
/// failing step's start, not a step further), and each as the same scene
/// run only up to that start leaves it. Every body falls (integrated): the
/// stage made and committed the steps of the two listed first before it
/// met the failing one, and undid them.
#[test]
fn a_diverging_step_moves_no_body() {
    // Explicit Euler on an undamped spring (ω dt = 1) doubles the energy
    // every step.
    let scene = |duration: &str| {
        format!(
            r#"Scene(name: "t", dt: 0.01, duration: {duration}, integrator: ExplicitEuler, gravity: (0.0, 0.0, -1.0),
            springs: [(body: "bob", anchor: (0.0, 0.0, 0.0), stiffness: 1e4)],
            bodies: [
                (name: "drifter", mesh: Box(half_extents: (0.1, 0.1, 0.1)), position: (0.0, 50.0, 0.0),
                 velocity: (1.0, 0.0, 0.0), mass: 1.0),
                (name: "tumbler", mesh: Box(half_extents: (0.1, 0.2, 0.3)), position: (0.0, -50.0, 0.0),
                 velocity: (0.0, 0.0, 1.0), angular_velocity: (0.0, 1.0, 2.0), mass: 1.0),
                (name: "bob", mesh: Box(half_extents: (0.05, 0.05, 0.05)), position: (1.0, 0.0, 0.0), mass: 1.0),
            ])"#
        )
    };
    let result = run_ron(&scene("1.0"));
    let nearmiss::run::Termination::Diverged { body, step, .. } = result.termination else {
        panic!("the spring should diverge: {:?}", result.termination)
    };
    assert_eq!((body, result.steps), (2, step + 1));
    assert!(step >= 1, "it should diverge after a step or more, not at once");
    let start = step as f64 * 0.01;
    assert_eq!(result.end_time, start, "the run ends at the failing step's start");
    let drifter = result.final_states[0].position;
    assert!(
        (drifter.x - start).abs() <= 1e-12 && drifter.y == 50.0,
        "{drifter} at the failing step's start {start}"
    );
    // The same scene run for `step` steps ends where the failing step began:
    // the same velocities (each a body's state), the same poses (a state
    // there, a motion's end here) to a few ulps.
    let shorter = run_ron(&scene(&format!("{start:?}")));
    assert_eq!((shorter.steps, shorter.end_time), (step, start));
    for (diverged, stopped) in result.final_states.iter().zip(&shorter.final_states) {
        assert_eq!(
            (diverged.velocity, diverged.angular_velocity),
            (stopped.velocity, stopped.angular_velocity)
        );
        assert!((diverged.position - stopped.position).norm() <= 1e-12, "{diverged:?} against {stopped:?}");
        assert!(
            diverged.orientation.angle_to(&stopped.orientation) <= 1e-12,
            "{diverged:?} against {stopped:?}"
        );
    }
}

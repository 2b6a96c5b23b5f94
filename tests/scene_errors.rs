//! Bad scenes: `nearmiss run` exits 2 with a message naming the file and
//! line/column or the field, and writes nothing.

use std::path::{Path, PathBuf};
use std::process::Command;

/// A fresh folder under the system's temporary folder.
fn workspace(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("nearmiss-scene-errors-{}-{name}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

const GOOD_BODIES: &str = r#"bodies: [
    (name: "a", mesh: Box(half_extents: (0.5, 0.5, 0.5)), fixed: true),
    (name: "b", mesh: Box(half_extents: (0.5, 0.5, 0.5)), position: (2.0, 0.0, 0.0), velocity: (-1.0, 0.0, 0.0)),
]"#;

/// Runs `nearmiss run` on `text` saved as `scene.ron`; asserts exit code 2,
/// that stderr contains every piece of `expected`, and that no output was
/// written.
fn assert_rejected(name: &str, text: &str, expected: &[&str]) {
    let dir = workspace(name);
    let scene = dir.join("scene.ron");
    std::fs::write(&scene, text).unwrap();
    std::fs::write(dir.join("broken.obj"), "v 0 0 0\nv 1 0 0\nv 0 1 oops\nf 1 2 3\n").unwrap();
    let out = dir.join("out");
    let output = Command::new(env!("CARGO_BIN_EXE_nearmiss"))
        .args(["run", scene.to_str().unwrap(), "--out", out.to_str().unwrap()])
        .output()
        .unwrap();
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert_eq!(output.status.code(), Some(2), "{name}: {stderr}");
    for piece in expected {
        assert!(stderr.contains(piece), "{name}: `{piece}` not in: {stderr}");
    }
    assert!(!Path::new(&out).exists(), "{name}: output was written");
    let _ = std::fs::remove_dir_all(&dir);
}

fn scene(fields: &str) -> String {
    format!("Scene(name: \"bad\", dt: 0.01, duration: 1.0, {fields})")
}

#[test]
fn malformed_ron_names_line_and_column() {
    assert_rejected("malformed", "Scene(name: \"bad\",\n  dt: 0.01\n  duration: 1.0)", &["scene.ron:3:3:"]);
}

#[test]
fn unknown_field_names_line_column_and_field() {
    let text = format!(
        "Scene(name: \"bad\", dt: 0.01, duration: 1.0,\n  gravty: (0.0, 0.0, -9.81),\n  {GOOD_BODIES})"
    );
    assert_rejected("unknown", &text, &["scene.ron:2:", "gravty"]);
}

#[test]
fn wrong_type_names_line_and_column() {
    let text = format!("Scene(name: \"bad\",\n dt: \"fast\", duration: 1.0, {GOOD_BODIES})");
    assert_rejected("type", &text, &["scene.ron:2:5:", "Expected float"]);
}

#[test]
fn nan_and_infinite_numbers_name_the_field() {
    let text = scene(&GOOD_BODIES.replace("(2.0, 0.0, 0.0)", "(NaN, 0.0, 0.0)"));
    assert_rejected("nan", &text, &["`bodies[1].position.x`", "finite"]);
    let text = scene(&GOOD_BODIES.replace("(-1.0, 0.0, 0.0)", "(-inf, 0.0, 0.0)"));
    assert_rejected("inf", &text, &["`bodies[1].velocity.x`", "finite"]);
}

#[test]
fn non_positive_step_and_zero_duration() {
    assert_rejected(
        "dt",
        &format!("Scene(name: \"bad\", dt: 0.0, duration: 1.0, {GOOD_BODIES})"),
        &["`dt`", "positive"],
    );
    assert_rejected("dt-neg", &format!("Scene(name: \"bad\", dt: -0.1, steps: 3, {GOOD_BODIES})"), &["`dt`"]);
    assert_rejected(
        "duration",
        &format!("Scene(name: \"bad\", dt: 0.1, duration: 0.0, {GOOD_BODIES})"),
        &["`duration`"],
    );
    assert_rejected(
        "steps",
        &format!("Scene(name: \"bad\", dt: 0.1, steps: 0, {GOOD_BODIES})"),
        &["`steps`"],
    );
}

#[test]
fn zero_size_and_degenerate_meshes() {
    let text = scene(&GOOD_BODIES.replacen("(0.5, 0.5, 0.5)", "(0.5, 0.0, 0.5)", 1));
    assert_rejected("zero-size", &text, &["`bodies[0].mesh.half_extents`", "positive"]);
    let text = scene(
        r#"bodies: [(name: "a", mesh: Triangle(a: (0.0, 0.0, 0.0), b: (1.0, 1.0, 1.0), c: (2.0, 2.0, 2.0)))]"#,
    );
    assert_rejected("degenerate", &text, &["`bodies[0].mesh`", "degenerate"]);
    let text = scene(&GOOD_BODIES.replacen("fixed: true", "scale: 0.0, fixed: true", 1));
    assert_rejected("scale", &text, &["`bodies[0].scale`"]);
}

#[test]
fn missing_and_malformed_obj_files() {
    let text = scene(r#"bodies: [(name: "a", mesh: Obj(path: "nowhere.obj"))]"#);
    assert_rejected("missing-obj", &text, &["`bodies[0].mesh`", "nowhere.obj", "cannot read"]);
    let text = scene(r#"bodies: [(name: "a", mesh: Obj(path: "broken.obj"))]"#);
    assert_rejected("broken-obj", &text, &["`bodies[0].mesh`", "broken.obj:3:7", "oops"]);
}

#[test]
fn quaternion_that_cannot_be_normalised() {
    let text = scene(&GOOD_BODIES.replacen(
        "fixed: true",
        "orientation: Quaternion(w: 0.0, x: 0.0, y: 0.0, z: 0.0), fixed: true",
        1,
    ));
    assert_rejected("quaternion", &text, &["`bodies[0].orientation`", "normalised"]);
}

#[test]
fn unresolved_names_and_inconsistent_bodies() {
    let text =
        scene(&format!("{GOOD_BODIES}, expect: Contact(time: 1.0, tolerance: 0.1, bodies: (\"a\", \"c\"))"));
    assert_rejected("expect-name", &text, &["`expect.bodies`", "`c`"]);
    let text =
        scene(&format!("{GOOD_BODIES}, springs: [(body: \"b\", anchor: (0.0, 0.0, 0.0), stiffness: 10.0)]"));
    assert_rejected("spring-mass", &text, &["`springs[0].body`", "mass"]);
    let text = scene(&GOOD_BODIES.replace("\"b\"", "\"a\""));
    assert_rejected("duplicate", &text, &["`bodies[1].name`", "already"]);
}

#[test]
fn missing_scene_file() {
    let output =
        Command::new(env!("CARGO_BIN_EXE_nearmiss")).args(["check", "no/such/scene.ron"]).output().unwrap();
    assert_eq!(output.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&output.stderr).contains("no/such/scene.ron"));
}

#[test]
fn bounce_needs_a_restitution_in_range_and_pushable_bodies_with_mass() {
    assert_rejected(
        "restitution",
        &scene(&format!("on_contact: Bounce(restitution: 1.5), {GOOD_BODIES}")),
        &["on_contact.restitution", "[0, 1]"],
    );
    // Body `b` moves and can be pushed but has no mass or inertia.
    assert_rejected(
        "bounce_mass",
        &scene(&format!("on_contact: Bounce(restitution: 0.5), {GOOD_BODIES}")),
        &["bodies[1].density", "mass and an inertia"],
    );
}

#[test]
fn open_or_doubled_mesh_with_a_density_names_the_edge() {
    // A tetrahedron missing a face, and one with a face given twice: no
    // volume to take a mass from. (Mass and inertia would be wrong.)
    let faces = ["f 1 3 2\nf 1 2 4\nf 1 4 3\n", "f 1 3 2\nf 1 2 4\nf 1 4 3\nf 2 3 4\nf 2 3 4\n"];
    let expected =
        [["open edge", "between vertices 3 and 2"], ["more than two faces", "from vertex 2 to vertex 3"]];
    for (k, (faces, [what, edge])) in faces.iter().zip(expected).enumerate() {
        let dir = workspace(&format!("open-mesh-{k}"));
        std::fs::write(dir.join("tetra.obj"), format!("v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\n{faces}"))
            .unwrap();
        let obj = dir.join("tetra.obj");
        let text = scene(&format!(
            r#"bodies: [(name: "a", mesh: Obj(path: {:?}), density: 1.0)]"#,
            obj.to_str().unwrap()
        ));
        assert_rejected(&format!("open-{k}"), &text, &["`bodies[0].density`", "closed", what, edge]);
        let _ = std::fs::remove_dir_all(&dir);
    }
}

#[test]
fn subnormal_or_huge_mass_and_inertia_are_rejected_at_load() {
    // They loaded, then "diverged at step 0" with advice to lower dt.
    let body = |extra: &str| {
        scene(&format!(
            r#"gravity: (0.0, 0.0, -9.81), bodies: [(name: "a", mesh: Box(half_extents: (0.5, 0.5, 0.5)), {extra})]"#
        ))
    };
    assert_rejected("subnormal-mass", &body("mass: 1e-310"), &["`bodies[0].mass`", "1e-310", "normal"]);
    assert_rejected(
        "subnormal-inertia",
        &body("mass: 1.0, inertia: (1e-315, 1e-315, 1e-315)"),
        &["`bodies[0].inertia.x`", "normal"],
    );
    assert_rejected("huge-mass", &body("mass: 1e308"), &["`bodies[0].mass`", "between"]);
    assert_rejected("subnormal-density", &body("density: 1e-320"), &["`bodies[0].density`"]);
}

#[test]
fn fixed_and_kinematic_together_is_a_contradiction() {
    let text = scene(&GOOD_BODIES.replacen("fixed: true", "fixed: true, kinematic: true", 1));
    assert_rejected("fixed-kinematic", &text, &["`bodies[0].kinematic`", "not both"]);
}

//! Issue 29's symptoms as a user met them: `nearmiss run` printed nothing
//! and exited 0 when the scene's expectation failed; an undecided run said
//! "no contact" before its error; `run --help` left out exit code 3; two
//! scene files of one name overwrote each other's outputs; `test --record`
//! put the comma into a trailing comment, and when the rewrite failed it
//! said so in a debug dump, skipped the scene and exited 0.

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

fn workspace(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("nearmiss-exit-codes-{}-{name}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

fn nearmiss(args: &[&str], dir: &Path) -> Output {
    Command::new(env!("CARGO_BIN_EXE_nearmiss")).args(args).current_dir(dir).output().unwrap()
}

/// A box falling at speed 1 onto a fixed one 1 below: contact at t = 1
/// (the CCD reports it at most its contact distance early).
fn falling(name: &str, tail: &str) -> String {
    format!(
        r#"Scene(
    name: "{name}",
    dt: 0.01,
    duration: 2.0,
    bodies: [
        (name: "floor", mesh: Box(half_extents: (1.0, 1.0, 0.5)), position: (0.0, 0.0, -0.5), fixed: true),
        (name: "box", mesh: Box(half_extents: (0.5, 0.5, 0.5)), position: (0.0, 0.0, 1.5), velocity: (0.0, 0.0, -1.0)),
    ]{tail}
)
"#
    )
}

#[test]
fn a_missed_expectation_is_printed_and_exits_1() {
    let dir = workspace("missed");
    let met = r#", expect: Contact(time: 1.0, tolerance: 1e-6, bodies: ("floor", "box"))"#;
    let missed = r#", expect: Contact(time: 0.5, tolerance: 1e-6, bodies: ("floor", "box"))"#;
    std::fs::write(dir.join("met.ron"), falling("met", met)).unwrap();
    std::fs::write(dir.join("missed.ron"), falling("missed", missed)).unwrap();

    let output = nearmiss(&["run", "met.ron", "-o", "out"], &dir);
    let stdout = String::from_utf8_lossy(&output.stdout);
    assert_eq!(output.status.code(), Some(0), "{stdout}");
    assert!(stdout.contains("expectation met: contact floor / box at t = 1 ± 1e-6"), "{stdout}");

    let output = nearmiss(&["run", "missed.ron", "-o", "out"], &dir);
    let (stdout, stderr) = (String::from_utf8_lossy(&output.stdout), String::from_utf8_lossy(&output.stderr));
    assert_eq!(output.status.code(), Some(1), "{stdout}{stderr}");
    assert!(
        stdout.contains("expectation NOT met: expected contact floor / box at t = 0.5 ± 1e-6; obtained contact floor / box at t = "),
        "{stdout}"
    );
    assert!(stderr.contains("missed.ron: the run did not meet the scene's expectation"), "{stderr}");
    // The outputs are written all the same: they show what happened.
    assert!(dir.join("out/missed/summary.json").is_file());
    let _ = std::fs::remove_dir_all(&dir);
}

/// A tolerance tighter than the contact contract allows: the box falling
/// at 1 with `ccd.distance_tolerance` 1e-3 may be reported up to its
/// contact distance (1e-3 of the smaller radius, √3/2) over the closing
/// speed early; an expectation of t = 1 ± 1e-12 fails with a hint that
/// names the field and the earliness allowed, and one whose own answer is
/// wrong (t = 0.5) gets none.
#[test]
fn a_tolerance_tighter_than_the_contract_gets_a_hint_naming_the_field() {
    let dir = workspace("hint");
    let ccd = ", ccd: (distance_tolerance: 1e-3)";
    let tight = format!(r#"{ccd}, expect: Contact(time: 1.0, tolerance: 1e-12, bodies: ("floor", "box"))"#);
    let wrong = format!(r#"{ccd}, expect: Contact(time: 0.5, tolerance: 1e-12, bodies: ("floor", "box"))"#);
    std::fs::write(dir.join("tight.ron"), falling("tight", &tight)).unwrap();
    std::fs::write(dir.join("wrong.ron"), falling("wrong", &wrong)).unwrap();

    let output = nearmiss(&["run", "tight.ron", "-o", "out"], &dir);
    let stdout = String::from_utf8_lossy(&output.stdout);
    assert_eq!(output.status.code(), Some(1), "{stdout}");
    let hint =
        stdout.lines().find(|l| l.starts_with("hint: ")).unwrap_or_else(|| panic!("no hint: {stdout}"));
    assert!(hint.contains("within what the CCD's contract allows here"), "{hint}");
    assert!(hint.contains("`ccd.distance_tolerance`"), "{hint}");
    // The contact distance is 1e-3 × √3/2 ≈ 8.66e-4, closing at 1.
    assert!(hint.contains("is 8.66e-4"), "{hint}");
    let output = nearmiss(&["test", "tight.ron"], &dir);
    let stdout = String::from_utf8_lossy(&output.stdout);
    assert!(stdout.contains("\n  hint: the contact came "), "{stdout}");

    let output = nearmiss(&["run", "wrong.ron", "-o", "out"], &dir);
    let stdout = String::from_utf8_lossy(&output.stdout);
    assert_eq!(output.status.code(), Some(1), "{stdout}");
    assert!(!stdout.contains("hint:"), "{stdout}");
    let _ = std::fs::remove_dir_all(&dir);
}

/// `spin.ron` in `dir`: a torus spinning at 60 rad/s around a bar through
/// its hole, with too few iterations for the CCD to decide (as
/// `undecided_is_not_contact.rs`).
fn write_undecidable(dir: &Path) {
    std::fs::write(
        dir.join("spin.ron"),
        r#"Scene(name: "spin", dt: 0.01, duration: 0.1, ccd: (max_iterations: 5), bodies: [
            (name: "bar", mesh: Box(half_extents: (0.55, 0.55, 1.0)), fixed: true),
            (name: "ring", mesh: Torus(major: 1.0, minor: 0.2), angular_velocity: (0.0, 0.0, 60.0), kinematic: true),
        ])"#,
    )
    .unwrap();
}

#[test]
fn an_undecided_run_says_so_and_not_no_contact() {
    let dir = workspace("undecided");
    write_undecidable(&dir);
    let output = nearmiss(&["run", "spin.ron", "-o", "out"], &dir);
    let (stdout, stderr) = (String::from_utf8_lossy(&output.stdout), String::from_utf8_lossy(&output.stderr));
    assert_eq!(output.status.code(), Some(3), "{stdout}{stderr}");
    assert!(!stdout.contains("no contact"), "{stdout}");
    assert!(stderr.contains("error: undecided at step 0: the CCD of `bar` / `ring`"), "{stderr}");
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn every_command_help_gives_every_exit_code() {
    for command in [&["--help"][..], &["run", "--help"], &["test", "--help"], &["check", "--help"]] {
        let output = Command::new(env!("CARGO_BIN_EXE_nearmiss")).args(command).output().unwrap();
        let stdout = String::from_utf8_lossy(&output.stdout);
        assert_eq!(output.status.code(), Some(0));
        for code in ["  0  success", "  1  a check failed", "  2  bad input", "  3  undecided"] {
            assert!(stdout.contains(code), "{command:?} lacks `{code}`:\n{stdout}");
        }
    }
}

#[test]
fn two_scenes_of_one_name_are_refused_before_anything_runs() {
    let dir = workspace("same-name");
    std::fs::write(dir.join("a.ron"), falling("same", "")).unwrap();
    std::fs::write(dir.join("b.ron"), falling("same", "")).unwrap();
    let output = nearmiss(&["run", "a.ron", "b.ron", "-o", "out"], &dir);
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert_eq!(output.status.code(), Some(2), "{stderr}");
    assert!(stderr.contains("a.ron and b.ron are both named `same`"), "{stderr}");
    assert!(!dir.join("out").exists(), "nothing is written");
    // Run one after the other, the second says whose outputs it replaced.
    assert_eq!(nearmiss(&["run", "a.ron", "-o", "out"], &dir).status.code(), Some(0));
    let output = nearmiss(&["run", "b.ron", "-o", "out"], &dir);
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert!(
        stderr.contains("held the outputs of a.ron, another scene of the same name: replaced"),
        "{stderr}"
    );
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn record_puts_the_comma_after_the_value_and_the_file_loads_back() {
    let dir = workspace("record");
    // The last field has no trailing comma, and a comment follows it.
    let text = falling("record", "").replace("    ]\n)", "    ] // the gap is < 3e-9.\n)");
    std::fs::write(dir.join("r.ron"), &text).unwrap();
    let output = nearmiss(&["test", "--record", "r.ron"], &dir);
    let stdout = String::from_utf8_lossy(&output.stdout);
    assert_eq!(output.status.code(), Some(0), "{stdout}{}", String::from_utf8_lossy(&output.stderr));
    assert!(stdout.contains("recorded r.ron: contact floor / box at t = "), "{stdout}");
    assert!(stdout.contains("1 passed, 0 failed, 0 skipped"), "{stdout}");
    let recorded = std::fs::read_to_string(dir.join("r.ron")).unwrap();
    assert!(recorded.contains("    ], // the gap is < 3e-9.\n    // expect: recorded"), "{recorded}");
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn a_scene_that_cannot_be_recorded_fails_the_command() {
    let dir = workspace("record-fails");
    // The run is undecided: there is no answer to pin.
    write_undecidable(&dir);
    let before = std::fs::read_to_string(dir.join("spin.ron")).unwrap();
    let output = nearmiss(&["test", "--record", "spin.ron"], &dir);
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert_eq!(output.status.code(), Some(1), "{stderr}");
    assert!(stderr.contains("spin.ron: not recorded: undecided"), "{stderr}");
    assert!(stderr.contains("1 scene not recorded"), "{stderr}");
    assert!(!stderr.contains("Err("), "{stderr}");
    assert_eq!(std::fs::read_to_string(dir.join("spin.ron")).unwrap(), before);
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn pictures_of_contacts_the_run_did_not_have_are_named() {
    let dir = workspace("pictures");
    let text = falling("pictures", "")
        .replace("    bodies:", "    trace: (pairs: All),\n    plot: (contacts: [1, 5, 9]),\n    bodies:");
    std::fs::write(dir.join("p.ron"), text).unwrap();
    let output = nearmiss(&["run", "p.ron", "-o", "out"], &dir);
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert_eq!(output.status.code(), Some(0), "{stderr}");
    let note =
        "`plot.contacts` asked for pictures of contacts 5, 9, but the run had 1 contact: no picture of those";
    assert!(stderr.contains(&format!("warning: {note}")), "{stderr}");
    let page = std::fs::read_to_string(dir.join("out/pictures/report.md")).unwrap();
    assert!(page.contains(note), "{page}");
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn meshes_overlapping_at_the_start_are_said_to_with_their_depth() {
    let dir = workspace("overlap");
    // The box (half extent 0.5) starts at z = 0.25: its bottom 0.25 deep in
    // the floor (top at 0). Lifting it 0.25 separates them; its four sides
    // cross the floor's top along a unit square, 4 long.
    let deep = falling("overlap", "").replace("(0.0, 0.0, 1.5)", "(0.0, 0.0, 0.25)");
    std::fs::write(dir.join("o.ron"), &deep).unwrap();
    let output = nearmiss(&["run", "o.ron", "-o", "out"], &dir);
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert_eq!(output.status.code(), Some(0), "{stderr}");
    assert!(
        stderr.contains(
            "warning: at t = 0 \"floor\" and \"box\" overlap by 0.25 (the shortest move that separates them: \"box\" by 0.25 along (0, 0, 1)); surfaces crossing at "
        ),
        "{stderr}"
    );
    assert!(stderr.contains("along a curve 4 long. The run starts overlapped"), "{stderr}");
    assert!(!stderr.contains("already touch"), "{stderr}");
    // summary.json says the same.
    let summary = std::fs::read_to_string(dir.join("out/overlap/summary.json")).unwrap();
    let summary: serde_json::Value = serde_json::from_str(&summary).unwrap();
    let overlap = &summary["initial_overlaps"][0];
    assert_eq!(overlap["bodies"], serde_json::json!(["floor", "box"]));
    assert_eq!(overlap["depth"], 0.25);
    assert_eq!(overlap["direction"], serde_json::json!([0.0, 0.0, 1.0]));
    assert!((overlap["curve_length"].as_f64().unwrap() - 4.0).abs() < 1e-12, "{overlap}");
    // Refused when the scene says so: exit 2, the bodies and depth named,
    // nothing written.
    let refuse = deep
        .replace("    bodies:", "    initial_overlap: Refuse,\n    bodies:")
        .replace("\"overlap\"", "\"refused\"");
    std::fs::write(dir.join("r.ron"), refuse).unwrap();
    let output = nearmiss(&["run", "r.ron", "-o", "out"], &dir);
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert_eq!(output.status.code(), Some(2), "{stderr}");
    assert!(
        stderr.contains("r.ron: `bodies[1]`: \"floor\" and \"box\" overlap by 0.25")
            && stderr.contains("at t = 0, and the scene says `initial_overlap: Refuse`: move them apart"),
        "{stderr}"
    );
    assert!(!dir.join("out/refused").exists());
    // A ring (not convex) dipped 0.1 into a slab: its local depth, a
    // bracket (the slab's big triangles bound their side by the ring's
    // half width, 0.25).
    std::fs::write(
        dir.join("ring.ron"),
        r#"Scene(name: "ring", dt: 0.01, duration: 0.1, bodies: [
            (name: "slab", mesh: Box(half_extents: (2.0, 2.0, 0.25)), fixed: true),
            (name: "ring", mesh: Torus(major: 1.0, minor: 0.25, around: 96, across: 48), position: (0.0, 0.0, 0.4), velocity: (0.0, 0.0, 1.0)),
        ])"#,
    )
    .unwrap();
    let output = nearmiss(&["run", "ring.ron", "-o", "out"], &dir);
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert!(
        stderr.contains("\"slab\" and \"ring\" overlap by at least 0.1 and at most 0.25 (the deepest place where their surfaces cross, a local depth: a mesh is not convex)"),
        "{stderr}"
    );
    // Resting on the floor (touching, not overlapping): said as touching.
    std::fs::write(dir.join("t.ron"), falling("touch", "").replace("(0.0, 0.0, 1.5)", "(0.0, 0.0, 0.5)"))
        .unwrap();
    let output = nearmiss(&["run", "t.ron", "-o", "out"], &dir);
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert!(
        stderr.contains("warning: at t = 0 these meshes already touch (distance 0): floor / box."),
        "{stderr}"
    );
    assert!(!stderr.contains("overlap by"), "{stderr}");
    // Apart at the start: no such word.
    std::fs::write(dir.join("a.ron"), falling("apart", "")).unwrap();
    let output = nearmiss(&["run", "a.ron", "-o", "out"], &dir);
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert!(!stderr.contains("already touch") && !stderr.contains("overlap"), "{stderr}");
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn a_near_miss_is_expected_like_a_contact() {
    let dir = workspace("near-miss");
    // A cube passes a fixed one 0.25 from its face (see tests/runs/near_misses.rs).
    let scene = |distance: &str| {
        format!(
            r#"Scene(name: "pass", dt: 0.01, duration: 2.0, near_misses: (within: 0.5), bodies: [
                (name: "fixed", mesh: Box(half_extents: (0.5, 0.5, 0.5)), fixed: true),
                (name: "passer", mesh: Box(half_extents: (0.5, 0.5, 0.5)), position: (-3.0, 1.25, 0.2), velocity: (3.0, 0.0, 0.0)),
            ], expect: NearMiss(bodies: ("passer", "fixed"), distance: {distance}, tolerance: 1e-6))"#
        )
    };
    std::fs::write(dir.join("met.ron"), scene("0.25")).unwrap();
    std::fs::write(dir.join("missed.ron"), scene("0.26")).unwrap();
    let output = nearmiss(&["test", "met.ron"], &dir);
    let stdout = String::from_utf8_lossy(&output.stdout);
    assert_eq!(output.status.code(), Some(0), "{stdout}");
    assert!(stdout.contains("pass met.ron: expected near miss fixed / passer: 0.25 ± 1e-6; obtained near miss fixed / passer: 0.25 at t = "), "{stdout}");
    let output = nearmiss(&["test", "missed.ron"], &dir);
    let stdout = String::from_utf8_lossy(&output.stdout);
    assert_eq!(output.status.code(), Some(1), "{stdout}");
    assert!(stdout.contains("FAIL missed.ron") && stdout.contains("error -0.01"), "{stdout}");
    let _ = std::fs::remove_dir_all(&dir);
}

/// An OBJ as exporters write them (issue 45): a cube whose top face's
/// edge is split by a T-junction, closed by a triangle of zero area, and
/// `f` lines of two vertices. The scene loads, says both counts on the
/// terminal and in summary.json, and the cube lands at t = 1 as a box does.
#[test]
fn an_obj_with_zero_area_and_short_faces_runs_and_says_so() {
    let dir = workspace("as-shipped");
    let obj = "v -0.5 -0.5 -0.5\nv 0.5 -0.5 -0.5\nv 0.5 0.5 -0.5\nv -0.5 0.5 -0.5\n\
               v -0.5 -0.5 0.5\nv 0.5 -0.5 0.5\nv 0.5 0.5 0.5\nv -0.5 0.5 0.5\nv 0 -0.5 0.5\n\
               f 1 3 2\nf 1 4 3\nf 1 2 6\nf 1 6 5\nf 2 3 7\nf 2 7 6\nf 3 4 8\nf 3 8 7\nf 4 1 5\nf 4 5 8\n\
               f 5 7 8\nf 5 9 7\nf 9 6 7\nf 5 6 9\nl 1 2\nf 1 2\nf 3 4\n";
    std::fs::write(dir.join("cube.obj"), obj).unwrap();
    let scene = falling("shipped", "").replace(
        "mesh: Box(half_extents: (0.5, 0.5, 0.5)), position",
        "mesh: Obj(path: \"cube.obj\"), position",
    );
    std::fs::write(dir.join("s.ron"), scene).unwrap();
    let output = nearmiss(&["run", "s.ron", "-o", "out"], &dir);
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert_eq!(output.status.code(), Some(0), "{stderr}");
    assert!(
        stderr.contains(
            "note: the mesh of body `box`: 1 triangle of zero area (kept: each is the segment or point it spans); 2 faces of fewer than 3 vertices in its file (dropped: a point or a line is no face)"
        ),
        "{stderr}"
    );
    let summary = std::fs::read_to_string(dir.join("out/shipped/summary.json")).unwrap();
    let summary: serde_json::Value = serde_json::from_str(&summary).unwrap();
    assert_eq!(
        summary["mesh_notes"],
        serde_json::json!([{"bodies": ["box"], "zero_area_triangles": 1, "dropped_faces": 2}])
    );
    // The box's bottom falls 1 at speed 1: contact at t = 1, reported at
    // most its contact distance early.
    let contact = &summary["first_contact"];
    let time = contact["time"].as_f64().unwrap();
    let early = contact["contact_distance"].as_f64().unwrap();
    assert!(time <= 1.0 && time >= 1.0 - early, "{contact}");
    // A plain box scene says nothing of the kind.
    std::fs::write(dir.join("p.ron"), falling("plain", "")).unwrap();
    let output = nearmiss(&["run", "p.ron", "-o", "out"], &dir);
    assert!(!String::from_utf8_lossy(&output.stderr).contains("note:"));
    let summary = std::fs::read_to_string(dir.join("out/plain/summary.json")).unwrap();
    assert!(!summary.contains("mesh_notes"));
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn check_warns_of_bodies_that_start_overlapped_as_run_does() {
    // Issue 46: `check` said `ok` for a scene `run` warned about.
    let dir = workspace("check-overlap");
    let scene = r#"Scene(
    name: "overlapped",
    dt: 0.01,
    duration: 0.1,
    bodies: [
        (name: "floor", mesh: Box(half_extents: (1.0, 1.0, 0.5)), position: (0.0, 0.0, -0.5), fixed: true),
        (name: "box", mesh: Box(half_extents: (0.5, 0.5, 0.5)), position: (0.0, 0.0, 0.3)),
    ],
)
"#;
    std::fs::write(dir.join("overlapped.ron"), scene).unwrap();
    let check = nearmiss(&["check", "overlapped.ron"], &dir);
    let run = nearmiss(&["run", "overlapped.ron"], &dir);
    let warning = |output: &Output| {
        String::from_utf8_lossy(&output.stderr)
            .lines()
            .find(|l| l.starts_with("warning: at t = 0"))
            .map(str::to_string)
    };
    assert_eq!(check.status.code(), Some(0), "{}", String::from_utf8_lossy(&check.stderr));
    assert!(String::from_utf8_lossy(&check.stdout).starts_with("ok overlapped.ron"));
    let said = warning(&check).expect("check warns");
    assert!(said.contains("floor") && said.contains("box") && said.contains("starts overlapped"), "{said}");
    assert_eq!(Some(said), warning(&run), "check and run say the same");
    let _ = std::fs::remove_dir_all(&dir);
}

//! Symptoms: a run without a trace into a folder holding an older
//! `trace.csv` and `distance.png` left them beside the new summary; `--out`
//! was checked only after the simulation; scenes that `check` accepted
//! failed at the end of `run` (a plot with nothing to draw, a name too long
//! for a file name or holding a NUL). A run's outputs appear together or not
//! at all.

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

fn workspace(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("nearmiss-output-{}-{name}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

fn nearmiss(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_nearmiss")).args(args).output().unwrap()
}

fn scene_text(name: &str, extra: &str) -> String {
    format!(
        r#"Scene(name: "{name}", dt: 0.01, duration: 0.5, {extra} bodies: [
            (name: "a", mesh: Box(half_extents: (0.5, 0.5, 0.5)), fixed: true),
            (name: "b", mesh: Box(half_extents: (0.5, 0.5, 0.5)), position: (3.0, 0.0, 0.0), velocity: (-1.0, 0.0, 0.0)),
        ])"#
    )
}

fn files(folder: &Path) -> Vec<String> {
    let mut names: Vec<String> = std::fs::read_dir(folder)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    names.sort();
    names
}

#[test]
fn a_run_replaces_the_files_of_the_last_run_and_keeps_the_rest() {
    let dir = workspace("replace");
    let (scene, out) = (dir.join("s.ron"), dir.join("out"));
    let run = |text: &str| {
        std::fs::write(&scene, text).unwrap();
        let output = nearmiss(&["run", scene.to_str().unwrap(), "--out", out.to_str().unwrap()]);
        assert!(output.status.success(), "{}", String::from_utf8_lossy(&output.stderr));
    };
    run(&scene_text("s", "trace: (pairs: All), plot: (log_y: true),"));
    let folder = out.join("s");
    let with_plot = if cfg!(feature = "plot") { vec!["distance.png"] } else { vec![] };
    let mut expected: Vec<&str> =
        ["report.md", "summary.json", "trace.csv"].into_iter().chain(with_plot).collect();
    expected.sort();
    assert_eq!(files(&folder), expected);
    // Something else of the scene's (a sweep's table) lives beside them.
    std::fs::write(folder.join("sweep.csv"), "kept").unwrap();
    run(&scene_text("s", ""));
    assert_eq!(files(&folder), ["report.md", "summary.json", "sweep.csv"]);
    assert_eq!(std::fs::read_to_string(folder.join("sweep.csv")).unwrap(), "kept");
    // No staging folder is left behind.
    assert_eq!(files(&out), ["s"]);
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn a_killed_runs_staging_folder_is_removed_by_the_next_run() {
    let dir = workspace("stale");
    let (scene, out) = (dir.join("s.ron"), dir.join("out"));
    std::fs::write(&scene, scene_text("s", "")).unwrap();
    // What a process that no longer exists left mid-write (pid beyond any
    // pid_max, so never alive).
    std::fs::create_dir_all(out.join(".s.4294967295.tmp")).unwrap();
    std::fs::write(out.join(".s.4294967295.tmp/summary.json"), "{").unwrap();
    let output = nearmiss(&["run", scene.to_str().unwrap(), "--out", out.to_str().unwrap()]);
    assert!(output.status.success());
    assert_eq!(files(&out), ["s"]);
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn an_unwritable_out_is_refused_before_the_run() {
    let dir = workspace("out");
    let scene = dir.join("s.ron");
    // A long run: refusing before it is the point (it would take minutes).
    std::fs::write(&scene, scene_text("s", "").replace("duration: 0.5", "duration: 1e5")).unwrap();
    let blocker = dir.join("a-file");
    std::fs::write(&blocker, "not a folder").unwrap();
    let start = std::time::Instant::now();
    let output = nearmiss(&["run", scene.to_str().unwrap(), "--out", blocker.to_str().unwrap()]);
    assert_eq!(output.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&output.stderr).contains("--out"));
    assert!(start.elapsed().as_secs() < 20, "it ran first");
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn what_check_accepts_run_finishes() {
    let dir = workspace("check");
    let scene = dir.join("s.ron");
    // A plot with nothing to draw: refused by check (and so by run).
    let fixed_only = r#"Scene(name: "f", dt: 0.1, steps: 2, trace: (pairs: All), plot: (log_y: true), bodies: [
        (name: "a", mesh: Tetrahedron(circumradius: 1.0), fixed: true)])"#;
    std::fs::write(&scene, fixed_only).unwrap();
    let output = nearmiss(&["check", scene.to_str().unwrap()]);
    assert_eq!(output.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&output.stderr).contains("`plot`"));
    // Names that are no folder name.
    for (name, piece) in [("x".repeat(300), "bytes long"), ("a\\u{0}b".to_string(), "control")] {
        std::fs::write(&scene, scene_text(&name, "")).unwrap();
        let output = nearmiss(&["check", scene.to_str().unwrap()]);
        assert_eq!(output.status.code(), Some(2), "{name}");
        assert!(String::from_utf8_lossy(&output.stderr).contains(piece));
    }
    // A log axis with every distance 0 (the bodies touch throughout) draws.
    let touching = scene_text("t", "on_contact: Record, trace: (pairs: All), plot: (log_y: true),")
        .replace("position: (3.0, 0.0, 0.0), velocity: (-1.0, 0.0, 0.0)", "position: (0.5, 0.0, 0.0)");
    std::fs::write(&scene, touching).unwrap();
    let out = dir.join("out");
    let output = nearmiss(&["run", scene.to_str().unwrap(), "--out", out.to_str().unwrap()]);
    assert!(output.status.success(), "{}", String::from_utf8_lossy(&output.stderr));
    let _ = std::fs::remove_dir_all(&dir);
}

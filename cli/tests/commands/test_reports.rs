//! `nearmiss test` for CI systems: scenes run in parallel with their lines
//! in file order, a closing `N passed, M failed, K skipped` line, and JUnit
//! XML and JSON reports, read back here with an independent XML parser and
//! serde_json.

use quick_xml::events::Event;
use quick_xml::Reader;
use std::collections::HashMap;
use std::path::PathBuf;
use std::process::Command;

fn workspace(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("nearmiss-test-reports-{}-{name}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

/// A box falling at speed 1 onto a fixed one 1 below: contact at t = 1.
fn scene(name: &str, expect: &str) -> String {
    format!(
        r#"Scene(name: "{name}", dt: 0.01, duration: 2.0, bodies: [
            (name: "floor", mesh: Box(half_extents: (1.0, 1.0, 0.5)), position: (0.0, 0.0, -0.5), fixed: true),
            (name: "box", mesh: Box(half_extents: (0.5, 0.5, 0.5)), position: (0.0, 0.0, 1.5), velocity: (0.0, 0.0, -1.0)),
        ]{expect})"#
    )
}

#[test]
fn junit_and_json_reports_carry_every_case() {
    let dir = workspace("junit");
    let files = [
        (
            "a_pass.ron",
            scene("pass", r#", expect: Contact(time: 1.0, tolerance: 1e-6, bodies: ("floor", "box"))"#),
        ),
        (
            "b_fail.ron",
            scene("fail", r#", expect: Contact(time: 0.5, tolerance: 1e-6, bodies: ("floor", "box"))"#),
        ),
        ("c_skip.ron", scene("skip", "")),
        ("d_bad.ron", "Scene(name: \"bad\", dt: -1.0, steps: 1, bodies: [])".to_string()),
    ];
    for (name, text) in &files {
        std::fs::write(dir.join(name), text).unwrap();
    }
    let (junit, json) = (dir.join("reports/junit.xml"), dir.join("reports/suite.json"));
    let output = Command::new(env!("CARGO_BIN_EXE_nearmiss"))
        .args(["test", dir.to_str().unwrap(), "--jobs", "2", "--junit"])
        .arg(&junit)
        .arg("--json")
        .arg(&json)
        .output()
        .unwrap();
    let stdout = String::from_utf8_lossy(&output.stdout);
    // A bad scene is bad input: exit 2, and it counts as failed in the line.
    assert_eq!(output.status.code(), Some(2), "{stdout}");
    let lines: Vec<&str> = stdout.lines().collect();
    assert!(
        lines[0].starts_with("pass ")
            && lines[1].starts_with("FAIL ")
            && lines[2].starts_with("skip ")
            && lines[2].ends_with("c_skip.ron: states no expectation")
            && lines[3].starts_with("bad "),
        "{stdout}"
    );
    assert_eq!(*lines.last().unwrap(), "1 passed, 2 failed, 1 skipped");

    // JUnit: the suite's counts and one testcase per file, read by a parser.
    let xml = std::fs::read_to_string(&junit).unwrap();
    let mut reader = Reader::from_str(&xml);
    let (mut suites, mut cases, mut inside) = (Vec::new(), Vec::new(), None::<String>);
    loop {
        match reader.read_event().expect("well-formed XML") {
            Event::Eof => break,
            Event::Start(e) | Event::Empty(e) => {
                let attributes: HashMap<String, String> = e
                    .attributes()
                    .map(|a| {
                        let a = a.unwrap();
                        (
                            String::from_utf8_lossy(a.key.as_ref()).into_owned(),
                            a.normalized_value(quick_xml::XmlVersion::Explicit1_0).unwrap().into_owned(),
                        )
                    })
                    .collect();
                match e.name().as_ref() {
                    b"testsuites" => suites.push(attributes),
                    b"testcase" => inside = attributes.get("name").cloned(),
                    b"failure" | b"error" | b"skipped" => cases.push((
                        inside.clone().unwrap(),
                        String::from_utf8_lossy(e.name().as_ref()).into_owned(),
                    )),
                    _ => {}
                }
            }
            _ => {}
        }
    }
    let root = &suites[0];
    for (key, value) in [("tests", "4"), ("failures", "1"), ("errors", "1"), ("skipped", "1")] {
        assert_eq!(root[key], value, "{key}");
    }
    assert_eq!(
        cases,
        [
            ("b_fail.ron".to_string(), "failure".to_string()),
            ("c_skip.ron".into(), "skipped".into()),
            ("d_bad.ron".into(), "error".into())
        ]
    );
    assert!(xml.contains("expected: contact floor / box at t = 0.5 ± 1e-6"));

    // JSON: counts and the failing case's numbers.
    let suite: serde_json::Value = serde_json::from_str(&std::fs::read_to_string(&json).unwrap()).unwrap();
    assert_eq!(
        (suite["passed"].as_u64(), suite["failed"].as_u64(), suite["bad"].as_u64()),
        (Some(1), Some(1), Some(1))
    );
    let fail = &suite["cases"][1];
    assert_eq!(fail["status"], "failed");
    // Contact at t = 1 (never late, within the contract), expected 0.5.
    let error = fail["error"].as_f64().unwrap();
    assert!(error > 0.49 && error <= 0.5, "{error}");
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn the_count_line_closes_a_passing_suite() {
    let output = Command::new(env!("CARGO_BIN_EXE_nearmiss"))
        .args(["test", concat!(env!("CARGO_MANIFEST_DIR"), "/../scenes/two_triangles.ron")])
        .output()
        .unwrap();
    assert!(output.status.success());
    assert_eq!(String::from_utf8_lossy(&output.stdout).lines().last(), Some("1 passed, 0 failed, 0 skipped"));
}

#[test]
fn record_pins_the_current_answer_and_leaves_derived_expectations_alone() {
    let dir = workspace("record");
    // No expectation, and a comment that must survive: the box meets the
    // floor at t = 1 (gap 1, speed 1).
    let fresh = dir.join("fresh.ron");
    std::fs::write(&fresh, format!("// my scene\n{}", scene("fresh", ""))).unwrap();
    let derived = dir.join("derived.ron");
    let derived_text =
        scene("derived", r#", expect: Contact(time: 1.0, tolerance: 1e-6, bodies: ("floor", "box"))"#);
    std::fs::write(&derived, &derived_text).unwrap();
    let output =
        Command::new(env!("CARGO_BIN_EXE_nearmiss")).args(["test", "--record"]).arg(&dir).output().unwrap();
    let stdout = String::from_utf8_lossy(&output.stdout);
    assert!(output.status.success(), "{stdout}{}", String::from_utf8_lossy(&output.stderr));
    assert!(stdout.contains("recorded ") && stdout.ends_with("2 passed, 0 failed, 0 skipped\n"), "{stdout}");
    // The derived expectation is untouched, byte for byte.
    assert_eq!(std::fs::read_to_string(&derived).unwrap(), derived_text);
    // The recorded one: marked, its comment kept, and its time the analytic
    // contact within the recorded tolerance (never late).
    let text = std::fs::read_to_string(&fresh).unwrap();
    assert!(
        text.starts_with("// my scene\n") && text.contains("recorded by `nearmiss test --record`"),
        "{text}"
    );
    match nearmiss::scene::Scene::load(&fresh).unwrap().into_parts().1.expect {
        Some(nearmiss::scene::Expectation::Contact { time, tolerance, bodies: (0, 1), recorded: true }) => {
            assert!(time <= 1.0 && 1.0 - time <= tolerance && tolerance < 1e-4, "{time} ± {tolerance}");
        }
        other => panic!("{other:?}"),
    }
    // Recording again changes nothing but keeps one mark.
    let output =
        Command::new(env!("CARGO_BIN_EXE_nearmiss")).args(["test", "--record"]).arg(&fresh).output().unwrap();
    assert!(output.status.success());
    assert_eq!(std::fs::read_to_string(&fresh).unwrap(), text);
    let _ = std::fs::remove_dir_all(&dir);
}

/// `nearmiss test --shard I/N --json` on each of three shards, then
/// `nearmiss merge`: the same JSON and JUnit reports, line for line, as one
/// unsharded run, apart from wall times (the shipped scenes: passes and
/// skips, in two folders' order).
#[test]
fn sharded_and_merged_equals_one_run() {
    let dir = workspace("shards");
    let root = concat!(env!("CARGO_MANIFEST_DIR"), "/..");
    let scenes = [format!("{root}/scenes"), format!("{root}/scenes/stability")];
    let nearmiss = |args: &[&str]| {
        let output = Command::new(env!("CARGO_BIN_EXE_nearmiss")).args(args).output().unwrap();
        assert!(output.status.success(), "{args:?}: {}", String::from_utf8_lossy(&output.stderr));
        String::from_utf8(output.stdout).unwrap()
    };
    let path = |name: &str| dir.join(name).to_string_lossy().into_owned();
    let whole =
        nearmiss(&["test", &scenes[0], &scenes[1], "--json", &path("all.json"), "--junit", &path("all.xml")]);
    let mut shard_files = Vec::new();
    for index in 1..=3 {
        let file = path(&format!("shard{index}.json"));
        let shard = format!("{index}/3");
        nearmiss(&["test", &scenes[0], &scenes[1], "--shard", &shard, "--json", &file]);
        shard_files.push(file);
    }
    let mut merge = vec!["merge"];
    merge.extend(shard_files.iter().map(|s| s.as_str()));
    let merged_json = path("merged.json");
    let merged_xml = path("merged.xml");
    merge.extend(["--json", &merged_json, "--junit", &merged_xml]);
    let merged = nearmiss(&merge);
    // The same lines and count line on the terminal.
    assert_eq!(merged, whole);
    let without_times = |file: &str, key: &str| {
        let text = std::fs::read_to_string(dir.join(file)).unwrap();
        text.lines()
            .map(|line| match line.find(key) {
                Some(at) => line[..at].to_string(),
                None => line.to_string(),
            })
            .collect::<Vec<_>>()
    };
    assert_eq!(without_times("merged.json", "\"wall_time_s\""), without_times("all.json", "\"wall_time_s\""));
    assert_eq!(without_times("merged.xml", "time=\""), without_times("all.xml", "time=\""));
    // A shard missing is refused.
    let output = Command::new(env!("CARGO_BIN_EXE_nearmiss"))
        .args(["merge", &shard_files[0], &shard_files[1]])
        .output()
        .unwrap();
    assert_eq!(output.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&output.stderr).contains("shard 3/3 is missing"));
    let _ = std::fs::remove_dir_all(&dir);
}

/// `nearmiss queries --shard I/N --json` then `nearmiss merge`: the same
/// table as one run, apart from its three time columns.
#[test]
fn sharded_queries_merge_into_one_table() {
    let dir = workspace("query-shards");
    let data = concat!(env!("CARGO_MANIFEST_DIR"), "/../tests/data/ccd-sample-queries/unit-tests");
    let nearmiss = |args: &[&str]| {
        let output = Command::new(env!("CARGO_BIN_EXE_nearmiss")).args(args).output().unwrap();
        assert!(output.status.success(), "{args:?}: {}", String::from_utf8_lossy(&output.stderr));
        String::from_utf8(output.stdout).unwrap()
    };
    // The time columns (mean, median, max µs) are wall times.
    let without_times = |table: &str| -> Vec<String> {
        table
            .lines()
            .map(|line| {
                let mut cells: Vec<&str> = line.split('|').collect();
                if cells.len() > 12 && cells[1].trim() != "file" && !cells[1].contains("---") {
                    cells[8..11].fill("");
                }
                cells.join("|")
            })
            .collect()
    };
    let whole = nearmiss(&["queries", data, "--repeats", "1"]);
    let shards: Vec<String> =
        (1..=3).map(|i| dir.join(format!("q{i}.json")).to_string_lossy().into_owned()).collect();
    for (i, file) in shards.iter().enumerate() {
        nearmiss(&["queries", data, "--repeats", "1", "--shard", &format!("{}/3", i + 1), "--json", file]);
    }
    let merged = nearmiss(&["merge", &shards[0], &shards[1], &shards[2]]);
    assert!(whole.lines().count() > 4, "{whole}");
    assert_eq!(without_times(&merged), without_times(&whole));
    let _ = std::fs::remove_dir_all(&dir);
}

/// `nearmiss sweep --shard I/N --json` then `nearmiss merge --out`: the same
/// table and `sweep.csv` as one run, apart from the wall-time column. The
/// scene states no expectation, so the reference is the finest run, which
/// every shard computes and carries; a shard whose reference differs (as
/// from another build) is refused, as is a missing one.
#[test]
fn sharded_sweep_merges_into_one_sweep() {
    let dir = workspace("sweep-shards");
    let scene_file = dir.join("fall.ron");
    std::fs::write(&scene_file, scene("fall", "")).unwrap();
    let path = |name: &str| dir.join(name).to_string_lossy().into_owned();
    let run = |args: &[&str]| Command::new(env!("CARGO_BIN_EXE_nearmiss")).args(args).output().unwrap();
    let nearmiss = |args: &[&str]| {
        let output = run(args);
        assert!(output.status.success(), "{args:?}: {}", String::from_utf8_lossy(&output.stderr));
        String::from_utf8(output.stdout).unwrap()
    };
    let scene_path = path("fall.ron");
    let grid = [
        "sweep",
        scene_path.as_str(),
        "--dt",
        "0.02,0.01,0.005",
        "--kernel",
        "exact,dyop-heron",
        "--integrator",
        "symplectic-euler,rk4",
    ];
    let whole_out = path("whole");
    let whole = nearmiss(&[&grid[..], &["--out", &whole_out]].concat());
    let shards: Vec<String> = (1..=4).map(|i| path(&format!("sweep{i}.json"))).collect();
    for (i, file) in shards.iter().enumerate() {
        let shard = format!("{}/4", i + 1);
        nearmiss(&[&grid[..], &["--shard", &shard, "--json", file]].concat());
    }
    let merged_out = path("merged");
    let shard_refs: Vec<&str> = shards.iter().map(String::as_str).collect();
    let merged = nearmiss(&[&["merge"][..], &shard_refs, &["--out", &merged_out]].concat());
    // Column `column` of each table row or CSV line left out.
    let without = |text: &str, separator: char, column: usize| -> Vec<String> {
        text.lines()
            .filter(|line| !line.starts_with("wrote "))
            .map(|line| {
                let mut cells: Vec<&str> = line.split(separator).collect();
                if cells.len() > column {
                    cells[column] = "";
                }
                cells.join(&separator.to_string())
            })
            .collect()
    };
    // The reference is the finest exact run: never late on the analytic
    // contact at t = 1, early by no more than the contact distance allows.
    let reference: f64 = whole
        .strip_prefix("sweep of fall: reference ")
        .and_then(|rest| rest.split_whitespace().next())
        .and_then(|r| r.parse().ok())
        .unwrap_or_else(|| panic!("{whole}"));
    assert!((0.0..1e-5).contains(&(1.0 - reference)) && whole.contains("finest exact run"), "{whole}");
    assert_eq!(whole.lines().filter(|l| l.contains("first contact")).count(), 12, "{whole}");
    assert_eq!(without(&merged, '|', 8), without(&whole, '|', 8));
    let csv = |out: &str| std::fs::read_to_string(format!("{out}/fall/sweep.csv")).unwrap();
    let (whole_csv, merged_csv) = (csv(&whole_out), csv(&merged_out));
    assert_eq!(whole_csv.lines().count(), 13);
    assert_eq!(without(&merged_csv, ',', 8), without(&whole_csv, ',', 8));
    // Another reference in one shard: refused, naming the disagreement.
    let text = std::fs::read_to_string(&shards[1]).unwrap();
    let reference = text.lines().find(|l| l.contains("\"reference\":")).unwrap().to_string();
    let tampered = text.replace(&reference, "    \"reference\": 0.999,");
    assert_ne!(tampered, text);
    std::fs::write(&shards[1], tampered).unwrap();
    let output = run(&[&["merge"][..], &shard_refs, &["--out", &path("bad")]].concat());
    assert_eq!(output.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&output.stderr).contains("disagree on the reference"));
    assert!(!dir.join("bad").exists(), "nothing written by a refused merge");
    // A missing shard: refused.
    let output = run(&["merge", &shards[0], &shards[2], &shards[3], "--out", &path("bad")]);
    assert_eq!(output.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&output.stderr).contains("shard 2/4 is missing"));
    let _ = std::fs::remove_dir_all(&dir);
}

//! The public CCD benchmark sample (vendored in `tests/data/ccd-sample-queries`,
//! with its licences and sources in its README): every
//! handcrafted and simulation query, against Mathematica's exact ground
//! truth and exact times of impact.
//!
//! Must hold: no false negative, and no reported time later than the largest
//! f64 not above the exact time (`toi_f64_lo`). False positives are counted
//! and printed (each is a pair that came within the contact distance).

use nearmiss::ccd::{CcdOptions, CcdStatus};
use nearmiss_cli::query_file::{query_files, QueryFile, QueryKind};
use nearmiss_cli::report::run_file;
use std::path::{Path, PathBuf};

/// The sample: `NEARMISS_CCD_DATA` if set, else the copy in the repository.
fn data() -> PathBuf {
    let path = std::env::var_os("NEARMISS_CCD_DATA")
        .map(PathBuf::from)
        .unwrap_or_else(|| Path::new(env!("CARGO_MANIFEST_DIR")).join("../tests/data/ccd-sample-queries"));
    assert!(
        path.is_dir(),
        "the CCD sample is expected at {} (tests/data in the repository, or set NEARMISS_CCD_DATA)",
        path.display()
    );
    path
}

fn all_files() -> Vec<QueryFile> {
    let root = data();
    let mut files: Vec<QueryFile> = query_files(&root)
        .expect("lists the sample")
        .iter()
        .filter(|p| !p.components().any(|c| c.as_os_str() == "CCD-Query-IO"))
        .map(|p| QueryFile::load(p, None).unwrap_or_else(|e| panic!("{e}")))
        .collect();
    // The one fixture whose path does not say its kind: two edge-edge queries.
    let fixture = root.join("CCD-Query-IO/tests/data/split-ground-truth/queries.csv");
    files.push(QueryFile::load(&fixture, Some(QueryKind::EdgeEdge)).unwrap_or_else(|e| panic!("{e}")));
    files
}

fn check(options: &CcdOptions) {
    let files = all_files();
    let (mut queries, mut positives, mut false_positives, mut checked) = (0, 0, 0, 0);
    for file in &files {
        let report = run_file(file, options, 1);
        assert_eq!(report.false_negatives, 0, "{}: false negatives", file.path.display());
        assert_eq!(report.late, 0, "{}: times later than the exact time of impact", file.path.display());
        assert_eq!(report.unknown_truth, 0, "{}: ground truth missing", file.path.display());
        queries += report.queries;
        positives += report.positives;
        false_positives += report.false_positives;
        checked += report.times_checked;
    }
    // The sample's size, as its README counts it.
    assert_eq!(queries, 17_459);
    assert_eq!(positives, 10_163);
    assert_eq!(checked, 9_728);
    println!(
        "tolerance {:e}: {queries} queries, {positives} positives, 0 false negatives, {false_positives} false positives, {checked} exact times respected",
        options.distance_tolerance
    );
}

#[test]
fn no_false_negatives_and_never_late_at_the_default_tolerance() {
    check(&CcdOptions::default());
}

#[test]
fn no_false_negatives_and_never_late_at_a_tight_tolerance() {
    // Tiny gaps are where rounding tilts the separating axis; the method
    // must stay conservative there too.
    check(&CcdOptions { distance_tolerance: 1e-11, ..CcdOptions::default() });
}

#[test]
fn false_positives_are_within_the_contact_distance() {
    // A false positive must be a pair that really came within the contact
    // distance at the reported time (or an iteration cap, reported as such).
    let options = CcdOptions::default();
    for file in all_files() {
        for (i, query) in file.queries.iter().enumerate() {
            let result = query.run(file.kind, &options);
            if query.truth == Some(false) && result.time_of_impact.is_some() {
                assert!(
                    result.status == CcdStatus::OutOfIterations || result.distance <= result.contact_distance,
                    "{} query {i}: {result:?}",
                    file.path.display()
                );
            }
        }
    }
}

#[test]
fn the_cli_runs_the_whole_folder() {
    // One fixture's path does not say its kind: skipped with a warning in a
    // folder run; every other file is run, none with a false negative.
    let output = std::process::Command::new(env!("CARGO_BIN_EXE_nearmiss"))
        .args(["queries", "--repeats", "1"])
        .arg(data())
        .output()
        .expect("runs");
    assert_eq!(output.status.code(), Some(0), "{}", String::from_utf8_lossy(&output.stderr));
    let stdout = String::from_utf8_lossy(&output.stdout);
    assert_eq!(stdout.lines().filter(|l| l.contains(".csv |")).count(), 47);
    assert!(String::from_utf8_lossy(&output.stderr).contains("warning: skipped"));
}

//! Bad benchmark files give errors that name the file, line and column, and
//! the CLI exits 2 without running anything.

use nearmiss_cli::query_file::{QueryFile, QueryKind};
use std::path::PathBuf;
use std::process::Command;

fn write(name: &str, text: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("nearmiss-query-file-{}", std::process::id()));
    std::fs::create_dir_all(&dir).expect("temp dir");
    let path = dir.join(name);
    std::fs::write(&path, text).expect("write");
    path
}

const GOOD_ROW: &str = "1,2,3,4,-5,8";

fn rows(n: usize, row: &str) -> String {
    (0..n).map(|_| format!("{row}\n")).collect()
}

fn error_of(name: &str, text: &str) -> String {
    QueryFile::load(&write(name, text), Some(QueryKind::VertexFace))
        .expect_err("must be rejected")
        .to_string()
}

#[test]
fn a_good_file_loads_exactly() {
    let file =
        QueryFile::load(&write("good.csv", &rows(8, GOOD_ROW)), Some(QueryKind::EdgeEdge)).expect("loads");
    assert_eq!(file.queries.len(), 1);
    assert_eq!(file.queries[0].points[0], nearmiss::math::Point::new(0.5, 0.75, -0.625));
    // Numerators and denominators beyond 64 bits (2^100 / 2^101 = 0.5).
    let big = "1267650600228229401496703205376,2535301200456458802993406410752";
    let file = QueryFile::load(
        &write("big.csv", &rows(8, &format!("{big},{big},{big}"))),
        Some(QueryKind::EdgeEdge),
    );
    assert_eq!(file.expect("loads").queries[0].points[7], nearmiss::math::Point::new(0.5, 0.5, 0.5));
}

#[test]
fn malformed_rows_name_their_line_and_column() {
    let e = error_of("short.csv", &(rows(3, GOOD_ROW) + "1,2,3,4,5\n"));
    assert!(e.ends_with("short.csv:4:1: expected 6 or 7 comma-separated values, found 5"), "{e}");
    let e = error_of("word.csv", &(rows(1, GOOD_ROW) + "1,2,x,4,5,8\n"));
    assert!(e.contains("word.csv:2:3: `x` is not an integer"), "{e}");
    let e = error_of("zero.csv", "1,0,1,1,1,1\n");
    assert!(e.contains("zero.csv:1:1: zero denominator"), "{e}");
    let e = error_of("third.csv", "1,3,1,1,1,1\n");
    assert!(e.contains("third.csv:1:1: 1/3 is not exactly representable as an f64"), "{e}");
    let e = error_of("count.csv", &rows(9, GOOD_ROW));
    assert!(e.contains("count.csv:9:1: 9 vertex rows is not a multiple of 8"), "{e}");
    let e = error_of("truth.csv", &(rows(7, &format!("{GOOD_ROW},1")) + &format!("{GOOD_ROW},0\n")));
    assert!(e.contains("truth.csv:8:7: the ground truth differs"), "{e}");
}

#[test]
fn a_file_of_unknown_kind_is_refused() {
    let e =
        QueryFile::load(&write("plain.csv", &rows(8, GOOD_ROW)), None).expect_err("kind unknown").to_string();
    assert!(e.contains("cannot tell edge-edge from vertex-face"), "{e}");
}

#[test]
fn the_cli_exits_2_on_a_bad_file() {
    let bad = write("cli-bad.csv", "1,2,3\n");
    let output = Command::new(env!("CARGO_BIN_EXE_nearmiss"))
        .args(["queries", "--kind", "vf"])
        .arg(&bad)
        .output()
        .expect("runs");
    assert_eq!(output.status.code(), Some(2));
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert!(stderr.contains("cli-bad.csv:1:1"), "{stderr}");
    assert!(output.stdout.is_empty(), "nothing is printed before the input is checked");
}

#[test]
fn an_empty_or_comment_only_file_is_not_a_row_of_zero_queries() {
    assert!(error_of("empty.csv", "").contains("no queries"));
    assert!(error_of("comments.csv", "# nothing here\n# at all\n").contains("no queries"));
}

#[test]
fn a_numerator_that_is_no_f64_is_rejected_not_saturated() {
    // 2^127 − 1 over 1: the old fast path rounded it to 2^127 and the
    // saturating cast back "recovered" 2^127 − 1.
    let row = "170141183460469231731687303715884105727,1,0,1,0,1";
    let error = error_of("wide.csv", &rows(8, row));
    assert!(error.contains("not exactly representable"), "{error}");
    // 2^126 (one significant bit) is an f64 and loads.
    let row = "85070591730234615865843651857942052864,1,0,1,0,1";
    let file = QueryFile::load(&write("pow.csv", &rows(8, row)), Some(QueryKind::VertexFace)).expect("loads");
    assert_eq!(file.queries[0].points[0].x, 2f64.powi(126));
}

#[test]
fn meaningless_options_are_refused_with_their_range() {
    let file = write("options.csv", &rows(8, GOOD_ROW));
    for (option, value) in [
        ("--tolerance", "NaN"),
        ("--tolerance", "0"),
        ("--tolerance", "inf"),
        ("--tolerance", "1e308"),
        ("--max-iterations", "0"),
        ("--repeats", "0"),
    ] {
        let output = Command::new(env!("CARGO_BIN_EXE_nearmiss"))
            .args(["queries", file.to_str().unwrap(), "--kind", "vf", option, value])
            .output()
            .unwrap();
        let stderr = String::from_utf8_lossy(&output.stderr);
        assert_eq!(output.status.code(), Some(2), "{option} {value}: {stderr}");
        assert!(stderr.contains(option), "{option} {value}: {stderr}");
    }
}

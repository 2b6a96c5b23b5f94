//! Bad benchmark files give errors that name the file, line and column, and
//! the CLI exits 2 without running anything.

use nearmiss::query_file::{QueryFile, QueryKind};
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

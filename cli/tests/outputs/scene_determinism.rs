//! The same scene run twice gives bit-identical `summary.json` (wall times
//! aside) and `trace.csv`.

use std::process::Command;

fn run_into(scene: &str, out: &std::path::Path) {
    let status = Command::new(env!("CARGO_BIN_EXE_nearmiss"))
        .args(["run", scene, "--out", out.to_str().unwrap()])
        .current_dir(concat!(env!("CARGO_MANIFEST_DIR"), "/.."))
        .output()
        .unwrap();
    assert!(status.status.success(), "{}", String::from_utf8_lossy(&status.stderr));
}

/// The summary without its wall-clock fields.
fn summary_without_times(path: &std::path::Path) -> serde_json::Value {
    let mut value: serde_json::Value = serde_json::from_str(&std::fs::read_to_string(path).unwrap()).unwrap();
    let object = value.as_object_mut().unwrap();
    assert!(object.remove("wall_time_s").is_some());
    assert!(object.remove("stage_wall_time_s").is_some());
    value
}

#[test]
fn runs_are_bit_identical() {
    let base = std::env::temp_dir().join(format!("nearmiss-determinism-{}", std::process::id()));
    // A rotating contact and an integrated spin (implicit gyroscopic step).
    for (scene, name) in
        [("scenes/tumbling_icospheres.ron", "tumbling_icospheres"), ("scenes/dzhanibekov.ron", "dzhanibekov")]
    {
        let (first, second) = (base.join("first"), base.join("second"));
        run_into(scene, &first);
        run_into(scene, &second);
        let (a, b) = (first.join(name), second.join(name));
        assert_eq!(
            summary_without_times(&a.join("summary.json")),
            summary_without_times(&b.join("summary.json"))
        );
        let trace = std::fs::read(a.join("trace.csv")).unwrap();
        assert!(trace.len() > 100);
        assert_eq!(trace, std::fs::read(b.join("trace.csv")).unwrap());
    }
    let _ = std::fs::remove_dir_all(&base);
}

//! The README's first run, as pasted there, is what the command prints
//! (issue 46: it showed a time of contact the run no longer gave). Only
//! the run's wall time may differ.

use std::path::Path;
use std::process::Command;

/// The README's fenced `text` block after "It prints:".
fn pasted_run(readme: &str) -> Vec<String> {
    let after = readme.split_once("It prints:").expect("the README's \"It prints:\"").1;
    let block = after.split_once("```text\n").expect("a ```text block").1;
    let block = block.split_once("```").expect("the block's end").0;
    block.lines().map(str::to_string).collect()
}

/// A line with its wall time (`in 353 µs`) cut off.
fn without_wall_time(line: &str) -> &str {
    line.rsplit_once(" in ").filter(|(_, time)| time.ends_with('s')).map_or(line, |(head, _)| head)
}

#[test]
fn the_readme_first_run_is_what_the_command_prints() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).parent().unwrap();
    let readme = std::fs::read_to_string(root.join("README.md")).unwrap();
    let pasted = pasted_run(&readme);
    assert!(readme.contains("cargo run --release -- run scenes/spinning_blade.ron"));
    let dir = std::env::temp_dir().join(format!("nearmiss-readme-run-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    let output = Command::new(env!("CARGO_BIN_EXE_nearmiss"))
        .args(["run", root.join("scenes/spinning_blade.ron").to_str().unwrap()])
        .current_dir(&dir)
        .output()
        .unwrap();
    assert!(output.status.success(), "{}", String::from_utf8_lossy(&output.stderr));
    let printed = String::from_utf8(output.stdout).unwrap();
    let printed: Vec<&str> = printed.lines().map(without_wall_time).collect();
    let pasted: Vec<&str> = pasted.iter().map(|l| without_wall_time(l)).collect();
    assert_eq!(printed, pasted, "the README's pasted run differs from the run");
    let _ = std::fs::remove_dir_all(&dir);
}

//! `nearmiss test`: every scene with an expectation, one line each.

use crate::progress::run_with_progress;
use crate::{load_scene, CliError, CommandResult};
use std::path::PathBuf;

#[derive(clap::Args)]
pub struct Args {
    /// Scene files or folders.
    #[arg(required = true)]
    paths: Vec<PathBuf>,
    /// The most steps a run may take (a longer one is refused before it
    /// starts: usually a typo in `dt` or `duration`).
    #[arg(long, default_value_t = nearmiss::scene::DEFAULT_MAX_STEPS)]
    max_steps: u64,
}

pub fn main(args: Args) -> CommandResult {
    let mut files = Vec::new();
    for path in &args.paths {
        let found = nearmiss::regression::scene_files(path)
            .map_err(|error| CliError::BadInput(format!("{}: {error}", path.display())))?;
        files.extend(found);
    }
    let (mut passed, mut failed, mut bad, mut skipped) = (0, 0, 0, 0);
    for file in &files {
        let scene = match load_scene(file, args.max_steps) {
            Ok(scene) => scene,
            Err(CliError::BadInput(message) | CliError::Failed(message) | CliError::Undecided(message)) => {
                eprintln!("error: {message}");
                bad += 1;
                continue;
            }
        };
        if scene.expect.is_none() {
            skipped += 1;
            continue;
        }
        let result = run_with_progress(&scene);
        let Some(verdict) = nearmiss::regression::verdict(&scene, &result) else { continue };
        let error = verdict.error.map_or(String::new(), |e| format!(", error {e:+.3e}"));
        println!(
            "{} {}: expected {}; obtained {}{error}",
            if verdict.passed { "pass" } else { "FAIL" },
            file.display(),
            verdict.expected,
            verdict.obtained
        );
        if verdict.passed {
            passed += 1;
        } else {
            failed += 1;
        }
    }
    println!("{passed} passed, {failed} failed, {bad} bad, {skipped} without expectation");
    if bad > 0 {
        Err(CliError::BadInput(String::new()))
    } else if failed > 0 {
        Err(CliError::Failed(String::new()))
    } else {
        Ok(())
    }
}

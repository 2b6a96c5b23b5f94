//! `nearmiss check`: validates scenes without running them.

use crate::{load_scene, CliError, CommandResult};
use nearmiss_cli::text;
use std::path::PathBuf;

#[derive(clap::Args)]
pub struct Args {
    /// Scene files, or folders searched for `.ron` files.
    #[arg(required = true, value_name = "SCENE")]
    scenes: Vec<PathBuf>,
    /// The most steps a run may take (a longer one is refused before it
    /// starts: usually a typo in `dt` or `duration`).
    #[arg(long, default_value_t = nearmiss::scene::DEFAULT_MAX_STEPS)]
    max_steps: u64,
}

pub fn main(args: Args) -> CommandResult {
    let mut files = Vec::new();
    for path in &args.scenes {
        let found = nearmiss_cli::regression::scene_files(path)
            .map_err(|error| CliError::BadInput(format!("{}: {error}", path.display())))?;
        if found.is_empty() {
            return Err(CliError::BadInput(format!("{}: no `.ron` scene files there", path.display())));
        }
        files.extend(found);
    }
    let mut bad = 0;
    // Scene name → the first file of that name: two files of one name
    // would write one output folder.
    let mut names: std::collections::BTreeMap<String, PathBuf> = Default::default();
    for path in &files {
        match load_scene(path, args.max_steps) {
            Ok(scene) => {
                println!(
                    "ok {}: scene `{}`, {}, {} of dt = {}",
                    path.display(),
                    scene.run().name,
                    text::count(scene.model().bodies.len() as u64, "body"),
                    text::count(scene.run().steps, "step"),
                    text::time(scene.model().dt)
                );
                // As `run` warns: bodies that start overlapped.
                for overlap in scene.initial_overlaps() {
                    eprintln!("{}", crate::run::overlap_warning(&overlap, &scene.model().bodies));
                }
                if let Some(first) = names.get(&scene.run().name) {
                    eprintln!(
                        "warning: {} and {} are both named `{}`: their runs would write one output folder",
                        first.display(),
                        path.display(),
                        scene.run().name
                    );
                } else {
                    names.insert(scene.run().name.clone(), path.clone());
                }
            }
            Err(CliError::BadInput(message) | CliError::Failed(message) | CliError::Undecided(message)) => {
                eprintln!("error: {message}");
                bad += 1;
            }
        }
    }
    if bad > 0 {
        return Err(CliError::BadInput(format!(
            "{} of {} bad",
            text::count(bad as u64, "scene"),
            files.len()
        )));
    }
    Ok(())
}

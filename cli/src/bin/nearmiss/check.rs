//! `nearmiss check`: validates scenes without running them.

use crate::{load_scene, CliError, CommandResult};
use std::path::PathBuf;

#[derive(clap::Args)]
pub struct Args {
    /// Scene files.
    #[arg(required = true)]
    scenes: Vec<PathBuf>,
    /// The most steps a run may take (a longer one is refused before it
    /// starts: usually a typo in `dt` or `duration`).
    #[arg(long, default_value_t = nearmiss::scene::DEFAULT_MAX_STEPS)]
    max_steps: u64,
}

pub fn main(args: Args) -> CommandResult {
    let mut bad = false;
    for path in &args.scenes {
        match load_scene(path, args.max_steps) {
            Ok(scene) => println!(
                "ok {}: scene `{}`, {} bodies, {} steps of dt = {:?}",
                path.display(),
                scene.run().name,
                scene.model().bodies.len(),
                scene.run().steps,
                scene.model().dt
            ),
            Err(CliError::BadInput(message) | CliError::Failed(message) | CliError::Undecided(message)) => {
                eprintln!("error: {message}");
                bad = true;
            }
        }
    }
    if bad {
        return Err(CliError::BadInput(String::new()));
    }
    Ok(())
}

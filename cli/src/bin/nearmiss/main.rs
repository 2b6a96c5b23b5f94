//! The `nearmiss` command line: parses arguments, calls the library, prints.
//! One file per subcommand; errors become exit codes here, in one place:
//! 0 success, 1 a check failed (a scene missed its expectation, a run
//! diverged, a CCD query was late or missed), 2 bad input (scene, query
//! file, arguments) or an output that could not be written, 3 a run
//! stopped because the CCD could not decide whether a pair touches.

mod check;
mod kernels;
mod merge;
mod paper;
mod progress;
mod queries;
mod run;
mod stability;
mod sweep;
mod test;

use clap::{Parser, Subcommand};
use nearmiss::scene::Scene;
use std::path::{Path, PathBuf};
use std::process::ExitCode;

/// The exit codes, as every command's help ends.
const EXIT_STATUS: &str = "\
Exit status:
  0  success: the runs completed and met their expectations
  1  a check failed: an expectation not met, an integration diverged, a CCD
     query late or missed
  2  bad input (a scene, a query file, an argument) or an output that could
     not be written; nothing is run or written then
  3  undecided: the CCD could not decide whether a pair touches (the run
     stops there; not a contact)";

#[derive(Parser)]
#[command(
    name = "nearmiss",
    version,
    about = "Continuous collision detection for triangle meshes: runs scenes, finds first contacts",
    after_help = EXIT_STATUS,
    after_long_help = EXIT_STATUS
)]
struct Cli {
    #[command(subcommand)]
    command: Command,
}

#[derive(Subcommand)]
enum Command {
    /// Run scenes and write their outputs
    ///
    /// Runs each scene file and writes `<out>/<scene name>/`: `summary.json`,
    /// and what the scene asks for (`trace.csv`, `poses.csv`, plots, contact
    /// pictures, `animation.glb`, `report.md`). Prints the first contact and,
    /// where the scene states one, whether its expectation was met.
    #[command(after_help = EXIT_STATUS)]
    Run(run::Args),
    /// Check scenes without running them
    ///
    /// Loads and validates scene files (or every `.ron` under folders): the
    /// errors name the file and the line and column or the field.
    #[command(after_help = EXIT_STATUS)]
    Check(check::Args),
    /// Test scenes against their expectations
    ///
    /// Runs every scene (files, or folders searched for `.ron`) that states
    /// an expectation, in parallel; one line per scene in file order, as
    /// each is known, and a closing `N passed, M failed, K skipped` line.
    #[command(after_help = EXIT_STATUS)]
    Test(test::Args),
    /// Sweep a scene over time steps, kernels and integrators
    ///
    /// Per setting: the time of first contact, its error against the
    /// reference (analytic, or the finest exact run), the kernel's error
    /// against the exact distance along the trace, and the wall time.
    /// Writes `<out>/<scene>/sweep.csv` and `error_vs_runtime.png`.
    Sweep(sweep::Args),
    /// Run the stability suite
    ///
    /// The stiff spring at ω·dt from 0.1 to 3 per integrator, the
    /// Dzhanibekov spin over 100,000 steps, and every scene of the folder
    /// against its expectation. Writes `<out>/stability/stability.md` and
    /// PNG charts.
    Stability(stability::Args),
    /// Run CCD benchmark query files
    ///
    /// Files or folders of queries: per file the queries, positives, false
    /// negatives, false positives, time per query and, where exact times
    /// are known, whether any reported time was late. Exits 1 if any query
    /// was a false negative or late.
    Queries(queries::Args),
    /// Measure the distance kernels against the exact reference
    ///
    /// Each kernel's error against the exact rational reference, per input
    /// class, beside its rough time per query.
    Kernels(kernels::Args),
    /// Reproduce the seed paper's experiments
    ///
    /// Six calibration placements, ten rotated ones, 90 type-against-type
    /// tests timed per formula, and the verdict on its claim that Heron is
    /// about 5% faster. Prints Markdown and writes `<out>/paper/paper.md`.
    Paper(paper::Args),
    /// Merge the shards of `test`, `queries` or `sweep`
    ///
    /// Puts the shards written with `--shard I/N --json FILE` back
    /// together: what one machine would have printed and written (wall
    /// times apart). Exits like the command, and 2 if the shards do not
    /// make one whole run.
    Merge(merge::Args),
}

/// Why a command did not succeed.
#[derive(Debug)]
pub enum CliError {
    /// Bad input, or an output that could not be written (exit 2). The
    /// message is printed; empty if the command already said what was bad.
    BadInput(String),
    /// A check failed (exit 1); the message is printed if not empty.
    Failed(String),
    /// A run stopped because the CCD could not decide a pair (exit 3).
    Undecided(String),
}

/// What each subcommand returns.
pub type CommandResult = Result<(), CliError>;

fn main() -> ExitCode {
    let cli = match Cli::try_parse() {
        Ok(cli) => cli,
        Err(e) => {
            let code = if e.use_stderr() { 2 } else { 0 };
            let _ = e.print();
            return ExitCode::from(code);
        }
    };
    let result = match cli.command {
        Command::Kernels(args) => kernels::main(args),
        Command::Queries(args) => queries::main(args),
        Command::Run(args) => run::main(args),
        Command::Sweep(args) => sweep::main(args),
        Command::Paper(args) => paper::main(args),
        Command::Stability(args) => stability::main(args),
        Command::Check(args) => check::main(args),
        Command::Test(args) => test::main(args),
        Command::Merge(args) => merge::main(args),
    };
    let (code, message) = match result {
        Ok(()) => return ExitCode::SUCCESS,
        Err(CliError::BadInput(message)) => (2, message),
        Err(CliError::Failed(message)) => (1, message),
        Err(CliError::Undecided(message)) => (3, message),
    };
    if !message.is_empty() {
        eprintln!("error: {message}");
    }
    ExitCode::from(code)
}

/// Loads a scene and checks that its run takes at most `max_steps` steps;
/// a bad one is [`CliError::BadInput`] naming the file and field.
pub fn load_scene(path: &Path, max_steps: u64) -> Result<Scene, CliError> {
    let scene = Scene::load_within(path, max_steps).map_err(|error| CliError::BadInput(error.to_string()))?;
    // What the scene needs of this build (a `Simulate` scene's contact
    // distances): refused here as bad input, not as a run that never started.
    nearmiss::run::check(&scene).map_err(|error| CliError::BadInput(error.to_string()))?;
    for note in scene.mesh_notes() {
        eprintln!("note: {note}");
    }
    Ok(scene)
}

/// Writes a report file through the library's one writer; failure is bad
/// output (exit 2). Prints and returns the path.
pub fn write_report(folder: &Path, name: &str, bytes: &[u8]) -> Result<PathBuf, CliError> {
    nearmiss_cli::output::write_report(folder, name, bytes)
        .map_err(|error| CliError::BadInput(format!("cannot write to {}: {error}", folder.display())))
}

/// Draws a chart into `folder/name`; a chart that cannot be drawn is a
/// warning (the report it illustrates is written already).
#[cfg(feature = "plot")]
pub fn write_chart(folder: &Path, name: &str, chart: &nearmiss_cli::plot::Chart) {
    match nearmiss_cli::output::write_chart(folder, name, chart) {
        Ok(path) => eprintln!("wrote {}", path.display()),
        Err(error) => eprintln!("warning: no chart {name}: {error}"),
    }
}

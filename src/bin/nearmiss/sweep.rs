//! `nearmiss sweep`: a scene over time steps, kernels and integrators.

use crate::progress::bar;
use crate::{load_scene, CliError, CommandResult};
use nearmiss::report::{parse_integrator, parse_kernel, sweep, sweep_csv, sweep_markdown};
use std::path::PathBuf;

#[derive(clap::Args)]
pub struct Args {
    /// The scene file.
    scene: PathBuf,
    /// Time steps, comma-separated.
    #[arg(long, value_delimiter = ',', required = true)]
    dt: Vec<f64>,
    /// Kernels, comma-separated: exact, dyop-vector, dyop-plain-vector,
    /// dyop-heron, dyop-stable-heron.
    #[arg(long, value_delimiter = ',', required = true)]
    kernel: Vec<String>,
    /// Integrators, comma-separated: symplectic-euler, explicit-euler,
    /// rk4 (default: the scene's).
    #[arg(long, value_delimiter = ',')]
    integrator: Vec<String>,
    /// The output folder.
    #[arg(long, default_value = "output")]
    out: PathBuf,
    /// The most steps a run may take per setting (a longer one is refused
    /// before the sweep starts).
    #[arg(long, default_value_t = nearmiss::scene::DEFAULT_MAX_STEPS)]
    max_steps: u64,
}

/// Parses each name of a list option; an unknown one is bad input naming
/// the option and the known names.
fn parse_names<T>(
    names: &[String],
    parse: fn(&str) -> Option<T>,
    option: &str,
    known: &str,
) -> Result<Vec<T>, CliError> {
    names
        .iter()
        .map(|name| {
            parse(name).ok_or_else(|| {
                CliError::BadInput(format!("{option}: unknown name `{name}` (known: {known})"))
            })
        })
        .collect()
}

pub fn main(args: Args) -> CommandResult {
    let scene = load_scene(&args.scene, args.max_steps)?;
    if let Some(bad) = args.dt.iter().find(|dt| !(dt.is_finite() && **dt > 0.0)) {
        return Err(CliError::BadInput(format!("--dt: every step must be a positive number, found {bad:?}")));
    }
    for &dt in &args.dt {
        let steps = (scene.duration / dt).ceil();
        if steps > args.max_steps as f64 {
            return Err(CliError::BadInput(format!(
                "--dt: {dt:?} gives {steps:e} steps over the scene's duration {:?}, more than the limit of {} (raise it with --max-steps)",
                scene.duration, args.max_steps
            )));
        }
    }
    let kernels = parse_names(
        &args.kernel,
        parse_kernel,
        "--kernel",
        "exact, dyop-vector, dyop-plain-vector, dyop-heron, dyop-stable-heron",
    )?;
    let mut integrators = parse_names(
        &args.integrator,
        parse_integrator,
        "--integrator",
        "symplectic-euler, explicit-euler, rk4",
    )?;
    if integrators.is_empty() {
        integrators.push(scene.integrator);
    }
    let total = (args.dt.len() * kernels.len() * integrators.len() + 1) as u64;
    let progress = bar(total, "sweep [{bar:40}] {pos}/{len} runs, {eta} left");
    let report =
        sweep(&scene, &args.dt, &kernels, &integrators, &mut |done, _| progress.set_position(done as u64));
    progress.finish_and_clear();
    print!("{}", sweep_markdown(&report));
    let folder = args.out.join(&scene.name);
    let path = crate::write_report(&folder, "sweep.csv", sweep_csv(&report).as_bytes())?;
    println!("wrote {}", path.display());
    #[cfg(feature = "plot")]
    crate::write_chart(&folder, "error_vs_runtime.png", &nearmiss::report::sweep_chart(&report));
    Ok(())
}

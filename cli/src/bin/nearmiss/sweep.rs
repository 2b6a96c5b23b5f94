//! `nearmiss sweep`: a scene over time steps, kernels and integrators.

use crate::progress::bar;
use crate::{load_scene, CliError, CommandResult};
use nearmiss_cli::report::{
    parse_integrator, parse_kernel, sweep_csv, sweep_markdown, sweep_share, Shard, ShardFile, SweepReport,
};
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
    #[arg(short, long, default_value = "output")]
    out: PathBuf,
    /// The most steps a run may take per setting (a longer one is refused
    /// before the sweep starts).
    #[arg(long, default_value_t = nearmiss::scene::DEFAULT_MAX_STEPS)]
    max_steps: u64,
    /// Run only share I of N of the settings (those at positions k of the
    /// grid, integrators outermost and time steps innermost, with
    /// k mod N = I − 1), to spread a sweep over machines. Needs `--json`,
    /// which then gets the shard's rows and its reference for `nearmiss
    /// merge` (no `sweep.csv` is written).
    #[arg(long)]
    shard: Option<Shard>,
    /// With `--shard`: write the shard's results to this file.
    #[arg(long)]
    json: Option<PathBuf>,
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
        let steps = (scene.run().duration / dt).ceil() as u64;
        if steps > args.max_steps {
            return Err(CliError::BadInput(format!(
                "--dt: {dt:?} gives {steps} steps over the scene's duration {:?}, more than the limit of {} (raise it with --max-steps)",
                scene.run().duration, args.max_steps
            )));
        }
        // The scene's trace and poses were checked at load for its own dt.
        let records = scene.most_records(steps);
        if records > nearmiss::scene::MAX_RECORDS {
            return Err(CliError::BadInput(format!(
                "--dt: {dt:?} gives {steps} steps, at which the scene's trace or poses would keep {records} records, more than the limit of {}: trace fewer pairs or sample less often (`every`)",
                nearmiss::scene::MAX_RECORDS
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
        integrators.push(scene.model().integrator);
    }
    if args.shard.is_some() != args.json.is_some() {
        return Err(CliError::BadInput(
            "--shard and --json go together (the shard's rows, for `nearmiss merge`)".into(),
        ));
    }
    let shard = args.shard.unwrap_or(Shard { index: 1, count: 1 });
    let progress = bar(1, "sweep [{bar:40}] {pos}/{len} runs, {eta} left");
    let share = sweep_share(&scene, &args.dt, &kernels, &integrators, shard, &mut |done, total| {
        progress.set_length(total as u64);
        progress.set_position(done as u64);
    });
    progress.finish_and_clear();
    if let Some(json) = &args.json {
        // The shard's own rows on the terminal; the merge prints the whole.
        let own = SweepReport { scene: format!("{} (shard {shard})", share.scene), ..share.report() };
        print!("{}", sweep_markdown(&own));
        crate::test::write_beside(json, &ShardFile::Sweep(share).to_json())?;
        println!("wrote {}", json.display());
        return Ok(());
    }
    write_sweep(&share.report(), &args.out)
}

/// Prints the sweep and writes `<out>/<scene>/sweep.csv` and its chart: one
/// machine's sweep, or the merge of its shards.
pub fn write_sweep(report: &SweepReport, out: &std::path::Path) -> CommandResult {
    print!("{}", sweep_markdown(report));
    let folder = out.join(&report.scene);
    let path = crate::write_report(&folder, "sweep.csv", sweep_csv(report).as_bytes())?;
    println!("wrote {}", path.display());
    #[cfg(feature = "plot")]
    crate::write_chart(&folder, "error_vs_runtime.png", &nearmiss_cli::report::sweep_chart(report));
    Ok(())
}

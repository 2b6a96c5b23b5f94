//! `nearmiss stability`: the stability suite.

use crate::progress::run_with_progress;
use crate::{load_scene, CliError, CommandResult};
use nearmiss::math::Real;
use nearmiss::scene::DEFAULT_MAX_STEPS;
use nearmiss_cli::report::{spin_drift, spring_omega, spring_sweep, stability_markdown, StabilitySuite};
use std::path::PathBuf;

#[derive(clap::Args)]
pub struct Args {
    /// The folder of the suite's scenes.
    #[arg(long, default_value = "scenes/stability")]
    scenes: PathBuf,
    /// The output folder.
    #[arg(short, long, default_value = "output")]
    out: PathBuf,
}

pub fn main(args: Args) -> CommandResult {
    let suite = StabilitySuite::default();
    let folder = &args.scenes;
    let spring = load_scene(&folder.join(suite.spring_scene), DEFAULT_MAX_STEPS)?;
    let spin = load_scene(&folder.join(suite.spin_scene), DEFAULT_MAX_STEPS)?;
    let springs = spring_sweep(&spring, &suite.spring_omega_dts, &suite.integrators);
    let drifts = spin_drift(&spin, spin.run().steps, suite.spin_sample_every);
    let files = nearmiss_cli::regression::scene_files(folder)
        .map_err(|error| CliError::BadInput(format!("{}: {error}", folder.display())))?;
    let mut verdicts = Vec::new();
    let mut failed = 0;
    for file in files {
        let scene = load_scene(&file, DEFAULT_MAX_STEPS)?;
        let result = run_with_progress(&scene);
        if let Some(v) = nearmiss_cli::regression::verdict(&scene, &result) {
            failed += usize::from(!v.passed);
            verdicts.push((file.display().to_string(), v.passed, v.expected, v.obtained, v.error));
        }
    }
    let text = stability_markdown(
        &springs,
        spring_omega(&spring).unwrap_or(Real::NAN),
        &drifts,
        spin.run().steps,
        &verdicts,
    );
    print!("{text}");
    let target = args.out.join("stability");
    crate::write_report(&target, "stability.md", text.as_bytes())?;
    #[cfg(feature = "plot")]
    {
        crate::write_chart(&target, "spring_energy_drift.png", &nearmiss_cli::report::spring_chart(&springs));
        crate::write_chart(
            &target,
            "dzhanibekov_energy_drift.png",
            &nearmiss_cli::report::spin_chart(&drifts),
        );
    }
    if failed > 0 {
        return Err(CliError::Failed(format!(
            "{} of the suite missed {} expectation",
            nearmiss_cli::text::count(failed as u64, "scene"),
            if failed == 1 { "its" } else { "their" }
        )));
    }
    Ok(())
}

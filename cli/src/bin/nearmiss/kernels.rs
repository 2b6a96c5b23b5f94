//! `nearmiss kernels`: the kernel report and its charts.

use crate::CommandResult;
use std::path::PathBuf;

#[derive(clap::Args)]
pub struct Args {
    /// Inputs per class.
    #[arg(long, default_value_t = 500)]
    count: usize,
    /// Seed of the input generators.
    #[arg(long, default_value_t = 1)]
    seed: u64,
    /// Output folder: the charts go to `<out>/kernels/`.
    #[arg(short, long, default_value = "output")]
    out: PathBuf,
}

pub fn main(args: Args) -> CommandResult {
    let rows = nearmiss_cli::report::kernel_report(args.count, args.seed);
    print!("{}", nearmiss_cli::report::kernel_report_markdown(&rows));
    #[cfg(feature = "plot")]
    {
        let folder = args.out.join("kernels");
        for (point_segment, name) in
            [(false, "triangle_error_vs_time.png"), (true, "point_segment_error_vs_time.png")]
        {
            let chart = nearmiss_cli::report::kernel_chart(&rows, point_segment);
            let path = nearmiss_cli::output::write_chart(&folder, name, &chart)
                .map_err(|error| crate::CliError::BadInput(format!("cannot write {name}: {error}")))?;
            eprintln!("wrote {}", path.display());
        }
    }
    #[cfg(not(feature = "plot"))]
    let _ = args.out;
    Ok(())
}

//! `nearmiss paper`: the seed paper's experiments.

use crate::CommandResult;
use nearmiss_cli::report::{
    calibration_placements, paper_report_markdown, paper_rows, paper_timing, rotated_placements,
};
use std::path::PathBuf;

#[derive(clap::Args)]
pub struct Args {
    /// Repeats of the 90 timed tests.
    #[arg(long, default_value_t = 2000)]
    repeats: usize,
    /// Seed of the rotated placements.
    #[arg(long, default_value_t = 1)]
    seed: u64,
    /// The output folder.
    #[arg(short, long, default_value = "output")]
    out: PathBuf,
}

pub fn main(args: Args) -> CommandResult {
    let text = paper_report_markdown(
        &paper_rows(&calibration_placements()),
        &paper_rows(&rotated_placements(args.seed)),
        &paper_timing(args.repeats.max(1)),
    );
    print!("{text}");
    crate::write_report(&args.out.join("paper"), "paper.md", text.as_bytes())?;
    Ok(())
}

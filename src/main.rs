//! The `nearmiss` command line: parses arguments, calls the library, prints.

use clap::{Parser, Subcommand};
use std::process::ExitCode;

#[derive(Parser)]
#[command(name = "nearmiss", version, about = "Continuous collision detection for triangle meshes")]
struct Cli {
    #[command(subcommand)]
    command: Command,
}

#[derive(Subcommand)]
enum Command {
    /// Print each distance kernel's error against the exact rational
    /// reference, per input class, beside its rough time per query.
    Kernels {
        /// Inputs per class.
        #[arg(long, default_value_t = 500)]
        count: usize,
        /// Seed of the input generators.
        #[arg(long, default_value_t = 1)]
        seed: u64,
    },
}

fn main() -> ExitCode {
    let cli = match Cli::try_parse() {
        Ok(cli) => cli,
        Err(e) => {
            let code = if e.use_stderr() { 2 } else { 0 };
            let _ = e.print();
            return ExitCode::from(code);
        }
    };
    match cli.command {
        Command::Kernels { count, seed } => {
            let rows = nearmiss::report::kernel_report(count, seed);
            print!("{}", nearmiss::report::kernel_report_markdown(&rows));
        }
    }
    ExitCode::SUCCESS
}

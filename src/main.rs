//! The `nearmiss` command line: parses arguments, calls the library, prints.

use clap::{Parser, Subcommand, ValueEnum};
use nearmiss::ccd::CcdOptions;
use nearmiss::query_file::{query_files, run_file, QueryFile, QueryKind};
use std::path::PathBuf;
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
    /// Run CCD benchmark query files (files or folders): per file the
    /// queries, positives, false negatives, false positives, time per query,
    /// and, where exact times are known, whether any reported time was late.
    /// Exits 1 if any query was a false negative or late.
    Queries {
        /// Query files or folders (searched for `.csv`, `derived/` skipped).
        #[arg(required = true)]
        paths: Vec<PathBuf>,
        /// Treat every file as this kind instead of reading it from the path.
        #[arg(long, value_enum)]
        kind: Option<Kind>,
        /// Timed runs per file; the median is reported.
        #[arg(long, default_value_t = 3)]
        repeats: usize,
        /// Distance tolerance, relative to each query's size.
        #[arg(long, default_value_t = CcdOptions::default().distance_tolerance)]
        tolerance: f64,
        /// Most advancement steps per query.
        #[arg(long, default_value_t = CcdOptions::default().max_iterations)]
        max_iterations: usize,
    },
}

#[derive(Copy, Clone, ValueEnum)]
enum Kind {
    /// Edge–edge.
    Ee,
    /// Vertex–face.
    Vf,
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
        Command::Queries { paths, kind, repeats, tolerance, max_iterations } => {
            let kind = kind.map(|k| match k {
                Kind::Ee => QueryKind::EdgeEdge,
                Kind::Vf => QueryKind::VertexFace,
            });
            let options =
                CcdOptions { distance_tolerance: tolerance, max_iterations, ..CcdOptions::default() };
            return run_queries(&paths, kind, &options, repeats);
        }
    }
    ExitCode::SUCCESS
}

/// Loads every file first (bad input: exit 2, nothing run), then runs them.
fn run_queries(paths: &[PathBuf], kind: Option<QueryKind>, options: &CcdOptions, repeats: usize) -> ExitCode {
    let mut files = Vec::new();
    for path in paths {
        let found = match query_files(path) {
            Ok(found) => found,
            Err(error) => {
                eprintln!("error: {error}");
                return ExitCode::from(2);
            }
        };
        for file in found {
            // Inside a folder, a file whose path does not tell its kind is
            // skipped (with a warning); a file named on the command line is not.
            if kind.is_none() && path.is_dir() && !QueryFile::kind_is_known(&file) {
                eprintln!("warning: skipped {} (its path does not say edge-edge or vertex-face; name it with --kind)", file.display());
                continue;
            }
            match QueryFile::load(&file, kind) {
                Ok(loaded) => files.push(loaded),
                Err(error) => {
                    eprintln!("error: {error}");
                    return ExitCode::from(2);
                }
            }
        }
    }
    if files.is_empty() {
        eprintln!(
            "error: no query files (.csv) under {}",
            paths.iter().map(|p| p.display().to_string()).collect::<Vec<_>>().join(", ")
        );
        return ExitCode::from(2);
    }
    println!("| file | kind | queries | positives | false neg. | false pos. | out of iter. | mean µs | median µs | max µs | exact times checked | late |");
    println!("|---|---|---|---|---|---|---|---|---|---|---|---|");
    let mut failed = false;
    for file in &files {
        let r = run_file(file, options, repeats);
        failed |= r.false_negatives > 0 || r.late > 0;
        let truth = |n: usize| if r.unknown_truth == r.queries { "?".to_string() } else { n.to_string() };
        println!(
            "| {} | {} | {} | {} | {} | {} | {} | {:.2} | {:.2} | {:.1} | {} | {} |",
            file.path.display(),
            r.kind.short_name(),
            r.queries,
            truth(r.positives),
            truth(r.false_negatives),
            truth(r.false_positives),
            r.out_of_iterations,
            r.mean_microseconds,
            r.median_microseconds,
            r.max_microseconds,
            r.times_checked,
            r.late
        );
    }
    if failed {
        ExitCode::from(1)
    } else {
        ExitCode::SUCCESS
    }
}

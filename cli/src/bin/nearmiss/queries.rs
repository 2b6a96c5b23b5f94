//! `nearmiss queries`: the CCD benchmark format's query files.

use crate::{CliError, CommandResult};
use nearmiss::ccd::CcdOptions;
use nearmiss_cli::query_file::{query_files, QueryFile, QueryKind};
use nearmiss_cli::report::{query_row, query_table_header, run_file, QueriesShard, ShardFile};
use std::path::PathBuf;

#[derive(clap::Args)]
pub struct Args {
    /// Query files or folders (searched for `.csv`, `derived/` skipped).
    #[arg(required = true)]
    paths: Vec<PathBuf>,
    /// Treat every file as this kind instead of reading it from the path.
    #[arg(long, value_enum)]
    kind: Option<Kind>,
    /// Timed runs per file; the median is reported.
    #[arg(long, default_value_t = 3)]
    repeats: usize,
    /// Distance tolerance, relative to each query's size: in (0, 1).
    #[arg(long, default_value_t = CcdOptions::default().distance_tolerance)]
    tolerance: f64,
    /// Most advancement steps per query: at least 1.
    #[arg(long, default_value_t = CcdOptions::default().max_iterations)]
    max_iterations: usize,
    /// Run only share I of N of the files (1 ≤ I ≤ N; the files at
    /// positions k with k mod N = I − 1), for spreading a benchmark over
    /// machines. Needs `--json`.
    #[arg(long)]
    shard: Option<nearmiss_cli::report::Shard>,
    /// With `--shard`: write the shard's rows to this file, for `nearmiss merge`.
    #[arg(long)]
    json: Option<PathBuf>,
}

#[derive(Copy, Clone, clap::ValueEnum)]
enum Kind {
    /// Edge–edge.
    Ee,
    /// Vertex–face.
    Vf,
}

/// Loads every file first (bad input: exit 2, nothing run), then runs them.
pub fn main(args: Args) -> CommandResult {
    // A tolerance of the query's whole size or more makes every query a
    // contact; 0 or NaN none.
    if !(args.tolerance > 0.0 && args.tolerance < 1.0) {
        return Err(CliError::BadInput(format!(
            "--tolerance: {:?} is not a relative tolerance: give a number in (0, 1), such as 1e-6",
            args.tolerance
        )));
    }
    if args.max_iterations == 0 {
        return Err(CliError::BadInput("--max-iterations: give at least 1".into()));
    }
    if args.repeats == 0 {
        return Err(CliError::BadInput("--repeats: give at least 1 (the timed runs per file)".into()));
    }
    let kind = args.kind.map(|k| match k {
        Kind::Ee => QueryKind::EdgeEdge,
        Kind::Vf => QueryKind::VertexFace,
    });
    let options = CcdOptions {
        distance_tolerance: args.tolerance,
        max_iterations: args.max_iterations,
        ..CcdOptions::default()
    };
    if args.shard.is_some() != args.json.is_some() {
        return Err(CliError::BadInput(
            "--shard and --json go together (the shard's rows, for `nearmiss merge`)".into(),
        ));
    }
    let mut files = Vec::new();
    for path in &args.paths {
        let found = query_files(path).map_err(|error| CliError::BadInput(error.to_string()))?;
        for file in found {
            // Inside a folder, a file whose path does not tell its kind is
            // skipped (with a warning); a file named on the command line is not.
            if kind.is_none() && path.is_dir() && !QueryFile::kind_is_known(&file) {
                eprintln!("warning: skipped {} (its path does not say edge-edge or vertex-face; name it with --kind)", file.display());
                continue;
            }
            files.push(QueryFile::load(&file, kind).map_err(|error| CliError::BadInput(error.to_string()))?);
        }
    }
    if files.is_empty() {
        let paths: Vec<String> = args.paths.iter().map(|p| p.display().to_string()).collect();
        return Err(CliError::BadInput(format!("no query files (.csv) under {}", paths.join(", "))));
    }
    let total = files.len();
    let shard = args.shard;
    let mut rows = Vec::new();
    print!("{}", query_table_header());
    for (position, file) in files.iter().enumerate().filter(|(k, _)| shard.is_none_or(|s| s.picks(*k))) {
        let report = run_file(file, &options, args.repeats);
        print!("{}", query_row(&file.path, &report));
        rows.push((position, (file.path.display().to_string(), report)));
    }
    if let (Some(shard), Some(json)) = (shard, &args.json) {
        let text = ShardFile::Queries(QueriesShard { shard, total, files: rows.clone() }).to_json();
        crate::test::write_beside(json, &text)?;
        eprintln!("wrote {}", json.display());
    }
    let reports: Vec<_> = rows.into_iter().map(|(_, (_, report))| report).collect();
    print!("{}", nearmiss_cli::report::query_totals_row(&reports));
    verdict(&reports)
}

/// The exit of a query run: 1 if a file had a false negative or a late time.
pub fn verdict(reports: &[nearmiss_cli::report::FileReport]) -> CommandResult {
    let failed = reports.iter().filter(|r| r.false_negatives > 0 || r.late > 0).count();
    if failed > 0 {
        return Err(CliError::Failed(format!(
            "{} with a false negative or a late time",
            nearmiss_cli::text::count(failed as u64, "file")
        )));
    }
    Ok(())
}

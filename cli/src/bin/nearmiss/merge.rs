//! `nearmiss merge`: the shards of a `nearmiss test`, `queries` or `sweep`
//! run with `--shard I/N --json FILE` put back together: what one machine
//! would have printed and written (wall times apart).

use crate::test::{verdict, write_beside};
use crate::{CliError, CommandResult};
use nearmiss_cli::report::{
    case_line, count_line, junit_xml, merge_queries, merge_suite, merge_sweep, query_row, query_table_header,
    query_totals_row, suite_json, ShardFile,
};
use std::path::PathBuf;

#[derive(clap::Args)]
pub struct Args {
    /// The shards' JSON files (each from `nearmiss test`, `queries` or
    /// `sweep` with `--shard I/N --json FILE`; all of one run).
    #[arg(required = true)]
    shards: Vec<PathBuf>,
    /// Write the merged results as JSON to this file (`test` shards).
    #[arg(long)]
    json: Option<PathBuf>,
    /// Write the merged results as JUnit XML to this file (`test` shards).
    #[arg(long)]
    junit: Option<PathBuf>,
    /// The output folder of merged `sweep` shards: `<out>/<scene>/sweep.csv`
    /// and `error_vs_runtime.png`, as `nearmiss sweep` writes them.
    #[arg(long)]
    out: Option<PathBuf>,
}

pub fn main(args: Args) -> CommandResult {
    let (mut suites, mut queries, mut sweeps) = (Vec::new(), Vec::new(), Vec::new());
    for path in &args.shards {
        let text = std::fs::read_to_string(path)
            .map_err(|error| CliError::BadInput(format!("{}: {error}", path.display())))?;
        let shard: ShardFile = serde_json::from_str(&text).map_err(|error| {
            CliError::BadInput(format!(
                "{}: not a shard file of `nearmiss test`, `queries` or `sweep` with --shard (line {}, column {}: {error})",
                path.display(),
                error.line(),
                error.column()
            ))
        })?;
        match shard {
            ShardFile::Suite(shard) => suites.push(shard),
            ShardFile::Queries(shard) => queries.push(shard),
            ShardFile::Sweep(shard) => sweeps.push(shard),
        }
    }
    let kinds = [suites.is_empty(), queries.is_empty(), sweeps.is_empty()];
    if kinds.iter().filter(|empty| !**empty).count() > 1 {
        return Err(CliError::BadInput(
            "the shards mix `test`, `queries` and `sweep` runs: merge each run apart".into(),
        ));
    }
    if (sweeps.is_empty() && args.out.is_some())
        || (!sweeps.is_empty() && (args.json.is_some() || args.junit.is_some()))
    {
        return Err(CliError::BadInput(
            "--out merges `sweep` shards; --json and --junit merge `test` shards".into(),
        ));
    }
    if !sweeps.is_empty() {
        let report = merge_sweep(&sweeps).map_err(CliError::BadInput)?;
        let out = args.out.unwrap_or_else(|| PathBuf::from("output"));
        return crate::sweep::write_sweep(&report, &out);
    }
    if !queries.is_empty() {
        if args.json.is_some() || args.junit.is_some() {
            return Err(CliError::BadInput(
                "--json and --junit merge `test` shards; `queries` prints its table".into(),
            ));
        }
        let files = merge_queries(&queries).map_err(CliError::BadInput)?;
        print!("{}", query_table_header());
        for (path, report) in &files {
            print!("{}", query_row(std::path::Path::new(path), report));
        }
        let reports: Vec<_> = files.into_iter().map(|(_, report)| report).collect();
        print!("{}", query_totals_row(&reports));
        return crate::queries::verdict(&reports);
    }
    let cases = merge_suite(&suites).map_err(CliError::BadInput)?;
    for line in cases.iter().map(case_line) {
        println!("{line}");
    }
    for (report, text) in [(&args.junit, junit_xml(&cases)), (&args.json, suite_json(&cases))] {
        if let Some(path) = report {
            write_beside(path, &text)?;
            eprintln!("wrote {}", path.display());
        }
    }
    println!("{}", count_line(&cases));
    verdict(&cases)
}

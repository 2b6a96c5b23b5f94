//! `nearmiss merge`: the shards of a `nearmiss test --shard I/N --json` or
//! `nearmiss queries --shard I/N --json` run put back together: what one
//! machine would have printed and written (wall times apart).

use crate::test::{verdict, write_beside};
use crate::{CliError, CommandResult};
use nearmiss::report::{
    case_line, count_line, junit_xml, merge_queries, merge_suite, query_row, query_table_header, suite_json,
    ShardFile,
};
use std::path::PathBuf;

#[derive(clap::Args)]
pub struct Args {
    /// The shards' JSON files (each from `nearmiss test` or `nearmiss
    /// queries` with `--shard I/N --json FILE`; all of one run).
    #[arg(required = true)]
    shards: Vec<PathBuf>,
    /// Write the merged results as JSON to this file (`test` shards).
    #[arg(long)]
    json: Option<PathBuf>,
    /// Write the merged results as JUnit XML to this file (`test` shards).
    #[arg(long)]
    junit: Option<PathBuf>,
}

pub fn main(args: Args) -> CommandResult {
    let (mut suites, mut queries) = (Vec::new(), Vec::new());
    for path in &args.shards {
        let text = std::fs::read_to_string(path)
            .map_err(|error| CliError::BadInput(format!("{}: {error}", path.display())))?;
        let shard: ShardFile = serde_json::from_str(&text).map_err(|error| {
            CliError::BadInput(format!(
                "{}: not a shard file of `nearmiss test` or `queries` with --shard (line {}, column {}: {error})",
                path.display(),
                error.line(),
                error.column()
            ))
        })?;
        match shard {
            ShardFile::Suite(shard) => suites.push(shard),
            ShardFile::Queries(shard) => queries.push(shard),
        }
    }
    if !suites.is_empty() && !queries.is_empty() {
        return Err(CliError::BadInput(
            "the shards mix `test` and `queries` runs: merge each run apart".into(),
        ));
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
        return crate::queries::verdict(&reports);
    }
    let cases = merge_suite(&suites).map_err(CliError::BadInput)?;
    for line in cases.iter().filter_map(case_line) {
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

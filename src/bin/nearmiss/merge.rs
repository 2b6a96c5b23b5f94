//! `nearmiss merge`: the shards of a `nearmiss test --shard I/N --json`
//! run put back together: the lines, the count line and the JSON and JUnit
//! reports one machine would have written (wall times apart).

use crate::test::{verdict, write_beside};
use crate::{CliError, CommandResult};
use nearmiss::report::{case_line, count_line, junit_xml, merge_suite, suite_json, SuiteShard};
use std::path::PathBuf;

#[derive(clap::Args)]
pub struct Args {
    /// The shards' JSON files (each from `nearmiss test --shard I/N --json FILE`).
    #[arg(required = true)]
    shards: Vec<PathBuf>,
    /// Write the merged results as JSON to this file.
    #[arg(long)]
    json: Option<PathBuf>,
    /// Write the merged results as JUnit XML to this file.
    #[arg(long)]
    junit: Option<PathBuf>,
}

pub fn main(args: Args) -> CommandResult {
    let mut shards = Vec::with_capacity(args.shards.len());
    for path in &args.shards {
        let text = std::fs::read_to_string(path)
            .map_err(|error| CliError::BadInput(format!("{}: {error}", path.display())))?;
        let shard: SuiteShard = serde_json::from_str(&text).map_err(|error| {
            CliError::BadInput(format!(
                "{}: not a shard of `nearmiss test --shard I/N --json` (line {}, column {}: {error})",
                path.display(),
                error.line(),
                error.column()
            ))
        })?;
        shards.push(shard);
    }
    let cases = merge_suite(&shards).map_err(CliError::BadInput)?;
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

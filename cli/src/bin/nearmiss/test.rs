//! `nearmiss test`: every scene with an expectation, run in parallel, one
//! line each in file order, a closing count line, and optionally JUnit XML
//! and JSON reports for CI systems.

use crate::{CliError, CommandResult};
use nearmiss_cli::regression::Recorded;
use nearmiss_cli::report::{
    case_line, count_line, junit_xml, run_case, suite_counts, suite_json, ShardFile, SuiteCase, SuiteShard,
};
use std::path::{Path, PathBuf};

#[derive(clap::Args)]
pub struct Args {
    /// Scene files or folders.
    #[arg(required = true)]
    paths: Vec<PathBuf>,
    /// The most steps a run may take (a longer one is refused before it
    /// starts: usually a typo in `dt` or `duration`).
    #[arg(long, default_value_t = nearmiss::scene::DEFAULT_MAX_STEPS)]
    max_steps: u64,
    /// Also write the results as JUnit XML to this file (GitLab, Jenkins,
    /// GitHub: one test case per scene with expected, obtained and error).
    #[arg(long)]
    junit: Option<PathBuf>,
    /// Also write the results as JSON to this file.
    #[arg(long)]
    json: Option<PathBuf>,
    /// Scenes run at once (default: one per core).
    #[arg(short, long)]
    jobs: Option<usize>,
    /// First pin each scene's current answer as its expectation, marked as
    /// recorded (scenes whose expectation was derived are left alone), then
    /// test as usual.
    #[arg(long)]
    record: bool,
    /// Run only share I of N of the scenes (1 ≤ I ≤ N; the scenes at
    /// positions k with k mod N = I − 1 of the sorted list), for spreading
    /// a suite over machines. Needs `--json`, which then writes the shard's
    /// results for `nearmiss merge`.
    #[arg(long)]
    shard: Option<nearmiss_cli::report::Shard>,
}

pub fn main(args: Args) -> CommandResult {
    let mut files = Vec::new();
    for path in &args.paths {
        let found = nearmiss_cli::regression::scene_files(path)
            .map_err(|error| CliError::BadInput(format!("{}: {error}", path.display())))?;
        files.extend(found);
    }
    if args.jobs == Some(0) {
        return Err(CliError::BadInput("--jobs: give at least 1".into()));
    }
    if args.shard.is_some() && args.json.is_none() {
        return Err(CliError::BadInput(
            "--shard: give --json FILE too (the shard's results, for `nearmiss merge`)".into(),
        ));
    }
    let total = files.len();
    let positions: Vec<usize> = match args.shard {
        Some(shard) => (0..total).filter(|&k| shard.picks(k)).collect(),
        None => (0..total).collect(),
    };
    let files: Vec<PathBuf> = positions.iter().map(|&k| files[k].clone()).collect();
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(args.jobs.unwrap_or(0))
        .build()
        .map_err(|error| CliError::BadInput(format!("--jobs: {error}")))?;
    if args.record {
        let mut not_recorded = 0;
        for file in &files {
            match nearmiss_cli::regression::record(file, args.max_steps) {
                Ok(Recorded::Pinned(words)) => println!("recorded {}: {words}", file.display()),
                Ok(Recorded::KeptDerived) => {
                    println!("kept {}: its expectation is derived, not recorded over", file.display())
                }
                Err(message) => {
                    eprintln!("error: {message}");
                    not_recorded += 1;
                }
            }
        }
        if not_recorded > 0 {
            return Err(CliError::Failed(format!(
                "{} not recorded (above); nothing was tested",
                nearmiss_cli::text::count(not_recorded as u64, "scene")
            )));
        }
    }
    let cases = run_in_order(&pool, &files, args.max_steps);
    let json = match args.shard {
        Some(shard) => ShardFile::Suite(SuiteShard {
            shard,
            total,
            cases: positions.into_iter().zip(cases.iter().cloned()).collect(),
        })
        .to_json(),
        None => suite_json(&cases),
    };
    for (report, text) in [(&args.junit, junit_xml(&cases)), (&args.json, json)] {
        if let Some(path) = report {
            write_beside(path, &text)?;
            eprintln!("wrote {}", path.display());
        }
    }
    println!("{}", count_line(&cases));
    verdict(&cases)
}

/// Runs the scenes on `pool` and prints each one's line as soon as it and
/// every scene before it are done, so the lines come in file order (each
/// scene's result is the same whatever runs beside it: runs are
/// deterministic) and a long suite shows its progress.
fn run_in_order(pool: &rayon::ThreadPool, files: &[PathBuf], max_steps: u64) -> Vec<SuiteCase> {
    eprintln!(
        "running {} on {}",
        nearmiss_cli::text::count(files.len() as u64, "scene"),
        nearmiss_cli::text::count(pool.current_num_threads() as u64, "thread")
    );
    let mut slots: Vec<Option<SuiteCase>> = vec![None; files.len()];
    let (sender, receiver) = std::sync::mpsc::channel();
    pool.in_place_scope(|scope| {
        for (k, file) in files.iter().enumerate() {
            let sender = sender.clone();
            scope.spawn(move |_| {
                // The receiver lives until every scene has reported.
                let _ = sender.send((k, run_case(file, max_steps)));
            });
        }
        drop(sender);
        let mut next = 0;
        for (k, case) in receiver {
            slots[k] = Some(case);
            while let Some(Some(case)) = slots.get(next) {
                println!("{}", case_line(case));
                next += 1;
            }
        }
    });
    slots.into_iter().map(|case| case.expect("every scene reported")).collect()
}

/// The exit of a suite: 2 if a scene was bad, 1 if one failed.
pub fn verdict(cases: &[nearmiss_cli::report::SuiteCase]) -> CommandResult {
    let (_, failed, bad, _) = suite_counts(cases);
    if bad > 0 {
        Err(CliError::BadInput(format!(
            "{} could not be loaded",
            nearmiss_cli::text::count(bad as u64, "scene")
        )))
    } else if failed > 0 {
        Err(CliError::Failed(String::new()))
    } else {
        Ok(())
    }
}

/// Writes a report file whole (its folder created if needed).
pub fn write_beside(path: &Path, text: &str) -> Result<(), CliError> {
    let folder = path.parent().filter(|p| !p.as_os_str().is_empty()).unwrap_or(Path::new("."));
    let name = path.file_name().map(|n| n.to_string_lossy().into_owned()).unwrap_or_default();
    crate::write_report(folder, &name, text.as_bytes()).map(|_| ())
}

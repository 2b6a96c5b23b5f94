//! The CCD benchmark runner: every query of a file ([`crate::query_file`])
//! timed, counted against its ground truth (false negatives must be 0) and,
//! where exact times are known, checked for late answers; and the Markdown
//! table `nearmiss queries` prints.

use std::time::Instant;

use crate::query_file::{QueryFile, QueryKind};
use nearmiss::ccd::CcdOptions;
use nearmiss::math::Real;

/// What running one file gave.
#[derive(Clone, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct FileReport {
    /// Edge–edge or vertex–face.
    pub kind: QueryKind,
    /// Number of queries.
    pub queries: usize,
    /// Queries whose ground truth is a contact.
    pub positives: usize,
    /// Contacts that were reported as none (must be 0).
    pub false_negatives: usize,
    /// Non-contacts that were reported as contacts.
    pub false_positives: usize,
    /// Queries with no ground truth.
    pub unknown_truth: usize,
    /// Queries that ran out of iterations.
    pub out_of_iterations: usize,
    /// Median over repeats of the mean time per query, in microseconds.
    pub mean_microseconds: Real,
    /// Median over queries of the time per query (last repeat), µs.
    pub median_microseconds: Real,
    /// The slowest query (last repeat), µs.
    pub max_microseconds: Real,
    /// Positive queries with a known exact time, and how many reported
    /// times were later than its lower bound (must be 0).
    pub times_checked: usize,
    /// Reported times later than `toi_f64_lo` (must be 0).
    pub late: usize,
}

/// Runs every query of `file` `repeats` times (at least once).
pub fn run_file(file: &QueryFile, options: &CcdOptions, repeats: usize) -> FileReport {
    let mut means = Vec::new();
    let mut per_query = vec![0.0; file.queries.len()];
    let mut results = Vec::with_capacity(file.queries.len());
    for _ in 0..repeats.max(1) {
        results.clear();
        let start = Instant::now();
        for (query, time) in file.queries.iter().zip(per_query.iter_mut()) {
            let one = Instant::now();
            results.push(query.run(file.kind, options));
            *time = one.elapsed().as_secs_f64() * 1e6;
        }
        means.push(start.elapsed().as_secs_f64() * 1e6 / file.queries.len().max(1) as Real);
    }
    let mut report = FileReport {
        kind: file.kind,
        queries: file.queries.len(),
        positives: 0,
        false_negatives: 0,
        false_positives: 0,
        unknown_truth: 0,
        out_of_iterations: 0,
        mean_microseconds: median(&mut means),
        median_microseconds: median(&mut per_query.clone()),
        max_microseconds: per_query.iter().copied().fold(0.0, Real::max),
        times_checked: 0,
        late: 0,
    };
    for (i, (query, result)) in file.queries.iter().zip(&results).enumerate() {
        let reported = result.time_of_impact.is_some();
        report.out_of_iterations += usize::from(result.status == nearmiss::ccd::CcdStatus::OutOfIterations);
        match query.truth {
            Some(true) => {
                report.positives += 1;
                report.false_negatives += usize::from(!reported);
            }
            Some(false) => report.false_positives += usize::from(reported),
            None => report.unknown_truth += 1,
        }
        if let (Some(bounds), Some(time)) = (&file.exact_time_lower_bounds, result.time_of_impact) {
            if let Some(lower) = bounds.get(i).copied().flatten() {
                report.times_checked += 1;
                report.late += usize::from(time > lower);
            }
        }
    }
    report
}

fn median(values: &mut [Real]) -> Real {
    values.sort_by(|a, b| a.total_cmp(b));
    values.get(values.len() / 2).copied().unwrap_or(0.0)
}

/// The header of the table of [`query_row`]s.
pub fn query_table_header() -> &'static str {
    "| file | kind | queries | positives | false neg. | false pos. | out of iter. | mean µs | median µs | max µs | exact times checked | late |\n|---|---|---|---|---|---|---|---|---|---|---|---|\n"
}

/// The closing Markdown row: every file's counts summed (positives and
/// false results over the files whose truth is known), the mean time per
/// query over all queries, the largest time; no median across files.
pub fn query_totals_row(reports: &[FileReport]) -> String {
    let sum = |f: fn(&FileReport) -> usize| reports.iter().map(f).sum::<usize>();
    let known: Vec<&FileReport> = reports.iter().filter(|r| r.unknown_truth < r.queries).collect();
    let known_sum = |f: fn(&FileReport) -> usize| {
        if known.is_empty() {
            "?".to_string()
        } else {
            known.iter().map(|r| f(r)).sum::<usize>().to_string()
        }
    };
    let queries = sum(|r| r.queries);
    let mean = reports.iter().map(|r| r.mean_microseconds * r.queries as Real).sum::<Real>()
        / queries.max(1) as Real;
    let max = reports.iter().map(|r| r.max_microseconds).fold(0.0, Real::max);
    format!(
        "| **all {}** | | {} | {} | {} | {} | {} | {:.2} | | {:.1} | {} | {} |\n",
        crate::text::count(reports.len() as u64, "file"),
        queries,
        known_sum(|r| r.positives),
        known_sum(|r| r.false_negatives),
        known_sum(|r| r.false_positives),
        sum(|r| r.out_of_iterations),
        mean,
        max,
        sum(|r| r.times_checked),
        sum(|r| r.late)
    )
}

/// One Markdown row: the report of the file at `path`.
pub fn query_row(path: &std::path::Path, r: &FileReport) -> String {
    let truth = |n: usize| if r.unknown_truth == r.queries { "?".to_string() } else { n.to_string() };
    format!(
        "| {} | {} | {} | {} | {} | {} | {} | {:.2} | {:.2} | {:.1} | {} | {} |\n",
        path.display(),
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
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    fn report(
        queries: usize,
        positives: usize,
        false_positives: usize,
        unknown: usize,
        mean: Real,
    ) -> FileReport {
        FileReport {
            kind: QueryKind::EdgeEdge,
            queries,
            positives,
            false_negatives: 0,
            false_positives,
            unknown_truth: unknown,
            out_of_iterations: 1,
            mean_microseconds: mean,
            median_microseconds: mean,
            max_microseconds: 2.0 * mean,
            times_checked: positives,
            late: 0,
        }
    }

    /// Counts summed, truths only over files that know them, the mean
    /// weighted by each file's queries.
    #[test]
    fn the_totals_row_sums_what_adds_up() {
        let rows = [report(100, 10, 3, 0, 1.0), report(300, 20, 5, 0, 3.0), report(50, 0, 0, 50, 9.0)];
        assert_eq!(
            query_totals_row(&rows),
            "| **all 3 files** | | 450 | 30 | 0 | 8 | 3 | 3.22 | | 18.0 | 30 | 0 |\n"
        );
        assert!(query_totals_row(&rows[2..]).starts_with("| **all 1 file** | | 50 | ? | ? | ? |"));
    }
}

//! Lists the queries of a benchmark file that are false negatives, late, or out of iterations (debugging aid).
use nearmiss::ccd::CcdOptions;
use nearmiss_cli::query_file::QueryFile;
use std::path::Path;
fn main() {
    let args: Vec<String> = std::env::args().collect();
    let file = QueryFile::load(Path::new(&args[1]), None).expect("loads");
    let tolerance: f64 = args.get(2).and_then(|t| t.parse().ok()).unwrap_or(1e-6);
    let options = CcdOptions { distance_tolerance: tolerance, ..CcdOptions::default() };
    let mut shown = 0;
    for (i, q) in file.queries.iter().enumerate() {
        let r = q.run(file.kind, &options);
        let lower = file.exact_time_lower_bounds.as_ref().and_then(|b| b[i]);
        let fn_ = q.truth == Some(true) && r.time_of_impact.is_none();
        let late = matches!((r.time_of_impact, lower), (Some(t), Some(l)) if t > l);
        let capped = r.status == nearmiss::ccd::CcdStatus::OutOfIterations;
        if (fn_ || late || capped) && shown < 6 {
            shown += 1;
            println!("query {i}: {:?} exact lower {:?}\n  points {:?}", r, lower, q.points);
        }
    }
}

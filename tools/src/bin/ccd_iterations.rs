//! Total advancement steps and statuses over a benchmark file (debugging aid).
use nearmiss::ccd::CcdOptions;
use nearmiss_cli::query_file::QueryFile;
use std::collections::BTreeMap;
use std::path::Path;
fn main() {
    let path = std::env::args().nth(1).expect("a query file");
    let file = QueryFile::load(Path::new(&path), None).expect("loads");
    let mut steps = 0;
    let mut statuses = BTreeMap::new();
    for q in &file.queries {
        let r = q.run(file.kind, &CcdOptions::default());
        steps += r.iterations;
        *statuses.entry(format!("{:?}", r.status)).or_insert(0) += 1;
    }
    println!("{} queries, {steps} steps, {statuses:?}", file.queries.len());
}

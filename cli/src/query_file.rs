//! Reader for the public CCD benchmark format (Wang et al.,
//! "A Large Scale Benchmark and an Inclusion-Based Algorithm for Continuous
//! Collision Detection", 2021; format and a vendored copy in `tests/data/ccd-sample-queries`).
//!
//! A query file is CSV without header, 8 rows per query (one vertex per
//! row: `ea0_t0, ea1_t0, eb0_t0, eb1_t0, ea0_t1, ...` for edge–edge,
//! `v_t0, f0_t0, f1_t0, f2_t0, v_t1, ...` for vertex–face), each row
//! `xn,xd,yn,yd,zn,zd[,truth]` with every coordinate the exact rational
//! `n/d` (integers beyond 64 bits). Coordinates are converted to f64
//! exactly, or the file is rejected. Ground truth comes from the 7th column
//! or from the `mma_bool` JSON beside the queries; exact times of impact,
//! where known, from `derived/.../<stem>_toi.csv`. The runner that measures
//! a file is [`crate::report::run_file`].

use nearmiss::ccd::{
    edge_edge_time_of_impact_detailed, vertex_face_time_of_impact_detailed, CcdOptions, CcdResult,
};
use nearmiss::math::{Point, Real};
use num_bigint::BigInt;
use num_rational::BigRational;
use num_traits::{FromPrimitive, Signed, ToPrimitive, Zero};
use std::path::{Path, PathBuf};
use std::str::FromStr;

/// Edge–edge or vertex–face.
#[derive(Copy, Clone, Debug, PartialEq, Eq, Hash, serde::Serialize, serde::Deserialize)]
pub enum QueryKind {
    /// Two edges: rows `ea0, ea1, eb0, eb1` at t0 then t1.
    EdgeEdge,
    /// A vertex and a face: rows `v, f0, f1, f2` at t0 then t1.
    VertexFace,
}

impl QueryKind {
    /// `"EE"` or `"VF"`.
    pub fn short_name(self) -> &'static str {
        match self {
            QueryKind::EdgeEdge => "EE",
            QueryKind::VertexFace => "VF",
        }
    }
}

/// One query: 8 points (4 at t0, then 4 at t1) and its ground truth.
#[derive(Clone, Debug, PartialEq)]
pub struct Query {
    /// The 8 vertices in file order.
    pub points: [Point; 8],
    /// Whether the primitives touch in the closed step, if known.
    pub truth: Option<bool>,
}

impl Query {
    /// Runs the CCD query.
    pub fn run(&self, kind: QueryKind, options: &CcdOptions) -> CcdResult {
        let p = &self.points;
        match kind {
            QueryKind::EdgeEdge => edge_edge_time_of_impact_detailed(
                &[p[0], p[1]],
                &[p[2], p[3]],
                &[p[4], p[5]],
                &[p[6], p[7]],
                options,
            ),
            QueryKind::VertexFace => vertex_face_time_of_impact_detailed(
                &p[0],
                &[p[1], p[2], p[3]],
                &p[4],
                &[p[5], p[6], p[7]],
                options,
            ),
        }
    }
}

/// A loaded query file.
#[derive(Clone, Debug)]
pub struct QueryFile {
    /// Where it was read from.
    pub path: PathBuf,
    /// Edge–edge or vertex–face.
    pub kind: QueryKind,
    /// The queries, in file order.
    pub queries: Vec<Query>,
    /// For each query, the largest f64 not above its exact first time of
    /// impact (`toi_f64_lo`), where a `derived/` table gives it.
    pub exact_time_lower_bounds: Option<Vec<Option<Real>>>,
}

/// Why a query file could not be read.
#[derive(Debug, thiserror::Error)]
pub enum QueryFileError {
    /// The file could not be read.
    #[error("{path}: {source}")]
    Io {
        /// The file.
        path: PathBuf,
        /// The I/O error.
        source: std::io::Error,
    },
    /// A line is malformed.
    #[error("{path}:{line}:{column}: {message}")]
    Syntax {
        /// The file.
        path: PathBuf,
        /// 1-based line.
        line: usize,
        /// 1-based column (token number).
        column: usize,
        /// What is wrong.
        message: String,
    },
    /// Anything else about the file (its kind, its ground truth).
    #[error("{path}: {message}")]
    File {
        /// The file.
        path: PathBuf,
        /// What is wrong.
        message: String,
    },
}

impl QueryFile {
    /// Whether the path alone tells the file's kind (see [`QueryFile::load`]).
    pub fn kind_is_known(path: &Path) -> bool {
        kind_from_path(path).is_some()
    }

    /// Reads a query file; `kind` overrides the kind read from the path
    /// (an `edge-edge`/`vertex-face` folder, or an `ee`/`vf` name suffix).
    pub fn load(path: &Path, kind: Option<QueryKind>) -> Result<QueryFile, QueryFileError> {
        let text = read_data(path)?;
        let kind = match kind.or_else(|| kind_from_path(path)) {
            Some(kind) => kind,
            None => {
                return Err(QueryFileError::File {
                    path: path.into(),
                    message: "cannot tell edge-edge from vertex-face queries: put the file under an \
                              `edge-edge` or `vertex-face` folder, end its name in `ee` or `vf`, or pass --kind"
                        .into(),
                })
            }
        };
        let syntax = |line: usize, column: usize, message: String| QueryFileError::Syntax {
            path: path.into(),
            line,
            column,
            message,
        };
        let mut rows: Vec<(usize, Point, Option<bool>)> = Vec::new();
        for (index, line) in text.lines().enumerate() {
            let trimmed = line.trim();
            if trimmed.is_empty() || trimmed.starts_with('#') {
                continue;
            }
            let tokens: Vec<&str> = trimmed.split(',').map(str::trim).collect();
            if tokens.len() != 6 && tokens.len() != 7 {
                return Err(syntax(
                    index + 1,
                    1,
                    format!("expected 6 or 7 comma-separated values, found {}", tokens.len()),
                ));
            }
            let mut coordinates = [0.0; 3];
            for (axis, coordinate) in coordinates.iter_mut().enumerate() {
                let (n, d) = (tokens[2 * axis], tokens[2 * axis + 1]);
                *coordinate = exact_f64(n, d).map_err(|message| syntax(index + 1, 2 * axis + 1, message))?;
            }
            let truth = match tokens.get(6) {
                None => None,
                Some(&"0") => Some(false),
                Some(&"1") => Some(true),
                Some(other) => {
                    return Err(syntax(index + 1, 7, format!("ground truth must be 0 or 1, found `{other}`")))
                }
            };
            rows.push((index + 1, Point::new(coordinates[0], coordinates[1], coordinates[2]), truth));
        }
        if rows.is_empty() {
            return Err(syntax(1, 1, "no queries: the file is empty or holds only comments".into()));
        }
        if rows.len() % 8 != 0 {
            let line = rows.last().map_or(1, |r| r.0);
            return Err(syntax(
                line,
                1,
                format!("{} vertex rows is not a multiple of 8 (8 rows per query)", rows.len()),
            ));
        }
        let mut queries = Vec::with_capacity(rows.len() / 8);
        for chunk in rows.chunks_exact(8) {
            let truth = chunk[0].2;
            if let Some(row) = chunk.iter().find(|r| r.2 != truth) {
                return Err(syntax(
                    row.0,
                    7,
                    "the ground truth differs between the 8 rows of one query".into(),
                ));
            }
            queries.push(Query { points: std::array::from_fn(|i| chunk[i].1), truth });
        }
        if queries.iter().all(|q| q.truth.is_none()) {
            if let Some(truths) = read_truth_json(path, queries.len())? {
                for (query, truth) in queries.iter_mut().zip(truths) {
                    query.truth = Some(truth);
                }
            }
        }
        let exact_time_lower_bounds = read_derived_times(path, queries.len())?;
        Ok(QueryFile { path: path.into(), kind, queries, exact_time_lower_bounds })
    }
}

/// The kind named by the path: an `edge-edge`/`vertex-face` folder, or a
/// file stem ending in `ee`/`vf`.
/// A query, truth or time file as text (regular files only, bounded size).
fn read_data(path: &Path) -> Result<String, QueryFileError> {
    nearmiss::scene::read_text(path, nearmiss::scene::MAX_DATA_BYTES, "query file")
        .map_err(|error| QueryFileError::Io { path: path.into(), source: error.into_io() })
}

fn kind_from_path(path: &Path) -> Option<QueryKind> {
    for component in path.components().rev() {
        match component.as_os_str().to_str() {
            Some("edge-edge") => return Some(QueryKind::EdgeEdge),
            Some("vertex-face") => return Some(QueryKind::VertexFace),
            _ => {}
        }
    }
    let stem = path.file_stem()?.to_str()?;
    if stem.ends_with("ee") {
        Some(QueryKind::EdgeEdge)
    } else if stem.ends_with("vf") {
        Some(QueryKind::VertexFace)
    } else {
        None
    }
}

/// `n / d` as an f64, exactly, or why not.
fn exact_f64(n: &str, d: &str) -> Result<Real, String> {
    // Fast path: both fit in i128, d is a power of two (every file here)
    // and n has at most 53 significant bits, so `n as f64` is exact (a
    // wider n, such as 2^127 − 1, would round, and casting back saturates:
    // the exact path below decides it).
    if let (Ok(n), Ok(d)) = (n.parse::<i128>(), d.parse::<i128>()) {
        let significant = n.unsigned_abs() >> n.unsigned_abs().trailing_zeros().min(127);
        if d > 0 && d.count_ones() == 1 && significant < (1u128 << 53) {
            let exponent = d.trailing_zeros() as i32;
            let whole = n as Real;
            let value = whole * (2.0 as Real).powi(-exponent);
            // Exact iff scaling back recovers n (rules out underflow).
            if n == 0 || (value != 0.0 && value * (2.0 as Real).powi(exponent) == whole) {
                return Ok(value);
            }
        }
    }
    let parse = |s: &str| BigInt::from_str(s).map_err(|_| format!("`{s}` is not an integer"));
    let (n, d) = (parse(n)?, parse(d)?);
    if d.is_zero() {
        return Err("zero denominator".into());
    }
    if d.is_negative() {
        return Err(format!("negative denominator `{d}`"));
    }
    let ratio = BigRational::new(n, d);
    let value =
        ratio.to_f64().filter(|v| v.is_finite()).ok_or_else(|| format!("{ratio} is out of f64 range"))?;
    match BigRational::from_f64(value) {
        Some(back) if back == ratio => Ok(value),
        _ => Err(format!("{ratio} is not exactly representable as an f64")),
    }
}

/// Ground truth from `mma_bool.json` beside the file, or from
/// `../mma_bool/<stem>_mma_bool.json`; `None` if neither exists.
fn read_truth_json(path: &Path, count: usize) -> Result<Option<Vec<bool>>, QueryFileError> {
    let directory = path.parent().unwrap_or(Path::new("."));
    let stem = path.file_stem().and_then(|s| s.to_str()).unwrap_or_default();
    let candidates = [
        directory.join("mma_bool.json"),
        directory.join("..").join("mma_bool").join(format!("{stem}_mma_bool.json")),
    ];
    let Some(json_path) = candidates.iter().find(|p| p.is_file()) else {
        return Ok(None);
    };
    let bad = |message: String| QueryFileError::File { path: json_path.clone(), message };
    let text = read_data(json_path)?;
    let body = text.trim();
    let inner = body
        .strip_prefix('[')
        .and_then(|b| b.strip_suffix(']'))
        .ok_or_else(|| bad("expected a JSON array of booleans".into()))?;
    let truths = inner
        .split(',')
        .map(str::trim)
        .filter(|t| !t.is_empty())
        .enumerate()
        .map(|(i, t)| match t {
            "true" => Ok(true),
            "false" => Ok(false),
            other => Err(bad(format!("entry {i} is `{other}`, not true or false"))),
        })
        .collect::<Result<Vec<bool>, _>>()?;
    if truths.len() != count {
        return Err(bad(format!("{} entries for {count} queries in {}", truths.len(), path.display())));
    }
    Ok(Some(truths))
}

/// `toi_f64_lo` per query from `<root>/derived/<scene path>/<stem>_toi.csv`,
/// where `<root>` is the nearest ancestor with a `derived` folder and the
/// scene path is the file's grandparent relative to it.
fn read_derived_times(path: &Path, count: usize) -> Result<Option<Vec<Option<Real>>>, QueryFileError> {
    let absolute = match path.canonicalize() {
        Ok(p) => p,
        Err(_) => return Ok(None),
    };
    let (Some(scene), Some(stem)) =
        (absolute.parent().and_then(Path::parent), absolute.file_stem().and_then(|s| s.to_str()))
    else {
        return Ok(None);
    };
    let Some(root) = scene.ancestors().find(|a| a.join("derived").is_dir()) else {
        return Ok(None);
    };
    let Ok(relative) = scene.strip_prefix(root) else {
        return Ok(None);
    };
    let table = root.join("derived").join(relative).join(format!("{stem}_toi.csv"));
    if !table.is_file() {
        return Ok(None);
    }
    let text = read_data(&table)?;
    let mut times = vec![None; count];
    for (index, line) in text.lines().enumerate().skip(1) {
        let tokens: Vec<&str> = line.split(',').map(str::trim).collect();
        let syntax = |message: String| QueryFileError::Syntax {
            path: table.clone(),
            line: index + 1,
            column: 1,
            message,
        };
        let query: usize =
            tokens.first().and_then(|t| t.parse().ok()).ok_or_else(|| syntax("bad query index".into()))?;
        let lower: Real =
            tokens.get(2).and_then(|t| t.parse().ok()).ok_or_else(|| syntax("bad toi_f64_lo".into()))?;
        *times
            .get_mut(query)
            .ok_or_else(|| syntax(format!("query {query} out of range ({count} queries)")))? = Some(lower);
    }
    Ok(Some(times))
}

/// The query files under `path` (itself if a file): every `.csv` except the
/// `derived/` tables, sorted.
pub fn query_files(path: &Path) -> Result<Vec<PathBuf>, QueryFileError> {
    if path.is_file() {
        return Ok(vec![path.into()]);
    }
    let mut found = Vec::new();
    let mut stack = vec![path.to_path_buf()];
    while let Some(directory) = stack.pop() {
        let entries = std::fs::read_dir(&directory)
            .map_err(|source| QueryFileError::Io { path: directory.clone(), source })?;
        for entry in entries {
            let entry = entry.map_err(|source| QueryFileError::Io { path: directory.clone(), source })?;
            let p = entry.path();
            if p.is_dir() {
                if p.file_name().and_then(|n| n.to_str()) != Some("derived") {
                    stack.push(p);
                }
            } else if p.extension().and_then(|e| e.to_str()) == Some("csv") {
                found.push(p);
            }
        }
    }
    found.sort();
    Ok(found)
}

//! The kernel report: each kernel's error against the exact rational
//! reference on each [`InputClass`], beside its time per query.
//!
//! Times here are rough (a timed loop, best of a few repeats) and only meant
//! to place kernels on an error-versus-time chart; the benchmark numbers
//! quoted in `BENCHMARKS.md` come from criterion (`cargo bench`).

use nearmiss::exact;
use nearmiss::kernels::{dyop_distance, point_segment_distance, triangle_distance, PointEdgeFormula};
use nearmiss::math::{Point, Real, Triangle};
use nearmiss::samples::{
    pair_extent, parry_triangle_distance, point_segment_queries, query_extent, triangle_pairs, InputClass,
};
use std::time::Instant;

/// A triangle–triangle distance kernel under test.
#[derive(Copy, Clone, Debug, PartialEq)]
pub enum TriangleKernel {
    /// [`triangle_distance`].
    Exact,
    /// [`dyop_distance`] with a point–edge formula.
    Dyop(PointEdgeFormula),
    /// parry3d-f64's `query::distance` on two triangles (GJK), the peer.
    Parry,
}

impl TriangleKernel {
    /// Every kernel, in report order.
    pub fn all() -> Vec<TriangleKernel> {
        let mut all = vec![TriangleKernel::Exact, TriangleKernel::Parry];
        all.extend(PointEdgeFormula::ALL.map(TriangleKernel::Dyop));
        all
    }

    /// A short name for reports.
    pub fn name(self) -> String {
        match self {
            TriangleKernel::Exact => "triangle_distance".to_string(),
            TriangleKernel::Dyop(f) => format!("dyop/{}", f.name()),
            TriangleKernel::Parry => "parry-gjk".to_string(),
        }
    }

    /// The kernel's distance between `a` and `b`.
    pub fn distance(self, a: &Triangle, b: &Triangle) -> Real {
        match self {
            TriangleKernel::Exact => triangle_distance(a, b).distance,
            TriangleKernel::Dyop(f) => dyop_distance(a, b, f),
            TriangleKernel::Parry => parry_triangle_distance(a, b),
        }
    }
}

/// Error statistics of one kernel on one set of inputs.
#[derive(Copy, Clone, Debug, PartialEq)]
pub struct ErrorStats {
    /// Number of inputs.
    pub count: usize,
    /// Largest `|d - d*| / d*` over inputs with `d* > 0` (and `∞` if an input
    /// with `d* = 0` got `d > 0`).
    pub max_relative: Real,
    /// Median of the relative errors.
    pub median_relative: Real,
    /// Largest `|d - d*|`.
    pub max_absolute: Real,
    /// Largest `|d - d*| / (ε · S)`, `S` the extent of the pair about its
    /// first vertex: the absolute error in ulps of the local coordinates.
    pub max_ulps_of_extent: Real,
    /// Number of results below the exact distance by more than
    /// `1e-12·d* + 8ε·S` (an under-estimate; unsafe for CCD).
    pub under_estimates: usize,
}

/// Errors of `computed[i]` against `exact[i]` for inputs with extents
/// `extent[i]`.
pub fn error_stats(computed: &[Real], exact: &[Real], extent: &[Real]) -> ErrorStats {
    let mut relative: Vec<Real> = Vec::with_capacity(computed.len());
    let (mut max_absolute, mut max_ulps, mut under) = (0.0 as Real, 0.0 as Real, 0);
    for ((&d, &e), &s) in computed.iter().zip(exact).zip(extent) {
        let error = (d - e).abs();
        let error = if error.is_nan() { Real::INFINITY } else { error };
        max_absolute = max_absolute.max(error);
        max_ulps = max_ulps.max(error / (Real::EPSILON * s));
        relative.push(if e > 0.0 {
            error / e
        } else if error == 0.0 {
            0.0
        } else {
            Real::INFINITY
        });
        if d < e - (1e-12 * e + 8.0 * Real::EPSILON * s) {
            under += 1;
        }
    }
    relative.sort_by(|x, y| x.total_cmp(y));
    ErrorStats {
        count: computed.len(),
        max_relative: relative.last().copied().unwrap_or(0.0),
        median_relative: relative.get(relative.len() / 2).copied().unwrap_or(0.0),
        max_absolute,
        max_ulps_of_extent: max_ulps,
        under_estimates: under,
    }
}

/// Exact distances (as the nearest f64) for triangle pairs.
pub fn exact_triangle_distances(pairs: &[(Triangle, Triangle)]) -> Vec<Real> {
    pairs.iter().map(|(a, b)| exact::triangle_distance_f64(a, b)).collect()
}

/// Exact distances (as the nearest f64) for point–segment queries.
pub fn exact_point_segment_distances(queries: &[(Point, Point, Point)]) -> Vec<Real> {
    queries
        .iter()
        .map(|(p, a, b)| exact::to_f64(&exact::point_segment_distance_squared(p, a, b)).sqrt())
        .collect()
}

/// Nanoseconds per call of `f` over `inputs`: best of `repeats` timed passes.
pub fn time_per_query<T>(inputs: &[T], repeats: usize, mut f: impl FnMut(&T) -> Real) -> Real {
    let mut best = Real::INFINITY;
    let mut sink = 0.0;
    for _ in 0..repeats.max(1) {
        let start = Instant::now();
        for x in inputs {
            sink += f(std::hint::black_box(x));
        }
        best = best.min(start.elapsed().as_secs_f64());
    }
    std::hint::black_box(sink);
    best * 1e9 / inputs.len().max(1) as Real
}

/// One row of the kernel report.
#[derive(Clone, Debug)]
pub struct KernelRow {
    /// Kernel name.
    pub kernel: String,
    /// Input class name.
    pub class: &'static str,
    /// Errors against the exact reference.
    pub errors: ErrorStats,
    /// Rough nanoseconds per query.
    pub nanoseconds: Real,
}

/// The kernel report: every triangle kernel and every point–segment formula
/// on every input class, `count` inputs each.
pub fn kernel_report(count: usize, seed: u64) -> Vec<KernelRow> {
    let mut rows = Vec::new();
    for class in InputClass::ALL {
        let pairs = triangle_pairs(class, count, seed);
        let exact = exact_triangle_distances(&pairs);
        let extent: Vec<Real> = pairs.iter().map(|(a, b)| pair_extent(a, b)).collect();
        for kernel in TriangleKernel::all() {
            let computed: Vec<Real> = pairs.iter().map(|(a, b)| kernel.distance(a, b)).collect();
            rows.push(KernelRow {
                kernel: kernel.name(),
                class: class.name(),
                errors: error_stats(&computed, &exact, &extent),
                nanoseconds: time_per_query(&pairs, 5, |(a, b)| kernel.distance(a, b)),
            });
        }
        let queries = point_segment_queries(class, count, seed);
        let exact = exact_point_segment_distances(&queries);
        let extent: Vec<Real> = queries.iter().map(|(p, a, b)| query_extent(p, a, b)).collect();
        for formula in PointEdgeFormula::ALL {
            let computed: Vec<Real> =
                queries.iter().map(|(p, a, b)| point_segment_distance(p, a, b, formula)).collect();
            rows.push(KernelRow {
                kernel: format!("point_segment/{}", formula.name()),
                class: class.name(),
                errors: error_stats(&computed, &exact, &extent),
                nanoseconds: time_per_query(&queries, 5, |(p, a, b)| {
                    point_segment_distance(p, a, b, formula)
                }),
            });
        }
    }
    rows
}

/// The report as a Markdown table.
pub fn kernel_report_markdown(rows: &[KernelRow]) -> String {
    let mut out = String::from(
        "| kernel | input class | n | max rel. error | median rel. error | max abs. error | max abs. error (ulps of extent) | under-estimates | ns/query (rough) |\n|---|---|---|---|---|---|---|---|---|\n",
    );
    for r in rows {
        let e = &r.errors;
        out.push_str(&format!(
            "| {} | {} | {} | {:.1e} | {:.1e} | {:.1e} | {:.1} | {} | {:.0} |\n",
            r.kernel,
            r.class,
            e.count,
            e.max_relative,
            e.median_relative,
            e.max_absolute,
            e.max_ulps_of_extent,
            e.under_estimates,
            r.nanoseconds
        ));
    }
    out
}

/// Errors below this are drawn at this value on the log axis of the kernel
/// chart (half an ulp of 1: the reference's own resolution in f64).
#[cfg(feature = "plot")]
pub const CHART_ERROR_FLOOR: Real = Real::EPSILON / 2.0;

/// The kernel report as a chart: maximum relative error against time per
/// query, log–log, one series per kernel, each point labelled with its
/// input class. `point_segment` picks the point–segment formulas, otherwise
/// the triangle–triangle kernels.
#[cfg(feature = "plot")]
pub fn kernel_chart(rows: &[KernelRow], point_segment: bool) -> crate::plot::Chart {
    use crate::plot::{Chart, Series};
    let rows: Vec<&KernelRow> =
        rows.iter().filter(|r| r.kernel.starts_with("point_segment/") == point_segment).collect();
    let mut kernels: Vec<&str> = rows.iter().map(|r| r.kernel.as_str()).collect();
    kernels.dedup();
    kernels.sort_unstable();
    kernels.dedup();
    let series = kernels
        .iter()
        .map(|&kernel| {
            let mine: Vec<&&KernelRow> = rows.iter().filter(|r| r.kernel == kernel).collect();
            Series {
                label: kernel.to_string(),
                points: mine
                    .iter()
                    .map(|r| (r.nanoseconds, r.errors.max_relative.max(CHART_ERROR_FLOOR)))
                    .collect(),
                line: false,
                point_labels: mine.iter().map(|r| r.class.to_string()).collect(),
            }
        })
        .collect();
    Chart {
        title: format!(
            "{} kernels: max relative error vs time per query",
            if point_segment { "Point–segment" } else { "Triangle–triangle" }
        ),
        x_label: "time per query (ns, rough timed loop, log scale)".into(),
        y_label: format!("max relative error vs exact (log; < {CHART_ERROR_FLOOR:.1e} drawn at it)"),
        log_x: true,
        log_y: true,
        series,
        marks: Vec::new(),
        ticks: Vec::new(),
    }
}

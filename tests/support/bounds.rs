//! Error bounds shared by the integration tests (derivations in
//! `kernels/point_segment_vs_exact.rs`).

use nearmiss::kernels::PointEdgeFormula;

/// The error each point–edge formula is allowed at exact distance `exact`,
/// for a query whose largest local coordinate is `extent`.
pub fn formula_bound(formula: PointEdgeFormula, exact: f64, extent: f64) -> f64 {
    match formula {
        PointEdgeFormula::Vector => 8.0 * f64::EPSILON * exact,
        PointEdgeFormula::PlainVector => 1e-14 * exact + 4.0 * f64::EPSILON * extent,
        PointEdgeFormula::Heron | PointEdgeFormula::StableHeron => 4.0 * f64::EPSILON.sqrt() * extent,
    }
}

//! The `nearmiss` command's own code, above the [`nearmiss`] library: what a
//! run writes ([`output`]: `summary.json`, `trace.csv`, `report.md`, the
//! distance chart, the contact pictures, the glTF animation, the run page),
//! the regression verdicts ([`regression`]), the reports (kernels, the CCD
//! benchmark sample read by [`query_file`], sweeps, stability, shards,
//! peers). The library never calls it.

pub mod animation;
#[cfg(feature = "plot")]
pub mod contact_picture;
pub mod output;
#[cfg(feature = "plot")]
pub mod plot;
pub mod query_file;
pub mod regression;
pub mod report;
pub mod run_page;
pub mod text;

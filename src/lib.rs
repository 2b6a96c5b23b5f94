//! # nearmiss
//!
//! A continuous-collision-detection (CCD) time-stepper for triangle meshes.
//! A fixed-step integrator moves and rotates meshes; a broad phase selects
//! candidate pairs; a conservative-advancement CCD driven by triangle distance
//! kernels finds the time of first contact without stepping past it; distances
//! over time are recorded and plotted.
//!
//! This release holds the foundation: the distance [`kernels`] (exact
//! triangle–triangle, point–segment by vector and Heron formulas, the seed
//! paper's DyOP kernel, and batched SIMD versions), the [`exact`] rational
//! reference they are tested against, [`samples`] (the seeded input classes
//! shared by tests, benchmarks and the kernel [`report`]), the linear-vertex
//! CCD queries in [`ccd`], and [`query_file`], the reader and runner for the
//! public CCD benchmark format.

pub mod ccd;
pub mod exact;
pub mod kernels;
pub mod math;
pub mod mesh;
pub mod motion;
pub mod output;
pub mod query_file;
pub mod regression;
pub mod report;
pub mod samples;
pub mod scene;
pub mod stepper;
pub mod trace;

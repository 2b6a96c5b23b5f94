//! # nearmiss
//!
//! A continuous-collision-detection (CCD) time-stepper for triangle meshes.
//! A fixed-step integrator moves and rotates meshes; a broad phase selects
//! candidate pairs; a conservative-advancement CCD driven by triangle distance
//! kernels finds the time of first contact without stepping past it; distances
//! over time are recorded and plotted.
//!
//! The pipeline: a [`scene`] (RON) is validated into bodies with shared
//! [`mesh`] assets (BVH built once) and motion state; the [`stepper`]
//! advances them step by step, one stage after another: integrate
//! ([`motion`]: exact free motion, or semi-implicit Euler / explicit Euler /
//! RK4 with an implicit gyroscopic step), broad phase ([`broad_phase`]),
//! narrow phase (conservative advancement, [`ccd::mesh_time_of_impact`],
//! with the exact triangle [`kernels`] as the proximity query and the
//! contact distance of [`ccd::ContactContract`]), respond ([`response`]:
//! stop, record, bounce), re-arm, observe (the distance [`trace`]); runs are
//! written by [`output`], and [`regression`] checks a run against the
//! scene's expectation.
//!
//! Underneath: the distance [`kernels`] (exact triangle–triangle,
//! point–segment by vector and Heron formulas, the seed paper's DyOP
//! kernel, batched SIMD versions), the [`exact`] rational reference they
//! are tested against, `samples` (seeded input classes shared by tests,
//! benchmarks and the kernel [`report`]; public with the `testing`
//! feature), the linear-vertex CCD queries in [`ccd`], and [`query_file`],
//! the reader for the public CCD benchmark format (run by
//! [`report::run_file`]).
//!
//! Features: `plot` (default) draws PNG charts with plotters; `cli`
//! (default) builds the `nearmiss` binary (clap, indicatif); `testing`
//! makes `samples` public for the crate's tests and benchmarks.

pub mod animation;
pub mod broad_phase;
pub mod ccd;
#[cfg(feature = "plot")]
pub mod contact_picture;
pub mod exact;
#[cfg(feature = "rapier")]
pub mod guard;
pub mod input;
pub mod kernels;
pub mod math;
pub mod mesh;
pub mod motion;
pub mod output;
#[cfg(feature = "plot")]
pub mod plot;
pub mod poses;
pub mod query_file;
pub mod regression;
pub mod report;
pub mod response;
pub mod run_page;
#[cfg(feature = "testing")]
pub mod samples;
#[cfg(not(feature = "testing"))]
#[allow(dead_code)] // what the reports do not use serves the tests, behind `testing`
pub(crate) mod samples;
pub mod scene;
pub mod stepper;
pub mod trace;

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
//! advances them step by step ([`motion`]: exact free motion, or
//! semi-implicit Euler / explicit Euler / RK4 with an implicit gyroscopic
//! step), runs conservative advancement ([`ccd::mesh_time_of_impact`]) on
//! every pair that can touch, with the exact triangle [`kernels`] as the
//! proximity query, and records contacts and distance traces ([`trace`]),
//! written by [`output`]; [`regression`] checks a run against the scene's
//! expectation.
//!
//! Underneath: the distance [`kernels`] (exact triangle–triangle,
//! point–segment by vector and Heron formulas, the seed paper's DyOP
//! kernel, batched SIMD versions), the [`exact`] rational reference they
//! are tested against, `samples` (seeded input classes shared by tests,
//! benchmarks and the kernel [`report`]; public with the `testing` feature), the linear-vertex CCD queries in
//! [`ccd`], and [`query_file`], the reader and runner for the public CCD
//! benchmark format.

pub mod broad_phase;
pub mod ccd;
pub mod exact;
pub mod kernels;
pub mod math;
pub mod mesh;
pub mod motion;
pub mod output;
#[cfg(feature = "plot")]
pub mod plot;
pub mod query_file;
pub mod regression;
pub mod report;
pub mod response;
#[cfg(feature = "testing")]
pub mod samples;
#[cfg(not(feature = "testing"))]
#[allow(dead_code)] // what the reports do not use serves the tests, behind `testing`
pub(crate) mod samples;
pub mod scene;
pub mod stepper;
pub mod trace;

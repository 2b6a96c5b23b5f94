//! # nearmiss
//!
//! A continuous-collision-detection (CCD) time-stepper for triangle meshes.
//! A fixed-step integrator moves and rotates meshes; a broad phase selects
//! candidate pairs; a conservative-advancement CCD driven by triangle distance
//! kernels finds the time of first contact without stepping past it.
//!
//! The pipeline: a [`scene`] (RON) is validated into bodies with shared
//! [`mesh`] assets (BVH built once) and motion state; the [`stepper`]
//! advances them step by step, one stage after another: integrate
//! ([`motion`]: exact free motion, or semi-implicit Euler / explicit Euler /
//! RK4 with an implicit gyroscopic step), broad phase ([`broad_phase`]),
//! narrow phase (conservative advancement, [`ccd::mesh_time_of_impact`],
//! with the exact triangle [`kernels`] as the proximity query and the
//! contact distance of [`ccd::ContactContract`]), respond ([`response`]:
//! stop, record, bounce), re-arm, observe (the distance [`trace`], the
//! [`poses`]). `guard` (the `rapier` feature) keeps rapier bodies from
//! tunnelling, and runs `on_contact: Simulate`.
//!
//! Underneath: the distance [`kernels`] (exact triangle–triangle,
//! point–segment by vector and Heron formulas, the seed paper's DyOP
//! kernel, batched SIMD versions), the [`exact`] rational reference they
//! are tested against, `samples` (seeded input classes shared by tests,
//! benchmarks and the kernel reports; public with the `testing` feature),
//! and the linear-vertex CCD queries in [`ccd`].
//!
//! This crate computes and never draws: the `nearmiss` binary (the
//! `nearmiss-cli` crate beside it) writes runs, plots, pictures and
//! reports. Features: `rapier` (default) the guard and `Simulate`;
//! `rapier-f32` the guard of an f32 rapier too; `testing` makes `samples`
//! public for the tests and benchmarks.

pub mod broad_phase;
pub mod ccd;
pub mod exact;
#[cfg(feature = "rapier")]
pub mod guard;
pub mod input;
pub mod kernels;
pub mod math;
pub mod mesh;
pub mod motion;
pub mod poses;
pub mod response;
#[cfg(any(test, feature = "testing"))]
pub mod samples;
pub mod scene;
pub mod stepper;
pub mod trace;

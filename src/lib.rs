//! # nearmiss
//!
//! A continuous-collision-detection (CCD) time-stepper for triangle meshes.
//! A fixed-step integrator moves and rotates meshes; a broad phase selects
//! candidate pairs; a conservative-advancement CCD driven by triangle distance
//! kernels finds the time of first contact without stepping past it.
//!
//! The pipeline: a [`scene`] (RON) is validated into bodies with shared
//! [`mesh`] assets (BVH built once) and motion state; [`run`](mod@run) picks the
//! scene's driver and steps it to the end. The [`stepper`] advances the
//! bodies one stage after another: integrate ([`motion`]: exact free
//! motion, or semi-implicit Euler / explicit Euler / RK4 with an implicit
//! gyroscopic step), broad phase ([`broad_phase`]), narrow phase
//! (conservative advancement, [`ccd::mesh_time_of_impact`], with the exact
//! triangle [`kernels`] as the proximity query and the contact distance of
//! [`ccd::ContactContract`]), respond (stop, record, bounce), re-arm,
//! observe (the distance trace, the poses, the near misses). `guard` (the
//! `rapier` feature) keeps rapier bodies from tunnelling, and drives
//! `on_contact: Simulate`.
//!
//! Underneath: the distance [`kernels`] (exact triangle–triangle,
//! point–segment by vector and Heron formulas, the seed paper's DyOP
//! kernel, batched SIMD versions), the [`exact`] rational reference they
//! are tested against, `samples` (seeded input classes shared by tests,
//! benchmarks and the kernel reports; public with the `testing` feature),
//! and the linear-vertex CCD queries in [`ccd`].
//!
//! # Quick start
//!
//! A scene is RON text (a file for the `nearmiss` command, or a string):
//! bodies with meshes, poses, velocities and forces. The stepper runs it
//! and returns every contact with its time, points and features:
//!
//! ```
//! use nearmiss::scene::Scene;
//!
//! // A ball dropped onto a fixed floor: its lowest point starts 1 above
//! // it, so it lands at t = sqrt(2 / 9.81) (the chord of a step of RK4
//! // runs below the parabola: never later).
//! let scene = Scene::from_ron_str(r#"Scene(
//!     name: "drop", dt: 0.001, duration: 1.0, integrator: Rk4,
//!     gravity: (0.0, 0.0, -9.81),
//!     bodies: [
//!         (name: "floor", mesh: Box(half_extents: (2.0, 2.0, 0.5)), position: (0.0, 0.0, -0.5), fixed: true),
//!         (name: "ball", mesh: Icosphere(radius: 0.5, subdivisions: 2), position: (0.0, 0.0, 1.5)),
//!     ],
//! )"#)?;
//! let result = nearmiss::run(&scene);
//! let contact = result.first_contact.expect("the ball lands");
//! let landing = (2.0_f64 / 9.81).sqrt();
//! assert!(contact.time <= landing && landing - contact.time < 1e-6);
//! println!("{} touches {} at t = {}", result.bodies[contact.body_b], result.bodies[contact.body_a], contact.time);
//! # Ok::<(), nearmiss::scene::SceneError>(())
//! ```
//!
//! The queries underneath are called directly too:
//! [`kernels::triangle_distance`] (two triangles),
//! [`ccd::mesh_time_of_impact`] (two moving meshes),
//! [`collection::Collection`] (one mesh, at rest or moving, against many
//! named ones: contacts, distances, first contact, certified clearance),
//! and with the `rapier`
//! feature `guard::Guard` keeps a rapier world from tunnelling.
//!
//! This crate computes and never draws: the `nearmiss` binary (the
//! `nearmiss-cli` crate beside it) writes runs, plots, pictures and
//! reports. Features: `rapier` (off by default; the command line and
//! the Python package turn it on) the guard and `Simulate`;
//! `rapier-f32` the guard of an f32 rapier too; `testing` makes `samples`
//! public for the tests and benchmarks.

// `unsafe` only where the SIMD kernels call intrinsics (`kernels/`, which
// allows it, each block with its `SAFETY:` reason).
#![deny(unsafe_code)]

pub mod broad_phase;
pub mod ccd;
pub mod collection;
#[cfg(test)]
mod documented_defaults;
pub mod exact;
#[cfg(feature = "rapier")]
pub mod guard;
mod input;
#[allow(unsafe_code)]
pub mod kernels;
pub mod math;
pub mod mesh;
pub mod motion;
pub mod run;
#[cfg(any(test, feature = "testing"))]
pub mod samples;
pub mod scene;
pub mod stepper;

pub use run::run;

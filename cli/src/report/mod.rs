//! Reports: the kernel report (error against the exact reference beside
//! time per query), sweeps of a scene over time steps, kernels and
//! integrators (error against run time), the stability suite, the seed
//! paper's experiments, and the CCD benchmark runner.

mod kernels;
mod paper;
mod peer;
mod queries;
mod shard;
mod stability;
mod suite;
mod sweep;

pub use kernels::*;
pub use paper::*;
pub use peer::*;
pub use queries::*;
pub use shard::*;
pub use stability::*;
pub use suite::*;
pub use sweep::*;

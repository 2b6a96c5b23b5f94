//! Stage 6, observe: what a run records besides its contacts, each when
//! the scene asks for it: the distance trace (`trace.rs`), the bodies'
//! poses (`poses.rs`) and the near misses (`near_miss.rs`, whose screens
//! also answer the narrow phase's far pairs).

pub(crate) mod near_miss;
pub(crate) mod poses;
pub(crate) mod trace;

//! The reports: the stability suite, the sweep against analysis, parry
//! beside nearmiss, and the public CCD benchmark sample.

mod ccd_sample_queries;
mod peer;
mod stability;
mod sweep;

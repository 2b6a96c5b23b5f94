//! Whole runs through the stepper: first contacts of scenes against analytic
//! times, `Bounce`'s analytic outcomes, the broad phase and threads changing
//! nothing, and the distance trace's certificates.

#[path = "../support/ball_rest.rs"]
mod ball_rest;
#[path = "../support/crowd.rs"]
mod crowd;

mod bounce;
mod near_misses;
mod parallel_and_broad_phase;
mod past_contact;
mod scene_analytic;
mod trace_certificate;

//! rapier guarded by nearmiss: `on_contact: Simulate` scenes and rapier
//! applications driving the guard (the `rapier` feature; the f32 rapier's
//! tests are `guard_f32.rs`, behind `rapier-f32`).

#[path = "../support/guard_worlds.rs"]
#[allow(dead_code)]
mod guard_worlds;
#[path = "../support/rapier_app.rs"]
mod rapier_app;

mod decisive;
mod invisible;
mod rules;
mod simulate;
mod simulate_never_tunnels;

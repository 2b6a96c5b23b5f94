//! What a run writes: `summary.json` bit for bit across runs, whole or not
//! at all, the distance plot, the run page and the glTF animation.

#[cfg(feature = "plot")]
#[path = "../../../tests/support/ball_rest.rs"]
mod ball_rest;

mod animation;
mod near_misses;
mod output_whole_or_absent;
mod pictures;
mod plots;
mod run_page;
mod scene_determinism;

//! Progress display for long runs.

use nearmiss::scene::Scene;
use nearmiss::stepper::RunResult;
use std::time::{Duration, Instant};

/// Runs a scene with a progress bar on a terminal, shown once the run has
/// taken a second.
pub fn run_with_progress(scene: &Scene) -> RunResult {
    let bar =
        indicatif::ProgressBar::with_draw_target(Some(scene.steps), indicatif::ProgressDrawTarget::hidden());
    bar.set_style(bar_style("{msg} [{bar:40}] {pos}/{len} steps, {eta} left"));
    bar.set_message(scene.name.clone());
    let start = Instant::now();
    let mut shown = false;
    let result = nearmiss::stepper::run_observed(scene, &mut |done| {
        if !shown && start.elapsed() > Duration::from_secs(1) {
            shown = true;
            bar.set_draw_target(indicatif::ProgressDrawTarget::stderr());
        }
        if shown && done % 64 == 0 {
            bar.set_position(done);
        }
    });
    bar.finish_and_clear();
    result
}

/// A bar of `total` units drawn with `template`.
pub fn bar(total: u64, template: &str) -> indicatif::ProgressBar {
    let bar = indicatif::ProgressBar::new(total);
    bar.set_style(bar_style(template));
    bar
}

fn bar_style(template: &str) -> indicatif::ProgressStyle {
    indicatif::ProgressStyle::with_template(template)
        .unwrap_or_else(|_| indicatif::ProgressStyle::default_bar())
        .progress_chars("=> ")
}

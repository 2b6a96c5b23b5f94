//! Progress display for long runs: a bar on a terminal; elsewhere (a log,
//! CI) a line every few seconds with the time left.

use nearmiss::run::RunResult;
use nearmiss::scene::Scene;
use std::io::IsTerminal;
use std::time::{Duration, Instant};

/// A run shows progress once it has taken this long.
const SHOW_AFTER: Duration = Duration::from_secs(1);

/// Progress is looked at every this many steps (the clock and the bar stay
/// off the step's cost).
const CHECK_EVERY_STEPS: u64 = 64;

/// Without a terminal, a progress line this often.
const LINE_EVERY: Duration = Duration::from_secs(5);

/// Runs a scene with a progress bar on a terminal, shown once the run has
/// taken a second; without a terminal, a line every few seconds.
pub fn run_with_progress(scene: &Scene) -> RunResult {
    if !std::io::stderr().is_terminal() {
        return run_with_lines(scene);
    }
    let bar = indicatif::ProgressBar::with_draw_target(
        Some(scene.run().steps),
        indicatif::ProgressDrawTarget::hidden(),
    );
    bar.set_style(bar_style("{msg} [{bar:40}] {pos}/{len} steps, {eta} left"));
    bar.set_message(scene.run().name.clone());
    let start = Instant::now();
    let mut shown = false;
    let result = nearmiss::run::run_observed(scene, &mut |done| {
        if !shown && start.elapsed() > SHOW_AFTER {
            shown = true;
            bar.set_draw_target(indicatif::ProgressDrawTarget::stderr());
        }
        if shown && done % CHECK_EVERY_STEPS == 0 {
            bar.set_position(done);
        }
    });
    bar.finish_and_clear();
    result
}

/// Progress as plain lines on stderr, every [`LINE_EVERY`].
fn run_with_lines(scene: &Scene) -> RunResult {
    let start = Instant::now();
    let mut next = LINE_EVERY;
    nearmiss::run::run_observed(scene, &mut |done| {
        if done % CHECK_EVERY_STEPS != 0 {
            return;
        }
        let elapsed = start.elapsed();
        if elapsed < next {
            return;
        }
        next = elapsed + LINE_EVERY;
        let fraction = done as f64 / scene.run().steps.max(1) as f64;
        let left = elapsed.as_secs_f64() * (1.0 - fraction) / fraction.max(f64::MIN_POSITIVE);
        eprintln!(
            "{}: {done}/{} steps ({:.1}%), {:.0} s so far, about {:.0} s left",
            scene.run().name,
            scene.run().steps,
            100.0 * fraction,
            elapsed.as_secs_f64(),
            left
        );
    })
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

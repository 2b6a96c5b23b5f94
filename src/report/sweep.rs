//! Error against run time: one scene run over a grid of time steps,
//! distance kernels and integrators.
//!
//! For each setting the sweep reports the time of first contact, its error
//! against the reference — the scene's analytic expectation when it states
//! one, otherwise the finest run (smallest `dt`, exact kernel, the most
//! accurate integrator asked for) — the largest relative error of the
//! setting's distance kernel against the exact reference along the trace
//! (rational arithmetic on the closest triangle pair of each sample), and
//! the wall time (the fastest of repeated runs, repeated until 50 ms have
//! been spent or 20 runs made).

use std::time::{Duration, Instant};

use crate::kernels::PointEdgeFormula;
use crate::math::Real;
use crate::mesh::DistanceKernel;
use crate::motion::Integrator;
use crate::scene::{Expectation, Scene, TraceSpec};
use crate::stepper::{run, RunResult, Termination};

/// The timed runs of a setting stop once they have taken this long...
pub const SWEEP_TIME_PER_SETTING: Duration = Duration::from_millis(50);
/// ...or after this many runs; the fastest is reported.
pub const SWEEP_MAX_REPEATS: usize = 20;

/// One setting of a sweep.
#[derive(Copy, Clone, Debug, PartialEq)]
pub struct SweepSetting {
    /// The time step.
    pub dt: Real,
    /// The distance kernel.
    pub kernel: DistanceKernel,
    /// The integrator.
    pub integrator: Integrator,
}

/// The outcome of one setting.
#[derive(Clone, Debug, PartialEq)]
pub struct SweepRow {
    /// The setting.
    pub setting: SweepSetting,
    /// Steps taken.
    pub steps: u64,
    /// The time of first contact, if any.
    pub time: Option<Real>,
    /// `time − reference`, when both exist.
    pub error: Option<Real>,
    /// The kernel's largest relative error against the exact distance over
    /// the trace samples (samples at distance 0 left out).
    pub kernel_error: Real,
    /// Wall time of one run, seconds (fastest of the repeats).
    pub wall_time_s: Real,
    /// How the run ended.
    pub termination: String,
}

/// A whole sweep.
#[derive(Clone, Debug, PartialEq)]
pub struct SweepReport {
    /// The scene.
    pub scene: String,
    /// The reference time of first contact, if there is one.
    pub reference: Option<Real>,
    /// Where the reference comes from.
    pub reference_source: String,
    /// One row per setting, in the order of the grid.
    pub rows: Vec<SweepRow>,
}

/// The short name of a kernel, as the command line takes it.
pub fn kernel_name(kernel: DistanceKernel) -> String {
    match kernel {
        DistanceKernel::Exact => "exact".into(),
        DistanceKernel::Dyop(formula) => format!("dyop-{}", formula.name()),
    }
}

/// The kernel with this short name (`exact`, `dyop-vector`,
/// `dyop-plain-vector`, `dyop-heron`, `dyop-stable-heron`).
pub fn parse_kernel(name: &str) -> Option<DistanceKernel> {
    if name == "exact" {
        return Some(DistanceKernel::Exact);
    }
    let formula = name.strip_prefix("dyop-")?;
    PointEdgeFormula::ALL.into_iter().find(|f| f.name() == formula).map(DistanceKernel::Dyop)
}

/// The short name of an integrator.
pub fn integrator_name(integrator: Integrator) -> &'static str {
    match integrator {
        Integrator::SymplecticEuler => "symplectic-euler",
        Integrator::ExplicitEuler => "explicit-euler",
        Integrator::Rk4 => "rk4",
    }
}

/// The integrator with this short name.
pub fn parse_integrator(name: &str) -> Option<Integrator> {
    [Integrator::SymplecticEuler, Integrator::ExplicitEuler, Integrator::Rk4]
        .into_iter()
        .find(|&i| integrator_name(i) == name)
}

/// Runs the scene with a setting, with the kernel's reference along the trace.
fn run_setting(scene: &Scene, setting: &SweepSetting) -> (RunResult, Real) {
    let mut scene = scene.with_settings(setting.dt, setting.kernel, setting.integrator);
    scene.trace = Some(TraceSpec {
        pairs: scene.trace.as_ref().map_or_else(|| scene.movable_pairs(), |t| t.pairs.clone()),
        every: scene.trace.as_ref().map_or(1, |t| t.every),
        reference: true,
    });
    let traced = run(&scene);
    // Timed runs without the trace's reference (which is report overhead).
    scene.trace = None;
    let start = Instant::now();
    let mut fastest = Real::INFINITY;
    for _ in 0..SWEEP_MAX_REPEATS {
        let result = run(&scene);
        fastest = fastest.min(result.wall_time_s);
        if start.elapsed() > SWEEP_TIME_PER_SETTING {
            break;
        }
    }
    (traced, fastest)
}

/// Runs the grid `dts × kernels × integrators`, calling `progress(done, total)`.
pub fn sweep(
    scene: &Scene,
    dts: &[Real],
    kernels: &[DistanceKernel],
    integrators: &[Integrator],
    progress: &mut dyn FnMut(usize, usize),
) -> SweepReport {
    let mut settings = Vec::new();
    for &integrator in integrators {
        for &kernel in kernels {
            for &dt in dts {
                settings.push(SweepSetting { dt, kernel, integrator });
            }
        }
    }
    let total = settings.len() + 1;
    let (reference, reference_source) = match &scene.expect {
        Some(Expectation::Contact { time, .. }) => {
            (Some(*time), "analytic (the scene's expectation)".to_string())
        }
        _ => {
            let finest = dts.iter().copied().fold(Real::INFINITY, Real::min);
            let integrator =
                if integrators.contains(&Integrator::Rk4) { Integrator::Rk4 } else { integrators[0] };
            let setting = SweepSetting { dt: finest, kernel: DistanceKernel::Exact, integrator };
            let result = run(&scene.with_settings(setting.dt, setting.kernel, setting.integrator));
            let source = format!("finest exact run (dt = {finest}, {})", integrator_name(integrator));
            (result.first_contact.map(|c| c.time), source)
        }
    };
    progress(1, total);
    let mut rows = Vec::with_capacity(settings.len());
    for (k, setting) in settings.iter().enumerate() {
        let (result, wall_time_s) = run_setting(scene, setting);
        let time = result.first_contact.as_ref().map(|c| c.time);
        let kernel_error = result
            .trace
            .iter()
            .filter_map(|r| r.reference.filter(|&d| d > 0.0).map(|d| (r.distance - d).abs() / d))
            .fold(0.0, Real::max);
        rows.push(SweepRow {
            setting: *setting,
            steps: result.steps,
            time,
            error: time.zip(reference).map(|(t, r)| t - r),
            kernel_error,
            wall_time_s,
            termination: match &result.termination {
                Termination::Diverged { reason, .. } => format!("diverged: {reason}"),
                Termination::FirstContact => "first contact".into(),
                Termination::Completed => "completed".into(),
                Termination::Undecided { time, .. } => format!("undecided after t = {time:?}"),
            },
        });
        progress(k + 2, total);
    }
    SweepReport { scene: scene.name.clone(), reference, reference_source, rows }
}
/// The sweep as Markdown: the reference, then one row per setting.
pub fn sweep_markdown(report: &SweepReport) -> String {
    let mut out = format!(
        "sweep of {}: reference {} ({})\n",
        report.scene,
        report.reference.map_or("none".into(), |r| format!("{r:.15e}")),
        report.reference_source
    );
    out.push_str("| dt | kernel | integrator | steps | time of contact | error | kernel max rel. error | wall time (s) | ended |\n");
    out.push_str("|---|---|---|---|---|---|---|---|---|\n");
    for r in &report.rows {
        out.push_str(&format!(
            "| {} | {} | {} | {} | {} | {} | {:.1e} | {:.2e} | {} |\n",
            r.setting.dt,
            kernel_name(r.setting.kernel),
            integrator_name(r.setting.integrator),
            r.steps,
            r.time.map_or("none".into(), |t| format!("{t:.12e}")),
            r.error.map_or("-".into(), |e| format!("{e:+.3e}")),
            r.kernel_error,
            r.wall_time_s,
            r.termination
        ));
    }
    out
}

/// The sweep as CSV: one line per setting.
pub fn sweep_csv(report: &SweepReport) -> String {
    let mut out = String::from(
        "dt,kernel,integrator,steps,time_of_contact,reference_time,error,kernel_max_relative_error,wall_time_s,termination\n",
    );
    let number = |v: Option<Real>| v.map_or(String::new(), |v| format!("{v:?}"));
    for r in &report.rows {
        out.push_str(&format!(
            "{:?},{},{},{},{},{},{},{:?},{:?},{}\n",
            r.setting.dt,
            kernel_name(r.setting.kernel),
            integrator_name(r.setting.integrator),
            r.steps,
            number(r.time),
            number(report.reference),
            number(r.error),
            r.kernel_error,
            r.wall_time_s,
            r.termination.replace(',', ";")
        ));
    }
    out
}

/// Errors below this are drawn at this value on the chart's log axis.
#[cfg(feature = "plot")]
pub const SWEEP_ERROR_FLOOR: Real = 1e-17;

/// |error| against wall time, log–log, one series per kernel and
/// integrator, each point labelled with its `dt`.
#[cfg(feature = "plot")]
pub fn sweep_chart(report: &SweepReport) -> crate::plot::Chart {
    use crate::plot::{Chart, Series};
    let mut series: Vec<Series> = Vec::new();
    for r in &report.rows {
        let label = format!("{} / {}", kernel_name(r.setting.kernel), integrator_name(r.setting.integrator));
        let index = match series.iter().position(|s| s.label == label) {
            Some(i) => i,
            None => {
                series.push(Series { label, line: true, ..Series::default() });
                series.len() - 1
            }
        };
        if let Some(error) = r.error {
            series[index].points.push((r.wall_time_s, error.abs().max(SWEEP_ERROR_FLOOR)));
            series[index].point_labels.push(format!("dt={}", r.setting.dt));
        }
    }
    Chart {
        title: format!("{}: error of the first contact time vs run time", report.scene),
        x_label: "wall time per run (s, log scale)".into(),
        y_label: format!("|time of contact − reference| (log; < {SWEEP_ERROR_FLOOR:.0e} drawn at it)"),
        log_x: true,
        log_y: true,
        series,
        marks: Vec::new(),
        ticks: Vec::new(),
    }
}

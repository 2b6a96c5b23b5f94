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
//!
//! A sweep shards like `nearmiss test` ([`sweep_share`], [`merge_sweep`]):
//! each shard runs its share of the grid and carries the reference it
//! computed, and the merge refuses shards that disagree on it.

use std::time::{Duration, Instant};

use serde::{Deserialize, Serialize};

use nearmiss::kernels::PointEdgeFormula;
use nearmiss::math::Real;
use nearmiss::mesh::DistanceKernel;
use nearmiss::motion::Integrator;
use nearmiss::run::{run, RunResult, Termination};
use nearmiss::scene::{Expectation, Scene, TraceSpec};

use super::{merge_positions, Shard};

/// The timed runs of a setting stop once they have taken this long...
pub const SWEEP_TIME_PER_SETTING: Duration = Duration::from_millis(50);
/// ...or after this many runs; the fastest is reported.
pub const SWEEP_MAX_REPEATS: usize = 20;

/// One setting of a sweep (in JSON: the kernel and integrator by their
/// command-line names).
#[derive(Copy, Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct SweepSetting {
    /// The time step.
    pub dt: Real,
    /// The distance kernel.
    #[serde(with = "kernel_by_name")]
    pub kernel: DistanceKernel,
    /// The integrator.
    #[serde(with = "integrator_by_name")]
    pub integrator: Integrator,
}

/// The outcome of one setting.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
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

/// One shard's part of a sweep (`nearmiss sweep --shard I/N --json FILE`):
/// the whole grid and the reference as this shard computed them, and its
/// rows with their positions in the grid.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct SweepShard {
    /// Which shard.
    pub shard: Shard,
    /// The scene.
    pub scene: String,
    /// The reference time of first contact, if there is one.
    pub reference: Option<Real>,
    /// Where the reference comes from.
    pub reference_source: String,
    /// The whole grid, in order.
    pub grid: Vec<SweepSetting>,
    /// This shard's rows with their positions in the grid.
    pub rows: Vec<(usize, SweepRow)>,
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
    let scene = scene.with_settings(setting.dt, setting.kernel, setting.integrator);
    let trace = TraceSpec {
        pairs: scene.run().trace.as_ref().map_or_else(|| scene.model().movable_pairs(), |t| t.pairs.clone()),
        every: scene.run().trace.as_ref().map_or(1, |t| t.every),
        reference: true,
    };
    let traced_scene = scene.with_trace(Some(trace)).expect("the scene's own pairs and step");
    let traced = run(&traced_scene);
    // Timed runs without the trace's reference (which is report overhead).
    let scene = scene.with_trace(None).expect("no trace is always valid");
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

/// The grid `dts × kernels × integrators` in the sweep's order: the
/// integrators outermost, the time steps innermost.
pub fn sweep_grid(dts: &[Real], kernels: &[DistanceKernel], integrators: &[Integrator]) -> Vec<SweepSetting> {
    let mut grid = Vec::with_capacity(dts.len() * kernels.len() * integrators.len());
    for &integrator in integrators {
        for &kernel in kernels {
            for &dt in dts {
                grid.push(SweepSetting { dt, kernel, integrator });
            }
        }
    }
    grid
}

/// The sweep's reference and where it comes from: the scene's analytic
/// expectation, else the finest run of the grid (smallest `dt`, exact
/// kernel, RK4 if the grid has it, else its first integrator).
fn sweep_reference(scene: &Scene, grid: &[SweepSetting]) -> (Option<Real>, String) {
    if let Some(Expectation::Contact { time, .. }) = &scene.run().expect {
        return (Some(*time), "analytic (the scene's expectation)".to_string());
    }
    let Some(first) = grid.first() else {
        return (None, "none (empty grid)".to_string());
    };
    let finest = grid.iter().map(|s| s.dt).fold(Real::INFINITY, Real::min);
    let integrator =
        if grid.iter().any(|s| s.integrator == Integrator::Rk4) { Integrator::Rk4 } else { first.integrator };
    let result = run(&scene.with_settings(finest, DistanceKernel::Exact, integrator));
    let source = format!("finest exact run (dt = {finest}, {})", integrator_name(integrator));
    (result.first_contact.map(|c| c.time), source)
}

/// Runs one setting and reports it against `reference`.
fn sweep_row(scene: &Scene, setting: &SweepSetting, reference: Option<Real>) -> SweepRow {
    let (result, wall_time_s) = run_setting(scene, setting);
    let time = result.first_contact.as_ref().map(|c| c.time);
    let kernel_error = result
        .trace
        .iter()
        .filter_map(|r| r.reference.filter(|&d| d > 0.0).map(|d| (r.distance - d).abs() / d))
        .fold(0.0, Real::max);
    SweepRow {
        setting: *setting,
        steps: result.steps,
        time,
        error: time.zip(reference).map(|(t, r)| t - r),
        kernel_error,
        wall_time_s,
        termination: match &result.termination {
            Termination::Diverged { reason, .. } => format!("diverged: {reason}"),
            Termination::NotStarted { .. } | Termination::Failed { .. } => result.termination_text(),
            Termination::FirstContact => "first contact".into(),
            Termination::Completed => "completed".into(),
            Termination::Undecided { time, .. } => format!("undecided after t = {time:?}"),
            // A termination the library adds later: its own words.
            _ => result.termination_text(),
        },
    }
}

/// Runs `shard`'s share of the grid `dts × kernels × integrators` (the
/// settings at positions `k` with `k mod N = I − 1`) after computing the
/// reference, calling `progress(done, total)` with the share's count (plus
/// one for the reference).
pub fn sweep_share(
    scene: &Scene,
    dts: &[Real],
    kernels: &[DistanceKernel],
    integrators: &[Integrator],
    shard: Shard,
    progress: &mut dyn FnMut(usize, usize),
) -> SweepShard {
    let grid = sweep_grid(dts, kernels, integrators);
    let share: Vec<usize> = (0..grid.len()).filter(|&k| shard.picks(k)).collect();
    let total = share.len() + 1;
    let (reference, reference_source) = sweep_reference(scene, &grid);
    progress(1, total);
    let mut rows = Vec::with_capacity(share.len());
    for (done, &k) in share.iter().enumerate() {
        rows.push((k, sweep_row(scene, &grid[k], reference)));
        progress(done + 2, total);
    }
    SweepShard { shard, scene: scene.run().name.clone(), reference, reference_source, grid, rows }
}

/// Runs the whole grid `dts × kernels × integrators` on this machine,
/// calling `progress(done, total)`.
pub fn sweep(
    scene: &Scene,
    dts: &[Real],
    kernels: &[DistanceKernel],
    integrators: &[Integrator],
    progress: &mut dyn FnMut(usize, usize),
) -> SweepReport {
    let whole = Shard { index: 1, count: 1 };
    sweep_share(scene, dts, kernels, integrators, whole, progress).report()
}

impl SweepShard {
    /// This shard's rows as a report (the whole sweep for shard 1/1).
    pub fn report(&self) -> SweepReport {
        SweepReport {
            scene: self.scene.clone(),
            reference: self.reference,
            reference_source: self.reference_source.clone(),
            rows: self.rows.iter().map(|(_, row)| row.clone()).collect(),
        }
    }
}

/// Puts the shards of one sweep back together: the report one machine
/// would have made (wall times apart). Refused: shards of different scenes
/// or grids, shards whose references differ (bit for bit: a reference run
/// on another build or machine would make the errors of the shards
/// incomparable), and anything `merge_positions` refuses.
pub fn merge_sweep(shards: &[SweepShard]) -> Result<SweepReport, String> {
    let first = shards.first().ok_or("no shard given")?;
    let bits = |r: Option<Real>| r.map(Real::to_bits);
    for other in shards {
        if other.scene != first.scene || other.grid != first.grid {
            return Err(format!(
                "shard {} sweeps scene `{}` over {} settings, shard {} scene `{}` over {} settings: not one sweep",
                first.shard,
                first.scene,
                first.grid.len(),
                other.shard,
                other.scene,
                other.grid.len()
            ));
        }
        if bits(other.reference) != bits(first.reference) || other.reference_source != first.reference_source
        {
            return Err(format!(
                "shards {} and {} disagree on the reference ({:?} from {}, {:?} from {}): were they run by different builds?",
                first.shard,
                other.shard,
                first.reference,
                first.reference_source,
                other.reference,
                other.reference_source
            ));
        }
    }
    let parts: Vec<_> = shards.iter().map(|s| (s.shard, s.grid.len(), s.rows.as_slice())).collect();
    let rows: Vec<SweepRow> = merge_positions(&parts)?;
    if let Some(k) = (0..rows.len()).find(|&k| rows[k].setting != first.grid[k]) {
        return Err(format!("the row at position {k} is not the grid's setting there"));
    }
    Ok(SweepReport {
        scene: first.scene.clone(),
        reference: first.reference,
        reference_source: first.reference_source.clone(),
        rows,
    })
}

/// A kernel in JSON: its command-line name.
mod kernel_by_name {
    use super::{kernel_name, parse_kernel, DistanceKernel};
    use serde::{de::Error, Deserialize, Deserializer, Serializer};

    pub fn serialize<S: Serializer>(kernel: &DistanceKernel, serializer: S) -> Result<S::Ok, S::Error> {
        serializer.serialize_str(&kernel_name(*kernel))
    }

    pub fn deserialize<'de, D: Deserializer<'de>>(deserializer: D) -> Result<DistanceKernel, D::Error> {
        let name = String::deserialize(deserializer)?;
        parse_kernel(&name).ok_or_else(|| D::Error::custom(format!("unknown kernel `{name}`")))
    }
}

/// An integrator in JSON: its command-line name.
mod integrator_by_name {
    use super::{integrator_name, parse_integrator, Integrator};
    use serde::{de::Error, Deserialize, Deserializer, Serializer};

    pub fn serialize<S: Serializer>(integrator: &Integrator, serializer: S) -> Result<S::Ok, S::Error> {
        serializer.serialize_str(integrator_name(*integrator))
    }

    pub fn deserialize<'de, D: Deserializer<'de>>(deserializer: D) -> Result<Integrator, D::Error> {
        let name = String::deserialize(deserializer)?;
        parse_integrator(&name).ok_or_else(|| D::Error::custom(format!("unknown integrator `{name}`")))
    }
}

/// The sweep as Markdown: the reference, then one row per setting.
pub fn sweep_markdown(report: &SweepReport) -> String {
    let mut out = format!(
        "sweep of {}: reference {} ({})\n",
        report.scene,
        report.reference.map_or("none".into(), crate::text::time),
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
            r.time.map_or("none".into(), crate::text::time),
            r.error.map_or("-".into(), |e| crate::text::signed(e, 3)),
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

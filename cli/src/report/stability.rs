//! The stability suite: the stiff spring over `ω·dt` per integrator, the
//! Dzhanibekov spin over 100,000 steps, and the extreme-case scenes of
//! `scenes/stability/` against their analytic expectations.

use nearmiss::math::Real;
use nearmiss::motion::{integrate, Dynamics, Gyroscopic, Integrator, RigidState};
use nearmiss::run::{run, Termination};
use nearmiss::scene::Scene;

use super::sweep::integrator_name;

/// Drifts below this are drawn at this value on the charts' log axes.
#[cfg(feature = "plot")]
pub const DRIFT_CHART_FLOOR: Real = 1e-17;

/// What the stability suite (`nearmiss stability`) runs, by default.
#[derive(Clone, Debug, PartialEq)]
pub struct StabilitySuite {
    /// The stiff-spring scene, in the suite's folder.
    pub spring_scene: &'static str,
    /// The long Dzhanibekov spin scene, in the suite's folder.
    pub spin_scene: &'static str,
    /// The ω·dt at which the spring is run: across the stability limits of
    /// semi-implicit Euler (2) and RK4 (2√2).
    pub spring_omega_dts: Vec<Real>,
    /// The integrators the spring is run with.
    pub integrators: Vec<Integrator>,
    /// The spin's energy and momentum are sampled every this many steps.
    pub spin_sample_every: u64,
}

impl Default for StabilitySuite {
    fn default() -> Self {
        StabilitySuite {
            spring_scene: "stiff_spring.ron",
            spin_scene: "dzhanibekov_long.ron",
            spring_omega_dts: vec![0.1, 0.25, 0.5, 1.0, 1.5, 1.8, 1.9, 1.99, 2.01, 2.1, 2.5, 2.8, 2.85, 3.0],
            integrators: vec![Integrator::SymplecticEuler, Integrator::ExplicitEuler, Integrator::Rk4],
            spin_sample_every: 100,
        }
    }
}

/// One run of the spring sweep.
#[derive(Clone, Debug, PartialEq)]
pub struct SpringRow {
    /// The integrator.
    pub integrator: Integrator,
    /// `ω·dt`.
    pub omega_dt: Real,
    /// The step.
    pub dt: Real,
    /// Whether the stepper declared the run diverged.
    pub diverged: bool,
    /// The stepper's message, if it diverged.
    pub message: String,
    /// The largest relative energy drift seen.
    pub max_energy_drift: Real,
}

/// The first integrated body of a scene and its dynamics.
fn integrated_body(scene: &Scene) -> Option<(usize, Dynamics<'_>)> {
    let model = scene.model();
    model.bodies.iter().enumerate().find_map(|(i, b)| Some((i, b.dynamics(model.gravity)?)))
}

/// The spring's natural frequency `ω = sqrt(Σk / m)` of the scene's first
/// integrated body.
pub fn spring_omega(scene: &Scene) -> Option<Real> {
    let (_, dynamics) = integrated_body(scene)?;
    dynamics.stable_step_limit(Integrator::SymplecticEuler).map(|limit| 2.0 / limit)
}

/// Runs the spring scene at each `ω·dt` with each integrator (the
/// scene's duration kept).
pub fn spring_sweep(scene: &Scene, omega_dts: &[Real], integrators: &[Integrator]) -> Vec<SpringRow> {
    let Some(omega) = spring_omega(scene) else { return Vec::new() };
    let mut rows = Vec::new();
    for &integrator in integrators {
        for &omega_dt in omega_dts {
            let dt = omega_dt / omega;
            let result = run(&scene.with_settings(dt, scene.model().kernel, integrator));
            let (diverged, message) = match &result.termination {
                Termination::Diverged { reason, .. }
                | Termination::NotStarted { reason }
                | Termination::Failed { reason, .. } => (true, reason.clone()),
                _ => (false, String::new()),
            };
            rows.push(SpringRow {
                integrator,
                omega_dt,
                dt,
                diverged,
                message,
                max_energy_drift: result.counters.work.max_energy_drift,
            });
        }
    }
    rows
}

/// The drift of a torque-free spin under one method.
#[derive(Clone, Debug, PartialEq)]
pub struct SpinDrift {
    /// The method.
    pub label: String,
    /// `(time, |E − E0| / E0, |L − L0| / |L0|)` every `sample_every` steps.
    pub samples: Vec<(Real, Real, Real)>,
    /// The largest relative energy drift.
    pub max_energy_drift: Real,
    /// The largest relative drift of the world angular momentum vector.
    pub max_momentum_drift: Real,
    /// Flips of the spin about the body's y axis (sign changes of that
    /// component beyond half its initial value).
    pub flips: usize,
}

/// Integrates the scene's first integrated body, torque-free, for `steps`
/// steps with semi-implicit Euler and the implicit gyroscopic step,
/// semi-implicit Euler with the explicit one, and RK4.
pub fn spin_drift(scene: &Scene, steps: u64, sample_every: u64) -> Vec<SpinDrift> {
    let Some((index, dynamics)) = integrated_body(scene) else { return Vec::new() };
    let body = &scene.model().bodies[index];
    let Some(inertia) = dynamics.inertia else { return Vec::new() };
    let start = RigidState {
        position: nearmiss::math::Point::from(body.pose.translation.vector),
        orientation: body.pose.rotation,
        velocity: body.velocity,
        angular_velocity: body.angular_velocity,
    };
    let momentum = |s: &RigidState| {
        s.orientation * (inertia * s.orientation.inverse_transform_vector(&s.angular_velocity))
    };
    let (e0, l0) = (dynamics.energy(&start), momentum(&start));
    let spin0 = start.orientation.inverse_transform_vector(&start.angular_velocity).y;
    let methods = [
        ("semi-implicit Euler, implicit gyroscopic", Integrator::SymplecticEuler, Gyroscopic::Implicit),
        ("semi-implicit Euler, explicit gyroscopic", Integrator::SymplecticEuler, Gyroscopic::Explicit),
        ("RK4", Integrator::Rk4, Gyroscopic::Implicit),
    ];
    methods
        .iter()
        .map(|&(label, integrator, gyroscopic)| {
            let mut state = start;
            let mut drift = SpinDrift {
                label: label.into(),
                samples: Vec::new(),
                max_energy_drift: 0.0,
                max_momentum_drift: 0.0,
                flips: 0,
            };
            let mut sign = spin0.signum();
            for step in 1..=steps {
                state = integrate(&state, &dynamics, integrator, gyroscopic, scene.model().dt).0;
                let energy = (dynamics.energy(&state) - e0).abs() / e0.abs().max(Real::MIN_POSITIVE);
                let momentum = (momentum(&state) - l0).norm() / l0.norm().max(Real::MIN_POSITIVE);
                drift.max_energy_drift = drift.max_energy_drift.max(energy);
                drift.max_momentum_drift = drift.max_momentum_drift.max(momentum);
                let spin = state.orientation.inverse_transform_vector(&state.angular_velocity).y;
                if spin * sign < -0.5 * spin0.abs() {
                    drift.flips += 1;
                    sign = -sign;
                }
                if step % sample_every == 0 {
                    drift.samples.push((step as Real * scene.model().dt, energy, momentum));
                }
            }
            drift
        })
        .collect()
}

/// The spring sweep as a chart: largest energy drift against `ω·dt`, one
/// series per integrator, log y.
#[cfg(feature = "plot")]
pub fn spring_chart(rows: &[SpringRow]) -> crate::plot::Chart {
    use crate::plot::{Chart, Series};
    let mut series: Vec<Series> = Vec::new();
    for r in rows {
        let label = integrator_name(r.integrator).to_string();
        let index = match series.iter().position(|s| s.label == label) {
            Some(i) => i,
            None => {
                series.push(Series { label, line: true, ..Series::default() });
                series.len() - 1
            }
        };
        series[index].points.push((r.omega_dt, at_least(r.max_energy_drift, DRIFT_CHART_FLOOR)));
    }
    // One marker series for every stopped run (a word at each point
    // overprinted the others).
    let growth = nearmiss::scene::StepParameters::default().divergence_energy_growth;
    series.push(Series {
        label: format!("stopped: energy past {growth}×"),
        points: rows
            .iter()
            .filter(|r| r.diverged)
            .map(|r| (r.omega_dt, at_least(r.max_energy_drift, DRIFT_CHART_FLOOR)))
            .collect(),
        line: false,
        point_labels: Vec::new(),
    });
    Chart {
        title: "Stiff spring (ω = 100 rad/s): largest energy drift over 20 periods".into(),
        x_label: "ω·dt".into(),
        y_label: "max |E − E0| / E0 (log scale)".into(),
        log_x: false,
        log_y: true,
        series,
        marks: vec![
            (2.0, "2: semi-implicit Euler's limit".into()),
            (2.0 * Real::sqrt(2.0), "2√2: RK4's limit".into()),
        ],
        ticks: Vec::new(),
    }
}

/// The spin drifts as a chart: relative energy drift against time.
#[cfg(feature = "plot")]
pub fn spin_chart(drifts: &[SpinDrift]) -> crate::plot::Chart {
    use crate::plot::{Chart, Series};
    Chart {
        title: "Dzhanibekov T-handle: kinetic energy drift".into(),
        x_label: "time (s)".into(),
        y_label: "|E − E0| / E0 (log scale)".into(),
        log_x: false,
        log_y: true,
        series: drifts
            .iter()
            .map(|d| Series {
                label: d.label.clone(),
                points: d.samples.iter().map(|s| (s.0, at_least(s.1, DRIFT_CHART_FLOOR))).collect(),
                line: true,
                point_labels: Vec::new(),
            })
            .collect(),
        marks: Vec::new(),
        ticks: Vec::new(),
    }
}

/// The suite's report in Markdown. `scenes` are the extreme-case verdicts
/// `(file, passed, expected, obtained, error)`.
pub fn stability_markdown(
    springs: &[SpringRow],
    omega: Real,
    drifts: &[SpinDrift],
    steps: u64,
    scenes: &[(String, bool, String, String, Option<Real>)],
) -> String {
    let mut out = String::from("# Stability on stiff and extreme cases\n\n");
    out.push_str(&format!(
        "## Stiff spring, ω = {omega} rad/s, 20 periods\n\nThe stepper stops a run when the body's mechanical energy exceeds its initial value by {}× its scale: \
         the integration is unstable, or too inaccurate to use. Theory (undamped): semi-implicit Euler stable for ω·dt < 2, RK4 for ω·dt < 2√2 ≈ 2.83, explicit Euler never. \
         Stable is not accurate: semi-implicit Euler's energy swings between bounds in the ratio (2 + ω·dt) / (2 − ω·dt) \
         (19 at ω·dt = 1.8, 39 at 1.9, 399 at 1.99), so below its limit too it can pass {0}× and be stopped; that is the criterion, not a divergence.\n\n\
         | integrator | ω·dt | dt | max energy drift | stopped (energy > {0}×) |\n|---|---|---|---|---|\n",
        nearmiss::scene::StepParameters::default().divergence_energy_growth
    ));
    for r in springs {
        out.push_str(&format!(
            "| {} | {} | {:.3e} | {:.2e} | {} |\n",
            integrator_name(r.integrator),
            r.omega_dt,
            r.dt,
            r.max_energy_drift,
            if r.diverged { "yes" } else { "no" }
        ));
    }
    for integrator in [Integrator::SymplecticEuler, Integrator::ExplicitEuler, Integrator::Rk4] {
        let mine: Vec<&SpringRow> = springs.iter().filter(|r| r.integrator == integrator).collect();
        let stable = mine.iter().filter(|r| !r.diverged).map(|r| r.omega_dt).fold(Real::NAN, Real::max);
        let first_diverged = mine.iter().find(|r| r.diverged);
        out.push_str(&format!(
            "\n- {}: largest ω·dt run to the end {}; {}",
            integrator_name(integrator),
            if stable.is_nan() { "none".to_string() } else { stable.to_string() },
            first_diverged.map_or("never stopped.".to_string(), |r| format!(
                "the stepper's message at ω·dt = {}: \"{}\"",
                r.omega_dt, r.message
            ))
        ));
    }
    out.push_str(&format!(
        "\n\n## Dzhanibekov T-handle, {steps} steps\n\n| method | max energy drift | max angular momentum drift | flips |\n|---|---|---|---|\n"
    ));
    for d in drifts {
        out.push_str(&format!(
            "| {} | {:.2e} | {:.2e} | {} |\n",
            d.label, d.max_energy_drift, d.max_momentum_drift, d.flips
        ));
    }
    out.push_str("\n## Extreme cases (scenes/stability/), against their analytic expectations\n\n| scene | result | expected | obtained | error |\n|---|---|---|---|---|\n");
    for (file, passed, expected, obtained, error) in scenes {
        out.push_str(&format!(
            "| {file} | {} | {expected} | {obtained} | {} |\n",
            if *passed { "pass" } else { "FAIL" },
            error.map_or("-".into(), |e| format!("{e:+.2e}"))
        ));
    }
    out
}

/// `value` raised to `floor` for a log axis; NaN stays NaN (left out of
/// the chart rather than drawn at the floor).
#[cfg(feature = "plot")]
fn at_least(value: Real, floor: Real) -> Real {
    if value.is_nan() {
        value
    } else {
        value.max(floor)
    }
}

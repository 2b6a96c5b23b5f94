//! The sweep against analysis: for a body falling from rest under gravity,
//! semi-implicit Euler lands ahead of the parabola by g t dt / 2 (so the
//! contact comes dt/2 early) and explicit Euler behind by as much; RK4 is
//! exact at the step ends. The exact kernel matches the rational reference
//! along the trace.

use nearmiss::mesh::DistanceKernel;
use nearmiss::motion::Integrator;
use nearmiss::scene::Scene;
use nearmiss_cli::report::{parse_integrator, parse_kernel, sweep, sweep_csv};

#[test]
fn integrator_errors_follow_their_analysis() {
    let scene = Scene::load(concat!(env!("CARGO_MANIFEST_DIR"), "/../scenes/falling_box.ron")).unwrap();
    let dts = [0.004, 0.002, 0.001];
    let integrators = [Integrator::SymplecticEuler, Integrator::ExplicitEuler, Integrator::Rk4];
    let report = sweep(&scene, &dts, &[DistanceKernel::Exact], &integrators, &mut |_, _| {});
    assert_eq!(report.rows.len(), 9);
    for row in &report.rows {
        let (dt, error) = (row.setting.dt, row.error.expect("contact found"));
        match row.setting.integrator {
            Integrator::SymplecticEuler => assert!((error + dt / 2.0).abs() <= 0.05 * dt, "{row:?}"),
            Integrator::ExplicitEuler => assert!((error - dt / 2.0).abs() <= 0.05 * dt, "{row:?}"),
            // Within a step the motion is the chord of the parabola: early by at most (g dt²/8)/(g t).
            Integrator::Rk4 => assert!(error <= 0.0 && -error <= dt * dt / 8.0 / 0.95 + 1e-8, "{row:?}"),
        }
        assert!(row.kernel_error <= 1e-15, "{row:?}");
    }
    let csv = sweep_csv(&report);
    assert_eq!(csv.lines().count(), 10);
    assert!(csv.starts_with("dt,kernel,integrator,"));
}

#[test]
fn names_round_trip() {
    for name in ["exact", "dyop-vector", "dyop-plain-vector", "dyop-heron", "dyop-stable-heron"] {
        assert_eq!(nearmiss_cli::report::kernel_name(parse_kernel(name).unwrap()), name);
    }
    for name in ["symplectic-euler", "explicit-euler", "rk4"] {
        assert_eq!(nearmiss_cli::report::integrator_name(parse_integrator(name).unwrap()), name);
    }
    assert!(parse_kernel("heron").is_none());
}

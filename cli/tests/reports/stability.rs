//! The stability suite's bounds: divergence is detected and named, never a
//! silent NaN; the implicit gyroscopic step keeps a Dzhanibekov spin's
//! energy; the extreme-case scenes meet their analytic expectations and are
//! never late; a 1e6 offset changes nothing beyond 1e-9.

use nearmiss::motion::Integrator;
use nearmiss::scene::{Expectation, Scene};
use nearmiss_cli::report::{spin_drift, spring_omega, spring_sweep};

fn scene(name: &str) -> Scene {
    Scene::load(format!("{}/../scenes/stability/{name}", env!("CARGO_MANIFEST_DIR"))).unwrap()
}

#[test]
fn stiff_spring_divergence_is_detected_at_the_analytic_limits() {
    let spring = scene("stiff_spring.ron");
    assert_eq!(spring_omega(&spring), Some(100.0));
    let omega_dts = [0.1, 0.5, 1.0, 1.5, 1.8, 2.01, 2.5, 2.8, 2.85, 3.0];
    let rows = spring_sweep(
        &spring,
        &omega_dts,
        &[Integrator::SymplecticEuler, Integrator::ExplicitEuler, Integrator::Rk4],
    );
    for row in &rows {
        // Never a silent NaN: a finite drift, or a named divergence.
        assert!(row.max_energy_drift.is_finite(), "{row:?}");
        let expected_stable = match row.integrator {
            // Stable below 2; up to 1.8 its bounded energy oscillation stays under the threshold.
            Integrator::SymplecticEuler => row.omega_dt <= 1.8,
            Integrator::Rk4 => row.omega_dt < 2.0 * 2f64.sqrt(),
            Integrator::ExplicitEuler => false,
        };
        assert_eq!(row.diverged, !expected_stable, "{row:?}");
        if row.diverged {
            let limit = match row.integrator {
                Integrator::Rk4 => "2.8284e-2",
                _ => "2.0000e-2",
            };
            assert!(
                row.message.contains(limit),
                "the message should name the largest stable dt: {}",
                row.message
            );
        }
    }
}

#[test]
fn implicit_gyroscopic_step_keeps_the_dzhanibekov_energy() {
    let spin = scene("dzhanibekov_long.ron");
    assert_eq!(spin.run().steps, 100_000);
    let drifts = spin_drift(&spin, spin.run().steps, 1000);
    let (implicit, explicit, rk4) = (&drifts[0], &drifts[1], &drifts[2]);
    // 1.4e-11 with the orientation renormalised each step, 2.8e-9 without.
    assert!(implicit.max_energy_drift <= 1e-10, "{}", implicit.max_energy_drift);
    assert!(implicit.max_momentum_drift <= 1e-3, "{}", implicit.max_momentum_drift);
    assert!(implicit.flips >= 10, "the handle should flip: {}", implicit.flips);
    assert_eq!(implicit.flips, rk4.flips, "the implicit step and RK4 should flip alike");
    assert!(
        explicit.max_energy_drift > 1.0,
        "explicit gyroscopic should gain energy: {}",
        explicit.max_energy_drift
    );
}

#[test]
fn extreme_cases_meet_their_expectations_and_are_never_late() {
    let files = nearmiss_cli::regression::scene_files(std::path::Path::new(concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/../scenes/stability"
    )))
    .unwrap();
    let mut checked = 0;
    for file in files {
        let scene = Scene::load(&file).unwrap();
        let Some(expectation) = scene.run().expect.clone() else { continue };
        let result = nearmiss::run(&scene);
        let verdict = nearmiss_cli::regression::verdict(&scene, &result).unwrap();
        assert!(verdict.passed, "{}: {verdict:?}", file.display());
        if let (Expectation::Contact { time, .. }, Some(contact)) = (expectation, &result.first_contact) {
            assert!(contact.time <= time * (1.0 + 4.0 * f64::EPSILON), "{}: late", file.display());
        }
        checked += 1;
    }
    assert!(checked >= 10, "{checked}");
}

#[test]
fn a_1e6_offset_gives_the_same_time_within_1e_9() {
    let time = |name: &str| nearmiss::run(&scene(name)).first_contact.unwrap().time;
    let (origin, far) = (time("offset_origin.ron"), time("offset_1e6.ron"));
    assert!((origin - far).abs() <= 1e-9 * origin, "{origin} vs {far}");
}

//! A scene written in code and run by the library, without the CLI or any
//! file: the RON text a scene file holds, loaded with `Scene::from_ron_str`
//! (the loader's checks and messages are the CLI's), then
//! `nearmiss::run`.
//!
//! A unit cube falls from rest, its lowest face 1 above a fixed floor,
//! under gravity 9.81: it touches at t = sqrt(2 / 9.81) = 0.4515236...
//! (`Stop` ends the run there). RK4 is exact at the step ends for a
//! constant acceleration; within a step the body moves along the chord,
//! below the parabola, so the contact can only be early, by at most
//! (g dt² / 8) / (g t) = 2.8e-7 at dt = 0.001, plus the contact distance
//! over the speed (1e-6 × 0.87 / 4.4 = 2e-7).
//!
//! Run: `cargo run --release --example scene_from_code`

use nearmiss::run::run;
use nearmiss::scene::Scene;

fn main() {
    let text = r#"Scene(
        name: "falling_cube",
        dt: 0.001,
        duration: 2.0,
        integrator: Rk4,
        gravity: (0.0, 0.0, -9.81),
        on_contact: Stop,
        bodies: [
            (name: "floor", mesh: Box(half_extents: (5.0, 5.0, 0.5)), position: (0.0, 0.0, -0.5), fixed: true),
            (name: "cube", mesh: Box(half_extents: (0.5, 0.5, 0.5)), position: (0.0, 0.0, 1.5)),
        ],
    )"#;
    let scene = match Scene::from_ron_str(text) {
        Ok(scene) => scene,
        Err(error) => {
            eprintln!("error: {error}");
            std::process::exit(2);
        }
    };
    let result = run(&scene);
    println!("ended: {:?} at t = {}", result.termination, result.end_time);
    match &result.first_contact {
        Some(contact) => println!(
            "first contact: {} and {} at t = {} (analytic {}), distance {:e}",
            result.bodies[contact.body_a],
            result.bodies[contact.body_b],
            contact.time,
            (2.0_f64 / 9.81).sqrt(),
            contact.closest.distance
        ),
        None => println!("no contact"),
    }
}

//! Time per step of a scene of N tumbling bodies (icospheres of 20–1280
//! triangles and boxes, random spins up to 8 rad/s, random velocities up to
//! 2), spread in a cube whose side grows with N^(1/3) so the density stays
//! the same, contacts recorded and the bodies kept moving (they pass through
//! each other: nearmiss has no collision response). dt = 1/240, 24 steps.
//! Usage: `cargo run --release --example many_bodies -- 10 100 1000`.
use nearmiss::samples::Rng;
use nearmiss::scene::Scene;
use nearmiss::stepper::{run_with, RunOptions};

fn scene(bodies: usize, seed: u64) -> Scene {
    let mut rng = Rng::new(seed);
    let side = 4.0 * (bodies as f64).cbrt();
    let mut text = format!(
        "Scene(name: \"many_{bodies}\", dt: 0.004166666666666667, steps: 24, on_contact: Record, bodies: ["
    );
    for k in 0..bodies {
        let v = |rng: &mut Rng, s: f64| {
            let x = rng.in_unit_ball() * s;
            format!("({:?}, {:?}, {:?})", x.x, x.y, x.z)
        };
        let mesh = match k % 5 {
            0 => "Box(half_extents: (0.3, 0.2, 0.25))".to_string(),
            n => format!("Icosphere(radius: 0.3, subdivisions: {})", n - 1),
        };
        let (position, velocity, spin) = (v(&mut rng, side / 2.0), v(&mut rng, 2.0), v(&mut rng, 8.0));
        text.push_str(&format!("(name: \"b{k}\", mesh: {mesh}, position: {position}, velocity: {velocity}, angular_velocity: {spin}),"));
    }
    text.push_str("])");
    Scene::from_ron_str(&text).expect("a valid scene")
}

fn main() {
    println!("| bodies | ms per step | steps per s | broad phase ms/step | CCD ms/step | candidate pairs/step | contacts |");
    println!("|---|---|---|---|---|---|---|");
    for arg in std::env::args().skip(1) {
        let n: usize = arg.parse().expect("a body count");
        let scene = scene(n, 1);
        let result = run_with(&scene, RunOptions::default(), &mut |_| {});
        let steps = result.steps as f64;
        let c = &result.counters;
        println!(
            "| {n} | {:.3} | {:.0} | {:.3} | {:.3} | {:.0} | {} |",
            result.wall_time_s * 1e3 / steps,
            steps / result.wall_time_s,
            c.broad_phase_s * 1e3 / steps,
            c.ccd_s * 1e3 / steps,
            c.candidate_pairs as f64 / steps,
            result.contacts.len()
        );
    }
}

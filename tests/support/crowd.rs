//! A random crowd of tumbling icospheres and boxes, for runs that compare
//! ways of computing the same thing.

use nearmiss::samples::Rng;
use nearmiss::scene::Scene;

/// `bodies` tumbling icospheres and boxes in a 6-unit cube (positions,
/// velocities and spins from `seed`), 0.6 s at steps of 0.01, with the
/// scene's other `settings` (RON fields, e.g. `on_contact: Record`) and
/// each body's (`body`, e.g. `density: 1.0`, or none).
pub fn random_crowd(bodies: usize, seed: u64, settings: &str, body: &str) -> Scene {
    let crowd = crowd_bodies(bodies, seed, body);
    Scene::from_ron_str(&format!(
        "Scene(name: \"many\", dt: 0.01, duration: 0.6, {settings}, bodies: [{crowd}])"
    ))
    .unwrap()
}

/// The bodies of [`random_crowd`] as RON entries (each followed by a comma).
pub fn crowd_bodies(bodies: usize, seed: u64, body: &str) -> String {
    let mut rng = Rng::new(seed);
    let mut text = String::new();
    for k in 0..bodies {
        let v = |rng: &mut Rng, s: f64| {
            let x = rng.in_unit_ball() * s;
            format!("({:?}, {:?}, {:?})", x.x, x.y, x.z)
        };
        let mesh = if k % 2 == 0 {
            format!("Icosphere(radius: {:?}, subdivisions: 1)", rng.range(0.2, 0.5))
        } else {
            format!(
                "Box(half_extents: ({:?}, {:?}, {:?}))",
                rng.range(0.1, 0.4),
                rng.range(0.1, 0.4),
                rng.range(0.1, 0.4)
            )
        };
        let (position, velocity, spin) = (v(&mut rng, 3.0), v(&mut rng, 3.0), v(&mut rng, 8.0));
        text.push_str(&format!(
            "(name: \"b{k}\", mesh: {mesh}, position: {position}, velocity: {velocity}, angular_velocity: {spin}, {body}),"
        ));
    }
    text
}

//! A few steps of any scene the loader accepts: never a panic, every number
//! of the result finite, every contact within its contact distance.
#![no_main]

use libfuzzer_sys::fuzz_target;
use nearmiss::scene::Scene;

/// The most steps (and bodies) a fuzz input may run, to keep inputs fast.
const MAX_STEPS: u64 = 50;
const MAX_BODIES: usize = 8;

fuzz_target!(|data: &[u8]| {
    let Ok(text) = std::str::from_utf8(data) else { return };
    let Ok(scene) = Scene::from_ron_str(text) else { return };
    let bodies = &scene.model().bodies;
    if bodies.len() > MAX_BODIES || bodies.iter().any(|b| b.mesh.triangles().len() > 2000) {
        return;
    }
    if scene.check_steps(MAX_STEPS).is_err() {
        return;
    }
    let result = nearmiss::run(&scene);
    assert_eq!(result.first_non_finite(), None);
    for contact in &result.contacts {
        assert!(contact.closest.distance <= contact.contact_distance, "{contact:?}");
        assert!(contact.time >= 0.0 && contact.time <= result.end_time, "{contact:?}");
    }
});

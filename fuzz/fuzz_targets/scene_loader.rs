//! The scene loader on arbitrary text: never a panic; an accepted scene
//! has only finite numbers within the documented range.
#![no_main]

use libfuzzer_sys::fuzz_target;
use nearmiss::scene::{Scene, MAX_MAGNITUDE};

fuzz_target!(|data: &[u8]| {
    let Ok(text) = std::str::from_utf8(data) else { return };
    let Ok(scene) = Scene::from_ron_str(text) else { return };
    let dt = scene.model().dt;
    assert!(dt.is_finite() && dt > 0.0 && dt <= MAX_MAGNITUDE);
    assert!(scene.run().steps >= 1);
    for body in scene.model().bodies.iter() {
        let pose = body.pose.translation.vector;
        assert!(pose.iter().all(|c| c.is_finite()), "{}: position", body.name);
        assert!((body.pose.rotation.norm() - 1.0).abs() < 1e-9, "{}: orientation not unit", body.name);
        assert!(body.mesh.radius().is_finite() && body.mesh.radius() > 0.0, "{}: mesh", body.name);
    }
});

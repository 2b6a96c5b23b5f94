//! Symptom: next to a big body the contact distance was relative to both
//! bodies' sizes, so a unit box falling onto a floor of half-extent 1e6 was
//! reported at t = 0.49, 0.71 units above it (true contact t = 1), and at
//! 1e7 "initially touching". The contact distance follows the smaller body.

use nearmiss::run::run;
use nearmiss::scene::Scene;

#[test]
fn a_unit_box_meets_a_floor_of_any_size_on_time() {
    for half in [1.0, 1e3, 1e6, 1e7] {
        // The box's bottom face starts 1 above the floor's top and falls at 1.
        let text = format!(
            r#"Scene(name: "floor", dt: 0.01, duration: 2.0, bodies: [
                (name: "floor", mesh: Box(half_extents: ({half:?}, {half:?}, {half:?})), position: (0.0, 0.0, {:?}), fixed: true),
                (name: "box", mesh: Box(half_extents: (0.5, 0.5, 0.5)), position: (0.0, 0.0, 1.5), velocity: (0.0, 0.0, -1.0)),
            ])"#,
            -half
        );
        let result = run(&Scene::from_ron_str(&text).unwrap());
        let contact = result.first_contact.unwrap_or_else(|| panic!("floor {half:e}: no contact"));
        let error = contact.time - 1.0;
        assert!(error <= 0.0, "floor {half:e}: late by {error:e}");
        assert!(error.abs() <= 1e-6, "floor {half:e}: reported at t = {}, error {error:e}", contact.time);
        // The contact distance is the box's (1e-6 x its radius), not the floor's.
        assert!(contact.contact_distance <= 1e-6, "floor {half:e}: {}", contact.contact_distance);
        assert!(contact.guaranteed_distance < contact.contact_distance);
    }
}

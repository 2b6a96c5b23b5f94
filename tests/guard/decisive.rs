//! Issue 43 §2 and §3: where rapier alone passes a mesh through another or
//! lets it sink far beyond its allowed error (a triangle-mesh bullet at 500
//! to 2,000 units/s into 1 and 2 mm plates, at the origin and 1e6 away; a
//! trimesh plate; a thin blade spinning into a ball, kinematic and dynamic;
//! a ball swept by a kinematic paddle into a thin plate; turned boxes
//! meeting head-on from beyond rapier's reach; a kinematic wall pushing a
//! crate), the guarded run puts no vertex out of the far side of a plate
//! while over it, overlaps no pair deeper than rapier's allowed linear error
//! at any pose it hands back, and holds no body still while rapier moves
//! it.
//!
//! The worlds are `tests/support/guard_worlds.rs`'s; each runs rapier alone
//! in the same test, which must fail it (the world's premise).

use crate::guard_worlds::{rapier_fails, GuardWorld};
use nearmiss::guard::GuardOptions;
use nearmiss::math::Real;

/// rapier 0.36's allowed linear error under its default parameters.
const ALLOWED_ERROR: Real = 0.005;

fn dynamic_bodies(world: &GuardWorld) -> Vec<bool> {
    world.handles.iter().map(|(_, h)| world.bodies[*h].is_dynamic()).collect()
}

#[test]
fn where_rapier_lets_a_mesh_through_the_guard_stops_it_and_freezes_nothing() {
    let count = rapier_fails().len();
    for k in 0..count {
        let world = rapier_fails().swap_remove(k);
        let (name, dynamic) = (world.name.clone(), dynamic_bodies(&world));
        let alone = world.run_alone();
        let guarded = rapier_fails().swap_remove(k).run_guarded(GuardOptions::default()).expect("decided");
        // The premise: rapier alone fails it.
        assert!(
            alone.deepest().0 > ALLOWED_ERROR || alone.far_margin() < 0.0,
            "{name}: rapier alone holds it (deepest {}, far side {})",
            alone.deepest().0,
            alone.far_margin()
        );
        let (deepest, step, i, j) = guarded.deepest();
        assert!(
            deepest <= ALLOWED_ERROR,
            "{name}: bodies {i} and {j} overlap by {deepest} after step {step}"
        );
        let margin = guarded.far_margin();
        assert!(margin > 0.0, "{name}: a vertex {} past the plate's far face", -margin);
        assert_eq!(guarded.frozen(&dynamic, 1e-9), None, "{name}: a body held still while rapier moves it");
        assert!(guarded.rewinds > 0 || !guarded.events.is_empty(), "{name}: the guard saw nothing");
    }
}

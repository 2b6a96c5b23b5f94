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

#[test]
fn a_thin_blade_never_sweeps_through_the_ball() {
    // The blade (2 × 0.04 × 0.4, along its x, turning about z at 60 rad/s)
    // meets a ball of radius 0.05 at radius 0.5 from its +y side: in the
    // blade's frame the ball comes at the +x arm from y > 0. Over the arm
    // (0 < x < 1 in the blade's frame) at two steps running, the ball's
    // centre must never go from the near side (y > 0) to past the blade's
    // far face (y < −0.02): rapier alone sweeps it through.
    for kinematic in [true, false] {
        let crossed = |run: &crate::guard_worlds::WorldRun| {
            let local: Vec<_> = run
                .poses
                .iter()
                .map(|p| p[0].inverse_transform_point(&p[1].translation.vector.into()))
                .collect();
            local.windows(2).any(|w| {
                let over = |p: &nalgebra::Point3<Real>| p.x > 0.0 && p.x < 1.0;
                over(&w[0]) && over(&w[1]) && w[0].y > 0.0 && w[1].y < -0.02
            })
        };
        let alone = crate::guard_worlds::blade(kinematic).run_alone();
        assert!(crossed(&alone), "kinematic {kinematic}: rapier alone keeps the ball in front");
        let guarded =
            crate::guard_worlds::blade(kinematic).run_guarded(GuardOptions::default()).expect("decided");
        assert!(!crossed(&guarded), "kinematic {kinematic}: the ball went through the blade");
    }
}

#[test]
fn a_resting_stack_elsewhere_does_not_stop_the_guard_rewinding() {
    // A plate at 100 units/s into a wall while a stack of five rests: the
    // plate's impact is rewound (rapier solves it at the contact), and the
    // stack stands (each box within rapier's allowed error per contact
    // below it of where it started).
    let world = crate::guard_worlds::plate_beside_a_stack();
    let guarded = world.run_guarded(GuardOptions::default()).expect("decided");
    assert!(guarded.rewinds >= 1, "no rewind for the plate");
    for (level, start) in [0.5, 1.5, 2.5, 3.5, 4.5].into_iter().enumerate() {
        let drift = (guarded.last_pose(level + 1).translation.vector
            - nalgebra::Vector3::new(0.0, 0.0, start))
        .norm();
        assert!(drift <= (level + 1) as Real * ALLOWED_ERROR, "box {level} drifted {drift}");
    }
}

#[test]
fn turned_boxes_meeting_from_beyond_rapiers_reach_leave_as_rapiers_solve_sends_them() {
    // Equal boxes turned 35° at z = 120, 2 each head-on, restitution 1, dt
    // 1/60: rapier alone does not see them coming (0.067 a step against its
    // 0.02) and solves them 3.3e-2 deep; guarded, rapier solves them at the
    // contact. Either way it is rapier's solve of the collision that sends
    // them off (its restitution on a corner adds speed: 2.28 each): the
    // guarded boxes leave at rapier alone's speed and spin, to 2%, moving
    // apart, their total momentum 0 to rounding.
    let alone = crate::guard_worlds::turned_boxes_head_on(2.0, 1.0 / 60.0).run_alone();
    let guarded = crate::guard_worlds::turned_boxes_head_on(2.0, 1.0 / 60.0)
        .run_guarded(GuardOptions::default())
        .unwrap();
    let (a, g) = (alone.velocities.last().unwrap(), guarded.velocities.last().unwrap());
    for body in 0..2 {
        let (speed, rapier) = (g[body].0.norm(), a[body].0.norm());
        assert!(
            (speed - rapier).abs() < 0.02 * rapier,
            "body {body}: {speed} against rapier alone's {rapier}"
        );
        let (spin, rapier) = (g[body].1.norm(), a[body].1.norm());
        assert!((spin - rapier).abs() < 0.02 * rapier, "body {body}: spin {spin} against {rapier}");
    }
    assert!((g[0].0 + g[1].0).norm() < 1e-9, "momentum {:?}", g[0].0 + g[1].0);
    let poses = guarded.poses.last().unwrap();
    let between = poses[1].translation.vector - poses[0].translation.vector;
    assert!(between.dot(&(g[1].0 - g[0].0)) > 0.0, "not moving apart");
}

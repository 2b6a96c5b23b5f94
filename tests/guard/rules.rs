//! Issue 43 §4: rapier's own rules. A pair rapier would not collide is not
//! guarded (sensors, collision groups, solver groups, disabled colliders,
//! an application's contact filter or contact modification): a fast cube
//! passes a thin plate guarded exactly as it does under rapier alone, bit
//! for bit. Where rapier does collide the same pair, the guard stops it.
//! Heightfield and half-space grounds are guarded; a shape the guard does
//! not sweep is refused with the body and the collider named, and a way
//! around.

use crate::guard_worlds::{trimesh_box, v, GuardWorld, WorldRun};
use nearmiss::guard::{Guard, GuardError, GuardOptions};
use nearmiss::math::Real;
use rapier3d_f64::prelude::*;

/// rapier 0.36's allowed linear error under its default parameters.
const ALLOWED_ERROR: Real = 0.005;

/// A 0.2 triangle-mesh cube falling at 20 units/s from z = 1 onto a 1 mm
/// plate made by `plate` (its collider), no gravity, 12 steps of 1/60:
/// rapier alone puts it through (0.33 a step).
fn cube_onto(plate: impl Fn() -> ColliderBuilder, cube: impl Fn() -> ColliderBuilder) -> GuardWorld {
    let mut world = GuardWorld::new("cube onto a plate", 1.0 / 60.0, 12, 0.0);
    world.add("plate", RigidBodyBuilder::fixed(), plate());
    world.add(
        "cube",
        RigidBodyBuilder::dynamic().translation(v(0.0, 0.0, 1.0)).linvel(v(0.0, 0.0, -20.0)),
        cube(),
    );
    world
}

fn plate() -> ColliderBuilder {
    ColliderBuilder::cuboid(2.0, 2.0, 0.0005)
}

fn cube() -> ColliderBuilder {
    trimesh_box([0.1, 0.1, 0.1])
}

/// The cube's centre's lowest z over a run.
fn lowest_centre(run: &WorldRun) -> Real {
    run.poses.iter().map(|p| p[1].translation.vector.z).fold(Real::INFINITY, Real::min)
}

/// Runs `make`'s world alone and guarded with `hooks`, and checks the pair
/// is left to rapier: the same poses and velocities, bit for bit, and the
/// cube through the plate.
fn left_to_rapier(what: &str, make: impl Fn() -> GuardWorld, hooks: &(dyn PhysicsHooks + 'static)) {
    let alone = {
        let mut world = make();
        let mut pipeline = crate::guard_worlds::Rapier::new();
        let mut run = Vec::new();
        for _ in 0..world.steps {
            let dt = world.parameters.dt;
            pipeline.step_with_hooks(
                &mut world.bodies,
                &mut world.colliders,
                world.gravity,
                &world.parameters,
                dt,
                hooks,
            );
            run.push(nearmiss::math::pose_from_parry(world.bodies[world.handle(1)].position()));
        }
        run
    };
    assert!(alone.last().expect("steps").translation.vector.z < -1.0, "{what}: rapier alone stopped it");
    let guarded = make().run_guarded_with(GuardOptions::default(), hooks).expect("decided");
    let guarded: Vec<_> = guarded.poses.iter().map(|p| p[1]).collect();
    assert_eq!(alone, guarded, "{what}: the guard acted on a pair rapier does not collide");
}

#[test]
fn a_sensor_plate_groups_solver_groups_and_a_disabled_plate_are_not_walls() {
    use rapier3d_f64::prelude::{Group, InteractionTestMode};
    let apart = |groups: InteractionGroups| groups;
    let one = InteractionGroups::new(Group::GROUP_1, Group::GROUP_1, InteractionTestMode::And);
    let two = InteractionGroups::new(Group::GROUP_2, Group::GROUP_2, InteractionTestMode::And);
    left_to_rapier("a sensor plate", || cube_onto(|| plate().sensor(true), cube), &());
    left_to_rapier(
        "collision groups that exclude each other",
        || cube_onto(|| plate().collision_groups(apart(one)), || cube().collision_groups(two)),
        &(),
    );
    left_to_rapier(
        "solver groups that exclude each other",
        || cube_onto(|| plate().solver_groups(one), || cube().solver_groups(two)),
        &(),
    );
    left_to_rapier("a disabled plate", || cube_onto(|| plate().enabled(false), cube), &());
    // The same pair with rapier's rules met: the guard stops the cube on
    // the plate's near half.
    let guarded = cube_onto(plate, cube).run_guarded(GuardOptions::default()).expect("decided");
    assert!(lowest_centre(&guarded) - 0.1 > 0.0, "the cube reaches {}", lowest_centre(&guarded) - 0.1);
}

/// An application's hooks: its filter refuses (or accepts) every pair, or
/// its contact modification drops every contact.
struct Hooks {
    accept: bool,
    drop_contacts: bool,
}

impl PhysicsHooks for Hooks {
    fn filter_contact_pair(&self, _context: &PairFilterContext) -> Option<SolverFlags> {
        self.accept.then_some(SolverFlags::COMPUTE_RIGID_IMPULSES)
    }

    fn modify_solver_contacts(&self, context: &mut ContactModificationContext) {
        if let (true, Some(rigid)) = (self.drop_contacts, context.rigid_mut()) {
            rigid.solver_contacts.clear();
        }
    }
}

#[test]
fn an_applications_contact_filter_and_contact_modification_are_honoured() {
    let filtered = || plate().active_hooks(ActiveHooks::FILTER_CONTACT_PAIRS);
    let refuse = Hooks { accept: false, drop_contacts: false };
    left_to_rapier("a filter refusing the pair", || cube_onto(filtered, cube), &refuse);
    let modified = || plate().active_hooks(ActiveHooks::MODIFY_SOLVER_CONTACTS);
    let drop_them = Hooks { accept: true, drop_contacts: true };
    left_to_rapier("a hook dropping the pair's contacts", || cube_onto(modified, cube), &drop_them);
    // A filter accepting the pair: guarded, the cube stops on the plate.
    let accept = Hooks { accept: true, drop_contacts: false };
    let guarded =
        cube_onto(filtered, cube).run_guarded_with(GuardOptions::default(), &accept).expect("decided");
    assert!(lowest_centre(&guarded) - 0.1 > 0.0, "the cube reaches {}", lowest_centre(&guarded) - 0.1);
}

#[test]
fn heightfield_and_half_space_grounds_are_guarded() {
    // A 0.2 triangle-mesh cube at 20 units/s onto a flat heightfield (its
    // surface z = 0) and onto a half-space below z = 0: rapier alone lets
    // it through the heightfield and deep into the half-space; guarded, it
    // never goes deeper than rapier's allowed error below z = 0.
    type Ground = fn() -> ColliderBuilder;
    let grounds: [(&str, Ground); 2] =
        [("a heightfield", heightfield_ground), ("a half-space", half_space_ground)];
    for (name, ground) in grounds {
        let alone = cube_onto(ground, cube).run_alone();
        let bottom = lowest_centre(&alone) - 0.1;
        assert!(bottom < -10.0 * ALLOWED_ERROR, "{name}: rapier alone held it ({bottom})");
        let guarded = cube_onto(ground, cube).run_guarded(GuardOptions::default()).expect("guarded");
        let bottom = lowest_centre(&guarded) - 0.1;
        assert!(bottom >= -ALLOWED_ERROR, "{name}: the cube's bottom reaches {bottom}");
    }
}

/// A flat heightfield whose surface is z = 0 (rapier's heightfields lie in
/// x and z with their heights along y: turned so that z is up).
fn heightfield_ground() -> ColliderBuilder {
    let heights = parry3d_f64::utils::Array2::new(5, 5, vec![0.0; 25]);
    ColliderBuilder::heightfield(heights, v(10.0, 1.0, 10.0)).rotation(v(
        std::f64::consts::FRAC_PI_2,
        0.0,
        0.0,
    ))
}

/// The half-space below z = 0.
fn half_space_ground() -> ColliderBuilder {
    ColliderBuilder::halfspace(nalgebra::Unit::new_unchecked(Vector::Z))
}

#[test]
fn a_shape_the_guard_does_not_sweep_is_refused_naming_the_body_and_collider() {
    let (mut bodies, mut colliders) = (RigidBodySet::new(), ColliderSet::new());
    let floor = bodies.insert(RigidBodyBuilder::fixed());
    colliders.insert_with_parent(ColliderBuilder::cuboid(1.0, 1.0, 1.0), floor, &mut bodies);
    let cone = bodies.insert(RigidBodyBuilder::dynamic());
    colliders.insert_with_parent(ColliderBuilder::cone(0.5, 0.2), cone, &mut bodies);
    let parameters = IntegrationParameters::default();
    let refused = Guard::new(&bodies, &mut colliders, &[floor, cone], &parameters, GuardOptions::default());
    let Err(error @ GuardError::Shape { .. }) = refused else { panic!("a cone is swept?") };
    let message = error.to_string();
    for part in ["rigid body #1", "collider #1", "Cone", "ColliderBuilder::trimesh"] {
        assert!(message.contains(part), "{message}");
    }
}

#[test]
fn bodies_joined_with_contacts_disabled_are_left_to_rapier() {
    // A robot's link hinged to a fixed base, their boxes overlapping at the
    // hinge (contacts disabled on the joint, as rapier's robots have it),
    // swinging under gravity: rapier never solves the pair, so after
    // `honour_joints` the guarded run is rapier's, bit for bit. Without it
    // the guard would take the overlap for a contact rapier let sink.
    let build = || {
        let (mut bodies, mut colliders) = (RigidBodySet::new(), ColliderSet::new());
        let base = bodies.insert(RigidBodyBuilder::fixed());
        colliders.insert_with_parent(ColliderBuilder::cuboid(0.1, 0.1, 0.1), base, &mut bodies);
        let link = bodies.insert(RigidBodyBuilder::dynamic().translation(v(0.25, 0.0, 0.0)));
        colliders.insert_with_parent(ColliderBuilder::cuboid(0.2, 0.05, 0.05), link, &mut bodies);
        let mut joints = ImpulseJointSet::new();
        let hinge = RevoluteJointBuilder::new(Vector::Y)
            .local_anchor1(v(0.08, 0.0, 0.0))
            .local_anchor2(v(-0.17, 0.0, 0.0))
            .contacts_enabled(false);
        joints.insert(base, link, hinge, true);
        (bodies, colliders, joints, [base, link])
    };
    let parameters = IntegrationParameters { dt: 1.0 / 60.0, ..Default::default() };
    let gravity = v(0.0, 0.0, -9.81);
    let run = |guarded: bool| {
        let (mut bodies, mut colliders, joints, handles) = build();
        let mut rapier = crate::guard_worlds::Rapier::new();
        *rapier.joints() = joints;
        let mut guard = guarded.then(|| {
            let mut guard =
                Guard::new(&bodies, &mut colliders, &handles, &parameters, GuardOptions::default())
                    .expect("cuboids");
            guard.honour_joints(rapier.joints());
            guard
        });
        let mut poses = Vec::new();
        for _ in 0..90 {
            let mut step = |bodies: &mut RigidBodySet, dt: Real| {
                rapier.step(bodies, &mut colliders, gravity, &parameters, dt)
            };
            match guard.as_mut() {
                Some(guard) => assert!(guard.step(&mut bodies, step).expect("decided").is_empty()),
                None => step(&mut bodies, parameters.dt),
            }
            poses.push(*bodies[handles[1]].position());
        }
        poses
    };
    let alone = run(false);
    let swung = alone.last().expect("steps").translation.z;
    assert!(swung < -0.1, "the link swings down: z = {swung}");
    assert_eq!(alone, run(true));
}

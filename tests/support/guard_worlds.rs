//! rapier3d-f64 worlds written from physics, each run by rapier alone and
//! under a `nearmiss::guard::Guard`, step for step: the guard's tests
//! (`tests/guard/`) and its report (`tools`' `guard_report`) share them.
//!
//! Nothing here is expected of the guard: a world says what it is (bodies,
//! materials, speeds), the runs record what happened (poses, velocities,
//! the deepest overlap by parry's contact query on each collider's convex
//! hull), and the tests compare the two runs, or a run with physics.

use nearmiss::guard::{Guard, GuardError, GuardEvent, GuardOptions};
use nearmiss::math::{pose_from_parry, pose_to_parry, Pose, Real, Vector as V};
use rapier3d_f64::prelude::*;

/// A world: rapier's sets and parameters, what the guard guards, and how
/// long it runs.
pub struct GuardWorld {
    /// Its name in messages and reports.
    pub name: String,
    pub bodies: RigidBodySet,
    pub colliders: ColliderSet,
    pub parameters: IntegrationParameters,
    pub gravity: Vector,
    /// Every body, named, in insertion order (the guard guards them all).
    pub handles: Vec<(String, RigidBodyHandle)>,
    pub steps: usize,
    /// Velocities set before given steps: `(step, body, linear velocity)`
    /// (a velocity-based kinematic body that stops, say).
    pub script: Vec<(usize, usize, V)>,
    /// A plate a body must never come out of the far side of.
    pub far_side: Option<FarSide>,
    /// The world's size (differences of poses are compared relative to it).
    pub size: Real,
}

/// A run of a world: after each step, every body's pose and velocities, the
/// deepest overlap of any two of its bodies' colliders, and what the guard
/// did.
pub struct WorldRun {
    /// `poses[s][i]`: body `i` after step `s + 1`.
    pub poses: Vec<Vec<Pose>>,
    /// `velocities[s][i]`: body `i`'s linear and angular velocity then.
    pub velocities: Vec<Vec<(V, V)>>,
    /// The deepest overlap after each step, and its pair.
    pub deepest: Vec<(Real, usize, usize)>,
    /// The far-side margin after each step (empty without a far side).
    pub far_margins: Vec<Real>,
    /// The guard's rewinds and events (empty for rapier alone).
    pub rewinds: u64,
    pub events: Vec<GuardEvent>,
}

crate::rapier_app!(rapier3d_f64);

impl GuardWorld {
    /// An empty world of `steps` steps of `dt`, gravity `g` along −z.
    pub fn new(name: impl Into<String>, dt: Real, steps: usize, g: Real) -> GuardWorld {
        let mut parameters = IntegrationParameters { dt, ..Default::default() };
        // The worlds' speeds are what they say (rapier caps 400 units/s).
        parameters.normalized_max_linear_velocity = Real::MAX;
        GuardWorld {
            name: name.into(),
            bodies: RigidBodySet::new(),
            colliders: ColliderSet::new(),
            parameters,
            gravity: Vector::new(0.0, 0.0, -g),
            handles: Vec::new(),
            steps,
            script: Vec::new(),
            far_side: None,
            size: 1.0,
        }
    }

    /// Adds a body with one collider; returns its index.
    pub fn add(&mut self, name: &str, body: RigidBodyBuilder, collider: ColliderBuilder) -> usize {
        let handle = self.bodies.insert(body);
        self.colliders.insert_with_parent(collider, handle, &mut self.bodies);
        self.handles.push((name.to_string(), handle));
        self.handles.len() - 1
    }

    /// The handle of body `i`.
    pub fn handle(&self, i: usize) -> RigidBodyHandle {
        self.handles[i].1
    }

    /// Runs rapier alone.
    pub fn run_alone(mut self) -> WorldRun {
        let mut pipeline = Rapier::new();
        let mut run = WorldRun::new();
        for step in 0..self.steps {
            self.apply_script(step);
            let dt = self.parameters.dt;
            pipeline.step(&mut self.bodies, &mut self.colliders, self.gravity, &self.parameters, dt);
            run.record(&self);
        }
        run
    }

    /// Runs rapier guarded by a guard of every body under `options`.
    pub fn run_guarded(self, options: GuardOptions) -> Result<WorldRun, GuardError> {
        self.run_guarded_with(options, &())
    }

    /// [`run_guarded`](Self::run_guarded) with rapier's `hooks` (the guard
    /// is handed them too).
    pub fn run_guarded_with(
        mut self,
        options: GuardOptions,
        hooks: &(dyn PhysicsHooks + 'static),
    ) -> Result<WorldRun, GuardError> {
        let handles: Vec<RigidBodyHandle> = self.handles.iter().map(|(_, h)| *h).collect();
        let mut guard = Guard::new(&self.bodies, &mut self.colliders, &handles, &self.parameters, options)?;
        let mut pipeline = Rapier::new();
        let mut run = WorldRun::new();
        for step in 0..self.steps {
            self.apply_script(step);
            let GuardWorld { bodies, colliders, parameters, gravity, .. } = &mut self;
            let events = guard.step_with_hooks(bodies, colliders, hooks, |bodies, colliders, dt| {
                pipeline.step_with_hooks(bodies, colliders, *gravity, parameters, dt, hooks)
            })?;
            run.events.extend(events);
            run.record(&self);
        }
        run.rewinds = guard.rewinds();
        Ok(run)
    }

    fn apply_script(&mut self, step: usize) {
        for &(at, body, velocity) in &self.script {
            if at == step {
                let handle = self.handles[body].1;
                self.bodies[handle].set_linvel(Vector::new(velocity.x, velocity.y, velocity.z), true);
            }
        }
    }

    /// The deepest overlap of any two colliders of different bodies (not
    /// both fixed) by parry's contact query on their convex hulls (balls as
    /// balls), and the pair's body indices.
    pub fn deepest_overlap(&self) -> (Real, usize, usize) {
        let mut deepest = (0.0, 0, 0);
        for i in 0..self.handles.len() {
            for j in i + 1..self.handles.len() {
                let (bi, bj) = (&self.bodies[self.handles[i].1], &self.bodies[self.handles[j].1]);
                if bi.is_fixed() && bj.is_fixed() {
                    continue;
                }
                for ci in bi.colliders() {
                    for cj in bj.colliders() {
                        let (ci, cj) = (&self.colliders[*ci], &self.colliders[*cj]);
                        if ci.is_sensor() || cj.is_sensor() {
                            continue;
                        }
                        let depth = overlap((ci, bi), (cj, bj));
                        if depth > deepest.0 {
                            deepest = (depth, i, j);
                        }
                    }
                }
            }
        }
        deepest
    }
}

/// Where a collider is: its body's pose (what the guard set last; rapier
/// moves the collider itself only at its next step) times its pose on it.
pub fn collider_pose(collider: &Collider, body: &RigidBody) -> rapier3d_f64::math::Pose {
    collider.position_wrt_parent().map_or(*body.position(), |local| *body.position() * *local)
}

/// How deep two colliders (with their bodies) overlap (0 apart), by
/// parry's contact query on their convex hulls (balls and cuboids as they
/// are).
pub fn overlap((a, body_a): (&Collider, &RigidBody), (b, body_b): (&Collider, &RigidBody)) -> Real {
    let (sa, sb) = (convex(a.shape()), convex(b.shape()));
    let (pa, pb) = (collider_pose(a, body_a), collider_pose(b, body_b));
    let contact = parry3d_f64::query::contact(&pa, &*sa, &pb, &*sb, 0.0).expect("convex shapes");
    contact.map_or(0.0, |c| (-c.dist).max(0.0))
}

/// A shape parry's contact query takes: balls, cuboids and convex
/// polyhedra as they are, a triangle mesh as its vertices' hull.
fn convex(shape: &dyn Shape) -> SharedShape {
    if let Some(mesh) = shape.as_trimesh() {
        return SharedShape::convex_hull(mesh.vertices()).expect("a hull");
    }
    SharedShape(std::sync::Arc::from(shape.clone_dyn()))
}

impl WorldRun {
    fn new() -> WorldRun {
        WorldRun {
            poses: Vec::new(),
            velocities: Vec::new(),
            deepest: Vec::new(),
            far_margins: Vec::new(),
            rewinds: 0,
            events: Vec::new(),
        }
    }

    fn record(&mut self, world: &GuardWorld) {
        let bodies = world.handles.iter().map(|(_, h)| &world.bodies[*h]);
        self.poses.push(bodies.clone().map(|b| pose_from_parry(b.position())).collect());
        self.velocities.push(
            bodies
                .map(|b| {
                    let (v, w) = (b.linvel(), b.angvel());
                    (V::new(v.x, v.y, v.z), V::new(w.x, w.y, w.z))
                })
                .collect(),
        );
        self.deepest.push(world.deepest_overlap());
        if let Some(far) = &world.far_side {
            self.far_margins.push(world.far_margin(far));
        }
    }

    /// The least far-side margin over the run (infinite without a far side).
    pub fn far_margin(&self) -> Real {
        self.far_margins.iter().copied().fold(Real::INFINITY, Real::min)
    }

    /// The largest difference between two runs' poses over every step and
    /// body: the centres' distance plus the turn between the orientations
    /// (radians) times `size`.
    pub fn largest_difference(&self, other: &WorldRun, size: Real) -> Real {
        self.poses
            .iter()
            .zip(&other.poses)
            .flat_map(|(a, b)| a.iter().zip(b))
            .map(|(a, b)| {
                // Equal poses differ by nothing (the angle between two equal
                // quaternions rounds to a few 1e-20).
                if a == b {
                    return 0.0;
                }
                (a.translation.vector - b.translation.vector).norm() + a.rotation.angle_to(&b.rotation) * size
            })
            .fold(0.0, Real::max)
    }

    /// The deepest overlap over the run, with its step and pair.
    pub fn deepest(&self) -> (Real, usize, usize, usize) {
        self.deepest.iter().enumerate().map(|(s, &(d, i, j))| (d, s, i, j)).fold((0.0, 0, 0, 0), |best, x| {
            if x.0 > best.0 {
                x
            } else {
                best
            }
        })
    }

    /// The first step (1-based) after which a dynamic body kept its pose
    /// from the step before and the one before that while its velocity
    /// (rapier's, after the step) was above `rounding` (units per second),
    /// and the body; `None` if no body froze. `dynamic[i]`: whether body
    /// `i` is dynamic.
    pub fn frozen(&self, dynamic: &[bool], rounding: Real) -> Option<(usize, usize)> {
        for s in 2..self.poses.len() {
            for (i, &moves) in dynamic.iter().enumerate() {
                let still =
                    self.poses[s][i] == self.poses[s - 1][i] && self.poses[s - 1][i] == self.poses[s - 2][i];
                if moves && still && self.velocities[s][i].0.norm() > rounding {
                    return Some((s + 1, i));
                }
            }
        }
        None
    }

    /// Body `i`'s pose after the last step.
    pub fn last_pose(&self, i: usize) -> Pose {
        *self.poses.last().expect("a step")[i..].first().expect("the body")
    }
}

/// A pose from a translation and an axis-angle turn (degrees).
pub fn pose(translation: [Real; 3], axis: [Real; 3], degrees: Real) -> Pose {
    let axis = nalgebra::Unit::new_normalize(V::new(axis[0], axis[1], axis[2]));
    Pose::from_parts(
        nalgebra::Translation3::new(translation[0], translation[1], translation[2]),
        nalgebra::UnitQuaternion::from_axis_angle(&axis, degrees.to_radians()),
    )
}

/// rapier's pose of `pose`.
pub fn rapier_pose(pose: &Pose) -> rapier3d_f64::math::Pose {
    pose_to_parry(pose)
}

/// A rapier vector.
pub fn v(x: Real, y: Real, z: Real) -> Vector {
    Vector::new(x, y, z)
}

/// A fixed floor: the slab `half` × `half` × 0.5 whose top face is z = `top`,
/// centred on (`x`, `y`), turned by `turn` about its top's centre, friction
/// `friction`.
pub fn floor(
    world: &mut GuardWorld,
    [x, y, top]: [Real; 3],
    half: Real,
    friction: Real,
    turn: &Pose,
) -> usize {
    let centre =
        pose([x, y, top], [1.0, 0.0, 0.0], 0.0) * turn * pose([0.0, 0.0, -0.5], [1.0, 0.0, 0.0], 0.0);
    world.add(
        "floor",
        RigidBodyBuilder::fixed().pose(rapier_pose(&centre)),
        ColliderBuilder::cuboid(half, half, 0.5).friction(friction),
    )
}

/// The same slab as a triangle mesh.
pub fn trimesh_floor(world: &mut GuardWorld, [x, y, top]: [Real; 3], half: Real, friction: Real) -> usize {
    let (vertices, indices) = parry3d_f64::shape::Cuboid::new(Vector::new(half, half, 0.5)).to_trimesh();
    world.add(
        "floor",
        RigidBodyBuilder::fixed().translation(v(x, y, top - 0.5)),
        ColliderBuilder::trimesh(vertices, indices).expect("a box").friction(friction),
    )
}

/// A triangle-mesh box of half extents `h`.
pub fn trimesh_box(h: [Real; 3]) -> ColliderBuilder {
    let (vertices, indices) = parry3d_f64::shape::Cuboid::new(v(h[0], h[1], h[2])).to_trimesh();
    ColliderBuilder::trimesh(vertices, indices).expect("a box")
}

/// A plate a body must never come out of the far side of: its far face is
/// the plane `n · x = offset` with `n` pointing out of the far side, and
/// the margin is `offset − n · x` for the body's point farthest along `n`
/// (negative: a point came out of the far side). Counted while the body's
/// centre is over the plate (within `half` of its centre `plate`, across
/// `n`): a body deflected past the plate's edge may go anywhere.
pub struct FarSide {
    pub body: usize,
    pub normal: V,
    pub offset: Real,
    pub plate: V,
    pub half: Real,
}

impl GuardWorld {
    /// How far body `i`'s shapes reach along `n` (world frame), now.
    pub fn reach(&self, i: usize, n: &V) -> Real {
        let body = &self.bodies[self.handles[i].1];
        let dir = Vector::new(n.x, n.y, n.z);
        body.colliders()
            .iter()
            .map(|c| {
                let collider = &self.colliders[*c];
                let position = &collider_pose(collider, body);
                if let Some(mesh) = collider.shape().as_trimesh() {
                    mesh.vertices()
                        .iter()
                        .map(|p| (*position * *p).dot(dir))
                        .fold(Real::NEG_INFINITY, Real::max)
                } else {
                    let support = collider.shape().as_support_map().expect("a convex shape");
                    support.support_point(position, dir).dot(dir)
                }
            })
            .fold(Real::NEG_INFINITY, Real::max)
    }

    /// The world's far-side margin now (infinite while the body is not
    /// over the plate).
    pub fn far_margin(&self, far: &FarSide) -> Real {
        let centre = self.bodies[self.handles[far.body].1].translation();
        let across = V::new(centre.x, centre.y, centre.z) - far.plate;
        let across = across - far.normal * across.dot(&far.normal);
        if across.abs().max() > far.half {
            return Real::INFINITY;
        }
        far.offset - self.reach(far.body, &far.normal)
    }
}

/// The box of the issue: 0.5 × 0.3 × 0.2, resting on a fixed floor at
/// `height` above it (negative: inside), at `origin`, with velocity `v`;
/// µ 0.3 (both colliders), g 9.81, dt 1/120, 300 steps.
pub fn box_on_floor(name: &str, origin: [Real; 3], height: Real, velocity: V) -> GuardWorld {
    let mut world = GuardWorld::new(name, 1.0 / 120.0, 300, 9.81);
    floor(&mut world, origin, 10.0, 0.3, &Pose::identity());
    let [x, y, z] = origin;
    world.add(
        "box",
        RigidBodyBuilder::dynamic()
            .translation(v(x, y, z + 0.1 + height))
            .linvel(v(velocity.x, velocity.y, velocity.z)),
        ColliderBuilder::cuboid(0.25, 0.15, 0.1).friction(0.3),
    );
    world
}

/// A box (0.5 × 0.3 × 0.2) at rest on a 30° incline of friction `mu`
/// (both colliders), g 9.81, dt 1/120, 240 steps.
pub fn box_on_incline(mu: Real) -> GuardWorld {
    let mut world = GuardWorld::new(format!("incline 30°, µ {mu}"), 1.0 / 120.0, 240, 9.81);
    let turn = pose([0.0, 0.0, 0.0], [1.0, 0.0, 0.0], 30.0);
    floor(&mut world, [0.0, 0.0, 0.0], 20.0, mu, &turn);
    let at = turn * pose([0.0, 0.0, 0.1], [1.0, 0.0, 0.0], 0.0);
    world.add(
        "box",
        RigidBodyBuilder::dynamic().pose(rapier_pose(&at)),
        ColliderBuilder::cuboid(0.25, 0.15, 0.1).friction(mu),
    );
    world
}

/// `levels` unit cubes stacked face to face on a floor at `origin`, 600
/// steps of 1/60.
pub fn stack(levels: usize, origin: [Real; 3]) -> GuardWorld {
    let name = if origin == [0.0; 3] {
        format!("stack of {levels}")
    } else {
        format!("stack of {levels} at {:e}", origin[0])
    };
    let mut world = GuardWorld::new(name, 1.0 / 60.0, 600, 9.81);
    floor(&mut world, origin, 10.0, 0.5, &Pose::identity());
    let [x, y, z] = origin;
    for level in 0..levels {
        world.add(
            &format!("box {level}"),
            RigidBodyBuilder::dynamic().translation(v(x, y, z + 0.5 + level as Real)),
            ColliderBuilder::cuboid(0.5, 0.5, 0.5).friction(0.5),
        );
    }
    world.size = levels as Real;
    world
}

/// A pyramid of unit cubes, rows of 4, 3, 2 and 1 face to face (each row
/// centred on the one below), 600 steps of 1/60.
pub fn pyramid() -> GuardWorld {
    let mut world = GuardWorld::new("pyramid of 10", 1.0 / 60.0, 600, 9.81);
    floor(&mut world, [0.0; 3], 10.0, 0.5, &Pose::identity());
    for (row, count) in [4, 3, 2, 1].into_iter().enumerate() {
        for k in 0..count {
            let x = k as Real - (count - 1) as Real / 2.0;
            world.add(
                &format!("row {row} box {k}"),
                RigidBodyBuilder::dynamic().translation(v(x, 0.0, 0.5 + row as Real)),
                ColliderBuilder::cuboid(0.5, 0.5, 0.5).friction(0.5),
            );
        }
    }
    world.size = 4.0;
    world
}

/// A ball of radius 0.5 rolling at 2 units/s on a floor (µ 0.5), 300 steps
/// of 1/120.
pub fn ball_rolling() -> GuardWorld {
    let mut world = GuardWorld::new("ball rolling", 1.0 / 120.0, 300, 9.81);
    floor(&mut world, [0.0; 3], 10.0, 0.5, &Pose::identity());
    world.add(
        "ball",
        RigidBodyBuilder::dynamic().translation(v(0.0, 0.0, 0.5)).linvel(v(2.0, 0.0, 0.0)),
        ColliderBuilder::ball(0.5).friction(0.5),
    );
    world
}

/// A triangle-mesh unit cube resting on a triangle-mesh floor, pushed at 2
/// units/s along x (µ 0.3), 120 steps of 1/60.
pub fn box_on_trimesh_floor() -> GuardWorld {
    let mut world = GuardWorld::new("trimesh box pushed on a trimesh floor", 1.0 / 60.0, 120, 9.81);
    trimesh_floor(&mut world, [0.0; 3], 10.0, 0.3);
    world.add(
        "box",
        RigidBodyBuilder::dynamic().translation(v(0.0, 0.0, 0.5)).linvel(v(2.0, 0.0, 0.0)),
        trimesh_box([0.5, 0.5, 0.5]).friction(0.3),
    );
    world
}

/// Two equal boxes (0.5 × 0.4 × 0.3, 2.5 kg) turned 35° about (1, 1, 0)
/// at z = 120, approaching along their common long axis at `speed` each,
/// restitution 1, no friction, no gravity; steps of `dt` for 0.5 s.
pub fn turned_boxes_head_on(speed: Real, dt: Real) -> GuardWorld {
    let steps = (0.5 / dt).round() as usize;
    let mut world =
        GuardWorld::new(format!("turned boxes head-on at {speed} each, dt {dt:.4}"), dt, steps, 0.0);
    let turn = pose([0.0; 3], [1.0, 1.0, 0.0], 35.0);
    let axis = turn.rotation * V::x();
    let centre = V::new(0.0, 0.0, 120.0);
    let density = 2.5 / (0.5 * 0.4 * 0.3);
    for (name, side) in [("left", -1.0), ("right", 1.0)] {
        let at = Pose::from_parts((centre + axis * (side * 0.5)).into(), turn.rotation);
        let velocity = axis * (-side * speed);
        world.add(
            name,
            RigidBodyBuilder::dynamic().pose(rapier_pose(&at)).linvel(v(velocity.x, velocity.y, velocity.z)),
            ColliderBuilder::cuboid(0.25, 0.2, 0.15).density(density).restitution(1.0).friction(0.0),
        );
    }
    world
}

/// A unit crate resting on a floor (µ 0.5) and a velocity-based kinematic
/// wall (0.2 thick) at 1.5 units/s reaching it after 1 s, 150 steps of
/// 1/60.
pub fn crate_and_kinematic_wall() -> GuardWorld {
    let mut world = GuardWorld::new("crate pushed by a kinematic wall", 1.0 / 60.0, 150, 9.81);
    floor(&mut world, [0.0; 3], 10.0, 0.5, &Pose::identity());
    world.add(
        "crate",
        RigidBodyBuilder::dynamic().translation(v(0.0, 0.0, 0.5)),
        ColliderBuilder::cuboid(0.5, 0.5, 0.5).friction(0.5),
    );
    world.add(
        "wall",
        RigidBodyBuilder::kinematic_velocity_based()
            .translation(v(-0.5 - 0.1 - 1.5, 0.0, 1.0))
            .linvel(v(1.5, 0.0, 0.0)),
        ColliderBuilder::cuboid(0.1, 2.0, 1.0),
    );
    world.size = 2.0;
    world
}

/// Two unit crates exactly touching side by side on a floor, the left one
/// pushed towards the right at 1 unit/s, 120 steps of 1/60.
pub fn crates_touching() -> GuardWorld {
    let mut world = GuardWorld::new("crates exactly touching, one pushed", 1.0 / 60.0, 120, 9.81);
    floor(&mut world, [0.0; 3], 10.0, 0.5, &Pose::identity());
    world.add(
        "left",
        RigidBodyBuilder::dynamic().translation(v(-0.5, 0.0, 0.5)).linvel(v(1.0, 0.0, 0.0)),
        ColliderBuilder::cuboid(0.5, 0.5, 0.5).friction(0.5),
    );
    world.add(
        "right",
        RigidBodyBuilder::dynamic().translation(v(0.5, 0.0, 0.5)),
        ColliderBuilder::cuboid(0.5, 0.5, 0.5).friction(0.5),
    );
    world.size = 2.0;
    world
}

/// The scenes where rapier alone holds (issue 43 §1): the guard must only
/// read.
pub fn rapier_holds() -> Vec<GuardWorld> {
    let slide = V::new(2.4, 3.2, 0.0);
    vec![
        box_on_floor("box resting", [0.0; 3], 0.0, V::zeros()),
        box_on_floor("box sliding from an exact touch", [0.0; 3], 0.0, slide),
        box_on_floor("box sliding from 1e-3 above", [0.0; 3], 1e-3, slide),
        box_on_floor("box sliding from 1e-4 inside", [0.0; 3], -1e-4, slide),
        box_on_incline(0.2),
        box_on_incline(0.8),
        stack(5, [0.0; 3]),
        stack(10, [0.0; 3]),
        pyramid(),
        ball_rolling(),
        box_on_trimesh_floor(),
        turned_boxes_head_on(1.0, 1.0 / 120.0),
        crates_touching(),
        box_on_floor("box sliding at 1e3", [1e3, 0.0, 0.0], 0.0, slide),
        box_on_floor("box sliding at 1e5", [1e5, 0.0, 0.0], 0.0, slide),
        stack(5, [1e5, 0.0, 0.0]),
    ]
}

/// A 6 × 30 × 6 mm triangle-mesh bullet, tilted 40°, at `speed` straight
/// down onto a plate `thickness` thick (a triangle mesh too if `trimesh`),
/// at `offset` along x; no gravity, dt 1/240 for 0.05 s.
pub fn bullet(speed: Real, thickness: Real, offset: Real, trimesh: bool) -> GuardWorld {
    let kind = if trimesh { "trimesh " } else { "" };
    let name = format!("bullet {speed} u/s, {kind}plate {} mm, at {offset:e}", thickness * 1e3);
    let mut world = GuardWorld::new(name, 1.0 / 240.0, 12, 0.0);
    let half = thickness / 2.0;
    let plate = if trimesh { trimesh_box([1.0, 1.0, half]) } else { ColliderBuilder::cuboid(1.0, 1.0, half) };
    world.add("plate", RigidBodyBuilder::fixed().translation(v(offset, 0.0, 0.0)), plate);
    let at = pose([offset, 0.0, speed * 0.0125], [1.0, 0.3, 0.0], 40.0);
    world.add(
        "bullet",
        RigidBodyBuilder::dynamic().pose(rapier_pose(&at)).linvel(v(0.0, 0.0, -speed)),
        trimesh_box([0.003, 0.015, 0.003]).density(7800.0),
    );
    world.far_side =
        Some(FarSide { body: 1, normal: -V::z(), offset: half, plate: V::new(offset, 0.0, 0.0), half: 1.0 });
    world.size = 0.03;
    world
}

/// A thin triangle-mesh blade (2 × 0.04 × 0.4) spinning at 60 rad/s about
/// z, kinematic (velocity-based) or dynamic (125 kg), into a resting ball of
/// radius 0.05 at radius 0.5; no gravity, dt 1/60 for 0.5 s.
pub fn blade(kinematic: bool) -> GuardWorld {
    let name = if kinematic {
        "kinematic blade at 60 rad/s into a ball"
    } else {
        "dynamic blade at 60 rad/s into a ball"
    };
    let mut world = GuardWorld::new(name, 1.0 / 60.0, 30, 0.0);
    let builder =
        if kinematic { RigidBodyBuilder::kinematic_velocity_based() } else { RigidBodyBuilder::dynamic() };
    world.add(
        "blade",
        builder.angvel(v(0.0, 0.0, 60.0)),
        trimesh_box([1.0, 0.02, 0.2]).density(125.0 / (2.0 * 0.04 * 0.4)),
    );
    world.add(
        "ball",
        RigidBodyBuilder::dynamic().translation(v(0.0, 0.5, 0.0)),
        ColliderBuilder::ball(0.05).density(1000.0),
    );
    world
}

/// A ball (radius 0.1, at rest) swept by a velocity-based kinematic paddle
/// at 10 units/s into a 2 mm fixed plate, the paddle stopping 0.21 short of
/// the plate (the ball's width and 1 cm): the ball is squeezed between
/// them. No gravity, dt 1/60 for 0.5 s.
pub fn squeezed_ball() -> GuardWorld {
    let mut world =
        GuardWorld::new("ball squeezed by a kinematic paddle into a 2 mm plate", 1.0 / 60.0, 30, 0.0);
    world.add(
        "plate",
        RigidBodyBuilder::fixed().translation(v(1.0, 0.0, 0.0)),
        ColliderBuilder::cuboid(0.001, 1.0, 1.0),
    );
    world.add(
        "ball",
        RigidBodyBuilder::dynamic().translation(v(0.0, 0.0, 0.0)),
        ColliderBuilder::ball(0.1).density(1000.0),
    );
    // Its face at x = −0.5 + 0.05; it stops with the face at 1 − 0.001 − 0.21.
    world.add(
        "paddle",
        RigidBodyBuilder::kinematic_velocity_based()
            .translation(v(-0.55, 0.0, 0.0))
            .linvel(v(10.0, 0.0, 0.0)),
        trimesh_box([0.05, 0.5, 0.5]),
    );
    let travel: Real = (1.0 - 0.001 - 0.21) - (-0.5);
    let stop = (travel / 10.0 * 60.0).floor() as usize;
    world.script.push((stop, 2, V::new((travel - stop as Real * 10.0 / 60.0) * 60.0, 0.0, 0.0)));
    world.script.push((stop + 1, 2, V::zeros()));
    world.far_side = Some(FarSide { body: 1, normal: V::x(), offset: 1.001, plate: V::x(), half: 1.0 });
    world
}

/// A stack of five unit cubes resting face to face on a floor and, 5 units
/// away, a triangle-mesh plate (0.5 × 0.5 × 0.01, edge on) at 100 units/s
/// into a fixed 1 cm wall: the guard must rewind for the plate while the
/// stack rests (issue 43: while a pair was held, no rewind happened
/// anywhere in the world). g 9.81, 60 steps of 1/60.
pub fn plate_beside_a_stack() -> GuardWorld {
    let mut world = stack(5, [0.0; 3]);
    world.name = "100 u/s plate into a 1 cm wall beside a resting stack".into();
    world.steps = 60;
    world.add(
        "wall",
        RigidBodyBuilder::fixed().translation(v(5.0, 0.0, 1.0)),
        ColliderBuilder::cuboid(0.005, 2.0, 2.0),
    );
    world.add(
        "plate",
        RigidBodyBuilder::dynamic()
            .translation(v(-1.0, 5.0, 1.0))
            .linvel(v(100.0, -80.0, 0.0))
            .gravity_scale(0.0),
        trimesh_box([0.25, 0.25, 0.005]).density(2000.0),
    );
    let plate = world.handles.len() - 1;
    world.far_side =
        Some(FarSide { body: plate, normal: V::x(), offset: 5.005, plate: V::new(5.0, 0.0, 1.0), half: 2.0 });
    world.size = 5.0;
    world
}

/// The scenes where rapier alone passes a mesh through another or sinks it
/// far beyond its allowed error (issue 43 §2): the guard must decide. (The
/// crate pushed by a kinematic wall is issue 43 §1's, but rapier 0.36's
/// soft contact lets the wall 5 cm into the crate.)
pub fn rapier_fails() -> Vec<GuardWorld> {
    let mut cases = Vec::new();
    for thickness in [0.001, 0.002] {
        for speed in [500.0, 2000.0] {
            for offset in [0.0, 1e6] {
                cases.push(bullet(speed, thickness, offset, false));
            }
        }
    }
    cases.push(bullet(1000.0, 0.001, 0.0, true));
    cases.push(blade(true));
    cases.push(blade(false));
    cases.push(squeezed_ball());
    cases.push(turned_boxes_head_on(2.0, 1.0 / 60.0));
    // rapier's soft contact lets a kinematic pusher 5 cm into what it pushes.
    cases.push(crate_and_kinematic_wall());
    cases.push(plate_beside_a_stack());
    cases
}

//! One mesh against a collection (issue 46 §4): collisions and nearest
//! objects against a brute force over every object and triangle pair
//! (no tree, no broad phase, no pruning), and the first contact and
//! certified clearance of a moving cube against analytic times and
//! distances.

use std::sync::Arc;

use nearmiss::ccd::{ApproachStatus, CcdOptions};
use nearmiss::collection::{Collection, FirstContactStatus, UnknownObject};
use nearmiss::math::{MatrixPose, Placement, Pose, Real, Vector};
use nearmiss::mesh::{
    box_mesh, icosphere, mesh_distance, mesh_distance_brute_force, DistanceSearch, MeshDistanceScratch,
    TriMesh,
};
use nearmiss::motion::StepMotion;

fn cube(half: Real) -> Arc<TriMesh> {
    Arc::new(box_mesh(&Vector::new(half, half, half)).unwrap())
}

/// A small deterministic generator (xorshift), so that the scattered
/// scenes are the same on every machine.
struct Draw(u64);

impl Draw {
    fn next(&mut self) -> Real {
        self.0 ^= self.0 << 13;
        self.0 ^= self.0 >> 7;
        self.0 ^= self.0 << 17;
        (self.0 >> 11) as Real / (1u64 << 53) as Real
    }

    fn pose(&mut self, spread: Real) -> Pose {
        let mut c = || (self.next() - 0.5) * spread;
        let (x, y, z) = (c(), c(), c());
        let axis = Vector::new(self.next() - 0.5, self.next() - 0.5, self.next() - 0.5) * 4.0;
        Pose::new(Vector::new(x, y, z), axis)
    }
}

/// Twenty boxes and spheres scattered in a cube of side 6, some touching.
fn scattered(seed: u64) -> Collection {
    let mut draw = Draw(seed);
    let shapes = [cube(0.5), Arc::new(icosphere(0.6, 1).unwrap()), cube(0.3)];
    let mut collection = Collection::new();
    for i in 0..20 {
        collection.insert(format!("object {i}"), shapes[i % 3].clone(), draw.pose(6.0));
    }
    collection
}

/// Two distances equal to the rounding of the coordinates (a few ulps of
/// the scene's size, 6).
fn same(x: Real, y: Real) -> bool {
    (x - y).abs() <= 64.0 * Real::EPSILON * 6.0
}

fn brute(a: (&TriMesh, &Pose), b: (&TriMesh, &Pose)) -> Real {
    mesh_distance_brute_force(a.0, a.1, b.0, b.1)
}

#[test]
fn collisions_and_nearest_objects_are_those_of_every_pair() {
    let (mut probes_touching, mut pairs_touching) = (0, 0);
    for seed in [1, 7, 1234, 99_991] {
        let collection = scattered(seed);
        let objects = collection.objects();
        let probe = cube(0.4);
        let mut draw = Draw(seed + 1);
        for _ in 0..8 {
            let pose = draw.pose(6.0);
            let distances: Vec<Real> =
                objects.iter().map(|o| brute((o.mesh(), o.pose()), (&probe, &pose))).collect();
            let touched: Vec<&str> =
                objects.iter().zip(&distances).filter(|(_, &d)| d == 0.0).map(|(o, _)| o.name()).collect();
            let found: Vec<&str> = collection.in_collision(&probe, &pose).iter().map(|t| t.a).collect();
            assert_eq!(found, touched, "seed {seed}");
            probes_touching += touched.len();
            // The same distance to rounding (the brute force transforms
            // each vertex, the search the pair's relative pose), of an
            // object that is that near.
            let least = distances.iter().copied().fold(Real::INFINITY, Real::min);
            let nearest = collection.min_distance(&probe, &pose).unwrap();
            assert!(same(nearest.found.distance, least), "seed {seed}: {} {least}", nearest.found.distance);
            let named = objects.iter().position(|o| o.name() == nearest.a).unwrap();
            assert!(same(distances[named], least), "seed {seed}");
        }
        // Among the objects.
        let mut pairs = Vec::new();
        let mut least: Option<(Real, &str, &str)> = None;
        for (i, a) in objects.iter().enumerate() {
            for b in &objects[i + 1..] {
                let d = brute((a.mesh(), a.pose()), (b.mesh(), b.pose()));
                if d == 0.0 {
                    pairs.push((a.name(), b.name()));
                }
                if least.is_none_or(|(l, ..)| d < l) {
                    least = Some((d, a.name(), b.name()));
                }
            }
        }
        let found: Vec<(&str, &str)> =
            collection.in_collision_internal().iter().map(|t| (t.a, t.b.unwrap())).collect();
        assert_eq!(found.len(), pairs.len(), "seed {seed}: {found:?} against {pairs:?}");
        assert!(pairs.iter().all(|p| found.contains(p)), "seed {seed}");
        pairs_touching += pairs.len();
        let nearest = collection.min_distance_internal(None).unwrap().unwrap();
        let (d, a, b) = least.unwrap();
        assert!(same(nearest.found.distance, d), "seed {seed}: {} {d}", nearest.found.distance);
        let mesh_of = |name: &str| collection.get(name).map(|o| (o.mesh().as_ref(), o.pose())).unwrap();
        assert!(same(brute(mesh_of(nearest.a), mesh_of(nearest.b.unwrap())), d), "seed {seed}: {a} {b}");
        // Of one object to the others.
        let name = "object 3";
        let own = objects.iter().position(|o| o.name() == name).unwrap();
        let least = objects
            .iter()
            .enumerate()
            .filter(|&(i, _)| i != own)
            .map(|(_, o)| brute((o.mesh(), o.pose()), (objects[own].mesh(), objects[own].pose())))
            .fold(Real::INFINITY, Real::min);
        let nearest = collection.min_distance_internal(Some(name)).unwrap().unwrap();
        assert!(same(nearest.found.distance, least), "seed {seed}");
        assert!(nearest.a == name || nearest.b == Some(name));
    }
    // The scenes hold both answers, not only "nothing touches".
    assert!(probes_touching >= 3 && pairs_touching >= 3, "{probes_touching} {pairs_touching}");
}

#[test]
fn surfaces_touch_and_a_mesh_inside_another_does_not() {
    let mut collection = Collection::new();
    collection.insert("room", cube(5.0), Pose::identity());
    collection.insert("crate", cube(0.5), Pose::translation(2.0, 0.0, 0.0));
    // A cube face to face with the crate (x = 2.5), inside the room.
    let probe = cube(0.5);
    let touches = collection.in_collision(&probe, &Pose::translation(3.0, 0.0, 0.0));
    assert_eq!(touches.len(), 1);
    assert_eq!(touches[0].a, "crate");
    assert_eq!(touches[0].found.distance, 0.0);
    assert_eq!(touches[0].found.point_a.x, 2.5);
    // 0.25 from the crate, 1.25 from the room's wall at 5.
    let nearest = collection.min_distance(&probe, &Pose::translation(3.25, 0.0, 0.0)).unwrap();
    assert_eq!((nearest.a, nearest.found.distance), ("crate", 0.25));
    assert!(collection.in_collision_internal().is_empty());
}

#[test]
fn objects_are_replaced_moved_and_removed_by_name() {
    let mut collection = Collection::new();
    for (i, name) in ["a", "b", "c"].iter().enumerate() {
        collection.insert(*name, cube(0.5), Pose::translation(3.0 * i as Real, 0.0, 0.0));
    }
    let probe = cube(0.5);
    assert!(collection.insert("b", cube(0.25), Pose::translation(3.0, 0.0, 0.0)).is_some());
    assert_eq!(collection.len(), 3);
    let at_c = Pose::translation(6.0, 1.0, 0.0);
    assert_eq!(collection.in_collision(&probe, &at_c)[0].a, "c");
    collection.set_pose("a", Pose::translation(6.0, 2.0, 0.0)).unwrap();
    let names: Vec<&str> = collection.in_collision(&probe, &at_c).iter().map(|t| t.a).collect();
    assert_eq!(names, ["a", "c"]);
    collection.remove("a").unwrap();
    assert_eq!(collection.get("c").unwrap().name(), "c");
    let names: Vec<&str> = collection.in_collision(&probe, &at_c).iter().map(|t| t.a).collect();
    assert_eq!(names, ["c"]);
    assert_eq!(collection.remove("a").unwrap_err(), UnknownObject("a".into()));
    assert!(collection.set_pose("zz", Pose::identity()).is_err());
    assert!(collection.min_distance_internal(Some("zz")).is_err());
}

/// A unit cube sliding along +x at speed 1 from the origin: it meets the
/// block at x = 3 (face at 2.5) at t = 2, not the farther one at 5 nor the
/// one beside its path, whatever the order they were added in.
#[test]
fn the_first_contact_is_the_earliest_over_every_object() {
    let motion = StepMotion::new(Pose::identity(), Vector::new(1.0, 0.0, 0.0), Vector::zeros());
    let options = CcdOptions::default();
    let objects = [("far", 5.0, 0.0), ("beside", 2.0, 3.0), ("near", 3.0, 0.0)];
    for order in [[0, 1, 2], [2, 1, 0], [1, 0, 2]] {
        let mut collection = Collection::new();
        for k in order {
            let (name, x, y) = objects[k];
            collection.insert(name, cube(0.5), Pose::translation(x, y, 0.0));
        }
        let found = collection.first_contact(&cube(0.5), &motion, 10.0, &options);
        assert_eq!(found.status, FirstContactStatus::Contact);
        assert_eq!(found.object, Some("near"));
        let contact_distance = found.contact.unwrap().contact_distance;
        assert!(found.time <= 2.0 && found.time >= 2.0 - contact_distance, "{}", found.time);
        // Over a shorter interval nothing is met.
        let clear = collection.first_contact(&cube(0.5), &motion, 1.5, &options);
        assert_eq!((clear.status, clear.object, clear.time), (FirstContactStatus::Clear, None, 1.5));
    }
}

/// A unit cube turning about z at 1 rad/s in place: its corners reach
/// `x = (cos θ + sin θ) / 2` at angle θ, so it meets a wall whose face is
/// at x = 0.6 at `θ = asin(0.6 √2) − π/4`, before the wall at y = 0.65.
#[test]
fn a_turning_cube_meets_the_wall_its_corner_reaches_first() {
    let motion = StepMotion::new(Pose::identity(), Vector::zeros(), Vector::new(0.0, 0.0, 1.0));
    let mut collection = Collection::new();
    collection.insert("y wall", cube(1.0), Pose::translation(0.0, 1.65, 0.0));
    collection.insert("x wall", cube(1.0), Pose::translation(1.6, 0.0, 0.0));
    let found = collection.first_contact(&cube(0.5), &motion, 1.0, &CcdOptions::default());
    let exact = (0.6 * 2.0_f64.sqrt()).asin() - std::f64::consts::FRAC_PI_4;
    assert_eq!(found.object, Some("x wall"));
    // The corner closes the contact distance at a speed of at least
    // r ω sin(angle to the wall) ≥ 0.5.
    let contact_distance = found.contact.unwrap().contact_distance;
    assert!(found.time <= exact && found.time >= exact - 2.0 * contact_distance, "{} {exact}", found.time);
}

/// A unit cube sliding along +x from x = 0 over 10: it passes a cube at
/// y = -1.25 (faces 0.25 apart) and one at y = 1.375 (0.375 apart).
#[test]
fn the_clearance_is_the_nearest_pass_bracketed() {
    let motion = StepMotion::new(Pose::identity(), Vector::new(1.0, 0.0, 0.0), Vector::zeros());
    let options = CcdOptions::default();
    let mut collection = Collection::new();
    collection.insert("high", cube(0.5), Pose::translation(5.0, 1.375, 0.0));
    collection.insert("low", cube(0.5), Pose::translation(2.0, -1.25, 0.0));
    collection.insert("far", cube(0.5), Pose::translation(4.0, 9.0, 0.0));
    let probe = cube(0.5);
    let found = collection.clearance(&probe, &motion, 10.0, Real::INFINITY, Some(1e-6), &options);
    let approach = found.approach;
    assert_eq!((approach.status, found.object), (ApproachStatus::Bracketed, Some("low")));
    assert!(
        approach.lower <= 0.25 && 0.25 <= approach.upper && approach.upper - approach.lower <= 1e-6,
        "{approach:?}"
    );
    // Within 0.3: the same; within 0.1: beyond, certified.
    let near = collection.clearance(&probe, &motion, 10.0, 0.3, Some(1e-6), &options);
    assert_eq!((near.approach.status, near.object), (ApproachStatus::Bracketed, Some("low")));
    assert!(near.approach.lower <= 0.25 && 0.25 <= near.approach.upper);
    let beyond = collection.clearance(&probe, &motion, 10.0, 0.1, Some(1e-6), &options);
    assert_eq!(
        (beyond.approach.status, beyond.object, beyond.approach.lower),
        (ApproachStatus::Beyond, None, 0.1)
    );
    // A block in the path: contact, at the time of first contact.
    collection.insert("in the way", cube(0.5), Pose::translation(7.0, 0.0, 0.0));
    let hit = collection.clearance(&probe, &motion, 10.0, Real::INFINITY, Some(1e-6), &options);
    assert_eq!((hit.approach.status, hit.object), (ApproachStatus::Contact, Some("in the way")));
    assert!(hit.approach.time <= 6.0 && hit.approach.time >= 6.0 - 1e-5);
    assert_eq!(hit.approach.lower, 0.0);
}

/// Objects and a query placed by rotation matrices as given
/// ([`MatrixPose`]): the nearest object's distance is the mesh distance of
/// the two poses as given, to the bit (posed exactly, within an ulp of the
/// exact distance: `tests/meshes/distance_search.rs`), for the query and
/// for the nearest two objects; each object keeps its matrix, and its
/// `Pose` is the matrix's quaternion.
#[test]
fn matrix_poses_are_kept_as_given() {
    let mut draw = Draw(4548);
    let shapes = [cube(0.5), Arc::new(icosphere(0.6, 1).unwrap()), cube(0.3)];
    let matrix = |pose: Pose| MatrixPose {
        rotation: nalgebra::Rotation3::new(pose.rotation.scaled_axis()).into_inner(),
        translation: pose.translation.vector,
    };
    let mut collection = Collection::new();
    let placements: Vec<MatrixPose> = (0..12).map(|_| matrix(draw.pose(6.0))).collect();
    for (i, placement) in placements.iter().enumerate() {
        collection.insert(format!("object {i}"), shapes[i % 3].clone(), *placement);
    }
    for (object, placement) in collection.objects().iter().zip(&placements) {
        assert_eq!(object.placement(), placement);
        assert_eq!(*object.pose(), placement.pose());
    }
    let search = DistanceSearch::default();
    let mut scratch = MeshDistanceScratch::default();
    let query_mesh = icosphere(0.4, 1).unwrap();
    for _ in 0..8 {
        let query = matrix(draw.pose(6.0));
        let nearest = collection.min_distance(&query_mesh, &query).expect("objects");
        let least = collection
            .objects()
            .iter()
            .map(|o| {
                mesh_distance(o.mesh(), o.placement(), &query_mesh, &query, &search, &mut scratch).distance
            })
            .fold(Real::INFINITY, Real::min);
        assert_eq!(nearest.found.distance, least);
    }
    let pair = collection.min_distance_internal(None).unwrap().expect("objects");
    let objects = collection.objects();
    let least = (0..objects.len())
        .flat_map(|i| (i + 1..objects.len()).map(move |j| (i, j)))
        .map(|(i, j)| {
            let (a, b) = (&objects[i], &objects[j]);
            mesh_distance(a.mesh(), a.placement(), b.mesh(), b.placement(), &search, &mut scratch).distance
        })
        .fold(Real::INFINITY, Real::min);
    assert_eq!(pair.found.distance, least);
}

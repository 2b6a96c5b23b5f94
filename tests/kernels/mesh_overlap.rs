//! Past contact for meshes: the intersection curve against a brute force
//! and an analytic length, and the convex penetration depth against
//! analysis, against parry's `contact` (SAT for boxes, GJK/EPA for convex
//! polyhedra) and against its own definition (moving `b` by the depth
//! separates the solids, a shorter move does not).

use nearmiss::math::{pose_to_parry, to_parry, Point, Pose, Real, Vector};
use nearmiss::mesh::{
    box_mesh, convex_penetration, icosphere, local_depths, mesh_distance, mesh_intersection,
    mesh_intersection_brute_force, point_signed_distance, signed_distance, torus, DistanceSearch,
    MeshDistanceScratch, MeshIntersection, MeshIntersectionScratch, Overlap, PointQueryScratch,
    SignedDistanceScratch, TriMesh,
};
use nearmiss::samples::Rng;
use parry3d_f64::query::contact;
use parry3d_f64::shape::{ConvexPolyhedron, Cuboid, Shape};

fn random_pose(rng: &mut Rng, reach: Real) -> Pose {
    Pose::new(rng.in_unit_ball() * reach, rng.in_unit_ball() * 3.0)
}

fn intersection(a: &TriMesh, pose_a: &Pose, b: &TriMesh, pose_b: &Pose) -> MeshIntersection {
    let mut out = MeshIntersection::default();
    mesh_intersection(a, pose_a, b, pose_b, &mut out, &mut MeshIntersectionScratch::default());
    out
}

#[test]
fn intersection_finds_every_meeting_pair_of_the_brute_force() {
    let a = icosphere(1.0, 2).expect("icosphere");
    let b = box_mesh(&Vector::new(0.3, 1.2, 0.5)).expect("box");
    let mut rng = Rng::new(3);
    let mut crossing = 0;
    for case in 0..60 {
        let (pose_a, pose_b) = (random_pose(&mut rng, 0.5), random_pose(&mut rng, 1.5));
        let mut found: Vec<(usize, usize)> = intersection(&a, &pose_a, &b, &pose_b)
            .pairs
            .iter()
            .map(|p| (p.triangle_a, p.triangle_b))
            .collect();
        found.sort_unstable();
        let expected = mesh_intersection_brute_force(&a, &pose_a, &b, &pose_b);
        assert_eq!(found, expected, "case {case}");
        crossing += usize::from(!expected.is_empty());
    }
    assert!(crossing > 20, "only {crossing} of 60 cases cross: the test is not testing");
}

/// A cube (half extent 1) through a plate (half extents 2, 2, 0.1),
/// off-centre: its four side faces cross the plate's two faces along two
/// squares of side 2, 16 long in all.
#[test]
fn a_cube_through_a_plate_crosses_along_two_squares() {
    let cube = box_mesh(&Vector::new(1.0, 1.0, 1.0)).expect("cube");
    let plate = box_mesh(&Vector::new(2.0, 2.0, 0.1)).expect("plate");
    let found = intersection(&cube, &Pose::identity(), &plate, &Pose::translation(0.1, 0.2, 0.0));
    approx::assert_relative_eq!(found.length(), 16.0, epsilon = 1e-12);
    for [p, q] in found.segments() {
        for end in [p, q] {
            assert!((end.z.abs() - 0.1).abs() < 1e-15, "{end:?} off the plate's faces");
            assert!((end.x.abs().max(end.y.abs()) - 1.0).abs() < 1e-15, "{end:?} off the cube's sides");
        }
    }
    // Turned about z by a quarter, the same squares.
    let turned = Pose::new(Vector::new(0.1, 0.2, 0.0), Vector::z() * std::f64::consts::FRAC_PI_2);
    approx::assert_relative_eq!(
        intersection(&cube, &Pose::identity(), &plate, &turned).length(),
        16.0,
        epsilon = 1e-12
    );
    // Apart: nothing.
    assert!(intersection(&cube, &Pose::identity(), &plate, &Pose::translation(0.0, 0.0, 1.2)).is_empty());
}

#[test]
fn a_mesh_that_is_not_convex_is_refused() {
    let cube = box_mesh(&Vector::new(1.0, 1.0, 1.0)).expect("cube");
    let open = nearmiss::mesh::single_triangle(
        Point::origin(),
        Point::new(1.0, 0.0, 0.0),
        Point::new(0.0, 1.0, 0.0),
    )
    .expect("triangle");
    let refused = convex_penetration(&cube, &Pose::identity(), &open, &Pose::identity());
    assert_eq!(refused, Err(nearmiss::mesh::NotConvex { which: 'b' }));
}

#[test]
fn boxes_overlapping_by_a_known_amount() {
    let big = box_mesh(&Vector::new(1.0, 1.0, 1.0)).expect("box");
    let small = box_mesh(&Vector::new(0.5, 0.5, 0.5)).expect("box");
    // Along x they overlap by 1 + 0.5 - 1.3 = 0.2, along y by 1.3.
    let found = convex_penetration(&big, &Pose::identity(), &small, &Pose::translation(1.3, 0.2, 0.0))
        .expect("convex")
        .expect("overlapping");
    approx::assert_relative_eq!(found.depth, 0.2, epsilon = 1e-15);
    approx::assert_relative_eq!(found.direction, Vector::x(), epsilon = 1e-15);
    approx::assert_relative_eq!(found.point_a.x, 1.0, epsilon = 1e-15);
    // Inside, surfaces apart: the solids still overlap (0.5 + 1 - 0.1 to
    // leave by +x, the shortest way out).
    let inside = convex_penetration(&big, &Pose::identity(), &small, &Pose::translation(0.1, 0.0, 0.0))
        .expect("convex")
        .expect("inside");
    approx::assert_relative_eq!(inside.depth, 1.4, epsilon = 1e-15);
    approx::assert_relative_eq!(inside.direction, Vector::x(), epsilon = 1e-15);
    // Apart and touching.
    assert_eq!(
        convex_penetration(&big, &Pose::identity(), &small, &Pose::translation(1.6, 0.0, 0.0)),
        Ok(None)
    );
    let touching = convex_penetration(&big, &Pose::identity(), &small, &Pose::translation(1.5, 0.0, 0.0))
        .expect("convex");
    assert_eq!(touching.map(|t| t.depth), Some(0.0));
    // An edge into a face: the small box turned 45° about x reaches
    // 0.5·√2 below its centre, its lowest edge 0.05 into the big box's top.
    let r = std::f64::consts::FRAC_PI_4;
    let rotation = nalgebra::UnitQuaternion::from_scaled_axis(Vector::x() * r);
    let center = Vector::new(0.0, 0.0, 1.0 + 0.5 * std::f64::consts::SQRT_2 - 0.05);
    let edge = Pose::from_parts(center.into(), rotation);
    let found =
        convex_penetration(&big, &Pose::identity(), &small, &edge).expect("convex").expect("edge in face");
    approx::assert_relative_eq!(found.depth, 0.05, epsilon = 1e-14);
    approx::assert_relative_eq!(found.direction, Vector::z(), epsilon = 1e-14);
}

/// Two boxes, turned at random, both ways: against parry's SAT to
/// rounding, and against the definition.
#[test]
fn boxes_against_parry() {
    let extents = [Vector::new(1.0, 0.4, 0.7), Vector::new(0.3, 1.2, 0.5)];
    let [a, b] = extents.map(|e| box_mesh(&e).expect("box"));
    let [shape_a, shape_b] = extents.map(|e| Cuboid::new(to_parry(&e.into())));
    let worst = compare_with_parry(&a, &shape_a, &b, &shape_b, 1e-12, 200, 17);
    println!("boxes: worst difference from parry {worst:.1e}");
}

/// An icosphere and a box as convex polyhedra: parry's GJK/EPA stops
/// within its tolerance (it agreed to 1e-15 here when this was written).
#[test]
fn convex_polyhedra_against_parry() {
    let a = icosphere(1.0, 1).expect("icosphere");
    let b = box_mesh(&Vector::new(0.3, 1.2, 0.5)).expect("box");
    let polyhedron = |m: &TriMesh| {
        let points: Vec<_> = m.vertices().iter().map(to_parry).collect();
        ConvexPolyhedron::from_convex_mesh(points, m.triangles()).expect("convex")
    };
    let worst = compare_with_parry(&a, &polyhedron(&a), &b, &polyhedron(&b), 1e-10, 200, 19);
    println!("icosphere and box: worst difference from parry {worst:.1e}");
    // Finer: most edge pairs are left out by the sweep of their arcs' boxes.
    let (c, d) = (icosphere(1.0, 2).expect("icosphere"), icosphere(0.7, 2).expect("icosphere"));
    let worst = compare_with_parry(&c, &polyhedron(&c), &d, &polyhedron(&d), 1e-10, 100, 29);
    println!("two icospheres of 320 triangles: worst difference from parry {worst:.1e}");
}

fn compare_with_parry(
    a: &TriMesh,
    shape_a: &dyn Shape,
    b: &TriMesh,
    shape_b: &dyn Shape,
    tolerance: Real,
    cases: usize,
    seed: u64,
) -> Real {
    let mut rng = Rng::new(seed);
    let (mut overlapping, mut worst) = (0, 0.0_f64);
    let mut scratch = MeshDistanceScratch::default();
    for case in 0..cases {
        let (pose_a, pose_b) = (random_pose(&mut rng, 0.5), random_pose(&mut rng, 1.2));
        let peer = contact(&pose_to_parry(&pose_a), shape_a, &pose_to_parry(&pose_b), shape_b, 0.0)
            .expect("parry measures the pair");
        let ours = convex_penetration(a, &pose_a, b, &pose_b).expect("convex");
        match (ours, peer.filter(|c| c.dist <= 0.0)) {
            (None, None) => continue,
            (Some(found), Some(peer)) => {
                overlapping += 1;
                let difference = (found.depth + peer.dist).abs();
                worst = worst.max(difference);
                assert!(
                    difference <= tolerance,
                    "case {case}: depth {} vs parry {}",
                    found.depth,
                    -peer.dist
                );
                check_definition(a, &pose_a, b, &pose_b, &found, &mut scratch, case);
            }
            (ours, peer) => panic!("case {case}: nearmiss {ours:?}, parry {peer:?}"),
        }
    }
    assert!(overlapping > cases / 4, "only {overlapping} of {cases} cases overlap: the test is not testing");
    worst
}

/// Moving `b` a little past the depth leaves the solids apart (by about
/// that little, and no longer overlapping); a little short of it, still
/// overlapping.
fn check_definition(
    a: &TriMesh,
    pose_a: &Pose,
    b: &TriMesh,
    pose_b: &Pose,
    found: &nearmiss::mesh::MeshPenetration,
    scratch: &mut MeshDistanceScratch,
    case: usize,
) {
    let margin = 1e-9;
    let moved =
        |t: Real| Pose::from_parts((pose_b.translation.vector + found.direction * t).into(), pose_b.rotation);
    let past = moved(found.depth + margin);
    let apart = mesh_distance(a, pose_a, b, &past, &DistanceSearch::default(), scratch).distance;
    assert!(apart > 0.0 && apart <= 2.0 * margin, "case {case}: moved past the depth, {apart:e} apart");
    assert!(
        convex_penetration(a, pose_a, b, &past).expect("convex").is_none(),
        "case {case}: still overlapping past the depth"
    );
    if found.depth > margin {
        let short = convex_penetration(a, pose_a, b, &moved(found.depth - margin)).expect("convex");
        assert!(short.is_some(), "case {case}: apart before the depth");
    }
    // Independently of the method: along no sampled direction does a
    // shorter move separate the solids (surfaces meet, or one holds a
    // vertex of the other).
    let mut rng = Rng::new(case as u64);
    for _ in 0..16 {
        let direction = rng.unit_vector();
        let shorter = found.depth - margin;
        if shorter <= 0.0 {
            break;
        }
        let pose =
            Pose::from_parts((pose_b.translation.vector + direction * shorter).into(), pose_b.rotation);
        let touching =
            mesh_distance(a, pose_a, b, &pose, &DistanceSearch::default(), scratch).distance == 0.0;
        let held =
            inside(a, pose_a, &(pose * b.vertices()[0])) || inside(b, &pose, &(pose_a * a.vertices()[0]));
        assert!(
            touching || held,
            "case {case}: {direction:?} separates by {shorter:e} < depth {:e}",
            found.depth
        );
    }
}

/// Whether `point` is inside the convex solid of `mesh` at `pose`: behind
/// every triangle's plane (faces oriented outward).
fn inside(mesh: &TriMesh, pose: &Pose, point: &Point) -> bool {
    let local = pose.inverse_transform_point(point);
    (0..mesh.triangles().len()).all(|t| {
        let [p, q, r] = mesh.triangle(t);
        (q - p).cross(&(r - p)).dot(&(local - p)) <= 0.0
    })
}

/// A box's signed distance is the nearest face's, negative inside; a
/// torus's is its tube's (|distance to the centre circle| − r), to the
/// inscribed mesh's sag.
#[test]
fn signed_distance_of_points_to_a_box_and_a_torus() {
    let mut scratch = PointQueryScratch::default();
    let cube = box_mesh(&Vector::new(1.0, 2.0, 3.0)).expect("box");
    let inside = point_signed_distance(&cube, &Point::new(0.5, 0.0, 0.0), &mut scratch);
    assert_eq!(inside.distance, -0.5);
    let outside = point_signed_distance(&cube, &Point::new(2.0, 3.0, 0.0), &mut scratch);
    approx::assert_relative_eq!(outside.distance, std::f64::consts::SQRT_2, epsilon = 1e-15);
    // Nearest a vertex and an edge, outside and in.
    assert!(point_signed_distance(&cube, &Point::new(1.5, 2.5, 3.5), &mut scratch).distance > 0.0);
    assert!(point_signed_distance(&cube, &Point::new(0.99, 1.99, 2.99), &mut scratch).distance < 0.0);
    let (major, minor) = (1.0, 0.25);
    let ring = torus(major, minor, 256, 128).expect("torus");
    // Sag of the inscribed mesh: at most about (π R / n)² / (2 r) along
    // the circle and (π r / m)² / (2 r) across it.
    let sag = (std::f64::consts::PI * (major + minor) / 256.0).powi(2) / (2.0 * minor);
    let mut rng = Rng::new(41);
    for _ in 0..200 {
        let p = Point::from(rng.in_unit_ball() * 1.5);
        let to_circle = (Vector::new(p.x, p.y, 0.0).norm() - major).hypot(p.z);
        let expected = to_circle - minor;
        let found = point_signed_distance(&ring, &p, &mut scratch);
        assert!((found.distance - expected).abs() <= 2.0 * sag, "{p:?}: {} vs {expected}", found.distance);
    }
}

/// Two unit spheres overlapping by δ: the point of one nearest the other's
/// centre lies δ inside the other. The bracket closes on δ as the
/// icospheres are refined.
#[test]
fn local_depth_of_two_spheres_converges_under_refinement() {
    let delta = 0.2;
    let direction = Vector::new(1.0, 2.0, 2.0) / 3.0;
    let pose_b = Pose::new(direction * (2.0 - delta), Vector::zeros());
    let mut widths = Vec::new();
    for subdivisions in 2..=5 {
        let sphere = icosphere(1.0, subdivisions).expect("icosphere");
        let found = intersection(&sphere, &Pose::identity(), &sphere, &pose_b);
        let depths = local_depths(&sphere, &Pose::identity(), &sphere, &pose_b, &found).expect("closed");
        assert_eq!(depths.len(), 1, "one circle: {} components", depths.len());
        let depth = &depths[0];
        // The inscribed mesh's sag: its edge length squared over 2r.
        let edge = 1.1 * std::f64::consts::PI / (5.0 * 2f64.powi(subdivisions as i32));
        let sag = edge * edge;
        assert!(
            depth.lower <= delta + sag && depth.upper >= delta - sag,
            "{subdivisions}: [{}, {}] misses {delta}",
            depth.lower,
            depth.upper
        );
        assert!(depth.curve_length > 0.0);
        widths.push((depth.upper - depth.lower, (depth.lower - delta).abs()));
    }
    println!("two spheres overlapping by 0.2, subdivisions 2 to 5 (bracket width, |lower − δ|): {widths:?}");
    // Each subdivision halves the edges: the bracket narrows, the deepest
    // vertex comes closer to δ.
    for w in widths.windows(2) {
        assert!(w[1].0 < 0.6 * w[0].0, "{widths:?}");
    }
    assert!(widths[3].1 < 0.01, "{widths:?}");
}

/// A ring (not convex) dipped into a slab by 0.1, and into two slabs (one
/// mesh of two boxes) by 0.05 and 0.1: one depth per place, each
/// converging to its dip.
#[test]
fn local_depth_of_a_ring_in_slabs() {
    let (major, minor) = (1.0, 0.25);
    let slab = box_mesh(&Vector::new(3.0, 3.0, 0.5)).expect("slab");
    // The slab's top at z = −r + 0.1: the tube's bottom circle 0.1 below it.
    let pose_slab = Pose::translation(0.0, 0.0, -minor + 0.1 - 0.5);
    for (around, across, tolerance) in [(64, 32, 0.01), (256, 128, 1e-3)] {
        let ring = torus(major, minor, around, across).expect("torus");
        assert!(convex_penetration(&ring, &Pose::identity(), &slab, &pose_slab).is_err());
        let found = intersection(&ring, &Pose::identity(), &slab, &pose_slab);
        let depths = local_depths(&ring, &Pose::identity(), &slab, &pose_slab, &found).expect("closed");
        // The inner and outer circles where the slab's top cuts the tube.
        assert_eq!(depths.len(), 2, "{around}: {} components", depths.len());
        for depth in &depths {
            assert!((depth.lower - 0.1).abs() <= tolerance, "{around}: {depth:?}");
            // The slab is not refined: its triangles, 6 wide, bound its
            // patch inside the ring only by the ring's half width, 0.25.
            assert!(depth.upper >= 0.1 - tolerance && depth.upper <= 0.25, "{around}: {depth:?}");
        }
    }
    // Two slabs in one mesh, standing at x = ±(R + r) − d: the tube's
    // outermost points d deep, two separate places.
    let mut vertices = Vec::new();
    let mut triangles = Vec::new();
    for (x, dip) in [(major + minor - 0.05 + 0.5, 0.05), (-(major + minor - 0.1 + 0.5), 0.1)] {
        let block = box_mesh(&Vector::new(0.5, 3.0, 3.0)).expect("block");
        let offset = vertices.len() as u32;
        vertices.extend(block.vertices().iter().map(|v| v + Vector::new(x, 0.0, 0.0)));
        triangles.extend(block.triangles().iter().map(|t| t.map(|i| i + offset)));
        assert!((x.abs() - 0.5 - (major + minor - dip)).abs() < 1e-15);
    }
    let blocks = TriMesh::new(vertices, triangles).expect("two blocks");
    let ring = torus(major, minor, 256, 128).expect("torus");
    let found = intersection(&ring, &Pose::identity(), &blocks, &Pose::identity());
    let depths = local_depths(&ring, &Pose::identity(), &blocks, &Pose::identity(), &found).expect("closed");
    assert_eq!(depths.len(), 2, "{depths:?}");
    // Deepest first: 0.1 on the −x side, then 0.05 on the +x side.
    assert!((depths[0].lower - 0.1).abs() < 1e-3 && depths[0].deepest.x < 0.0, "{:?}", depths[0]);
    assert!((depths[1].lower - 0.05).abs() < 1e-3 && depths[1].deepest.x > 0.0, "{:?}", depths[1]);
}

/// One number for every way two meshes stand: apart, touching, convex
/// overlap (and containment), a ring in a slab, a box inside a ring's
/// tube, an open surface through a box.
#[test]
fn signed_distance_in_every_case() {
    let mut scratch = SignedDistanceScratch::default();
    let big = box_mesh(&Vector::new(1.0, 1.0, 1.0)).expect("box");
    let small = box_mesh(&Vector::new(0.5, 0.5, 0.5)).expect("box");
    let at = |x: Real, y: Real, z: Real| Pose::translation(x, y, z);
    let signed = |a: &TriMesh, pa: &Pose, b: &TriMesh, pb: &Pose, scratch: &mut SignedDistanceScratch| {
        signed_distance(a, pa, b, pb, scratch)
    };
    let apart = signed(&big, &Pose::identity(), &small, &at(1.75, 0.0, 0.0), &mut scratch);
    assert!(matches!(apart.overlap, Overlap::Apart(_)) && apart.value == 0.25, "{apart:?}");
    let touching = signed(&big, &Pose::identity(), &small, &at(1.5, 0.0, 0.0), &mut scratch);
    assert_eq!(touching.value, 0.0, "{touching:?}");
    let overlapping = signed(&big, &Pose::identity(), &small, &at(1.3, 0.2, 0.0), &mut scratch);
    assert!(matches!(overlapping.overlap, Overlap::Convex(_)), "{overlapping:?}");
    approx::assert_relative_eq!(overlapping.value, -0.2, epsilon = 1e-15);
    // Wholly inside, either way round.
    let inside = signed(&big, &Pose::identity(), &small, &at(0.1, 0.0, 0.0), &mut scratch);
    approx::assert_relative_eq!(inside.value, -1.4, epsilon = 1e-15);
    let holding = signed(&small, &at(0.1, 0.0, 0.0), &big, &Pose::identity(), &mut scratch);
    approx::assert_relative_eq!(holding.value, -1.4, epsilon = 1e-15);
    // A ring dipped 0.1 into a slab: minus its local depth.
    let (major, minor) = (1.0, 0.25);
    let ring = torus(major, minor, 256, 128).expect("torus");
    let slab = box_mesh(&Vector::new(3.0, 3.0, 0.5)).expect("slab");
    let dipped = signed(&ring, &Pose::identity(), &slab, &at(0.0, 0.0, -minor + 0.1 - 0.5), &mut scratch);
    assert!(matches!(dipped.overlap, Overlap::Local(_)), "{dipped:?}");
    assert!((dipped.value + 0.1).abs() < 1e-3, "{dipped:?}");
    // A small box inside the ring's tube: its deepest corner's depth,
    // r less the corner's distance to the tube's centre circle.
    let cube = box_mesh(&Vector::new(0.05, 0.05, 0.05)).expect("cube");
    let pose = at(major, 0.0, 0.0);
    let expected = cube
        .vertices()
        .iter()
        .map(|v| {
            let p = pose * v;
            minor - (Vector::new(p.x, p.y, 0.0).norm() - major).hypot(p.z)
        })
        .fold(0.0, Real::max);
    let held = signed(&ring, &Pose::identity(), &cube, &pose, &mut scratch);
    let Overlap::Inside { which, lower, upper } = held.overlap else { panic!("{held:?}") };
    assert_eq!(which, 'b');
    assert!(
        (lower - expected).abs() < 1e-3 && upper >= lower && held.value == -lower,
        "{held:?} vs {expected}"
    );
    // An open surface (one triangle) through a box: no inside, no depth.
    let sheet = nearmiss::mesh::single_triangle(
        Point::new(-3.0, -3.0, 0.0),
        Point::new(3.0, -3.0, 0.0),
        Point::new(0.0, 3.0, 0.0),
    )
    .expect("triangle");
    let through = signed(&big, &Pose::identity(), &sheet, &Pose::identity(), &mut scratch);
    assert!(matches!(through.overlap, Overlap::OpenCrossing(_)) && through.value == 0.0, "{through:?}");
}

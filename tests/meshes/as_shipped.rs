//! A cube closed across a T-junction by a triangle of zero area (the
//! commonest zero-area face in exported meshes: a vertex in the middle of
//! another face's edge), a lone segment, and an OBJ file with faces of two
//! vertices: each is accepted, counted, and answers every query as the
//! geometry it is. The expected values come from the same cube without the
//! junction (the same point set, so the same answers) and from the exact
//! rational reference.

use nearmiss::ccd::{
    closest_approach, mesh_time_of_impact, CcdOptions, ClosestApproachQuery, MeshCcdQuery, MeshCcdScratch,
    MovingMesh, WarmStart,
};
use nearmiss::exact::{segment_segment_distance_squared, to_f64, triangle_distance_squared};
use nearmiss::math::{Point, Pose, Real, Vector};
use nearmiss::mesh::{
    box_mesh, icosphere, mesh_distance, mesh_distance_brute_force, parse_obj, point_signed_distance,
    signed_distance, DistanceSearch, MeshDistanceScratch, PointQueryScratch, SignedDistanceScratch, TriMesh,
};
use nearmiss::motion::StepMotion;
use nearmiss::samples::Rng;

/// The cube `[-1, 1]³`, and the same cube with the top face's front edge
/// split at its middle `M`: the top triangle `A B C` becomes `A M C` and
/// `M B C`, and the zero-area triangle `A B M` closes the surface against
/// the front face's edge `B A`.
fn cube_and_junction_cube() -> (TriMesh, TriMesh) {
    sheared_cube_and_junction_cube(0.0)
}

/// [`cube_and_junction_cube`] sheared by `y += shear · z`: with a negative
/// shear the junction's edge is sharp (the faces' normals more than a
/// right angle apart), where one face's normal alone gives the wrong side.
fn sheared_cube_and_junction_cube(shear: Real) -> (TriMesh, TriMesh) {
    let corners = [
        [-1.0, -1.0, -1.0],
        [1.0, -1.0, -1.0],
        [1.0, 1.0, -1.0],
        [-1.0, 1.0, -1.0],
        [-1.0, -1.0, 1.0],
        [1.0, -1.0, 1.0],
        [1.0, 1.0, 1.0],
        [-1.0, 1.0, 1.0],
        [0.0, -1.0, 1.0],
    ];
    let vertices: Vec<Point> = corners.iter().map(|c| Point::new(c[0], c[1] + shear * c[2], c[2])).collect();
    let sides = [
        [0, 2, 1],
        [0, 3, 2],
        [0, 1, 5],
        [0, 5, 4],
        [1, 2, 6],
        [1, 6, 5],
        [2, 3, 7],
        [2, 7, 6],
        [3, 0, 4],
        [3, 4, 7],
        [4, 6, 7],
    ];
    let mut plain = sides.to_vec();
    plain.push([4, 5, 6]);
    let mut junction = sides.to_vec();
    junction.extend([[4, 8, 6], [8, 5, 6], [4, 5, 8]]);
    let plain = TriMesh::new(vertices[..8].to_vec(), plain).unwrap();
    let junction = TriMesh::new(vertices, junction).unwrap();
    (plain, junction)
}

#[test]
fn a_junction_cube_is_accepted_closed_and_of_the_cubes_volume() {
    let (plain, junction) = cube_and_junction_cube();
    assert_eq!(plain.zero_area_triangles(), 0);
    assert_eq!(junction.zero_area_triangles(), 1);
    assert_eq!(junction.check_closed(), Ok(()));
    let volume = junction.mass_properties().expect("closed, outward").volume;
    assert_eq!(volume, 8.0);
    // Not taken as convex (a face with no normal has no side), so the
    // convex-only shortcuts stay off; everything else works.
    assert!(plain.is_convex() && !junction.is_convex());
}

/// Random poses of a small ball about the junction's edge: the same
/// distance as to the plain cube (the same surface), to rounding.
#[test]
fn distances_near_the_junction_are_the_cubes() {
    let (plain, junction) = cube_and_junction_cube();
    let ball = icosphere(0.3, 1).unwrap();
    let mut rng = Rng::new(45);
    let mut scratch = MeshDistanceScratch::default();
    for case in 0..200 {
        let at = Point::new(0.0, -1.0, 1.0) + rng.in_unit_ball() * 0.8;
        let pose = Pose::new(at.coords, rng.in_unit_ball() * 3.0);
        let search = DistanceSearch::default();
        let expected = mesh_distance(&plain, &Pose::identity(), &ball, &pose, &search, &mut scratch).distance;
        let found = mesh_distance(&junction, &Pose::identity(), &ball, &pose, &search, &mut scratch);
        assert!((found.distance - expected).abs() <= 1e-15, "case {case}: {found:?} vs {expected}");
        let brute = mesh_distance_brute_force(&junction, &Pose::identity(), &ball, &pose);
        assert!((found.distance - brute).abs() <= 1e-15, "case {case}");
    }
}

/// Points about the junction, inside and out, some closest to the
/// junction's edge, of a cube sheared so that the edge is sharp: the same
/// signed distance as for the plain (sheared) cube.
#[test]
fn inside_and_outside_about_the_junction_are_the_cubes() {
    let shear = -2.5;
    let (plain, junction) = sheared_cube_and_junction_cube(shear);
    let mut rng = Rng::new(7);
    let mut scratch = PointQueryScratch::default();
    let mut at_the_junction = 0;
    for case in 0..4000 {
        let point = Point::new(0.0, -1.0 + shear, 1.0) + rng.in_unit_ball() * 0.5;
        let expected = point_signed_distance(&plain, &point, &mut scratch);
        let found = point_signed_distance(&junction, &point, &mut scratch);
        // Closest to the junction's edge: the zero-area triangle is one of
        // the faces there, and it has no side.
        at_the_junction += usize::from(found.closest.y == -1.0 + shear && found.closest.z == 1.0);
        assert!((found.distance.abs() - expected.distance.abs()).abs() <= 1e-15, "case {case}: {point:?}");
        // The sign: inside the sheared cube iff every coordinate of the
        // unsheared point is inside.
        let unsheared = Vector::new(point.x, point.y - shear * point.z, point.z);
        let inside = unsheared.iter().all(|c| c.abs() < 1.0);
        assert_eq!(found.distance < 0.0, inside, "case {case}: {point:?} {found:?}");
        assert_eq!(expected.distance < 0.0, inside, "case {case}: {point:?} {expected:?}");
    }
    assert!(at_the_junction > 100, "{at_the_junction} points closest to the junction's edge");
}

/// A prism with a deep valley along x (its cross-section the pentagon
/// (-1, -1), (1, -1), (1, 1), (0, -0.5), (-1, 1) in y, z): the valley's
/// edge is reflex and its faces' normals more than a right angle apart,
/// and a T-junction at its middle makes a zero-area triangle on it. Points
/// inside, closest to that edge, are inside.
#[test]
fn inside_at_a_reflex_junction_edge() {
    let section = [(-1.0, -1.0), (1.0, -1.0), (1.0, 1.0), (0.0, -0.5), (-1.0, 1.0)];
    let mut vertices: Vec<Point> = Vec::new();
    for x in [-1.0, 1.0] {
        vertices.extend(section.iter().map(|&(y, z)| Point::new(x, y, z)));
    }
    vertices.push(Point::new(0.0, 0.0, -0.5));
    let (left, right, middle) = (|i: u32| i, |i: u32| 5 + i, 10);
    let mut triangles = vec![
        [right(0), right(1), right(3)],
        [right(1), right(2), right(3)],
        [right(0), right(3), right(4)],
        [left(0), left(3), left(1)],
        [left(1), left(3), left(2)],
        [left(0), left(4), left(3)],
    ];
    for i in 0..5 {
        let j = (i + 1) % 5;
        if i == 2 {
            // The valley's first face, split at the junction.
            triangles.extend([
                [left(2), left(3), middle],
                [left(2), middle, right(3)],
                [left(2), right(3), right(2)],
            ]);
        } else {
            triangles.extend([[left(i), left(j), right(j)], [left(i), right(j), right(i)]]);
        }
    }
    triangles.push([left(3), right(3), middle]);
    let prism = TriMesh::new(vertices, triangles).unwrap();
    assert_eq!(prism.zero_area_triangles(), 1);
    assert_eq!(prism.check_closed(), Ok(()));
    assert!(prism.mass_properties().unwrap().volume > 0.0);
    let mut rng = Rng::new(9);
    let mut scratch = PointQueryScratch::default();
    let mut at_the_edge = 0;
    for case in 0..4000 {
        let point = Point::new(0.0, 0.0, -0.5) + rng.in_unit_ball() * 0.4;
        let found = point_signed_distance(&prism, &point, &mut scratch);
        let inside = point.x.abs() < 1.0 && point.z > -1.0 && point.z < -0.5 + 1.5 * point.y.abs();
        at_the_edge += usize::from(inside && found.closest.y == 0.0 && found.closest.z == -0.5);
        assert_eq!(found.distance < 0.0, inside, "case {case}: {point:?} {found:?}");
    }
    assert!(at_the_edge > 100, "{at_the_edge} inside points closest to the valley's edge");
}

#[test]
fn mesh_against_mesh_across_the_junction() {
    let (plain, junction) = cube_and_junction_cube();
    // Mesh against mesh across the junction: apart, the same distance;
    // overlapping, an overlap too (the plain cube is convex and gets the
    // exact depth, the junction cube the local one: the values differ).
    let ball = icosphere(0.3, 2).unwrap();
    let mut both = SignedDistanceScratch::default();
    for z in [0.75, 0.9, 1.0, 1.1, 1.35, 1.6] {
        let pose = Pose::translation(0.1, -1.0, z);
        let expected = signed_distance(&plain, &Pose::identity(), &ball, &pose, &mut both).value;
        let found = signed_distance(&junction, &Pose::identity(), &ball, &pose, &mut both).value;
        assert_eq!(found < 0.0, expected < 0.0, "z {z}: {found} vs {expected}");
        if expected > 0.0 {
            assert!((found - expected).abs() <= 1e-15, "z {z}: {found} vs {expected}");
        }
    }
}

/// A ball flying at the junction's edge, tumbling: the time of impact and
/// the closest approach are the plain cube's, within the contact distance.
#[test]
fn time_of_impact_and_closest_approach_at_the_junction_are_the_cubes() {
    let (plain, junction) = cube_and_junction_cube();
    let ball = icosphere(0.25, 2).unwrap();
    let fixed = StepMotion::fixed(Pose::identity());
    let mut scratch = MeshCcdScratch::default();
    let mut rng = Rng::new(3);
    for case in 0..20 {
        let aim = Point::new(rng.in_unit_ball().x * 0.9, -1.0, 1.0);
        let start = aim + Vector::new(0.0, -1.0, 1.0) * 2.0 + rng.in_unit_ball() * 0.2;
        let flying = StepMotion::free(
            &Pose::translation(start.x, start.y, start.z),
            (aim - start) * 1.5,
            rng.in_unit_ball() * 6.0,
            0.0,
        );
        let query = |cube| {
            MeshCcdQuery::new(
                MovingMesh { mesh: cube, motion: &fixed },
                MovingMesh { mesh: &ball, motion: &flying },
                1.0,
                CcdOptions::default(),
            )
        };
        let expected = mesh_time_of_impact(&query(&plain), WarmStart::default(), &mut scratch);
        let found = mesh_time_of_impact(&query(&junction), WarmStart::default(), &mut scratch);
        let (t0, t1) = (expected.time_of_impact.unwrap(), found.time_of_impact.unwrap());
        // Both are conservative; each is within its contact distance of the
        // same true time, which the other's speed turns into a time.
        let speed = (aim - start).norm() * 1.5 + 6.0 * ball.radius();
        assert!(
            (t0 - t1).abs() * speed <= found.contact_distance.max(expected.contact_distance),
            "case {case}"
        );

        let away = StepMotion::free(
            &Pose::translation(start.x, start.y - 0.4, start.z + 0.4),
            Vector::new(2.5, 0.0, 0.0),
            rng.in_unit_ball() * 6.0,
            0.0,
        );
        let mut approach = |cube| {
            let q = ClosestApproachQuery::new(
                MovingMesh { mesh: cube, motion: &fixed },
                MovingMesh { mesh: &ball, motion: &away },
                1.0,
            );
            closest_approach(&q, &mut scratch)
        };
        let (e, f) = (approach(&plain), approach(&junction));
        assert!(e.lower <= f.upper && f.lower <= e.upper, "case {case}: {e:?} vs {f:?}");
    }
}

/// A mesh that is one segment (its only triangle has a repeated vertex):
/// its distance to a triangle is the exact segment–triangle distance.
#[test]
fn a_lone_segment_is_measured_as_a_segment() {
    let mut rng = Rng::new(11);
    let mut scratch = MeshDistanceScratch::default();
    for case in 0..100 {
        let (p, q) = (Point::from(rng.in_unit_ball()), Point::from(rng.in_unit_ball()));
        let segment = TriMesh::new(vec![p, q], vec![[0, 1, 1]]).unwrap();
        assert_eq!(segment.zero_area_triangles(), 1);
        let other = [0; 3].map(|_| Point::from(rng.in_unit_ball() * 2.0));
        let triangle = TriMesh::new(other.to_vec(), vec![[0, 1, 2]]).unwrap();
        let found = mesh_distance(
            &segment,
            &Pose::identity(),
            &triangle,
            &Pose::identity(),
            &DistanceSearch::default(),
            &mut scratch,
        );
        let exact = to_f64(&triangle_distance_squared(&[p, q, q], &other)).sqrt();
        // The exact squared distance, rounded once, then its square root.
        assert!(
            (found.distance - exact).abs() <= 4.0 * Real::EPSILON * 3.0,
            "case {case}: {found:?} vs {exact}"
        );
        // And against one of the triangle's edges, as a segment pair.
        let edge = to_f64(&segment_segment_distance_squared(&p, &q, &other[0], &other[1])).sqrt();
        assert!(found.distance <= edge + 1e-15, "case {case}");
    }
}

/// A sliver near the closest point: a box whose top face is fanned from a
/// point a hair inside its edge, making a triangle of height 1e-12 and one
/// of area zero beside it. The distance to a plate over the sliver is the
/// exact one (rationals) to the last bits.
#[test]
fn a_sliver_at_the_closest_point_is_exact() {
    let h = 1e-12;
    let vertices = vec![
        Point::new(-1.0, -1.0, 0.0),
        Point::new(1.0, -1.0, 0.0),
        Point::new(1.0, 1.0, 0.0),
        Point::new(-1.0, 1.0, 0.0),
        Point::new(0.3, -1.0 + h, 0.0),
        Point::new(0.6, -1.0, 0.0),
    ];
    // The sliver (0, 5, 4) of height h, a zero-area triangle (0, 5, 1) on
    // the edge, and the rest of the square fanned from vertex 4.
    let triangles = vec![[0, 5, 4], [0, 1, 5], [5, 1, 4], [1, 2, 4], [2, 3, 4], [3, 0, 4]];
    let sheet = TriMesh::new(vertices, triangles).unwrap();
    assert_eq!(sheet.zero_area_triangles(), 1);
    let needle = TriMesh::new(
        vec![Point::new(0.0, -1.0, 0.0), Point::new(0.5, -1.0, 0.0), Point::new(0.25, -1.0, 0.5)],
        vec![[0, 1, 2]],
    )
    .unwrap();
    let mut scratch = MeshDistanceScratch::default();
    let mut rng = Rng::new(5);
    for case in 0..50 {
        let lift = 1e-9 * (1.0 + rng.in_unit_ball().x);
        let pose = Pose::new(Vector::new(0.2, 2e-13, lift), rng.in_unit_ball() * 1e-3);
        let found = mesh_distance(
            &sheet,
            &Pose::identity(),
            &needle,
            &pose,
            &DistanceSearch::default(),
            &mut scratch,
        );
        let moved = needle.triangle(0).map(|p| pose * p);
        let exact = (0..sheet.triangles().len())
            .map(|t| to_f64(&triangle_distance_squared(&sheet.triangle(t), &moved)).sqrt())
            .fold(Real::INFINITY, Real::min);
        // Within an ulp of the largest coordinate (1) of the exact value.
        assert!(
            (found.distance - exact).abs() <= Real::EPSILON,
            "case {case}: {} vs {exact}",
            found.distance
        );
    }
}

/// An OBJ file as exporters write them: a zero-area face kept, faces of
/// two vertices (lines) and one dropped, each counted; the mesh is the
/// cube it describes.
#[test]
fn an_obj_with_short_and_zero_area_faces_reads_as_its_solid() {
    let (_, junction) = cube_and_junction_cube();
    let mut text = String::new();
    for v in junction.vertices() {
        text += &format!("v {} {} {}\n", v.x, v.y, v.z);
    }
    for t in junction.triangles() {
        text += &format!("f {} {} {}\n", t[0] + 1, t[1] + 1, t[2] + 1);
        text += &format!("f {} {}\n", t[0] + 1, t[1] + 1);
    }
    text += "f 1\n";
    let mesh = parse_obj(&text, std::path::Path::new("junction.obj")).unwrap();
    assert_eq!(mesh.zero_area_triangles(), 1);
    assert_eq!(mesh.dropped_faces(), junction.triangles().len() + 1);
    assert_eq!(mesh.mass_properties().unwrap().volume, 8.0);
    let plain = box_mesh(&Vector::new(1.0, 1.0, 1.0)).unwrap();
    let mut scratch = MeshDistanceScratch::default();
    let pose = Pose::translation(0.5, -1.7, 1.4);
    let search = DistanceSearch::default();
    let a = mesh_distance(&mesh, &Pose::identity(), &plain, &pose, &search, &mut scratch).distance;
    let b = mesh_distance(&junction, &Pose::identity(), &plain, &pose, &search, &mut scratch).distance;
    assert_eq!(a, b);
}

/// A scene's `Triangle` of collinear corners is the segment it spans: it
/// loads, and the scene notes it.
#[test]
fn a_scene_triangle_of_collinear_corners_is_noted() {
    let scene = nearmiss::scene::Scene::from_ron_str(
        r#"Scene(name: "s", dt: 0.01, duration: 0.1, bodies: [
            (name: "a", mesh: Triangle(a: (0.0, 0.0, 0.0), b: (1.0, 1.0, 1.0), c: (2.0, 2.0, 2.0))),
        ])"#,
    )
    .unwrap();
    let notes = scene.mesh_notes();
    assert_eq!(notes.len(), 1);
    assert_eq!((notes[0].zero_area_triangles, notes[0].dropped_faces), (1, 0));
    assert_eq!(notes[0].bodies, ["a"]);
}

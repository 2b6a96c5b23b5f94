//! The mesh distance search (oriented boxes, bounds both ways round)
//! against the brute force over every triangle pair, on meshes that make
//! boxes loose or tight: a torus (curved, with a hole), a long slanted
//! needle, a flat plate turned off the axes, a lone sliver; at poses
//! separated, grazing and overlapping, both argument orders.

use nearmiss::math::{Point, Pose, Real, Vector};
use nearmiss::mesh::{
    box_mesh, icosphere, mesh_distance, mesh_distance_brute_force, needle, torus, DistanceSearch,
    MeshDistanceScratch, TriMesh,
};
use nearmiss::samples::Rng;

fn turned(mesh: &TriMesh, axis_angle: Vector, scale: Real) -> TriMesh {
    let pose = Pose::new(Vector::zeros(), axis_angle);
    let vertices = mesh.vertices().iter().map(|p| pose * (p * scale)).collect();
    TriMesh::new(vertices, mesh.triangles().to_vec()).unwrap()
}

#[test]
fn the_search_is_the_brute_force_on_hard_meshes_both_ways_round() {
    let meshes = [
        torus(1.0, 0.2, 48, 16).unwrap(),
        turned(&needle(3.0, 0.01).unwrap(), Vector::new(0.3, 0.7, 0.2), 1.0),
        turned(&box_mesh(&Vector::new(2.0, 1.5, 0.001)).unwrap(), Vector::new(0.5, -0.4, 0.9), 1.0),
        turned(&icosphere(1.0, 2).unwrap(), Vector::new(0.1, 0.2, 0.3), 1e3),
        TriMesh::new(
            vec![Point::new(0.0, 0.0, 0.0), Point::new(2.0, 0.1, 0.0), Point::new(1.0, 0.05, 1e-9)],
            vec![[0, 1, 2]],
        )
        .unwrap(),
    ];
    let mut rng = Rng::new(4545);
    let mut scratch = MeshDistanceScratch::default();
    let search = DistanceSearch::default();
    for case in 0..240 {
        let (i, j) = (case % meshes.len(), (case / meshes.len()) % meshes.len());
        let (a, b) = (&meshes[i], &meshes[j]);
        let reach = (a.radius() + b.radius()) * [0.3, 0.9, 1.0, 1.3][case % 4];
        let pose_a = Pose::new(rng.in_unit_ball() * a.radius(), rng.in_unit_ball() * 3.0);
        let pose_b =
            Pose::new(pose_a.translation.vector + rng.unit_vector() * reach, rng.in_unit_ball() * 3.0);
        let expected = mesh_distance_brute_force(a, &pose_a, b, &pose_b);
        let forward = mesh_distance(a, &pose_a, b, &pose_b, &search, &mut scratch);
        let backward = mesh_distance(b, &pose_b, a, &pose_a, &search, &mut scratch);
        // The search moves b into a's frame, the brute force both into the
        // world: they agree to the rounding of the poses (a few ulps of the
        // largest coordinate).
        let scale =
            a.radius() + b.radius() + pose_a.translation.vector.norm() + pose_b.translation.vector.norm();
        let tolerance = 64.0 * Real::EPSILON * scale;
        for found in [forward.distance, backward.distance] {
            assert!((found - expected).abs() <= tolerance, "case {case} ({i}, {j}): {found} vs {expected}");
        }
        assert!(((forward.point_a - forward.point_b).norm() - forward.distance).abs() <= tolerance);
    }
}

/// A small body in a ring's hole (a robot link in a gear ring, in the
/// benchmark): every ring triangle is nearly as close as the nearest, and
/// its box is far looser than the spread of the candidates. The leaf
/// triangles' distances to the small body's node spheres prune them; the
/// search stays the brute force, does the same work both ways round, and
/// evaluates a small share of the pairs the boxes alone leave (they left
/// 6,400–12,200 of the 245,760 here).
#[test]
fn a_small_body_in_a_ring_hole_is_searched_briefly_and_alike_both_ways() {
    let ring = torus(1.0, 0.2, 192, 32).unwrap();
    let body = icosphere(0.01, 2).unwrap();
    let mut rng = Rng::new(4546);
    let mut scratch = MeshDistanceScratch::default();
    let search = DistanceSearch::default();
    for case in 0..4 {
        let pose_ring = Pose::new(Vector::zeros(), rng.in_unit_ball() * 3.0);
        let pose_body = Pose::new(rng.in_unit_ball() * 0.05, rng.in_unit_ball() * 3.0);
        let expected = mesh_distance_brute_force(&ring, &pose_ring, &body, &pose_body);
        let forward = mesh_distance(&ring, &pose_ring, &body, &pose_body, &search, &mut scratch);
        let forward_pairs = scratch.triangle_pairs();
        let backward = mesh_distance(&body, &pose_body, &ring, &pose_ring, &search, &mut scratch);
        let backward_pairs = scratch.triangle_pairs();
        let tolerance = 64.0 * Real::EPSILON * 2.0;
        for found in [forward.distance, backward.distance] {
            assert!((found - expected).abs() <= tolerance, "case {case}: {found} vs {expected}");
        }
        assert_eq!(forward_pairs, backward_pairs, "case {case}");
        assert!(forward_pairs <= 2_500, "case {case}: {forward_pairs} triangle pairs");
    }
}

//! The mesh distance search (oriented boxes, bounds both ways round)
//! against the brute force over every triangle pair, on meshes that make
//! boxes loose or tight: a torus (curved, with a hole), a long slanted
//! needle, a flat plate turned off the axes, a lone sliver; at poses
//! separated, grazing and overlapping, both argument orders.

use nearmiss::exact;
use nearmiss::kernels::triangle_distance;
use nearmiss::math::{MatrixPose, Point, Pose, Real, Vector};
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

/// Poses given as rotation matrices ([`MatrixPose`], applied as given): the
/// distance is within an ulp of the largest posed coordinate of the exact
/// least distance over every triangle pair, each triangle posed exactly in
/// rationals, both argument orders; separated, grazing and overlapping.
/// The matrices are f64 rotations (orthonormal to rounding, not exactly),
/// as a user's forward kinematics gives them. The meshes sit near the
/// origin, where the roundings of b's pose in a's frame are of the size of
/// the answer's ulp: the search's own value misses the bound on some of
/// these poses (1.25 ulps on one), the closest pair posed again meets it.
#[test]
fn matrix_poses_give_the_exact_distance_to_an_ulp() {
    let ball = icosphere(0.7, 1).unwrap();
    let plate = turned(&box_mesh(&Vector::new(1.0, 0.6, 0.05)).unwrap(), Vector::new(0.2, -0.3, 0.1), 1.0);
    let mut rng = Rng::new(4547);
    let mut scratch = MeshDistanceScratch::default();
    let search = DistanceSearch::default();
    let matrix = |rng: &mut Rng| nalgebra::Rotation3::new(rng.in_unit_ball() * 3.0).into_inner();
    // The exact least over the pairs that plain f64 posing puts within 1e-9
    // of its least (its rounding is some 1e-13 here: the least is among them).
    let exact_least = |a: &TriMesh, pose_a: &MatrixPose, b: &TriMesh, pose_b: &MatrixPose| {
        let plain = |mesh: &TriMesh, pose: &MatrixPose, k: usize| {
            mesh.triangle(k).map(|p| Point::from(pose.rotation * p.coords + pose.translation))
        };
        let pairs: Vec<_> = (0..a.triangles().len())
            .flat_map(|i| (0..b.triangles().len()).map(move |j| (i, j)))
            .map(|(i, j)| (triangle_distance(&plain(a, pose_a, i), &plain(b, pose_b, j)).distance, i, j))
            .collect();
        let least = pairs.iter().map(|p| p.0).fold(Real::INFINITY, Real::min);
        let posed = |mesh: &TriMesh, pose: &MatrixPose, k: usize| {
            mesh.triangle(k).map(|p| exact::RationalVector::posed(&p, &pose.rotation, &pose.translation))
        };
        pairs
            .iter()
            .filter(|p| p.0 <= least + 1e-9)
            .map(|&(_, i, j)| {
                exact::rational_triangle_distance_squared(&posed(a, pose_a, i), &posed(b, pose_b, j))
            })
            .min()
            .map(|d| exact::to_f64(&d).sqrt())
            .unwrap()
    };
    for case in 0..48 {
        let centre = rng.unit_vector() * 0.3;
        let pose_a = MatrixPose { rotation: matrix(&mut rng), translation: centre };
        let rotation_b = matrix(&mut rng);
        // b's centre along a random direction at a reach whose gap is
        // about 0.2, 1e-6 or -0.01 (overlapping).
        let gap = [0.2, 1e-6, -0.01][case % 3];
        let direction = rng.unit_vector();
        let reach_of =
            |reach: Real| MatrixPose { rotation: rotation_b, translation: centre + direction * reach };
        let (mut low, mut high) = (0.0, 3.0);
        for _ in 0..60 {
            let middle = 0.5 * (low + high);
            let d = mesh_distance(&ball, &pose_a, &plate, &reach_of(middle), &search, &mut scratch).distance;
            if d > 0.0 {
                high = middle;
            } else {
                low = middle;
            }
        }
        let pose_b = reach_of(high + gap);
        let expected = exact_least(&ball, &pose_a, &plate, &pose_b);
        let largest = [(&ball, &pose_a), (&plate, &pose_b)]
            .iter()
            .flat_map(|(mesh, pose)| {
                mesh.vertices().iter().map(|p| (pose.rotation * p.coords + pose.translation).amax())
            })
            .fold(0.0, Real::max);
        let ulp = f64::from_bits(largest.to_bits() + 1) - largest;
        let forward = mesh_distance(&ball, &pose_a, &plate, &pose_b, &search, &mut scratch);
        let backward = mesh_distance(&plate, &pose_b, &ball, &pose_a, &search, &mut scratch);
        for found in [forward.distance, backward.distance] {
            let error = (found - expected).abs() / ulp;
            assert!(
                error <= 1.0,
                "case {case} (gap {gap}): {found:e} against exact {expected:e}: {error:.2} ulps"
            );
        }
    }
}

//! The penetration depth of overlapping convex meshes: nearmiss's
//! `convex_penetration` (separating axes, exact to rounding) against
//! parry3d-f64's `query::contact` on the same shapes and poses, in the same
//! run: two boxes (parry: its box–box SAT), an icosphere of 80 triangles
//! and a box, and two icospheres of 320 triangles (parry: GJK/EPA on
//! convex polyhedra). 100 seeded overlapping poses each; before timing,
//! the largest difference between the two depths is printed.
//!
//! `cargo bench --bench penetration`.

use criterion::{criterion_group, criterion_main, Criterion};
use nearmiss::math::{pose_to_parry, to_parry, Pose, Real, Vector};
use nearmiss::mesh::{box_mesh, convex_penetration, icosphere, TriMesh};
use nearmiss::samples::Rng;
use parry3d_f64::query::contact;
use parry3d_f64::shape::{ConvexPolyhedron, Cuboid, Shape};
use std::hint::black_box;
use std::time::Duration;

/// `count` seeded pose pairs at which the two meshes overlap (by parry's
/// and nearmiss's word alike).
fn overlapping_poses(a: &TriMesh, b: &TriMesh, count: usize) -> Vec<(Pose, Pose)> {
    let mut rng = Rng::new(23);
    let reach = 0.6 * (a.radius() + b.radius());
    let mut poses = Vec::with_capacity(count);
    while poses.len() < count {
        let pose_a = Pose::new(Vector::zeros(), rng.in_unit_ball() * 3.0);
        let pose_b = Pose::new(rng.in_unit_ball() * reach, rng.in_unit_ball() * 3.0);
        if let Ok(Some(_)) = convex_penetration(a, &pose_a, b, &pose_b) {
            poses.push((pose_a, pose_b));
        }
    }
    poses
}

fn nearmiss_all(a: &TriMesh, b: &TriMesh, poses: &[(Pose, Pose)]) -> Real {
    poses
        .iter()
        .map(|(pa, pb)| {
            convex_penetration(a, black_box(pa), b, black_box(pb)).map_or(0.0, |d| d.map_or(0.0, |d| d.depth))
        })
        .sum()
}

fn parry_all(a: &dyn Shape, b: &dyn Shape, poses: &[(Pose, Pose)]) -> Real {
    poses
        .iter()
        .map(|(pa, pb)| {
            let found = contact(&pose_to_parry(black_box(pa)), a, &pose_to_parry(black_box(pb)), b, 0.0);
            found.ok().flatten().map_or(0.0, |c| -c.dist)
        })
        .sum()
}

fn polyhedron(mesh: &TriMesh) -> ConvexPolyhedron {
    let points = mesh.vertices().iter().map(to_parry).collect();
    ConvexPolyhedron::from_convex_mesh(points, mesh.triangles()).expect("a convex mesh")
}

/// A case: its name, then each mesh beside parry's shape of it.
type Case = (&'static str, TriMesh, Box<dyn Shape>, TriMesh, Box<dyn Shape>);

fn bench(c: &mut Criterion) {
    let box_a = Vector::new(1.0, 0.4, 0.7);
    let box_b = Vector::new(0.3, 1.2, 0.5);
    let small_sphere = icosphere(1.0, 1).expect("icosphere");
    let sphere = icosphere(1.0, 2).expect("icosphere");
    let cases: Vec<Case> = vec![
        (
            "two boxes",
            box_mesh(&box_a).expect("box"),
            Box::new(Cuboid::new(to_parry(&box_a.into()))),
            box_mesh(&box_b).expect("box"),
            Box::new(Cuboid::new(to_parry(&box_b.into()))),
        ),
        (
            "icosphere 80 and a box",
            small_sphere.clone(),
            Box::new(polyhedron(&small_sphere)),
            box_mesh(&box_b).expect("box"),
            Box::new(polyhedron(&box_mesh(&box_b).expect("box"))),
        ),
        (
            "icospheres 320 and 320",
            sphere.clone(),
            Box::new(polyhedron(&sphere)),
            sphere.clone(),
            Box::new(polyhedron(&sphere)),
        ),
    ];
    let mut group = c.benchmark_group("penetration");
    group.measurement_time(Duration::from_secs(3)).warm_up_time(Duration::from_secs(1)).sample_size(20);
    for (name, a, shape_a, b, shape_b) in &cases {
        let poses = overlapping_poses(a, b, 100);
        let worst = poses
            .iter()
            .map(|(pa, pb)| {
                let ours = convex_penetration(a, pa, b, pb).ok().flatten().map_or(0.0, |d| d.depth);
                let peer =
                    contact(&pose_to_parry(pa), shape_a.as_ref(), &pose_to_parry(pb), shape_b.as_ref(), 0.0);
                (ours + peer.ok().flatten().map_or(0.0, |c| c.dist)).abs()
            })
            .fold(0.0, Real::max);
        println!("{name}: 100 overlapping poses, largest depth difference from parry {worst:.1e}");
        group.bench_function(format!("{name}/nearmiss"), |bench| bench.iter(|| nearmiss_all(a, b, &poses)));
        group.bench_function(format!("{name}/parry contact"), |bench| {
            bench.iter(|| parry_all(shape_a.as_ref(), shape_b.as_ref(), &poses))
        });
    }
    group.finish();
}

criterion_group!(benches, bench);
criterion_main!(benches);

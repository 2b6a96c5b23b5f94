//! Real meshes (issue 16 §3): mesh–mesh time of impact on the Stanford
//! bunny (3,674 triangles; `scripts/fetch-bunny.sh` fetches it, the bench
//! says so and skips without it), scaled to radius 1 about its box centre,
//! against parry3d-f64 in the same run, one thread:
//! - two bunnies tumbling into each other (`samples::approach_cases`, the
//!   cases of the icosphere bench with bunnies) against parry's
//!   `cast_shapes_nonlinear`;
//! - the same without spins against parry's `cast_shapes`;
//! - a tumbling bunny falling onto a box floor, against
//!   `cast_shapes_nonlinear` (TriMesh against Cuboid).
//!
//! Before timing, each case's time of impact from both is printed, and a
//! later one is checked: where the meshes already intersect (exact
//! distance 0) at a time before it, that answer was late.
//!
//! `cargo bench --bench bunny_ccd` (a few minutes: parry's rotating casts
//! take up to a second per case).

use criterion::{criterion_group, criterion_main, Criterion};
use nearmiss::ccd::{mesh_time_of_impact, CcdOptions, MeshCcdQuery, MeshCcdScratch, MovingMesh, WarmStart};
use nearmiss::math::{motion_to_parry, pose_to_parry, to_parry, vector_to_parry, Point, Pose, Real, Vector};
use nearmiss::mesh::{
    box_mesh, load_obj, mesh_distance, DistanceKernel, DistanceSearch, MeshDistanceScratch, TriMesh,
};
use nearmiss::motion::StepMotion;
use nearmiss::samples::{approach_cases, Rng};
use parry3d_f64::query::{cast_shapes, cast_shapes_nonlinear, ShapeCastOptions};
use parry3d_f64::shape::Shape;
use std::hint::black_box;
use std::path::Path;
use std::time::{Duration, Instant};

const BUNNY: &str = concat!(env!("CARGO_MANIFEST_DIR"), "/scenes/meshes/bunny.obj");

/// Cases per group (parry's rotating cast on two bunnies takes 0.1–0.6 s
/// a case; the thin bunny misses in some of them).
const CASES: usize = 10;

/// The bunny with its box centre at the origin, scaled to radius 1.
fn bunny() -> Option<TriMesh> {
    let mesh = load_obj(Path::new(BUNNY)).ok()?;
    let (low, high) = mesh.vertices().iter().fold(
        (Point::from(Vector::repeat(Real::INFINITY)), Point::from(Vector::repeat(Real::NEG_INFINITY))),
        |(low, high), v| (low.inf(v), high.sup(v)),
    );
    let centred = mesh.recentered(&nalgebra::center(&low, &high));
    centred.scaled(1.0 / centred.radius()).ok()
}

/// One body of a case: a mesh, nearmiss's motion and parry's shape.
struct Body<'m> {
    mesh: &'m TriMesh,
    shape: &'m dyn Shape,
}

/// nearmiss's time of impact of one case (`None`: none in [0, 1]).
fn nearmiss_toi(
    a: &Body,
    b: &Body,
    (ma, mb): &(StepMotion, StepMotion),
    scratch: &mut MeshCcdScratch,
) -> Option<Real> {
    let query = MeshCcdQuery::new(
        MovingMesh { mesh: a.mesh, motion: black_box(ma) },
        MovingMesh { mesh: b.mesh, motion: black_box(mb) },
        1.0,
        CcdOptions::default(),
    );
    mesh_time_of_impact(&query, WarmStart::default(), scratch).time_of_impact
}

/// parry's time of impact of one case, rotating (`cast_shapes_nonlinear`)
/// or translating (`cast_shapes`, for motions without spin).
fn parry_toi(a: &Body, b: &Body, (ma, mb): &(StepMotion, StepMotion), rotating: bool) -> Option<Real> {
    let hit = if rotating {
        let motion = |m: &StepMotion| motion_to_parry(&m.pose_t0(), &m.velocity, &m.angular_velocity);
        cast_shapes_nonlinear(&motion(ma), a.shape, &motion(mb), b.shape, 0.0, 1.0, true)
    } else {
        cast_shapes(
            &pose_to_parry(&ma.pose_t0()),
            vector_to_parry(&ma.velocity),
            a.shape,
            &pose_to_parry(&mb.pose_t0()),
            vector_to_parry(&mb.velocity),
            b.shape,
            ShapeCastOptions::with_max_time_of_impact(1.0),
        )
    };
    hit.ok().flatten().map(|h| h.time_of_impact)
}

/// Whether the meshes intersect (exact distance 0) somewhere in `[from, to)`
/// on a scan of 64 times: an answer `to` is then late.
fn intersect_before(a: &Body, b: &Body, case: &(StepMotion, StepMotion), from: Real, to: Real) -> bool {
    (0..64).any(|k| distance_at(a, b, case, from + (to - from) * k as Real / 64.0) == 0.0)
}

/// The exact distance between the meshes at time `s` of a case.
fn distance_at(a: &Body, b: &Body, (ma, mb): &(StepMotion, StepMotion), s: Real) -> Real {
    let search = DistanceSearch::new(DistanceKernel::Exact, None);
    mesh_distance(
        a.mesh,
        &ma.pose_at(s),
        b.mesh,
        &mb.pose_at(s),
        &search,
        &mut MeshDistanceScratch::default(),
    )
    .distance
}

/// Prints each case's answers, the exact distance at each, and which one
/// was late (the meshes intersect on a scan of the time before it, after
/// the other's answer); a contact only one reports is checked the same way
/// up to the interval's end.
fn report(name: &str, a: &Body, b: &Body, cases: &[(StepMotion, StepMotion)], rotating: bool) {
    let mut scratch = MeshCcdScratch::default();
    println!("{name}: case | nearmiss toi (distance there) | parry toi (distance there) | parry s | late or missed");
    for (k, case) in cases.iter().enumerate() {
        let ours = nearmiss_toi(a, b, case, &mut scratch);
        let clock = Instant::now();
        let theirs = parry_toi(a, b, case, rotating);
        let seconds = clock.elapsed().as_secs_f64();
        let late = match (ours, theirs) {
            (Some(x), Some(y)) if y > x && intersect_before(a, b, case, x, y) => "parry late",
            (Some(x), Some(y)) if x > y && intersect_before(a, b, case, y, x) => "nearmiss late",
            (Some(x), None) if intersect_before(a, b, case, x, 1.0) => "parry missed",
            (None, Some(y)) if intersect_before(a, b, case, y, 1.0) => "nearmiss missed",
            _ => "-",
        };
        let show = |t: Option<Real>| {
            t.map_or("none".to_string(), |t| format!("{t:.9} ({:.1e})", distance_at(a, b, case, t)))
        };
        println!("  {k} | {} | {} | {seconds:.3} | {late}", show(ours), show(theirs));
    }
}

fn group(
    c: &mut Criterion,
    name: &str,
    a: &Body,
    b: &Body,
    cases: &[(StepMotion, StepMotion)],
    rotating: bool,
) {
    report(name, a, b, cases, rotating);
    let mut scratch = MeshCcdScratch::default();
    let mut group = c.benchmark_group(name);
    group.sample_size(10).measurement_time(Duration::from_secs(10));
    group.bench_function("nearmiss mesh_time_of_impact", |bench| {
        bench.iter(|| {
            cases.iter().map(|case| nearmiss_toi(a, b, case, &mut scratch).unwrap_or(2.0)).sum::<Real>()
        })
    });
    let peer = if rotating { "parry3d-f64 cast_shapes_nonlinear" } else { "parry3d-f64 cast_shapes" };
    group.bench_function(peer, |bench| {
        bench.iter(|| cases.iter().map(|case| parry_toi(a, b, case, rotating).unwrap_or(2.0)).sum::<Real>())
    });
    group.finish();
}

fn bunnies(c: &mut Criterion) {
    let Some(mesh) = bunny() else {
        eprintln!("bunny_ccd bench skipped: no scenes/meshes/bunny.obj (run scripts/fetch-bunny.sh)");
        return;
    };
    let shape = mesh.to_parry().expect("a parry mesh");
    let a = Body { mesh: &mesh, shape: &shape };
    let b = Body { mesh: &mesh, shape: &shape };
    let tumbling = approach_cases(CASES, 5, 10.0);
    group(c, &format!("two tumbling bunnies, {CASES} cases"), &a, &b, &tumbling, true);
    let translating = approach_cases(CASES, 5, 0.0);
    group(c, &format!("two translating bunnies, {CASES} cases"), &a, &b, &translating, false);

    // A tumbling bunny falls onto a floor (the box's top face at y = 0).
    let floor_mesh = box_mesh(&Vector::new(10.0, 0.5, 10.0)).expect("a box");
    let floor_shape = parry3d_f64::shape::Cuboid::new(to_parry(&Point::new(10.0, 0.5, 10.0)));
    let floor = Body { mesh: &floor_mesh, shape: &floor_shape };
    let mut rng = Rng::new(9);
    let falling: Vec<(StepMotion, StepMotion)> = (0..CASES)
        .map(|_| {
            let floor_motion = StepMotion::fixed(Pose::new(Vector::new(0.0, -0.5, 0.0), Vector::zeros()));
            let bunny_motion = StepMotion::new(
                Pose::new(Vector::new(0.0, 2.5, 0.0) + rng.in_unit_ball() * 0.3, rng.in_unit_ball() * 3.0),
                Vector::new(0.0, -3.0, 0.0) + rng.in_unit_ball() * 0.3,
                rng.in_unit_ball() * 10.0,
            );
            (floor_motion, bunny_motion)
        })
        .collect();
    group(c, &format!("tumbling bunny onto a box floor, {CASES} cases"), &floor, &a, &falling, true);
}

criterion_group!(benches, bunnies);
criterion_main!(benches);

//! The Rust library's answers to the queries in a JSON document on stdin,
//! written as JSON to stdout (every float exactly, `float_roundtrip`): the
//! Python package's tests (`python/tests/test_agreement.py`) ask the same
//! queries through the wheel and compare bit for bit.
//!
//! Input: `{"triangle_pairs": [[a, b], ...], "point_segments": [[p, a, b],
//! ...], "moving_pairs": [{"vertices_a", "faces_a", "vertices_b",
//! "faces_b", "pose_a", "motion_a", "pose_b", "motion_b", "duration"}]}`,
//! triangles as three `[x, y, z]` rows, poses `[[x, y, z], [w, x, y, z]]`,
//! motions `[velocity, angular_velocity]`.
//!
//! Usage: `cargo run --release -p nearmiss-cli --example rust_answers < queries.json`.
//!
//! With `--time FILE` instead: FILE holds triangle pairs as raw float64
//! (`a` then `b`, each N × 3 × 3, row-major, as numpy's `tofile` writes
//! them); prints the Rust library's time per pair on one thread, one pair
//! a call (`triangle_distance`) and batched (`batch::triangle_distances`),
//! the best of several runs: what `python/benchmarks/overhead.py` compares
//! its calls with.

use std::io::Read;

use nearmiss::ccd::{
    closest_approach, mesh_time_of_impact, ClosestApproachQuery, MeshCcdQuery, MeshCcdScratch, MovingMesh,
    WarmStart,
};
use nearmiss::kernels::batch::{triangle_distances, TrianglesSoa};
use nearmiss::kernels::{dyop_distance, point_segment_distance, triangle_distance, PointEdgeFormula};
use nearmiss::math::{Point, Pose, Triangle, Vector};
use nearmiss::mesh::{MeshDistance, TriMesh};
use nearmiss::motion::StepMotion;
use serde::Deserialize;
use serde_json::{json, Value};

type Xyz = [f64; 3];

#[derive(Deserialize)]
struct Queries {
    triangle_pairs: Vec<[[Xyz; 3]; 2]>,
    point_segments: Vec<[Xyz; 3]>,
    moving_pairs: Vec<MovingPair>,
}

#[derive(Deserialize)]
struct MovingPair {
    vertices_a: Vec<Xyz>,
    faces_a: Vec<[u32; 3]>,
    vertices_b: Vec<Xyz>,
    faces_b: Vec<[u32; 3]>,
    pose_a: (Xyz, [f64; 4]),
    motion_a: (Xyz, Xyz),
    pose_b: (Xyz, [f64; 4]),
    motion_b: (Xyz, Xyz),
    duration: f64,
}

fn point(p: &Xyz) -> Point {
    Point::new(p[0], p[1], p[2])
}

fn triangle(t: &[Xyz; 3]) -> Triangle {
    t.each_ref().map(point)
}

fn mesh(vertices: &[Xyz], faces: &[[u32; 3]]) -> TriMesh {
    TriMesh::new(vertices.iter().map(point).collect(), faces.to_vec()).expect("a valid mesh")
}

fn motion((position, q): &(Xyz, [f64; 4]), (velocity, angular): &(Xyz, Xyz)) -> StepMotion {
    let rotation = nalgebra::UnitQuaternion::new_normalize(nalgebra::Quaternion::new(q[0], q[1], q[2], q[3]));
    let pose = Pose::from_parts(point(position).into(), rotation);
    StepMotion::new(pose, Vector::from(*velocity), Vector::from(*angular))
}

fn xyz(p: &Point) -> Value {
    json!([p.x, p.y, p.z])
}

fn mesh_distance(d: &MeshDistance) -> Value {
    json!({
        "distance": d.distance, "point_a": xyz(&d.point_a), "point_b": xyz(&d.point_b),
        "triangle_a": d.triangle_a, "triangle_b": d.triangle_b,
        "feature_a": d.feature_a.to_string(), "feature_b": d.feature_b.to_string(),
    })
}

/// `--time FILE`: the Rust calls' time per pair on the pairs in FILE.
fn time_pairs(path: &str) {
    let bytes = std::fs::read(path).expect("the pairs file");
    let numbers: Vec<f64> =
        bytes.chunks_exact(8).map(|b| f64::from_le_bytes(b.try_into().expect("8 bytes"))).collect();
    let n = numbers.len() / 18;
    let triangle = |k: usize| -> Triangle {
        [0, 1, 2]
            .map(|v| point(&[numbers[9 * k + 3 * v], numbers[9 * k + 3 * v + 1], numbers[9 * k + 3 * v + 2]]))
    };
    let a: Vec<Triangle> = (0..n).map(triangle).collect();
    let b: Vec<Triangle> = (n..2 * n).map(triangle).collect();
    let best = |runs: usize, work: &mut dyn FnMut() -> f64| {
        (0..runs)
            .map(|_| {
                let clock = std::time::Instant::now();
                std::hint::black_box(work());
                clock.elapsed().as_secs_f64()
            })
            .fold(f64::INFINITY, f64::min)
    };
    let single = best(5, &mut || a.iter().zip(&b).map(|(x, y)| triangle_distance(x, y).distance).sum());
    let (soa_a, soa_b) = (TrianglesSoa::from_triangles(&a), TrianglesSoa::from_triangles(&b));
    let mut out = vec![0.0; n];
    let batched = best(20, &mut || {
        triangle_distances(&soa_a, &soa_b, &mut out);
        out.iter().sum()
    });
    println!(
        "{{\"pairs\": {n}, \"single_ns\": {}, \"batched_ns\": {}}}",
        single / n as f64 * 1e9,
        batched / n as f64 * 1e9
    );
}

fn main() {
    let arguments: Vec<String> = std::env::args().collect();
    if let [_, flag, path] = arguments.as_slice() {
        if flag == "--time" {
            return time_pairs(path);
        }
    }
    let mut text = String::new();
    std::io::stdin().read_to_string(&mut text).expect("stdin");
    let queries: Queries = serde_json::from_str(&text).expect("the queries document");
    let pairs: Vec<(Triangle, Triangle)> =
        queries.triangle_pairs.iter().map(|[a, b]| (triangle(a), triangle(b))).collect();
    let single: Vec<Value> = pairs
        .iter()
        .map(|(a, b)| {
            let d = triangle_distance(a, b);
            json!({
                "distance": d.distance, "point_a": xyz(&d.point_a), "point_b": xyz(&d.point_b),
                "feature_a": d.feature_a.to_string(), "feature_b": d.feature_b.to_string(),
                "dyop_vector": dyop_distance(a, b, PointEdgeFormula::Vector),
                "dyop_heron": dyop_distance(a, b, PointEdgeFormula::Heron),
            })
        })
        .collect();
    let (a, b): (Vec<Triangle>, Vec<Triangle>) = pairs.iter().copied().unzip();
    let mut batched = vec![0.0; pairs.len()];
    triangle_distances(&TrianglesSoa::from_triangles(&a), &TrianglesSoa::from_triangles(&b), &mut batched);
    let formulas = [
        ("vector", PointEdgeFormula::Vector),
        ("plain_vector", PointEdgeFormula::PlainVector),
        ("heron", PointEdgeFormula::Heron),
        ("stable_heron", PointEdgeFormula::StableHeron),
    ];
    let point_segments: Vec<Value> = queries
        .point_segments
        .iter()
        .map(|[p, a, b]| {
            let answers: serde_json::Map<String, Value> = formulas
                .iter()
                .map(|(name, f)| {
                    (name.to_string(), json!(point_segment_distance(&point(p), &point(a), &point(b), *f)))
                })
                .collect();
            Value::Object(answers)
        })
        .collect();
    let moving: Vec<Value> = queries
        .moving_pairs
        .iter()
        .map(|q| {
            let (mesh_a, mesh_b) = (mesh(&q.vertices_a, &q.faces_a), mesh(&q.vertices_b, &q.faces_b));
            let (motion_a, motion_b) = (motion(&q.pose_a, &q.motion_a), motion(&q.pose_b, &q.motion_b));
            let a = MovingMesh { mesh: &mesh_a, motion: &motion_a };
            let b = MovingMesh { mesh: &mesh_b, motion: &motion_b };
            let ccd = MeshCcdQuery::new(a, b, q.duration, Default::default());
            let toi = mesh_time_of_impact(&ccd, WarmStart::default(), &mut MeshCcdScratch::default());
            let approach = closest_approach(
                &ClosestApproachQuery::new(a, b, q.duration),
                &mut MeshCcdScratch::default(),
            );
            json!({
                "time_of_impact": toi.time_of_impact,
                "iterations": toi.iterations,
                "lower": approach.lower,
                "upper": approach.upper,
                "time": approach.time,
                "closest": approach.closest.as_ref().map(mesh_distance),
            })
        })
        .collect();
    let answers = json!({
        "triangle_distance": single,
        "triangle_distances": batched,
        "point_segment_distance": point_segments,
        "moving_pairs": moving,
    });
    println!("{answers}");
}

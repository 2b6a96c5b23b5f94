//! Mesh files (issue 46): a 1,000,000-triangle binary STL (a torus of
//! 1,000 × 500 segments, written to a temporary file first), read by
//! `load_mesh` (read, check, weld, validate and build the BVH: a mesh
//! ready for queries) beside its parts and the peer in the same run:
//! - `stl_io::read_stl`, the crate's own indexed read (welds as well, in
//!   f32, and builds nothing);
//! - `read_mesh` on bytes already in memory, without the file read;
//! - `TriMesh::new` on the welded arrays: the validation and BVH alone.
//!
//! `cargo bench --bench mesh_files` (about a minute).

use criterion::{criterion_group, criterion_main, Criterion};
use nearmiss::mesh::{load_mesh, read_mesh, torus, TriMesh};
use std::hint::black_box;
use std::path::{Path, PathBuf};

/// The torus's segments around and across: 2 × 1,000 × 500 triangles.
const AROUND: u32 = 1000;
const ACROSS: u32 = 500;

/// Writes the torus as a binary STL and returns its path.
fn write_stl() -> PathBuf {
    let mesh = torus(1.0, 0.3, AROUND, ACROSS).expect("a torus");
    let mut bytes = b"nearmiss mesh_files bench".to_vec();
    bytes.resize(80, b' ');
    bytes.extend_from_slice(&(mesh.triangles().len() as u32).to_le_bytes());
    for t in mesh.triangles() {
        bytes.extend_from_slice(&[0; 12]);
        for &v in t {
            for c in mesh.vertices()[v as usize].coords.iter() {
                bytes.extend_from_slice(&(*c as f32).to_le_bytes());
            }
        }
        bytes.extend_from_slice(&[0, 0]);
    }
    let path = std::env::temp_dir().join(format!("nearmiss-bench-{}.stl", std::process::id()));
    std::fs::write(&path, bytes).expect("the STL written");
    path
}

fn bench(c: &mut Criterion) {
    let path = write_stl();
    let loaded = load_mesh(&path).expect("the STL read");
    println!(
        "{}: {} triangles, {} vertices after welding ({} bytes)",
        path.display(),
        loaded.triangles().len(),
        loaded.vertices().len(),
        std::fs::metadata(&path).map(|m| m.len()).unwrap_or(0)
    );
    let bytes = std::fs::read(&path).expect("the STL read");
    let mut group = c.benchmark_group("stl_1m_triangles");
    group.sample_size(10);
    group.bench_function("nearmiss load_mesh (file to ready mesh)", |b| {
        b.iter(|| black_box(load_mesh(black_box(&path)).expect("read")))
    });
    group.bench_function("nearmiss read_mesh (bytes to ready mesh)", |b| {
        b.iter(|| black_box(read_mesh(bytes.clone(), Path::new("bench.stl")).expect("read")))
    });
    group.bench_function("nearmiss TriMesh::new (welded arrays to ready mesh)", |b| {
        b.iter(|| {
            black_box(TriMesh::new(loaded.vertices().to_vec(), loaded.triangles().to_vec()).expect("valid"))
        })
    });
    group.bench_function("stl_io read_stl (file to indexed arrays)", |b| {
        b.iter(|| {
            let mut file = std::fs::File::open(&path).expect("open");
            black_box(stl_io::read_stl(&mut file).expect("read"))
        })
    });
    group.finish();
    let _ = std::fs::remove_file(&path);
}

criterion_group!(benches, bench);
criterion_main!(benches);

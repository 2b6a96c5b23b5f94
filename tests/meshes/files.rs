//! Mesh files in every format read (issue 46): the same box written as
//! binary and ASCII STL, ASCII and binary PLY, glTF with a data URI, glTF
//! with a buffer file beside it, and GLB. Each must read as the closed box it
//! is: its corners welded (STL stores each triangle's corners apart), its
//! volume and bounds those of the box by analysis, node transforms applied
//! (a mirroring one keeping the faces outward). Bad files name the file, the
//! format and the place.

use std::path::{Path, PathBuf};

use base64::Engine;
use nearmiss::math::{Point, Vector};
use nearmiss::mesh::{box_mesh, load_mesh, read_mesh, MeshFileError, MeshFormat, TriMesh};

/// The box `[1, 3] × [-1, 2] × [0, 4]` (volume 24): its 8 corners and 12
/// outward triangles, written out by hand below in each format.
fn the_box() -> (Vec<[f32; 3]>, Vec<[u32; 3]>) {
    let unit = box_mesh(&Vector::new(1.0, 1.5, 2.0)).unwrap();
    let centre = Vector::new(2.0, 0.5, 2.0);
    let corners = unit.vertices().iter().map(|p| (p + centre).coords.map(|c| c as f32).into()).collect();
    (corners, unit.triangles().to_vec())
}

const VOLUME: f64 = 2.0 * 3.0 * 4.0;

fn temp_file(name: &str, bytes: &[u8]) -> PathBuf {
    let folder = std::env::temp_dir().join(format!("nearmiss-mesh-files-{}", std::process::id()));
    std::fs::create_dir_all(&folder).unwrap();
    let path = folder.join(name);
    std::fs::write(&path, bytes).unwrap();
    path
}

/// The mesh is the box moved by `offset`: 8 vertices, 12 triangles, closed,
/// outward, its volume and bounds those of the box.
fn assert_is_the_box(mesh: &TriMesh, offset: Vector) {
    assert_eq!(mesh.vertices().len(), 8, "corners welded");
    assert_eq!(mesh.triangles().len(), 12);
    mesh.check_closed().unwrap();
    let mass = mesh.mass_properties().expect("a closed, outward surface");
    assert!((mass.volume - VOLUME).abs() < 1e-12, "volume {}", mass.volume);
    let (low, high) = mesh.bounds();
    assert_eq!(low, Point::new(1.0, -1.0, 0.0) + offset);
    assert_eq!(high, Point::new(3.0, 2.0, 4.0) + offset);
}

fn binary_stl(header: &[u8]) -> Vec<u8> {
    let (corners, triangles) = the_box();
    let mut bytes = header.to_vec();
    bytes.resize(80, b' ');
    bytes.extend_from_slice(&(triangles.len() as u32).to_le_bytes());
    for t in &triangles {
        bytes.extend_from_slice(&[0u8; 12]); // the normal, which nothing reads
        for &v in t {
            corners[v as usize].iter().for_each(|c| bytes.extend_from_slice(&c.to_le_bytes()));
        }
        bytes.extend_from_slice(&[0, 0]);
    }
    bytes
}

fn ascii_stl(name: &str) -> String {
    let (corners, triangles) = the_box();
    let mut text = format!("solid{name}\n");
    for t in &triangles {
        text += "  facet normal 0 0 0\n    outer loop\n";
        for &v in t {
            let [x, y, z] = corners[v as usize];
            text += &format!("      vertex {x:e} {y:e} {z:e}\n");
        }
        text += "    endloop\n  endfacet\n";
    }
    text + "endsolid\n"
}

/// A PLY header for the box's vertices (as `float`) and faces (as
/// `uchar`-counted `int` lists), in `encoding`.
fn ply_header(encoding: &str) -> String {
    format!(
        "ply\nformat {encoding} 1.0\ncomment the box\nelement vertex 8\nproperty float x\nproperty float y\nproperty float z\nelement face 12\nproperty list uchar int vertex_indices\nend_header\n"
    )
}

fn ascii_ply() -> String {
    let (corners, triangles) = the_box();
    let mut text = ply_header("ascii");
    for [x, y, z] in corners {
        text += &format!("{x} {y} {z}\n");
    }
    for [a, b, c] in triangles {
        text += &format!("3 {a} {b} {c}\n");
    }
    text
}

fn binary_ply() -> Vec<u8> {
    let (corners, triangles) = the_box();
    let mut bytes = ply_header("binary_big_endian").into_bytes();
    corners.iter().flatten().for_each(|c| bytes.extend_from_slice(&c.to_be_bytes()));
    for t in &triangles {
        bytes.push(3);
        t.iter().for_each(|&i| bytes.extend_from_slice(&(i as i32).to_be_bytes()));
    }
    bytes
}

/// The box's positions (f32) then indices (u32), as one glTF buffer.
fn gltf_buffer() -> Vec<u8> {
    let (corners, triangles) = the_box();
    let mut bytes: Vec<u8> = corners.iter().flatten().flat_map(|c| c.to_le_bytes()).collect();
    bytes.extend(triangles.iter().flatten().flat_map(|i| i.to_le_bytes()));
    bytes
}

/// A glTF document placing the box at a node with `node` (its transform
/// fields), its buffer at `uri` (absent: the GLB's BIN chunk).
fn gltf_json(uri: Option<&str>, node: &str) -> String {
    let length = gltf_buffer().len();
    let uri = uri.map(|u| format!(r#""uri": "{u}", "#)).unwrap_or_default();
    format!(
        r#"{{
  "asset": {{"version": "2.0"}},
  "scene": 0,
  "scenes": [{{"nodes": [0]}}],
  "nodes": [{{"children": [1], "translation": [0, 0, 10]}}, {{"mesh": 0{node}}}],
  "meshes": [{{"primitives": [{{"attributes": {{"POSITION": 0}}, "indices": 1}}]}}],
  "buffers": [{{{uri}"byteLength": {length}}}],
  "bufferViews": [
    {{"buffer": 0, "byteOffset": 0, "byteLength": 96}},
    {{"buffer": 0, "byteOffset": 96, "byteLength": 144}}
  ],
  "accessors": [
    {{"bufferView": 0, "componentType": 5126, "count": 8, "type": "VEC3",
      "min": [1, -1, 0], "max": [3, 2, 4]}},
    {{"bufferView": 1, "componentType": 5125, "count": 36, "type": "SCALAR"}}
  ]
}}"#
    )
}

fn glb(json: &str) -> Vec<u8> {
    let mut json = json.as_bytes().to_vec();
    json.resize(json.len().next_multiple_of(4), b' ');
    let mut bin = gltf_buffer();
    bin.resize(bin.len().next_multiple_of(4), 0);
    let total = 12 + 8 + json.len() + 8 + bin.len();
    let mut bytes = b"glTF".to_vec();
    for word in [2, total as u32, json.len() as u32, 0x4E4F534A] {
        bytes.extend_from_slice(&word.to_le_bytes());
    }
    bytes.extend_from_slice(&json);
    bytes.extend_from_slice(&(bin.len() as u32).to_le_bytes());
    bytes.extend_from_slice(&0x004E4942u32.to_le_bytes());
    bytes.extend_from_slice(&bin);
    bytes
}

fn read(name: &str, bytes: impl Into<Vec<u8>>) -> Result<TriMesh, MeshFileError> {
    read_mesh(bytes.into(), Path::new(name))
}

fn format_of(name: &str, bytes: impl AsRef<[u8]>) -> MeshFormat {
    MeshFormat::of(bytes.as_ref(), Path::new(name))
}

#[test]
fn every_format_reads_the_closed_box() {
    let none = Vector::zeros();
    // Binary STL, with and without a header that begins `solid`.
    for header in [&b"binary box"[..], b"solid box, from an exporter that writes it so"] {
        assert_eq!(format_of("box.stl", binary_stl(header)), MeshFormat::BinaryStl);
        assert_is_the_box(&read("box.stl", binary_stl(header)).unwrap(), none);
    }
    // ASCII STL, with a named and an unnamed solid.
    for name in [" box", ""] {
        assert_eq!(format_of("box.stl", ascii_stl(name)), MeshFormat::AsciiStl);
        assert_is_the_box(&read("box.stl", ascii_stl(name)).unwrap(), none);
    }
    assert_is_the_box(&read("box.ply", ascii_ply()).unwrap(), none);
    assert_is_the_box(&read("box.ply", binary_ply()).unwrap(), none);
    // glTF: the root node's translation (0, 0, 10) carries to its child.
    let up = Vector::new(0.0, 0.0, 10.0);
    let data_uri = format!(
        "data:application/octet-stream;base64,{}",
        base64::engine::general_purpose::STANDARD.encode(gltf_buffer())
    );
    assert_is_the_box(&read("box.gltf", gltf_json(Some(&data_uri), "")).unwrap(), up);
    assert_eq!(format_of("box.glb", glb(&gltf_json(None, ""))), MeshFormat::Glb);
    assert_is_the_box(&read("box.glb", glb(&gltf_json(None, ""))).unwrap(), up);
    // A buffer in a file beside the glTF file.
    temp_file("box.bin", &gltf_buffer());
    let beside = temp_file("box.gltf", gltf_json(Some("box.bin"), "").as_bytes());
    assert_is_the_box(&load_mesh(&beside).unwrap(), up);
    // Any name: the contents decide.
    assert_is_the_box(&load_mesh(&temp_file("box.mesh", &binary_stl(b"x"))).unwrap(), none);
}

/// The same box as trimesh writes it in each format (`tests/data/mesh_files`):
/// a writer these readers were not made beside.
#[test]
fn files_another_library_wrote_read_as_the_box() {
    let folder = Path::new(concat!(env!("CARGO_MANIFEST_DIR"), "/tests/data/mesh_files"));
    let expected = [
        ("box.stl", MeshFormat::BinaryStl),
        ("box_ascii.stl", MeshFormat::AsciiStl),
        ("box.ply", MeshFormat::Ply),
        ("box_ascii.ply", MeshFormat::Ply),
        ("box.glb", MeshFormat::Glb),
        ("box.obj", MeshFormat::Obj),
    ];
    for (name, format) in expected {
        let path = folder.join(name);
        assert_eq!(format_of(name, std::fs::read(&path).unwrap()), format, "{name}");
        let mesh = load_mesh(&path).unwrap_or_else(|e| panic!("{e}"));
        assert_is_the_box(&mesh, Vector::zeros());
    }
}

/// A node's scale of -1 along x mirrors the box to `[-3, -1]`; its
/// triangles' winding is turned back, so the surface stays outward (a
/// positive volume) and closed.
#[test]
fn a_mirroring_node_keeps_the_box_outward() {
    let mesh = read("mirror.gltf", glb(&gltf_json(None, r#", "scale": [-1, 1, 1]"#))).unwrap();
    mesh.check_closed().unwrap();
    let mass = mesh.mass_properties().expect("outward");
    assert!((mass.volume - VOLUME).abs() < 1e-12);
    let (low, high) = mesh.bounds();
    assert_eq!((low, high), (Point::new(-3.0, -1.0, 10.0), Point::new(-1.0, 2.0, 14.0)));
}

/// The same box in OBJ with its corners repeated at a seam (as exporters
/// write them for texture seams) is welded to the closed box too.
#[test]
fn obj_corners_repeated_at_a_seam_are_welded() {
    let (corners, triangles) = the_box();
    let mut text = String::new();
    for [x, y, z] in corners.iter().chain(&corners) {
        text += &format!("v {x} {y} {z}\n");
    }
    for (k, [a, b, c]) in triangles.iter().enumerate() {
        let seam = if k % 2 == 0 { 1 } else { 9 }; // every other face on the copies
        text += &format!("f {} {} {}\n", a + seam, b + seam, c + seam);
    }
    assert_is_the_box(&read("seam.obj", text).unwrap(), Vector::zeros());
}

fn message(name: &str, bytes: impl Into<Vec<u8>>) -> String {
    read(name, bytes).unwrap_err().to_string()
}

#[test]
fn bad_files_name_the_file_the_format_and_the_place() {
    let mut cut = binary_stl(b"box");
    cut.truncate(cut.len() - 7);
    assert_eq!(
        message("cut.stl", cut),
        "cut.stl: binary STL, the header: it states 12 triangles, so 84 + 50 × 12 = 684 bytes, but the file has 677 (cut short, or not an STL)"
    );
    let bad_vertex = ascii_stl(" box").replacen("vertex 3e0", "vertex three", 1);
    let text = message("bad.stl", bad_vertex.clone());
    let line = bad_vertex.lines().position(|l| l.contains("three")).unwrap() + 1;
    let facet_line = bad_vertex.lines().take(line).filter(|l| l.trim_start().starts_with("facet")).count();
    assert_eq!(
        text,
        format!("bad.stl: ASCII STL, facet {facet_line} (line {line}): `three` is not a number")
    );
    let nan = ascii_stl(" box").replacen("vertex 3e0", "vertex NaN", 1);
    assert_eq!(message("nan.stl", nan), text.replace("bad.stl", "nan.stl").replace("three", "NaN"));
    let bad_index = ascii_ply().replacen("3 0 ", "3 8 ", 1);
    assert_eq!(
        message("bad.ply", bad_index),
        "bad.ply: PLY, face 1: vertex index 8 is not one of the 8 vertices (0-based)"
    );
    let cloud = ascii_ply().replace("element face 12", "element face 0");
    let cloud: String = cloud.lines().take(18).map(|l| format!("{l}\n")).collect();
    assert_eq!(
        message("cloud.ply", cloud),
        "cloud.ply: PLY, the header: no `face` element with faces (a point cloud is not a surface)"
    );
    let bad_ply = ascii_ply().replacen("1 -1 0", "1 -1 zero", 1);
    let line = bad_ply.lines().position(|l| l.contains("zero")).unwrap() + 1;
    let text = message("bad.ply", bad_ply);
    assert!(text.starts_with(&format!("bad.ply: PLY, line {line}: ")), "{text}");
    let missing = message("box.gltf", gltf_json(Some("no-such-file.bin"), ""));
    assert!(missing.starts_with("box.gltf: glTF, buffers[0]: no-such-file.bin: "), "{missing}");
    let far = message("box.gltf", gltf_json(Some("https://example.invalid/box.bin"), ""));
    assert!(far.contains("nothing is fetched"), "{far}");
    let wrong_index = glb(&gltf_json(None, "")).len();
    let mut bad_glb = glb(&gltf_json(None, ""));
    bad_glb[wrong_index - 4..].copy_from_slice(&99u32.to_le_bytes());
    assert_eq!(
        message("bad.glb", bad_glb),
        "bad.glb: GLB, meshes[0].primitives[0] (at nodes[1]): index 99 is not one of its 8 positions"
    );
    let text = message("binary.obj", vec![0x80, 0x81, 0x82]);
    assert!(text.starts_with("binary.obj:1:1: not valid UTF-8 text (not a mesh format"), "{text}");
}

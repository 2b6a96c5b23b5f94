//! `animation.glb`: the run as a glTF 2.0 binary with one animation, so it
//! can be replayed with no code in Blender, any glTF viewer or a browser
//! (written with `poses.csv`, from the same pose records).
//!
//! glTF is +Y up and the scene states its own up axis (`up`, by default
//! against gravity, else Z): one root node turns the scene's up axis onto
//! +Y, and under it the bodies keep the scene's coordinates, so a ball that
//! falls along −z in the scene falls down in Blender or three.js.
//!
//! Each body is a node with its own material (a colour of its own; bodies
//! that share a mesh share its vertices and triangles in the file, each
//! with its own glTF mesh naming its material); each moving body has a
//! translation and a rotation channel, sampled at the pose records' times and interpolated
//! linearly (rotations: spherical-linear, glTF's rule for quaternions).
//! glTF stores 32-bit floats: coordinates keep about 7 significant digits,
//! plenty to look at and not an exact record (`poses.csv` is).

use serde_json::json;

use nearmiss::math::Real;
use nearmiss::run::PoseRecord;
use nearmiss::scene::{Axis, Scene};

/// Body colours (RGBA, linear), in body order.
const COLOURS: [[f32; 4]; 6] = [
    [0.12, 0.47, 0.71, 1.0],
    [1.0, 0.5, 0.05, 1.0],
    [0.17, 0.63, 0.17, 1.0],
    [0.84, 0.15, 0.16, 1.0],
    [0.58, 0.4, 0.74, 1.0],
    [0.55, 0.34, 0.29, 1.0],
];

/// Body `i`'s colour: the palette, then hues a golden angle apart, so that
/// neighbours in body order differ.
fn colour(i: usize) -> [f32; 4] {
    if let Some(c) = COLOURS.get(i) {
        return *c;
    }
    let hue = (i as f32 * 0.618_034).fract() * 6.0;
    let x = 1.0 - (hue % 2.0 - 1.0).abs();
    let [r, g, b] = match hue as u32 {
        0 => [1.0, x, 0.0],
        1 => [x, 1.0, 0.0],
        2 => [0.0, 1.0, x],
        3 => [0.0, x, 1.0],
        4 => [x, 0.0, 1.0],
        _ => [1.0, 0.0, x],
    };
    // Saturation 0.65, value 0.8.
    [r, g, b]
        .map(|c| 0.8 * (1.0 - 0.65 * (1.0 - c)))
        .into_iter()
        .chain([1.0])
        .collect::<Vec<f32>>()
        .try_into()
        .unwrap_or([0.5, 0.5, 0.5, 1.0])
}

/// glTF's component types and buffer view targets.
const FLOAT: u32 = 5126;
const UNSIGNED_INT: u32 = 5125;
const ARRAY_BUFFER: u32 = 34962;
const ELEMENT_ARRAY_BUFFER: u32 = 34963;

/// The binary buffer and the accessors into it, as they are added.
#[derive(Default)]
struct Buffer {
    bytes: Vec<u8>,
    views: Vec<serde_json::Value>,
    accessors: Vec<serde_json::Value>,
}

impl Buffer {
    /// Appends `values` (f32, `width` per element: 1 SCALAR, 3 VEC3, 4 VEC4)
    /// as an accessor with its bounds; returns its index.
    fn floats(&mut self, values: &[f32], width: usize, target: Option<u32>) -> usize {
        let kind = match width {
            1 => "SCALAR",
            3 => "VEC3",
            _ => "VEC4",
        };
        let (mut min, mut max) = (vec![f32::INFINITY; width], vec![f32::NEG_INFINITY; width]);
        for chunk in values.chunks(width) {
            for (k, v) in chunk.iter().enumerate() {
                min[k] = min[k].min(*v);
                max[k] = max[k].max(*v);
            }
        }
        let view = self.view(values.iter().flat_map(|v| v.to_le_bytes()).collect(), target);
        self.accessors.push(json!({
            "bufferView": view, "componentType": FLOAT, "count": values.len() / width,
            "type": kind, "min": min, "max": max,
        }));
        self.accessors.len() - 1
    }

    /// Appends triangle indices; returns the accessor's index.
    fn indices(&mut self, triangles: &[[u32; 3]]) -> usize {
        let bytes = triangles.iter().flatten().flat_map(|i| i.to_le_bytes()).collect();
        let view = self.view(bytes, Some(ELEMENT_ARRAY_BUFFER));
        self.accessors.push(json!({
            "bufferView": view, "componentType": UNSIGNED_INT, "count": triangles.len() * 3, "type": "SCALAR",
        }));
        self.accessors.len() - 1
    }

    fn view(&mut self, bytes: Vec<u8>, target: Option<u32>) -> usize {
        let offset = self.bytes.len();
        self.bytes.extend_from_slice(&bytes);
        while self.bytes.len() % 4 != 0 {
            self.bytes.push(0);
        }
        let mut view = json!({ "buffer": 0, "byteOffset": offset, "byteLength": bytes.len() });
        if let Some(target) = target {
            view["target"] = json!(target);
        }
        self.views.push(view);
        self.views.len() - 1
    }
}

/// The run as a GLB file: `scene`'s bodies and meshes, animated by `poses`
/// (each body's frame, the records of a run in time order). Fails only
/// when the file would pass glTF's 4 GiB limit.
pub fn glb(scene: &Scene, poses: &[PoseRecord]) -> Result<Vec<u8>, String> {
    let mut buffer = Buffer::default();
    // The accessors (positions, indices) of each mesh asset, written once.
    let mut assets: Vec<(*const nearmiss::mesh::TriMesh, usize, usize)> = Vec::new();
    let mut meshes = Vec::new();
    let mut materials = Vec::new();
    let mut nodes = Vec::new();
    for (i, body) in scene.model().bodies.iter().enumerate() {
        let colour = colour(i);
        materials.push(json!({
            "name": body.name,
            "pbrMetallicRoughness": { "baseColorFactor": colour, "metallicFactor": 0.0, "roughnessFactor": 0.8 },
            "doubleSided": true,
        }));
        let asset = std::sync::Arc::as_ptr(&body.mesh);
        let (positions, indices) = match assets.iter().find(|a| a.0 == asset) {
            Some(&(_, positions, indices)) => (positions, indices),
            None => {
                let positions: Vec<f32> =
                    body.mesh.vertices().iter().flat_map(|p| [p.x as f32, p.y as f32, p.z as f32]).collect();
                let positions = buffer.floats(&positions, 3, Some(ARRAY_BUFFER));
                let indices = buffer.indices(body.mesh.triangles());
                assets.push((asset, positions, indices));
                (positions, indices)
            }
        };
        meshes.push(json!({
            "name": body.name,
            "primitives": [{ "attributes": { "POSITION": positions }, "indices": indices, "material": i }],
        }));
        let (t, q) = (body.pose.translation.vector, body.pose.rotation);
        nodes.push(json!({
            "name": body.name,
            "mesh": i,
            "translation": [t.x, t.y, t.z],
            "rotation": [q.i, q.j, q.k, q.w],
        }));
    }

    let (samplers, channels) = animations(scene, poses, &mut buffer);

    // The root, last: the bodies' nodes keep their indices (the channels'
    // targets), and it turns the scene's up axis onto glTF's +Y.
    let half = std::f64::consts::FRAC_1_SQRT_2;
    let turn_up = match scene.run().up {
        Axis::Y => [0.0, 0.0, 0.0, 1.0],
        // −90° about x: +z → +y, +y → −z.
        Axis::Z => [-half, 0.0, 0.0, half],
        // +90° about z: +x → +y, +y → −x.
        Axis::X => [0.0, 0.0, half, half],
    };
    let bodies: Vec<usize> = (0..nodes.len()).collect();
    nodes.push(json!({
        "name": format!("{} ({:?} up)", scene.run().name, scene.run().up),
        "rotation": turn_up,
        "children": bodies,
    }));
    let mut document = json!({
        "asset": { "version": "2.0", "generator": concat!("nearmiss ", env!("CARGO_PKG_VERSION")) },
        "scene": 0,
        "scenes": [{ "name": scene.run().name, "nodes": [nodes.len() - 1] }],
        "nodes": nodes,
        "meshes": meshes,
        "materials": materials,
        "buffers": [{ "byteLength": buffer.bytes.len() }],
        "bufferViews": buffer.views,
        "accessors": buffer.accessors,
    });
    if !channels.is_empty() {
        document["animations"] =
            json!([{ "name": scene.run().name, "samplers": samplers, "channels": channels }]);
    }
    container(serde_json::to_vec(&document).expect("JSON of plain values"), &buffer.bytes)
}

/// Each moving body's animation: a sampler and a channel for its
/// translations and its rotations, their data written to `buffer`.
fn animations(
    scene: &Scene,
    poses: &[PoseRecord],
    buffer: &mut Buffer,
) -> (Vec<serde_json::Value>, Vec<serde_json::Value>) {
    // Each body's records, in time order, strictly increasing times.
    let mut tracks: Vec<Vec<&PoseRecord>> = vec![Vec::new(); scene.model().bodies.len()];
    for record in poses {
        let track = &mut tracks[record.body];
        if track.last().is_none_or(|last| record.time > last.time) {
            track.push(record);
        }
    }
    let mut samplers = Vec::new();
    let mut channels = Vec::new();
    for (node, track) in tracks.iter().enumerate() {
        let moves =
            track.windows(2).any(|w| w[0].position != w[1].position || w[0].orientation != w[1].orientation);
        if track.len() < 2 || !moves {
            continue;
        }
        let times: Vec<f32> = track.iter().map(|r| r.time as f32).collect();
        let input = buffer.floats(&times, 1, None);
        let translations: Vec<f32> = track
            .iter()
            .flat_map(|r| [r.position.x, r.position.y, r.position.z].map(|v: Real| v as f32))
            .collect();
        let rotations: Vec<f32> = track
            .iter()
            .flat_map(|r| {
                let q = r.orientation;
                [q.i, q.j, q.k, q.w].map(|v: Real| v as f32)
            })
            .collect();
        for (path, values, width) in [("translation", translations, 3), ("rotation", rotations, 4)] {
            let output = buffer.floats(&values, width, None);
            samplers.push(json!({ "input": input, "output": output, "interpolation": "LINEAR" }));
            channels.push(json!({ "sampler": samplers.len() - 1, "target": { "node": node, "path": path } }));
        }
    }
    (samplers, channels)
}

/// The GLB file: the JSON chunk (`text`, padded to four bytes) and the
/// binary chunk.
fn container(mut text: Vec<u8>, bytes: &[u8]) -> Result<Vec<u8>, String> {
    while text.len() % 4 != 0 {
        text.push(b' ');
    }
    let total = 12 + 8 + text.len() + 8 + bytes.len();
    if u32::try_from(total).is_err() {
        return Err(format!(
            "animation.glb would be {total} bytes, beyond glTF's 4 GiB: record fewer poses (`poses: (every: n)`)"
        ));
    }
    let mut file = Vec::with_capacity(total);
    file.extend_from_slice(b"glTF");
    file.extend_from_slice(&2u32.to_le_bytes());
    file.extend_from_slice(&(total as u32).to_le_bytes());
    file.extend_from_slice(&(text.len() as u32).to_le_bytes());
    file.extend_from_slice(b"JSON");
    file.extend_from_slice(&text);
    file.extend_from_slice(&(bytes.len() as u32).to_le_bytes());
    file.extend_from_slice(b"BIN\0");
    file.extend_from_slice(bytes);
    Ok(file)
}

//! glTF 2.0 through the `gltf` crate (JSON and accessors only: no images,
//! nothing fetched): every triangle primitive (`TRIANGLES`,
//! `TRIANGLE_STRIP`, `TRIANGLE_FAN`) of every mesh that the scene's nodes
//! place, each posed by its node's transform composed down from the root,
//! into one mesh. Points and lines are skipped. Buffers come from the GLB
//! container, from base64 data URIs, or from files beside the glTF file.

use std::borrow::Cow;
use std::path::Path;

use base64::Engine;
use gltf::mesh::Mode;
use nalgebra::Matrix4;

use super::files::{checked_point, Malformed, Soup};
use crate::input::{read_bytes, MAX_DATA_BYTES};

/// Reads a glTF or GLB file's `bytes`; `path`'s folder holds its buffers.
pub(super) fn read(bytes: &[u8], path: &Path) -> Result<Soup, Malformed> {
    // The `gltf` crate subtracts the header's 12 bytes from the length it
    // states before comparing (an overflow where it states fewer).
    if let Some(stated) = bytes.get(8..12).filter(|_| bytes.starts_with(b"glTF")) {
        let stated = u32::from_le_bytes(stated.try_into().expect("4 bytes"));
        if stated < 12 {
            return Err(Malformed::at(
                "the header",
                format!("it states a length of {stated} bytes, less than its own 12"),
            ));
        }
    }
    let unchecked = gltf::Gltf::from_slice_without_validation(bytes)
        .map_err(|e| Malformed::at("the document", e.to_string()))?;
    check_attribute_accessors(unchecked.document.as_json())?;
    let blob = unchecked.blob;
    let gltf = gltf::Document::from_json(unchecked.document.into_json())
        .map_err(|e| Malformed::at("the document", e.to_string()))?;
    let buffers = gltf
        .buffers()
        .map(|buffer| {
            let place = || format!("buffers[{}]", buffer.index());
            let data: Cow<'_, [u8]> = match buffer.source() {
                gltf::buffer::Source::Bin => Cow::Borrowed(
                    blob.as_deref().ok_or_else(|| Malformed::at(place(), "the GLB has no BIN chunk"))?,
                ),
                gltf::buffer::Source::Uri(uri) => {
                    Cow::Owned(buffer_of_uri(uri, path).map_err(|m| Malformed::at(place(), m))?)
                }
            };
            if data.len() < buffer.length() {
                return Err(Malformed::at(
                    place(),
                    format!("it declares {} bytes but holds {}", buffer.length(), data.len()),
                ));
            }
            Ok(data)
        })
        .collect::<Result<Vec<_>, _>>()?;

    // The meshes the scene places, with their nodes' transforms: the
    // default scene, else the first, else every mesh as it is.
    let mut placed: Vec<(gltf::Mesh<'_>, Matrix4<f64>, String)> = Vec::new();
    match gltf.default_scene().or_else(|| gltf.scenes().next()) {
        Some(scene) => {
            let mut stack: Vec<(gltf::Node<'_>, Matrix4<f64>, usize)> =
                scene.nodes().map(|node| (node, Matrix4::identity(), 0)).collect();
            let node_count = gltf.nodes().len();
            while let Some((node, parent, depth)) = stack.pop() {
                if depth > node_count {
                    return Err(Malformed::at(
                        format!("nodes[{}]", node.index()),
                        "the node hierarchy has a cycle",
                    ));
                }
                let local = node.transform().matrix();
                let world = parent * Matrix4::from_fn(|row, column| f64::from(local[column][row]));
                if let Some(mesh) = node.mesh() {
                    placed.push((mesh, world, format!("nodes[{}]", node.index())));
                }
                stack.extend(node.children().map(|child| (child, world, depth + 1)));
            }
        }
        None => placed.extend(gltf.meshes().map(|mesh| (mesh, Matrix4::identity(), String::new()))),
    }

    let mut soup = Soup { vertices: Vec::new(), triangles: Vec::new(), dropped: 0 };
    for (mesh, world, node) in &placed {
        // A mirroring transform turns the winding; turned back, so that
        // outward faces stay outward.
        let mirrored = world.fixed_view::<3, 3>(0, 0).determinant() < 0.0;
        for primitive in mesh.primitives() {
            let place =
                format!("meshes[{}].primitives[{}]{}", mesh.index(), primitive.index(), at_node(node));
            append_primitive(&primitive, world, mirrored, &buffers, &mut soup)
                .map_err(|message| Malformed::at(place, message))?;
        }
    }
    Ok(soup)
}

/// Every primitive's attributes name accessors that exist. Checked before
/// the `gltf` crate's own validation, which looks up the `POSITION`
/// accessor before it checks that index (and panics on a missing one).
fn check_attribute_accessors(root: &gltf::json::Root) -> Result<(), Malformed> {
    for (m, mesh) in root.meshes.iter().enumerate() {
        for (p, primitive) in mesh.primitives.iter().enumerate() {
            for accessor in primitive.attributes.values().chain(&primitive.indices) {
                if accessor.value() >= root.accessors.len() {
                    return Err(Malformed::at(
                        format!("meshes[{m}].primitives[{p}]"),
                        format!(
                            "accessor {} does not exist (there are {})",
                            accessor.value(),
                            root.accessors.len()
                        ),
                    ));
                }
            }
        }
    }
    Ok(())
}

/// ` (at nodes[i])` where the node is known.
fn at_node(node: &str) -> String {
    if node.is_empty() {
        String::new()
    } else {
        format!(" (at {node})")
    }
}

/// A buffer's bytes from its URI: base64 data, or a file beside `path`.
fn buffer_of_uri(uri: &str, path: &Path) -> Result<Vec<u8>, String> {
    if let Some(data) = uri.strip_prefix("data:") {
        let Some((_, encoded)) = data.split_once(";base64,") else {
            return Err("a data URI that is not base64".into());
        };
        return base64::engine::general_purpose::STANDARD
            .decode(encoded)
            .map_err(|e| format!("its base64 data: {e}"));
    }
    if uri.contains("://") {
        return Err(format!("`{uri}` is not a file beside the glTF file (nothing is fetched)"));
    }
    let file = path.parent().unwrap_or(Path::new("")).join(uri);
    read_bytes(&file, MAX_DATA_BYTES, "glTF buffer").map_err(|e| format!("{}: {e}", file.display()))
}

/// Adds one primitive's triangles, posed by `world`, to `soup`.
fn append_primitive(
    primitive: &gltf::Primitive<'_>,
    world: &Matrix4<f64>,
    mirrored: bool,
    buffers: &[Cow<'_, [u8]>],
    soup: &mut Soup,
) -> Result<(), String> {
    if !matches!(primitive.mode(), Mode::Triangles | Mode::TriangleStrip | Mode::TriangleFan) {
        return Ok(());
    }
    for accessor in primitive.attributes().map(|(_, a)| a).chain(primitive.indices()) {
        if accessor.count() == 0 || accessor.sparse().is_some_and(|s| s.count() == 0) {
            return Err(format!("accessors[{}] has no elements", accessor.index()));
        }
    }
    let reader = primitive.reader(|buffer| buffers.get(buffer.index()).map(|b| b.as_ref()));
    let positions =
        reader.read_positions().ok_or("no POSITION attribute, or its data lies outside its buffer")?;
    let first = soup.vertices.len();
    for (k, p) in positions.enumerate() {
        let local = nalgebra::Point3::new(f64::from(p[0]), f64::from(p[1]), f64::from(p[2]));
        let posed = world.transform_point(&local);
        let point = checked_point([posed.x, posed.y, posed.z], || format!("position {k}"))
            .map_err(|m| format!("{}: {}", m.place, m.message))?;
        soup.vertices.push(point);
    }
    let count = soup.vertices.len() - first;
    let indices: Vec<u32> = match reader.read_indices() {
        Some(indices) => indices.into_u32().collect(),
        None if primitive.indices().is_some() => return Err("its indices lie outside their buffer".into()),
        None => (0..count as u32).collect(),
    };
    if let Some(bad) = indices.iter().find(|&&i| i as usize >= count) {
        return Err(format!("index {bad} is not one of its {count} positions"));
    }
    let corner = |i: usize| first as u32 + indices[i];
    let mut push = |a: usize, b: usize, c: usize| {
        let (b, c) = if mirrored { (c, b) } else { (b, c) };
        soup.triangles.push([corner(a), corner(b), corner(c)]);
    };
    let n = indices.len();
    match primitive.mode() {
        Mode::Triangles => (0..n / 3).for_each(|t| push(3 * t, 3 * t + 1, 3 * t + 2)),
        // Every other triangle of a strip is turned, to keep one winding.
        Mode::TriangleStrip => (0..n.saturating_sub(2)).for_each(|t| {
            if t % 2 == 0 {
                push(t, t + 1, t + 2)
            } else {
                push(t + 1, t, t + 2)
            }
        }),
        _ => (1..n.saturating_sub(1)).for_each(|t| push(0, t, t + 1)),
    }
    Ok(())
}

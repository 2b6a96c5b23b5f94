//! Mesh files as users have them: OBJ, STL (binary and ASCII), PLY (ASCII
//! and binary) and glTF 2.0 (`.gltf` with its buffers, or `.glb`), the
//! format told by the contents ([`MeshFormat::of`]), not the name.
//!
//! Every format but OBJ goes through a maintained crate (`stl_io`,
//! `ply-rs-bw`, `gltf`); the OBJ reader is [`super::obj`]. Coincident
//! vertices (the same coordinates, bit for bit, `-0` as `0`) are welded
//! into one ([`weld`]), in their first appearance's order: STL stores each
//! triangle's corners apart and glTF splits vertices at seams, so without
//! it a closed surface reads as a soup of loose triangles (no volume, no
//! inside). Polygons are fan-triangulated; faces of fewer than three
//! vertices are dropped and counted ([`TriMesh::dropped_faces`]). Errors
//! name the file, the format and the place (line, facet, element or glTF
//! object).

use std::collections::HashMap;
use std::hash::{BuildHasherDefault, Hash, Hasher};
use std::path::{Path, PathBuf};

use super::obj::{parse_obj, ObjError};
use super::trimesh::{MeshError, TriMesh, MAX_COORDINATE};
use crate::input::{read_bytes, text_of, ReadError, MAX_DATA_BYTES};
use crate::math::Point;

/// The format of a mesh file, as told by its contents.
#[non_exhaustive]
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum MeshFormat {
    /// Wavefront OBJ text.
    Obj,
    /// STL of 50-byte records after an 80-byte header and a count.
    BinaryStl,
    /// STL text: `solid`, `facet normal`, `outer loop`, `vertex`.
    AsciiStl,
    /// PLY, ASCII or binary (the header says which).
    Ply,
    /// glTF 2.0 JSON, its buffers embedded (data URIs) or beside it.
    Gltf,
    /// glTF 2.0 binary container.
    Glb,
}

impl std::fmt::Display for MeshFormat {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(match self {
            MeshFormat::Obj => "OBJ",
            MeshFormat::BinaryStl => "binary STL",
            MeshFormat::AsciiStl => "ASCII STL",
            MeshFormat::Ply => "PLY",
            MeshFormat::Gltf => "glTF",
            MeshFormat::Glb => "GLB",
        })
    }
}

impl MeshFormat {
    /// The format of a file's `bytes` (`path` breaks a tie: a file named
    /// `.stl` that is neither STL form is read as binary STL, so that its
    /// error says what its size should be).
    ///
    /// GLB by its magic `glTF`; PLY by its first line `ply`; binary STL by
    /// its size (84 + 50 × the count at byte 80, whatever the header says:
    /// some exporters begin it with `solid`); ASCII STL by a first word
    /// `solid`; glTF JSON by a first character `{`; OBJ otherwise.
    pub fn of(bytes: &[u8], path: &Path) -> MeshFormat {
        let text = bytes.strip_prefix("\u{feff}".as_bytes()).unwrap_or(bytes);
        let start = text.trim_ascii_start();
        if bytes.starts_with(b"glTF") {
            MeshFormat::Glb
        } else if bytes.starts_with(b"ply\n") || bytes.starts_with(b"ply\r\n") {
            MeshFormat::Ply
        } else if super::stl::stated_count(bytes)
            .is_some_and(|n| bytes.len() as u64 == super::stl::binary_size(n))
        {
            MeshFormat::BinaryStl
        } else if start.starts_with(b"solid") && std::str::from_utf8(start).is_ok() {
            MeshFormat::AsciiStl
        } else if start.starts_with(b"{") {
            MeshFormat::Gltf
        } else if path.extension().is_some_and(|e| e.eq_ignore_ascii_case("stl")) {
            MeshFormat::BinaryStl
        } else {
            MeshFormat::Obj
        }
    }
}

/// Why a mesh file could not be read.
#[non_exhaustive]
#[derive(Debug, thiserror::Error)]
pub enum MeshFileError {
    /// The file could not be read.
    #[error("{}: cannot read the mesh file: {source}", path.display())]
    Io {
        /// The file.
        path: PathBuf,
        /// Why.
        source: ReadError,
    },
    /// An OBJ file's error (with its line and column).
    #[error(transparent)]
    Obj(#[from] ObjError),
    /// The file is malformed where `place` says.
    #[error("{}: {format}, {place}: {message}", path.display())]
    Malformed {
        /// The file.
        path: PathBuf,
        /// Its format.
        format: MeshFormat,
        /// Where: a line, a facet, an element or a glTF object.
        place: String,
        /// What is wrong.
        message: String,
    },
    /// The file reads but does not make a usable mesh.
    #[error("{}: {format}: {source}", path.display())]
    Mesh {
        /// The file.
        path: PathBuf,
        /// Its format.
        format: MeshFormat,
        /// Why the mesh is unusable.
        source: MeshError,
    },
}

/// Reads a mesh file of any format [`MeshFormat::of`] knows; glTF buffers
/// named by a relative URI are read from the file's folder.
pub fn load_mesh(path: &Path) -> Result<TriMesh, MeshFileError> {
    let bytes = read_bytes(path, MAX_DATA_BYTES, "mesh file")
        .map_err(|source| MeshFileError::Io { path: path.into(), source })?;
    read_mesh(bytes, path)
}

/// Reads a mesh file's `bytes`; `path` names it in errors and is where a
/// glTF file's relative buffer URIs are resolved from.
pub fn read_mesh(bytes: Vec<u8>, path: &Path) -> Result<TriMesh, MeshFileError> {
    let format = MeshFormat::of(&bytes, path);
    let soup = match format {
        MeshFormat::Obj => {
            let text = text_of(bytes).map_err(|error| match error {
                ReadError::NotUtf8 { line, column } => ObjError::Parse {
                    path: path.into(),
                    line,
                    column,
                    message: "not valid UTF-8 text (not a mesh format that nearmiss reads: OBJ, STL, PLY, glTF or GLB)".into(),
                },
                other => ObjError::Io { path: path.into(), source: other.into_io() },
            })?;
            return Ok(parse_obj(&text, path)?);
        }
        MeshFormat::BinaryStl | MeshFormat::AsciiStl => super::stl::read(bytes, format),
        MeshFormat::Ply => super::ply::read(&bytes),
        MeshFormat::Gltf | MeshFormat::Glb => super::gltf::read(&bytes, path),
    }
    .map_err(|Malformed { place, message }| MeshFileError::Malformed {
        path: path.into(),
        format,
        place,
        message,
    })?;
    let (vertices, triangles) = weld(soup.vertices, soup.triangles);
    let mesh = TriMesh::new(vertices, triangles).map_err(|source| MeshFileError::Mesh {
        path: path.into(),
        format,
        source,
    })?;
    Ok(mesh.with_dropped_faces(soup.dropped))
}

/// What a format's reader gives: vertices (finite, within
/// [`MAX_COORDINATE`]), triangles indexing them, and the faces of fewer than
/// three vertices it dropped.
pub(super) struct Soup {
    pub(super) vertices: Vec<Point>,
    pub(super) triangles: Vec<[u32; 3]>,
    pub(super) dropped: usize,
}

/// A format reader's error: where, and what is wrong.
pub(super) struct Malformed {
    pub(super) place: String,
    pub(super) message: String,
}

impl Malformed {
    pub(super) fn at(place: impl Into<String>, message: impl Into<String>) -> Malformed {
        Malformed { place: place.into(), message: message.into() }
    }
}

/// Checks a vertex read at `place`: finite and within [`MAX_COORDINATE`].
pub(super) fn checked_point(
    coordinates: [f64; 3],
    place: impl FnOnce() -> String,
) -> Result<Point, Malformed> {
    if let Some(c) = coordinates.iter().find(|c| !c.is_finite()) {
        return Err(Malformed::at(place(), format!("a vertex coordinate is {c}, not a finite number")));
    }
    if let Some(c) = coordinates.iter().find(|c| c.abs() > MAX_COORDINATE) {
        return Err(Malformed::at(
            place(),
            format!(
                "the vertex coordinate {c:e} is outside the usable range: |x| ≤ {MAX_COORDINATE:e} (products of coordinates must stay finite)"
            ),
        ));
    }
    Ok(Point::from(coordinates))
}

/// A vertex's coordinates as bits: the key of [`weld`]'s table.
#[derive(PartialEq, Eq)]
struct CoordinateBits([u64; 3]);

impl Hash for CoordinateBits {
    fn hash<H: Hasher>(&self, state: &mut H) {
        self.0.iter().for_each(|&bits| state.write_u64(bits));
    }
}

/// A fast hash of [`CoordinateBits`] (a file's own coordinates, not
/// adversarial input a table must withstand): multiply-rotate per word, then
/// a full avalanche (MurmurHash3's finaliser), so that coordinates that
/// differ in their low mantissa bits alone spread over the table.
#[derive(Default)]
struct CoordinateHasher(u64);

impl Hasher for CoordinateHasher {
    fn write(&mut self, bytes: &[u8]) {
        bytes.iter().for_each(|&b| self.write_u64(b.into()));
    }

    fn write_u64(&mut self, word: u64) {
        self.0 = (self.0.rotate_left(23) ^ word).wrapping_mul(0x9e37_79b9_7f4a_7c15);
    }

    fn finish(&self) -> u64 {
        let mut h = self.0;
        h ^= h >> 33;
        h = h.wrapping_mul(0xff51_afd7_ed55_8ccd);
        h ^= h >> 33;
        h = h.wrapping_mul(0xc4ce_b9fe_1a85_ec53);
        h ^ (h >> 33)
    }
}

/// Welds coincident vertices: those with the same coordinates bit for bit
/// (`-0` taken as `0`) become the first of them. Order is kept, so a file
/// whose vertices are all distinct keeps its numbering. An index out of
/// range is left for [`TriMesh::new`] to report.
pub fn weld(vertices: Vec<Point>, mut triangles: Vec<[u32; 3]>) -> (Vec<Point>, Vec<[u32; 3]>) {
    let key = |p: &Point| CoordinateBits(p.coords.map(|c| if c == 0.0 { 0u64 } else { c.to_bits() }).into());
    // A closed mesh's vertex is a corner of about six triangles, so an STL
    // welds to about a sixth of its corners: a table an eighth as large
    // grows once, and stays in cache better than one sized for every corner.
    let mut first: HashMap<CoordinateBits, u32, BuildHasherDefault<CoordinateHasher>> =
        HashMap::with_capacity_and_hasher(vertices.len() / 8, Default::default());
    let mut welded = Vec::with_capacity(vertices.len());
    let new_index: Vec<u32> = vertices
        .iter()
        .map(|vertex| {
            *first.entry(key(vertex)).or_insert_with(|| {
                welded.push(*vertex);
                (welded.len() - 1) as u32
            })
        })
        .collect();
    if welded.len() == vertices.len() {
        return (vertices, triangles);
    }
    for corner in triangles.iter_mut().flatten() {
        // One beyond the vertices stays beyond the fewer welded ones.
        if let Some(&index) = new_index.get(*corner as usize) {
            *corner = index;
        }
    }
    (welded, triangles)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn weld_joins_equal_coordinates_and_keeps_order() {
        let p = |x: f64, y: f64| Point::new(x, y, 0.0);
        let vertices = vec![p(0.0, 0.0), p(1.0, 0.0), p(0.0, 1.0), p(1.0, 0.0), p(-0.0, 1.0), p(1.0, 1.0)];
        let (welded, triangles) = weld(vertices, vec![[0, 1, 2], [3, 5, 4]]);
        assert_eq!(welded, vec![p(0.0, 0.0), p(1.0, 0.0), p(0.0, 1.0), p(1.0, 1.0)]);
        assert_eq!(triangles, vec![[0, 1, 2], [1, 3, 2]]);
    }

    #[test]
    fn format_is_told_by_contents() {
        let named = |name: &str, bytes: &[u8]| MeshFormat::of(bytes, Path::new(name));
        assert_eq!(named("a.obj", b"glTF\x02\0\0\0"), MeshFormat::Glb);
        assert_eq!(named("a.obj", b"ply\nformat ascii 1.0\n"), MeshFormat::Ply);
        assert_eq!(named("a.obj", b"  solid cube\nfacet normal 0 0 1\n"), MeshFormat::AsciiStl);
        assert_eq!(named("a.obj", b"{\"asset\": {}}"), MeshFormat::Gltf);
        assert_eq!(named("a.stl", b"v 0 0 0\n"), MeshFormat::BinaryStl);
        assert_eq!(named("a.mesh", b"v 0 0 0\n"), MeshFormat::Obj);
        // A binary STL whose header begins with `solid`, as some exporters
        // write it: its size decides.
        let mut binary = b"solid exported".to_vec();
        binary.resize(80, b' ');
        binary.extend_from_slice(&1u32.to_le_bytes());
        binary.resize(134, 0);
        assert_eq!(named("a.obj", &binary), MeshFormat::BinaryStl);
    }
}

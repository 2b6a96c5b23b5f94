//! A Wavefront OBJ reader: `v` and `f` lines (polygons fan-triangulated;
//! `i`, `i/t`, `i//n`, `i/t/n` and negative indices); every other statement
//! is ignored, and so are `f` lines of one or two vertices (a point or a
//! line, as exporters write them: counted, [`TriMesh::dropped_faces`]).
//! Errors name the file, line and column.

use std::path::{Path, PathBuf};

use super::trimesh::{MeshError, TriMesh, MAX_COORDINATE};
use crate::math::Point;

/// Why an OBJ file could not be read as a mesh.
#[non_exhaustive]
#[derive(Debug, thiserror::Error)]
pub enum ObjError {
    /// The file could not be read.
    #[error("{}: cannot read the OBJ file: {source}", path.display())]
    Io {
        /// The file.
        path: PathBuf,
        /// The I/O error.
        source: std::io::Error,
    },
    /// A statement is malformed.
    #[error("{}:{line}:{column}: {message}", path.display())]
    Parse {
        /// The file.
        path: PathBuf,
        /// 1-based line.
        line: usize,
        /// 1-based column.
        column: usize,
        /// What is wrong and what was expected.
        message: String,
    },
    /// The statements parse but do not make a usable mesh.
    #[error("{}: {source}", path.display())]
    Mesh {
        /// The file.
        path: PathBuf,
        /// Why the mesh is unusable.
        source: MeshError,
    },
}

/// Reads an OBJ file.
pub fn load_obj(path: &Path) -> Result<TriMesh, ObjError> {
    let text =
        crate::input::read_text(path, crate::input::MAX_DATA_BYTES, "mesh file").map_err(
            |error| match error {
                crate::input::ReadError::NotUtf8 { line, column } => ObjError::Parse {
                    path: path.into(),
                    line,
                    column,
                    message: "not valid UTF-8 text".into(),
                },
                other => ObjError::Io { path: path.into(), source: other.into_io() },
            },
        )?;
    parse_obj(&text, path)
}

/// The longest part of a bad word quoted in a message, in characters.
const EXCERPT_CHARS: usize = 40;

/// `word` in backticks, or its first [`EXCERPT_CHARS`] characters and its
/// length.
fn excerpt(word: &str) -> String {
    let count = word.chars().count();
    if count <= EXCERPT_CHARS {
        return format!("`{word}`");
    }
    let head: String = word.chars().take(EXCERPT_CHARS).collect();
    format!("`{head}…` ({count} characters)")
}

/// Parses OBJ text; `path` names the source in error messages.
pub fn parse_obj(text: &str, path: &Path) -> Result<TriMesh, ObjError> {
    let error = |line: usize, column: usize, message: String| ObjError::Parse {
        path: path.into(),
        line,
        column,
        message,
    };
    let mut vertices: Vec<Point> = Vec::new();
    let mut triangles: Vec<[u32; 3]> = Vec::new();
    // Where each triangle came from, to report mesh errors at their line.
    let mut origins: Vec<(usize, usize)> = Vec::new();
    let mut dropped_faces = 0;
    for (number, raw) in text.lines().enumerate() {
        let line = number + 1;
        let content = raw.split('#').next().unwrap_or("");
        let mut words = tokens(content);
        let Some((_, keyword)) = words.next() else { continue };
        match keyword {
            "v" => {
                let vertex = vertex_of(words, raw.len()).map_err(|(column, m)| error(line, column, m))?;
                vertices.push(vertex);
            }
            "f" => {
                let corners = face_of(words, vertices.len()).map_err(|(column, m)| error(line, column, m))?;
                if corners.len() < 3 {
                    dropped_faces += 1;
                    continue;
                }
                for k in 1..corners.len() - 1 {
                    triangles.push([corners[0], corners[k], corners[k + 1]]);
                    origins.push((line, 1));
                }
            }
            _ => {}
        }
    }
    // OBJ shares vertices by its format, but exporters repeat positions
    // at texture seams: welded as every mesh file is.
    let defined = vertices.len();
    let (vertices, triangles) = super::files::weld(vertices, triangles);
    let mesh = TriMesh::new(vertices, triangles).map_err(|source| match source {
        MeshError::IndexOutOfRange { triangle, index, .. } => {
            let (line, column) = origins[triangle];
            let message =
                format!("the face refers to vertex {}, but the file defines {defined} vertices", index + 1);
            error(line, column, message)
        }
        MeshError::Empty if dropped_faces > 0 => error(
            text.lines().count().max(1),
            1,
            format!("the file has no faces of 3 or more vertices (`f` lines; {dropped_faces} of 1 or 2 were skipped)"),
        ),
        MeshError::Empty => error(text.lines().count().max(1), 1, "the file has no faces (`f` lines)".into()),
        MeshError::NonFinite { .. } | MeshError::OutOfRange { .. } | MeshError::NotClosed(_) => {
            ObjError::Mesh { path: path.into(), source }
        }
    })?;
    Ok(mesh.with_dropped_faces(dropped_faces))
}

/// A `v` line's vertex from its words after the keyword (`end`: the
/// line's length, where a missing coordinate is reported); an error is its
/// column and message. An optional fourth value (w) or vertex colours may
/// follow.
fn vertex_of<'a>(
    mut words: impl Iterator<Item = (usize, &'a str)>,
    end: usize,
) -> Result<Point, (usize, String)> {
    let mut coordinates = [0.0; 3];
    for (k, coordinate) in coordinates.iter_mut().enumerate() {
        let Some((column, word)) = words.next() else {
            return Err((end + 1, format!("a vertex needs 3 coordinates, found {k}")));
        };
        *coordinate = match word.parse::<f64>() {
            Ok(value) if value.abs() <= MAX_COORDINATE => value,
            Ok(value) if value.is_finite() => {
                return Err((
                    column,
                    format!(
                        "{} is outside the usable range: |x| ≤ {MAX_COORDINATE:e} (products of coordinates must stay finite)",
                        excerpt(word)
                    ),
                ))
            }
            _ => return Err((column, format!("expected a finite number, found {}", excerpt(word)))),
        };
    }
    Ok(Point::from(coordinates))
}

/// An `f` line's corners (0-based vertex indices, negative ones counted
/// back from the `defined` vertices) from its words after the keyword; an
/// error is its column and message.
fn face_of<'a>(
    words: impl Iterator<Item = (usize, &'a str)>,
    defined: usize,
) -> Result<Vec<u32>, (usize, String)> {
    let mut corners = Vec::new();
    for (column, word) in words {
        let index_text = word.split('/').next().unwrap_or("");
        let index = match index_text.parse::<i64>() {
            Ok(i) if i > 0 => i - 1,
            Ok(i) if i < 0 => defined as i64 + i,
            _ => {
                return Err((
                    column,
                    format!("expected a vertex index (1-based, or negative), found {}", excerpt(word)),
                ))
            }
        };
        if index < 0 || index > u32::MAX as i64 {
            return Err((column, format!("vertex index {} is out of range", excerpt(word))));
        }
        corners.push(index as u32);
    }
    Ok(corners)
}

/// The whitespace-separated words of a line with their 1-based columns.
fn tokens(line: &str) -> impl Iterator<Item = (usize, &str)> {
    line.split_ascii_whitespace().map(move |word| (word.as_ptr() as usize - line.as_ptr() as usize + 1, word))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn parse(text: &str) -> Result<TriMesh, ObjError> {
        parse_obj(text, Path::new("test.obj"))
    }

    #[test]
    fn reads_polygons_and_index_forms() {
        let mesh = parse("# a quad\nv 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nvn 0 0 1\nf 1//1 2//1 3//1 -1//1\n")
            .unwrap();
        assert_eq!(mesh.triangles().len(), 2);
        assert_eq!(mesh.vertices().len(), 4);
    }

    /// Exporters write zero-area faces and `f` lines of two vertices (a
    /// line); coal and trimesh take such files, and so does the reader:
    /// the zero-area face is kept, the short faces are dropped, each counted.
    #[test]
    fn keeps_zero_area_faces_and_drops_short_ones_with_counts() {
        let text = "v 0 0 0\nv 1 0 0\nv 2 0 0\nv 0 1 0\nf 1 2 3\nf 1 2 4\nf 2 4\nf 3\nl 1 2\n";
        let mesh = parse(text).unwrap();
        assert_eq!(mesh.triangles().len(), 2);
        assert_eq!(mesh.zero_area_triangles(), 1);
        assert_eq!(mesh.dropped_faces(), 2);
    }

    #[test]
    fn errors_name_line_and_column() {
        let message = parse("v 0 0 0\nv 1 0 zero\n").unwrap_err().to_string();
        assert_eq!(message, "test.obj:2:7: expected a finite number, found `zero`");
        let message = parse("v 0 0 0\nv 1 0 0\nf 1 2\nf 1\n").unwrap_err().to_string();
        assert_eq!(
            message,
            "test.obj:4:1: the file has no faces of 3 or more vertices (`f` lines; 2 of 1 or 2 were skipped)"
        );
        let message = parse("v 0 0 0\nf 1 2 9\n").unwrap_err().to_string();
        assert_eq!(message, "test.obj:2:1: the face refers to vertex 2, but the file defines 1 vertices");
        let message = parse("v 0 0 0\nf 1 0 2\n").unwrap_err().to_string();
        assert_eq!(message, "test.obj:2:5: expected a vertex index (1-based, or negative), found `0`");
        let message = parse("v 0 0 0\n").unwrap_err().to_string();
        assert_eq!(message, "test.obj:1:1: the file has no faces (`f` lines)");
    }
}

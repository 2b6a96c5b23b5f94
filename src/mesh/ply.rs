//! PLY through `ply-rs-bw`, ASCII or binary of either byte order: the
//! `vertex` element's `x`, `y`, `z` (any numeric type) and the `face`
//! element's `vertex_indices` (or `vertex_index`) lists, fan-triangulated.
//! Every other element and property is read past.

use std::io::Cursor;

use ply_rs_bw::parser::Parser;
use ply_rs_bw::ply::{Property, PropertyAccess, PropertyAccessResult};

use super::files::{checked_point, Malformed, Soup};

/// The properties of one element that a mesh needs, whatever element it is.
#[derive(Default)]
struct Element {
    /// `x`, `y`, `z`, as found.
    coordinates: [Option<f64>; 3],
    /// A face's corners.
    corners: Option<Result<Vec<i64>, &'static str>>,
}

/// A scalar property as f64; lists and nothing else are `None`.
fn scalar(property: &Property) -> Option<f64> {
    Some(match *property {
        Property::Char(v) => v.into(),
        Property::UChar(v) => v.into(),
        Property::Short(v) => v.into(),
        Property::UShort(v) => v.into(),
        Property::Int(v) => v.into(),
        Property::UInt(v) => v.into(),
        Property::Float(v) => v.into(),
        Property::Double(v) => v,
        _ => return None,
    })
}

/// An integer list property as i64; float lists are refused.
fn index_list(property: Property) -> Result<Vec<i64>, &'static str> {
    fn widen<T: Into<i64>>(list: Vec<T>) -> Vec<i64> {
        list.into_iter().map(Into::into).collect()
    }
    Ok(match property {
        Property::ListChar(list) => widen(list),
        Property::ListUChar(list) => widen(list),
        Property::ListShort(list) => widen(list),
        Property::ListUShort(list) => widen(list),
        Property::ListInt(list) => widen(list),
        Property::ListUInt(list) => widen(list),
        _ => return Err("the face's vertex indices are not a list of integers"),
    })
}

impl PropertyAccess for Element {
    fn new() -> Self {
        Element::default()
    }

    fn set_property(&mut self, name: &str, property: Property) -> PropertyAccessResult {
        let axis = match name {
            "x" => 0,
            "y" => 1,
            "z" => 2,
            "vertex_indices" | "vertex_index" => {
                self.corners = Some(index_list(property));
                return PropertyAccessResult::Set;
            }
            _ => return PropertyAccessResult::Ignored,
        };
        self.coordinates[axis] = scalar(&property);
        PropertyAccessResult::Set
    }
}

/// Reads a PLY file's `bytes`.
pub(super) fn read(bytes: &[u8]) -> Result<Soup, Malformed> {
    let ply = Parser::<Element>::new().read_ply(&mut Cursor::new(bytes)).map_err(|e| match e.line() {
        Some(line) => {
            Malformed::at(format!("line {line}"), e.to_string().replacen(&format!("Line {line}: "), "", 1))
        }
        None => Malformed::at("the data", e.to_string()),
    })?;
    let elements = |name: &str| ply.payload.get(name).map(Vec::as_slice).unwrap_or_default();
    let mut vertices = Vec::with_capacity(elements("vertex").len());
    for (v, element) in elements("vertex").iter().enumerate() {
        let place = || format!("vertex {}", v + 1);
        let mut coordinates = [0.0; 3];
        for (axis, (found, out)) in element.coordinates.iter().zip(&mut coordinates).enumerate() {
            *out = found.ok_or_else(|| {
                Malformed::at(place(), format!("no numeric property `{}`", ["x", "y", "z"][axis]))
            })?;
        }
        vertices.push(checked_point(coordinates, place)?);
    }
    let faces = elements("face");
    if faces.is_empty() {
        return Err(Malformed::at(
            "the header",
            "no `face` element with faces (a point cloud is not a surface)",
        ));
    }
    let mut triangles = Vec::with_capacity(faces.len());
    let mut dropped = 0;
    for (f, face) in faces.iter().enumerate() {
        let place = || format!("face {}", f + 1);
        let corners = match &face.corners {
            None => return Err(Malformed::at(place(), "no `vertex_indices` list")),
            Some(Err(message)) => return Err(Malformed::at(place(), *message)),
            Some(Ok(corners)) => corners,
        };
        let mut checked = Vec::with_capacity(corners.len());
        for &index in corners {
            match u32::try_from(index) {
                Ok(i) if (i as usize) < vertices.len() => checked.push(i),
                _ => {
                    return Err(Malformed::at(
                        place(),
                        format!(
                            "vertex index {index} is not one of the {} vertices (0-based)",
                            vertices.len()
                        ),
                    ))
                }
            }
        }
        if checked.len() < 3 {
            dropped += 1;
            continue;
        }
        for k in 1..checked.len() - 1 {
            triangles.push([checked[0], checked[k], checked[k + 1]]);
        }
    }
    Ok(Soup { vertices, triangles, dropped })
}

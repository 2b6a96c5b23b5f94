//! The `Mesh` class: a validated triangle mesh, from arrays or a file.

use std::sync::Arc;

use crate::args::*;
use nearmiss::mesh::TriMesh;
use numpy::ndarray::Array2;
use numpy::{IntoPyArray, PyArray2, PyReadonlyArrayDyn, PyUntypedArrayMethods};
use pyo3::exceptions::{PyTypeError, PyValueError};
use pyo3::prelude::*;

/// `value` as a contiguous numpy array of `dtype`, if its numbers are of
/// one of the numpy kinds `kinds` (`TypeError` naming `name` if not).
pub(crate) fn converted<'py>(
    value: &Bound<'py, PyAny>,
    name: &str,
    kinds: &str,
    dtype: &str,
) -> PyResult<Bound<'py, PyAny>> {
    let numpy = value.py().import("numpy")?;
    let array = numpy.call_method1("asarray", (value,))?;
    let kind: String = array.getattr("dtype")?.getattr("kind")?.extract()?;
    if !kinds.contains(kind.as_str()) {
        let found = array.getattr("dtype")?.str()?.to_string();
        return Err(PyTypeError::new_err(format!(
            "{name}: expected numbers of dtype {dtype}, got dtype {found}"
        )));
    }
    if dtype == "int64" && kind == "u" && array.getattr("size")?.extract::<usize>()? > 0 {
        let too_large: bool = array.call_method0("max")?.gt(i64::MAX)?;
        if too_large {
            return Err(PyValueError::new_err(format!(
                "{name}: an index is larger than any vertex index can be"
            )));
        }
    }
    numpy.call_method1("ascontiguousarray", (array, dtype))
}

/// A triangle mesh (validated, with its bounding-volume tree).
#[pyclass(frozen, module = "nearmiss._nearmiss")]
pub(crate) struct Mesh {
    pub(crate) inner: Arc<TriMesh>,
}

#[pymethods]
impl Mesh {
    /// A mesh of `vertices` (V, 3) and `faces` (F, 3) vertex indices.
    /// Faces of zero area (repeated or collinear vertices) are kept and
    /// take part as the segments or points they span
    /// (`zero_area_triangles` counts them).
    #[new]
    pub(crate) fn new(vertices: &Bound<'_, PyAny>, faces: &Bound<'_, PyAny>) -> PyResult<Mesh> {
        let vertices = converted(vertices, "vertices", "biuf", "float64")?;
        let faces = converted(faces, "faces", "iu", "int64")?;
        let vertices: PyReadonlyArrayDyn<'_, f64> = vertices.extract()?;
        let faces: PyReadonlyArrayDyn<'_, i64> = faces.extract()?;
        let vertices = points("vertices", &vertices)?;
        let shape = faces.shape();
        if shape.len() != 2 || shape[1] != 3 {
            return Err(PyValueError::new_err(format!(
                "faces: expected an array of shape (F, 3), got shape {}",
                shape_text(shape)
            )));
        }
        let indices: Vec<i64> = faces.as_array().iter().copied().collect();
        let mut triangles = Vec::with_capacity(shape[0]);
        for f in 0..shape[0] {
            let mut triangle = [0u32; 3];
            for k in 0..3 {
                let index = indices[3 * f + k];
                triangle[k] = u32::try_from(index).map_err(|_| {
                    PyValueError::new_err(format!(
                        "faces: element [{f}, {k}] is {index}, not a vertex index (there are {} vertices)",
                        vertices.len()
                    ))
                })?;
            }
            triangles.push(triangle);
        }
        let mesh =
            TriMesh::new(vertices, triangles).map_err(|e| PyValueError::new_err(format!("mesh: {e}")))?;
        Ok(Mesh { inner: Arc::new(mesh) })
    }

    /// A mesh read from a file: OBJ, STL (binary or ASCII), PLY (ASCII or
    /// binary) or glTF 2.0 (`.gltf` with its buffers, or `.glb`: every
    /// triangle primitive the scene places, node transforms applied), the
    /// format told by the contents. Coincident vertices are welded (STL
    /// stores each triangle's corners apart), faces of zero area kept,
    /// faces of one or two vertices dropped (`dropped_faces`). Errors name
    /// the file, the format and the place.
    #[staticmethod]
    pub(crate) fn from_file(path: std::path::PathBuf) -> PyResult<Mesh> {
        let mesh = nearmiss::mesh::load_mesh(&path).map_err(|e| PyValueError::new_err(e.to_string()))?;
        Ok(Mesh { inner: Arc::new(mesh) })
    }

    /// `Mesh.from_file`, by its name of the OBJ-only days.
    #[staticmethod]
    pub(crate) fn from_obj(path: std::path::PathBuf) -> PyResult<Mesh> {
        Mesh::from_file(path)
    }

    /// The vertices, (V, 3).
    #[getter]
    pub(crate) fn vertices<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray2<f64>> {
        rows(py, self.inner.vertices().to_vec())
    }

    /// The faces, (F, 3) vertex indices.
    #[getter]
    pub(crate) fn faces<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray2<i64>> {
        let flat: Vec<i64> = self.inner.triangles().iter().flat_map(|t| t.map(i64::from)).collect();
        Array2::from_shape_vec((self.inner.triangles().len(), 3), flat).expect("rows of 3").into_pyarray(py)
    }

    /// The radius of the smallest origin-centred ball holding the vertices.
    #[getter]
    pub(crate) fn radius(&self) -> f64 {
        self.inner.radius()
    }

    /// Triangles of exactly zero area, kept: each takes part as the
    /// segment or point it spans.
    #[getter]
    pub(crate) fn zero_area_triangles(&self) -> usize {
        self.inner.zero_area_triangles()
    }

    /// Faces of fewer than three vertices that the file's reader dropped
    /// (0 for a mesh made from arrays).
    #[getter]
    pub(crate) fn dropped_faces(&self) -> usize {
        self.inner.dropped_faces()
    }

    /// The same mesh in the frame whose origin is its point `about`
    /// (vertices minus `about`; the triangles in the same order), for a body
    /// that turns about that point (`motion_between`).
    pub(crate) fn pivoted(&self, about: numpy::PyReadonlyArrayDyn<'_, f64>) -> PyResult<Mesh> {
        let about = crate::args::point("about", &about)?;
        let moved = self.inner.pivoted(&about).map_err(|e| PyValueError::new_err(format!("about: {e}")))?;
        Ok(Mesh { inner: Arc::new(moved) })
    }

    pub(crate) fn __len__(&self) -> usize {
        self.inner.triangles().len()
    }

    pub(crate) fn __repr__(&self) -> String {
        let mut notes = String::new();
        if self.inner.zero_area_triangles() > 0 {
            notes += &format!(", {} of zero area", self.inner.zero_area_triangles());
        }
        if self.inner.dropped_faces() > 0 {
            notes += &format!(", {} short faces dropped", self.inner.dropped_faces());
        }
        format!(
            "Mesh({} vertices, {} triangles{notes}, radius {})",
            self.inner.vertices().len(),
            self.inner.triangles().len(),
            self.inner.radius()
        )
    }
}

//! `nearmiss._nearmiss`: the library's queries on numpy arrays, for the
//! Python package `nearmiss` (python/nearmiss/, which adds the types,
//! docstrings and argument forms; call that, not this).
//!
//! Every array argument is checked here, whatever called: its shape, and
//! that every number is finite; a bad one raises `ValueError` naming the
//! argument and the element (never a panic, never a silent NaN). Queries
//! that may take long run without the GIL; batches run on all cores.

use std::borrow::Cow;
use std::sync::Arc;

use nearmiss::ccd::{
    closest_approach, ApproachStatus, CcdOptions, CcdStatus, ClosestApproachQuery, ContactRule, MeshCcdQuery,
    MeshCcdScratch, MovingMesh, WarmStart,
};
use nearmiss::kernels::batch::TrianglesSoa;
use nearmiss::kernels::{self, Feature, PointEdgeFormula};
use nearmiss::math::{Point, Pose, Triangle, Vector};
use nearmiss::mesh::{
    mesh_distance, mesh_intersection, signed_distance, DistanceKernel, DistanceSearch, MeshDistance,
    MeshIntersection, Overlap, TriMesh,
};
use nearmiss::motion::StepMotion;
use nearmiss::scene::Scene;
use numpy::ndarray::Array2;
use numpy::{IntoPyArray, PyArray1, PyArray2, PyReadonlyArrayDyn, PyUntypedArrayMethods};
use pyo3::create_exception;
use pyo3::exceptions::{PyRuntimeError, PyTypeError, PyValueError};
use pyo3::prelude::*;
use rayon::prelude::*;

create_exception!(
    _nearmiss,
    SceneError,
    PyValueError,
    "A scene file that cannot be read or is not valid (the message names the file, line and column or field)."
);

/// How far a rotation argument may be from one: a quaternion's norm from 1,
/// a matrix's `MᵀM` from the identity (largest entry): `1e-9`, room for
/// the rounding of a rotation computed in float64 and written out, far
/// below a mistake (a quaternion is then normalised, a matrix taken as
/// its nearest rotation).
const ROTATION_TOLERANCE: f64 = 1e-9;

/// Pairs per parallel task of the batched queries.
const BATCH_CHUNK: usize = 1024;

/// The shape of `array` as Python writes it: `(3, 3)`.
fn shape_text(shape: &[usize]) -> String {
    match shape {
        [n] => format!("({n},)"),
        _ => format!("({})", shape.iter().map(|n| n.to_string()).collect::<Vec<_>>().join(", ")),
    }
}

/// `array`'s numbers, checked: its trailing dimensions are `tail`, every
/// number finite. Returns the leading count (1 when `leading` is false)
/// and the numbers in row-major order (borrowed when the array is
/// contiguous, as the package passes it).
fn checked<'a>(
    name: &str,
    array: &'a PyReadonlyArrayDyn<'_, f64>,
    leading: bool,
    tail: &[usize],
) -> PyResult<(usize, Cow<'a, [f64]>)> {
    let numbers = Numbers::of(name, array, leading, tail)?;
    numbers.finite().map_err(PyValueError::new_err)?;
    Ok((numbers.count, numbers.values))
}

/// An array argument whose shape was checked (its numbers not yet).
struct Numbers<'a> {
    name: String,
    shape: Vec<usize>,
    /// The leading count (1 for a single item).
    count: usize,
    /// Row-major.
    values: Cow<'a, [f64]>,
}

impl<'a> Numbers<'a> {
    /// `array`, if its trailing dimensions are `tail` (after one leading
    /// dimension if `leading`).
    fn of(
        name: &str,
        array: &'a PyReadonlyArrayDyn<'_, f64>,
        leading: bool,
        tail: &[usize],
    ) -> PyResult<Numbers<'a>> {
        let shape = array.shape();
        let expected = if leading { 1 + tail.len() } else { tail.len() };
        if shape.len() != expected || shape[shape.len() - tail.len()..] != *tail {
            let dims: Vec<String> = tail.iter().map(|n| n.to_string()).collect();
            let wanted = if leading { format!("(N, {})", dims.join(", ")) } else { shape_text(tail) };
            return Err(PyValueError::new_err(format!(
                "{name}: expected an array of shape {wanted}, got shape {}",
                shape_text(shape)
            )));
        }
        let values: Cow<'a, [f64]> = match array.as_slice() {
            Ok(slice) => Cow::Borrowed(slice),
            Err(_) => Cow::Owned(array.as_array().iter().copied().collect()),
        };
        Ok(Numbers {
            name: name.to_string(),
            shape: shape.to_vec(),
            count: if leading { shape[0] } else { 1 },
            values,
        })
    }

    /// Every number finite, or the message naming the first that is not.
    fn finite(&self) -> Result<(), String> {
        let Some(flat) = self.values.iter().position(|v| !v.is_finite()) else { return Ok(()) };
        // The element's index, from the row-major position.
        let mut index = vec![0; self.shape.len()];
        let mut rest = flat;
        for (k, n) in self.shape.iter().enumerate().rev() {
            (index[k], rest) = (rest % n, rest / n);
        }
        let index: Vec<String> = index.iter().map(|i| i.to_string()).collect();
        Err(format!(
            "{}: element [{}] is {}, not a finite number",
            self.name,
            index.join(", "),
            self.values[flat]
        ))
    }

    /// The (N, 3, 3) batch as triangles, checked finite (no GIL needed).
    fn triangles(&self) -> Result<Vec<Triangle>, String> {
        self.finite()?;
        Ok((0..self.count).map(|i| [0, 1, 2].map(|k| point_at(&self.values, 3 * i + k))).collect())
    }

    /// The (N, 3) batch as points, checked finite (no GIL needed).
    fn points(&self) -> Result<Vec<Point>, String> {
        self.finite()?;
        Ok((0..self.count).map(|i| point_at(&self.values, i)).collect())
    }
}

fn point_at(v: &[f64], k: usize) -> Point {
    Point::new(v[3 * k], v[3 * k + 1], v[3 * k + 2])
}

fn point(name: &str, array: &PyReadonlyArrayDyn<'_, f64>) -> PyResult<Point> {
    let (_, v) = checked(name, array, false, &[3])?;
    Ok(point_at(&v, 0))
}

fn vector(name: &str, array: &PyReadonlyArrayDyn<'_, f64>) -> PyResult<Vector> {
    Ok(point(name, array)?.coords)
}

fn triangle(name: &str, array: &PyReadonlyArrayDyn<'_, f64>) -> PyResult<Triangle> {
    let (_, v) = checked(name, array, false, &[3, 3])?;
    Ok([0, 1, 2].map(|k| point_at(&v, k)))
}

fn points(name: &str, array: &PyReadonlyArrayDyn<'_, f64>) -> PyResult<Vec<Point>> {
    Numbers::of(name, array, true, &[3])?.points().map_err(PyValueError::new_err)
}

/// Two batch arguments of one length.
fn same_length(names: (&str, &str), lengths: (usize, usize)) -> PyResult<()> {
    if lengths.0 == lengths.1 {
        Ok(())
    } else {
        Err(PyValueError::new_err(format!(
            "{} and {} must hold as many items: {} and {}",
            names.0, names.1, lengths.0, lengths.1
        )))
    }
}

/// A point–edge formula by name.
fn formula(name: &str) -> PyResult<PointEdgeFormula> {
    match name {
        "vector" => Ok(PointEdgeFormula::Vector),
        "plain_vector" => Ok(PointEdgeFormula::PlainVector),
        "heron" => Ok(PointEdgeFormula::Heron),
        "stable_heron" => Ok(PointEdgeFormula::StableHeron),
        _ => Err(PyValueError::new_err(format!(
            "formula: {name:?} is not one of \"vector\", \"plain_vector\", \"heron\", \"stable_heron\""
        ))),
    }
}

/// A distance kernel by name: `exact`, or `dyop_<formula>`.
fn kernel(name: &str) -> PyResult<DistanceKernel> {
    match name {
        "exact" => Ok(DistanceKernel::Exact),
        _ => match name.strip_prefix("dyop_").map(formula) {
            Some(Ok(f)) => Ok(DistanceKernel::Dyop(f)),
            _ => Err(PyValueError::new_err(format!(
                "kernel: {name:?} is not \"exact\" or \"dyop_vector\", \"dyop_heron\", \"dyop_stable_heron\", \"dyop_plain_vector\""
            ))),
        },
    }
}

/// A feature as a small code: vertex `i` is `i`, edge `i` is `3 + i`, the
/// face `6` (`nearmiss.FEATURES` names them).
fn feature_code(feature: Feature) -> i8 {
    match feature {
        Feature::Vertex(i) => i as i8,
        Feature::Edge(i) => 3 + i as i8,
        Feature::Face => 6,
    }
}

fn array3<'py>(py: Python<'py>, p: &Point) -> Bound<'py, PyArray1<f64>> {
    PyArray1::from_vec(py, vec![p.x, p.y, p.z])
}

fn rows<'py>(py: Python<'py>, points: Vec<Point>) -> Bound<'py, PyArray2<f64>> {
    let n = points.len();
    let flat: Vec<f64> = points.iter().flat_map(|p| [p.x, p.y, p.z]).collect();
    Array2::from_shape_vec((n, 3), flat).expect("n rows of 3").into_pyarray(py)
}

/// `(distance, point_a, point_b, feature_a, feature_b, within_range)` of
/// two triangles.
#[allow(clippy::type_complexity)]
#[pyfunction]
fn triangle_distance<'py>(
    py: Python<'py>,
    a: PyReadonlyArrayDyn<'py, f64>,
    b: PyReadonlyArrayDyn<'py, f64>,
) -> PyResult<(f64, Bound<'py, PyArray1<f64>>, Bound<'py, PyArray1<f64>>, String, String, bool)> {
    let (ta, tb) = (triangle("a", &a)?, triangle("b", &b)?);
    let d = kernels::triangle_distance(&ta, &tb);
    Ok((
        d.distance,
        array3(py, &d.point_a),
        array3(py, &d.point_b),
        d.feature_a.to_string(),
        d.feature_b.to_string(),
        d.within_range,
    ))
}

/// The distances of `a[i]` and `b[i]` (the vectorised kernel), on all
/// cores without the GIL.
#[pyfunction]
fn triangle_distances<'py>(
    py: Python<'py>,
    a: PyReadonlyArrayDyn<'py, f64>,
    b: PyReadonlyArrayDyn<'py, f64>,
) -> PyResult<Bound<'py, PyArray1<f64>>> {
    let (a, b) = (Numbers::of("a", &a, true, &[3, 3])?, Numbers::of("b", &b, true, &[3, 3])?);
    same_length(("a", "b"), (a.count, b.count))?;
    let out = py.detach(|| -> Result<Vec<f64>, String> {
        a.finite()?;
        b.finite()?;
        // Each task converts its own chunk (the arrays stay borrowed).
        let chunk = |numbers: &Numbers<'_>, start: usize, len: usize| -> TrianglesSoa {
            let triangles: Vec<Triangle> = (start..start + len)
                .map(|i| [0, 1, 2].map(|k| point_at(&numbers.values, 3 * i + k)))
                .collect();
            TrianglesSoa::from_triangles(&triangles)
        };
        let mut out = vec![0.0; a.count];
        out.par_chunks_mut(BATCH_CHUNK).enumerate().for_each(|(k, out)| {
            let start = k * BATCH_CHUNK;
            kernels::batch::triangle_distances(
                &chunk(&a, start, out.len()),
                &chunk(&b, start, out.len()),
                out,
            )
        });
        Ok(out)
    });
    Ok(PyArray1::from_vec(py, out.map_err(PyValueError::new_err)?))
}

/// Closest points and features of `a[i]` and `b[i]` (the scalar kernel),
/// on all cores without the GIL: `(distance, point_a, point_b, feature_a,
/// feature_b)` as arrays.
#[allow(clippy::type_complexity)]
#[pyfunction]
fn triangle_closest_points<'py>(
    py: Python<'py>,
    a: PyReadonlyArrayDyn<'py, f64>,
    b: PyReadonlyArrayDyn<'py, f64>,
) -> PyResult<(
    Bound<'py, PyArray1<f64>>,
    Bound<'py, PyArray2<f64>>,
    Bound<'py, PyArray2<f64>>,
    Bound<'py, PyArray1<i8>>,
    Bound<'py, PyArray1<i8>>,
)> {
    let (a, b) = (Numbers::of("a", &a, true, &[3, 3])?, Numbers::of("b", &b, true, &[3, 3])?);
    same_length(("a", "b"), (a.count, b.count))?;
    let found = py.detach(|| -> Result<Vec<kernels::TriangleDistance>, String> {
        let (ta, tb) = (a.triangles()?, b.triangles()?);
        Ok(ta.par_iter().zip(&tb).map(|(x, y)| kernels::triangle_distance(x, y)).collect())
    });
    let found = found.map_err(PyValueError::new_err)?;
    Ok((
        PyArray1::from_vec(py, found.iter().map(|d| d.distance).collect()),
        rows(py, found.iter().map(|d| d.point_a).collect()),
        rows(py, found.iter().map(|d| d.point_b).collect()),
        PyArray1::from_vec(py, found.iter().map(|d| feature_code(d.feature_a)).collect()),
        PyArray1::from_vec(py, found.iter().map(|d| feature_code(d.feature_b)).collect()),
    ))
}

/// The distance from `p` to the segment `a`–`b` by `formula`.
#[pyfunction]
fn point_segment_distance(
    p: PyReadonlyArrayDyn<'_, f64>,
    a: PyReadonlyArrayDyn<'_, f64>,
    b: PyReadonlyArrayDyn<'_, f64>,
    formula: &str,
) -> PyResult<f64> {
    let f = self::formula(formula)?;
    Ok(kernels::point_segment_distance(&point("p", &p)?, &point("a", &a)?, &point("b", &b)?, f))
}

/// The distances from `p[i]` to the segments `a[i]`–`b[i]`, on all cores.
#[pyfunction]
fn point_segment_distances<'py>(
    py: Python<'py>,
    p: PyReadonlyArrayDyn<'py, f64>,
    a: PyReadonlyArrayDyn<'py, f64>,
    b: PyReadonlyArrayDyn<'py, f64>,
    formula: &str,
) -> PyResult<Bound<'py, PyArray1<f64>>> {
    let f = self::formula(formula)?;
    let p = Numbers::of("p", &p, true, &[3])?;
    let a = Numbers::of("a", &a, true, &[3])?;
    let b = Numbers::of("b", &b, true, &[3])?;
    same_length(("p", "a"), (p.count, a.count))?;
    same_length(("p", "b"), (p.count, b.count))?;
    let out = py.detach(|| -> Result<Vec<f64>, String> {
        let (p, a, b) = (p.points()?, a.points()?, b.points()?);
        Ok((0..p.len())
            .into_par_iter()
            .map(|i| kernels::point_segment_distance(&p[i], &a[i], &b[i], f))
            .collect())
    });
    let out = out.map_err(PyValueError::new_err)?;
    Ok(PyArray1::from_vec(py, out))
}

/// The seed paper's DyOP distance of two triangles by `formula`.
#[pyfunction]
fn dyop_distance(
    a: PyReadonlyArrayDyn<'_, f64>,
    b: PyReadonlyArrayDyn<'_, f64>,
    formula: &str,
) -> PyResult<f64> {
    let f = self::formula(formula)?;
    Ok(kernels::dyop_distance(&triangle("a", &a)?, &triangle("b", &b)?, f))
}

/// `value` as a contiguous numpy array of `dtype`, if its numbers are of
/// one of the numpy kinds `kinds` (`TypeError` naming `name` if not).
fn converted<'py>(
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
struct Mesh {
    inner: Arc<TriMesh>,
}

#[pymethods]
impl Mesh {
    /// A mesh of `vertices` (V, 3) and `faces` (F, 3) vertex indices.
    #[new]
    fn new(vertices: &Bound<'_, PyAny>, faces: &Bound<'_, PyAny>) -> PyResult<Mesh> {
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

    /// A mesh read from a Wavefront OBJ file.
    #[staticmethod]
    fn from_obj(path: std::path::PathBuf) -> PyResult<Mesh> {
        let mesh = nearmiss::mesh::load_obj(&path).map_err(|e| PyValueError::new_err(e.to_string()))?;
        Ok(Mesh { inner: Arc::new(mesh) })
    }

    /// The vertices, (V, 3).
    #[getter]
    fn vertices<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray2<f64>> {
        rows(py, self.inner.vertices().to_vec())
    }

    /// The faces, (F, 3) vertex indices.
    #[getter]
    fn faces<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray2<i64>> {
        let flat: Vec<i64> = self.inner.triangles().iter().flat_map(|t| t.map(i64::from)).collect();
        Array2::from_shape_vec((self.inner.triangles().len(), 3), flat).expect("rows of 3").into_pyarray(py)
    }

    /// The radius of the smallest origin-centred ball holding the vertices.
    #[getter]
    fn radius(&self) -> f64 {
        self.inner.radius()
    }

    fn __len__(&self) -> usize {
        self.inner.triangles().len()
    }

    fn __repr__(&self) -> String {
        format!(
            "Mesh({} vertices, {} triangles, radius {})",
            self.inner.vertices().len(),
            self.inner.triangles().len(),
            self.inner.radius()
        )
    }
}

/// A pose from a position (3,) and a rotation: a unit quaternion (4,)
/// `[w, x, y, z]` or a rotation matrix (3, 3), each within
/// [`ROTATION_TOLERANCE`] of one.
fn pose(
    name: &str,
    position: &PyReadonlyArrayDyn<'_, f64>,
    rotation: &PyReadonlyArrayDyn<'_, f64>,
) -> PyResult<Pose> {
    let translation = vector(&format!("{name} position"), position)?;
    let rotation_name = format!("{name} rotation");
    let rotation = match rotation.shape() {
        [4] => {
            let (_, q) = checked(&rotation_name, rotation, false, &[4])?;
            let q = nalgebra::Quaternion::new(q[0], q[1], q[2], q[3]);
            if (q.norm() - 1.0).abs() > ROTATION_TOLERANCE {
                return Err(PyValueError::new_err(format!(
                    "{rotation_name}: a quaternion [w, x, y, z] must have norm 1, this one has {}",
                    q.norm()
                )));
            }
            nalgebra::UnitQuaternion::new_normalize(q)
        }
        [3, 3] => {
            let (_, m) = checked(&rotation_name, rotation, false, &[3, 3])?;
            let m = nalgebra::Matrix3::from_fn(|i, j| m[3 * i + j]);
            let off = (m.transpose() * m - nalgebra::Matrix3::identity()).amax();
            if off > ROTATION_TOLERANCE || m.determinant() < 0.0 {
                return Err(PyValueError::new_err(format!(
                    "{rotation_name}: not a rotation matrix (orthonormal, determinant +1): M^T M is off the identity by {off:e}, det {}",
                    m.determinant()
                )));
            }
            nalgebra::UnitQuaternion::from_matrix(&m)
        }
        shape => {
            return Err(PyValueError::new_err(format!(
                "{rotation_name}: expected a quaternion (4,) or a rotation matrix (3, 3), got shape {}",
                shape_text(shape)
            )))
        }
    };
    Ok(Pose::from_parts(translation.into(), rotation))
}

/// Two arrays of an argument: a pose's position and rotation, a motion's
/// velocity and angular velocity.
type Arrays<'py> = (PyReadonlyArrayDyn<'py, f64>, PyReadonlyArrayDyn<'py, f64>);

/// Two meshes moving over `[0, duration]`, from a query's arguments.
struct MovingPair {
    a: (Arc<TriMesh>, StepMotion),
    b: (Arc<TriMesh>, StepMotion),
    duration: f64,
}

impl MovingPair {
    fn of(
        (mesh_a, pose_a, motion_a): (&Mesh, Arrays<'_>, Arrays<'_>),
        (mesh_b, pose_b, motion_b): (&Mesh, Arrays<'_>, Arrays<'_>),
        duration: f64,
    ) -> PyResult<MovingPair> {
        Ok(MovingPair {
            a: (mesh_a.inner.clone(), motion("a", pose_a, motion_a)?),
            b: (mesh_b.inner.clone(), motion("b", pose_b, motion_b)?),
            duration: positive_duration(duration)?,
        })
    }
}

/// A body's motion: its pose at the start, and its constant linear and
/// angular velocities (world frame).
fn motion(
    name: &str,
    (position, rotation): Arrays<'_>,
    (velocity, angular): Arrays<'_>,
) -> PyResult<StepMotion> {
    let pose = pose(name, &position, &rotation)?;
    let velocity = vector(&format!("{name} velocity"), &velocity)?;
    let angular = vector(&format!("{name} angular velocity"), &angular)?;
    Ok(StepMotion::new(pose, velocity, angular))
}

/// `(distance, point_a, point_b, triangle_a, triangle_b, feature_a,
/// feature_b)`.
type MeshDistanceTuple<'py> =
    (f64, Bound<'py, PyArray1<f64>>, Bound<'py, PyArray1<f64>>, usize, usize, String, String);

fn mesh_distance_tuple<'py>(py: Python<'py>, d: &MeshDistance) -> MeshDistanceTuple<'py> {
    (
        d.distance,
        array3(py, &d.point_a),
        array3(py, &d.point_b),
        d.triangle_a,
        d.triangle_b,
        d.feature_a.to_string(),
        d.feature_b.to_string(),
    )
}

/// Two meshes (shared, for a query without the GIL) and their poses, the
/// poses checked.
fn posed_pair(
    (mesh_a, pose_a): (&Mesh, Arrays<'_>),
    (mesh_b, pose_b): (&Mesh, Arrays<'_>),
) -> PyResult<(Arc<TriMesh>, Pose, Arc<TriMesh>, Pose)> {
    let pa = pose("pose_a", &pose_a.0, &pose_a.1)?;
    let pb = pose("pose_b", &pose_b.0, &pose_b.1)?;
    Ok((mesh_a.inner.clone(), pa, mesh_b.inner.clone(), pb))
}

/// The distance between two posed meshes (exact), without the GIL.
#[pyfunction]
fn mesh_distance_between<'py>(
    py: Python<'py>,
    mesh_a: &Mesh,
    pose_a: Arrays<'py>,
    mesh_b: &Mesh,
    pose_b: Arrays<'py>,
) -> PyResult<MeshDistanceTuple<'py>> {
    let (a, pa, b, pb) = posed_pair((mesh_a, pose_a), (mesh_b, pose_b))?;
    let found = py.detach(|| {
        let search = DistanceSearch::new(DistanceKernel::Exact, None);
        mesh_distance(&a, &pa, &b, &pb, &search, &mut Default::default())
    });
    Ok(mesh_distance_tuple(py, &found))
}

fn status_name(status: CcdStatus) -> &'static str {
    match status {
        CcdStatus::Separated => "separated",
        CcdStatus::Converged => "converged",
        CcdStatus::InitiallyTouching => "initially_touching",
        CcdStatus::OutOfIterations => "out_of_iterations",
        CcdStatus::Filtered => "filtered",
        _ => "invalid_input",
    }
}

/// Options of the CCD from the keyword arguments (`None`: the default).
fn options(distance_tolerance: Option<f64>, max_iterations: Option<usize>) -> PyResult<CcdOptions> {
    let mut options = CcdOptions::default();
    if let Some(tolerance) = distance_tolerance {
        if !(tolerance.is_finite() && tolerance > 0.0) {
            return Err(PyValueError::new_err(format!(
                "distance_tolerance: {tolerance} is not a positive number"
            )));
        }
        options.distance_tolerance = tolerance;
    }
    if let Some(iterations) = max_iterations {
        if iterations == 0 {
            return Err(PyValueError::new_err("max_iterations: must be at least 1"));
        }
        options.max_iterations = iterations;
    }
    Ok(options)
}

fn positive_duration(duration: f64) -> PyResult<f64> {
    if duration.is_finite() && duration > 0.0 {
        Ok(duration)
    } else {
        Err(PyValueError::new_err(format!("duration: {duration} is not a positive number")))
    }
}

/// The time of first contact of two moving meshes over `[0, duration]`
/// (never late), without the GIL: `(time or None, status,
/// contact_distance, guaranteed_distance, closest or None, iterations)`.
#[allow(clippy::too_many_arguments, clippy::type_complexity)]
#[pyfunction]
#[pyo3(signature = (mesh_a, pose_a, motion_a, mesh_b, pose_b, motion_b, duration, distance_tolerance, minimum_separation, max_iterations, kernel))]
fn mesh_time_of_impact<'py>(
    py: Python<'py>,
    mesh_a: &Mesh,
    pose_a: Arrays<'py>,
    motion_a: Arrays<'py>,
    mesh_b: &Mesh,
    pose_b: Arrays<'py>,
    motion_b: Arrays<'py>,
    duration: f64,
    distance_tolerance: Option<f64>,
    minimum_separation: f64,
    max_iterations: Option<usize>,
    kernel: &str,
) -> PyResult<(Option<f64>, &'static str, f64, f64, Option<MeshDistanceTuple<'py>>, usize)> {
    let pair = MovingPair::of((mesh_a, pose_a, motion_a), (mesh_b, pose_b, motion_b), duration)?;
    let mut options = options(distance_tolerance, max_iterations)?;
    if !(minimum_separation.is_finite() && minimum_separation >= 0.0) {
        return Err(PyValueError::new_err(format!(
            "minimum_separation: {minimum_separation} is not a number at least 0"
        )));
    }
    options.minimum_separation = minimum_separation;
    let kernel = self::kernel(kernel)?;
    let result = py.detach(|| {
        let query = MeshCcdQuery {
            a: MovingMesh { mesh: &pair.a.0, motion: &pair.a.1 },
            b: MovingMesh { mesh: &pair.b.0, motion: &pair.b.1 },
            duration: pair.duration,
            options,
            contact: ContactRule::ScaleRelative,
            kernel,
        };
        nearmiss::ccd::mesh_time_of_impact(&query, WarmStart::default(), &mut MeshCcdScratch::default())
    });
    Ok((
        result.time_of_impact,
        status_name(result.status),
        result.contact_distance,
        result.guaranteed_distance,
        result.closest.as_ref().map(|d| mesh_distance_tuple(py, d)),
        result.iterations,
    ))
}

/// The closest approach of two moving meshes over `[0, duration]` as a
/// certified bracket, without the GIL: `(status, lower, upper, time,
/// closest or None, runs)`.
#[allow(clippy::too_many_arguments, clippy::type_complexity)]
#[pyfunction]
#[pyo3(signature = (mesh_a, pose_a, motion_a, mesh_b, pose_b, motion_b, duration, within, tolerance, max_iterations))]
fn closest_approach_between<'py>(
    py: Python<'py>,
    mesh_a: &Mesh,
    pose_a: Arrays<'py>,
    motion_a: Arrays<'py>,
    mesh_b: &Mesh,
    pose_b: Arrays<'py>,
    motion_b: Arrays<'py>,
    duration: f64,
    within: f64,
    tolerance: Option<f64>,
    max_iterations: Option<usize>,
) -> PyResult<(&'static str, f64, f64, f64, Option<MeshDistanceTuple<'py>>, usize)> {
    let pair = MovingPair::of((mesh_a, pose_a, motion_a), (mesh_b, pose_b, motion_b), duration)?;
    if within.is_nan() || within <= 0.0 {
        return Err(PyValueError::new_err(format!("within: {within} is not a positive distance")));
    }
    if let Some(t) = tolerance.filter(|t| !(t.is_finite() && *t > 0.0)) {
        return Err(PyValueError::new_err(format!("tolerance: {t} is not a positive number")));
    }
    let options = options(None, max_iterations)?;
    let found = py.detach(|| {
        let mut query = ClosestApproachQuery::new(
            MovingMesh { mesh: &pair.a.0, motion: &pair.a.1 },
            MovingMesh { mesh: &pair.b.0, motion: &pair.b.1 },
            pair.duration,
        );
        (query.within, query.tolerance, query.options) = (within, tolerance, options);
        closest_approach(&query, &mut MeshCcdScratch::default())
    });
    let status = match found.status {
        ApproachStatus::Bracketed => "bracketed",
        ApproachStatus::Contact => "contact",
        ApproachStatus::Beyond => "beyond",
        ApproachStatus::OutOfIterations => "out_of_iterations",
        _ => "undecided",
    };
    Ok((
        status,
        found.lower,
        found.upper,
        found.time,
        found.closest.as_ref().map(|d| mesh_distance_tuple(py, d)),
        found.runs,
    ))
}

/// Loads a scene file (validated as `nearmiss check` does): its name, its
/// bodies' names and its steps; `SceneError` with the file, line and column
/// or field when it is not valid.
#[pyfunction]
fn load_scene(path: std::path::PathBuf) -> PyResult<(String, Vec<String>, u64, f64)> {
    let scene = Scene::load(&path).map_err(|e| SceneError::new_err(e.to_string()))?;
    let model = scene.model();
    Ok((
        scene.run().name.clone(),
        model.bodies.iter().map(|b| b.name.clone()).collect(),
        scene.run().steps,
        model.dt,
    ))
}

/// Runs a scene file without the GIL: its `summary.json` text, and its
/// trace as `(step, time, body_a, body_b, distance)` columns.
#[allow(clippy::type_complexity)]
#[pyfunction]
fn run_scene_json<'py>(
    py: Python<'py>,
    path: std::path::PathBuf,
) -> PyResult<(
    String,
    (
        Bound<'py, PyArray1<u64>>,
        Bound<'py, PyArray1<f64>>,
        Bound<'py, PyArray1<u64>>,
        Bound<'py, PyArray1<u64>>,
        Bound<'py, PyArray1<f64>>,
    ),
)> {
    let scene = Scene::load(&path).map_err(|e| SceneError::new_err(e.to_string()))?;
    nearmiss::run::check(&scene).map_err(|e| SceneError::new_err(e.to_string()))?;
    let result = py.detach(|| nearmiss::run(&scene));
    if let Some(field) = result.first_non_finite() {
        return Err(PyRuntimeError::new_err(format!(
            "{}: the run produced a number that is not finite ({field}). Please report the scene",
            path.display()
        )));
    }
    let json = nearmiss_summary::summary_json(&result, &scene);
    let trace = &result.trace;
    Ok((
        json,
        (
            PyArray1::from_vec(py, trace.iter().map(|r| r.step).collect()),
            PyArray1::from_vec(py, trace.iter().map(|r| r.time).collect()),
            PyArray1::from_vec(py, trace.iter().map(|r| r.pair.0 as u64).collect()),
            PyArray1::from_vec(py, trace.iter().map(|r| r.pair.1 as u64).collect()),
            PyArray1::from_vec(py, trace.iter().map(|r| r.distance).collect()),
        ),
    ))
}

/// What two triangles share: `(kind, points)`, kind `"disjoint"`,
/// `"point"`, `"segment"` or `"polygon"`, the points (k, 3) spanning it.
#[pyfunction]
fn triangle_intersection<'py>(
    py: Python<'py>,
    a: PyReadonlyArrayDyn<'py, f64>,
    b: PyReadonlyArrayDyn<'py, f64>,
) -> PyResult<(&'static str, Bound<'py, PyArray2<f64>>)> {
    let (ta, tb) = (triangle("a", &a)?, triangle("b", &b)?);
    let shared = kernels::triangle_intersection(&ta, &tb);
    let kind = match shared {
        kernels::TriangleIntersection::Disjoint => "disjoint",
        kernels::TriangleIntersection::Point(_) => "point",
        kernels::TriangleIntersection::Segment(_) => "segment",
        kernels::TriangleIntersection::Polygon(_) => "polygon",
    };
    Ok((kind, rows(py, shared.points().to_vec())))
}

/// The shortest translation that separates two triangles: `(depth,
/// direction)`, or `None` when they do not meet.
#[pyfunction]
fn triangle_penetration<'py>(
    py: Python<'py>,
    a: PyReadonlyArrayDyn<'py, f64>,
    b: PyReadonlyArrayDyn<'py, f64>,
) -> PyResult<Option<(f64, Bound<'py, PyArray1<f64>>)>> {
    let (ta, tb) = (triangle("a", &a)?, triangle("b", &b)?);
    Ok(kernels::triangle_penetration(&ta, &tb).map(|p| (p.depth, array3(py, &Point::from(p.direction)))))
}

/// Every triangle pair of two posed meshes that meets, without the GIL:
/// `(pairs (k, 2), segments (m, 6): each segment's two ends, length)`.
#[allow(clippy::type_complexity)]
#[pyfunction]
fn mesh_intersection_between<'py>(
    py: Python<'py>,
    mesh_a: &Mesh,
    pose_a: Arrays<'py>,
    mesh_b: &Mesh,
    pose_b: Arrays<'py>,
) -> PyResult<(Bound<'py, PyArray2<u64>>, Bound<'py, PyArray2<f64>>, f64)> {
    let (a, pa, b, pb) = posed_pair((mesh_a, pose_a), (mesh_b, pose_b))?;
    let found = py.detach(|| {
        let mut found = MeshIntersection::default();
        mesh_intersection(&a, &pa, &b, &pb, &mut found, &mut Default::default());
        found
    });
    let pairs: Vec<u64> =
        found.pairs.iter().flat_map(|p| [p.triangle_a as u64, p.triangle_b as u64]).collect();
    let segments: Vec<f64> = found.segments().flat_map(|[p, q]| [p.x, p.y, p.z, q.x, q.y, q.z]).collect();
    let (k, m) = (found.pairs.len(), segments.len() / 6);
    Ok((
        Array2::from_shape_vec((k, 2), pairs).expect("k rows of 2").into_pyarray(py),
        Array2::from_shape_vec((m, 6), segments).expect("m rows of 6").into_pyarray(py),
        found.length(),
    ))
}

/// The signed distance of two posed meshes, without the GIL: `(value,
/// kind, lower, upper, direction)`; kind `"apart"`, `"convex"`,
/// `"local"`, `"inside"` or `"open_crossing"`; `lower`/`upper` the depth's
/// bracket (None apart or open), `direction` the separating move's (convex
/// only).
#[allow(clippy::type_complexity)]
#[pyfunction]
fn signed_distance_between<'py>(
    py: Python<'py>,
    mesh_a: &Mesh,
    pose_a: Arrays<'py>,
    mesh_b: &Mesh,
    pose_b: Arrays<'py>,
) -> PyResult<(f64, &'static str, Option<f64>, Option<f64>, Option<Bound<'py, PyArray1<f64>>>)> {
    let (a, pa, b, pb) = posed_pair((mesh_a, pose_a), (mesh_b, pose_b))?;
    let found = py.detach(|| signed_distance(&a, &pa, &b, &pb, &mut Default::default()));
    Ok(match &found.overlap {
        Overlap::Apart(_) => (found.value, "apart", None, None, None),
        Overlap::Convex(d) => {
            (found.value, "convex", Some(d.depth), Some(d.depth), Some(array3(py, &Point::from(d.direction))))
        }
        Overlap::Local(depths) => {
            let deepest = depths.first();
            (found.value, "local", deepest.map(|d| d.lower), deepest.map(|d| d.upper), None)
        }
        Overlap::Inside { lower, upper, .. } => (found.value, "inside", Some(*lower), Some(*upper), None),
        Overlap::OpenCrossing(_) => (found.value, "open_crossing", None, None, None),
    })
}

/// The extension module.
#[pymodule]
fn _nearmiss(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add("SceneError", m.py().get_type::<SceneError>())?;
    m.add_class::<Mesh>()?;
    m.add_function(wrap_pyfunction!(triangle_distance, m)?)?;
    m.add_function(wrap_pyfunction!(triangle_distances, m)?)?;
    m.add_function(wrap_pyfunction!(triangle_closest_points, m)?)?;
    m.add_function(wrap_pyfunction!(point_segment_distance, m)?)?;
    m.add_function(wrap_pyfunction!(point_segment_distances, m)?)?;
    m.add_function(wrap_pyfunction!(dyop_distance, m)?)?;
    m.add_function(wrap_pyfunction!(mesh_distance_between, m)?)?;
    m.add_function(wrap_pyfunction!(mesh_time_of_impact, m)?)?;
    m.add_function(wrap_pyfunction!(closest_approach_between, m)?)?;
    m.add_function(wrap_pyfunction!(triangle_intersection, m)?)?;
    m.add_function(wrap_pyfunction!(triangle_penetration, m)?)?;
    m.add_function(wrap_pyfunction!(mesh_intersection_between, m)?)?;
    m.add_function(wrap_pyfunction!(signed_distance_between, m)?)?;
    m.add_function(wrap_pyfunction!(load_scene, m)?)?;
    m.add_function(wrap_pyfunction!(run_scene_json, m)?)?;
    Ok(())
}

//! The arguments as the extension takes them: arrays checked and turned
//! into the library's points, poses and motions; names and options.

use std::borrow::Cow;
use std::sync::Arc;

use crate::mesh::Mesh;
use nearmiss::ccd::{ApproachStatus, CcdOptions, CcdStatus};
use nearmiss::kernels::{Feature, PointEdgeFormula};
use nearmiss::math::{MatrixPose, Placement, Point, Pose, Triangle, Vector};
use nearmiss::mesh::{DistanceKernel, MeshDistance, TriMesh};
use nearmiss::motion::StepMotion;
use numpy::ndarray::Array2;
use numpy::{IntoPyArray, PyArray1, PyArray2, PyReadonlyArrayDyn, PyUntypedArrayMethods};
use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;

/// How far a rotation argument may be from one: a quaternion's norm from 1,
/// a matrix's `MᵀM` from the identity (largest entry): `1e-6`, room for a
/// rotation stored in float32 (about 1e-7 off) and for the noise of forward
/// kinematics, far below a mistake. Within it the rotation is
/// re-orthonormalised (a quaternion normalised, a matrix projected onto its
/// nearest rotation); farther, it is refused with a message saying how to
/// make it one.
pub(crate) const ROTATION_TOLERANCE: f64 = 1e-6;

/// Pairs per parallel task of the batched queries.
pub(crate) const BATCH_CHUNK: usize = 1024;

/// The shape of `array` as Python writes it: `(3, 3)`.
pub(crate) fn shape_text(shape: &[usize]) -> String {
    match shape {
        [n] => format!("({n},)"),
        _ => format!("({})", shape.iter().map(|n| n.to_string()).collect::<Vec<_>>().join(", ")),
    }
}

/// `array`'s numbers, checked: its trailing dimensions are `tail`, every
/// number finite. Returns the leading count (1 when `leading` is false)
/// and the numbers in row-major order (borrowed when the array is
/// contiguous, as the package passes it).
pub(crate) fn checked<'a>(
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
pub(crate) struct Numbers<'a> {
    pub(crate) name: String,
    pub(crate) shape: Vec<usize>,
    /// The leading count (1 for a single item).
    pub(crate) count: usize,
    /// Row-major.
    pub(crate) values: Cow<'a, [f64]>,
}

impl<'a> Numbers<'a> {
    /// `array`, if its trailing dimensions are `tail` (after one leading
    /// dimension if `leading`).
    pub(crate) fn of(
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
    pub(crate) fn finite(&self) -> Result<(), String> {
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
    pub(crate) fn triangles(&self) -> Result<Vec<Triangle>, String> {
        self.finite()?;
        Ok((0..self.count).map(|i| [0, 1, 2].map(|k| point_at(&self.values, 3 * i + k))).collect())
    }

    /// The (N, 3) batch as points, checked finite (no GIL needed).
    pub(crate) fn points(&self) -> Result<Vec<Point>, String> {
        self.finite()?;
        Ok((0..self.count).map(|i| point_at(&self.values, i)).collect())
    }
}

pub(crate) fn point_at(v: &[f64], k: usize) -> Point {
    Point::new(v[3 * k], v[3 * k + 1], v[3 * k + 2])
}

pub(crate) fn point(name: &str, array: &PyReadonlyArrayDyn<'_, f64>) -> PyResult<Point> {
    let (_, v) = checked(name, array, false, &[3])?;
    Ok(point_at(&v, 0))
}

pub(crate) fn vector(name: &str, array: &PyReadonlyArrayDyn<'_, f64>) -> PyResult<Vector> {
    Ok(point(name, array)?.coords)
}

pub(crate) fn triangle(name: &str, array: &PyReadonlyArrayDyn<'_, f64>) -> PyResult<Triangle> {
    let (_, v) = checked(name, array, false, &[3, 3])?;
    Ok([0, 1, 2].map(|k| point_at(&v, k)))
}

pub(crate) fn points(name: &str, array: &PyReadonlyArrayDyn<'_, f64>) -> PyResult<Vec<Point>> {
    Numbers::of(name, array, true, &[3])?.points().map_err(PyValueError::new_err)
}

/// Two batch arguments of one length.
pub(crate) fn same_length(names: (&str, &str), lengths: (usize, usize)) -> PyResult<()> {
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
pub(crate) fn formula(name: &str) -> PyResult<PointEdgeFormula> {
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
pub(crate) fn kernel(name: &str) -> PyResult<DistanceKernel> {
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
pub(crate) fn feature_code(feature: Feature) -> i8 {
    match feature {
        Feature::Vertex(i) => i as i8,
        Feature::Edge(i) => 3 + i as i8,
        Feature::Face => 6,
    }
}

pub(crate) fn array3<'py>(py: Python<'py>, p: &Point) -> Bound<'py, PyArray1<f64>> {
    PyArray1::from_vec(py, vec![p.x, p.y, p.z])
}

pub(crate) fn rows<'py>(py: Python<'py>, points: Vec<Point>) -> Bound<'py, PyArray2<f64>> {
    let n = points.len();
    let flat: Vec<f64> = points.iter().flat_map(|p| [p.x, p.y, p.z]).collect();
    Array2::from_shape_vec((n, 3), flat).expect("n rows of 3").into_pyarray(py)
}

/// How far `MᵀM` may be from the identity for a matrix to be read as the
/// rotation it is, with no projection onto the nearest one: `1e-14`
/// (float64 rotations as computed, a few dozen ulps).
const ORTHONORMAL_TO_ROUNDING: f64 = 1e-14;

/// A pose from a position (3,) and a rotation: a unit quaternion (4,)
/// `[w, x, y, z]` or a rotation matrix (3, 3), each within
/// [`ROTATION_TOLERANCE`] of one.
pub(crate) fn pose(
    name: &str,
    position: &PyReadonlyArrayDyn<'_, f64>,
    rotation: &PyReadonlyArrayDyn<'_, f64>,
) -> PyResult<Pose> {
    Ok(placed(name, position, rotation)?.pose())
}

/// A pose as the queries that pose exactly take it: a rotation matrix that
/// is one to rounding (within [`ORTHONORMAL_TO_ROUNDING`]) kept as it is,
/// any other rotation as its quaternion.
#[derive(Copy, Clone, Debug)]
pub(crate) enum Placed {
    Quaternion(Pose),
    Matrix(MatrixPose),
}

impl Placement for Placed {
    fn matrix_pose(&self) -> MatrixPose {
        match self {
            Placed::Quaternion(pose) => pose.matrix_pose(),
            Placed::Matrix(matrix) => *matrix,
        }
    }

    fn pose(&self) -> Pose {
        match self {
            Placed::Quaternion(pose) => *pose,
            Placed::Matrix(matrix) => matrix.pose(),
        }
    }
}

/// [`pose`], kept as given ([`Placed`]).
pub(crate) fn placed(
    name: &str,
    position: &PyReadonlyArrayDyn<'_, f64>,
    rotation: &PyReadonlyArrayDyn<'_, f64>,
) -> PyResult<Placed> {
    let translation = vector(&format!("{name} position"), position)?;
    let rotation_name = format!("{name} rotation");
    let rotation = match rotation.shape() {
        [4] => {
            let (_, q) = checked(&rotation_name, rotation, false, &[4])?;
            let q = nalgebra::Quaternion::new(q[0], q[1], q[2], q[3]);
            if (q.norm() - 1.0).abs() > ROTATION_TOLERANCE {
                return Err(PyValueError::new_err(format!(
                    "{rotation_name}: a quaternion [w, x, y, z] must have norm 1 (within {ROTATION_TOLERANCE:e}), this one has {}; divide it by its norm if it is meant as a rotation",
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
                    "{rotation_name}: not a rotation matrix (orthonormal, determinant +1): M^T M is off the identity by {off:e} (at most {ROTATION_TOLERANCE:e} is re-orthonormalised), det {}; if it is a rotation with noise, take its nearest rotation first (scipy.spatial.transform.Rotation.from_matrix(M).as_matrix(), or U V^T of its SVD)",
                    m.determinant()
                )));
            }
            if off <= ORTHONORMAL_TO_ROUNDING {
                // A rotation to rounding: kept as it is (its quaternion by
                // Shepperd's method where one is needed; the nearest-rotation
                // iteration moves it by a few ulps more).
                return Ok(Placed::Matrix(MatrixPose { rotation: m, translation }));
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
    Ok(Placed::Quaternion(Pose::from_parts(translation.into(), rotation)))
}

/// Two arrays of an argument: a pose's position and rotation, a motion's
/// velocity and angular velocity.
pub(crate) type Arrays<'py> = (PyReadonlyArrayDyn<'py, f64>, PyReadonlyArrayDyn<'py, f64>);

/// A moving body as a query takes it: its mesh, its pose's arrays and its
/// motion's.
pub(crate) type Body<'py> = (PyRef<'py, Mesh>, Arrays<'py>, Arrays<'py>);

/// Two meshes moving over `[0, duration]`, from a query's arguments.
pub(crate) struct MovingPair {
    pub(crate) a: (Arc<TriMesh>, StepMotion),
    pub(crate) b: (Arc<TriMesh>, StepMotion),
    pub(crate) duration: f64,
}

impl MovingPair {
    pub(crate) fn of(
        (mesh_a, pose_a, motion_a): Body<'_>,
        (mesh_b, pose_b, motion_b): Body<'_>,
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
pub(crate) fn motion(
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
pub(crate) type MeshDistanceTuple<'py> =
    (f64, Bound<'py, PyArray1<f64>>, Bound<'py, PyArray1<f64>>, usize, usize, String, String);

pub(crate) fn mesh_distance_tuple<'py>(py: Python<'py>, d: &MeshDistance) -> MeshDistanceTuple<'py> {
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
pub(crate) fn posed_pair(
    (mesh_a, pose_a): (&Mesh, Arrays<'_>),
    (mesh_b, pose_b): (&Mesh, Arrays<'_>),
) -> PyResult<(Arc<TriMesh>, Pose, Arc<TriMesh>, Pose)> {
    let pa = pose("pose_a", &pose_a.0, &pose_a.1)?;
    let pb = pose("pose_b", &pose_b.0, &pose_b.1)?;
    Ok((mesh_a.inner.clone(), pa, mesh_b.inner.clone(), pb))
}

pub(crate) fn status_name(status: CcdStatus) -> &'static str {
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
pub(crate) fn options(
    distance_tolerance: Option<f64>,
    max_iterations: Option<usize>,
) -> PyResult<CcdOptions> {
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

/// The CCD's options with a minimum separation (at least 0).
pub(crate) fn contact_options(
    distance_tolerance: Option<f64>,
    minimum_separation: f64,
    max_iterations: Option<usize>,
) -> PyResult<CcdOptions> {
    let mut options = options(distance_tolerance, max_iterations)?;
    if !(minimum_separation.is_finite() && minimum_separation >= 0.0) {
        return Err(PyValueError::new_err(format!(
            "minimum_separation: {minimum_separation} is not a number at least 0"
        )));
    }
    options.minimum_separation = minimum_separation;
    Ok(options)
}

/// A closest approach's `within` (positive, infinite for every approach)
/// and bracket width (positive), checked; the CCD options of its runs.
pub(crate) fn approach_options(
    within: f64,
    tolerance: Option<f64>,
    max_iterations: Option<usize>,
) -> PyResult<CcdOptions> {
    if within.is_nan() || within <= 0.0 {
        return Err(PyValueError::new_err(format!("within: {within} is not a positive distance")));
    }
    if let Some(t) = tolerance.filter(|t| !(t.is_finite() && *t > 0.0)) {
        return Err(PyValueError::new_err(format!("tolerance: {t} is not a positive number")));
    }
    options(None, max_iterations)
}

pub(crate) fn approach_status_name(status: ApproachStatus) -> &'static str {
    match status {
        ApproachStatus::Bracketed => "bracketed",
        ApproachStatus::Contact => "contact",
        ApproachStatus::Beyond => "beyond",
        ApproachStatus::OutOfIterations => "out_of_iterations",
        _ => "undecided",
    }
}

pub(crate) fn positive_duration(duration: f64) -> PyResult<f64> {
    if duration.is_finite() && duration > 0.0 {
        Ok(duration)
    } else {
        Err(PyValueError::new_err(format!("duration: {duration} is not a positive number")))
    }
}

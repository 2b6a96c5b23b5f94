//! The mesh queries: distance, time of impact, closest approach,
//! intersection and penetration, without the GIL.

use crate::args::*;
use crate::mesh::Mesh;
use nearmiss::ccd::{
    closest_approach, ClosestApproachQuery, ContactRule, MeshCcdQuery, MeshCcdScratch, MovingMesh, WarmStart,
};
use nearmiss::kernels::{self};
use nearmiss::math::Point;
use nearmiss::mesh::{
    mesh_distance, mesh_intersection, signed_distance, DistanceKernel, DistanceSearch, MeshIntersection,
    Overlap,
};
use numpy::ndarray::Array2;
use numpy::{IntoPyArray, PyArray1, PyArray2, PyReadonlyArrayDyn};
use pyo3::prelude::*;

/// The distance between two posed meshes (exact), without the GIL.
#[pyfunction]
pub(crate) fn mesh_distance_between<'py>(
    py: Python<'py>,
    mesh_a: &Mesh,
    pose_a: Arrays<'py>,
    mesh_b: &Mesh,
    pose_b: Arrays<'py>,
) -> PyResult<MeshDistanceTuple<'py>> {
    // The poses as given: a rotation matrix is applied as it is.
    let pa = placed("pose_a", &pose_a.0, &pose_a.1)?;
    let pb = placed("pose_b", &pose_b.0, &pose_b.1)?;
    let (a, b) = (mesh_a.inner.clone(), mesh_b.inner.clone());
    let found = py.detach(|| {
        let search = DistanceSearch::new(DistanceKernel::Exact, None);
        mesh_distance(&a, &pa, &b, &pb, &search, &mut Default::default())
    });
    Ok(mesh_distance_tuple(py, &found))
}

/// The time of first contact of two moving meshes over `[0, duration]`
/// (never late), without the GIL: `(time or None, status,
/// contact_distance, guaranteed_distance, closest or None, iterations)`.
///
/// `a`, `b`: `(mesh, (position, rotation), (velocity, angular_velocity))`;
/// `options`: `(distance_tolerance, minimum_separation, max_iterations,
/// kernel)`.
#[allow(clippy::type_complexity)]
#[pyfunction]
pub(crate) fn mesh_time_of_impact<'py>(
    py: Python<'py>,
    a: Body<'py>,
    b: Body<'py>,
    duration: f64,
    options: (Option<f64>, f64, Option<usize>, String),
) -> PyResult<(Option<f64>, &'static str, f64, f64, Option<MeshDistanceTuple<'py>>, usize)> {
    let (distance_tolerance, minimum_separation, max_iterations, kernel) = options;
    let pair = MovingPair::of(a, b, duration)?;
    let options = contact_options(distance_tolerance, minimum_separation, max_iterations)?;
    let kernel = self::kernel(&kernel)?;
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

/// The motion from `pose0` to `pose1` in `duration` turning about the
/// body's point `about` (its own frame): `(position, quaternion, velocity,
/// angular_velocity)` of the frame at `about`, quaternion `[w, x, y, z]`.
#[allow(clippy::type_complexity)]
#[pyfunction]
pub(crate) fn motion_between<'py>(
    py: Python<'py>,
    pose0: Arrays<'py>,
    pose1: Arrays<'py>,
    duration: f64,
    about: PyReadonlyArrayDyn<'py, f64>,
) -> PyResult<(
    Bound<'py, PyArray1<f64>>,
    Bound<'py, PyArray1<f64>>,
    Bound<'py, PyArray1<f64>>,
    Bound<'py, PyArray1<f64>>,
)> {
    let start = pose("pose0", &pose0.0, &pose0.1)?;
    let end = pose("pose1", &pose1.0, &pose1.1)?;
    let duration = positive_duration(duration)?;
    let about = point("about", &about)?;
    let motion = nearmiss::motion::StepMotion::between_about(&start, &end, duration, &about);
    let q = motion.reference.rotation.into_inner();
    let array = |values: Vec<f64>| values.into_pyarray(py);
    Ok((
        array(motion.reference.translation.vector.iter().copied().collect()),
        array(vec![q.w, q.i, q.j, q.k]),
        array(motion.velocity.iter().copied().collect()),
        array(motion.angular_velocity.iter().copied().collect()),
    ))
}

/// The closest approach of two moving meshes over `[0, duration]` as a
/// certified bracket, without the GIL: `(status, lower, upper, time,
/// closest or None, runs)`.
///
/// `a`, `b` as for `mesh_time_of_impact`; `options`: `(within, tolerance,
/// max_iterations)`.
#[allow(clippy::type_complexity)]
#[pyfunction]
pub(crate) fn closest_approach_between<'py>(
    py: Python<'py>,
    a: Body<'py>,
    b: Body<'py>,
    duration: f64,
    options: (f64, Option<f64>, Option<usize>),
) -> PyResult<(&'static str, f64, f64, f64, Option<MeshDistanceTuple<'py>>, usize)> {
    let (within, tolerance, max_iterations) = options;
    let pair = MovingPair::of(a, b, duration)?;
    let options = approach_options(within, tolerance, max_iterations)?;
    let found = py.detach(|| {
        let mut query = ClosestApproachQuery::new(
            MovingMesh { mesh: &pair.a.0, motion: &pair.a.1 },
            MovingMesh { mesh: &pair.b.0, motion: &pair.b.1 },
            pair.duration,
        );
        (query.within, query.tolerance, query.options) = (within, tolerance, options);
        closest_approach(&query, &mut MeshCcdScratch::default())
    });
    Ok((
        approach_status_name(found.status),
        found.lower,
        found.upper,
        found.time,
        found.closest.as_ref().map(|d| mesh_distance_tuple(py, d)),
        found.runs,
    ))
}

/// What two triangles share: `(kind, points)`, kind `"disjoint"`,
/// `"point"`, `"segment"` or `"polygon"`, the points (k, 3) spanning it.
#[pyfunction]
pub(crate) fn triangle_intersection<'py>(
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
pub(crate) fn triangle_penetration<'py>(
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
pub(crate) fn mesh_intersection_between<'py>(
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
pub(crate) fn signed_distance_between<'py>(
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

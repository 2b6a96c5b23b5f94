//! The distance kernels on numpy arrays: one pair, or a batch on all
//! cores.

use crate::args::*;
use nearmiss::kernels::batch::TrianglesSoa;
use nearmiss::kernels::{self};
use nearmiss::math::Triangle;
use numpy::{PyArray1, PyArray2, PyReadonlyArrayDyn};
use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;
use rayon::prelude::*;

/// `(distance, point_a, point_b, feature_a, feature_b, within_range)` of
/// two triangles.
#[allow(clippy::type_complexity)]
#[pyfunction]
pub(crate) fn triangle_distance<'py>(
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
pub(crate) fn triangle_distances<'py>(
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
pub(crate) fn triangle_closest_points<'py>(
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
pub(crate) fn point_segment_distance(
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
pub(crate) fn point_segment_distances<'py>(
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
pub(crate) fn dyop_distance(
    a: PyReadonlyArrayDyn<'_, f64>,
    b: PyReadonlyArrayDyn<'_, f64>,
    formula: &str,
) -> PyResult<f64> {
    let f = self::formula(formula)?;
    Ok(kernels::dyop_distance(&triangle("a", &a)?, &triangle("b", &b)?, f))
}

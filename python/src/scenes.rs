//! Scene files: loaded and checked, or run to their `summary.json`.

use crate::SceneError;
use nearmiss::scene::Scene;
use numpy::PyArray1;
use pyo3::exceptions::PyRuntimeError;
use pyo3::prelude::*;

/// Loads a scene file (validated as `nearmiss check` does): its name, its
/// bodies' names and its steps; `SceneError` with the file, line and column
/// or field when it is not valid.
#[pyfunction]
pub(crate) fn load_scene(path: std::path::PathBuf) -> PyResult<(String, Vec<String>, u64, f64)> {
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
pub(crate) fn run_scene_json<'py>(
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

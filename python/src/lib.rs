//! `nearmiss._nearmiss`: the library's queries on numpy arrays, for the
//! Python package `nearmiss` (python/nearmiss/, which adds the types,
//! docstrings and argument forms; call that, not this).
//!
//! Every array argument is checked here, whatever called: its shape, and
//! that every number is finite; a bad one raises `ValueError` naming the
//! argument and the element (never a panic, never a silent NaN). Queries
//! that may take long run without the GIL; batches run on all cores.

mod args;
mod collection;
mod kernels;
mod mesh;
mod queries;
mod scenes;

use pyo3::create_exception;
use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;

create_exception!(
    _nearmiss,
    SceneError,
    PyValueError,
    "A scene file that cannot be read or is not valid (the message names the file, line and column or field)."
);

/// The extension module.
#[pymodule]
fn _nearmiss(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add("SceneError", m.py().get_type::<SceneError>())?;
    m.add("__version__", env!("CARGO_PKG_VERSION"))?;
    m.add_class::<mesh::Mesh>()?;
    m.add_class::<collection::Collection>()?;
    m.add_function(wrap_pyfunction!(kernels::triangle_distance, m)?)?;
    m.add_function(wrap_pyfunction!(kernels::triangle_distances, m)?)?;
    m.add_function(wrap_pyfunction!(kernels::triangle_closest_points, m)?)?;
    m.add_function(wrap_pyfunction!(kernels::point_segment_distance, m)?)?;
    m.add_function(wrap_pyfunction!(kernels::point_segment_distances, m)?)?;
    m.add_function(wrap_pyfunction!(kernels::dyop_distance, m)?)?;
    m.add_function(wrap_pyfunction!(queries::mesh_distance_between, m)?)?;
    m.add_function(wrap_pyfunction!(queries::mesh_time_of_impact, m)?)?;
    m.add_function(wrap_pyfunction!(queries::closest_approach_between, m)?)?;
    m.add_function(wrap_pyfunction!(queries::motion_between, m)?)?;
    m.add_function(wrap_pyfunction!(queries::triangle_intersection, m)?)?;
    m.add_function(wrap_pyfunction!(queries::triangle_penetration, m)?)?;
    m.add_function(wrap_pyfunction!(queries::mesh_intersection_between, m)?)?;
    m.add_function(wrap_pyfunction!(queries::signed_distance_between, m)?)?;
    m.add_function(wrap_pyfunction!(scenes::load_scene, m)?)?;
    m.add_function(wrap_pyfunction!(scenes::run_scene_json, m)?)?;
    Ok(())
}

//! The `Collection` class: named meshes with poses and the broad phase
//! inside (`nearmiss::collection`), under `nearmiss.CollisionManager`.

use crate::args::*;
use crate::mesh::Mesh;
use nearmiss::collection::{self, FirstContactStatus, Nearest, Touch};
use pyo3::exceptions::PyKeyError;
use pyo3::prelude::*;

/// `(name, other name or None, the pair's distance tuple)`.
type Found<'py> = (String, Option<String>, MeshDistanceTuple<'py>);

fn found<'py>(py: Python<'py>, a: &str, b: Option<&str>, d: &nearmiss::mesh::MeshDistance) -> Found<'py> {
    (a.to_owned(), b.map(str::to_owned), mesh_distance_tuple(py, d))
}

fn touches<'py>(py: Python<'py>, touches: &[Touch<'_>]) -> Vec<Found<'py>> {
    touches.iter().map(|t| found(py, t.a, t.b, &t.found)).collect()
}

fn nearest<'py>(py: Python<'py>, nearest: Option<Nearest<'_>>) -> Option<Found<'py>> {
    nearest.map(|n| found(py, n.a, n.b, &n.found))
}

fn unknown(error: collection::UnknownObject) -> PyErr {
    PyKeyError::new_err(error.0)
}

/// Named meshes with poses; the queries run without the GIL.
#[pyclass(module = "nearmiss._nearmiss")]
pub(crate) struct Collection {
    inner: collection::Collection,
}

#[pymethods]
impl Collection {
    #[new]
    fn new() -> Collection {
        Collection { inner: collection::Collection::new() }
    }

    /// Adds (or replaces) the object `name`.
    fn insert(&mut self, name: String, mesh: &Mesh, pose: Arrays<'_>) -> PyResult<()> {
        let pose = placed(&format!("pose of {name:?}"), &pose.0, &pose.1)?;
        self.inner.insert(name, mesh.inner.clone(), pose);
        Ok(())
    }

    /// Removes the object `name` (`KeyError` if there is none).
    fn remove(&mut self, name: &str) -> PyResult<()> {
        self.inner.remove(name).map(drop).map_err(unknown)
    }

    /// Moves the object `name` (`KeyError` if there is none).
    fn set_pose(&mut self, name: &str, pose: Arrays<'_>) -> PyResult<()> {
        let pose = placed(&format!("pose of {name:?}"), &pose.0, &pose.1)?;
        self.inner.set_pose(name, pose).map_err(unknown)
    }

    fn __len__(&self) -> usize {
        self.inner.len()
    }

    fn __contains__(&self, name: &str) -> bool {
        self.inner.get(name).is_some()
    }

    /// The objects `mesh` at `pose` touches: `[(name, None, distance tuple)]`.
    fn in_collision<'py>(
        &self,
        py: Python<'py>,
        mesh: &Mesh,
        pose: Arrays<'py>,
    ) -> PyResult<Vec<Found<'py>>> {
        let pose = placed("transform", &pose.0, &pose.1)?;
        let (inner, mesh) = (&self.inner, &mesh.inner);
        Ok(touches(py, &py.detach(|| inner.in_collision(mesh, &pose))))
    }

    /// Every two objects that touch: `[(name, name, distance tuple)]`.
    fn in_collision_internal<'py>(&self, py: Python<'py>) -> Vec<Found<'py>> {
        let inner = &self.inner;
        touches(py, &py.detach(|| inner.in_collision_internal()))
    }

    /// The nearest object to `mesh` at `pose`, or None when empty.
    fn min_distance<'py>(
        &self,
        py: Python<'py>,
        mesh: &Mesh,
        pose: Arrays<'py>,
    ) -> PyResult<Option<Found<'py>>> {
        let pose = placed("transform", &pose.0, &pose.1)?;
        let (inner, mesh) = (&self.inner, &mesh.inner);
        Ok(nearest(py, py.detach(|| inner.min_distance(mesh, &pose))))
    }

    /// The nearest two objects (of `name` to the others), or None.
    #[pyo3(signature = (name=None))]
    fn min_distance_internal<'py>(
        &self,
        py: Python<'py>,
        name: Option<&str>,
    ) -> PyResult<Option<Found<'py>>> {
        let inner = &self.inner;
        Ok(nearest(py, py.detach(|| inner.min_distance_internal(name)).map_err(unknown)?))
    }

    /// The first contact of a moving mesh with any object: `(status, time,
    /// name or None, closest or None, contact_distance or None,
    /// candidates)`; status `"clear"`, `"contact"` or `"undecided"`.
    #[allow(clippy::type_complexity)]
    fn first_contact<'py>(
        &self,
        py: Python<'py>,
        body: Body<'py>,
        duration: f64,
        options: (Option<f64>, f64, Option<usize>),
    ) -> PyResult<(&'static str, f64, Option<String>, Option<MeshDistanceTuple<'py>>, Option<f64>, usize)>
    {
        let (mesh, pose, velocities) = body;
        let motion = motion("motion", pose, velocities)?;
        let duration = positive_duration(duration)?;
        let options = contact_options(options.0, options.1, options.2)?;
        let (inner, mesh) = (&self.inner, &mesh.inner);
        let found = py.detach(|| inner.first_contact(mesh, &motion, duration, &options));
        let status = match found.status {
            FirstContactStatus::Clear => "clear",
            FirstContactStatus::Contact => "contact",
            _ => "undecided",
        };
        let contact = found.contact.as_ref();
        Ok((
            status,
            found.time,
            found.object.map(str::to_owned),
            contact.and_then(|c| c.closest.as_ref()).map(|d| mesh_distance_tuple(py, d)),
            contact.map(|c| c.contact_distance),
            found.candidates,
        ))
    }

    /// The certified clearance of a moving mesh from the objects:
    /// `(status, lower, upper, time, name or None, closest or None, runs,
    /// candidates)`.
    #[allow(clippy::type_complexity)]
    fn clearance<'py>(
        &self,
        py: Python<'py>,
        body: Body<'py>,
        duration: f64,
        options: (f64, Option<f64>, Option<usize>),
    ) -> PyResult<(&'static str, f64, f64, f64, Option<String>, Option<MeshDistanceTuple<'py>>, usize, usize)>
    {
        let (mesh, pose, velocities) = body;
        let motion = motion("motion", pose, velocities)?;
        let duration = positive_duration(duration)?;
        let (within, tolerance, max_iterations) = options;
        let ccd = approach_options(within, tolerance, max_iterations)?;
        let (inner, mesh) = (&self.inner, &mesh.inner);
        let found = py.detach(|| inner.clearance(mesh, &motion, duration, within, tolerance, &ccd));
        let approach = &found.approach;
        Ok((
            approach_status_name(approach.status),
            approach.lower,
            approach.upper,
            approach.time,
            found.object.map(str::to_owned),
            approach.closest.as_ref().map(|d| mesh_distance_tuple(py, d)),
            approach.runs,
            found.candidates,
        ))
    }
}

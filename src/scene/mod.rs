//! Scenes: the RON file format (`file`), its validation, and the
//! validated [`Scene`] that the [`stepper`](crate::stepper) runs: its
//! [`Model`] (what is simulated: bodies, step, engine settings; what the
//! stepper and the guard take) and its [`RunSpec`] (what a run covers and
//! writes: name, length, trace, plot, poses, expectation).
//!
//! Loading resolves everything a run needs and checks it: numbers finite
//! and in range, names unique and resolved, meshes built (OBJ paths
//! relative to the scene file) and shared between bodies that use the same
//! mesh. Errors name the file and the line and column (syntax, unknown
//! fields, wrong types) or the field (values).
//!
//! ```
//! let scene = nearmiss::scene::Scene::from_ron_str(r#"
//!     Scene(
//!         name: "approach",
//!         dt: 0.01,
//!         duration: 1.0,
//!         bodies: [
//!             (name: "a", mesh: Box(half_extents: (0.5, 0.5, 0.5)), velocity: (1.0, 0.0, 0.0)),
//!             (name: "b", mesh: Box(half_extents: (0.5, 0.5, 0.5)), position: (2.0, 0.0, 0.0), fixed: true),
//!         ],
//!         expect: Contact(time: 1.0, tolerance: 1e-6, bodies: ("a", "b")),
//!     )
//! "#).unwrap();
//! assert_eq!(scene.run().steps, 100);
//! assert_eq!(scene.model().bodies.len(), 2);
//! ```

mod build;
mod build_body;
mod build_run;
mod error;
pub(crate) mod file;
mod file_body;
mod model;
mod overlap;
mod parameters;
mod record;

use std::path::Path;

pub use crate::input::{read_text, ReadError, MAX_DATA_BYTES, MAX_SCENE_BYTES};
pub use build::{MAX_MAGNITUDE, MAX_NAME_BYTES, MAX_SOLVER_ITERATIONS, MIN_MAGNITUDE};
pub use build_body::{KEYFRAME_TIME_TOLERANCE, KEYFRAME_TURN_MARGIN, MAX_TORUS_SEGMENTS};
pub use error::SceneError;
pub use file::{OnContact, PlotSettings, DEFAULT_FRICTION, DEFAULT_SOLVER_ITERATIONS};
pub use overlap::{initial_overlaps, InitialOverlap};
pub use parameters::StepParameters;
pub use record::{set_expectation, RECORDED_COMMENT};

use crate::math::Real;
use crate::mesh::{DistanceKernel, TriMesh};
use crate::motion::Integrator;
pub use model::{
    Axis, Body, BodyMotion, Expectation, InitialOverlapPolicy, KeyframePath, Material, Model, NearMissSpec,
    PlotSpec, PosesSpec, RunSpec, Scene, TraceSpec,
};

/// The `source` of a scene read by [`Scene::from_ron_str`] (no file).
pub const FROM_STRING: &str = "<string>";

/// The most steps a run may take unless the caller allows more
/// (`nearmiss run --max-steps`): 100 million. A scene asking for more is
/// most likely a typo in `dt` or `duration`; even a scene of two bodies
/// would run for hours.
pub const DEFAULT_MAX_STEPS: u64 = 100_000_000;

/// The most records a run's trace (pairs × samples) or poses (bodies ×
/// samples) may keep: 100 million, about 5.6 GB of trace records in memory
/// and more as CSV. A scene asking for more (every pair of a 10,000-body
/// scene: 50 million a sample) is refused at load with the count, instead
/// of running out of memory mid-run.
pub const MAX_RECORDS: u64 = 100_000_000;

/// The most records `count` pairs or bodies sampled every `every` of
/// `steps` steps keep: the first state, every `every` steps, the last step
/// and a contact that ends the run.
pub(crate) fn most_records(count: u64, steps: u64, every: u64) -> u64 {
    count.saturating_mul(steps / every + 2)
}

/// A mesh of a scene as it was read: zero-area triangles kept (each takes
/// part as the segment or point it spans) and faces of fewer than three
/// vertices dropped ([`Scene::mesh_notes`]).
#[derive(Clone, Debug, PartialEq, Eq, serde::Serialize)]
pub struct MeshNote {
    /// The bodies that use the mesh.
    pub bodies: Vec<String>,
    /// Its triangles of exactly zero area, kept.
    pub zero_area_triangles: usize,
    /// Faces of its file with fewer than three vertices, dropped.
    pub dropped_faces: usize,
}

impl std::fmt::Display for MeshNote {
    /// `the mesh of bodies a, b: 3 triangles of zero area (kept: each is the
    /// segment or point it spans); 2 faces of fewer than 3 vertices (dropped)`.
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        let plural = |n: usize, one: &'static str, many: &'static str| if n == 1 { one } else { many };
        let names = self.bodies.iter().map(|b| format!("`{b}`")).collect::<Vec<_>>().join(", ");
        write!(f, "the mesh of {} {names}:", plural(self.bodies.len(), "body", "bodies"))?;
        let mut parts = Vec::new();
        if self.zero_area_triangles > 0 {
            let n = self.zero_area_triangles;
            parts.push(format!(
                " {n} {} of zero area (kept: each is the segment or point it spans)",
                plural(n, "triangle", "triangles")
            ));
        }
        if self.dropped_faces > 0 {
            let n = self.dropped_faces;
            parts.push(format!(
                " {n} {} of fewer than 3 vertices in its file (dropped: a point or a line is no face)",
                plural(n, "face", "faces")
            ));
        }
        write!(f, "{}", parts.join(";"))
    }
}

/// The steps of `dt` that cover `duration` (at least one).
pub(crate) fn steps_for(duration: Real, dt: Real) -> u64 {
    ((duration / dt) * (1.0 - 4.0 * Real::EPSILON)).ceil().max(1.0) as u64
}

impl Scene {
    /// What is simulated: the bodies, the step, the engine's settings
    /// (read-only: a scene is validated as a whole; [`Scene::with_settings`]
    /// and [`Scene::with_trace`] make changed copies).
    pub fn model(&self) -> &Model {
        &self.model
    }

    /// The pairs of bodies that overlap at time 0, with their depth where
    /// both meshes are convex (see [`initial_overlaps`]).
    pub fn initial_overlaps(&self) -> Vec<InitialOverlap> {
        initial_overlaps(&self.model.bodies)
    }

    /// The meshes that hold zero-area triangles or whose files had faces
    /// of fewer than three vertices, once per mesh (bodies that share one
    /// are named together), in the order of the bodies.
    pub fn mesh_notes(&self) -> Vec<MeshNote> {
        let mut notes: Vec<(*const TriMesh, MeshNote)> = Vec::new();
        for body in self.model.bodies.iter() {
            let mesh = &body.mesh;
            if mesh.zero_area_triangles() == 0 && mesh.dropped_faces() == 0 {
                continue;
            }
            let key = std::sync::Arc::as_ptr(mesh);
            match notes.iter_mut().find(|(k, _)| *k == key) {
                Some((_, note)) => note.bodies.push(body.name.clone()),
                None => notes.push((
                    key,
                    MeshNote {
                        bodies: vec![body.name.clone()],
                        zero_area_triangles: mesh.zero_area_triangles(),
                        dropped_faces: mesh.dropped_faces(),
                    },
                )),
            }
        }
        notes.into_iter().map(|(_, note)| note).collect()
    }

    /// What a run of it covers and writes: its name, length, trace, plot,
    /// poses and expectation.
    pub fn run(&self) -> &RunSpec {
        &self.run
    }

    /// The scene's two halves (what is simulated, and what the run
    /// records), for callers that take them apart.
    pub fn into_parts(self) -> (Model, RunSpec) {
        (self.model, self.run)
    }

    /// Parses and validates a scene; OBJ paths are relative to the current
    /// directory.
    pub fn from_ron_str(text: &str) -> Result<Scene, SceneError> {
        build::build(text, FROM_STRING, Path::new("."))
    }

    /// Reads, parses and validates a scene file; OBJ paths are relative to
    /// the file's folder.
    pub fn load(path: impl AsRef<Path>) -> Result<Scene, SceneError> {
        let path = path.as_ref();
        let name = path.display().to_string();
        let text =
            crate::input::read_text(path, crate::input::MAX_SCENE_BYTES, "scene file").map_err(|error| {
                match error {
                    crate::input::ReadError::NotUtf8 { line, column } => SceneError::Syntax {
                        path: name.clone(),
                        line,
                        column,
                        message: "not valid UTF-8 text".into(),
                    },
                    other => SceneError::Io { path: name.clone(), source: other.into_io() },
                }
            })?;
        let base = path.parent().unwrap_or(Path::new("."));
        build::build(&text, &path.display().to_string(), base)
    }

    /// The same scene with another step, kernel and integrator (the number
    /// of steps recomputed to cover the same duration).
    pub fn with_settings(&self, dt: Real, kernel: DistanceKernel, integrator: Integrator) -> Scene {
        let mut scene = self.clone();
        scene.model.dt = dt;
        scene.run.steps = steps_for(self.run.duration, dt);
        scene.run.steps_given = false;
        scene.model.kernel = kernel;
        scene.model.integrator = integrator;
        scene
    }

    /// The same scene stepped with other [`StepParameters`] (how the work
    /// is done: thresholds for threads, the broad phase's rounding and the
    /// like; not part of the file format).
    ///
    /// [`StepParameters`]: StepParameters
    pub fn with_parameters(&self, parameters: StepParameters) -> Scene {
        let mut scene = self.clone();
        scene.model.parameters = parameters;
        scene
    }

    /// The same scene stopping at its first contact (`on_contact: Stop`),
    /// as `nearmiss test --record` runs it.
    pub fn stopping_at_first_contact(&self) -> Scene {
        let mut scene = self.clone();
        scene.model.on_contact = OnContact::Stop;
        scene
    }

    /// The same scene with another distance trace (or none). The pairs are
    /// body indices `i < j` of this scene; a pair out of range or repeated
    /// is refused with the field named.
    pub fn with_trace(&self, trace: Option<TraceSpec>) -> Result<Scene, SceneError> {
        if let Some(spec) = &trace {
            let n = self.model.bodies.len();
            let mut seen = std::collections::HashSet::new();
            for &(i, j) in &spec.pairs {
                if !(i < j && j < n && seen.insert((i, j))) {
                    return Err(SceneError::Invalid {
                        path: self.run.source.clone(),
                        field: "trace.pairs".into(),
                        message: format!(
                            "({i}, {j}) is not a pair of distinct bodies i < j of the {n} bodies, each once"
                        ),
                    });
                }
            }
            if spec.every == 0 {
                return Err(SceneError::Invalid {
                    path: self.run.source.clone(),
                    field: "trace.every".into(),
                    message: "must be at least 1".into(),
                });
            }
        }
        let mut scene = self.clone();
        scene.run.trace = trace;
        Ok(scene)
    }

    /// The same scene with another pose record (or none); `every` at least 1.
    pub fn with_poses(&self, poses: Option<PosesSpec>) -> Result<Scene, SceneError> {
        if poses.as_ref().is_some_and(|p| p.every == 0) {
            return Err(SceneError::Invalid {
                path: self.run.source.clone(),
                field: "poses.every".into(),
                message: "must be at least 1".into(),
            });
        }
        let mut scene = self.clone();
        scene.run.poses = poses;
        Ok(scene)
    }

    /// [`Scene::load`], refused if the run would take more than `max_steps`
    /// steps ([`Scene::check_steps`]).
    pub fn load_within(path: impl AsRef<Path>, max_steps: u64) -> Result<Scene, SceneError> {
        let scene = Scene::load(path)?;
        scene.check_steps(max_steps)?;
        Ok(scene)
    }

    /// Checks that the run takes at most `max_steps` steps (see
    /// [`DEFAULT_MAX_STEPS`]); the error names the field and the limit.
    pub fn check_steps(&self, max_steps: u64) -> Result<(), SceneError> {
        if self.run.steps <= max_steps {
            return Ok(());
        }
        Err(SceneError::Invalid {
            path: self.run.source.clone(),
            field: if self.run.steps_given { "steps" } else { "duration" }.into(),
            message: match self.run.steps_given {
                true => format!(
                    "{} steps are more than the limit of {max_steps}: check `steps`, or allow more with --max-steps",
                    self.run.steps
                ),
                false => format!(
                    "the run would take {} steps (duration {} / dt {}), more than the limit of {max_steps}: check `dt` and `duration`, or allow more with --max-steps",
                    self.run.steps,
                    crate::math::shortest(self.run.duration),
                    crate::math::shortest(self.model.dt)
                ),
            },
        })
    }

    /// The most records the scene's trace or its poses (the larger of the
    /// two, each held to [`MAX_RECORDS`]) keep over a run of `steps` steps.
    pub fn most_records(&self, steps: u64) -> u64 {
        let trace = self.run.trace.as_ref().map_or(0, |t| most_records(t.pairs.len() as u64, steps, t.every));
        let poses = self
            .run
            .poses
            .as_ref()
            .map_or(0, |p| most_records(self.model.bodies.len() as u64, steps, p.every));
        trace.max(poses)
    }

    /// The index of the body with this name.
    pub fn body_index(&self, name: &str) -> Option<usize> {
        self.model.bodies.iter().position(|b| b.name == name)
    }
}

impl Model {
    /// Every pair of bodies that can touch (not both fixed), `i < j`.
    pub fn movable_pairs(&self) -> Vec<(usize, usize)> {
        let n = self.bodies.len();
        let fixed = |i: usize| self.bodies[i].motion == BodyMotion::Fixed;
        (0..n)
            .flat_map(|i| (i + 1..n).map(move |j| (i, j)))
            .filter(|&(i, j)| !(fixed(i) && fixed(j)))
            .collect()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn two_boxes() -> Scene {
        Scene::from_ron_str(
            r#"Scene(name: "s", dt: 0.01, duration: 1.0, bodies: [
                (name: "a", mesh: Box(half_extents: (0.5, 0.5, 0.5)), velocity: (1.0, 0.0, 0.0)),
                (name: "b", mesh: Box(half_extents: (0.5, 0.5, 0.5)), position: (2.0, 0.0, 0.0), fixed: true),
            ])"#,
        )
        .unwrap()
    }

    /// A changed copy is validated as the file would be: pairs of distinct
    /// bodies in range, each once, and a positive sampling interval.
    #[test]
    fn changed_copies_are_validated() {
        let scene = two_boxes();
        let trace = |pairs: Vec<(usize, usize)>, every| Some(TraceSpec { pairs, every, reference: false });
        assert_eq!(scene.with_trace(trace(vec![(0, 1)], 5)).unwrap().run().trace.as_ref().unwrap().every, 5);
        for (pairs, every, field) in [
            (vec![(0, 2)], 1, "trace.pairs"),
            (vec![(1, 0)], 1, "trace.pairs"),
            (vec![(0, 0)], 1, "trace.pairs"),
            (vec![(0, 1), (0, 1)], 1, "trace.pairs"),
            (vec![(0, 1)], 0, "trace.every"),
        ] {
            match scene.with_trace(trace(pairs.clone(), every)) {
                Err(SceneError::Invalid { field: f, .. }) => assert_eq!(f, field, "{pairs:?} every {every}"),
                other => panic!("{pairs:?} every {every}: {other:?}"),
            }
        }
        assert!(scene.with_poses(Some(PosesSpec { every: 0 })).is_err());
        assert!(scene.with_trace(None).unwrap().run().trace.is_none());
        assert_eq!(scene.run().up, Axis::Z, "no gravity: Z");
        let stopping = scene.stopping_at_first_contact();
        assert_eq!(stopping.model().on_contact, OnContact::Stop);
    }

    /// The up axis is the scene's word, or against gravity along an axis,
    /// or Z.
    #[test]
    fn the_up_axis_is_stated_or_against_gravity() {
        let text = |extra: &str| {
            format!(
                r#"Scene(name: "s", dt: 0.01, steps: 1, {extra} bodies: [(name: "a", mesh: Box(half_extents: (0.5, 0.5, 0.5)))])"#
            )
        };
        let up = |extra: &str| Scene::from_ron_str(&text(extra)).map(|s| s.run().up);
        assert_eq!(up("gravity: (0.0, -9.81, 0.0),").unwrap(), Axis::Y);
        assert_eq!(up("gravity: (-1.0, 0.0, 0.0),").unwrap(), Axis::X);
        assert_eq!(up("gravity: (0.0, 0.0, -9.81),").unwrap(), Axis::Z);
        assert_eq!(up("gravity: (0.0, 1.0, -9.81),").unwrap(), Axis::Z, "not along an axis");
        assert_eq!(up("gravity: (0.0, 9.81, 0.0),").unwrap(), Axis::Z, "pulling up: no up axis to infer");
        assert_eq!(up("gravity: (0.0, -9.81, 0.0), up: X,").unwrap(), Axis::X);
        let error = up("up: W,").unwrap_err().to_string();
        assert!(error.contains("W") && error.contains("1:"), "{error}");
    }
}

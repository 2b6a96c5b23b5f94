//! Distance-over-time records: the observer that samples them during a
//! run (the stepper calls it after each step), and their CSV writer.
//!
//! A sample is the distance of each traced pair by the scene's kernel at
//! the step's end (every `every` steps, at the start and the last step, and
//! at a contact that ends the run); with `reference`, also the exact
//! distance of the closest triangle pair in rational arithmetic.

use std::io::Write;
use std::sync::Arc;
use std::time::Instant;

use crate::math::Real;
use crate::mesh::{mesh_distance_relative, DistanceKernel, DistanceSearch, MeshDistanceScratch};
use crate::motion::StepMotion;
use crate::scene::{Scene, TraceSpec};

/// One distance sample of a traced pair.
#[derive(Copy, Clone, Debug, PartialEq)]
pub struct TraceRecord {
    /// The step after which it was taken (0: the initial state).
    pub step: u64,
    /// The time.
    pub time: Real,
    /// The pair (body indices).
    pub pair: (usize, usize),
    /// The distance between the two meshes (by the scene's kernel).
    pub distance: Real,
    /// The exact distance (rational arithmetic on the closest triangle
    /// pair, rounded), when the trace asks for it.
    pub reference: Option<Real>,
}

/// Samples a run's trace. Built only for a scene that asks for a trace.
#[derive(Debug)]
pub struct TraceObserver {
    scene: Arc<Scene>,
    spec: TraceSpec,
    records: Vec<TraceRecord>,
    scratch: MeshDistanceScratch,
    /// Each traced pair's closest triangle pair at its last sample: the
    /// next sample's search starts from it (its distance bounds the search
    /// at once, so the BVH descent prunes most of both meshes).
    hints: Vec<Option<(usize, usize)>>,
    /// Mesh distance queries made.
    pub distance_queries: usize,
    /// Seconds spent sampling.
    pub seconds: Real,
}

impl TraceObserver {
    /// The observer of `scene`'s trace, or `None` if it asks for none.
    pub fn of(scene: &Arc<Scene>) -> Option<TraceObserver> {
        scene.trace.clone().map(|spec| TraceObserver {
            hints: vec![None; spec.pairs.len()],
            scene: Arc::clone(scene),
            spec,
            records: Vec::new(),
            scratch: MeshDistanceScratch::default(),
            distance_queries: 0,
            seconds: 0.0,
        })
    }

    /// After step `step` (1-based count of steps done) ending at `time`:
    /// samples if the cadence asks for it.
    pub fn step_done(&mut self, step: u64, time: Real, motions: &[StepMotion]) {
        if step % self.spec.every == 0 || step == self.scene.steps {
            self.sample(step, time, self.scene.dt, motions);
        }
    }

    /// Appends one sample per traced pair, the bodies at time `s` into
    /// their current step motions (`time` in all), after `step` steps.
    pub fn sample(&mut self, step: u64, time: Real, s: Real, motions: &[StepMotion]) {
        let clock = Instant::now();
        let scene = &*self.scene;
        for (k, &(a, b)) in self.spec.pairs.iter().enumerate() {
            let pos_ab = StepMotion::relative_pose(&motions[a], &motions[b], s);
            let (mesh_a, mesh_b) = (&scene.bodies[a].mesh, &scene.bodies[b].mesh);
            let search = DistanceSearch::new(scene.kernel, self.hints[k]);
            let d = mesh_distance_relative(mesh_a, mesh_b, &pos_ab, &search, &mut self.scratch);
            self.hints[k] = Some((d.triangle_a, d.triangle_b));
            self.distance_queries += 1;
            let reference = self.spec.reference.then(|| {
                let exact = DistanceSearch::new(DistanceKernel::Exact, None);
                let exact = mesh_distance_relative(mesh_a, mesh_b, &pos_ab, &exact, &mut self.scratch);
                // The closest pair as the kernels see it: b in a's frame.
                let tb = mesh_b.triangle(exact.triangle_b).map(|p| pos_ab * p);
                crate::exact::triangle_distance_f64(&mesh_a.triangle(exact.triangle_a), &tb)
            });
            self.records.push(TraceRecord { step, time, pair: (a, b), distance: d.distance, reference });
        }
        self.seconds += clock.elapsed().as_secs_f64();
    }

    /// The samples taken.
    pub fn into_records(self) -> Vec<TraceRecord> {
        self.records
    }
}

/// Writes `step,time,body_a,body_b,distance` lines with a header; numbers
/// in the shortest form that reads back to the same `f64`.
pub fn write_trace_csv(
    records: &[TraceRecord],
    bodies: &[String],
    out: &mut impl Write,
) -> std::io::Result<()> {
    writeln!(out, "step,time,body_a,body_b,distance")?;
    for r in records {
        writeln!(out, "{},{:?},{},{},{:?}", r.step, r.time, bodies[r.pair.0], bodies[r.pair.1], r.distance)?;
    }
    Ok(())
}

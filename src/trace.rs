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

use crate::ccd::{first_within, hull_gap};
use crate::math::{Real, Vector};
use crate::mesh::{
    mesh_distance_relative, triangle_pair_distance, DistanceKernel, DistanceSearch, MeshDistanceScratch,
};
use crate::motion::StepMotion;
use crate::scene::{Scene, TraceSpec};

/// A sample is certified without a search when the hulls' gap is within
/// this many ulps of the pair's scale (the centres' distance plus both
/// radii) below the last closest triangle pair's distance: the rounding of
/// the two computations, not geometry.
pub const CERTIFICATE_ULPS: Real = 64.0;

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
    /// Each traced pair's last hull-gap direction (world frame).
    axes: Vec<Option<Vector>>,
    /// Samples settled by the certificate (see [`TraceObserver::sample`]).
    pub certified: usize,
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
            axes: vec![None; spec.pairs.len()],
            certified: 0,
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
    ///
    /// A sample is the smallest kernel distance over the two meshes'
    /// triangle pairs. It starts from the pair's last closest triangle pair:
    /// when the gap between the two meshes' vertex hulls (GJK, a lower
    /// bound on every triangle pair's distance) comes within
    /// [`CERTIFICATE_ULPS`] ulps of the pair's scale of that pair's
    /// distance, that distance is the smallest (to that rounding) and no
    /// search is needed: the usual case for convex meshes, near or far;
    /// otherwise (and with a DyOP kernel) the BVH search runs, seeded with
    /// it.
    pub fn sample(&mut self, step: u64, time: Real, s: Real, motions: &[StepMotion]) {
        let clock = Instant::now();
        let scene = Arc::clone(&self.scene);
        let scene = &*scene;
        for k in 0..self.spec.pairs.len() {
            let (a, b) = self.spec.pairs[k];
            let pos_ab = StepMotion::relative_pose(&motions[a], &motions[b], s);
            let (mesh_a, mesh_b) = (&scene.bodies[a].mesh, &scene.bodies[b].mesh);
            let distance = match self.certify(k, (a, b), &pos_ab, &motions[a].rotation_at(s)) {
                Some(distance) => {
                    self.certified += 1;
                    distance
                }
                None => {
                    let search = DistanceSearch::new(scene.kernel, self.hints[k]);
                    let d = mesh_distance_relative(mesh_a, mesh_b, &pos_ab, &search, &mut self.scratch);
                    self.hints[k] = Some((d.triangle_a, d.triangle_b));
                    d.distance
                }
            };
            self.distance_queries += 1;
            let reference = self.spec.reference.then(|| {
                let exact = DistanceSearch::new(DistanceKernel::Exact, self.hints[k]);
                let exact = mesh_distance_relative(mesh_a, mesh_b, &pos_ab, &exact, &mut self.scratch);
                // The closest pair as the kernels see it: b in a's frame.
                let tb = mesh_b.triangle(exact.triangle_b).map(|p| pos_ab * p);
                crate::exact::triangle_distance_f64(&mesh_a.triangle(exact.triangle_a), &tb)
            });
            self.records.push(TraceRecord { step, time, pair: (a, b), distance, reference });
        }
        self.seconds += clock.elapsed().as_secs_f64();
    }

    /// The distance of traced pair `k` = `(a, b)` at `pos_ab` (`rotation_a`:
    /// a's orientation) without a search, if the certificate holds (see
    /// [`TraceObserver::sample`]): from the pair's last closest triangle
    /// pair, then from the triangles around the hulls' closest vertices.
    fn certify(
        &mut self,
        k: usize,
        (a, b): (usize, usize),
        pos_ab: &crate::math::Pose,
        rotation_a: &nalgebra::UnitQuaternion<Real>,
    ) -> Option<Real> {
        let scene = Arc::clone(&self.scene);
        let scene = &*scene;
        // The certificate holds for the exact kernel's values (DyOP's own
        // error may exceed its slack: always searched).
        if scene.kernel != DistanceKernel::Exact {
            return None;
        }
        let (mesh_a, mesh_b) = (&scene.bodies[a].mesh, &scene.bodies[b].mesh);
        let scale = pos_ab.translation.vector.norm() + mesh_a.radius() + mesh_b.radius();
        let slack = CERTIFICATE_ULPS * Real::EPSILON * scale;
        let mut best = self.hints[k]
            .map(|(i, j)| (triangle_pair_distance(mesh_a, i, mesh_b, j, pos_ab).distance, (i, j)));
        let mut axis = self.axes[k].map(|axis| rotation_a.inverse_transform_vector(&axis));
        for _ in 0..2 {
            let wanted = best.map_or(Real::INFINITY, |(d, _)| d - slack);
            // Converged (no early stop where the hulls come closer than a
            // stale pair): only then can its bound certify a pair.
            let gap = hull_gap(mesh_a, mesh_b, pos_ab, axis, (0.0, wanted));
            axis = gap.axis.or(axis);
            if let Some(axis) = gap.axis {
                self.axes[k] = Some(rotation_a * axis);
            }
            let certified = |best: Option<(Real, (usize, usize))>| {
                best.filter(|&(d, _)| d > 0.0 && gap.lower >= d - slack)
            };
            if let Some((d, pair)) = certified(best) {
                self.hints[k] = Some(pair);
                return Some(d);
            }
            // The triangles around the hulls' closest vertices.
            let (va, vb) = gap.support?;
            let enough = gap.lower + slack;
            if let Some((d, pair)) = first_within((mesh_a, va), (mesh_b, vb), pos_ab, gap.axis, enough).found
            {
                if best.is_none_or(|(b, _)| d < b) {
                    best = Some((d, pair));
                }
            }
            if let Some((d, pair)) = certified(best) {
                self.hints[k] = Some(pair);
                return Some(d);
            }
        }
        None
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

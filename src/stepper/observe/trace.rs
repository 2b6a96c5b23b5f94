//! Distance-over-time records: the observer that samples them during a
//! run (the stepper calls it after each step), and their CSV writer.
//!
//! A sample is the distance of each traced pair by the scene's kernel at
//! the step's end (every `every` steps, at the start and the last step, and
//! at a contact that ends the run); with `reference`, also the exact
//! distance of the closest triangle pair in rational arithmetic. Each pair
//! keeps what its last sample found (closest triangles, GJK's simplex and
//! direction), so a sample is a warm start, not a search from scratch (see
//! [`TraceObserver::sample`]).

use std::cell::RefCell;
use std::io::Write;
use std::sync::Arc;
use std::time::Instant;

use nalgebra::UnitQuaternion;
use rayon::prelude::*;

use crate::ccd::{convex_distance, first_within, hull_gap, ConvexDistance, WarmSimplex};
use crate::math::{Pose, Real, Vector};
use crate::mesh::{
    mesh_distance_relative, overlap_beyond, triangle_pair_distance, DistanceKernel, DistanceSearch,
    MeshDistanceScratch, SignedDistanceScratch, TriMesh,
};
use crate::motion::StepMotion;
use crate::scene::{Model, RunSpec, TraceSpec};

/// A sample is certified without a search when the hulls' gap is within
/// this many ulps of the pair's scale (the centres' distance plus both
/// radii) below the last closest triangle pair's distance: the rounding of
/// the two computations, not geometry.
pub(crate) const CERTIFICATE_ULPS: Real = 64.0;

/// One distance sample of a traced pair.
#[derive(Copy, Clone, Debug, PartialEq)]
pub struct TraceRecord {
    /// The step after which it was taken (0: the initial state).
    pub step: u64,
    /// The time.
    pub time: Real,
    /// The pair (body indices).
    pub pair: (usize, usize),
    /// The distance between the two meshes (by the scene's kernel); where
    /// they overlap, minus the depth (see [`crate::mesh::signed_distance`]:
    /// exact for convex pairs, the deepest local depth's lower end for
    /// closed ones; 0 where an open mesh crosses).
    pub distance: Real,
    /// The exact distance (rational arithmetic on the closest triangle
    /// pair, rounded), when the trace asks for it: the surfaces' distance
    /// (0 where the meshes overlap, whatever their depth).
    pub reference: Option<Real>,
}

/// Samples a run's trace. Built only for a scene that asks for a trace.
#[derive(Debug)]
pub struct TraceObserver {
    model: Arc<Model>,
    spec: TraceSpec,
    /// The run's steps (its last step is always sampled).
    steps: u64,
    records: Vec<TraceRecord>,
    /// What each traced pair's next sample starts from.
    states: Vec<PairTrace>,
    /// Sample the pairs on rayon's threads (the run's `parallel` option)
    /// from this many pairs on ([`RunOptions::parallel_trace_pairs`]).
    ///
    /// [`RunOptions::parallel_trace_pairs`]: crate::stepper::RunOptions::parallel_trace_pairs
    parallel_from: Option<usize>,
    /// The bodies in traced pairs (each once, in order).
    traced_bodies: Vec<usize>,
    /// Kept between samples: the bodies' orientations at the sample's time
    /// (set for the traced bodies), the sequential path's search scratch,
    /// and the samples' results.
    rotations: Vec<UnitQuaternion<Real>>,
    scratch: SampleScratch,
    samples: Vec<PairSample>,
    /// Samples settled without a search: by the convex meshes' GJK bounds
    /// or by the hulls' certificate (see [`TraceObserver::sample`]).
    pub certified: usize,
    /// Mesh distance queries made.
    pub distance_queries: usize,
    /// Seconds spent sampling.
    pub seconds: Real,
}

/// One traced pair's state between samples.
#[derive(Copy, Clone, Debug, Default)]
struct PairTrace {
    /// The closest triangle pair at its last search or certificate: the
    /// next search starts from it (its distance bounds the search at once,
    /// so the BVH descent prunes most of both meshes).
    hint: Option<(usize, usize)>,
    /// The last hull-gap direction (world frame).
    axis: Option<Vector>,
    /// GJK's last simplex, for two convex meshes.
    warm: WarmSimplex,
}

/// One pair's sample, before it becomes a record.
#[derive(Copy, Clone, Debug)]
struct PairSample {
    distance: Real,
    reference: Option<Real>,
    certified: bool,
}

/// What every pair's sample in one call shares: the scene, the motions,
/// the bodies' orientations and the time.
struct SampleAt<'a> {
    model: &'a Model,
    motions: &'a [StepMotion],
    rotations: &'a [UnitQuaternion<Real>],
    s: Real,
    reference: bool,
}

impl TraceObserver {
    /// The observer of the trace `run` asks for on `model` (its pairs
    /// sampled on rayon's threads from `parallel_from` pairs on; the
    /// samples are the same either way), or `None` if it asks for none.
    pub fn of(model: &Arc<Model>, run: &RunSpec, parallel_from: Option<usize>) -> Option<TraceObserver> {
        run.trace.clone().map(|spec| TraceObserver {
            steps: run.steps,
            states: vec![PairTrace::default(); spec.pairs.len()],
            parallel_from,
            traced_bodies: {
                let mut bodies: Vec<usize> = spec.pairs.iter().flat_map(|&(a, b)| [a, b]).collect();
                bodies.sort_unstable();
                bodies.dedup();
                bodies
            },
            rotations: vec![UnitQuaternion::identity(); model.bodies.len()],
            scratch: SampleScratch::default(),
            samples: Vec::new(),
            certified: 0,
            model: Arc::clone(model),
            spec,
            records: Vec::new(),
            distance_queries: 0,
            seconds: 0.0,
        })
    }

    /// After step `step` (1-based count of steps done) ending at `time`:
    /// samples if the cadence asks for it.
    pub fn step_done(&mut self, step: u64, time: Real, motions: &[StepMotion]) {
        if step.is_multiple_of(self.spec.every) || step == self.steps {
            self.sample(step, time, self.model.dt, motions);
        }
    }

    /// Appends one sample per traced pair, the bodies at time `s` into
    /// their current step motions (`time` in all), after `step` steps.
    ///
    /// A sample is the smallest kernel distance over the two meshes'
    /// triangle pairs, found by the first of these that settles it:
    /// - two convex meshes ([`TriMesh::is_convex`]), exact kernel: GJK on
    ///   the meshes themselves, started from the pair's last simplex, once
    ///   its upper bound (the distance between a point of each mesh) is
    ///   within [`CERTIFICATE_ULPS`] ulps of the pair's scale (the centres'
    ///   distance plus both radii) of its lower bound (a gap between the
    ///   two meshes' shadows on a direction); the sample is the upper
    ///   bound (for pairs nearer than [`CONVEX_VALUE_RELATIVE_ERROR`] asks,
    ///   the kernel's distance of the closest features' triangles, by the
    ///   next way). Where the closest features are the last sample's, this
    ///   costs two supports and the closest point of a simplex of at most
    ///   three points;
    /// - the hulls' certificate, exact kernel: when the gap between the two
    ///   meshes' vertex hulls (GJK, a lower bound on every triangle pair's
    ///   distance) comes within those ulps of the distance of the pair's
    ///   last closest triangle pair (or of one around the hulls' closest
    ///   vertices), that distance is the smallest (to that rounding);
    /// - otherwise (and with a DyOP kernel), the BVH search, seeded with the
    ///   pair's last closest triangle pair.
    ///
    /// With `reference` the convex path is skipped: the exact distance is
    /// that of the closest triangle pair, which the other two name.
    pub fn sample(&mut self, step: u64, time: Real, s: Real, motions: &[StepMotion]) {
        let clock = Instant::now();
        for &body in &self.traced_bodies {
            self.rotations[body] = motions[body].rotation_at(s);
        }
        let at = SampleAt {
            model: &self.model,
            motions,
            rotations: &self.rotations,
            s,
            reference: self.spec.reference,
        };
        let pairs = &self.spec.pairs;
        if self.parallel_from.is_some_and(|from| pairs.len() >= from) {
            self.states
                .par_iter_mut()
                .zip(pairs.par_iter())
                .map(|(state, &pair)| {
                    THREAD_SCRATCH.with(|scratch| at.pair_sample(pair, state, &mut scratch.borrow_mut()))
                })
                .collect_into_vec(&mut self.samples);
        } else {
            self.samples.clear();
            let scratch = &mut self.scratch;
            self.samples.extend(
                self.states.iter_mut().zip(pairs).map(|(state, &pair)| at.pair_sample(pair, state, scratch)),
            );
        }
        for (sample, &pair) in self.samples.iter().zip(pairs) {
            self.certified += usize::from(sample.certified);
            self.records.push(TraceRecord {
                step,
                time,
                pair,
                distance: sample.distance,
                reference: sample.reference,
            });
        }
        self.distance_queries += pairs.len();
        self.seconds += clock.elapsed().as_secs_f64();
    }

    /// The samples taken.
    pub fn into_records(self) -> Vec<TraceRecord> {
        self.records
    }
}

/// Two convex meshes' sample is GJK's certified upper bound when the
/// certificate's slack is at most this fraction of it: within the accuracy
/// the exact kernel states (its plain pass is used above 1e-3 of the pair's
/// extent for the same reason). Nearer pairs take the kernel's distance of
/// the closest features' triangles. Default `1e-12`.
pub(crate) const CONVEX_VALUE_RELATIVE_ERROR: Real = 1e-12;

thread_local! {
    /// Each rayon thread's search scratch, kept between samples and runs.
    static THREAD_SCRATCH: RefCell<SampleScratch> = RefCell::new(SampleScratch::default());
}

/// A sample's reusable buffers: the distance search's, and the signed
/// distance's where meshes overlap.
#[derive(Debug, Default)]
struct SampleScratch {
    distance: MeshDistanceScratch,
    signed: SignedDistanceScratch,
}

impl SampleAt<'_> {
    /// Pair `(a, b)`'s sample (see [`TraceObserver::sample`]).
    fn pair_sample(
        &self,
        (a, b): (usize, usize),
        state: &mut PairTrace,
        scratch: &mut SampleScratch,
    ) -> PairSample {
        let model = self.model;
        let pos_ab = StepMotion::relative_pose_turned(
            (&self.motions[a], &self.rotations[a]),
            (&self.motions[b], &self.rotations[b]),
            self.s,
        );
        let (mesh_a, mesh_b) = (&*model.bodies[a].mesh, &*model.bodies[b].mesh);
        let scale = pos_ab.translation.vector.norm() + mesh_a.radius() + mesh_b.radius();
        let slack = CERTIFICATE_ULPS * Real::EPSILON * scale;
        // The certificates hold for the exact kernel's values (DyOP's own
        // error may exceed their slack: always searched).
        let exact = model.kernel == DistanceKernel::Exact;
        if exact && !self.reference && mesh_a.is_convex() && mesh_b.is_convex() {
            if let ConvexDistance::Certified(upper) =
                convex_distance(mesh_a, mesh_b, &pos_ab, &mut state.warm, slack)
            {
                if slack <= CONVEX_VALUE_RELATIVE_ERROR * upper {
                    return PairSample { distance: upper, reference: None, certified: true };
                }
                // Near: the kernel's distance of triangles holding the
                // closest features (at most the upper bound, at least the
                // meshes' distance), which the hulls' certificate below
                // starts from.
                state.hint = state.warm.triangles(mesh_a, mesh_b).or(state.hint);
            }
        }
        let certified = exact.then(|| certify(state, (mesh_a, mesh_b), &pos_ab, &self.rotations[a], slack));
        let (distance, certified) = match certified.flatten() {
            Some(distance) => (distance, true),
            None => {
                let search = DistanceSearch::new(model.kernel, state.hint);
                let d = mesh_distance_relative(mesh_a, mesh_b, &pos_ab, &search, &mut scratch.distance);
                state.hint = Some((d.triangle_a, d.triangle_b));
                (d.distance, false)
            }
        };
        let reference = self.reference.then(|| {
            let exact = DistanceSearch::new(DistanceKernel::Exact, state.hint);
            let exact = mesh_distance_relative(mesh_a, mesh_b, &pos_ab, &exact, &mut scratch.distance);
            // The closest pair as the kernels see it: b in a's frame.
            let tb = mesh_b.triangle(exact.triangle_b).map(|p| pos_ab * p);
            crate::exact::triangle_distance_f64(&mesh_a.triangle(exact.triangle_a), &tb)
        });
        // Overlapping meshes: minus the depth (see `mesh::signed_distance`).
        let distance =
            overlap_beyond(mesh_a, &Pose::identity(), mesh_b, &pos_ab, distance, &mut scratch.signed)
                .map_or(distance, |(value, _)| value);
        PairSample { distance, reference, certified }
    }
}

/// The distance of a traced pair's meshes at `pos_ab` (`rotation_a`: a's
/// orientation) without a search, if the hulls' certificate holds within
/// `slack` (see [`TraceObserver::sample`]): from the pair's last closest
/// triangle pair, then from the triangles around the hulls' closest
/// vertices.
fn certify(
    state: &mut PairTrace,
    (mesh_a, mesh_b): (&TriMesh, &TriMesh),
    pos_ab: &Pose,
    rotation_a: &UnitQuaternion<Real>,
    slack: Real,
) -> Option<Real> {
    let mut best =
        state.hint.map(|(i, j)| (triangle_pair_distance(mesh_a, i, mesh_b, j, pos_ab).distance, (i, j)));
    let mut axis = state.axis.map(|axis| rotation_a.inverse_transform_vector(&axis));
    for _ in 0..2 {
        let wanted = best.map_or(Real::INFINITY, |(d, _)| d - slack);
        // Converged (no early stop where the hulls come closer than a
        // stale pair): only then can its bound certify a pair.
        let gap = hull_gap(mesh_a, mesh_b, pos_ab, axis, (0.0, wanted));
        axis = gap.axis.or(axis);
        if let Some(axis) = gap.axis {
            state.axis = Some(rotation_a * axis);
        }
        let certified =
            |best: Option<(Real, (usize, usize))>| best.filter(|&(d, _)| d > 0.0 && gap.lower >= d - slack);
        if let Some((d, pair)) = certified(best) {
            state.hint = Some(pair);
            return Some(d);
        }
        // The triangles around the hulls' closest vertices.
        let (va, vb) = gap.support?;
        let enough = gap.lower + slack;
        if let Some((d, pair)) = first_within((mesh_a, va), (mesh_b, vb), pos_ab, gap.axis, enough).found {
            if best.is_none_or(|(b, _)| d < b) {
                best = Some((d, pair));
            }
        }
        if let Some((d, pair)) = certified(best) {
            state.hint = Some(pair);
            return Some(d);
        }
    }
    None
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

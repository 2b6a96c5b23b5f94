//! What a run returns: contacts, why it ended, work counters.

use crate::ccd::CcdStatus;
use crate::math::{Pose, Real};
use crate::mesh::MeshDistance;
use crate::motion::RigidState;
use crate::stepper::observe::poses::PoseRecord;
use crate::stepper::observe::trace::TraceRecord;

/// The outside engine that solved a run's contact response.
#[derive(Clone, Debug, PartialEq)]
pub struct Solver {
    /// The engine and its version (`rapier3d-f64 0.36`).
    pub engine: String,
    /// Per body, the collider shape the engine was given.
    pub colliders: Vec<String>,
    /// Each collider's contact skin (0 unless the scene asks for one; with
    /// skins the engine's contacts start two skins apart, where the run's
    /// contacts are reported).
    pub contact_skin: Real,
    /// How many times the guard moved the world back to a contact and let
    /// the engine solve the rest of the step from there.
    pub rewinds: u64,
}

/// A contact event.
#[derive(Clone, Debug, PartialEq)]
pub struct Contact {
    /// The time of first contact (never later than the true one).
    pub time: Real,
    /// The first body (index into the scene's bodies; the lower index).
    pub body_a: usize,
    /// The second body.
    pub body_b: usize,
    /// The distance at `time` (at most the contact distance) and where:
    /// the closest points (world frame), the triangles (in their meshes'
    /// triangle order) and the features they lie on. Not necessarily the
    /// closest pair at `time`: the pair within the contact distance that
    /// stopped the search.
    pub closest: MeshDistance,
    /// How the CCD iteration ended.
    pub status: CcdStatus,
    /// The contact distance of the pair (`minimum_separation + tolerance`):
    /// no contact is reported farther apart.
    pub contact_distance: Real,
    /// Every approach of the pair closer than this (`minimum_separation +
    /// tolerance / 2`) is reported.
    pub guaranteed_distance: Real,
    /// The pose of `body_a`'s frame (its mesh's frame) at `time`.
    pub pose_a: Pose,
    /// The pose of `body_b`'s frame at `time`.
    pub pose_b: Pose,
}

/// Why a run ended.
#[non_exhaustive]
#[derive(Clone, Debug, PartialEq)]
pub enum Termination {
    /// All steps ran.
    Completed,
    /// Stopped at the first contact (`on_contact: Stop`).
    FirstContact,
    /// The CCD of a pair could not decide, within its iterations, whether
    /// the pair comes into contact in a step: the run stops there (not a
    /// contact; nothing after `time` is known).
    Undecided {
        /// The pair (body indices).
        pair: (usize, usize),
        /// Up to this time the pair was proven apart.
        time: Real,
        /// The step (0-based).
        step: u64,
        /// The iterations spent (`ccd.max_iterations`).
        iterations: usize,
    },
    /// A body's state stopped being usable: not finite, or turning too far
    /// in one step for the in-step motion to be defined.
    Diverged {
        /// The body.
        body: usize,
        /// The step at which it happened (0-based).
        step: u64,
        /// What happened.
        reason: String,
    },
    /// The driver failed during a step (the guard of a `Simulate` run
    /// refusing what it was handed): the run ends there, nothing after is
    /// known.
    Failed {
        /// The step (0-based).
        step: u64,
        /// Why.
        reason: String,
    },
    /// The run could not start: its driver could not be set up (a scene
    /// built by hand that `nearmiss::run::check` refuses, or rapier
    /// refusing a body). No step was made.
    NotStarted {
        /// Why.
        reason: String,
    },
}

/// Work and time per stage: `summary.json`'s `work` and
/// `stage_wall_time_s`, written as they are.
#[derive(Clone, Debug, Default, PartialEq, serde::Serialize)]
pub struct Counters {
    /// Work done (deterministic).
    pub work: Work,
    /// Seconds per stage (wall clock: not deterministic).
    pub seconds: StageSeconds,
}

/// The work of a run (deterministic: the same scene does the same work).
#[derive(Clone, Debug, Default, PartialEq, serde::Serialize)]
pub struct Work {
    /// Mesh queries: CCD advancement searches and trace distances.
    pub distance_queries: usize,
    /// Triangle pairs evaluated.
    pub triangle_pairs: usize,
    /// Pair-steps settled without a mesh query (spheres, carried bound or
    /// the hulls' gap).
    pub pairs_culled: usize,
    /// CCD advancement steps taken on the hulls' gap alone (one GJK each),
    /// before or instead of a search.
    pub hull_steps: usize,
    /// Steps where the implicit gyroscopic solve did not converge.
    pub gyroscopic_unconverged: usize,
    /// Pairs handed to CCD, summed over steps.
    pub candidate_pairs: usize,
    /// The largest drift of an integrated body's mechanical energy,
    /// `|E − E0|` over its initial energy scale (0 without integrated bodies).
    pub max_energy_drift: Real,
    /// Trace samples settled without a search: the gap between the two
    /// meshes' vertex hulls met the distance of a triangle pair (see
    /// `TraceObserver::sample`).
    pub trace_certified: usize,
}

impl Work {
    /// Adds one mesh CCD query's work: its search iterations, triangle
    /// pairs and steps on the hulls (a `MeshCcdResult`'s fields of those
    /// names).
    pub(crate) fn add_query(&mut self, iterations: usize, triangle_pairs: usize, hull_steps: usize) {
        self.distance_queries += iterations;
        self.triangle_pairs += triangle_pairs;
        self.hull_steps += hull_steps;
    }
}

/// Seconds spent per stage of the step.
#[derive(Clone, Debug, Default, PartialEq, serde::Serialize)]
pub struct StageSeconds {
    /// Integrating.
    pub integrate: Real,
    /// The broad phase.
    pub broad_phase: Real,
    /// CCD (the narrow phase).
    pub ccd: Real,
    /// The contact response (`Bounce`'s ordering, re-checks and impulses;
    /// recording contacts).
    pub respond: Real,
    /// Re-arming pairs that separated.
    pub rearm: Real,
    /// Tracing.
    pub trace: Real,
    /// The near misses' closest approaches.
    pub near_misses: Real,
    /// An outside engine's steps (`on_contact: Simulate`: rapier's dynamics
    /// and contact solving; a `Guard`'s `rapier_step`).
    pub engine: Real,
    /// A guard's work besides its sweeps (broad phase to re-arm): reading
    /// the engine's bodies into each step's motions, moving bodies back to
    /// a contact, holding them.
    pub engine_sync: Real,
}

impl StageSeconds {
    /// The stages of a sweep: broad phase, CCD, response and re-arm.
    pub fn sweep(&self) -> Real {
        self.broad_phase + self.ccd + self.respond + self.rearm
    }
}

/// The outcome of a run.
#[derive(Clone, Debug, PartialEq)]
pub struct RunResult {
    /// The scene's name.
    pub scene: String,
    /// The body names (for the indices in contacts and traces).
    pub bodies: Vec<String>,
    /// Steps taken (the last one possibly cut short by a contact).
    pub steps: u64,
    /// The time reached.
    pub end_time: Real,
    /// Wall-clock time of the run, in seconds.
    pub wall_time_s: Real,
    /// The earliest contact, if any.
    pub first_contact: Option<Contact>,
    /// Every contact in time order (only the first with `on_contact: Stop`).
    pub contacts: Vec<Contact>,
    /// The distance trace (empty unless the scene asks for one).
    pub trace: Vec<TraceRecord>,
    /// The bodies' poses (empty unless the scene asks for them).
    pub poses: Vec<PoseRecord>,
    /// Who solved the contact response, when an outside engine did
    /// (`on_contact: Simulate`).
    pub solver: Option<Solver>,
    /// Why the run ended.
    pub termination: Termination,
    /// Work and time per stage.
    pub counters: Counters,
    /// Each body at `end_time`.
    pub final_states: Vec<RigidState>,
    /// With `near_misses` in the scene: every pair that came within its
    /// distance without touching, nearest first.
    pub near_misses: Vec<crate::stepper::observe::near_miss::record::NearMiss>,
    /// The pairs of bodies that overlap at time 0, with their depth where
    /// both meshes are convex (computed once, before the first step).
    pub initial_overlaps: Vec<crate::scene::InitialOverlap>,
}

impl RunResult {
    /// How the run ended, as `summary.json`'s `termination` and the CLI's
    /// messages write it: `completed`, `first_contact`, `diverged at step
    /// ...` or `undecided at step ...` with what to do.
    pub fn termination_text(&self) -> String {
        match &self.termination {
            Termination::Completed => "completed".into(),
            Termination::FirstContact => "first_contact".into(),
            Termination::Diverged { step, reason, .. } => format!("diverged at step {step}: {reason}"),
            Termination::NotStarted { reason } => format!("not started: {reason}"),
            Termination::Failed { step, reason } => format!("failed at step {step}: {reason}"),
            Termination::Undecided { pair: (a, b), time, step, iterations } => format!(
                "undecided at step {step}: the CCD of `{}` / `{}` could not decide in {iterations} iterations whether they touch after t = {} (they are apart until then; nothing later is known). Raise `ccd.max_iterations`, lower `dt`, or raise `ccd.distance_tolerance`",
                self.bodies[*a], self.bodies[*b], crate::math::shortest(*time)
            ),
        }
    }

    /// The first number of a run's result that is not finite (which JSON would
    /// write as `null` and CSV as `inf`), named; `None` if all are finite.
    pub fn first_non_finite(&self) -> Option<String> {
        let contact_numbers = |c: &Contact| {
            [c.time, c.closest.distance, c.contact_distance, c.guaranteed_distance]
                .into_iter()
                .chain(c.closest.point_a.iter().copied())
                .chain(c.closest.point_b.iter().copied())
                .chain([&c.pose_a, &c.pose_b].into_iter().flat_map(|p| {
                    p.translation
                        .vector
                        .iter()
                        .chain(p.rotation.coords.iter())
                        .copied()
                        .collect::<Vec<Real>>()
                }))
                .collect::<Vec<Real>>()
        };
        if !self.end_time.is_finite() {
            return Some("end_time".into());
        }
        if let Some(k) = self.contacts.iter().position(|c| contact_numbers(c).iter().any(|v| !v.is_finite()))
        {
            return Some(format!("contacts[{k}]"));
        }
        if let Some(k) = self.trace.iter().position(|r| !r.time.is_finite() || !r.distance.is_finite()) {
            return Some(format!("trace sample {k}"));
        }
        let pose_numbers = |r: &PoseRecord| {
            r.position.iter().chain(r.orientation.coords.iter()).all(|v| v.is_finite()) && r.time.is_finite()
        };
        if let Some(k) = self.poses.iter().position(|r| !pose_numbers(r)) {
            return Some(format!("pose record {k}"));
        }
        (!self.counters.work.max_energy_drift.is_finite()).then(|| "work.max_energy_drift".into())
    }
}

//! The run's world state: the bodies' states and motions over the current
//! step, the pairs in play with what each carries between steps, and the
//! contacts found so far. The stages read and change it; the stepper's
//! scratch buffers live apart (`mod.rs`).

use super::result::Contact;
use crate::ccd::{MeshCcdResult, WarmSimplex, WarmStart};
use crate::math::{Point, Real, Vector};
use crate::motion::{RigidState, StepMotion};
use crate::scene::{Body, BodyMotion, Model};
use crate::stepper::respond::ImpactBody;

/// The world state of a run.
pub(crate) struct World {
    /// The bodies' states where the stepper keeps one (integrated bodies,
    /// and kinematic ones when the response can stop them); others `None`.
    pub states: Vec<Option<RigidState>>,
    /// Integrated bodies' initial energy and energy scale, where the
    /// energy is checked (empty otherwise).
    pub energies: Vec<(Real, Real)>,
    /// Each body's motion over the current step.
    pub motions: Vec<StepMotion>,
    /// The pairs in play, sorted by `(a, b)`: all pairs not both fixed,
    /// or with a broad phase the pairs whose swept boxes overlap.
    pub pairs: Vec<PairState>,
    /// The contacts found so far.
    pub contacts: Vec<Contact>,
    /// A pair whose CCD could not decide (the run ends after the step).
    pub undecided: Option<Undecided>,
    /// The pairs in contact that separated in the current step (re-armed,
    /// or apart for the whole step), `(a, b)`.
    pub separated: Vec<(usize, usize)>,
    /// The contacts the guard's response stops at in the current sweep:
    /// their pairs' dynamic bodies stay at their poses then for the rest of
    /// the step, their approach at the contact removed (read by the guard,
    /// which needs the `rapier` feature).
    #[cfg_attr(not(feature = "rapier"), allow(dead_code))]
    pub stops: Vec<GuardHit>,
    /// The pairs `(a, b)` the guard moved the world back to in the current
    /// step (their next contact in the step stops them).
    #[cfg_attr(not(feature = "rapier"), allow(dead_code))]
    pub rewound: Vec<(usize, usize)>,
    /// The guard may ask for a rewind in this sweep (it has substeps left;
    /// read by its response, which needs the `rapier` feature).
    #[cfg_attr(not(feature = "rapier"), allow(dead_code))]
    pub may_rewind: bool,
    /// The guard's response asks to move the world back to this contact's
    /// time into the sweep and let the engine solve from there.
    pub rewind: Option<GuardHit>,
}

/// A contact that needs the guard: the world goes back to it
/// (`World::rewind`) or its pair stops at it (`World::stops`). Read by the
/// guard, which needs the `rapier` feature.
#[derive(Copy, Clone, Debug)]
#[cfg_attr(not(feature = "rapier"), allow(dead_code))]
pub(crate) struct GuardHit {
    /// Time into the sweep.
    pub time: Real,
    /// The pair.
    pub a: usize,
    pub b: usize,
    /// The contact's point (world frame) and normal (from `a` towards
    /// `b`).
    pub point: Option<Point>,
    pub normal: Option<Vector>,
}

/// A CCD query that ran out of iterations: the pair (index into `pairs`),
/// the time into the step up to which it was proven apart, the iterations.
#[derive(Copy, Clone, Debug)]
pub(crate) struct Undecided {
    pub pair: (usize, usize),
    pub time: Real,
    pub iterations: usize,
}

/// What the CCD keeps per pair between steps.
#[derive(Clone, Debug)]
pub(crate) struct PairState {
    pub a: usize,
    pub b: usize,
    /// A lower bound on the distance at the start of the next step.
    pub lower_bound: Option<Real>,
    /// The last closest triangle pair.
    pub hint: Option<(usize, usize)>,
    /// The last direction of the hulls' gap (world frame).
    pub axis: Option<Vector>,
    /// The hulls' last GJK simplex.
    pub simplex: WarmSimplex,
    /// In contact (`on_contact: Record` or `Bounce`): not re-reported until
    /// it separates (`Bounce`: until it comes within a fraction of this
    /// distance).
    pub touching: Option<Touching>,
}

/// A pair in contact: one episode, from its first contact until it is
/// re-armed (every contact re-detected meanwhile belongs to it).
#[derive(Copy, Clone, Debug)]
pub(crate) struct Touching {
    /// The largest contact distance of the episode's contacts (re-armed
    /// beyond a multiple).
    pub contact_distance: Real,
    /// The largest distance at the episode's contacts.
    pub distance: Real,
}

impl PairState {
    pub fn new(a: usize, b: usize) -> PairState {
        PairState {
            a,
            b,
            lower_bound: None,
            hint: None,
            axis: None,
            simplex: WarmSimplex::default(),
            touching: None,
        }
    }

    /// What the pair's next CCD query may start from.
    pub fn warm_start(&self) -> WarmStart {
        WarmStart { lower_bound: self.lower_bound, hint: self.hint, axis: self.axis, simplex: self.simplex }
    }
}

impl World {
    /// Frees the bodies' states and motions and the pairs, once the run's
    /// result has read them.
    pub fn release_buffers(&mut self) {
        (self.states, self.motions, self.energies, self.pairs) =
            (Vec::new(), Vec::new(), Vec::new(), Vec::new());
    }

    /// The world at the scene's start. `kinematic_states`: keep a state for
    /// kinematic bodies too (a response that can stop them needs it).
    /// `energy_checked`: keep each integrated body's initial energy (the
    /// divergence check's reference, which a response that exchanges
    /// momentum turns off).
    pub fn new(model: &Model, kinematic_states: bool, energy_checked: bool) -> World {
        let states: Vec<Option<RigidState>> = model
            .bodies
            .iter()
            .map(|body| {
                let needs_state = match body.motion {
                    BodyMotion::Integrated { .. } => true,
                    BodyMotion::Free => kinematic_states,
                    BodyMotion::Fixed => false,
                };
                needs_state.then(|| RigidState {
                    position: Point::from(body.pose.translation.vector),
                    orientation: body.pose.rotation,
                    velocity: body.velocity,
                    angular_velocity: body.angular_velocity,
                })
            })
            .collect();
        let energy = |(body, state): (&Body, &Option<RigidState>)| match (body.dynamics(model.gravity), state)
        {
            (Some(dynamics), Some(state)) => {
                (dynamics.energy(state), dynamics.energy_scale(state).max(Real::MIN_POSITIVE))
            }
            _ => (0.0, 0.0),
        };
        let energies =
            if energy_checked { model.bodies.iter().zip(&states).map(energy).collect() } else { Vec::new() };
        World {
            states,
            energies,
            motions: model.bodies.iter().map(|b| StepMotion::fixed(b.pose)).collect(),
            pairs: Vec::new(),
            contacts: Vec::new(),
            undecided: None,
            separated: Vec::new(),
            stops: Vec::new(),
            rewound: Vec::new(),
            may_rewind: false,
            rewind: None,
        }
    }

    /// Body `i` at time `s` into the current step.
    pub fn state_at(&self, i: usize, s: Real) -> RigidState {
        let motion = &self.motions[i];
        let pose = motion.pose_at(s);
        let (velocity, angular_velocity) = match &self.states[i] {
            Some(state) => (state.velocity, state.angular_velocity),
            None => (motion.velocity, motion.angular_velocity),
        };
        RigidState {
            position: Point::from(pose.translation.vector),
            orientation: pose.rotation,
            velocity,
            angular_velocity,
        }
    }

    /// Body `i` of `scene` at time `s` into the step, for an impulse.
    pub fn impact_body(&self, model: &Model, i: usize, s: Real) -> ImpactBody {
        let body = &model.bodies[i];
        let state = self.state_at(i, s);
        let pushable = body.is_integrated();
        let rotation = state.orientation.to_rotation_matrix().into_inner();
        let inverse_inertia = match body.inertia.and_then(|inertia| inertia.try_inverse()) {
            Some(inverse) if pushable => rotation * inverse * rotation.transpose(),
            _ => nalgebra::Matrix3::zeros(),
        };
        ImpactBody {
            center: state.position,
            inverse_mass: if pushable { body.mass.map_or(0.0, |m| 1.0 / m) } else { 0.0 },
            inverse_inertia,
            velocity: state.velocity,
            angular_velocity: state.angular_velocity,
        }
    }

    /// Notes that the query of pair `k` could not decide (the earliest such
    /// query of a step is kept).
    pub fn note_undecided(&mut self, k: usize, result: &MeshCcdResult) {
        let pair = &self.pairs[k];
        let time = result.time_of_impact.unwrap_or(0.0);
        if self.undecided.is_none_or(|u| time < u.time) {
            self.undecided = Some(Undecided { pair: (pair.a, pair.b), time, iterations: result.iterations });
        }
    }

    /// Records the contact of pair `k` at `time` into the step starting at
    /// `t0` and marks the pair touching.
    pub fn record_contact(&mut self, k: usize, t0: Real, time: Real, result: &MeshCcdResult) {
        let Some(closest) = result.closest else { return };
        let pair = &mut self.pairs[k];
        let (pose_a, pose_b) = (self.motions[pair.a].pose_at(time), self.motions[pair.b].pose_at(time));
        // A contact re-detected while the pair still touches (under
        // `Bounce`) belongs to the same episode: the episode keeps the
        // larger of its distances, so the re-detection distance (a fraction
        // of it) does not halve at every bounce of a pair pressed together
        // until conservative advancement crawls at the rounding floor.
        let (contact_distance, distance) = match pair.touching {
            Some(episode) => (
                episode.contact_distance.max(result.contact_distance),
                episode.distance.max(closest.distance),
            ),
            None => (result.contact_distance, closest.distance),
        };
        pair.touching = Some(Touching { contact_distance, distance });
        pair.lower_bound = None;
        self.contacts.push(Contact {
            time: t0 + time,
            body_a: pair.a,
            body_b: pair.b,
            closest,
            status: result.status,
            contact_distance: result.contact_distance,
            guaranteed_distance: result.guaranteed_distance,
            pose_a,
            pose_b,
        });
    }
}

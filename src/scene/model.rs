//! A validated scene's types: the model the stepper and the guard simulate,
//! and what a run of it writes and checks.

use super::file::OnContact;
use super::parameters::StepParameters;
use crate::ccd::CcdOptions;
use crate::math::{Pose, Real, Vector};
use crate::mesh::{DistanceKernel, TriMesh};
use crate::motion::{Dynamics, Gyroscopic, Integrator, Spring, StepMotion};
use nalgebra::Matrix3;
use std::sync::Arc;

/// A validated scene, ready to run.
#[derive(Clone, Debug)]
pub struct Scene {
    pub(crate) model: Model,
    pub(crate) run: RunSpec,
}

/// What a run writes and how long it runs (a [`Scene`]'s half that the
/// simulation does not need).
#[derive(Clone, Debug)]
#[non_exhaustive]
pub struct RunSpec {
    /// The scene's name (its output folder).
    pub name: String,
    /// Where it was read from (for messages).
    pub source: String,
    /// The number of steps.
    pub steps: u64,
    /// The time the scene asks to cover (`duration`, or `steps × dt`).
    pub duration: Real,
    /// The distance trace, if asked for.
    pub trace: Option<TraceSpec>,
    /// The distance plot, if asked for (drawn from the trace).
    pub plot: Option<PlotSpec>,
    /// The expectation `nearmiss test` checks.
    pub expect: Option<Expectation>,
    /// The pose record (`poses.csv`), if asked for.
    pub poses: Option<PosesSpec>,
    /// The near misses to list, if asked for.
    pub near_misses: Option<NearMissSpec>,
    /// The scene's up axis (for viewers; the simulation has none).
    pub up: Axis,
    /// The file gave `steps` (not `duration`): messages name what it wrote.
    pub(crate) steps_given: bool,
}

/// What is simulated: the bodies and how they move and meet (a [`Scene`]'s
/// half that the stepper and the guard need).
#[derive(Clone, Debug)]
#[non_exhaustive]
pub struct Model {
    /// The fixed step.
    pub dt: Real,
    /// The integrator of bodies with forces.
    pub integrator: Integrator,
    /// The rotation update of semi-implicit Euler.
    pub gyroscopic: Gyroscopic,
    /// CCD tolerances and limits (tolerance relative to each pair's size).
    pub ccd: CcdOptions,
    /// The CCD's distance kernel.
    pub kernel: DistanceKernel,
    /// What happens at a contact.
    pub on_contact: OnContact,
    /// The uniform gravitational acceleration on every integrated body.
    pub gravity: Vector,
    /// The bodies, shared: a copy of the model (the stepper keeps one)
    /// does not copy them; `Arc::make_mut` changes a copy's own.
    pub bodies: Arc<Vec<Body>>,
    /// The stepper's parameters (not part of the file format: defaults).
    pub parameters: StepParameters,
}

/// A body, resolved.
#[derive(Clone, Debug)]
#[non_exhaustive]
pub struct Body {
    /// Its unique name.
    pub name: String,
    /// Its mesh, vertices relative to the centre of mass (the centre of
    /// rotation), shared with bodies that use the same mesh.
    pub mesh: Arc<TriMesh>,
    /// The pose at time 0 (translation: the centre of mass).
    pub pose: Pose,
    /// Velocity of the centre of mass at time 0.
    pub velocity: Vector,
    /// Angular velocity (world frame) at time 0.
    pub angular_velocity: Vector,
    /// Mass, if given or derived from a density.
    pub mass: Option<Real>,
    /// Inertia about the centre of mass, body frame, if given or derived.
    pub inertia: Option<Matrix3<Real>>,
    /// How the body moves.
    pub motion: BodyMotion,
    /// Moves at its given velocities whatever acts on it (`kinematic: true`).
    pub kinematic: bool,
    /// Its contact material under `on_contact: Simulate` (the scene's,
    /// or the body's own); `None` under the other responses.
    pub material: Option<Material>,
    /// The keyframes a kinematic body follows (`path`), if any.
    pub path: Option<Arc<KeyframePath>>,
}

/// The keyframes of a kinematic body: its pose at steps of the run (the
/// first at step 0, its start). Between two keyframes it moves with the
/// constant velocity of its centre (the pivot) and the constant angular
/// velocity (the short way) that take one pose to the next; after the
/// last it stays there.
#[derive(Clone, Debug, PartialEq)]
pub struct KeyframePath {
    /// `(step, pose)` (the pose's translation the body's centre), steps
    /// increasing, the first 0.
    pub keys: Vec<(u64, Pose)>,
}

impl KeyframePath {
    /// The body's motion over step `step` (of length `dt`): the segment's
    /// [`StepMotion::between`] from its first keyframe, referred to it (so
    /// each segment is one straight line and one exponential, with no
    /// rounding carried from step to step); at rest after the last.
    pub fn motion(&self, step: u64, dt: Real) -> StepMotion {
        let k = self.keys.partition_point(|&(s, _)| s <= step) - 1;
        let (start, pose) = self.keys[k];
        let Some(&(end, next)) = self.keys.get(k + 1) else {
            return StepMotion::fixed(pose);
        };
        let mut motion = StepMotion::between(&pose, &next, (end - start) as Real * dt);
        motion.elapsed = (step - start) as Real * dt;
        motion
    }
}

/// A body's contact material (`on_contact: Simulate`).
#[derive(Copy, Clone, Debug, PartialEq)]
pub struct Material {
    /// Friction coefficient (at least 0).
    pub friction: Real,
    /// Coefficient of restitution, in `[0, 1]`.
    pub restitution: Real,
    /// Give rapier the triangle mesh even where the mesh is convex.
    pub triangle_mesh: bool,
}

/// What a scene does with bodies that overlap at time 0
/// (`initial_overlap`). Default: `Warn`.
#[derive(Copy, Clone, Debug, Default, PartialEq, Eq, serde::Deserialize)]
pub enum InitialOverlapPolicy {
    /// Run, and say so (the terminal, with each pair's depth).
    #[default]
    Warn,
    /// Refuse the scene at load: an error naming the bodies and the depth
    /// (exit code 2).
    Refuse,
}

/// A world axis: the scene's up direction (`up`).
#[derive(Copy, Clone, Debug, PartialEq, Eq, serde::Deserialize)]
pub enum Axis {
    /// +x.
    X,
    /// +y.
    Y,
    /// +z.
    Z,
}

impl Axis {
    /// The axis gravity pulls down along (`g` along −axis), else `Z`.
    pub fn against(gravity: &Vector) -> Axis {
        match [gravity.x, gravity.y, gravity.z] {
            [x, 0.0, 0.0] if x < 0.0 => Axis::X,
            [0.0, y, 0.0] if y < 0.0 => Axis::Y,
            _ => Axis::Z,
        }
    }
}

/// The pose record of a run.
#[derive(Clone, Debug, PartialEq)]
pub struct PosesSpec {
    /// Record every this many steps (and the first and last).
    pub every: u64,
}

/// How a body moves.
#[derive(Clone, Debug, PartialEq)]
pub enum BodyMotion {
    /// Never moves.
    Fixed,
    /// Constant velocities, moved exactly (nothing acts on it, or it is kinematic).
    Free,
    /// Integrated under the scene's gravity, contacts and these springs
    /// ([`Body::dynamics`] gathers what its step needs).
    Integrated {
        /// The springs attached to the body.
        springs: Vec<Spring>,
    },
}

impl Body {
    /// Whether the body is still for good: fixed, or free (nothing acts on
    /// it) with zero velocities and no keyframe path. No response moves a
    /// free body (a stop holds it where it is), so a stepper may box it once
    /// and pass over it in its integration, as a fixed one.
    pub fn stays_put(&self) -> bool {
        match self.motion {
            BodyMotion::Fixed => true,
            BodyMotion::Free => {
                self.path.is_none()
                    && self.velocity == Vector::zeros()
                    && self.angular_velocity == Vector::zeros()
            }
            BodyMotion::Integrated { .. } => false,
        }
    }

    /// Whether the body is integrated (moved by forces: gravity, springs,
    /// contacts).
    pub fn is_integrated(&self) -> bool {
        matches!(self.motion, BodyMotion::Integrated { .. })
    }

    /// What an integrated body's step needs (its mass properties, springs
    /// and `gravity`, the scene's), borrowed; `None` for a body that is not
    /// integrated.
    pub fn dynamics(&self, gravity: Vector) -> Option<Dynamics<'_>> {
        let BodyMotion::Integrated { springs } = &self.motion else { return None };
        Some(Dynamics {
            inverse_mass: self.mass.map_or(0.0, |m| 1.0 / m),
            inertia: self.inertia.as_ref(),
            gravity,
            springs,
        })
    }
}

/// The distance trace of a scene.
#[derive(Clone, Debug, PartialEq)]
pub struct TraceSpec {
    /// Traced pairs as body indices `(i, j)`, `i < j`.
    pub pairs: Vec<(usize, usize)>,
    /// Record every this many steps (and the first and last).
    pub every: u64,
    /// Also compute the exact reference distance of each sample (rational
    /// arithmetic on the closest triangle pair): set by reports that
    /// measure the kernel's error, never by scene files.
    pub reference: bool,
}

/// The near misses of a scene (`near_misses: (within: D)`).
#[derive(Clone, Debug, PartialEq)]
pub struct NearMissSpec {
    /// Pairs that come this close or closer are listed.
    pub within: Real,
    /// The pairs looked at (body indices `i < j`), or `None`: every pair
    /// that is not fixed.
    pub pairs: Option<Vec<(usize, usize)>>,
    /// The largest width of a pair's bracket (absolute), or `None`:
    /// [`crate::ccd::DEFAULT_APPROACH_TOLERANCE`] of the pair's smaller
    /// radius.
    pub tolerance: Option<Real>,
}

/// The distance plot of a scene.
#[derive(Clone, Debug, PartialEq)]
pub struct PlotSpec {
    /// Logarithmic distance axis (`Some(true)`), linear, or chosen from the
    /// trace (`None`; the application's distance chart draws it).
    pub log_y: Option<bool>,
    /// Contacts (1-based) pictured besides the first three.
    pub contacts: Vec<usize>,
}

/// What a run is expected to do.
#[derive(Clone, Debug, PartialEq)]
pub enum Expectation {
    /// The first contact is between these bodies at `time ± tolerance`.
    Contact {
        /// Expected time.
        time: Real,
        /// Allowed deviation.
        tolerance: Real,
        /// The two bodies (indices).
        bodies: (usize, usize),
        /// Pinned from a run by `nearmiss test --record`, not derived.
        recorded: bool,
    },
    /// Nothing touches.
    NoContact,
    /// The two bodies (indices) come within `distance ± tolerance` of each
    /// other at their closest, without touching.
    NearMiss {
        /// The two bodies.
        bodies: (usize, usize),
        /// Expected closest approach.
        distance: Real,
        /// Allowed deviation.
        tolerance: Real,
    },
}

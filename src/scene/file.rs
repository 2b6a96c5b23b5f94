//! The RON schema of a scene file, as written by users. Every struct denies
//! unknown fields, so a misspelt field is an error rather than a silent
//! default. [`super::Scene`] is the validated form.

use serde::Deserialize;

pub(crate) use super::file_body::{
    BodySettings, ColliderSettings, MeshSettings, OrientationSettings, SpringSettings, Triple,
};
use crate::motion::{Gyroscopic, Integrator};

/// A scene file: `Scene(name: ..., dt: ..., bodies: [...], ...)`.
#[derive(Clone, Debug, Deserialize)]
#[serde(deny_unknown_fields, rename = "Scene")]
pub struct SceneFile {
    /// The scene's name: the output folder is `<out>/<name>/`.
    pub name: String,
    /// The fixed step (time units; usually seconds).
    pub dt: f64,
    /// How long to run (give this or `steps`). The run covers at least this
    /// time: `ceil(duration / dt)` steps.
    #[serde(default)]
    pub duration: Option<f64>,
    /// How many steps to run (give this or `duration`).
    #[serde(default)]
    pub steps: Option<u64>,
    /// The integrator of bodies with forces. Default: `SymplecticEuler`.
    #[serde(default)]
    pub integrator: Integrator,
    /// The rotation update of `SymplecticEuler`. Default: `Implicit`.
    #[serde(default)]
    pub gyroscopic: Gyroscopic,
    /// CCD settings.
    #[serde(default)]
    pub ccd: CcdSettings,
    /// What happens at a contact. Default: `Stop`.
    #[serde(default)]
    pub on_contact: OnContact,
    /// The distance trace; none by default.
    #[serde(default)]
    pub trace: Option<TraceSettings>,
    /// A distance plot of the trace (`distance.png`); needs `trace`.
    #[serde(default)]
    pub plot: Option<PlotSettings>,
    /// Uniform gravitational acceleration on every body that is neither
    /// fixed nor kinematic.
    #[serde(default)]
    pub gravity: Option<Triple>,
    /// Springs from body points to world anchors.
    #[serde(default)]
    pub springs: Vec<SpringSettings>,
    /// The bodies.
    pub bodies: Vec<BodySettings>,
    /// What `nearmiss test` checks.
    #[serde(default)]
    pub expect: Option<ExpectSettings>,
    /// The bodies' poses over time (`poses.csv`); none by default.
    #[serde(default)]
    pub poses: Option<PosesSettings>,
    /// Near misses: every pair whose closest approach over the run is at
    /// most `within` (an absolute distance), in `summary.json`'s
    /// `near_misses` with a certified bracket; none by default.
    #[serde(default)]
    pub near_misses: Option<NearMissSettings>,
    /// The scene's up axis, `X`, `Y` or `Z`: how viewers stand it up
    /// (`animation.glb` is written +Y up, as glTF requires). Default: the
    /// axis gravity pulls down along, else `Z`.
    #[serde(default)]
    pub up: Option<super::Axis>,
    /// Bodies overlapping at time 0: `Warn` (run, and say how deep) or
    /// `Refuse` (an error at load). Default: `Warn`.
    #[serde(default)]
    pub initial_overlap: super::InitialOverlapPolicy,
}

/// The pose record of a run (`poses.csv`: step, time, body, position,
/// orientation quaternion).
#[derive(Clone, Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct PosesSettings {
    /// Record every this many steps (and at the first and last step).
    /// Default: the trace's cadence when there is a trace, otherwise 1.
    #[serde(default)]
    pub every: Option<u64>,
}

/// CCD settings of a scene.
#[derive(Clone, Debug, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct CcdSettings {
    /// The proximity kernel. Default: `Exact`.
    pub kernel: KernelSettings,
    /// Contact is declared within `minimum_separation + distance_tolerance ×
    /// min(r_a, r_b)`, `r` being each mesh's radius about its centre of
    /// mass; every approach within half the tolerance is reported. Relative
    /// to the smaller body. Default: `1e-6`.
    pub distance_tolerance: f64,
    /// An absolute gap that counts as contact. Default: `0`.
    pub minimum_separation: f64,
    /// The most advancement steps per pair and step. Default: `10000`.
    pub max_iterations: usize,
}

impl Default for CcdSettings {
    fn default() -> Self {
        let options = crate::ccd::CcdOptions::default();
        CcdSettings {
            kernel: KernelSettings::Exact,
            distance_tolerance: options.distance_tolerance,
            minimum_separation: options.minimum_separation,
            max_iterations: options.max_iterations,
        }
    }
}

/// The triangle distance kernel of the CCD.
#[derive(Copy, Clone, Debug, Default, Deserialize, PartialEq, Eq)]
#[serde(deny_unknown_fields)]
pub enum KernelSettings {
    /// The exact kernel (conservative CCD).
    #[default]
    Exact,
    /// The seed paper's DyOP kernel: may over-estimate, so the CCD may be late.
    Dyop {
        /// `Vector` (default), `PlainVector`, `Heron` or `StableHeron`.
        #[serde(default)]
        formula: FormulaSettings,
    },
}

/// A point–edge distance formula of the DyOP kernel.
#[derive(Copy, Clone, Debug, Default, Deserialize, PartialEq, Eq)]
pub enum FormulaSettings {
    /// Cross product, compensated.
    #[default]
    Vector,
    /// Cross product, plain (the seed's).
    PlainVector,
    /// Heron's formula (the seed's).
    Heron,
    /// Kahan's stable Heron.
    StableHeron,
}

/// What the run does at a contact.
#[non_exhaustive]
#[derive(Copy, Clone, Debug, Default, Deserialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub enum OnContact {
    /// Stop at the first contact. The default.
    #[default]
    Stop,
    /// Record every contact and keep moving (bodies pass through each
    /// other; `Bounce` is the collision response). A pair in contact is
    /// re-armed once its distance at a step's end exceeds twice the contact
    /// distance.
    Record,
    /// Record every contact and bounce: the two bodies stop at their time of
    /// contact for the rest of the step (no body ever moves past a contact),
    /// an impulse along the contact normal with this coefficient of
    /// restitution (0: the approach speed is absorbed, 1: elastic) sets
    /// their velocities, and they move on from the next step. Contacts are
    /// taken in time order within a step; every body's motion after another
    /// stopped is checked again. Every body that is neither fixed nor
    /// kinematic needs a mass and an inertia (`density`, or `mass` and
    /// `inertia`) and is integrated (so a tumbling body precesses); a
    /// kinematic body is not pushed (infinite mass) but also stops at a
    /// contact for the rest of its step. Meant for bouncing, not resting,
    /// contact: a pair pressed together for many steps is re-detected at
    /// half its distance each time.
    Bounce {
        /// The coefficient of restitution, in `[0, 1]`.
        restitution: f64,
    },
    /// Rigid-body dynamics by rapier3d (resting contact, friction,
    /// stacking), guarded by nearmiss (`nearmiss::guard`): each step rapier
    /// moves and solves the bodies, then nearmiss sweeps every pair from the
    /// step's start poses to rapier's end poses; where a pair arrives that
    /// rapier would let go deeper than its allowed error or through, the
    /// world goes back to the contact and rapier solves the rest of the step
    /// from there. Where rapier holds, the run is rapier's. A contact is
    /// reported once, when a pair comes into contact; pairs in contact are
    /// rapier's to hold and are armed again once they separate. Every body
    /// that is neither fixed nor kinematic needs a mass and an inertia
    /// (`density`, or `mass` and `inertia`). Needs the `rapier` feature (on
    /// by default).
    Simulate {
        /// The coefficient of restitution of every body (a body's own
        /// `restitution` overrides it), in `[0, 1]`; rapier averages the
        /// two bodies' values. Default: 0.
        #[serde(default)]
        restitution: f64,
        /// The friction coefficient of every body (a body's own `friction`
        /// overrides it), at least 0; rapier averages the two bodies'
        /// values. Default: 0.5 (rapier's).
        #[serde(default = "default_friction")]
        friction: f64,
        /// Rapier's solver iterations per step. Default: 4 (rapier's).
        #[serde(default = "default_solver_iterations")]
        solver_iterations: usize,
        /// Each collider's contact skin, as a multiple of rapier's allowed
        /// linear error (0.005): at 0 rapier's contacts are as they are
        /// (resting bodies overlap a little, about 1e-4 on a floor); above
        /// 0 the meshes never overlap, and resting bodies float the two
        /// skins, less what rapier lets them sink, apart. In `[0, 100]`.
        /// Default: 0.
        #[serde(default)]
        skin: f64,
    },
}

/// Rapier's default friction coefficient.
pub const DEFAULT_FRICTION: f64 = 0.5;
/// Rapier's default number of solver iterations.
pub const DEFAULT_SOLVER_ITERATIONS: usize = 4;

fn default_friction() -> f64 {
    DEFAULT_FRICTION
}

fn default_solver_iterations() -> usize {
    DEFAULT_SOLVER_ITERATIONS
}

/// Which pairs are traced, how often.
#[derive(Clone, Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct TraceSettings {
    /// `All` pairs (not both fixed), or `Only([("a", "b"), ...])`.
    #[serde(default)]
    pub pairs: TracePairs,
    /// Record every this many steps (and at the first and last step).
    /// Default: 1.
    #[serde(default = "one")]
    pub every: u64,
}

fn one() -> u64 {
    1
}

/// The near misses a run lists.
#[derive(Clone, Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct NearMissSettings {
    /// List the pairs that come this close or closer (an absolute
    /// distance, positive).
    pub within: f64,
    /// `All` pairs (not both fixed, the default), or `Only([("a", "b"), ...])`.
    #[serde(default)]
    pub pairs: TracePairs,
    /// The largest width of each pair's bracket (an absolute distance,
    /// positive); default: the closest approach's, 1e-6 of the pair's
    /// smaller radius.
    #[serde(default)]
    pub tolerance: Option<f64>,
}

/// The traced pairs.
#[derive(Clone, Debug, Default, Deserialize)]
pub enum TracePairs {
    /// Every pair of bodies that are not both fixed.
    #[default]
    All,
    /// These pairs, by body name.
    Only(Vec<(String, String)>),
}

/// The distance plot.
#[derive(Clone, Debug, Default, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct PlotSettings {
    /// Logarithmic distance axis (`true`), linear (`false`), or chosen from
    /// the trace when absent: logarithmic when its distances span more than
    /// the distance chart's `LOG_AXIS_SPAN` (in `nearmiss-cli`; a fall's
    /// last millimetres are invisible on a linear axis of metres). Default:
    /// chosen.
    #[serde(default)]
    pub log_y: Option<bool>,
    /// Contacts (1-based, in the order reported) to picture as
    /// `contact_<n>.png` besides the first three. Default: none.
    #[serde(default)]
    pub contacts: Vec<usize>,
}

/// What the run is expected to do.
#[derive(Clone, Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub enum ExpectSettings {
    /// The first contact, between these bodies, at this time.
    Contact {
        /// The expected time of first contact.
        time: f64,
        /// The allowed |obtained − expected|.
        tolerance: f64,
        /// The two bodies, in either order.
        bodies: (String, String),
        /// `true` when the time was pinned by `nearmiss test --record` from
        /// a run (not derived by analysis). Default: `false`.
        #[serde(default)]
        recorded: bool,
    },
    /// No contact during the run.
    NoContact,
    /// The two bodies pass each other without touching, their closest
    /// approach over the run `distance ± tolerance` (the certified bracket
    /// inside that band); needs `near_misses` with `within` at least
    /// `distance + tolerance`.
    NearMiss {
        /// The two bodies, in either order.
        bodies: (String, String),
        /// The expected closest approach.
        distance: f64,
        /// The allowed deviation.
        tolerance: f64,
    },
}

//! The schema of `summary.json`, the document a run of a scene is written
//! as: one definition for the `nearmiss` command and the Python package,
//! which both write it, so that neither builds the other (the Python
//! wheel's build tree has no command-line crate in it). The fields are
//! listed in `scenes/README.md`.

use nearmiss::math::Real;
use nearmiss::mesh::MeshDistance;
use nearmiss::run::{Contact, RunResult, StageSeconds, Work};
use nearmiss::scene::Scene;
use serde::Serialize;

/// The `summary.json` document (its fields are listed in `scenes/README.md`).
#[derive(Serialize)]
pub struct Summary<'a> {
    /// The scene's name.
    pub scene: &'a str,
    /// The scene file, as it was given (absent for a scene built in code).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub source: Option<&'a str>,
    /// Steps taken.
    pub steps: u64,
    /// The time reached.
    pub end_time: Real,
    /// Wall-clock time of the run (not deterministic).
    pub wall_time_s: Real,
    /// Why the run ended: `completed`, `first_contact`, `diverged at ...`
    /// or `undecided at ...` (the CCD of a pair ran out of iterations: not a
    /// contact; the run stops there).
    pub termination: String,
    /// The earliest contact or `null`.
    pub first_contact: Option<ContactJson<'a>>,
    /// Every contact in time order.
    pub contacts: Vec<ContactJson<'a>>,
    /// Work counters (deterministic).
    pub work: &'a Work,
    /// Seconds per stage (not deterministic).
    pub stage_wall_time_s: &'a StageSeconds,
    /// Who solved the contact response (`on_contact`), and with `Simulate`
    /// which collider shape rapier was given for each body.
    pub response: ResponseJson,
    /// With `--compare parry`: parry's answers beside nearmiss's.
    #[serde(skip_serializing_if = "<[_]>::is_empty")]
    pub peer: &'a [PeerComparison],
    /// With `--compare rapier`: rapier's outcome per pair beside nearmiss's.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub rapier: Option<serde_json::Value>,
    /// With `near_misses` in the scene: every pair that came within its
    /// distance without touching, nearest first.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub near_misses: Option<Vec<NearMissJson<'a>>>,
    /// Bodies that overlap at time 0 (absent when none do).
    #[serde(skip_serializing_if = "<[_]>::is_empty")]
    pub initial_overlaps: Vec<OverlapJson<'a>>,
    /// Meshes with zero-area triangles (kept) or faces of fewer than three
    /// vertices in their files (dropped), with their counts (absent when none).
    #[serde(skip_serializing_if = "<[_]>::is_empty")]
    pub mesh_notes: Vec<nearmiss::scene::MeshNote>,
}

/// Two bodies overlapping at time 0, in `summary.json`.
#[derive(Serialize)]
pub struct OverlapJson<'a> {
    /// The two bodies' names.
    pub bodies: [&'a str; 2],
    /// The penetration depth of the two solids, where both meshes are
    /// convex (absent otherwise): `depth`, `direction` (the second body
    /// moved by `depth` along it touches the first), `point_a`, `point_b`.
    #[serde(flatten, skip_serializing_if = "Option::is_none")]
    pub depth: Option<DepthJson>,
    /// Closed meshes not both convex: the deepest local depth where their
    /// surfaces cross, `[lower, upper]` (absent otherwise).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub local_depth: Option<[Real; 2]>,
    /// Triangle pairs whose surfaces meet.
    pub crossing_pairs: usize,
    /// The intersection curve's length.
    pub curve_length: Real,
}

/// A penetration depth in `summary.json`.
#[derive(Serialize)]
pub struct DepthJson {
    /// The shortest move that separates the solids.
    pub depth: Real,
    /// Its direction (unit).
    pub direction: [Real; 3],
    /// Where it ends on the first body's surface.
    pub point_a: [Real; 3],
    /// The second body's deepest point.
    pub point_b: [Real; 3],
}

impl<'a> OverlapJson<'a> {
    fn of(scene: &'a Scene, overlap: &nearmiss::scene::InitialOverlap) -> OverlapJson<'a> {
        let bodies = &scene.model().bodies;
        let array = |v: &nearmiss::math::Vector| [v.x, v.y, v.z];
        OverlapJson {
            bodies: [&bodies[overlap.body_a].name, &bodies[overlap.body_b].name],
            depth: overlap.depth.map(|d| DepthJson {
                depth: d.depth,
                direction: array(&d.direction),
                point_a: array(&d.point_a.coords),
                point_b: array(&d.point_b.coords),
            }),
            local_depth: overlap.local_depth.map(|(lower, upper)| [lower, upper]),
            crossing_pairs: overlap.intersection.pairs.len(),
            curve_length: overlap.intersection.length(),
        }
    }
}

/// A near miss in `summary.json`.
#[derive(Serialize)]
pub struct NearMissJson<'a> {
    /// The two bodies' names.
    pub bodies: [&'a str; 2],
    /// The closest approach found, where: `distance` (the certified
    /// bracket's upper end, reached at `time`), `point_a`, `point_b`,
    /// `triangle_a`, `triangle_b`, `feature_a`, `feature_b`.
    #[serde(flatten)]
    pub closest: &'a MeshDistance,
    /// The pair is never closer than this over the run (certified).
    pub lower: Real,
    /// When `distance` is reached.
    pub time: Real,
    /// Every step's bracket closed within its tolerance (`false`: a CCD run
    /// ran out of iterations; the bracket holds, wider).
    pub decided: bool,
    /// The first body's pose (its mesh's frame) at `time`.
    pub pose_a: PoseJson,
    /// The second body's pose at `time`.
    pub pose_b: PoseJson,
}

impl<'a> NearMissJson<'a> {
    /// The near miss of a run, named.
    pub fn of(result: &'a RunResult, miss: &'a nearmiss::run::NearMiss) -> NearMissJson<'a> {
        NearMissJson {
            bodies: [&result.bodies[miss.body_a], &result.bodies[miss.body_b]],
            closest: &miss.closest,
            lower: miss.lower,
            time: miss.time,
            decided: miss.decided,
            pose_a: PoseJson::of(&miss.pose_a),
            pose_b: PoseJson::of(&miss.pose_b),
        }
    }
}

/// The peers' answers a run is written with (`--compare`).
#[derive(Clone, Debug, Default)]
pub struct Peers<'a> {
    /// parry's first contacts.
    pub parry: &'a [PeerComparison],
    /// rapier's outcome per pair, as JSON (`nearmiss::guard::RapierPair` rows).
    pub rapier: Option<serde_json::Value>,
}

/// The contact response in `summary.json`.
#[derive(Serialize)]
pub struct ResponseJson {
    /// `nearmiss` (Stop, Record, Bounce) or the engine that solved it
    /// (`rapier3d-f64 0.36` under Simulate, guarded by nearmiss's CCD).
    pub solved_by: String,
    /// Under Simulate: body name → the shape rapier was given (`convex
    /// hull` or `triangle mesh`).
    #[serde(skip_serializing_if = "std::collections::BTreeMap::is_empty")]
    pub colliders: std::collections::BTreeMap<String, String>,
    /// Under Simulate: each collider's contact skin (0 unless the scene asks
    /// for one; contacts are then reported two skins apart).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub contact_skin: Option<Real>,
    /// Under Simulate: how often the guard moved the world back to a
    /// contact for the engine to solve from there.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub rewinds: Option<u64>,
}

/// A body's pose in `summary.json`: its frame's origin and orientation.
#[derive(Serialize)]
pub struct PoseJson {
    /// The frame's origin, world frame.
    pub position: [Real; 3],
    /// The orientation quaternion `[w, x, y, z]`.
    pub orientation: [Real; 4],
}

impl PoseJson {
    fn of(pose: &nearmiss::math::Pose) -> PoseJson {
        let q = pose.rotation.quaternion();
        PoseJson { position: pose.translation.vector.into(), orientation: [q.w, q.i, q.j, q.k] }
    }
}

/// A contact in `summary.json`.
#[derive(Serialize)]
pub struct ContactJson<'a> {
    /// Time of first contact.
    pub time: Real,
    /// First body's name.
    pub body_a: &'a str,
    /// Second body's name.
    pub body_b: &'a str,
    /// The distance at `time` and where: `distance`, `point_a`, `point_b`,
    /// `triangle_a`, `triangle_b`, `feature_a`, `feature_b` (the library's
    /// [`nearmiss::mesh::MeshDistance`], written as it serialises).
    #[serde(flatten)]
    pub closest: &'a MeshDistance,
    /// How the CCD iteration ended ([`nearmiss::ccd::CcdStatus::name`]).
    pub status: &'static str,
    /// The pose of `body_a` at `time`.
    pub pose_a: PoseJson,
    /// The pose of `body_b` at `time`.
    pub pose_b: PoseJson,
    /// No contact is reported farther than this.
    pub contact_distance: Real,
    /// Every approach closer than this is reported.
    pub guaranteed_distance: Real,
}

impl<'a> Summary<'a> {
    /// The summary of a run.
    pub fn of(result: &'a RunResult) -> Summary<'a> {
        Summary::with_peer(result, &[])
    }

    /// The summary of a run, with parry's answers beside.
    pub fn with_peer(result: &'a RunResult, peer: &'a [PeerComparison]) -> Summary<'a> {
        let contact = |c: &'a Contact| ContactJson {
            time: c.time,
            body_a: &result.bodies[c.body_a],
            body_b: &result.bodies[c.body_b],
            closest: &c.closest,
            status: c.status.name(),
            pose_a: PoseJson::of(&c.pose_a),
            pose_b: PoseJson::of(&c.pose_b),
            contact_distance: c.contact_distance,
            guaranteed_distance: c.guaranteed_distance,
        };
        Summary {
            scene: &result.scene,
            source: None,
            steps: result.steps,
            end_time: result.end_time,
            wall_time_s: result.wall_time_s,
            termination: result.termination_text(),
            first_contact: result.first_contact.as_ref().map(contact),
            contacts: result.contacts.iter().map(contact).collect(),
            work: &result.counters.work,
            stage_wall_time_s: &result.counters.seconds,
            response: match &result.solver {
                Some(solver) => ResponseJson {
                    solved_by: format!("{} (guarded by nearmiss)", solver.engine),
                    colliders: result.bodies.iter().cloned().zip(solver.colliders.iter().cloned()).collect(),
                    contact_skin: Some(solver.contact_skin),
                    rewinds: Some(solver.rewinds),
                },
                None => ResponseJson {
                    solved_by: "nearmiss".into(),
                    colliders: Default::default(),
                    contact_skin: None,
                    rewinds: None,
                },
            },
            peer,
            rapier: None,
            near_misses: None,
            initial_overlaps: Vec::new(),
            mesh_notes: Vec::new(),
        }
    }

    /// The summary of `result`, a run of `scene`, with the peers' answers.
    pub fn of_run(result: &'a RunResult, scene: &'a Scene, peers: &Peers<'a>) -> Summary<'a> {
        Summary {
            rapier: peers.rapier.clone(),
            source: Some(scene.run().source.as_str()).filter(|s| *s != nearmiss::scene::FROM_STRING),
            near_misses: scene
                .run()
                .near_misses
                .is_some()
                .then(|| result.near_misses.iter().map(|m| NearMissJson::of(result, m)).collect()),
            initial_overlaps: result.initial_overlaps.iter().map(|o| OverlapJson::of(scene, o)).collect(),
            mesh_notes: scene.mesh_notes(),
            ..Summary::with_peer(result, peers.parry)
        }
    }

    /// Pretty JSON text.
    pub fn to_json(&self) -> String {
        // Serializing plain structs of numbers and strings cannot fail;
        // non-finite numbers become `null`.
        serde_json::to_string_pretty(self).unwrap_or_default() + "\n"
    }
}

/// `summary.json`'s text for `result`, a run of `scene` (without peers).
pub fn summary_json(result: &RunResult, scene: &Scene) -> String {
    Summary::of_run(result, scene, &Peers::default()).to_json()
}

/// One pair, both answers.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct PeerComparison {
    /// First body's name.
    pub body_a: String,
    /// Second body's name.
    pub body_b: String,
    /// nearmiss's first contact time of the pair (`null`: none).
    pub nearmiss: Option<Real>,
    /// parry's time of impact (`null`: none, or not computed).
    pub parry: Option<Real>,
    /// The parry query used, or why none was.
    pub parry_query: String,
    /// parry's wall time for the query, seconds.
    pub parry_wall_time_s: Real,
}

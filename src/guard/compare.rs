//! `nearmiss run --compare rapier`: the same scene in rapier alone, its own
//! CCD on for every moving body (`ccd_enabled` and soft CCD with a
//! prediction of the body's radius), beside nearmiss's run.
//!
//! Per pair: the first contact as rapier sees it (the end time of the first
//! step after which rapier has an active contact between the two), and
//! whether rapier let the pair pass through or intersect, judged
//! independently of rapier's narrow phase:
//! - **passed through**: in some step, nearmiss's CCD of rapier's own motion
//!   (a guard that watches and never clamps) finds the pair touching, yet
//!   rapier had no contact between them at the step's start or end;
//! - **intersected**: parry's contact query between the two colliders at a
//!   step's end finds them deeper than [`PENETRATION_LIMIT_FACTOR`] times
//!   rapier's allowed linear error.
//!
//! A pair touching at a step's start (bodies placed in contact) is not a
//! crossing: rapier's narrow phase has not run before the first step.
//!
//! Per body: its pose and velocities at the run's end in rapier alone,
//! beside nearmiss's.

use std::collections::BTreeMap;
use std::sync::Arc;

use serde::Serialize;

use super::simulate::RapierScene;
use super::{Guard, GuardEvent};
use crate::math::Real;
use crate::scene::{BodyMotion, Scene};

/// How deep, in multiples of rapier's allowed linear error
/// (`normalized_allowed_linear_error` × length unit, 0.005 by default in
/// rapier 0.36), a pair may overlap at a step's end before it counts as
/// intersecting: 2. rapier's soft contacts settle under load a little beyond
/// the allowed error (a stack of five unit boxes: 1.92e-3 at an allowed
/// error of 0.001, measured with an earlier rapier).
pub(crate) const PENETRATION_LIMIT_FACTOR: Real = 2.0;

/// rapier alone beside nearmiss: per pair and per body (see the module).
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct RapierComparison {
    /// Per pair of bodies not both fixed.
    pub pairs: Vec<RapierPair>,
    /// Per body, in the scene's order.
    pub bodies: Vec<RapierBody>,
}

/// rapier's outcome for one pair. Fields that do not apply are left out of
/// the JSON (never `null`).
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct RapierPair {
    /// First body's name.
    pub body_a: String,
    /// Second body's name.
    pub body_b: String,
    /// nearmiss's first contact of the pair (absent: none).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub nearmiss: Option<Real>,
    /// rapier's first contact: the end of the first step after which it has
    /// an active contact between them (absent: none).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub rapier: Option<Real>,
    /// The first step's start time in which rapier let them pass through
    /// (see the module), if any.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub passed_through_at: Option<Real>,
    /// The deepest overlap at a step's end (parry's contact depth; 0 when
    /// never overlapping, absent where parry cannot measure the shapes).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub max_penetration: Option<Real>,
    /// Whether that exceeds the limit (see the module).
    pub intersected: bool,
    /// rapier's verdict in words: `held`, `passed through`, `intersected`,
    /// `no contact`.
    pub verdict: String,
}

/// One body's pose and velocities at the run's end, in rapier alone and in
/// nearmiss's run (world frame; angular in radians per time unit;
/// orientations as `[w, x, y, z]` quaternions).
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct RapierBody {
    /// The body's name.
    pub body: String,
    /// rapier alone: the centre of mass.
    pub rapier_position: [Real; 3],
    /// rapier alone: the orientation.
    pub rapier_orientation: [Real; 4],
    /// nearmiss's run: the centre of mass.
    pub nearmiss_position: [Real; 3],
    /// nearmiss's run: the orientation.
    pub nearmiss_orientation: [Real; 4],
    /// rapier alone: velocity of the centre of mass.
    pub rapier_velocity: [Real; 3],
    /// rapier alone: angular velocity.
    pub rapier_angular_velocity: [Real; 3],
    /// nearmiss's run: velocity of the centre of mass.
    pub nearmiss_velocity: [Real; 3],
    /// nearmiss's run: angular velocity.
    pub nearmiss_angular_velocity: [Real; 3],
}

/// Runs `scene` in rapier alone and compares each pair with nearmiss's
/// first contacts (`nearmiss_first`: per pair `(a, b)` with `a < b`) and
/// each body's final velocities with nearmiss's (`nearmiss_final`, the
/// run's `final_states`).
pub fn compare_with_rapier(
    scene: &Scene,
    nearmiss_first: &BTreeMap<(usize, usize), Real>,
    nearmiss_final: &[crate::motion::RigidState],
) -> Result<RapierComparison, super::GuardError> {
    let mut rapier = RapierScene::build(scene, true, false)?;
    let allowed = rapier.parameters.allowed_linear_error();
    let mut guard = watcher(scene, &rapier, allowed)?;
    let pairs = scene.model.movable_pairs();
    // Per pair: rapier's first contact, the step it passed through, the
    // deepest overlap so far.
    type Row = (Option<Real>, Option<Real>, Option<Real>);
    let mut rows: BTreeMap<(usize, usize), Row> =
        pairs.iter().map(|&p| (p, (None, None, Some(0.0)))).collect();
    let mut touching_before: Vec<bool> = pairs.iter().map(|&(a, b)| rapier.in_contact(a, b)).collect();
    for step in 0..scene.run.steps {
        guard.before_step(&rapier.bodies);
        rapier.step(scene, step);
        let end = (step + 1) as Real * scene.model.dt;
        let crossed: Vec<(usize, usize)> = match guard.after_step(&mut rapier.bodies) {
            Ok(events) => events
                .iter()
                .filter_map(|event| match event {
                    // Touching at the step's start is not a crossing.
                    GuardEvent::Started { contact, .. }
                        if contact.status != crate::ccd::CcdStatus::InitiallyTouching =>
                    {
                        Some((contact.body_a, contact.body_b))
                    }
                    _ => None,
                })
                .collect(),
            // Undecided: nothing is claimed about this step.
            Err(_) => Vec::new(),
        };
        for (k, &(a, b)) in pairs.iter().enumerate() {
            let row = rows.get_mut(&(a, b)).expect("every pair has a row");
            let touching = rapier.in_contact(a, b);
            if touching && row.0.is_none() {
                row.0 = Some(end);
            }
            if crossed.contains(&(a, b)) && !touching && !touching_before[k] && row.1.is_none() {
                row.1 = Some(end - scene.model.dt);
            }
            touching_before[k] = touching;
            row.2 = match (row.2, rapier.penetration(a, b)) {
                (Some(deepest), Some(depth)) => Some(deepest.max(depth)),
                _ => None,
            };
        }
    }
    let bodies = final_bodies(scene, &rapier, nearmiss_final);
    let pairs = pairs
        .iter()
        .map(|&(a, b)| {
            let (first, passed, penetration) = rows[&(a, b)];
            let intersected = penetration.is_some_and(|d| d > PENETRATION_LIMIT_FACTOR * allowed);
            let verdict = if passed.is_some() {
                "passed through"
            } else if intersected {
                "intersected"
            } else if first.is_some() {
                "held"
            } else {
                "no contact"
            };
            RapierPair {
                body_a: scene.model.bodies[a].name.clone(),
                body_b: scene.model.bodies[b].name.clone(),
                nearmiss: nearmiss_first.get(&(a, b)).copied(),
                rapier: first,
                passed_through_at: passed,
                max_penetration: penetration,
                intersected,
                verdict: verdict.into(),
            }
        })
        .collect();
    Ok(RapierComparison { pairs, bodies })
}

/// A guard that watches rapier's motion in `scene` and never moves a body
/// (`allowed`: rapier's allowed linear error, the depth it tolerates).
fn watcher(scene: &Scene, rapier: &RapierScene, allowed: Real) -> Result<Guard, super::GuardError> {
    let mut watched = scene.model.clone();
    for body in Arc::make_mut(&mut watched.bodies) {
        if body.motion != BodyMotion::Fixed {
            body.motion = BodyMotion::Free;
        }
    }
    let watched = std::sync::Arc::new(watched);
    let stoppable = vec![false; scene.model.bodies.len()];
    let centers = vec![crate::math::Vector::zeros(); scene.model.bodies.len()];
    let setup = super::GuardSetup {
        handles: rapier.handles.clone(),
        centers,
        stoppable,
        skin: 0.0,
        tolerated_depth: allowed,
        solved: rapier.solved_pairs(),
        acts: false,
        max_substeps: 0,
        parallel: true,
    };
    Guard::with_model(watched, None, setup, &rapier.parameters)
}

/// Each body's final pose and velocities in rapier's run and in
/// nearmiss's (`nearmiss_final`).
fn final_bodies(
    scene: &Scene,
    rapier: &RapierScene,
    nearmiss_final: &[crate::motion::RigidState],
) -> Vec<RapierBody> {
    let triple = |v: &crate::math::Vector| [v.x, v.y, v.z];
    // A body with no state (none in either run) is where the scene put it.
    let parts = |state: Option<crate::motion::RigidState>, i: usize| {
        let start = &scene.model.bodies[i].pose;
        let state = state.unwrap_or(crate::motion::RigidState {
            position: start.translation.vector.into(),
            orientation: start.rotation,
            velocity: crate::math::Vector::zeros(),
            angular_velocity: crate::math::Vector::zeros(),
        });
        let q = state.orientation;
        (
            triple(&state.position.coords),
            [q.w, q.i, q.j, q.k],
            triple(&state.velocity),
            triple(&state.angular_velocity),
        )
    };
    (0..scene.model.bodies.len())
        .map(|i| {
            let (p, q, v, w) = parts(rapier.state(i), i);
            let (np, nq, nv, nw) = parts(nearmiss_final.get(i).copied(), i);
            RapierBody {
                body: scene.model.bodies[i].name.clone(),
                rapier_position: p,
                rapier_orientation: q,
                nearmiss_position: np,
                nearmiss_orientation: nq,
                rapier_velocity: v,
                rapier_angular_velocity: w,
                nearmiss_velocity: nv,
                nearmiss_angular_velocity: nw,
            }
        })
        .collect()
}

/// The comparison as three Markdown tables (pairs, then bodies' final
/// poses, then their final velocities).
pub fn rapier_markdown(comparison: &RapierComparison) -> String {
    let time = |t: Option<Real>| t.map_or("no contact".to_string(), |t| format!("{t:.9}"));
    let mut out = String::from(
        "| pair | nearmiss first contact | rapier first contact | rapier | deepest overlap |\n|---|---|---|---|---|\n",
    );
    for row in &comparison.pairs {
        let depth = row.max_penetration.map_or("not measured".to_string(), |d| format!("{d:.3e}"));
        out.push_str(&format!(
            "| {} / {} | {} | {} | {} | {} |\n",
            row.body_a,
            row.body_b,
            time(row.nearmiss),
            time(row.rapier),
            row.verdict,
            depth
        ));
    }
    let numbers = |v: &[Real]| {
        let parts: Vec<String> = v.iter().map(|x| format!("{x:.4}")).collect();
        format!("({})", parts.join(", "))
    };
    type Columns = fn(&RapierBody) -> [&[Real]; 4];
    let tables: [(&str, Columns); 2] = [
        (
            "final position, nearmiss | rapier alone | orientation [w, x, y, z], nearmiss | rapier alone",
            |row| {
                [
                    &row.nearmiss_position,
                    &row.rapier_position,
                    &row.nearmiss_orientation,
                    &row.rapier_orientation,
                ]
            },
        ),
        ("final velocity, nearmiss | rapier alone | angular velocity, nearmiss | rapier alone", |row| {
            [
                &row.nearmiss_velocity,
                &row.rapier_velocity,
                &row.nearmiss_angular_velocity,
                &row.rapier_angular_velocity,
            ]
        }),
    ];
    for (header, columns) in tables {
        out.push_str(&format!("\n| body | {header} |\n|---|---|---|---|---|\n"));
        for row in &comparison.bodies {
            let cells: Vec<String> = columns(row).iter().map(|v| numbers(v)).collect();
            out.push_str(&format!("| {} | {} |\n", row.body, cells.join(" | ")));
        }
    }
    out
}

/// A run of a scene in rapier alone, for speed comparisons.
#[derive(Copy, Clone, Debug, PartialEq)]
pub struct RapierAlone {
    /// Steps run.
    pub steps: u64,
    /// Wall time of the steps (not the set-up), seconds.
    pub wall_time_s: Real,
}

/// Runs `scene` in rapier alone, its CCD on for every moving body, each
/// body given its convex hull where the mesh is convex (or, with
/// `triangle_meshes`, every body its triangle mesh), and times the steps.
pub fn run_rapier_alone(scene: &Scene, triangle_meshes: bool) -> Result<RapierAlone, super::GuardError> {
    let mut scene = scene.clone();
    if triangle_meshes {
        for body in Arc::make_mut(&mut scene.model.bodies) {
            let material = body.material.get_or_insert(crate::scene::Material {
                friction: crate::scene::file::DEFAULT_FRICTION,
                restitution: 0.0,
                triangle_mesh: true,
            });
            material.triangle_mesh = true;
        }
    }
    let mut rapier = RapierScene::build(&scene, true, false)?;
    let clock = std::time::Instant::now();
    for step in 0..scene.run.steps {
        rapier.step(&scene, step);
    }
    Ok(RapierAlone { steps: scene.run.steps, wall_time_s: clock.elapsed().as_secs_f64() })
}

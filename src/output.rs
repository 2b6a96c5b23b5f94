//! What `nearmiss run` writes: `summary.json` and, when the scene asks for
//! a trace, `trace.csv`, in `<out>/<scene name>/`. Each file is written to a
//! temporary name in the same folder and renamed into place, so a reader
//! never sees a half-written file.

use std::fs;
use std::io::Write;
use std::path::{Path, PathBuf};

use serde::Serialize;

use crate::kernels::Feature;
use crate::math::{Point, Real};
use crate::report::PeerComparison;
use crate::scene::Scene;
use crate::stepper::{Contact, RunResult, Termination};
use crate::trace::write_trace_csv;

/// The `summary.json` document (DESIGN.md's fields, and more).
#[derive(Serialize)]
pub struct Summary<'a> {
    /// The scene's name.
    pub scene: &'a str,
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
    pub work: WorkJson,
    /// Seconds per stage (not deterministic).
    pub stage_wall_time_s: StagesJson,
    /// With `--compare parry`: parry's answers beside nearmiss's.
    #[serde(skip_serializing_if = "<[_]>::is_empty")]
    pub peer: &'a [PeerComparison],
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
    /// Distance at `time`.
    pub distance: Real,
    /// Closest point on `body_a`.
    pub point_a: [Real; 3],
    /// Closest point on `body_b`.
    pub point_b: [Real; 3],
    /// Triangle of `body_a`.
    pub triangle_a: usize,
    /// Triangle of `body_b`.
    pub triangle_b: usize,
    /// Feature of `triangle_a` (`vertex 0`, `edge 2`, `face`).
    pub feature_a: String,
    /// Feature of `triangle_b`.
    pub feature_b: String,
    /// How the CCD iteration ended.
    pub status: String,
    /// No contact is reported farther than this.
    pub contact_distance: Real,
    /// Every approach closer than this is reported.
    pub guaranteed_distance: Real,
}

/// A number in the shortest form that reads back to the same `f64`.
pub fn shortest(value: Real) -> String {
    format!("{value:?}")
}

/// Work counters in `summary.json`.
#[derive(Serialize)]
pub struct WorkJson {
    /// Mesh distance queries.
    pub distance_queries: usize,
    /// Triangle pairs evaluated.
    pub triangle_pairs: usize,
    /// Pair-steps skipped without a mesh query.
    pub pairs_culled: usize,
    /// Steps whose implicit gyroscopic solve did not converge.
    pub gyroscopic_unconverged: usize,
    /// Pairs handed to CCD by the broad phase, summed over steps.
    pub candidate_pairs: usize,
    /// Largest relative drift of an integrated body's mechanical energy.
    pub max_energy_drift: Real,
}

/// Stage times in `summary.json`.
#[derive(Serialize)]
pub struct StagesJson {
    /// Integration.
    pub integrate: Real,
    /// Broad phase.
    pub broad_phase: Real,
    /// CCD (the narrow phase).
    pub ccd: Real,
    /// The contact response.
    pub respond: Real,
    /// Re-arming pairs that separated.
    pub rearm: Real,
    /// Trace.
    pub trace: Real,
}

fn point(p: &Point) -> [Real; 3] {
    [p.x, p.y, p.z]
}

fn feature(f: Feature) -> String {
    match f {
        Feature::Vertex(i) => format!("vertex {i}"),
        Feature::Edge(i) => format!("edge {i}"),
        Feature::Face => "face".into(),
    }
}

/// The termination as a short text.
pub fn termination_text(result: &RunResult) -> String {
    match &result.termination {
        Termination::Completed => "completed".into(),
        Termination::FirstContact => "first_contact".into(),
        Termination::Diverged { step, reason, .. } => format!("diverged at step {step}: {reason}"),
        Termination::Undecided { pair: (a, b), time, step, iterations } => format!(
            "undecided at step {step}: the CCD of `{}` / `{}` could not decide in {iterations} iterations whether they touch after t = {} (they are apart until then; nothing later is known). Raise `ccd.max_iterations`, lower `dt`, or raise `ccd.distance_tolerance`",
            result.bodies[*a], result.bodies[*b], crate::output::shortest(*time)
        ),
    }
}

impl<'a> Summary<'a> {
    /// The summary of a run.
    pub fn of(result: &'a RunResult) -> Summary<'a> {
        Summary::with_peer(result, &[])
    }

    /// The summary of a run, with parry's answers beside.
    pub fn with_peer(result: &'a RunResult, peer: &'a [PeerComparison]) -> Summary<'a> {
        let contact = |c: &Contact| ContactJson {
            time: c.time,
            body_a: &result.bodies[c.body_a],
            body_b: &result.bodies[c.body_b],
            distance: c.distance,
            point_a: point(&c.point_a),
            point_b: point(&c.point_b),
            triangle_a: c.triangle_a,
            triangle_b: c.triangle_b,
            feature_a: feature(c.feature_a),
            feature_b: feature(c.feature_b),
            status: format!("{:?}", c.status),
            contact_distance: c.contact_distance,
            guaranteed_distance: c.guaranteed_distance,
        };
        let counters = &result.counters;
        Summary {
            scene: &result.scene,
            steps: result.steps,
            end_time: result.end_time,
            wall_time_s: result.wall_time_s,
            termination: termination_text(result),
            first_contact: result.first_contact.as_ref().map(contact),
            contacts: result.contacts.iter().map(contact).collect(),
            work: WorkJson {
                distance_queries: counters.distance_queries,
                triangle_pairs: counters.triangle_pairs,
                pairs_culled: counters.pairs_culled,
                gyroscopic_unconverged: counters.gyroscopic_unconverged,
                candidate_pairs: counters.candidate_pairs,
                max_energy_drift: counters.max_energy_drift,
            },
            stage_wall_time_s: StagesJson {
                integrate: counters.integrate_s,
                broad_phase: counters.broad_phase_s,
                ccd: counters.ccd_s,
                respond: counters.respond_s,
                rearm: counters.rearm_s,
                trace: counters.trace_s,
            },
            peer,
        }
    }

    /// Pretty JSON text.
    pub fn to_json(&self) -> String {
        // Serializing plain structs of numbers and strings cannot fail;
        // non-finite numbers become `null`.
        serde_json::to_string_pretty(self).unwrap_or_default() + "\n"
    }
}

/// Writes the run's files into `<out>/<scene>/` and returns their paths:
/// `summary.json`, and as the scene asks `trace.csv` and `distance.png`.
pub fn write_outputs(out: &Path, result: &RunResult, scene: &Scene) -> std::io::Result<Vec<PathBuf>> {
    write_outputs_with_peer(out, result, scene, &[])
}

/// [`write_outputs`], with parry's answers in `summary.json`.
pub fn write_outputs_with_peer(
    out: &Path,
    result: &RunResult,
    scene: &Scene,
    peer: &[PeerComparison],
) -> std::io::Result<Vec<PathBuf>> {
    let trace = scene.trace.is_some();
    let folder = out.join(&result.scene);
    fs::create_dir_all(&folder)?;
    let mut written = Vec::new();
    let summary = Summary::with_peer(result, peer).to_json();
    written.push(write_atomically(&folder.join("summary.json"), summary.as_bytes())?);
    if trace {
        let mut csv = Vec::new();
        write_trace_csv(&result.trace, &result.bodies, &mut csv)?;
        written.push(write_atomically(&folder.join("trace.csv"), &csv)?);
    }
    #[cfg(feature = "plot")]
    if let Some(plot) = &scene.plot {
        let path = folder.join("distance.png");
        crate::plot::render(&distance_chart(result, plot.log_y), &path).map_err(std::io::Error::other)?;
        written.push(path);
    }
    Ok(written)
}

/// The distance-over-time chart of a run's trace: one line per traced pair,
/// contacts marked.
#[cfg(feature = "plot")]
pub fn distance_chart(result: &RunResult, log_y: bool) -> crate::plot::Chart {
    use crate::plot::{Chart, Series};
    let mut pairs: Vec<(usize, usize)> = result.trace.iter().map(|r| r.pair).collect();
    pairs.sort_unstable();
    pairs.dedup();
    let series = pairs
        .iter()
        .map(|&pair| Series {
            label: format!("{} – {}", result.bodies[pair.0], result.bodies[pair.1]),
            points: result.trace.iter().filter(|r| r.pair == pair).map(|r| (r.time, r.distance)).collect(),
            line: true,
            point_labels: Vec::new(),
        })
        .collect();
    let marks = result
        .contacts
        .iter()
        .map(|c| {
            (
                c.time,
                format!(
                    "contact {} / {}: t = {:.6}",
                    result.bodies[c.body_a], result.bodies[c.body_b], c.time
                ),
            )
        })
        .collect();
    Chart {
        title: format!("{}: distance between traced pairs", result.scene),
        x_label: "time (scene time units)".into(),
        y_label: format!("distance (scene length units{})", if log_y { ", log scale" } else { "" }),
        log_x: false,
        log_y,
        series,
        marks,
    }
}

/// Writes a report file `name` into `folder` (created if needed), whole or
/// not at all; returns its path. Every report of the CLI goes through here.
pub fn write_report(folder: &Path, name: &str, bytes: &[u8]) -> std::io::Result<PathBuf> {
    fs::create_dir_all(folder)?;
    write_atomically(&folder.join(name), bytes)
}

/// Draws `chart` to `folder/name` (created if needed); returns its path.
#[cfg(feature = "plot")]
pub fn write_chart(folder: &Path, name: &str, chart: &crate::plot::Chart) -> std::io::Result<PathBuf> {
    fs::create_dir_all(folder)?;
    let path = folder.join(name);
    crate::plot::render(chart, &path).map_err(std::io::Error::other)?;
    Ok(path)
}

/// Writes `bytes` to a temporary file beside `path`, then renames it.
pub fn write_atomically(path: &Path, bytes: &[u8]) -> std::io::Result<PathBuf> {
    let name = path.file_name().map(|n| n.to_string_lossy().into_owned()).unwrap_or_default();
    let temporary = path.with_file_name(format!(".{name}.{}.tmp", std::process::id()));
    let result = (|| {
        let mut file = fs::File::create(&temporary)?;
        file.write_all(bytes)?;
        file.sync_all()?;
        fs::rename(&temporary, path)
    })();
    if result.is_err() {
        let _ = fs::remove_file(&temporary);
    }
    result.map(|_| path.to_path_buf())
}

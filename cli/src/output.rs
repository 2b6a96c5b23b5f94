//! What `nearmiss run` writes: `summary.json` and, when the scene asks for
//! a trace, `trace.csv` (and with a plot `distance.png`), in
//! `<out>/<scene name>/`.
//!
//! A run's files appear together or not at all: they are written into a
//! fresh staging folder beside the target (`.<scene>.<pid>.tmp`, per
//! process) and the folder is then swapped into place, so a reader never
//! sees a half-written run, and no file of an earlier run (a `trace.csv` the
//! new run did not write) sits beside the new ones. Files in the folder that
//! are not a run's (a sweep's `sweep.csv`) are carried over. Staging
//! folders left by a killed process are removed by the next run. Report
//! files (sweeps, suites) are written one by one, each under a temporary
//! name and renamed ([`write_report`]).

use std::fs;
use std::io::Write;
use std::path::{Path, PathBuf};

use nearmiss::math::Real;
use nearmiss::run::write_trace_csv;
use nearmiss::run::{Contact, RunResult};
use nearmiss::scene::Scene;
pub use nearmiss_summary::{
    summary_json, ContactJson, DepthJson, NearMissJson, OverlapJson, Peers, PoseJson, ResponseJson, Summary,
};

/// Writes the run's files into `<out>/<scene>/` and returns their paths:
/// `summary.json`, and as the scene asks `trace.csv` and `distance.png`.
pub fn write_outputs(out: &Path, result: &RunResult, scene: &Scene) -> std::io::Result<Vec<PathBuf>> {
    write_outputs_with_peer(out, result, scene, &Peers::default())
}

/// How many times a run's folder swap is tried when a concurrent run into
/// the same folder gets in between its two renames. `8`.
pub const SWAP_ATTEMPTS: usize = 8;

/// The file names a run writes (and replaces as a whole).
pub const RUN_FILES: [&str; 7] = [
    "summary.json",
    "trace.csv",
    "distance.png",
    crate::run_page::NEAREST_NEAR_MISS_PICTURE,
    "poses.csv",
    "animation.glb",
    "report.md",
];

/// Whether `name` is a file a run writes: one of [`RUN_FILES`] or a contact
/// picture (`contact_<n>.png`).
pub fn is_run_file(name: &str) -> bool {
    RUN_FILES.contains(&name)
        || name
            .strip_prefix("contact_")
            .and_then(|rest| rest.strip_suffix(".png"))
            .is_some_and(|n| !n.is_empty() && n.bytes().all(|b| b.is_ascii_digit()))
}

/// The scene file whose outputs `folder` holds, if that is another file
/// than `source` (two scenes of one name write to one folder): read from
/// its `summary.json`. `None` when the folder is new, holds `source`'s
/// outputs, or its `source` no longer resolves to a file (nothing to warn
/// of with certainty).
pub fn previous_source(folder: &Path, source: &Path) -> Option<String> {
    let text = fs::read_to_string(folder.join("summary.json")).ok()?;
    let summary: serde_json::Value = serde_json::from_str(&text).ok()?;
    let previous = summary.get("source")?.as_str()?;
    let (old, new) = (fs::canonicalize(previous).ok()?, fs::canonicalize(source).ok()?);
    (old != new).then(|| previous.to_string())
}

/// [`write_outputs`], with the peers' answers in `summary.json`.
pub fn write_outputs_with_peer(
    out: &Path,
    result: &RunResult,
    scene: &Scene,
    peers: &Peers<'_>,
) -> std::io::Result<Vec<PathBuf>> {
    fs::create_dir_all(out)?;
    remove_abandoned_staging(out, &result.scene);
    let folder = out.join(&result.scene);
    let staging = out.join(format!(".{}.{}.tmp", result.scene, std::process::id()));
    let _ = fs::remove_dir_all(&staging);
    fs::create_dir(&staging)?;
    let written = write_run_files(&staging, result, scene, peers)
        .and_then(|names| {
            carry_over(&folder, &staging)?;
            swap_into_place(&staging, &folder, out, &result.scene)?;
            Ok(names)
        })
        .inspect_err(|_| {
            let _ = fs::remove_dir_all(&staging);
        })?;
    Ok(written.iter().map(|name| folder.join(name)).collect())
}

/// Writes the run's files into `folder`; returns their names.
fn write_run_files(
    folder: &Path,
    result: &RunResult,
    scene: &Scene,
    peers: &Peers<'_>,
) -> std::io::Result<Vec<String>> {
    if let Some(field) = result.first_non_finite() {
        // Never a silent null or inf in an output: nothing is written.
        return Err(std::io::Error::other(format!(
            "the run produced a number that is not finite ({field}); nothing was written. Please report the scene"
        )));
    }
    let mut written = Vec::new();
    let summary = Summary::of_run(result, scene, peers).to_json();
    write_synced(&folder.join("summary.json"), summary.as_bytes())?;
    written.push("summary.json".to_string());
    if scene.run().trace.is_some() {
        let mut csv = Vec::new();
        write_trace_csv(&result.trace, &result.bodies, &mut csv)?;
        write_synced(&folder.join("trace.csv"), &csv)?;
        written.push("trace.csv".to_string());
    }
    if scene.run().poses.is_some() {
        let mut csv = Vec::new();
        nearmiss::run::write_poses_csv(&result.poses, &result.bodies, &mut csv)?;
        write_synced(&folder.join("poses.csv"), &csv)?;
        written.push("poses.csv".to_string());
        let glb = crate::animation::glb(scene, &result.poses).map_err(std::io::Error::other)?;
        write_synced(&folder.join("animation.glb"), &glb)?;
        written.push("animation.glb".to_string());
    }
    #[cfg(feature = "plot")]
    if let Some(plot) = &scene.run().plot {
        let path = folder.join("distance.png");
        crate::plot::render(&distance_chart(result, plot.log_y), &path).map_err(std::io::Error::other)?;
        written.push("distance.png".to_string());
        for n in crate::contact_picture::pictured(result.contacts.len(), &plot.contacts) {
            let contact = &result.contacts[n - 1];
            let meshes =
                (&*scene.model().bodies[contact.body_a].mesh, &*scene.model().bodies[contact.body_b].mesh);
            let names = (result.bodies[contact.body_a].as_str(), result.bodies[contact.body_b].as_str());
            let name = format!("contact_{n}.png");
            crate::contact_picture::draw_contact(contact, n, meshes, names, &folder.join(&name))
                .map_err(std::io::Error::other)?;
            written.push(name);
        }
        if let Some(miss) = result.near_misses.first() {
            let meshes = (&*scene.model().bodies[miss.body_a].mesh, &*scene.model().bodies[miss.body_b].mesh);
            let names = (result.bodies[miss.body_a].as_str(), result.bodies[miss.body_b].as_str());
            let encounter = crate::contact_picture::Encounter::of_near_miss(miss, "nearest near miss");
            let path = folder.join(crate::run_page::NEAREST_NEAR_MISS_PICTURE);
            crate::contact_picture::draw_encounter(&encounter, meshes, names, &path)
                .map_err(std::io::Error::other)?;
            written.push(crate::run_page::NEAREST_NEAR_MISS_PICTURE.to_string());
        }
    }
    written.push("report.md".to_string());
    let names: Vec<&str> = written.iter().map(String::as_str).collect();
    let page = crate::run_page::run_page(result, scene, &names);
    write_synced(&folder.join("report.md"), page.as_bytes())?;
    Ok(written)
}

/// Hard-links (or copies) into `staging` every entry of the old `folder`
/// that is not a run file, so that what else lives there survives the swap.
fn carry_over(folder: &Path, staging: &Path) -> std::io::Result<()> {
    let Ok(entries) = fs::read_dir(folder) else { return Ok(()) };
    for entry in entries {
        let entry = entry?;
        let name = entry.file_name();
        let target = staging.join(&name);
        if is_run_file(&name.to_string_lossy()) || target.exists() {
            continue;
        }
        link_or_copy(&entry.path(), &target)?;
    }
    Ok(())
}

fn link_or_copy(from: &Path, to: &Path) -> std::io::Result<()> {
    if fs::symlink_metadata(from)?.is_dir() {
        fs::create_dir(to)?;
        for entry in fs::read_dir(from)? {
            let entry = entry?;
            link_or_copy(&entry.path(), &to.join(entry.file_name()))?;
        }
        return Ok(());
    }
    fs::hard_link(from, to).or_else(|_| fs::copy(from, to).map(|_| ()))
}

/// Puts `staging` where `folder` is: the old folder is renamed aside first
/// and removed after (two renames; retried if a concurrent run gets in
/// between).
fn swap_into_place(staging: &Path, folder: &Path, out: &Path, scene: &str) -> std::io::Result<()> {
    let aside = out.join(format!(".{scene}.{}.old", std::process::id()));
    let mut last_error = None;
    for _ in 0..SWAP_ATTEMPTS {
        if folder.exists() {
            let _ = fs::remove_dir_all(&aside);
            if let Err(error) = fs::rename(folder, &aside) {
                last_error = Some(error);
                continue;
            }
        }
        match fs::rename(staging, folder) {
            Ok(()) => {
                let _ = fs::remove_dir_all(&aside);
                return Ok(());
            }
            Err(error) => last_error = Some(error),
        }
    }
    Err(last_error.unwrap_or_else(|| std::io::Error::other("the output folder kept changing")))
}

/// Removes the staging folders (and set-aside old folders) of `scene` left
/// in `out` by processes that no longer run (killed mid-write).
fn remove_abandoned_staging(out: &Path, scene: &str) {
    let Ok(entries) = fs::read_dir(out) else { return };
    let prefix = format!(".{scene}.");
    for entry in entries.flatten() {
        let name = entry.file_name().to_string_lossy().into_owned();
        let Some(rest) = name.strip_prefix(&prefix) else { continue };
        let Some((pid, kind)) = rest.split_once('.') else { continue };
        let Ok(pid) = pid.parse::<u32>() else { continue };
        if (kind == "tmp" || kind == "old") && pid != std::process::id() && !process_alive(pid) {
            let _ = fs::remove_dir_all(entry.path());
        }
    }
}

/// Whether process `pid` still runs (where the system says; elsewhere,
/// assumed alive, so nothing of a running process is ever removed).
fn process_alive(pid: u32) -> bool {
    let proc = Path::new("/proc");
    !proc.is_dir() || proc.join(pid.to_string()).exists()
}

/// Writes `bytes` to `path` and syncs it to disk.
fn write_synced(path: &Path, bytes: &[u8]) -> std::io::Result<()> {
    let mut file = fs::File::create(path)?;
    file.write_all(bytes)?;
    file.sync_all()
}

/// Checks, before a run, that `out` can take its outputs: creates it if
/// needed and writes (then removes) a probe file.
pub fn check_writable(out: &Path) -> std::io::Result<()> {
    fs::create_dir_all(out)?;
    let probe = out.join(format!(".nearmiss-probe.{}", std::process::id()));
    fs::write(&probe, b"")?;
    fs::remove_file(&probe)
}

/// Contacts labelled on the distance chart (the first ones); every contact
/// gets a red line across the chart at its time.
pub const LABELLED_CONTACTS: usize = 3;

/// Traced pairs named in the distance chart's legend (the first ones; the
/// title says how many there are).
pub const LEGEND_PAIRS: usize = 10;

/// The distance axis is chosen logarithmic when the trace's positive
/// distances (contacts included) span more than this ratio: on a linear
/// axis the last hundredth of a fall would be a flat line on the floor.
pub const LOG_AXIS_SPAN: Real = 100.0;

/// The decades a log distance axis shows below the largest distance:
/// resting contacts at 1e-14 would otherwise squeeze the approach into the
/// top of the chart.
pub const LOG_AXIS_DECADES: i32 = 8;

/// The distance-over-time chart of a run's trace: one line per traced
/// pair, each running down to the distance at its contacts (the CCD's
/// distance at the time of impact, inside the step), every contact a red line
/// on the time axis and the first [`LABELLED_CONTACTS`] labelled. `log_y`:
/// the axis asked for, or `None` to choose it by [`LOG_AXIS_SPAN`].
#[cfg(feature = "plot")]
pub fn distance_chart(result: &RunResult, log_y: Option<bool>) -> crate::plot::Chart {
    use crate::plot::{Chart, Series};
    let mut pairs: Vec<(usize, usize)> = result.trace.iter().map(|r| r.pair).collect();
    pairs.sort_unstable();
    pairs.dedup();
    let samples = pair_samples(result, &pairs);
    // The traced pairs' near misses: their certified closest approaches,
    // which the samples at the step ends pass by.
    let approaches: Vec<(Real, Real)> = result
        .near_misses
        .iter()
        .filter(|m| pairs.iter().any(|&p| (p.0.min(p.1), p.0.max(p.1)) == (m.body_a, m.body_b)))
        .map(|m| (m.time, m.distance))
        .collect();
    let positive =
        samples.iter().flatten().chain(&approaches).map(|p| p.1).filter(|d| *d > 0.0 && d.is_finite());
    let (smallest, largest) =
        positive.fold((Real::INFINITY, 0.0 as Real), |(lo, hi), d| (lo.min(d), hi.max(d)));
    let chosen = log_y.is_none();
    // Overlapping meshes trace minus their depth: a linear axis shows it.
    let overlapping = samples.iter().flatten().any(|p| p.1 < 0.0);
    let log_y = log_y.unwrap_or(!overlapping && largest > LOG_AXIS_SPAN * smallest);
    // On a log axis a distance of 0 (touching), or below
    // `LOG_AXIS_DECADES` decades under the largest, is drawn at the floor.
    let floor = smallest.max(largest * Real::powi(10.0, -LOG_AXIS_DECADES)).clamp(Real::MIN_POSITIVE, 1.0);
    let shown = |d: Real| if log_y { d.max(floor) } else { d };
    let series = pairs
        .iter()
        .zip(&samples)
        .enumerate()
        .map(|(k, (&pair, points))| Series {
            label: if k < LEGEND_PAIRS {
                format!("{} – {}", result.bodies[pair.0], result.bodies[pair.1])
            } else {
                String::new()
            },
            points: points.iter().map(|&(t, d)| (t, shown(d))).collect(),
            line: true,
            point_labels: Vec::new(),
        })
        .chain((!approaches.is_empty()).then(|| Series {
            label: "closest approach (near misses, certified)".to_string(),
            points: approaches.iter().map(|&(t, d)| (t, shown(d))).collect(),
            line: false,
            point_labels: approaches.iter().map(|&(_, d)| crate::text::approx(d, 6)).collect(),
        }))
        .collect();
    let mut title = format!("{}: distance between traced pairs", result.scene);
    if pairs.len() > LEGEND_PAIRS {
        title.push_str(&format!(" ({} pairs, the first {LEGEND_PAIRS} named)", pairs.len()));
    }
    Chart {
        title,
        x_label: time_label(result.contacts.len()),
        y_label: distance_label(log_y, overlapping, chosen, floor),
        log_x: false,
        log_y,
        series,
        marks: contact_marks(result),
        ticks: result.contacts.iter().map(|c| c.time).collect(),
    }
}

/// Each traced pair's samples: the trace's, and its contacts' (time of
/// impact, distance there), in time order.
fn pair_samples(result: &RunResult, pairs: &[(usize, usize)]) -> Vec<Vec<(Real, Real)>> {
    let contact_pair = |c: &Contact| (c.body_a.min(c.body_b), c.body_a.max(c.body_b));
    pairs
        .iter()
        .map(|&pair| {
            let sampled: Vec<(Real, Real)> =
                result.trace.iter().filter(|r| r.pair == pair).map(|r| (r.time, r.distance)).collect();
            // A contact at a sample's time is that sample (which, where the
            // meshes overlap, is signed: the contact's surface distance, 0,
            // would draw a spike).
            let mut points: Vec<(Real, Real)> = sampled
                .iter()
                .copied()
                .chain(
                    result
                        .contacts
                        .iter()
                        .filter(|c| contact_pair(c) == (pair.0.min(pair.1), pair.0.max(pair.1)))
                        .filter(|c| !sampled.iter().any(|s| s.0 == c.time))
                        .map(|c| (c.time, c.closest.distance)),
                )
                .collect();
            points.sort_by(|x, y| x.0.total_cmp(&y.0));
            points
        })
        .collect()
}

/// The first contacts' marks on the chart: time and label.
fn contact_marks(result: &RunResult) -> Vec<(Real, String)> {
    result
        .contacts
        .iter()
        .take(LABELLED_CONTACTS)
        .enumerate()
        .map(|(n, c)| {
            (
                c.time,
                format!(
                    "contact {}: {} / {}, t = {}",
                    n + 1,
                    result.bodies[c.body_a],
                    result.bodies[c.body_b],
                    crate::text::time(c.time)
                ),
            )
        })
        .collect()
}

/// The time axis's label, with how the run's `contacts` are drawn.
fn time_label(contacts: usize) -> String {
    match contacts {
        0 => "time (scene time units)".to_string(),
        n if n <= LABELLED_CONTACTS => {
            format!("time (scene time units); {}, red", crate::text::count(n as u64, "contact"))
        }
        n => format!(
            "time (scene time units); {n} contacts: red lines, the first {LABELLED_CONTACTS} labelled"
        ),
    }
}

/// The distance axis's label: its scale, whether it was `chosen` (not
/// asked for), and where overlaps and distances below `floor` go.
fn distance_label(log_y: bool, overlapping: bool, chosen: bool, floor: Real) -> String {
    let how = if chosen { "chosen: " } else { "" };
    match (log_y, overlapping) {
        (true, false) => format!("distance ({how}log scale; 0 and below {floor:.0e} drawn at it)"),
        (true, true) => format!("distance ({how}log scale; overlaps, 0 and below {floor:.0e} drawn at it)"),
        (false, false) => {
            format!("distance (scene length units{})", if chosen { ", linear: chosen" } else { "" })
        }
        (false, true) => "signed distance (scene length units; below 0: overlap depth)".to_string(),
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
    let result = write_synced(&temporary, bytes).and_then(|()| fs::rename(&temporary, path));
    if result.is_err() {
        let _ = fs::remove_file(&temporary);
    }
    result.map(|_| path.to_path_buf())
}

//! Regression checks of scenes against their stated expectations
//! (`nearmiss test`).

use std::path::{Path, PathBuf};

use crate::text;
use nearmiss::math::Real;
use nearmiss::run::{RunResult, Termination};
use nearmiss::scene::{Expectation, Scene};

/// The verdict on one scene.
#[derive(Clone, Debug, PartialEq)]
pub struct Verdict {
    /// Whether the run met the expectation.
    pub passed: bool,
    /// The expectation, in words.
    pub expected: String,
    /// What the run gave, in words.
    pub obtained: String,
    /// obtained − expected time, when both are times.
    pub error: Option<Real>,
    /// Why a failed expectation may be the expectation's own fault: a
    /// contact early by no more than the contact contract allows, against a
    /// tolerance tighter than that.
    pub hint: Option<String>,
}

/// The speed at which a contact's closest points close along the line
/// between them, the bodies as they are at the contact (positive when
/// closing).
fn closing_speed(result: &RunResult, contact: &nearmiss::run::Contact) -> Real {
    let [a, b] = [contact.body_a, contact.body_b].map(|i| &result.final_states[i]);
    let velocity = |s: &nearmiss::motion::RigidState, p: &nearmiss::math::Point| {
        s.velocity + s.angular_velocity.cross(&(p - s.position))
    };
    let relative = velocity(a, &contact.closest.point_a) - velocity(b, &contact.closest.point_b);
    let gap = contact.closest.point_b - contact.closest.point_a;
    if gap.norm() > 0.0 {
        relative.dot(&gap) / gap.norm()
    } else {
        relative.norm()
    }
}

/// The hint for a contact `early` before the expected time (positive)
/// that the contact contract allows (its contact distance over the closing
/// speed) but the expectation's `tolerance` does not.
fn contract_hint(
    result: &RunResult,
    contact: &nearmiss::run::Contact,
    early: Real,
    tolerance: Real,
) -> Option<String> {
    let closing = closing_speed(result, contact);
    if !(early > tolerance && closing > 0.0) {
        return None;
    }
    let allowed = contact.contact_distance / closing;
    // A little over the bound: the closing speed is taken at the contact.
    (early <= 1.01 * allowed).then(|| {
        format!(
            "the contact came {} early, within what the CCD's contract allows here: its contact distance {} over the closing speed {} is {}. The expectation's tolerance {} is tighter: widen it to at least {}, or make `ccd.distance_tolerance` smaller (it sets the contact distance)",
            text::approx(early, 3),
            text::approx(contact.contact_distance, 3),
            text::approx(closing, 3),
            text::approx(allowed, 3),
            text::approx(tolerance, 2),
            text::approx(allowed, 2)
        )
    })
}

/// Checks a run against the scene's expectation (`None` without one).
pub fn verdict(scene: &Scene, result: &RunResult) -> Option<Verdict> {
    let expectation = scene.run().expect.as_ref()?;
    let name = |i: usize| scene.model().bodies[i].name.as_str();
    let obtained = match (&result.termination, &result.first_contact) {
        (Termination::Diverged { reason, .. }, _) => format!("diverged: {reason}"),
        (Termination::NotStarted { .. } | Termination::Failed { .. }, _) => result.termination_text(),
        (Termination::Undecided { .. }, None) => result.termination_text(),
        (_, Some(c)) => {
            format!("contact {} / {} at t = {}", name(c.body_a), name(c.body_b), text::time(c.time))
        }
        (_, None) => format!("no contact up to t = {}", text::time(result.end_time)),
    };
    let diverged = matches!(
        result.termination,
        Termination::Diverged { .. } | Termination::NotStarted { .. } | Termination::Failed { .. }
    );
    let undecided = matches!(result.termination, Termination::Undecided { .. });
    Some(match expectation {
        Expectation::NoContact => Verdict {
            passed: !diverged && !undecided && result.first_contact.is_none(),
            expected: "no contact".into(),
            obtained,
            error: None,
            hint: None,
        },
        Expectation::NearMiss { bodies, distance, tolerance } => {
            let miss = result
                .near_misses
                .iter()
                .find(|m| (m.body_a, m.body_b) == *bodies)
                .filter(|_| !diverged && !undecided);
            let obtained = match miss {
                Some(m) => format!(
                    "near miss {} / {}: {} at t = {} (never closer than {})",
                    name(m.body_a),
                    name(m.body_b),
                    text::approx(m.distance, 9),
                    text::time(m.time),
                    text::approx(m.lower, 9)
                ),
                None => format!("no near miss of {} / {} ({obtained})", name(bodies.0), name(bodies.1)),
            };
            Verdict {
                passed: miss
                    .is_some_and(|m| m.lower >= distance - tolerance && m.distance <= distance + tolerance),
                expected: format!(
                    "near miss {} / {}: {} ± {}",
                    name(bodies.0),
                    name(bodies.1),
                    text::approx(*distance, 9),
                    text::approx(*tolerance, 2)
                ),
                obtained,
                error: miss.map(|m| m.distance - distance),
                hint: None,
            }
        }
        Expectation::Contact { time, tolerance, bodies, recorded } => {
            let contact = result.first_contact.as_ref().filter(|_| !diverged);
            let error = contact.map(|c| c.time - time);
            let same_bodies = contact.is_some_and(|c| (c.body_a, c.body_b) == *bodies);
            let passed = same_bodies && error.is_some_and(|e| e.abs() <= *tolerance);
            let hint = match (contact, error) {
                (Some(c), Some(e)) if same_bodies && !passed => contract_hint(result, c, -e, *tolerance),
                _ => None,
            };
            Verdict {
                passed,
                expected: format!(
                    "contact {} / {} at t = {} ± {}{}",
                    name(bodies.0),
                    name(bodies.1),
                    text::time(*time),
                    text::approx(*tolerance, 2),
                    if *recorded { " (recorded)" } else { "" }
                ),
                obtained,
                error,
                hint,
            }
        }
    })
}

/// The scene files (`.ron`) named by `path`: the file itself, or every
/// `.ron` file under the folder, sorted.
pub fn scene_files(path: &Path) -> std::io::Result<Vec<PathBuf>> {
    if !path.is_dir() {
        // A missing file is reported when it is loaded.
        return Ok(vec![path.to_path_buf()]);
    }
    let mut found = Vec::new();
    let mut folders = vec![path.to_path_buf()];
    while let Some(folder) = folders.pop() {
        for entry in std::fs::read_dir(&folder)? {
            let entry = entry?.path();
            if entry.is_dir() {
                folders.push(entry);
            } else if entry.extension().is_some_and(|e| e == "ron") {
                found.push(entry);
            }
        }
    }
    found.sort();
    Ok(found)
}

/// What `nearmiss test --record` did to a scene.
#[derive(Clone, Debug, PartialEq)]
pub enum Recorded {
    /// The run's answer was written as the expectation (in words).
    Pinned(String),
    /// The scene's expectation was derived by analysis: left as it is.
    KeptDerived,
}

/// A recorded expectation's tolerance is this many times the time the
/// contact's bodies take to close its contact distance at their closing
/// speed (the most a change within the CCD's contract can move the time).
/// `2.0`.
pub const RECORD_TOLERANCE_FACTOR: Real = 2.0;

/// Pins the current answer of the scene at `path` as its expectation
/// (`nearmiss test --record`): runs it to its first contact, and writes
/// `expect: Contact(time, tolerance, bodies, recorded: true)` (or
/// `NoContact`) into the file, marked as recorded. The tolerance is
/// [`RECORD_TOLERANCE_FACTOR`] × contact distance / closing speed (one step
/// `dt` if the bodies do not close). A scene whose expectation was derived
/// (not recorded) is left alone, as is a run that diverged or could not
/// decide (an error). Returns what was recorded, in words.
pub fn record(path: &Path, max_steps: u64) -> Result<Recorded, String> {
    use nearmiss::scene::{set_expectation, RECORDED_COMMENT};
    let text = nearmiss::scene::read_text(path, nearmiss::scene::MAX_SCENE_BYTES, "scene file")
        .map_err(|e| format!("{}: {e}", path.display()))?;
    let scene = Scene::load_within(path, max_steps).map_err(|e| e.to_string())?;
    let derived = match &scene.run().expect {
        None => false,
        Some(Expectation::Contact { recorded, .. }) => !recorded,
        Some(Expectation::NoContact) => !text.contains(RECORDED_COMMENT),
        // A near miss is derived (or written by hand): never recorded over.
        Some(_) => true,
    };
    if derived {
        return Ok(Recorded::KeptDerived);
    }
    let first_contact_only = scene.stopping_at_first_contact();
    let result = nearmiss::run(&first_contact_only);
    if !matches!(result.termination, Termination::Completed | Termination::FirstContact) {
        return Err(format!("{}: not recorded: {}", path.display(), result.termination_text()));
    }
    let name = |i: usize| scene.model().bodies[i].name.as_str();
    let (value, words, intended) = match &result.first_contact {
        None => (
            "NoContact".to_string(),
            format!("no contact up to t = {}", text::time(result.end_time)),
            Expectation::NoContact,
        ),
        Some(c) => {
            let closing = closing_speed(&result, c);
            let tolerance = if closing > 0.0 {
                RECORD_TOLERANCE_FACTOR * c.contact_distance / closing
            } else {
                scene.model().dt
            };
            let value = format!(
                "Contact(time: {:?}, tolerance: {:?}, bodies: ({:?}, {:?}), recorded: true)",
                c.time,
                tolerance,
                name(c.body_a),
                name(c.body_b)
            );
            let words = format!(
                "contact {} / {} at t = {} ± {}",
                name(c.body_a),
                name(c.body_b),
                text::time(c.time),
                text::approx(tolerance, 2)
            );
            let intended = Expectation::Contact {
                time: c.time,
                tolerance,
                bodies: (c.body_a, c.body_b),
                recorded: true,
            };
            (value, words, intended)
        }
    };
    let updated = set_expectation(&text, &value).map_err(|e| format!("{}: {e}", path.display()))?;
    // Written beside, loaded back, and only then put in place.
    let name_of = path.file_name().map(|n| n.to_string_lossy().into_owned()).unwrap_or_default();
    let staging = path.with_file_name(format!(".{name_of}.{}.record", std::process::id()));
    std::fs::write(&staging, &updated).map_err(|e| format!("{}: {e}", staging.display()))?;
    match Scene::load(&staging).map(|s| s.into_parts().1.expect) {
        Ok(Some(loaded)) if loaded == intended => {
            std::fs::rename(&staging, path).map_err(|e| format!("{}: {e}", path.display()))?;
            Ok(Recorded::Pinned(words))
        }
        other => {
            let _ = std::fs::remove_file(&staging);
            let why = match other {
                Err(error) => error.to_string(),
                Ok(loaded) => format!("its expectation read back as {loaded:?}"),
            };
            Err(format!("{}: not recorded, the file is left unchanged: the rewritten text did not load back as recorded: {why}", path.display()))
        }
    }
}

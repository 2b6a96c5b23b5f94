//! Regression checks of scenes against their stated expectations
//! (`nearmiss test`).

use std::path::{Path, PathBuf};

use crate::math::Real;
use crate::scene::{Expectation, Scene};
use crate::stepper::{RunResult, Termination};

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
}

/// Checks a run against the scene's expectation (`None` without one).
pub fn verdict(scene: &Scene, result: &RunResult) -> Option<Verdict> {
    let expectation = scene.expect.as_ref()?;
    let name = |i: usize| scene.bodies[i].name.as_str();
    let obtained = match (&result.termination, &result.first_contact) {
        (Termination::Diverged { reason, .. }, _) => format!("diverged: {reason}"),
        (Termination::Undecided { .. }, None) => crate::output::termination_text(result),
        (_, Some(c)) => format!("contact {} / {} at t = {:.12e}", name(c.body_a), name(c.body_b), c.time),
        (_, None) => format!("no contact up to t = {:.6e}", result.end_time),
    };
    let diverged = matches!(result.termination, Termination::Diverged { .. });
    let undecided = matches!(result.termination, Termination::Undecided { .. });
    Some(match expectation {
        Expectation::NoContact => Verdict {
            passed: !diverged && !undecided && result.first_contact.is_none(),
            expected: "no contact".into(),
            obtained,
            error: None,
        },
        Expectation::Contact { time, tolerance, bodies } => {
            let contact = result.first_contact.as_ref().filter(|_| !diverged);
            let error = contact.map(|c| c.time - time);
            let same_bodies = contact.is_some_and(|c| (c.body_a, c.body_b) == *bodies);
            Verdict {
                passed: same_bodies && error.is_some_and(|e| e.abs() <= *tolerance),
                expected: format!(
                    "contact {} / {} at t = {:.12e} ± {:.1e}",
                    name(bodies.0),
                    name(bodies.1),
                    time,
                    tolerance
                ),
                obtained,
                error,
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

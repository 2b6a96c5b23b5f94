//! `report.md`: one page per run that puts the summary, the plot and the
//! files a run wrote together, readable in a browser or a repository
//! viewer without opening five files. Every link is relative to the run's
//! folder and names a file written beside it.

use std::fmt::Write;

use crate::text;
use nearmiss::run::{Contact, RunResult};
use nearmiss::scene::Scene;

/// Contacts listed in the page's table (the first ones; the count is
/// always given, and `summary.json` has them all).
pub const LISTED_CONTACTS: usize = 20;

/// The picture of a run's nearest near miss (with `plot` and
/// `near_misses` in the scene).
pub const NEAREST_NEAR_MISS_PICTURE: &str = "nearest_near_miss.png";

/// The page of a run that wrote `files` (names in its folder).
pub fn run_page(result: &RunResult, scene: &Scene, files: &[&str]) -> String {
    let mut page = String::new();
    summary_table(&mut page, result, scene);
    overlaps_table(&mut page, result);
    contacts_table(&mut page, result, files);
    near_misses_table(&mut page, result, scene, files);
    if let Some(note) = missing_pictures(scene, result) {
        let _ = writeln!(page, "{note}.\n");
    }
    if files.contains(&"distance.png") {
        let _ = writeln!(page, "## Distance over time\n\n![distance between traced pairs](distance.png)\n");
    }
    files_list(&mut page, files);
    page
}

/// The run in a table: how it ended, its steps, contacts, work, and the
/// expectation's verdict.
fn summary_table(page: &mut String, result: &RunResult, scene: &Scene) {
    let _ = writeln!(page, "# {}\n", result.scene);
    if scene.run().source != nearmiss::scene::FROM_STRING {
        let _ = writeln!(page, "Scene file: `{}`\n", scene.run().source);
    }
    let _ = writeln!(page, "| | |\n|---|---|");
    let _ = writeln!(page, "| ended | {} |", cell(&result.termination_text()));
    let _ = writeln!(
        page,
        "| steps | {} of dt = {} (to t = {}) |",
        result.steps,
        text::time(scene.model().dt),
        text::time(result.end_time)
    );
    let _ = writeln!(page, "| contacts | {} |", result.contacts.len());
    if let Some(solver) = &result.solver {
        let _ = writeln!(page, "| response solved by | {} |", solver.engine);
    }
    let _ = writeln!(page, "| wall time | {} |", text::wall(result.wall_time_s));
    let c = &result.counters.work;
    let _ = writeln!(
        page,
        "| work | {}, {}, {} skipped without a mesh query |",
        text::count(c.distance_queries as u64, "CCD advancement step"),
        text::count(c.triangle_pairs as u64, "triangle pair"),
        text::count(c.pairs_culled as u64, "pair-step")
    );
    page.push('\n');
    if let Some(verdict) = crate::regression::verdict(scene, result) {
        let _ = writeln!(
            page,
            "**{}**: expected {}; obtained {}.\n",
            if verdict.passed { "Expectation met" } else { "Expectation NOT met" },
            verdict.expected,
            verdict.obtained
        );
    }
}

/// The bodies overlapping at the start, with their depths.
fn overlaps_table(page: &mut String, result: &RunResult) {
    let name = |i: usize| cell(&result.bodies[i]);
    let overlaps = &result.initial_overlaps;
    if !overlaps.is_empty() {
        let _ = writeln!(
            page,
            "## Overlapping at the start\n\nBodies whose solids overlap at t = 0: the depth is the shortest move that separates them (both meshes convex), or the deepest local depth where their surfaces cross (closed meshes, not both convex); the curve is where their surfaces cross (green in the contact pictures).\n"
        );
        let _ = writeln!(page, "| bodies | depth | moving the second body along | curve | crossing triangle pairs |\n|---|---|---|---|---|");
        for overlap in overlaps {
            let (depth, along) = match &overlap.depth {
                Some(d) => (
                    text::approx(d.depth, 6),
                    format!(
                        "({}, {}, {})",
                        text::approx(d.direction.x, 3),
                        text::approx(d.direction.y, 3),
                        text::approx(d.direction.z, 3)
                    ),
                ),
                None => match overlap.local_depth {
                    Some((lower, upper)) => (
                        format!(
                            "{} to {} (local: a mesh is not convex)",
                            text::approx(lower, 6),
                            text::approx(upper, 6)
                        ),
                        "—".to_string(),
                    ),
                    None => ("— (a mesh is not closed)".to_string(), "—".to_string()),
                },
            };
            let _ = writeln!(
                page,
                "| {} / {} | {depth} | {along} | {} long | {} |",
                name(overlap.body_a),
                name(overlap.body_b),
                text::approx(overlap.intersection.length(), 6),
                overlap.intersection.pairs.len()
            );
        }
        page.push('\n');
    }
}

/// The first contacts, and their pictures.
fn contacts_table(page: &mut String, result: &RunResult, files: &[&str]) {
    let name = |i: usize| cell(&result.bodies[i]);
    if !result.contacts.is_empty() {
        let _ = writeln!(page, "## Contacts\n");
        if result.contacts.len() > LISTED_CONTACTS {
            let _ = writeln!(
                page,
                "The first {LISTED_CONTACTS} of {}; `summary.json` lists them all.\n",
                result.contacts.len()
            );
        }
        let _ = writeln!(
            page,
            "| # | time | bodies | features | distance | contact distance |\n|---|---|---|---|---|---|"
        );
        for (n, contact) in result.contacts.iter().take(LISTED_CONTACTS).enumerate() {
            let _ = writeln!(
                page,
                "| {} | {} | {} / {} | {} | {} | {} |",
                n + 1,
                text::time(contact.time),
                name(contact.body_a),
                name(contact.body_b),
                features(contact),
                text::approx(contact.closest.distance, 3),
                text::approx(contact.contact_distance, 3)
            );
        }
        page.push('\n');
        for picture in files.iter().filter(|f| f.starts_with("contact_")) {
            let _ = writeln!(page, "![{}]({picture})\n", picture.trim_end_matches(".png").replace('_', " "));
        }
    }
}

/// The near misses, when the scene asks for them, and the nearest's picture.
fn near_misses_table(page: &mut String, result: &RunResult, scene: &Scene, files: &[&str]) {
    let name = |i: usize| cell(&result.bodies[i]);
    if let Some(spec) = &scene.run().near_misses {
        let _ = writeln!(
            page,
            "## Near misses\n\nPairs that came within {} without touching: {}. Each pair is never closer than `lower` over the run (certified{}), and `distance` apart at `time`.\n",
            text::approx(spec.within, 3),
            result.near_misses.len(),
            // What the bracket does not cover (see `nearmiss::near_miss`).
            if result.contacts.is_empty() { "" } else { "; not over the rest of a step after either body's contact" }
        );
        if !result.near_misses.is_empty() {
            let _ = writeln!(page, "| bodies | distance | lower | time | features |\n|---|---|---|---|---|");
            for miss in result.near_misses.iter().take(LISTED_CONTACTS) {
                let _ = writeln!(
                    page,
                    "| {} / {} | {} | {} | {} | {} / {} |",
                    name(miss.body_a),
                    name(miss.body_b),
                    text::approx(miss.distance, 6),
                    text::approx(miss.lower, 6),
                    text::time(miss.time),
                    miss.closest.feature_a,
                    miss.closest.feature_b
                );
            }
            page.push('\n');
        }
        if files.contains(&NEAREST_NEAR_MISS_PICTURE) {
            let _ = writeln!(page, "![the nearest near miss]({NEAREST_NEAR_MISS_PICTURE})\n");
        }
    }
}

/// The run's files, each with what it holds.
fn files_list(page: &mut String, files: &[&str]) {
    let _ = writeln!(page, "## Files\n");
    for file in files.iter().filter(|f| **f != "report.md") {
        let what = match *file {
            "summary.json" => "every number of the run (contacts, work, wall times)",
            "trace.csv" => "distances over time (step, time, the two bodies, distance)",
            "animation.glb" => "the run as a glTF animation (Blender or any glTF viewer)",
            "poses.csv" => "every body's pose over time",
            "distance.png" => "the plot above",
            f if f.starts_with("contact_") => "the two bodies at that contact (pictured above)",
            NEAREST_NEAR_MISS_PICTURE => "the two bodies where they came nearest (pictured above)",
            _ => "",
        };
        let what = if what.is_empty() { String::new() } else { format!(": {what}") };
        let _ = writeln!(page, "- [{file}]({file}){what}");
    }
}

/// Text for a table cell: a `|` would end the cell.
fn cell(text: &str) -> String {
    text.replace('|', "\\|")
}

/// The features in contact, e.g. "triangle 12 vertex 0 / triangle 3 face".
fn features(contact: &Contact) -> String {
    format!(
        "triangle {} {} / triangle {} {}",
        contact.closest.triangle_a,
        contact.closest.feature_a,
        contact.closest.triangle_b,
        contact.closest.feature_b
    )
}

/// The contacts `plot: (contacts: [...])` asked pictures of that the run
/// did not have, as a sentence (`None` if every one was there).
pub fn missing_pictures(scene: &Scene, result: &RunResult) -> Option<String> {
    let missing: Vec<String> = scene
        .run()
        .plot
        .iter()
        .flat_map(|plot| plot.contacts.iter().filter(|&&n| n > result.contacts.len()).map(|n| n.to_string()))
        .collect();
    let asked = if missing.len() == 1 { "contact" } else { "contacts" };
    (!missing.is_empty()).then(|| {
        format!(
            "`plot.contacts` asked for pictures of {asked} {}, but the run had {}: no picture of {}",
            missing.join(", "),
            text::count(result.contacts.len() as u64, "contact"),
            if missing.len() == 1 { "it" } else { "those" }
        )
    })
}

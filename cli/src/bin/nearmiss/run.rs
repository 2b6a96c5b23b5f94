//! `nearmiss run`: scenes, their outputs and verdicts, optionally beside a
//! peer.

use crate::progress::run_with_progress;
use crate::{load_scene, CliError, CommandResult};
use nearmiss::run::{RunResult, Termination};
use nearmiss::scene::Scene;
use nearmiss_cli::text;
use std::path::PathBuf;

#[derive(clap::Args)]
pub struct Args {
    /// Scene files (RON), run one after another.
    #[arg(required = true, value_name = "SCENE")]
    scenes: Vec<PathBuf>,
    /// The output folder: each scene's files go to OUT/<scene name>/.
    #[arg(short, long, default_value = "output")]
    out: PathBuf,
    /// Also run the scene with a peer library and show both answers:
    /// `parry` (each first contact by parry's casts) or `rapier` (the scene
    /// in rapier alone with its CCD on: its first contacts, and whether it
    /// let pairs pass through or intersect).
    #[arg(long, value_enum)]
    compare: Option<Peer>,
    /// The most steps a run may take (a longer one is refused before it
    /// starts: usually a typo in `dt` or `duration`).
    #[arg(long, default_value_t = nearmiss::scene::DEFAULT_MAX_STEPS)]
    max_steps: u64,
}

#[derive(Copy, Clone, clap::ValueEnum)]
enum Peer {
    /// parry3d-f64: `cast_shapes_nonlinear` for rotating bodies, `cast_shapes` for translating ones.
    Parry,
    /// rapier3d-f64 alone, its CCD on for every moving body.
    #[cfg(feature = "rapier")]
    Rapier,
}

pub fn main(args: Args) -> CommandResult {
    // Every scene is loaded before any runs: a bad one runs nothing.
    let mut scenes: Vec<(PathBuf, Scene)> = Vec::with_capacity(args.scenes.len());
    for path in &args.scenes {
        let scene = load_scene(path, args.max_steps)?;
        if let Some((other, _)) = scenes.iter().find(|(_, s)| s.run().name == scene.run().name) {
            return Err(CliError::BadInput(format!(
                "{} and {} are both named `{}`: their outputs would overwrite each other in {}; rename one (its `name` field)",
                other.display(),
                path.display(),
                scene.run().name,
                args.out.join(&scene.run().name).display()
            )));
        }
        scenes.push((path.clone(), scene));
    }
    // Before the runs, not after them: a run is not wasted on an unusable folder.
    nearmiss_cli::output::check_writable(&args.out).map_err(|error| {
        CliError::BadInput(format!("--out {}: cannot write there: {error}", args.out.display()))
    })?;
    // The worst outcome decides the exit: undecided (3) over failed (1).
    let mut outcome: CommandResult = Ok(());
    for (k, (path, scene)) in scenes.iter().enumerate() {
        if k > 0 {
            println!();
        }
        match run_one(&args, path, scene) {
            Ok(()) => {}
            Err(CliError::Failed(message)) => {
                eprintln!("error: {message}");
                if outcome.is_ok() {
                    outcome = Err(CliError::Failed(String::new()));
                }
            }
            Err(CliError::Undecided(message)) => {
                eprintln!("error: {message}");
                outcome = Err(CliError::Undecided(String::new()));
            }
            Err(bad) => return Err(bad),
        }
    }
    outcome
}

/// Runs one scene, writes its outputs and prints what a user checks.
fn run_one(args: &Args, path: &std::path::Path, scene: &Scene) -> CommandResult {
    let result = run_with_progress(scene);
    let parry = match args.compare {
        Some(Peer::Parry) => nearmiss_cli::report::compare_with_parry(scene, &result),
        _ => Vec::new(),
    };
    // Without the `rapier` feature nothing below changes them.
    #[cfg_attr(not(feature = "rapier"), allow(unused_mut))]
    let mut peers = nearmiss_cli::output::Peers { parry: &parry, rapier: None };
    #[cfg_attr(not(feature = "rapier"), allow(unused_mut))]
    let mut table = (!parry.is_empty()).then(|| nearmiss_cli::report::peer_markdown(&parry));
    #[cfg(feature = "rapier")]
    if let Some(Peer::Rapier) = args.compare {
        let mut first = std::collections::BTreeMap::new();
        for c in &result.contacts {
            first.entry((c.body_a.min(c.body_b), c.body_a.max(c.body_b))).or_insert(c.time);
        }
        let rows = nearmiss::guard::compare_with_rapier(scene, &first, &result.final_states)
            .map_err(|error| CliError::Failed(format!("rapier could not run the scene: {error}")))?;
        table = Some(nearmiss::guard::rapier_markdown(&rows));
        peers.rapier = serde_json::to_value(&rows).ok();
    }
    let folder = args.out.join(&scene.run().name);
    if let Some(previous) = nearmiss_cli::output::previous_source(&folder, path) {
        eprintln!(
            "warning: {} held the outputs of {previous}, another scene of the same name: replaced",
            folder.display()
        );
    }
    let written = nearmiss_cli::output::write_outputs_with_peer(&args.out, &result, scene, &peers)
        .map_err(|error| CliError::BadInput(format!("cannot write to {}: {error}", folder.display())))?;
    print_result(scene, &result);
    if let Some(table) = table {
        print!("{table}");
    }
    let names: Vec<String> =
        written.iter().filter_map(|f| f.file_name()).map(|n| n.to_string_lossy().into_owned()).collect();
    println!("wrote {}/: {}", folder.display(), names.join(", "));
    if let Some(note) = nearmiss_cli::run_page::missing_pictures(scene, &result) {
        eprintln!("warning: {note}");
    }
    let verdict = nearmiss_cli::regression::verdict(scene, &result);
    if let Some(v) = &verdict {
        let error = v.error.map_or(String::new(), |e| format!(", error {}", text::signed(e, 3)));
        match v.passed {
            true => println!("expectation met: {}{error}", v.expected),
            false => println!("expectation NOT met: expected {}; obtained {}{error}", v.expected, v.obtained),
        }
        if let Some(hint) = &v.hint {
            println!("hint: {hint}");
        }
    }
    match result.termination {
        Termination::Diverged { .. } | Termination::Failed { .. } => {
            Err(CliError::Failed(result.termination_text()))
        }
        Termination::NotStarted { .. } => Err(CliError::BadInput(result.termination_text())),
        Termination::Undecided { .. } => Err(CliError::Undecided(result.termination_text())),
        _ if verdict.is_some_and(|v| !v.passed) => {
            Err(CliError::Failed(format!("{}: the run did not meet the scene's expectation", path.display())))
        }
        _ => Ok(()),
    }
}

/// Near misses listed on the terminal (all are in `summary.json`).
const NEAR_MISSES_SHOWN: usize = 5;

/// The run in two lines: how far it went, and its first contact.
fn print_result(scene: &Scene, result: &RunResult) {
    println!(
        "{}: {} of dt = {} to t = {} in {}",
        scene.run().name,
        text::count(result.steps, "step"),
        text::time(scene.model().dt),
        text::time(result.end_time),
        text::wall(result.wall_time_s)
    );
    match (&result.first_contact, &result.termination) {
        (Some(c), _) => println!(
            "first contact: {} / {} at t = {}, distance {} ({}); {} in all",
            result.bodies[c.body_a],
            result.bodies[c.body_b],
            text::time(c.time),
            text::approx(c.closest.distance, 3),
            c.status.name(),
            text::count(result.contacts.len() as u64, "contact")
        ),
        // Said by the error that follows: not "no contact".
        (
            None,
            Termination::Undecided { .. }
            | Termination::Diverged { .. }
            | Termination::NotStarted { .. }
            | Termination::Failed { .. },
        ) => {}
        (None, _) => println!("no contact up to t = {}", text::time(result.end_time)),
    }
    if let Some(spec) = &scene.run().near_misses {
        let list = &result.near_misses;
        println!(
            "near misses within {}: {}{}",
            text::approx(spec.within, 3),
            text::count(list.len() as u64, "pair"),
            if list.len() > NEAR_MISSES_SHOWN {
                format!(", the nearest {NEAR_MISSES_SHOWN}:")
            } else {
                String::new()
            }
        );
        for miss in list.iter().take(NEAR_MISSES_SHOWN) {
            println!(
                "  {} / {} at t = {}: distance {} (never closer than {}){}",
                result.bodies[miss.body_a],
                result.bodies[miss.body_b],
                text::time(miss.time),
                text::approx(miss.distance, 6),
                text::approx(miss.lower, 6),
                if miss.decided { "" } else { ", not decided to the tolerance" }
            );
        }
    }
    // Bodies overlapping at the start: each said with its depth; meshes
    // only touching: said, not only written as a status.
    let overlaps = &result.initial_overlaps;
    let bodies = &scene.model().bodies;
    for overlap in overlaps {
        eprintln!("{}", overlap_warning(overlap, bodies));
    }
    let overlapping =
        |a: usize, b: usize| overlaps.iter().any(|o| (o.body_a, o.body_b) == (a.min(b), a.max(b)));
    let at_start: Vec<String> = result
        .contacts
        .iter()
        .filter(|c| c.time == 0.0 && c.closest.distance == 0.0 && !overlapping(c.body_a, c.body_b))
        .map(|c| format!("{} / {}", result.bodies[c.body_a], result.bodies[c.body_b]))
        .collect();
    if !at_start.is_empty() {
        eprintln!(
            "warning: at t = 0 these meshes already touch (distance 0): {}. The run starts in contact; check the bodies' positions",
            at_start.join(", ")
        );
    }
}

/// The warning of two bodies overlapping at the start (`run` and `check`).
pub(crate) fn overlap_warning(
    overlap: &nearmiss::scene::InitialOverlap,
    bodies: &[nearmiss::scene::Body],
) -> String {
    format!(
        "warning: at t = 0 {}. The run starts overlapped; move them apart, or add `initial_overlap: Refuse` to refuse such scenes",
        overlap.describe(bodies)
    )
}

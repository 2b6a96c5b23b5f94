//! `nearmiss run`: one scene, its outputs, optionally beside parry.

use crate::progress::run_with_progress;
use crate::{load_scene, CliError, CommandResult};
use nearmiss::stepper::Termination;
use std::path::PathBuf;

#[derive(clap::Args)]
pub struct Args {
    /// The scene file (RON).
    scene: PathBuf,
    /// The output folder.
    #[arg(long, default_value = "output")]
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
    let scene = load_scene(&args.scene, args.max_steps)?;
    // Before the run, not after it: a run is not wasted on an unusable folder.
    nearmiss_cli::output::check_writable(&args.out).map_err(|error| {
        CliError::BadInput(format!("--out {}: cannot write there: {error}", args.out.display()))
    })?;
    let result = run_with_progress(&scene);
    let parry = match args.compare {
        Some(Peer::Parry) => nearmiss_cli::report::compare_with_parry(&scene, &result),
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
        let rows = nearmiss::guard::compare_with_rapier(&scene, &first, &result.final_states)
            .map_err(|error| CliError::Failed(format!("rapier could not run the scene: {error}")))?;
        table = Some(nearmiss::guard::rapier_markdown(&rows));
        peers.rapier = serde_json::to_value(&rows).ok();
    }
    let written = nearmiss_cli::output::write_outputs_with_peer(&args.out, &result, &scene, &peers).map_err(
        |error| {
            CliError::BadInput(format!(
                "cannot write to {}: {error}",
                args.out.join(&scene.run().name).display()
            ))
        },
    )?;
    println!(
        "scene {}: {} steps of dt = {:?} to t = {:.9}, {:.3} s",
        scene.run().name,
        result.steps,
        scene.model().dt,
        result.end_time,
        result.wall_time_s
    );
    match &result.first_contact {
        Some(c) => println!(
            "first contact: {} / {} at t = {:.15e}, distance {:.3e} ({}); {} contact(s)",
            result.bodies[c.body_a],
            result.bodies[c.body_b],
            c.time,
            c.closest.distance,
            c.status.name(),
            result.contacts.len()
        ),
        None => println!("no contact"),
    }
    if let Some(table) = table {
        print!("{table}");
    }
    for file in &written {
        println!("wrote {}", file.display());
    }
    match result.termination {
        Termination::Diverged { .. } => Err(CliError::Failed(result.termination_text())),
        Termination::Undecided { .. } => Err(CliError::Undecided(result.termination_text())),
        _ => Ok(()),
    }
}

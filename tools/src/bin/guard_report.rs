//! The guard beside rapier alone on the worlds of `tests/support/guard_worlds.rs`
//! (issue 43): for the worlds rapier holds, the largest difference of the
//! guarded run's poses from rapier alone's and how deep rapier let them
//! overlap; for the worlds where rapier fails, the deepest overlap and the
//! far-side margin of each run. Prints a Markdown table for `BENCHMARKS.md`.
//!
//! Usage: `cargo run --release -p nearmiss-tools --bin guard_report [-- --skin S]`.

#[path = "../../../tests/support/guard_worlds.rs"]
#[allow(dead_code)]
mod guard_worlds;
#[path = "../../../tests/support/rapier_app.rs"]
mod rapier_app;

use guard_worlds::{rapier_fails, rapier_holds, GuardWorld, WorldRun};
use nearmiss::guard::{GuardEvent, GuardOptions};

fn main() {
    let mut options = GuardOptions::default();
    let args: Vec<String> = std::env::args().skip(1).collect();
    if let Some(k) = args.iter().position(|a| a == "--skin") {
        options.skin = args.get(k + 1).and_then(|s| s.parse().ok()).expect("--skin S");
    }
    println!("## rapier holds: the guard must only read (skin {})\n", options.skin);
    println!("| world | steps | rapier alone: deepest overlap | guarded: largest difference from rapier alone | guarded: deepest overlap | rewinds | overlaps pushed | frozen body |");
    println!("|---|---|---|---|---|---|---|---|");
    for twin in twins(rapier_holds(), rapier_holds(), options) {
        let Twin { world, alone, guarded, pushed, frozen } = twin;
        println!(
            "| {} | {} | {:.2e} | {:.2e} | {:.2e} | {} | {pushed} | {frozen} |",
            world.name,
            world.steps,
            alone.deepest().0,
            alone.largest_difference(&guarded, world.size),
            guarded.deepest().0,
            guarded.rewinds,
        );
    }
    skins();
    println!("\n## rapier fails: the guard must decide (skin {})\n", options.skin);
    println!("| world | rapier alone: deepest overlap | far-side margin | guarded: deepest overlap | far-side margin | rewinds | overlaps pushed | frozen body |");
    println!("|---|---|---|---|---|---|---|---|");
    for twin in twins(rapier_fails(), rapier_fails(), options) {
        let Twin { world, alone, guarded, pushed, frozen } = twin;
        println!(
            "| {} | {:.2e} | {} | {:.2e} | {} | {} | {pushed} | {frozen} |",
            world.name,
            alone.deepest().0,
            margin(alone.far_margin()),
            guarded.deepest().0,
            margin(guarded.far_margin()),
            guarded.rewinds,
        );
    }
}

/// A world run twice, rapier alone and guarded: what the tables read.
struct Twin {
    /// The world as built (name, steps, size).
    world: Summary,
    alone: WorldRun,
    guarded: WorldRun,
    /// The guard's pushes (`GuardEvent::Overlap`).
    pushed: usize,
    /// The first frozen body, in words (`none`).
    frozen: String,
}

/// What of a world the tables name.
struct Summary {
    name: String,
    steps: usize,
    size: f64,
}

/// Each world of `alone` (rapier alone) beside its twin of `guarded`
/// (guarded under `options`).
fn twins(alone: Vec<GuardWorld>, guarded: Vec<GuardWorld>, options: GuardOptions) -> Vec<Twin> {
    alone
        .into_iter()
        .zip(guarded)
        .map(|(alone_world, guarded_world)| {
            let world =
                Summary { name: alone_world.name.clone(), steps: alone_world.steps, size: alone_world.size };
            let dynamic = dynamic_bodies(&alone_world);
            let alone = alone_world.run_alone();
            let guarded = guarded_world.run_guarded(options).expect("the guard decides");
            let pushed = guarded.events.iter().filter(|e| matches!(e, GuardEvent::Overlap { .. })).count();
            let frozen = guarded
                .frozen(&dynamic, 1e-9)
                .map_or("none".to_string(), |(s, i)| format!("body {i} at step {s}"));
            Twin { world, alone, guarded, pushed, frozen }
        })
        .collect()
}

/// What a skin costs to look at: a box resting on a floor and the top of a
/// stack of five, how far above (+) or into (−) where face to face puts
/// them they end, without a skin and with one of rapier's allowed error.
fn skins() {
    println!("\n## skins: where resting bodies end (after the worlds' runs)\n");
    println!("| world | rapier alone | guarded, no skin | guarded, skin 1.0 (0.005 a collider) |");
    println!("|---|---|---|---|");
    type Make = fn() -> GuardWorld;
    let worlds: [(&str, Make, usize, f64); 2] = [
        (
            "box resting on a floor: its centre above 0.1",
            || guard_worlds::box_on_floor("box", [0.0; 3], 0.0, Default::default()),
            1,
            0.1,
        ),
        (
            "stack of five unit cubes: the top one's centre above 4.5",
            || guard_worlds::stack(5, [0.0; 3]),
            5,
            4.5,
        ),
    ];
    for (name, make, body, nominal) in worlds {
        let height = |run: guard_worlds::WorldRun| run.last_pose(body).translation.vector.z - nominal;
        let alone = height(make().run_alone());
        let plain = height(make().run_guarded(GuardOptions::default()).expect("decides"));
        let skin = GuardOptions { skin: 1.0, ..GuardOptions::default() };
        let skinned = height(make().run_guarded(skin).expect("decides"));
        println!("| {name} | {alone:+.2e} | {plain:+.2e} | {skinned:+.2e} |");
    }
}

/// Whether each body of `world` is dynamic.
fn dynamic_bodies(world: &GuardWorld) -> Vec<bool> {
    world.handles.iter().map(|(_, h)| world.bodies[*h].is_dynamic()).collect()
}

/// A far-side margin in words.
fn margin(m: f64) -> String {
    if m.is_infinite() {
        "—".into()
    } else {
        format!("{m:.2e}")
    }
}

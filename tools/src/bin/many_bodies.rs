//! Time per step of N tumbling bodies (icospheres of 20 to 1,280 triangles
//! and boxes, random spins up to 8 rad/s, random velocities up to 2) in a
//! closed box of six fixed walls, bouncing elastically off the walls and
//! each other (`on_contact: Bounce(restitution: 1.0)`), dt = 1/240. The
//! bodies start on a jittered grid (one per cell of side 1.2, so none
//! overlap) and the box grows with N^(1/3), so the density stays the same.
//! Prints the time per step and per stage, and checks that no pair of
//! bodies ends a run touching.
//! With `--simulate`: the same bodies under `on_contact: Simulate(restitution:
//! 1.0, friction: 0.0)` (rapier3d solves, nearmiss guards), beside rapier
//! alone on the same scene in the same run (its CCD on; convex hulls, then
//! every body a triangle mesh), with the guard's share of each step.
//! With `--trace N`: every pair traced every N steps (the trace column).
//! With `--near-misses D [--near-miss-tolerance T]`: every pair's near
//! misses within `D`, each bracketed to the width `T` (default 1e-6 of the
//! pair's smaller radius); the near misses column is their time, the last
//! how many pairs were listed.
//! With `--simulate --no-peers`: Simulate only (for profiling the guard).
//! With `--rapier` (Bounce): rapier alone on the same bodies in the same
//! run (restitution 1, no friction, its CCD on, convex hulls), its steps
//! per second and nearmiss's rate over it; built with the tools'
//! `rapier-parallel` feature, rapier on its own threads.
//! With `--fixed P`: P% of the bodies (spread through the box; with
//! `--fixed-first`, the first P% of them, a block of the box) are fixed
//! where they start, the others move as without it (a clutter of fixed
//! obstacles); with `--at-rest`, those bodies are kinematic with no
//! velocity instead (obstacles at rest, not declared fixed).
//! With `--final-states PREFIX`: every body's final state and every
//! contact written to `PREFIX<N>.txt` (to compare two builds).
//! With `--speed K`: velocities up to `2 K` instead of 2 (fast bodies).
//! With `--bunnies`: every fifth body (those that were icospheres of 320
//! triangles) is the Stanford bunny (3,674 triangles, scaled to radius
//! 0.29; `scripts/fetch-bunny.sh` fetches it).
//! Usage: `cargo run --release -p nearmiss-tools --bin many_bodies -- 10 100 1000 [--steps 240] [--simulate] [--trace N] [--bunnies]`.
use nearmiss::run::{run_with, RunOptions};
use nearmiss::samples::Rng;
use nearmiss::scene::Scene;

/// The scene's options beside its body count.
#[derive(Copy, Clone)]
struct Setup {
    steps: usize,
    simulate: bool,
    trace: Option<u64>,
    bunnies: bool,
    /// `--near-misses D`: every pair's near misses within `D`.
    near_misses: Option<f64>,
    /// `--near-miss-tolerance T`: their brackets' width.
    near_miss_tolerance: Option<f64>,
    /// `--fixed P`: this percentage of the bodies fixed where they start,
    /// spread through the box; with `--fixed-first`, the first bodies.
    fixed_percent: usize,
    fixed_first: bool,
    /// `--at-rest`: those bodies kinematic and still, not fixed.
    at_rest: bool,
    /// `--speed K`: velocities up to `2 K` instead of 2.
    speed: f64,
}

/// The bunny's OBJ file (see `scripts/fetch-bunny.sh`).
const BUNNY: &str = concat!(env!("CARGO_MANIFEST_DIR"), "/../scenes/meshes/bunny.obj");

fn box_scene(bodies: usize, seed: u64, setup: Setup) -> Scene {
    let Setup {
        steps,
        simulate,
        trace,
        bunnies,
        near_misses,
        near_miss_tolerance,
        fixed_percent,
        fixed_first,
        at_rest,
        speed,
    } = setup;
    let mut rng = Rng::new(seed);
    let per_side = (bodies as f64).cbrt().ceil() as usize;
    let cell = 1.2;
    let half = cell * per_side as f64 / 2.0;
    let response =
        if simulate { "Simulate(restitution: 1.0, friction: 0.0)" } else { "Bounce(restitution: 1.0)" };
    let trace = trace.map_or(String::new(), |every| format!("trace: (pairs: All, every: {every}), "))
        + &near_misses.map_or(String::new(), |within| {
            let tolerance = near_miss_tolerance.map_or(String::new(), |t| format!(", tolerance: {t:?}"));
            format!("near_misses: (within: {within:?}{tolerance}), ")
        });
    let mut text = format!(
        "Scene(name: \"box_{bodies}\", dt: 0.004166666666666667, steps: {steps}, on_contact: {response}, {trace}bodies: ["
    );
    // The walls: slabs 0.5 thick just outside the cells.
    let (t, l) = (0.25, half + 0.5);
    for (k, (position, extents)) in [
        ((half + t, 0.0, 0.0), (t, l, l)),
        ((-half - t, 0.0, 0.0), (t, l, l)),
        ((0.0, half + t, 0.0), (l, t, l)),
        ((0.0, -half - t, 0.0), (l, t, l)),
        ((0.0, 0.0, half + t), (l, l, t)),
        ((0.0, 0.0, -half - t), (l, l, t)),
    ]
    .iter()
    .enumerate()
    {
        text.push_str(&format!(
            "(name: \"wall{k}\", mesh: Box(half_extents: ({:?}, {:?}, {:?})), position: ({:?}, {:?}, {:?}), fixed: true),",
            extents.0, extents.1, extents.2, position.0, position.1, position.2
        ));
    }
    for k in 0..bodies {
        let (i, j, m) = (k % per_side, (k / per_side) % per_side, k / (per_side * per_side));
        let centre = |n: usize| -half + cell * (n as f64 + 0.5);
        let jitter = rng.in_unit_ball() * 0.2;
        let position = (centre(i) + jitter.x, centre(j) + jitter.y, centre(m) + jitter.z);
        let v = |rng: &mut Rng, s: f64| {
            let x = rng.in_unit_ball() * s;
            format!("({:?}, {:?}, {:?})", x.x, x.y, x.z)
        };
        let mesh = match k % 5 {
            0 => "mesh: Box(half_extents: (0.3, 0.2, 0.25)), density: 1.0".to_string(),
            // The bunny is open at its base: a mass and inertia, not a density.
            3 if bunnies => {
                format!(
                    "mesh: Obj(path: {BUNNY:?}), scale: 0.028, mass: 0.02, inertia: (0.0005, 0.0005, 0.0005)"
                )
            }
            n => format!("mesh: Icosphere(radius: 0.3, subdivisions: {}), density: 1.0", n - 1),
        };
        let (velocity, spin) = (v(&mut rng, 2.0 * speed), v(&mut rng, 8.0));
        // `--fixed P`: P in every 100 bodies, spread through the box, or the
        // first P% (the others move as without it).
        let fixed = if fixed_first { k * 100 < fixed_percent * bodies } else { k * 37 % 100 < fixed_percent };
        let motion = if fixed {
            if at_rest { "kinematic: true" } else { "fixed: true" }.to_string()
        } else {
            format!("velocity: {velocity}, angular_velocity: {spin}")
        };
        text.push_str(&format!(
            "(name: \"b{k}\", {mesh}, position: ({:?}, {:?}, {:?}), {motion}),",
            position.0, position.1, position.2
        ));
    }
    text.push_str("])");
    Scene::from_ron_str(&text).expect("a valid scene")
}

/// The value after `flag` in `args`, parsed (`what` it should be, in the
/// panic of a value that does not parse).
fn value_of<T: std::str::FromStr>(args: &[String], flag: &str, what: &str) -> Option<T>
where
    T::Err: std::fmt::Debug,
{
    let value = args.iter().position(|a| a == flag).and_then(|k| args.get(k + 1))?;
    Some(value.parse().expect(what))
}

fn main() {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let flag = |name: &str| args.iter().any(|a| a == name);
    let setup = Setup {
        steps: value_of(&args, "--steps", "a step count").unwrap_or(240),
        simulate: flag("--simulate"),
        trace: value_of(&args, "--trace", "a trace cadence"),
        bunnies: flag("--bunnies"),
        near_misses: value_of(&args, "--near-misses", "a near-miss distance"),
        near_miss_tolerance: value_of(&args, "--near-miss-tolerance", "a near-miss tolerance"),
        fixed_percent: value_of(&args, "--fixed", "a percentage of fixed bodies").unwrap_or(0),
        speed: value_of(&args, "--speed", "a speed factor").unwrap_or(1.0),
        fixed_first: flag("--fixed-first"),
        at_rest: flag("--at-rest"),
    };
    if setup.bunnies && !std::path::Path::new(BUNNY).exists() {
        eprintln!("--bunnies needs {BUNNY}: run scripts/fetch-bunny.sh");
        std::process::exit(2);
    }
    if setup.simulate {
        return simulate_beside_rapier(&args, setup);
    }
    let counts = body_counts(&args);
    println!("| bodies | steps | ms per step | steps per s | set-up s | integrate ms | broad phase ms | CCD ms | respond ms | re-arm ms | trace ms | near misses ms | candidate pairs/step | contacts | near misses |");
    println!("|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|");
    for n in counts {
        let scene = box_scene(n, 1, setup);
        // The run's own peak: the scene's text and parse are behind it.
        reset_peak_rss();
        let resident_before = resident_bytes("VmRSS:");
        // The steps are timed from the end of the first to the end of the
        // last: the run's set-up (the initial overlaps, the first tree) is
        // its own column.
        let start = std::time::Instant::now();
        let (mut first, mut last) = (None, start);
        let result = run_with(&scene, RunOptions::default(), &mut |_| {
            last = std::time::Instant::now();
            first.get_or_insert(last);
        });
        let steps = result.steps as f64;
        let c = &result.counters;
        let per_step = |seconds: f64| seconds * 1e3 / steps;
        let first = first.unwrap_or(start);
        let stepping = if result.steps > 1 {
            (last - first).as_secs_f64() / (steps - 1.0)
        } else {
            result.wall_time_s / steps
        };
        let set_up = ((first - start).as_secs_f64() - stepping).max(0.0);
        println!(
            "| {n} | {steps} | {:.3} | {:.0} | {set_up:.3} | {:.3} | {:.3} | {:.3} | {:.3} | {:.3} | {:.3} | {:.3} | {:.0} | {} | {} |",
            stepping * 1e3,
            1.0 / stepping,
            per_step(c.seconds.integrate),
            per_step(c.seconds.broad_phase),
            per_step(c.seconds.ccd),
            per_step(c.seconds.respond),
            per_step(c.seconds.rearm),
            per_step(c.seconds.trace),
            per_step(c.seconds.near_misses),
            c.work.candidate_pairs as f64 / steps,
            result.contacts.len(),
            result.near_misses.len()
        );
        if result.steps < setup.steps as u64 {
            eprintln!("{n} bodies: the run ended after {} steps: {:?}", result.steps, result.termination);
        }
        if args.iter().any(|a| a == "--rapier") {
            // The same bodies as rapier sees them under Simulate.
            let same = box_scene(n, 1, Setup { simulate: true, trace: None, near_misses: None, ..setup });
            let convex = nearmiss::guard::run_rapier_alone(&same, false).expect("rapier runs");
            let rate = convex.steps as f64 / convex.wall_time_s;
            let ours = steps / result.wall_time_s;
            let threads = if cfg!(feature = "rapier-parallel") { "on" } else { "off" };
            println!("rapier alone (convex, CCD on, its `parallel` feature {threads}) on the same bodies: {rate:.0} steps/s; nearmiss Bounce / rapier = {:.2}", ours / rate);
        }
        // The mesh assets (shared between bodies) with their BVHs and
        // tables, in bytes.
        let mut assets: Vec<*const nearmiss::mesh::TriMesh> =
            scene.model().bodies.iter().map(|b| std::sync::Arc::as_ptr(&b.mesh)).collect();
        assets.sort();
        assets.dedup();
        let mesh_bytes: usize = scene
            .model()
            .bodies
            .iter()
            .filter(|b| {
                let p = std::sync::Arc::as_ptr(&b.mesh);
                assets.iter().position(|&q| q == p).map(|k| assets[k] = std::ptr::null()).is_some()
            })
            .map(|b| b.mesh.heap_bytes())
            .sum();
        eprintln!("{n} bodies: mesh assets (vertices, triangles, BVHs, tables) {mesh_bytes} bytes");
        eprintln!("{n} bodies: digest of the final states and contacts {:016x}", digest(&result));
        if let Some(prefix) = value_of::<String>(&args, "--final-states", "a path prefix") {
            let path = format!("{prefix}{n}.txt");
            std::fs::write(&path, final_states(&result)).expect("a writable --final-states path");
            eprintln!("{n} bodies: final states and contacts written to {path}");
        }
        if let (Some(before), Some(peak)) = (resident_before, resident_bytes("VmHWM:")) {
            eprintln!(
                "{n} bodies: resident memory {:.1} MB with the scene loaded, {:.1} MB at the run's peak: {:.0} bytes a body beyond the mesh assets",
                before as f64 / 1e6,
                peak as f64 / 1e6,
                (peak as f64 - mesh_bytes as f64) / n as f64
            );
        }
    }
}

/// Resets the process's peak resident memory to its current one (Linux:
/// `5` into `/proc/self/clear_refs`).
fn reset_peak_rss() {
    let _ = std::fs::write("/proc/self/clear_refs", "5");
}

/// Every body's final state (position, velocity, angular velocity,
/// orientation's coordinates) and every contact (time, bodies), one a line,
/// to compare two builds whose digests differ.
fn final_states(result: &nearmiss::run::RunResult) -> String {
    let mut text = String::new();
    for state in &result.final_states {
        let q = state.orientation.coords;
        let numbers = state
            .position
            .iter()
            .chain(state.velocity.iter())
            .chain(state.angular_velocity.iter())
            .chain(q.iter());
        text += &numbers.map(|x| format!("{x:?}")).collect::<Vec<_>>().join(" ");
        text.push('\n');
    }
    for contact in &result.contacts {
        text += &format!("contact {:?} {} {}\n", contact.time, contact.body_a, contact.body_b);
    }
    text
}

/// A hash (FNV-1a) of the bits of every body's final state and of every
/// contact's time and bodies: two builds that agree on it ran the same.
fn digest(result: &nearmiss::run::RunResult) -> u64 {
    let mut hash: u64 = 0xcbf2_9ce4_8422_2325;
    let mut eat = |word: u64| {
        for byte in word.to_le_bytes() {
            hash = (hash ^ u64::from(byte)).wrapping_mul(0x0100_0000_01b3);
        }
    };
    for state in &result.final_states {
        let q = state.orientation.coords;
        for x in state
            .position
            .iter()
            .chain(state.velocity.iter())
            .chain(state.angular_velocity.iter())
            .chain(q.iter())
        {
            eat(x.to_bits());
        }
    }
    for contact in &result.contacts {
        eat(contact.time.to_bits());
        eat(contact.body_a as u64);
        eat(contact.body_b as u64);
    }
    hash
}

/// The process's resident memory (`VmRSS:`) or its peak (`VmHWM:`) since
/// the last reset, from `/proc/self/status` (Linux).
fn resident_bytes(field: &str) -> Option<u64> {
    let status = std::fs::read_to_string("/proc/self/status").ok()?;
    let line = status.lines().find(|l| l.starts_with(field))?;
    let kb: u64 = line.split_whitespace().nth(1)?.parse().ok()?;
    Some(kb * 1024)
}

/// `--simulate`: nearmiss's Simulate (rapier + guard) beside rapier alone.
fn simulate_beside_rapier(args: &[String], setup: Setup) {
    let counts = body_counts(args);
    println!("| bodies | steps | Simulate steps/s | guard share of a step | guard ms/step | rapier in Simulate ms/step | rapier alone (convex, CCD) steps/s | ratio | rapier alone (triangle meshes, CCD) steps/s | ratio | contacts |");
    println!("|---|---|---|---|---|---|---|---|---|---|---|");
    for n in counts {
        let scene = box_scene(n, 1, setup);
        let result = run_with(&scene, RunOptions::default(), &mut |_| {});
        let c = &result.counters;
        // The guard's whole cost: its sweeps and its work on rapier's bodies.
        let guard = c.seconds.sweep() + c.seconds.engine_sync;
        let steps = result.steps as f64;
        let ours = steps / result.wall_time_s;
        if args.iter().any(|a| a == "--no-peers") {
            println!(
                "| {n} | {steps} | {ours:.0} | {:.1}% | {:.3} | {:.3} | | | | | {} |",
                100.0 * guard / result.wall_time_s,
                guard * 1e3 / steps,
                c.seconds.engine * 1e3 / steps,
                result.contacts.len()
            );
            eprintln!(
                "guard ms/step: broad phase {:.3}, CCD {:.3}, respond {:.3}, re-arm {:.3}, bodies {:.3}",
                c.seconds.broad_phase * 1e3 / steps,
                c.seconds.ccd * 1e3 / steps,
                c.seconds.respond * 1e3 / steps,
                c.seconds.rearm * 1e3 / steps,
                c.seconds.engine_sync * 1e3 / steps
            );
            continue;
        }
        let convex = nearmiss::guard::run_rapier_alone(&scene, false).expect("rapier runs");
        let meshes = nearmiss::guard::run_rapier_alone(&scene, true).expect("rapier runs");
        let rate = |r: &nearmiss::guard::RapierAlone| r.steps as f64 / r.wall_time_s;
        println!(
            "| {n} | {steps} | {ours:.0} | {:.1}% | {:.3} | {:.3} | {:.0} | {:.2} | {:.0} | {:.2} | {} |",
            100.0 * guard / result.wall_time_s,
            guard * 1e3 / steps,
            c.seconds.engine * 1e3 / steps,
            rate(&convex),
            ours / rate(&convex),
            rate(&meshes),
            ours / rate(&meshes),
            result.contacts.len()
        );
    }
}

/// The flags followed by a value (a number among them is not a body count).
const VALUE_FLAGS: [&str; 7] =
    ["--steps", "--trace", "--near-misses", "--near-miss-tolerance", "--fixed", "--final-states", "--speed"];

/// The body counts among the arguments (the numbers that are not a flag's
/// value).
fn body_counts(args: &[String]) -> Vec<usize> {
    args.iter()
        .enumerate()
        .filter(|&(k, _)| k == 0 || !VALUE_FLAGS.contains(&args[k - 1].as_str()))
        .filter_map(|(_, a)| a.parse().ok())
        .collect()
}

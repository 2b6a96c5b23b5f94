//! Runs each scene file many times in one process (warm caches, no output
//! written) and prints the median and least run time of each, as
//! `wall_time_s` measures a run: for comparing two scenes' costs (say with
//! and without `near_misses`) more steadily than one command each.
//! Usage: `cargo run --release -p nearmiss-tools --bin scene_repeat --
//! benches/scenes/bunny_tumble_plain.ron benches/scenes/bunny_tumble_nm.ron
//! [--repeats 300]`; the scenes are run in turn, round after round.
use nearmiss::run::{run_with, RunOptions};
use nearmiss::scene::Scene;

fn main() {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let repeats = args
        .iter()
        .position(|a| a == "--repeats")
        .and_then(|k| args.get(k + 1))
        .and_then(|r| r.parse().ok())
        .unwrap_or(300usize);
    let paths: Vec<&String> = args
        .iter()
        .enumerate()
        .filter(|&(k, a)| !a.starts_with("--") && (k == 0 || args[k - 1] != "--repeats"))
        .map(|(_, a)| a)
        .collect();
    if paths.is_empty() || repeats == 0 {
        eprintln!("usage: scene_repeat SCENE.ron... [--repeats N] (N at least 1)");
        std::process::exit(2);
    }
    let mut scenes = Vec::with_capacity(paths.len());
    for path in &paths {
        match Scene::load(std::path::Path::new(path)) {
            Ok(scene) => scenes.push(scene),
            Err(error) => {
                eprintln!("{error}");
                std::process::exit(2);
            }
        }
    }
    let mut times = vec![Vec::with_capacity(repeats); scenes.len()];
    for _ in 0..repeats {
        for (scene, times) in scenes.iter().zip(&mut times) {
            times.push(run_with(scene, RunOptions::default(), &mut |_| {}).wall_time_s);
        }
    }
    println!("| scene | runs | median ms | least ms |");
    println!("|---|---|---|---|");
    for (path, times) in paths.iter().zip(&mut times) {
        times.sort_by(f64::total_cmp);
        println!("| {path} | {repeats} | {:.3} | {:.3} |", times[times.len() / 2] * 1e3, times[0] * 1e3);
    }
}

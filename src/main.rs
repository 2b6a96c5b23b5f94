//! The `nearmiss` command line: parses arguments, calls the library, prints.

use clap::{Parser, Subcommand, ValueEnum};
use nearmiss::ccd::CcdOptions;
use nearmiss::math::Real;
use nearmiss::query_file::{query_files, run_file, QueryFile, QueryKind};
use nearmiss::scene::Scene;
use nearmiss::stepper::{RunResult, Termination};
use std::path::{Path, PathBuf};
use std::process::ExitCode;
use std::time::{Duration, Instant};

#[derive(Parser)]
#[command(name = "nearmiss", version, about = "Continuous collision detection for triangle meshes")]
struct Cli {
    #[command(subcommand)]
    command: Command,
}

#[derive(Subcommand)]
enum Command {
    /// Print each distance kernel's error against the exact rational
    /// reference, per input class, beside its rough time per query.
    Kernels {
        /// Inputs per class.
        #[arg(long, default_value_t = 500)]
        count: usize,
        /// Seed of the input generators.
        #[arg(long, default_value_t = 1)]
        seed: u64,
        /// Output folder: the chart goes to `<out>/kernels/error_vs_time.png`.
        #[arg(long, default_value = "output")]
        out: PathBuf,
    },
    /// Run CCD benchmark query files (files or folders): per file the
    /// queries, positives, false negatives, false positives, time per query,
    /// and, where exact times are known, whether any reported time was late.
    /// Exits 1 if any query was a false negative or late.
    Queries {
        /// Query files or folders (searched for `.csv`, `derived/` skipped).
        #[arg(required = true)]
        paths: Vec<PathBuf>,
        /// Treat every file as this kind instead of reading it from the path.
        #[arg(long, value_enum)]
        kind: Option<Kind>,
        /// Timed runs per file; the median is reported.
        #[arg(long, default_value_t = 3)]
        repeats: usize,
        /// Distance tolerance, relative to each query's size.
        #[arg(long, default_value_t = CcdOptions::default().distance_tolerance)]
        tolerance: f64,
        /// Most advancement steps per query.
        #[arg(long, default_value_t = CcdOptions::default().max_iterations)]
        max_iterations: usize,
    },
    /// Run a scene: writes `<out>/<scene name>/summary.json`, and
    /// `trace.csv` when the scene asks for a trace. Exits 2 on a bad scene,
    /// 1 if the integration diverged.
    Run {
        /// The scene file (RON).
        scene: PathBuf,
        /// The output folder.
        #[arg(long, default_value = "output")]
        out: PathBuf,
        /// Also compute each first contact with a peer library and show
        /// both answers (`parry`).
        #[arg(long, value_enum)]
        compare: Option<Peer>,
    },
    /// Run a scene over time steps, kernels and integrators: per setting the
    /// time of first contact, its error against the reference (analytic, or
    /// the finest exact run), the kernel's error against the exact distance
    /// along the trace, and the wall time. Writes `<out>/<scene>/sweep.csv`
    /// and `error_vs_runtime.png`.
    Sweep {
        /// The scene file.
        scene: PathBuf,
        /// Time steps, comma-separated.
        #[arg(long, value_delimiter = ',', required = true)]
        dt: Vec<f64>,
        /// Kernels, comma-separated: exact, dyop-vector, dyop-plain-vector,
        /// dyop-heron, dyop-stable-heron.
        #[arg(long, value_delimiter = ',', required = true)]
        kernel: Vec<String>,
        /// Integrators, comma-separated: symplectic-euler, explicit-euler,
        /// rk4 (default: the scene's).
        #[arg(long, value_delimiter = ',')]
        integrator: Vec<String>,
        /// The output folder.
        #[arg(long, default_value = "output")]
        out: PathBuf,
    },
    /// The seed paper's experiments: six calibration placements, ten
    /// rotated ones, 90 type-against-type tests timed per formula, and the
    /// verdict on its claim that Heron is about 5% faster. Prints Markdown
    /// and writes `<out>/paper/paper.md`.
    Paper {
        /// Repeats of the 90 timed tests.
        #[arg(long, default_value_t = 2000)]
        repeats: usize,
        /// Seed of the rotated placements.
        #[arg(long, default_value_t = 1)]
        seed: u64,
        /// The output folder.
        #[arg(long, default_value = "output")]
        out: PathBuf,
    },
    /// The stability suite: the stiff spring at ω·dt from 0.1 to 3 per
    /// integrator, the Dzhanibekov spin over 100,000 steps, and every scene
    /// of the folder against its expectation. Writes
    /// `<out>/stability/stability.md` and PNG charts.
    Stability {
        /// The folder of the suite's scenes.
        #[arg(long, default_value = "scenes/stability")]
        scenes: PathBuf,
        /// The output folder.
        #[arg(long, default_value = "output")]
        out: PathBuf,
    },
    /// Validate a scene without running it. Exits 2 on a bad scene.
    Check {
        /// Scene files.
        #[arg(required = true)]
        scenes: Vec<PathBuf>,
    },
    /// Run every scene (files, or folders searched for `.ron`) that states
    /// an expectation; one line per scene. Exits 1 if any fails, 2 if a
    /// scene is bad.
    Test {
        /// Scene files or folders.
        #[arg(required = true)]
        paths: Vec<PathBuf>,
    },
}

#[derive(Copy, Clone, ValueEnum)]
enum Peer {
    /// parry3d-f64: `cast_shapes_nonlinear` for rotating bodies, `cast_shapes` for translating ones.
    Parry,
}

#[derive(Copy, Clone, ValueEnum)]
enum Kind {
    /// Edge–edge.
    Ee,
    /// Vertex–face.
    Vf,
}

fn main() -> ExitCode {
    let cli = match Cli::try_parse() {
        Ok(cli) => cli,
        Err(e) => {
            let code = if e.use_stderr() { 2 } else { 0 };
            let _ = e.print();
            return ExitCode::from(code);
        }
    };
    match cli.command {
        Command::Kernels { count, seed, out } => {
            let rows = nearmiss::report::kernel_report(count, seed);
            print!("{}", nearmiss::report::kernel_report_markdown(&rows));
            #[cfg(feature = "plot")]
            {
                let folder = out.join("kernels");
                for (point_segment, name) in
                    [(false, "triangle_error_vs_time.png"), (true, "point_segment_error_vs_time.png")]
                {
                    let path = folder.join(name);
                    let chart = nearmiss::report::kernel_chart(&rows, point_segment);
                    let written = std::fs::create_dir_all(&folder)
                        .map_err(|e| e.to_string())
                        .and_then(|_| nearmiss::plot::render(&chart, &path).map_err(|e| e.to_string()));
                    match written {
                        Ok(()) => eprintln!("wrote {}", path.display()),
                        Err(error) => {
                            eprintln!("error: {error}");
                            return ExitCode::from(2);
                        }
                    }
                }
            }
            #[cfg(not(feature = "plot"))]
            let _ = out;
        }
        Command::Run { scene, out, compare } => return run_scene(&scene, &out, compare.is_some()),
        Command::Check { scenes } => return check_scenes(&scenes),
        Command::Stability { scenes, out } => return stability(&scenes, &out),
        Command::Paper { repeats, seed, out } => {
            use nearmiss::report::{
                calibration_placements, paper_report_markdown, paper_rows, paper_timing, rotated_placements,
            };
            let text = paper_report_markdown(
                &paper_rows(&calibration_placements()),
                &paper_rows(&rotated_placements(seed)),
                &paper_timing(repeats.max(1)),
            );
            print!("{text}");
            let folder = out.join("paper");
            let written = std::fs::create_dir_all(&folder)
                .and_then(|_| nearmiss::output::write_atomically(&folder.join("paper.md"), text.as_bytes()));
            if let Err(error) = written {
                eprintln!("error: cannot write to {}: {error}", folder.display());
                return ExitCode::from(2);
            }
        }
        Command::Sweep { scene, dt, kernel, integrator, out } => {
            return sweep_scene(&scene, &dt, &kernel, &integrator, &out)
        }
        Command::Test { paths } => return test_scenes(&paths),
        Command::Queries { paths, kind, repeats, tolerance, max_iterations } => {
            let kind = kind.map(|k| match k {
                Kind::Ee => QueryKind::EdgeEdge,
                Kind::Vf => QueryKind::VertexFace,
            });
            let options =
                CcdOptions { distance_tolerance: tolerance, max_iterations, ..CcdOptions::default() };
            return run_queries(&paths, kind, &options, repeats);
        }
    }
    ExitCode::SUCCESS
}

/// Loads every file first (bad input: exit 2, nothing run), then runs them.
fn run_queries(paths: &[PathBuf], kind: Option<QueryKind>, options: &CcdOptions, repeats: usize) -> ExitCode {
    let mut files = Vec::new();
    for path in paths {
        let found = match query_files(path) {
            Ok(found) => found,
            Err(error) => {
                eprintln!("error: {error}");
                return ExitCode::from(2);
            }
        };
        for file in found {
            // Inside a folder, a file whose path does not tell its kind is
            // skipped (with a warning); a file named on the command line is not.
            if kind.is_none() && path.is_dir() && !QueryFile::kind_is_known(&file) {
                eprintln!("warning: skipped {} (its path does not say edge-edge or vertex-face; name it with --kind)", file.display());
                continue;
            }
            match QueryFile::load(&file, kind) {
                Ok(loaded) => files.push(loaded),
                Err(error) => {
                    eprintln!("error: {error}");
                    return ExitCode::from(2);
                }
            }
        }
    }
    if files.is_empty() {
        eprintln!(
            "error: no query files (.csv) under {}",
            paths.iter().map(|p| p.display().to_string()).collect::<Vec<_>>().join(", ")
        );
        return ExitCode::from(2);
    }
    println!("| file | kind | queries | positives | false neg. | false pos. | out of iter. | mean µs | median µs | max µs | exact times checked | late |");
    println!("|---|---|---|---|---|---|---|---|---|---|---|---|");
    let mut failed = false;
    for file in &files {
        let r = run_file(file, options, repeats);
        failed |= r.false_negatives > 0 || r.late > 0;
        let truth = |n: usize| if r.unknown_truth == r.queries { "?".to_string() } else { n.to_string() };
        println!(
            "| {} | {} | {} | {} | {} | {} | {} | {:.2} | {:.2} | {:.1} | {} | {} |",
            file.path.display(),
            r.kind.short_name(),
            r.queries,
            truth(r.positives),
            truth(r.false_negatives),
            truth(r.false_positives),
            r.out_of_iterations,
            r.mean_microseconds,
            r.median_microseconds,
            r.max_microseconds,
            r.times_checked,
            r.late
        );
    }
    if failed {
        ExitCode::from(1)
    } else {
        ExitCode::SUCCESS
    }
}

/// Loads a scene; prints the error and gives exit code 2 if it is bad.
fn load_scene(path: &Path) -> Result<Scene, ExitCode> {
    Scene::load(path).map_err(|error| {
        eprintln!("error: {error}");
        ExitCode::from(2)
    })
}

/// Runs a scene with a progress bar on a terminal, shown once the run has
/// taken a second.
fn run_with_progress(scene: &Scene) -> RunResult {
    let bar =
        indicatif::ProgressBar::with_draw_target(Some(scene.steps), indicatif::ProgressDrawTarget::hidden());
    let style = indicatif::ProgressStyle::with_template("{msg} [{bar:40}] {pos}/{len} steps, {eta} left")
        .unwrap_or_else(|_| indicatif::ProgressStyle::default_bar());
    bar.set_style(style.progress_chars("=> "));
    bar.set_message(scene.name.clone());
    let start = Instant::now();
    let mut shown = false;
    let result = nearmiss::stepper::run_observed(scene, &mut |done| {
        if !shown && start.elapsed() > Duration::from_secs(1) {
            shown = true;
            bar.set_draw_target(indicatif::ProgressDrawTarget::stderr());
        }
        if shown && done % 64 == 0 {
            bar.set_position(done);
        }
    });
    bar.finish_and_clear();
    result
}

fn run_scene(path: &Path, out: &Path, compare: bool) -> ExitCode {
    let scene = match load_scene(path) {
        Ok(scene) => scene,
        Err(code) => return code,
    };
    let result = run_with_progress(&scene);
    let peer = if compare { nearmiss::report::compare_with_parry(&scene, &result) } else { Vec::new() };
    let written = match nearmiss::output::write_outputs_with_peer(out, &result, &scene, &peer) {
        Ok(written) => written,
        Err(error) => {
            eprintln!("error: cannot write to {}: {error}", out.join(&scene.name).display());
            return ExitCode::from(2);
        }
    };
    println!(
        "scene {}: {} steps of dt = {} to t = {:.9}, {:.3} s",
        scene.name, result.steps, scene.dt, result.end_time, result.wall_time_s
    );
    match &result.first_contact {
        Some(c) => println!(
            "first contact: {} / {} at t = {:.15e}, distance {:.3e} ({:?}); {} contact(s)",
            result.bodies[c.body_a],
            result.bodies[c.body_b],
            c.time,
            c.distance,
            c.status,
            result.contacts.len()
        ),
        None => println!("no contact"),
    }
    if compare {
        println!("| pair | nearmiss | parry | parry query | parry s |\n|---|---|---|---|---|");
        let time = |t: Option<f64>| t.map_or("no contact".to_string(), |t| format!("{t:.12e}"));
        for p in &peer {
            println!(
                "| {} / {} | {} | {} | {} | {:.3} |",
                p.body_a,
                p.body_b,
                time(p.nearmiss),
                time(p.parry),
                p.parry_query,
                p.parry_wall_time_s
            );
        }
    }
    for file in &written {
        println!("wrote {}", file.display());
    }
    if let Termination::Diverged { .. } = result.termination {
        eprintln!("error: {}", nearmiss::output::termination_text(&result));
        return ExitCode::from(1);
    }
    ExitCode::SUCCESS
}

fn check_scenes(paths: &[PathBuf]) -> ExitCode {
    let mut bad = false;
    for path in paths {
        match load_scene(path) {
            Ok(scene) => println!(
                "ok {}: scene `{}`, {} bodies, {} steps of dt = {}",
                path.display(),
                scene.name,
                scene.bodies.len(),
                scene.steps,
                scene.dt
            ),
            Err(_) => bad = true,
        }
    }
    if bad {
        ExitCode::from(2)
    } else {
        ExitCode::SUCCESS
    }
}

fn test_scenes(paths: &[PathBuf]) -> ExitCode {
    let mut files = Vec::new();
    for path in paths {
        match nearmiss::regression::scene_files(path) {
            Ok(found) => files.extend(found),
            Err(error) => {
                eprintln!("error: {}: {error}", path.display());
                return ExitCode::from(2);
            }
        }
    }
    let (mut passed, mut failed, mut bad, mut skipped) = (0, 0, 0, 0);
    for file in &files {
        let scene = match load_scene(file) {
            Ok(scene) => scene,
            Err(_) => {
                bad += 1;
                continue;
            }
        };
        if scene.expect.is_none() {
            skipped += 1;
            continue;
        }
        let result = run_with_progress(&scene);
        let Some(verdict) = nearmiss::regression::verdict(&scene, &result) else { continue };
        let error = verdict.error.map_or(String::new(), |e| format!(", error {e:+.3e}"));
        println!(
            "{} {}: expected {}; obtained {}{error}",
            if verdict.passed { "pass" } else { "FAIL" },
            file.display(),
            verdict.expected,
            verdict.obtained
        );
        if verdict.passed {
            passed += 1;
        } else {
            failed += 1;
        }
    }
    println!("{passed} passed, {failed} failed, {bad} bad, {skipped} without expectation");
    if bad > 0 {
        ExitCode::from(2)
    } else if failed > 0 {
        ExitCode::from(1)
    } else {
        ExitCode::SUCCESS
    }
}

/// Parses each name of a list option; an unknown one is an error naming the
/// option and the known names (exit code 2).
fn parse_names<T>(
    names: &[String],
    parse: fn(&str) -> Option<T>,
    option: &str,
    known: &str,
) -> Result<Vec<T>, ExitCode> {
    names
        .iter()
        .map(|name| {
            parse(name).ok_or_else(|| {
                eprintln!("error: {option}: unknown name `{name}` (known: {known})");
                ExitCode::from(2)
            })
        })
        .collect()
}

fn sweep_scene(path: &Path, dts: &[f64], kernels: &[String], integrators: &[String], out: &Path) -> ExitCode {
    use nearmiss::report::{parse_integrator, parse_kernel};
    let scene = match load_scene(path) {
        Ok(scene) => scene,
        Err(code) => return code,
    };
    if let Some(bad) = dts.iter().find(|dt| !(dt.is_finite() && **dt > 0.0)) {
        eprintln!("error: --dt: every step must be a positive number, found {bad}");
        return ExitCode::from(2);
    }
    let parsed_kernels = match parse_names(
        kernels,
        parse_kernel,
        "--kernel",
        "exact, dyop-vector, dyop-plain-vector, dyop-heron, dyop-stable-heron",
    ) {
        Ok(parsed) => parsed,
        Err(code) => return code,
    };
    let mut parsed_integrators = match parse_names(
        integrators,
        parse_integrator,
        "--integrator",
        "symplectic-euler, explicit-euler, rk4",
    ) {
        Ok(parsed) => parsed,
        Err(code) => return code,
    };
    if parsed_integrators.is_empty() {
        parsed_integrators.push(scene.integrator);
    }
    let total = (dts.len() * parsed_kernels.len() * parsed_integrators.len() + 1) as u64;
    let bar = indicatif::ProgressBar::new(total);
    bar.set_style(
        indicatif::ProgressStyle::with_template("sweep [{bar:40}] {pos}/{len} runs, {eta} left")
            .unwrap_or_else(|_| indicatif::ProgressStyle::default_bar())
            .progress_chars("=> "),
    );
    let report =
        nearmiss::report::sweep(&scene, dts, &parsed_kernels, &parsed_integrators, &mut |done, _| {
            bar.set_position(done as u64)
        });
    bar.finish_and_clear();
    println!(
        "sweep of {}: reference {} ({})",
        report.scene,
        report.reference.map_or("none".into(), |r| format!("{r:.15e}")),
        report.reference_source
    );
    println!("| dt | kernel | integrator | steps | time of contact | error | kernel max rel. error | wall time (s) | ended |");
    println!("|---|---|---|---|---|---|---|---|---|");
    for r in &report.rows {
        println!(
            "| {} | {} | {} | {} | {} | {} | {:.1e} | {:.2e} | {} |",
            r.setting.dt,
            nearmiss::report::kernel_name(r.setting.kernel),
            nearmiss::report::integrator_name(r.setting.integrator),
            r.steps,
            r.time.map_or("none".into(), |t| format!("{t:.12e}")),
            r.error.map_or("-".into(), |e| format!("{e:+.3e}")),
            r.kernel_error,
            r.wall_time_s,
            r.termination
        );
    }
    let folder = out.join(&scene.name);
    let written = std::fs::create_dir_all(&folder).and_then(|_| {
        nearmiss::output::write_atomically(
            &folder.join("sweep.csv"),
            nearmiss::report::sweep_csv(&report).as_bytes(),
        )
    });
    match written {
        Ok(path) => println!("wrote {}", path.display()),
        Err(error) => {
            eprintln!("error: cannot write to {}: {error}", folder.display());
            return ExitCode::from(2);
        }
    }
    #[cfg(feature = "plot")]
    {
        let path = folder.join("error_vs_runtime.png");
        match nearmiss::plot::render(&nearmiss::report::sweep_chart(&report), &path) {
            Ok(()) => println!("wrote {}", path.display()),
            Err(error) => eprintln!("warning: no chart: {error}"),
        }
    }
    ExitCode::SUCCESS
}

fn stability(folder: &Path, out: &Path) -> ExitCode {
    use nearmiss::motion::Integrator;
    use nearmiss::report::{spin_drift, spring_omega, spring_sweep, stability_markdown};
    let (spring, spin) = match (
        load_scene(&folder.join("stiff_spring.ron")),
        load_scene(&folder.join("dzhanibekov_long.ron")),
    ) {
        (Ok(spring), Ok(spin)) => (spring, spin),
        (Err(code), _) | (_, Err(code)) => return code,
    };
    let omega_dts = [0.1, 0.25, 0.5, 1.0, 1.5, 1.8, 1.9, 1.99, 2.01, 2.1, 2.5, 2.8, 2.85, 3.0];
    let integrators = [Integrator::SymplecticEuler, Integrator::ExplicitEuler, Integrator::Rk4];
    let springs = spring_sweep(&spring, &omega_dts, &integrators);
    let drifts = spin_drift(&spin, spin.steps, 100);
    let files = match nearmiss::regression::scene_files(folder) {
        Ok(files) => files,
        Err(error) => {
            eprintln!("error: {}: {error}", folder.display());
            return ExitCode::from(2);
        }
    };
    let mut verdicts = Vec::new();
    let mut failed = false;
    for file in files {
        let scene = match load_scene(&file) {
            Ok(scene) => scene,
            Err(code) => return code,
        };
        let result = run_with_progress(&scene);
        if let Some(v) = nearmiss::regression::verdict(&scene, &result) {
            failed |= !v.passed;
            verdicts.push((file.display().to_string(), v.passed, v.expected, v.obtained, v.error));
        }
    }
    let text = stability_markdown(
        &springs,
        spring_omega(&spring).unwrap_or(Real::NAN),
        &drifts,
        spin.steps,
        &verdicts,
    );
    print!("{text}");
    let target = out.join("stability");
    let written = std::fs::create_dir_all(&target)
        .and_then(|_| nearmiss::output::write_atomically(&target.join("stability.md"), text.as_bytes()));
    if let Err(error) = written {
        eprintln!("error: cannot write to {}: {error}", target.display());
        return ExitCode::from(2);
    }
    #[cfg(feature = "plot")]
    for (chart, name) in [
        (nearmiss::report::spring_chart(&springs), "spring_energy_drift.png"),
        (nearmiss::report::spin_chart(&drifts), "dzhanibekov_energy_drift.png"),
    ] {
        let path = target.join(name);
        match nearmiss::plot::render(&chart, &path) {
            Ok(()) => eprintln!("wrote {}", path.display()),
            Err(error) => eprintln!("warning: no chart {name}: {error}"),
        }
    }
    if failed {
        ExitCode::from(1)
    } else {
        ExitCode::SUCCESS
    }
}

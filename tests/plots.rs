//! Plots: a scene that asks for one gets `distance.png`, 1200 × 800; a plot
//! without a trace is refused.
#![cfg(feature = "plot")]

use nearmiss::scene::Scene;

/// Width and height from a PNG's IHDR chunk.
fn png_size(bytes: &[u8]) -> (u32, u32) {
    assert_eq!(&bytes[..8], b"\x89PNG\r\n\x1a\n", "not a PNG");
    let word = |at: usize| u32::from_be_bytes(bytes[at..at + 4].try_into().unwrap());
    (word(16), word(20))
}

#[test]
fn scene_with_a_plot_writes_distance_png() {
    let scene = Scene::load(concat!(env!("CARGO_MANIFEST_DIR"), "/scenes/spinning_blade.ron")).unwrap();
    assert!(scene.plot.is_some());
    let result = nearmiss::stepper::run(&scene);
    let out = std::env::temp_dir().join(format!("nearmiss-plots-{}", std::process::id()));
    let written = nearmiss::output::write_outputs(&out, &result, &scene).unwrap();
    let png = written.iter().find(|p| p.ends_with("distance.png")).expect("distance.png written");
    assert_eq!(png_size(&std::fs::read(png).unwrap()), nearmiss::plot::CHART_SIZE);
    // No temporary file is left beside it.
    let leftovers: Vec<_> = std::fs::read_dir(png.parent().unwrap())
        .unwrap()
        .filter_map(|e| e.ok())
        .filter(|e| e.file_name().to_string_lossy().contains("tmp"))
        .collect();
    assert!(leftovers.is_empty());
    let _ = std::fs::remove_dir_all(&out);
}

#[test]
fn a_plot_needs_a_trace() {
    let error = Scene::from_ron_str(
        r#"Scene(name: "p", dt: 0.1, steps: 1, plot: (), bodies: [(name: "a", mesh: Tetrahedron(circumradius: 1.0))])"#,
    )
    .unwrap_err()
    .to_string();
    assert!(error.contains("`plot`") && error.contains("trace"), "{error}");
}

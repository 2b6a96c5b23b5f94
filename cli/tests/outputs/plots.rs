//! Plots: a scene that asks for one gets `distance.png`, 1200 × 800; a plot
//! without a trace is refused.
#![cfg(feature = "plot")]

use crate::ball_rest;

use nearmiss::scene::Scene;

/// Width and height from a PNG's IHDR chunk.
fn png_size(bytes: &[u8]) -> (u32, u32) {
    assert_eq!(&bytes[..8], b"\x89PNG\r\n\x1a\n", "not a PNG");
    let word = |at: usize| u32::from_be_bytes(bytes[at..at + 4].try_into().unwrap());
    (word(16), word(20))
}

#[test]
fn scene_with_a_plot_writes_distance_png() {
    let scene = Scene::load(concat!(env!("CARGO_MANIFEST_DIR"), "/../scenes/spinning_blade.ron")).unwrap();
    assert!(scene.run().plot.is_some());
    let result = nearmiss::run(&scene);
    let out = std::env::temp_dir().join(format!("nearmiss-plots-{}", std::process::id()));
    let written = nearmiss_cli::output::write_outputs(&out, &result, &scene).unwrap();
    let png = written.iter().find(|p| p.ends_with("distance.png")).expect("distance.png written");
    assert_eq!(png_size(&std::fs::read(png).unwrap()), nearmiss_cli::plot::CHART_SIZE);
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

/// A ball under `Bounce(restitution: 0.5)` comes to rest touching the floor
/// and reports hundreds of contacts: the chart labels the first few, ticks
/// every one on the time axis, and its line runs down to each contact's
/// distance at the time of impact (inside the step, not at a step's end).
#[test]
fn hundreds_of_contacts_stay_legible() {
    let text = ball_rest::under_bounce().replace("plot: (log_y: false)", "plot: ()");
    let scene = Scene::from_ron_str(&text).unwrap();
    let result = nearmiss::run(&scene);
    assert!(result.contacts.len() > 100, "{} contacts", result.contacts.len());
    let chart = nearmiss_cli::output::distance_chart(&result, scene.run().plot.as_ref().unwrap().log_y);
    assert_eq!(chart.marks.len(), nearmiss_cli::output::LABELLED_CONTACTS);
    assert_eq!(chart.ticks.len(), result.contacts.len());
    assert!(chart.x_label.contains(&format!("{} contacts", result.contacts.len())), "{}", chart.x_label);
    // From 8 units down to contact: the axis is chosen logarithmic.
    assert!(chart.log_y && chart.y_label.contains("chosen"), "{}", chart.y_label);
    // The first contact is inside a step, not on a trace sample (every 4
    // steps), and the line reaches it.
    let first = &result.contacts[0];
    assert!(result.trace.iter().all(|r| r.time != first.time));
    assert!(chart.series[0].points.iter().any(|&(t, _)| t == first.time));
    // Asked for linear, it stays linear.
    assert!(!nearmiss_cli::output::distance_chart(&result, Some(false)).log_y);
    let out = std::env::temp_dir().join(format!("nearmiss-plot-contacts-{}.png", std::process::id()));
    nearmiss_cli::plot::render(&chart, &out).unwrap();
    assert_eq!(png_size(&std::fs::read(&out).unwrap()), nearmiss_cli::plot::CHART_SIZE);
    let _ = std::fs::remove_file(&out);
}

/// With a plot, the first contacts are pictured (`contact_<n>.png`, the
/// first `PICTURED_CONTACTS`) and any the scene names; the run's page shows
/// them and says which named contact did not happen; a picture of an
/// earlier run that this one does not draw is not kept.
#[test]
fn the_first_contacts_and_the_named_ones_are_pictured() {
    let text = ball_rest::under_bounce();
    let named = text.replace("plot: (log_y: false)", "plot: (log_y: false, contacts: [7, 100000])");
    let scene = Scene::from_ron_str(&named).unwrap();
    let result = nearmiss::run(&scene);
    assert!(result.contacts.len() > 7 && result.contacts.len() < 100000);
    let out = std::env::temp_dir().join(format!("nearmiss-contact-pictures-{}", std::process::id()));
    let written = nearmiss_cli::output::write_outputs(&out, &result, &scene).unwrap();
    let pictures: Vec<String> = written
        .iter()
        .map(|p| p.file_name().unwrap().to_string_lossy().into_owned())
        .filter(|name| name.starts_with("contact_"))
        .collect();
    assert_eq!(pictures, ["contact_1.png", "contact_2.png", "contact_3.png", "contact_7.png"]);
    for picture in &pictures {
        let bytes = std::fs::read(out.join("ball_rest").join(picture)).unwrap();
        assert_eq!(png_size(&bytes), nearmiss_cli::plot::CHART_SIZE);
    }
    let page = std::fs::read_to_string(out.join("ball_rest/report.md")).unwrap();
    assert!(
        page.contains("![contact 1](contact_1.png)") && page.contains("![contact 7](contact_7.png)"),
        "{page}"
    );
    assert!(page.contains("asked for pictures of contact 100000, but the run had"), "{page}");
    // The same scene without the named contact: contact_7.png goes.
    let plain = Scene::from_ron_str(&text).unwrap();
    nearmiss_cli::output::write_outputs(&out, &nearmiss::run(&plain), &plain).unwrap();
    assert!(out.join("ball_rest/contact_3.png").exists());
    assert!(!out.join("ball_rest/contact_7.png").exists());
    let _ = std::fs::remove_dir_all(&out);
}

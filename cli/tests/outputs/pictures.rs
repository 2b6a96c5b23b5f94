//! Every kind of picture the shipped scenes and reports draw, read back as
//! pixels: the right size, not blank, and nothing drawn into the image's
//! outer frame (a label or a body running off the edge would be there).
#![cfg(feature = "plot")]

use std::path::Path;

use nearmiss::kernels::PointEdgeFormula;
use nearmiss::mesh::DistanceKernel;
use nearmiss::motion::Integrator;
use nearmiss::scene::Scene;
use nearmiss_cli::plot::{render, CHART_SIZE};

/// The outer frame of the image that must stay white, in pixels.
const FRAME: u32 = 3;

/// Decodes a PNG into RGB rows.
fn pixels(path: &Path) -> (u32, u32, Vec<[u8; 3]>) {
    let decoder = png::Decoder::new(std::io::BufReader::new(std::fs::File::open(path).unwrap()));
    let mut reader = decoder.read_info().unwrap();
    let mut buffer = vec![0; reader.output_buffer_size()];
    let info = reader.next_frame(&mut buffer).unwrap();
    let channels = info.color_type.samples();
    let rgb = buffer[..info.buffer_size()].chunks(channels).map(|p| [p[0], p[1], p[2]]).collect();
    (info.width, info.height, rgb)
}

fn check(path: &Path) {
    let (width, height, rgb) = pixels(path);
    let name = path.display();
    assert_eq!((width, height), CHART_SIZE, "{name}");
    let white = |p: &[u8; 3]| p.iter().all(|&c| c >= 250);
    let inked = rgb.iter().filter(|p| !white(p)).count();
    assert!(inked as f64 > 0.02 * (width * height) as f64, "{name}: almost blank ({inked} pixels)");
    for y in 0..height {
        for x in 0..width {
            if x < FRAME || y < FRAME || x >= width - FRAME || y >= height - FRAME {
                assert!(white(&rgb[(y * width + x) as usize]), "{name}: drawn at the edge, pixel ({x}, {y})");
            }
        }
    }
}

fn scene(name: &str) -> Scene {
    Scene::load(format!("{}/../scenes/{name}.ron", env!("CARGO_MANIFEST_DIR"))).unwrap()
}

#[test]
fn every_picture_of_a_run_is_whole() {
    let out = std::env::temp_dir().join(format!("nearmiss-pictures-{}", std::process::id()));
    // Linear and log distance axes, many and few contacts, contact pictures
    // of boxes, balls, triangles and a turning blade, a near miss.
    for name in [
        "ball_between_walls",
        "falling_box",
        "ball_rest",
        "two_triangles",
        "spinning_blade",
        "bar_clearance",
        "ring_through_slab",
    ] {
        let scene = scene(name);
        let result = nearmiss::run(&scene);
        let written = nearmiss_cli::output::write_outputs(&out, &result, &scene).unwrap();
        let pictures: Vec<_> = written.iter().filter(|p| p.extension().is_some_and(|e| e == "png")).collect();
        assert!(pictures.len() >= 2, "{name}: a distance chart and a contact picture at least");
        if !result.near_misses.is_empty() {
            assert!(written.iter().any(|p| p.ends_with("nearest_near_miss.png")), "{name}: {written:?}");
        }
        for picture in pictures {
            check(picture);
        }
    }
    let _ = std::fs::remove_dir_all(&out);
}

/// A ball starting 0.15 deep in a floor and moving up: its contact
/// picture draws the curve where the surfaces cross (green), the page
/// lists the overlap with its depth, and the chart goes below 0.
#[test]
fn an_overlap_is_pictured_with_its_curve_and_listed_on_the_page() {
    let out = std::env::temp_dir().join(format!("nearmiss-overlap-picture-{}", std::process::id()));
    let scene = Scene::from_ron_str(
        r#"Scene(name: "overlap", dt: 0.01, duration: 0.5, on_contact: Record, trace: (pairs: All), plot: (),
        bodies: [
            (name: "floor", mesh: Box(half_extents: (1.0, 1.0, 0.5)), position: (0.0, 0.0, -0.5), fixed: true),
            (name: "ball", mesh: Icosphere(radius: 0.5, subdivisions: 1), position: (0.3, 0.2, 0.35), velocity: (0.0, 0.0, 1.0)),
        ])"#,
    )
    .unwrap();
    let result = nearmiss::run(&scene);
    // The icosphere has a vertex at its bottom: 0.15 deep exactly.
    assert!((result.trace[0].distance + 0.15).abs() < 1e-12, "{:?}", result.trace[0]);
    let written = nearmiss_cli::output::write_outputs(&out, &result, &scene).unwrap();
    let picture = written.iter().find(|p| p.ends_with("contact_1.png")).expect("a contact picture");
    check(picture);
    let (_, _, rgb) = pixels(picture);
    let green = rgb.iter().filter(|p| **p == [20, 150, 60]).count();
    assert!(green > 200, "{green} pixels of the crossing curve's green");
    check(written.iter().find(|p| p.ends_with("distance.png")).expect("a chart"));
    let page = std::fs::read_to_string(written.iter().find(|p| p.ends_with("report.md")).unwrap()).unwrap();
    assert!(page.contains("## Overlapping at the start"), "{page}");
    assert!(page.contains("| floor / ball | 0.15 | (0, 0, 1) |"), "{page}");
    let _ = std::fs::remove_dir_all(&out);
}

#[test]
fn every_report_chart_is_whole() {
    let out = std::env::temp_dir().join(format!("nearmiss-report-charts-{}", std::process::id()));
    std::fs::create_dir_all(&out).unwrap();
    let spring = scene("stability/stiff_spring");
    let integrators = [Integrator::SymplecticEuler, Integrator::ExplicitEuler, Integrator::Rk4];
    let rows = nearmiss_cli::report::spring_sweep(&spring, &[0.1, 1.0, 1.9, 2.1, 3.0], &integrators);
    let spin = nearmiss_cli::report::spin_drift(&scene("stability/dzhanibekov_long"), 2000, 100);
    let falling = scene("falling_box");
    let kernels = [DistanceKernel::Exact, DistanceKernel::Dyop(PointEdgeFormula::Heron)];
    let sweep = nearmiss_cli::report::sweep(&falling, &[0.01, 0.005], &kernels, &integrators, &mut |_, _| {});
    let kernel_rows = nearmiss_cli::report::kernel_report(20, 1);
    let charts = [
        ("spring.png", nearmiss_cli::report::spring_chart(&rows)),
        ("spin.png", nearmiss_cli::report::spin_chart(&spin)),
        ("sweep.png", nearmiss_cli::report::sweep_chart(&sweep)),
        ("triangle_kernels.png", nearmiss_cli::report::kernel_chart(&kernel_rows, false)),
        ("point_segment_kernels.png", nearmiss_cli::report::kernel_chart(&kernel_rows, true)),
    ];
    for (name, chart) in charts {
        let path = out.join(name);
        render(&chart, &path).unwrap();
        check(&path);
    }
    let _ = std::fs::remove_dir_all(&out);
}

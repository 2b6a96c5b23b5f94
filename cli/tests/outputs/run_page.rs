//! `report.md`: one page per run, written with the run's other files; every
//! link on it names a file in the run's folder, and it states the run's
//! contacts and its expectation's verdict.

use nearmiss::scene::Scene;

/// The targets of the markdown links and images `](target)` of a page.
fn link_targets(page: &str) -> Vec<String> {
    page.split("](").skip(1).map(|rest| rest[..rest.find(')').expect("a closed link")].to_string()).collect()
}

#[test]
fn the_page_links_only_files_written_beside_it() {
    let scene = Scene::load(concat!(env!("CARGO_MANIFEST_DIR"), "/../scenes/falling_box.ron")).unwrap();
    let result = nearmiss::run(&scene);
    let out = std::env::temp_dir().join(format!("nearmiss-run-page-{}", std::process::id()));
    let written = nearmiss_cli::output::write_outputs(&out, &result, &scene).unwrap();
    let page_path = written.iter().find(|p| p.ends_with("report.md")).expect("report.md written");
    let page = std::fs::read_to_string(page_path).unwrap();
    let folder = page_path.parent().unwrap();
    let targets = link_targets(&page);
    assert!(targets.iter().any(|t| t == "summary.json"), "{page}");
    for target in &targets {
        assert!(folder.join(target).is_file(), "{target} is linked but not in {}", folder.display());
    }
    // Every file is described.
    for line in page.lines().filter(|l| l.starts_with("- [")) {
        assert!(line.contains("): ") && !line.ends_with(": "), "{line}");
    }
    // The contact time as summary.json writes it, and the verdict.
    let first = result.first_contact.as_ref().expect("the box hits the floor");
    assert!(page.contains(&format!("| 1 | {} |", nearmiss::math::shortest(first.time))), "{page}");
    assert!(page.contains("Expectation met"), "{page}");
    #[cfg(feature = "plot")]
    assert!(targets.iter().any(|t| t == "distance.png"));
    let _ = std::fs::remove_dir_all(&out);
}

#[test]
fn a_pipe_in_a_body_name_stays_in_its_cell() {
    let scene = Scene::from_ron_str(
        r#"Scene(name: "pipes", dt: 0.01, steps: 100, bodies: [
            (name: "floor|slab", mesh: Box(half_extents: (2.0, 2.0, 0.5)), position: (0.0, 0.0, -0.5), fixed: true),
            (name: "a|b", mesh: Tetrahedron(circumradius: 0.5), position: (0.0, 0.0, 1.0), velocity: (0.0, 0.0, -2.0)),
        ])"#,
    )
    .unwrap();
    let result = nearmiss::run(&scene);
    assert!(!result.contacts.is_empty());
    let page = nearmiss_cli::run_page::run_page(&result, &scene, &["summary.json", "report.md"]);
    let row = page.lines().find(|l| l.starts_with("| 1 |")).expect("a contact row");
    // Six cells, so seven unescaped pipes: the escaped ones split none.
    let unescaped = row.char_indices().filter(|&(k, c)| c == '|' && !row[..k].ends_with('\\')).count();
    assert_eq!(unescaped, 7, "{row}");
    assert!(row.contains("floor\\|slab / a\\|b"), "{row}");
}

#[test]
fn the_work_line_counts_in_the_singular_where_it_is_one() {
    // Issue 46: two triangles meeting took "1 triangle pairs".
    let scene = Scene::load(concat!(env!("CARGO_MANIFEST_DIR"), "/../scenes/two_triangles.ron")).unwrap();
    let result = nearmiss::run(&scene);
    assert_eq!(result.counters.work.triangle_pairs, 1);
    let page = nearmiss_cli::run_page::run_page(&result, &scene, &["summary.json", "report.md"]);
    let work = page.lines().find(|l| l.starts_with("| work |")).expect("the work row");
    assert!(work.contains(", 1 triangle pair,"), "{work}");
    assert!(work.contains("CCD advancement steps") && work.contains("pair-steps skipped"), "{work}");
}

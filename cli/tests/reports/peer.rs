//! `--compare parry`: parry's answer beside nearmiss's, for the pairs that
//! parry can follow.

use nearmiss::run::run;
use nearmiss::scene::Scene;
use nearmiss_cli::report::compare_with_parry;

fn shipped(name: &str) -> Scene {
    Scene::load(format!("{}/../scenes/{name}", env!("CARGO_MANIFEST_DIR"))).unwrap()
}

#[test]
fn translating_pair_agrees_with_parry_cast_shapes() {
    let scene = shipped("two_triangles.ron");
    let result = run(&scene);
    let rows = compare_with_parry(&scene, &result);
    assert_eq!(rows.len(), 1);
    assert_eq!(rows[0].parry_query, "cast_shapes");
    let (ours, theirs) = (rows[0].nearmiss.unwrap(), rows[0].parry.unwrap());
    // Both against the analytic 0.5: nearmiss never late, parry within its own tolerance.
    assert!(ours <= 0.5 && 0.5 - ours <= 1e-8);
    assert!((theirs - 0.5).abs() <= 1e-6, "{theirs}");
}

#[test]
fn integrated_bodies_are_not_sent_to_parry() {
    let scene = shipped("falling_box.ron");
    let result = run(&scene);
    let rows = compare_with_parry(&scene, &result);
    assert_eq!(rows.len(), 1);
    assert!(rows[0].parry.is_none() && rows[0].parry_query.starts_with("none"));
}

//! `summary.json`'s `near_misses` (DESIGN's names: `bodies`, `distance`,
//! `lower`, `time`, the closest points and features), present only where
//! the scene asks; `report.md` lists them.

use nearmiss::scene::Scene;

fn scene(near_misses: &str) -> Scene {
    Scene::from_ron_str(&format!(
        r#"Scene(name: "pass_by", dt: 0.01, duration: 2.0, {near_misses} bodies: [
            (name: "fixed", mesh: Box(half_extents: (0.5, 0.5, 0.5)), fixed: true),
            (name: "passer", mesh: Box(half_extents: (0.5, 0.5, 0.5)), position: (-3.0, 1.25, 0.2), velocity: (3.0, 0.0, 0.0)),
        ])"#
    ))
    .unwrap()
}

#[test]
fn near_misses_are_written_where_asked() {
    let out = std::env::temp_dir().join(format!("nearmiss-near-misses-{}", std::process::id()));
    let asked = scene("near_misses: (within: 0.5),");
    nearmiss_cli::output::write_outputs(&out, &nearmiss::run(&asked), &asked).unwrap();
    let summary: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(out.join("pass_by/summary.json")).unwrap()).unwrap();
    let list = summary["near_misses"].as_array().expect("a near_misses list");
    assert_eq!(list.len(), 1);
    let miss = &list[0];
    assert_eq!(miss["bodies"], serde_json::json!(["fixed", "passer"]));
    for key in ["distance", "lower", "time"] {
        assert!(miss[key].is_f64(), "{key}: {miss}");
    }
    for key in ["point_a", "point_b"] {
        assert_eq!(miss[key].as_array().map(Vec::len), Some(3), "{key}: {miss}");
    }
    // The faces pass parallel, 0.25 apart: the closest points are a tie
    // over a face, written as a face or one of its edges, and they are the
    // distance apart.
    for key in ["feature_a", "feature_b"] {
        let feature = miss[key].as_str().unwrap_or_default();
        assert!(
            feature == "face" || feature.starts_with("edge ") || feature.starts_with("vertex "),
            "{miss}"
        );
    }
    let point = |key: &str| -> Vec<f64> {
        miss[key].as_array().unwrap().iter().map(|c| c.as_f64().unwrap()).collect()
    };
    let (a, b) = (point("point_a"), point("point_b"));
    let gap = ((a[0] - b[0]).powi(2) + (a[1] - b[1]).powi(2) + (a[2] - b[2]).powi(2)).sqrt();
    let (distance, lower) = (miss["distance"].as_f64().unwrap(), miss["lower"].as_f64().unwrap());
    assert!((gap - distance).abs() < 1e-12, "{miss}");
    assert!(lower <= 0.25 && 0.25 <= distance * (1.0 + 1e-12));
    let page = std::fs::read_to_string(out.join("pass_by/report.md")).unwrap();
    assert!(page.contains("## Near misses") && page.contains("| fixed / passer | 0.25 |"), "{page}");

    let plain = scene("");
    nearmiss_cli::output::write_outputs(&out, &nearmiss::run(&plain), &plain).unwrap();
    let summary: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(out.join("pass_by/summary.json")).unwrap()).unwrap();
    assert!(summary.get("near_misses").is_none(), "{summary}");
    let _ = std::fs::remove_dir_all(&out);
}

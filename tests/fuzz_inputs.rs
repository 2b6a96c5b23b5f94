//! Bad-input fuzzing on the stable toolchain: generated edits of real
//! inputs (the shipped scenes, an OBJ file, STL, PLY and GLB files) go
//! through the scene loader, the mesh readers and a short run, and
//! proptest minimises whatever fails.
//!
//! What must hold for any text: the loader never panics and either refuses
//! it with a message, or accepts a scene whose run (when short enough to
//! run here) never panics and writes no number that is not finite.
//!
//! The number of cases is bounded for CI (`NEARMISS_FUZZ_CASES`, default
//! 1,024, each a few milliseconds or less); the generator's seed is fixed, so a
//! failure is reproduced by running the test again. The cargo-fuzz targets
//! in `fuzz/` search the same ground with coverage, where a nightly
//! toolchain is at hand.

use std::path::Path;

use proptest::prelude::*;
use proptest::test_runner::{Config, RngAlgorithm, TestCaseError, TestError, TestRng, TestRunner};

use nearmiss::mesh::parse_obj;
use nearmiss::run::{run_with, RunOptions};
use nearmiss::scene::Scene;

/// The shipped scenes the edits start from (those that read no mesh file).
const SCENES: &[&str] = &[
    include_str!("../scenes/two_triangles.ron"),
    include_str!("../scenes/ball_between_walls.ron"),
    include_str!("../scenes/ball_rest.ron"),
    include_str!("../scenes/box_stack.ron"),
    include_str!("../scenes/bullet_guarded.ron"),
    include_str!("../scenes/falling_box.ron"),
    include_str!("../scenes/stiff_spring.ron"),
    include_str!("../scenes/spinning_blade.ron"),
    include_str!("../scenes/stability/grazing.ron"),
    include_str!("../scenes/stability/needles.ron"),
    include_str!("../scenes/stability/tiny_scale.ron"),
    include_str!("../scenes/stability/offset_1e6.ron"),
];

/// The OBJ file the mesh edits start from.
const OBJ: &str = include_str!("../scenes/meshes/t_handle.obj");

/// Numbers that find the edges of a range.
const NUMBERS: &[&str] = &[
    "0",
    "-0.0",
    "-1",
    "1e-320",
    "1e-12",
    "1e-9",
    "3",
    "1e9",
    "1e308",
    "-1e308",
    "NaN",
    "inf",
    "-inf",
    "18446744073709551616",
    "0.5",
];

/// Text that breaks structure or asks for too much.
const FRAGMENTS: &[&str] = &[
    "(",
    ")",
    ",",
    "[",
    "]",
    "\"",
    ":",
    "//",
    "\u{0}",
    "é",
    "Box(half_extents: (0.0, 0.0, 0.0))",
    "fixed: true,",
    "kinematic: true,",
    "velocity: (1e300, 0.0, 0.0),",
    "steps: 0,",
    "density: 0.0,",
    "Icosphere(radius: 1.0, subdivisions: 9)",
    "f 1 1 1\n",
    "v nan 0 0\n",
    "f 1 2 99\n",
];

/// One edit of an input's text; positions are taken modulo its length.
#[derive(Clone, Debug)]
enum Edit {
    /// The `nth` number in the text becomes `NUMBERS[value]`.
    Number { nth: usize, value: usize },
    /// `len` bytes from `at` go (at character boundaries).
    Delete { at: usize, len: usize },
    /// `FRAGMENTS[fragment]` goes in at `at`.
    Insert { at: usize, fragment: usize },
    /// `len` bytes from `at` appear twice.
    Repeat { at: usize, len: usize },
}

fn edit() -> impl Strategy<Value = Edit> {
    prop_oneof![
        (0..32usize, 0..NUMBERS.len()).prop_map(|(nth, value)| Edit::Number { nth, value }),
        (0..4096usize, 1..16usize).prop_map(|(at, len)| Edit::Delete { at, len }),
        (0..4096usize, 0..FRAGMENTS.len()).prop_map(|(at, fragment)| Edit::Insert { at, fragment }),
        (0..4096usize, 1..200usize).prop_map(|(at, len)| Edit::Repeat { at, len }),
    ]
}

/// The character boundary at or before `at % (len + 1)`.
fn boundary(text: &str, at: usize) -> usize {
    let mut at = at % (text.len() + 1);
    while !text.is_char_boundary(at) {
        at -= 1;
    }
    at
}

/// `text` with `edits` applied in order.
fn edited(text: &str, edits: &[Edit]) -> String {
    let mut text = text.to_string();
    for edit in edits {
        match *edit {
            Edit::Number { nth, value } => {
                let numbers = number_spans(&text);
                if let Some(&(start, end)) = numbers.get(nth % numbers.len().max(1)) {
                    text.replace_range(start..end, NUMBERS[value]);
                }
            }
            Edit::Delete { at, len } => {
                let start = boundary(&text, at);
                let end = boundary(&text, start + len).max(start);
                text.replace_range(start..end, "");
            }
            Edit::Insert { at, fragment } => {
                let at = boundary(&text, at);
                text.insert_str(at, FRAGMENTS[fragment]);
            }
            Edit::Repeat { at, len } => {
                let start = boundary(&text, at);
                let end = boundary(&text, start + len).max(start);
                let copy = text[start..end].to_string();
                text.insert_str(end, &copy);
            }
        }
    }
    text
}

/// The byte spans of the numbers in `text` (digits with their sign,
/// point and exponent), but for those in `//` comments.
fn number_spans(text: &str) -> Vec<(usize, usize)> {
    let bytes = text.as_bytes();
    let mut spans = Vec::new();
    let mut i = 0;
    while i < bytes.len() {
        if bytes[i..].starts_with(b"//") {
            while i < bytes.len() && bytes[i] != b'\n' {
                i += 1;
            }
            continue;
        }
        let starts = bytes[i].is_ascii_digit() && (i == 0 || !bytes[i - 1].is_ascii_alphanumeric());
        if !starts {
            i += 1;
            continue;
        }
        let start = if i > 0 && bytes[i - 1] == b'-' { i - 1 } else { i };
        while i < bytes.len() && (bytes[i].is_ascii_alphanumeric() || matches!(bytes[i], b'.' | b'_' | b'-'))
        {
            if bytes[i] == b'-' && !matches!(bytes[i - 1], b'e' | b'E') {
                break;
            }
            i += 1;
        }
        spans.push((start, i));
    }
    spans
}

/// What must hold for a scene text (see the module); `plant`, when given,
/// is a fault planted in the loader's place (a test that the fuzzing finds
/// and minimises it).
fn scene_holds(text: &str, plant: Option<&dyn Fn(&Scene) -> bool>) -> Result<(), TestCaseError> {
    let scene = match Scene::from_ron_str(text) {
        Err(error) => {
            prop_assert!(!error.to_string().trim().is_empty(), "an empty message");
            return Ok(());
        }
        Ok(scene) => scene,
    };
    if let Some(fault) = plant {
        prop_assert!(!fault(&scene), "the planted fault");
    }
    // Short runs only: CI's time is bounded, and a run's cost grows with
    // its steps and its meshes.
    let triangles: usize = scene.model().bodies.iter().map(|b| b.mesh.triangles().len()).sum();
    if scene.check_steps(1000).is_err() || triangles > 20_000 {
        return Ok(());
    }
    let result = run_with(&scene, RunOptions { parallel: false, ..RunOptions::default() }, &mut |_| {});
    prop_assert!(result.first_non_finite().is_none(), "{:?}", result.first_non_finite());
    prop_assert!(result.contacts.iter().all(|c| (0.0..=result.end_time).contains(&c.time)));
    Ok(())
}

/// A runner of `cases` cases from a fixed seed.
fn runner(cases: u32) -> TestRunner {
    let config = Config { cases, failure_persistence: None, ..Config::default() };
    TestRunner::new_with_rng(config, TestRng::deterministic_rng(RngAlgorithm::ChaCha))
}

/// The cases CI runs (`NEARMISS_FUZZ_CASES` asks for more).
fn cases() -> u32 {
    std::env::var("NEARMISS_FUZZ_CASES").ok().and_then(|n| n.parse().ok()).unwrap_or(1024)
}

fn scene_plan() -> impl Strategy<Value = (usize, Vec<Edit>)> {
    (0..SCENES.len(), proptest::collection::vec(edit(), 0..6))
}

#[test]
fn edited_scenes_are_refused_with_a_message_or_run_without_a_panic() {
    let result =
        runner(cases()).run(&scene_plan(), |(seed, edits)| scene_holds(&edited(SCENES[seed], &edits), None));
    if let Err(error) = result {
        panic!("{error}");
    }
}

#[test]
fn edited_obj_files_are_refused_with_a_message_or_read_whole() {
    let plan = proptest::collection::vec(edit(), 0..8);
    let result = runner(cases() * 4).run(&plan, |edits| {
        match parse_obj(&edited(OBJ, &edits), Path::new("fuzz.obj")) {
            Err(error) => prop_assert!(error.to_string().contains("fuzz.obj"), "{error}"),
            Ok(mesh) => {
                prop_assert!(mesh.radius().is_finite() && mesh.radius() > 0.0);
                let count = mesh.vertices().len() as u32;
                prop_assert!(mesh.triangles().iter().flatten().all(|&v| v < count));
            }
        }
        Ok(())
    });
    if let Err(error) = result {
        panic!("{error}");
    }
}

/// The mesh files in every other format (`tests/data/mesh_files`, written
/// by trimesh) the byte edits start from.
const MESH_FILES: &[(&str, &[u8])] = &[
    ("box.stl", include_bytes!("data/mesh_files/box.stl")),
    ("box_ascii.stl", include_bytes!("data/mesh_files/box_ascii.stl")),
    ("box.ply", include_bytes!("data/mesh_files/box.ply")),
    ("box_ascii.ply", include_bytes!("data/mesh_files/box_ascii.ply")),
    ("box.glb", include_bytes!("data/mesh_files/box.glb")),
];

/// One edit of a file's bytes; positions are taken modulo its length.
#[derive(Clone, Debug)]
enum ByteEdit {
    /// The byte at `at` becomes `value`.
    Set { at: usize, value: u8 },
    /// `len` bytes from `at` go.
    Delete { at: usize, len: usize },
    /// `len` bytes from `at` appear twice.
    Repeat { at: usize, len: usize },
}

fn byte_edit() -> impl Strategy<Value = ByteEdit> {
    prop_oneof![
        (0..4096usize, any::<u8>()).prop_map(|(at, value)| ByteEdit::Set { at, value }),
        (0..4096usize, 1..64usize).prop_map(|(at, len)| ByteEdit::Delete { at, len }),
        (0..4096usize, 1..200usize).prop_map(|(at, len)| ByteEdit::Repeat { at, len }),
    ]
}

#[test]
fn edited_stl_ply_and_glb_files_are_refused_with_a_message_or_read_whole() {
    let plan = (0..MESH_FILES.len(), proptest::collection::vec(byte_edit(), 1..6));
    let result = runner(cases() * 4).run(&plan, |(seed, edits)| {
        let (name, original) = MESH_FILES[seed];
        let mut bytes = original.to_vec();
        for edit in &edits {
            let at = |at: usize| at % (bytes.len() + 1);
            match *edit {
                ByteEdit::Set { at: a, value } if !bytes.is_empty() => {
                    let a = a % bytes.len();
                    bytes[a] = value;
                }
                ByteEdit::Set { .. } => {}
                ByteEdit::Delete { at: a, len } => {
                    let a = at(a);
                    bytes.drain(a..(a + len).min(bytes.len()));
                }
                ByteEdit::Repeat { at: a, len } => {
                    let a = at(a);
                    let copy = bytes[a..(a + len).min(bytes.len())].to_vec();
                    bytes.splice(a..a, copy);
                }
            }
        }
        match nearmiss::mesh::read_mesh(bytes, Path::new(name)) {
            Err(error) => prop_assert!(error.to_string().starts_with(name), "{error}"),
            Ok(mesh) => {
                prop_assert!(mesh.radius().is_finite());
                let count = mesh.vertices().len() as u32;
                prop_assert!(mesh.triangles().iter().flatten().all(|&v| v < count));
            }
        }
        Ok(())
    });
    if let Err(error) = result {
        panic!("{error}");
    }
}

#[test]
fn a_planted_fault_is_found_and_minimised_to_one_edit() {
    // The fault planted: a loader that falls over on a body placed or
    // moving at 1e9 or beyond in any coordinate (no seed is; one edit of
    // one number reaches it).
    let fault = |scene: &Scene| {
        scene.model().bodies.iter().any(|body| {
            let far = |v: &nearmiss::math::Vector| v.amax() >= 1e9;
            far(&body.pose.translation.vector) || far(&body.velocity)
        })
    };
    let result = runner(cases())
        .run(&scene_plan(), |(seed, edits)| scene_holds(&edited(SCENES[seed], &edits), Some(&fault)));
    match result {
        Err(TestError::Fail(why, (seed, edits))) => {
            assert!(why.message().contains("planted"), "another failure: {why}");
            assert_eq!(edits.len(), 1, "not minimised: {edits:?}");
            let text = edited(SCENES[seed], &edits);
            assert!(fault(&Scene::from_ron_str(&text).expect("the minimal case loads")));
        }
        other => panic!("the planted fault was not found: {other:?}"),
    }
}

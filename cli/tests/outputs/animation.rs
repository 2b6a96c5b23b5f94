//! `animation.glb`: a run with `poses` is also written as glTF 2.0 with one
//! animation. Read back with an independent parser and validator (the
//! `gltf` crate): it validates, has a node and a mesh per body (shared
//! meshes shared), and its keyframes are the run's pose records (times
//! strictly increasing, positions and rotations to f32 rounding).

use nearmiss::scene::Scene;

/// Five boxes share one mesh: each keeps a colour of its own (they were all
/// one colour), and the mesh's vertices are written once.
#[test]
fn bodies_sharing_a_mesh_keep_their_colours() {
    let scene = Scene::load(concat!(env!("CARGO_MANIFEST_DIR"), "/../scenes/box_stack.ron")).unwrap();
    let result = nearmiss::run(&scene);
    let bytes = nearmiss_cli::animation::glb(&scene, &result.poses).unwrap();
    let gltf = gltf::Gltf::from_slice(&bytes).expect("valid glTF");
    let colours: std::collections::HashSet<_> =
        gltf.materials().map(|m| m.pbr_metallic_roughness().base_color_factor().map(f32::to_bits)).collect();
    assert_eq!(gltf.materials().count(), scene.model().bodies.len());
    assert_eq!(colours.len(), scene.model().bodies.len(), "every body a colour of its own");
    let positions: std::collections::HashSet<_> = gltf
        .meshes()
        .map(|m| m.primitives().next().unwrap().get(&gltf::Semantic::Positions).unwrap().index())
        .collect();
    assert!(positions.len() < scene.model().bodies.len(), "shared meshes' vertices are written once");
}

#[test]
fn a_bouncing_ball_replays() {
    let scene = Scene::load(concat!(env!("CARGO_MANIFEST_DIR"), "/../scenes/ball_rest.ron")).unwrap();
    check(&scene, "ball");
}

/// The spinning blade turns a third of a turn: a quaternion written in the
/// wrong order would not read back.
#[test]
fn a_spinning_blade_replays() {
    let text = std::fs::read_to_string(concat!(env!("CARGO_MANIFEST_DIR"), "/../scenes/spinning_blade.ron"))
        .unwrap()
        .replace("    trace: (pairs: All, every: 1),", "    trace: (pairs: All, every: 1),\n    poses: (),");
    let scene = Scene::from_ron_str(&text).unwrap();
    check(&scene, "blade");
}

fn check(scene: &Scene, moving: &str) {
    assert!(scene.run().poses.is_some());
    let result = nearmiss::run(scene);
    let out = std::env::temp_dir().join(format!("nearmiss-animation-{moving}-{}", std::process::id()));
    let written = nearmiss_cli::output::write_outputs(&out, &result, scene).unwrap();
    let path = written.iter().find(|p| p.ends_with("animation.glb")).expect("animation.glb written");
    let bytes = std::fs::read(path).unwrap();
    let gltf = gltf::Gltf::from_slice(&bytes).expect("valid glTF");
    let blob = gltf.blob.clone().expect("a GLB buffer");

    // One root, turning the scene's up axis (+z: gravity pulls along −z)
    // onto glTF's +Y, with every body under it.
    let roots: Vec<_> = gltf.default_scene().expect("a scene").nodes().collect();
    assert_eq!(roots.len(), 1);
    let (_, rotation, _) = roots[0].transform().decomposed();
    let up = nalgebra::UnitQuaternion::from_quaternion(nalgebra::Quaternion::new(
        rotation[3] as f64,
        rotation[0] as f64,
        rotation[1] as f64,
        rotation[2] as f64,
    )) * nalgebra::Vector3::z();
    assert!((up - nalgebra::Vector3::y()).norm() < 1e-6, "scene up becomes {up:?}");
    let nodes: Vec<_> = roots[0].children().collect();
    assert_eq!(nodes.len(), scene.model().bodies.len());
    let mut materials = std::collections::HashSet::new();
    for (k, (node, body)) in nodes.iter().zip(scene.model().bodies.iter()).enumerate() {
        assert_eq!(node.index(), k, "body nodes keep the body order");
        assert_eq!(node.name(), Some(body.name.as_str()));
        let primitive = node.mesh().expect("a mesh").primitives().next().expect("a primitive");
        assert!(materials.insert(primitive.material().index()), "{}: a material of its own", body.name);
        let reader = primitive.reader(|_| Some(&blob));
        assert_eq!(reader.read_positions().expect("positions").count(), body.mesh.vertices().len());
        assert_eq!(
            reader.read_indices().expect("indices").into_u32().count(),
            3 * body.mesh.triangles().len()
        );
    }

    // One body moves (the other is fixed): its two channels.
    let animation = gltf.animations().next().expect("an animation");
    let ball = scene.model().bodies.iter().position(|b| b.name == moving).unwrap();
    let records: Vec<_> = result.poses.iter().filter(|r| r.body == ball).collect();
    let mut channels = 0;
    for channel in animation.channels() {
        assert_eq!(channel.target().node().index(), ball);
        channels += 1;
        let reader = channel.reader(|_| Some(&blob));
        let times: Vec<f32> = reader.read_inputs().expect("times").collect();
        assert!(times.windows(2).all(|w| w[0] < w[1]), "key times not increasing");
        // Records with the same time (a last sample at a step end) are one key.
        let mut expected: Vec<_> = records.clone();
        expected.dedup_by(|later, earlier| later.time <= earlier.time);
        assert_eq!(times.len(), expected.len());
        match reader.read_outputs().expect("values") {
            gltf::animation::util::ReadOutputs::Translations(values) => {
                for ((value, record), time) in values.zip(&expected).zip(&times) {
                    assert_eq!(*time, record.time as f32);
                    let scale = record.position.coords.amax().max(1.0);
                    for (got, want) in value.iter().zip(record.position.iter()) {
                        assert!((*got as f64 - want).abs() <= 1e-6 * scale);
                    }
                }
            }
            gltf::animation::util::ReadOutputs::Rotations(values) => {
                let mut turned = false;
                for (value, record) in values.into_f32().zip(&expected) {
                    turned |= record.orientation.angle() > 0.1;
                    let q = record.orientation;
                    let want = [q.i, q.j, q.k, q.w];
                    for (got, want) in value.iter().zip(want) {
                        assert!((*got as f64 - want).abs() <= 1e-6);
                    }
                }
                assert!(turned || moving == "ball", "the blade should turn");
            }
            _ => panic!("only translations and rotations are animated"),
        }
    }
    assert_eq!(channels, 2);
    let _ = std::fs::remove_dir_all(&out);
}

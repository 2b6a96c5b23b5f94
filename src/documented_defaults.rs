//! The defaults stated in the docs are the ones in the code (the
//! application's: `cli/tests/documented_defaults.rs`). Here, in the
//! library, since its tuning constants are not public.

use crate::kernels::PointEdgeFormula;
use crate::kernels::{REFINE_BELOW_EXTENT, REFINE_TIE_BAND_ULPS};

#[test]
fn documented_defaults_are_the_real_ones() {
    // kernels::point_segment: "Vector ... (default)".
    assert_eq!(PointEdgeFormula::default(), PointEdgeFormula::Vector);
    // kernels::refine: "Default `1e-3`" and "Default `16`".
    assert_eq!(REFINE_BELOW_EXTENT, 1e-3);
    assert_eq!(REFINE_TIE_BAND_ULPS, 16.0);
    // mesh/penetration.rs: "Default `1e-10`" and "Default `1e-12`".
    assert_eq!(crate::mesh::PARALLEL_EDGE_SINE, 1e-10);
    assert_eq!(crate::mesh::FLAT_EDGE_TOLERANCE, 1e-12);
    // ccd/closest_approach.rs: "`10`" (BUDGET_GROWTH); mesh/bvh.rs: "`0.9`".
    assert_eq!(crate::ccd::BUDGET_GROWTH, 10);
    // ccd/swept_plane.rs: "Default `64`".
    assert_eq!(crate::ccd::PLANE_ROUNDING_ULPS, 64.0);
    assert_eq!(crate::mesh::PRINCIPAL_BOX_GAIN, 0.9);
}

#[test]
fn scene_defaults_are_the_documented_ones() {
    use crate::scene::{OnContact, Scene};
    let scene = Scene::from_ron_str(
        r#"Scene(name: "d", dt: 0.1, steps: 1, trace: (), bodies: [(name: "a", mesh: Tetrahedron(circumradius: 1.0))])"#,
    )
    .unwrap();
    // scene/file.rs: integrator "Default: `SymplecticEuler`", gyroscopic "Default: `Implicit`",
    // on_contact "Default: `Stop`", ccd kernel "Default: `Exact`", distance_tolerance
    // "Default: `1e-6`", minimum_separation "Default: `0`", max_iterations "Default: `10000`",
    // trace every "Default: 1", scale "Default: 1".
    assert_eq!(scene.model().integrator, crate::motion::Integrator::SymplecticEuler);
    assert_eq!(scene.model().gyroscopic, crate::motion::Gyroscopic::Implicit);
    assert_eq!(scene.model().on_contact, OnContact::Stop);
    assert_eq!(scene.model().kernel, crate::mesh::DistanceKernel::Exact);
    assert_eq!(scene.model().ccd.distance_tolerance, 1e-6);
    assert_eq!(scene.model().ccd.minimum_separation, 0.0);
    assert_eq!(scene.model().ccd.max_iterations, 10_000);
    assert_eq!(scene.run().trace.as_ref().unwrap().every, 1);
    assert_eq!(scene.model().bodies[0].mesh.radius(), 1.0);
    // motion/classify.rs: a spin is steady within `64` ulps.
    assert_eq!(crate::motion::classify::STEADY_SPIN_ULPS, 64.0);
    // motion/gyroscopic.rs: at most 20 Newton iterations.
    assert_eq!(crate::motion::GYROSCOPIC_MAX_ITERATIONS, 20);
    assert_eq!(crate::motion::COFACTOR_UNSCALED_RANGE, 1e100);
    // ccd/mesh_pair.rs: "plus 8 ulps of an integrated body's coordinates".
    assert_eq!(crate::ccd::INTEGRATED_JUMP_ULPS, 8.0);
    // ccd/mesh_search.rs: the search's slack `0.1` and opening ratio `1.0`.
    assert_eq!(crate::ccd::STEP_SLACK, 0.1);
    assert_eq!(crate::ccd::OPEN_RATIO, 1.0);
    // ccd/mesh_bound.rs: the spin-swept bound from `1.0` rad of turn, below `1/64` of
    // the horizon, after `32` steps of a query.
    assert_eq!(crate::ccd::SPIN_SWEEP_MIN_TURN, 1.0);
    assert_eq!(crate::ccd::SPIN_SWEEP_MAX_RATE_FRACTION, 1.0 / 64.0);
    assert_eq!(crate::ccd::SPIN_SWEEP_AFTER_ITERATIONS, 32);
    // ccd/contact.rs: the target at `0.5` of the tolerance, box margins `2.0` x tolerance x r.
    assert_eq!(crate::ccd::TARGET_FRACTION, 0.5);
    assert_eq!(crate::ccd::BOX_MARGIN_TOLERANCE_FACTOR, 2.0);
    // stepper/parameters.rs (and README, scenes/README.md): a run is stopped when the
    // energy grows past 10x its scale; re-armed beyond "twice the contact distance"; a
    // bounced pair is a new contact "within half its distance at the bounce"; box
    // rounding 1e3 ulps; integration on the threads from 64 bodies; the narrow phase on
    // them when it costs more than handing it over, 1e-4 s (under the guard 3e-4 s).
    // motion/step_motion.rs: a whole turn's axis is the spin's below 4 ulps.
    assert_eq!(crate::motion::TURN_ROUNDING_ULPS, 4.0);
    // scene/build_body.rs: a keyframe's time on a step within `1e-9` of
    // itself; keyframes' turns under half a turn by `1e-9` rad.
    // collection.rs: world boxes widened by `1e3` ulps of their reach, as
    // the stepper's (`broad_phase_rounding_ulps` below).
    assert_eq!(crate::scene::KEYFRAME_TIME_TOLERANCE, 1e-9);
    assert_eq!(crate::scene::KEYFRAME_TURN_MARGIN, 1e-9);
    assert_eq!(crate::collection::BOX_ROUNDING_ULPS, 1e3);
    // broad_phase.rs: the tree re-optimised at every second refit.
    assert_eq!(crate::broad_phase::OPTIMIZE_EVERY_REFITS, 2);
    assert_eq!(crate::broad_phase::GRID_BROAD_PHASE_BOXES, 8192);
    assert_eq!(crate::broad_phase::PARALLEL_GRID_BOXES, 4096);
    let parameters = crate::scene::StepParameters::default();
    assert_eq!(parameters.divergence_energy_growth, 10.0);
    assert_eq!(parameters.rearm_distance_factor, 2.0);
    assert_eq!(parameters.bounce_redetect_fraction, 0.5);
    assert_eq!(parameters.broad_phase_rounding_ulps, 1e3);
    let options = crate::run::RunOptions::default();
    assert_eq!(options.parallel_integration_bodies, 64);
    assert_eq!(options.parallel_narrow_phase_seconds, 1e-4);
    assert_eq!(options.parallel_trace_pairs, 64);
    assert_eq!(options.kept_boxes_bodies, crate::broad_phase::GRID_BROAD_PHASE_BOXES);
    #[cfg(feature = "rapier")]
    assert_eq!(crate::guard::PARALLEL_NARROW_PHASE_SECONDS, 3e-4);
    assert_eq!(scene.model().parameters, parameters);
}

#[test]
fn the_format_example_in_scenes_readme_loads() {
    let readme = std::fs::read_to_string(concat!(env!("CARGO_MANIFEST_DIR"), "/scenes/README.md")).unwrap();
    let start = readme.find("```ron\n").expect("a ron block") + "```ron\n".len();
    let end = start + readme[start..].find("```").unwrap();
    let scene = crate::scene::Scene::from_ron_str(&readme[start..end]).unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(scene.model().bodies.len(), 2);
}

#[cfg(feature = "rapier")]
#[test]
fn the_guards_documented_defaults_are_the_real_ones() {
    use crate::guard::{
        GuardOptions, BALL_EXCESS_OF_SKIN, DEFAULT_MAX_SUBSTEPS, DEFAULT_SKIN, DEFAULT_TOLERATED_DEPTH,
        HALF_SPACE_EXTENT, PUSHED_DEPTH_FRACTION, THIN_BODY_FRACTION,
    };
    // guard/mod.rs: skin "Default: `0`", the tolerated depth "`1.0`" (of
    // rapier's allowed linear error), max_substeps "`4`", a round shape's
    // polyhedron at most `0.25` of the skin outside it, a pair pushed back
    // to `0.5` of its tolerated depth, which is at most `0.5` of the
    // thinner body; a half-space a box `1e4` length units out; docs/guard.md:
    // the tolerated depth is 0.005 under rapier's default parameters.
    let options = GuardOptions::default();
    assert_eq!((options.skin, DEFAULT_SKIN), (0.0, 0.0));
    assert_eq!((options.tolerated_depth, DEFAULT_TOLERATED_DEPTH), (1.0, 1.0));
    assert_eq!((options.max_substeps, DEFAULT_MAX_SUBSTEPS), (4, 4));
    assert_eq!(BALL_EXCESS_OF_SKIN, 0.25);
    assert_eq!((PUSHED_DEPTH_FRACTION, THIN_BODY_FRACTION), (0.5, 0.5));
    assert_eq!(HALF_SPACE_EXTENT, 1e4);
    let parameters = rapier3d_f64::prelude::IntegrationParameters::default();
    assert_eq!(options.skin_under(&parameters), 0.0);
    assert_eq!(options.tolerated_depth_under(&parameters), 0.005);
    // scenes/README.md: "rapier's prediction distance (0.02)".
    assert_eq!(parameters.prediction_distance(), 0.02);
}

#[test]
fn ccd_statuses_are_written_by_their_documented_names() {
    use crate::ccd::CcdStatus;
    // summary.json's `status` (scenes/README.md, "Outputs"): the names are
    // the file format, fixed whatever the variants are called.
    let readme = std::fs::read_to_string(concat!(env!("CARGO_MANIFEST_DIR"), "/scenes/README.md")).unwrap();
    for status in [
        CcdStatus::Converged,
        CcdStatus::InitiallyTouching,
        CcdStatus::OutOfIterations,
        CcdStatus::NonFiniteInput,
    ] {
        assert!(
            readme.contains(&format!("`{}`", status.name())),
            "{status:?} is not documented as `{}`",
            status.name()
        );
    }
    let names: Vec<&str> = CcdStatus::ALL.iter().map(|s| s.name()).collect();
    assert_eq!(
        names,
        ["Separated", "Converged", "InitiallyTouching", "OutOfIterations", "Filtered", "NonFiniteInput"]
    );
}

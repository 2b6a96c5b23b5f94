//! `ccd::closest_approach` (issue 30 §1, §4): the bracket holds the
//! analytic closest approach of passes that miss by a known distance
//! (translating and rotating, at scales 1e-5 to 1e6), and against a dense
//! brute-force scan of tumbling pairs (every triangle pair, exact kernel):
//! no sample is below `lower`, and `upper` is the distance at `time`.

use nearmiss::ccd::{
    closest_approach, ApproachStatus, CcdOptions, ClosestApproachQuery, MeshCcdScratch, MovingMesh,
    DEFAULT_APPROACH_TOLERANCE,
};
use nearmiss::math::{Pose, Real, Vector};
use nearmiss::mesh::{
    box_mesh, icosphere, mesh_distance, mesh_distance_brute_force, torus, DistanceKernel, DistanceSearch,
    MeshDistanceScratch, TriMesh,
};
use nearmiss::motion::StepMotion;
use nearmiss::samples::Rng;

fn bracket(
    a: &TriMesh,
    motion_a: &StepMotion,
    b: &TriMesh,
    motion_b: &StepMotion,
    duration: Real,
    within: Real,
) -> nearmiss::ccd::ClosestApproach {
    let mut query = ClosestApproachQuery::new(
        MovingMesh { mesh: a, motion: motion_a },
        MovingMesh { mesh: b, motion: motion_b },
        duration,
    );
    query.within = within;
    closest_approach(&query, &mut MeshCcdScratch::default())
}

/// A cube passes a fixed cube, its face `gap` from the other's at the
/// closest (they overlap in x for a while): the closest approach is `gap`,
/// at every scale.
#[test]
fn a_translating_pass_is_bracketed_at_every_scale() {
    for scale in [1e-5, 1e-2, 1.0, 1e3, 1e6] {
        let cube = box_mesh(&(Vector::new(0.5, 0.5, 0.5) * scale)).unwrap();
        let gap = 0.25 * scale;
        let fixed = StepMotion::new(Pose::identity(), Vector::zeros(), Vector::zeros());
        let start = Pose::translation(-3.0 * scale, 1.0 * scale + gap, 0.2 * scale);
        let moving = StepMotion::new(start, Vector::new(3.0 * scale, 0.0, 0.0), Vector::zeros());
        let approach = bracket(&cube, &fixed, &cube, &moving, 2.0, Real::INFINITY);
        let width = 1e-6 * cube.radius();
        assert_eq!(approach.status, ApproachStatus::Bracketed, "scale {scale}");
        // (upper is a computed distance: to its rounding, 1e-12 of it.)
        assert!(
            approach.lower <= gap && gap <= approach.upper * (1.0 + 1e-12),
            "scale {scale}: {approach:?}"
        );
        assert!(approach.upper - approach.lower <= width, "scale {scale}: {approach:?}");
        // Reached while the faces overlap (|x| ≤ 1, t in [2/3, 4/3]), or
        // where an edge is within the width of the gap: δ ≤ sqrt(2 gap width)
        // beyond, at speed 3.
        let slack = (2.0 * gap * width).sqrt() / (3.0 * scale);
        assert!(
            (2.0 / 3.0 - slack..=4.0 / 3.0 + slack).contains(&approach.time),
            "scale {scale}: {approach:?}"
        );
        let closest = approach.closest.unwrap();
        assert!(((closest.point_b - closest.point_a).norm() - approach.upper).abs() <= 1e-12 * scale);
        // Only nearer than a given distance: the same pair is beyond 0.2.
        let beyond = bracket(&cube, &fixed, &cube, &moving, 2.0, 0.2 * scale);
        assert_eq!(beyond.status, ApproachStatus::Beyond, "scale {scale}");
        assert!(beyond.lower >= 0.2 * scale && beyond.lower <= gap && beyond.runs == 1, "{beyond:?}");
    }
}

/// A cube closing head-on on a fixed cube, stopping 0.5 short of it at the
/// interval's end (measured first: its hulls are the nearer) or starting
/// there and backing away (the start measured first): the closest
/// approach is 0.5 at the nearer end; two cubes at rest keep the start.
#[test]
fn the_nearer_end_is_the_closest_approach_of_a_steady_approach() {
    let cube = box_mesh(&Vector::new(0.5, 0.5, 0.5)).unwrap();
    let fixed = StepMotion::new(Pose::identity(), Vector::zeros(), Vector::zeros());
    for (start, velocity, end) in [(4.0, -2.5, 1.0), (1.5, 2.5, 0.0), (1.5, 0.0, 0.0)] {
        let moving = StepMotion::new(
            Pose::translation(start, 0.2, 0.1),
            Vector::new(velocity, 0.0, 0.0),
            Vector::zeros(),
        );
        let approach = bracket(&cube, &fixed, &cube, &moving, 1.0, Real::INFINITY);
        assert_eq!(approach.status, ApproachStatus::Bracketed, "{approach:?}");
        assert!(approach.lower <= 0.5 && (approach.upper - 0.5).abs() <= 1e-12, "{approach:?}");
        assert_eq!(approach.time, end, "{approach:?}");
    }
}

/// A small cube moves straight away from a torus's outside, or straight
/// at it, or up along its axis over its hole: the closest approach is at
/// the start or the end. Beside the outside, the torus's outermost vertex
/// `(R + r, 0, 0)` faces the cube's face, so the distance there is the
/// face's `x` less `R + r` (0.1), taken from the pair at the hulls' closest
/// vertices; over the hole the hull's flat top is far nearer than the tube,
/// and the distance is the brute force's at the start.
#[test]
fn the_ends_of_a_torus_and_a_cube_are_measured_beside_and_over_its_hole() {
    let ring = torus(1.0, 0.3, 24, 8).unwrap();
    let cube = box_mesh(&Vector::new(0.1, 0.1, 0.1)).unwrap();
    let fixed = StepMotion::new(Pose::identity(), Vector::zeros(), Vector::zeros());
    let over_the_hole = Pose::translation(0.0, 0.0, 0.3 + 0.5 + 0.1);
    let exact_over = mesh_distance_brute_force(&ring, &Pose::identity(), &cube, &over_the_hole);
    for (pose, velocity, distance, end) in [
        (Pose::translation(1.5, 0.0, 0.0), Vector::new(1.0, 0.0, 0.0), 0.1, 0.0),
        (Pose::translation(2.5, 0.0, 0.0), Vector::new(-1.0, 0.0, 0.0), 0.1, 1.0),
        (over_the_hole, Vector::new(0.0, 0.0, 1.0), exact_over, 0.0),
    ] {
        let moving = StepMotion::new(pose, velocity, Vector::zeros());
        let approach = bracket(&ring, &fixed, &cube, &moving, 1.0, Real::INFINITY);
        assert_eq!(approach.status, ApproachStatus::Bracketed, "{approach:?}");
        assert!(approach.lower <= distance + 1e-12 && distance <= approach.upper + 1e-12, "{approach:?}");
        assert!(
            approach.upper - approach.lower <= DEFAULT_APPROACH_TOLERANCE * cube.radius(),
            "{approach:?}"
        );
        assert_eq!(approach.time, end, "{approach:?}");
        // Whether anything touches, then the proof from the end's distance.
        assert_eq!(approach.runs, 2, "{approach:?}");
    }
}

/// The small cube slides past the torus's outside, its face 0.1 beyond
/// the outermost vertex `(R + r, 0, 0)` while it passes `y = 0`: the
/// closest approach is 0.1, reached while the face is level with that
/// vertex (the cube's centre within 0.1 of `y = 0`, from `t = 0.9` to
/// `1.1`), found by a descent from where the first proof stopped.
#[test]
fn a_cube_sliding_past_a_torus_is_bracketed_at_its_outermost_vertex() {
    let ring = torus(1.0, 0.3, 24, 8).unwrap();
    let cube = box_mesh(&Vector::new(0.1, 0.1, 0.1)).unwrap();
    let fixed = StepMotion::new(Pose::identity(), Vector::zeros(), Vector::zeros());
    let sliding =
        StepMotion::new(Pose::translation(1.5, -1.0, 0.0), Vector::new(0.0, 1.0, 0.0), Vector::zeros());
    let approach = bracket(&ring, &fixed, &cube, &sliding, 2.0, Real::INFINITY);
    assert_eq!(approach.status, ApproachStatus::Bracketed, "{approach:?}");
    assert!(approach.lower <= 0.1 + 1e-12 && 0.1 <= approach.upper + 1e-12, "{approach:?}");
    assert!(approach.upper - approach.lower <= DEFAULT_APPROACH_TOLERANCE * cube.radius(), "{approach:?}");
    assert!((0.9..=1.1).contains(&approach.time), "{approach:?}");
}

/// A cube passes over two fixed blocks in turn, 0.3 above the first and
/// 0.25 above the second (one mesh of two boxes): the run from the end's
/// distance stops at the first pass, the next (from where that one
/// stopped) at the second, and a third closes the bracket on 0.25.
#[test]
fn a_pass_over_two_blocks_is_bracketed_at_the_lower_one() {
    let (first, second) =
        (box_mesh(&Vector::new(0.5, 0.5, 0.5)).unwrap(), box_mesh(&Vector::new(0.5, 0.55, 0.5)).unwrap());
    let mut vertices = first.vertices().to_vec();
    vertices.extend(second.vertices().iter().map(|p| p + Vector::new(4.0, 0.0, 0.0)));
    let mut triangles = first.triangles().to_vec();
    triangles.extend(second.triangles().iter().map(|t| t.map(|k| k + 8)));
    let blocks = TriMesh::new(vertices, triangles).unwrap();
    let cube = box_mesh(&Vector::new(0.5, 0.5, 0.5)).unwrap();
    let fixed = StepMotion::new(Pose::identity(), Vector::zeros(), Vector::zeros());
    let moving =
        StepMotion::new(Pose::translation(-3.0, 1.3, 0.0), Vector::new(5.0, 0.0, 0.0), Vector::zeros());
    let approach = bracket(&blocks, &fixed, &cube, &moving, 2.0, Real::INFINITY);
    assert_eq!(approach.status, ApproachStatus::Bracketed, "{approach:?}");
    assert!(approach.lower <= 0.25 && 0.25 <= approach.upper * (1.0 + 1e-12), "{approach:?}");
    assert!(approach.upper - approach.lower <= 1e-6 * cube.radius(), "{approach:?}");
    // Over the second block: x from 3 to 5, t from 1.2 to 1.6.
    assert!((1.2..=1.6).contains(&approach.time), "{approach:?}");
    // Whether anything touches, then the two passes and the proof.
    assert_eq!(approach.runs, 4, "{approach:?}");
}

/// A bar spinning a whole turn about z next to a fixed block: its corner,
/// `sqrt(L² + w²)` from the axis, sweeps past the block's face at `x = f`,
/// so the closest approach is `f − sqrt(L² + w²)`, at the turn where the
/// corner points along +x.
#[test]
fn a_spinning_bar_is_bracketed_at_every_scale() {
    for scale in [1e-5, 1.0, 1e6] {
        let (length, width) = (1.0, 0.1);
        let bar = box_mesh(&(Vector::new(length, width, width) * scale)).unwrap();
        let block = box_mesh(&(Vector::new(0.5, 2.0, 2.0) * scale)).unwrap();
        let face = 1.1 * scale;
        let omega = 3.0;
        let spinning = StepMotion::new(Pose::identity(), Vector::zeros(), Vector::new(0.0, 0.0, omega));
        let fixed = StepMotion::new(
            Pose::translation(face + 0.5 * scale, 0.0, 0.0),
            Vector::zeros(),
            Vector::zeros(),
        );
        // Turning a little over half a turn from rest: each corner family
        // passes +x once.
        let duration = 1.2 * std::f64::consts::PI / omega;
        let approach = bracket(&bar, &spinning, &block, &fixed, duration, Real::INFINITY);
        let analytic = face - (length * length + width * width).sqrt() * scale;
        assert_eq!(approach.status, ApproachStatus::Bracketed, "scale {scale}");
        assert!(
            approach.lower <= analytic && analytic <= approach.upper * (1.0 + 1e-12),
            "scale {scale}: {analytic} {approach:?}"
        );
        assert!(approach.upper - approach.lower <= 1e-6 * bar.radius().min(block.radius()), "{approach:?}");
        // The corner at (L, −w) points along +x after turning atan(w / L);
        // near it the distance grows as r (1 − cos δθ), so within the
        // bracket's width the turn is known to sqrt(2 width / r).
        let turn = (width / length).atan();
        let r = (length * length + width * width).sqrt() * scale;
        let slack = 1.5 * (2.0 * 1e-6 * bar.radius() / r).sqrt() / omega;
        let time = approach.time;
        assert!((time - turn / omega).abs() <= slack, "time {time} vs {} ± {slack}", turn / omega);
    }
}

#[test]
fn meshes_that_touch_are_a_contact_at_their_first_contact() {
    // Head on: the faces meet at t = (3 - 1) / 3.
    let cube = box_mesh(&Vector::new(0.5, 0.5, 0.5)).unwrap();
    let fixed = StepMotion::new(Pose::identity(), Vector::zeros(), Vector::zeros());
    let moving =
        StepMotion::new(Pose::translation(-3.0, 0.3, 0.0), Vector::new(3.0, 0.0, 0.0), Vector::zeros());
    let approach = bracket(&cube, &fixed, &cube, &moving, 2.0, Real::INFINITY);
    assert_eq!(approach.status, ApproachStatus::Contact);
    assert_eq!(approach.lower, 0.0);
    let contact = 2.0 / 3.0;
    assert!(approach.time <= contact && contact - approach.time < 1e-6, "{approach:?}");
}

/// Tumbling pairs against a dense brute-force scan of the whole interval.
#[test]
fn no_sample_of_a_dense_scan_is_below_the_lower_bound() {
    let a = icosphere(0.6, 1).unwrap();
    let b = box_mesh(&Vector::new(0.7, 0.2, 0.4)).unwrap();
    let mut rng = Rng::new(47);
    let (mut bracketed, mut contacts) = (0, 0);
    for case in 0..24 {
        let motion_a = StepMotion::new(
            Pose::new(rng.in_unit_ball() * 0.3, rng.in_unit_ball() * 3.0),
            Vector::new(1.0, 0.0, 0.0) + rng.in_unit_ball() * 0.3,
            rng.in_unit_ball() * 6.0,
        );
        // b sits off the axis of a's travel, by 0.3 to 1.8: near misses of
        // various depths, some touching.
        let offset = Vector::new(1.0, rng.range(0.3, 1.8), 0.0);
        let motion_b = StepMotion::new(
            Pose::new(offset, rng.in_unit_ball() * 3.0),
            Vector::zeros(),
            rng.in_unit_ball() * 6.0,
        );
        let approach = bracket(&a, &motion_a, &b, &motion_b, 1.0, Real::INFINITY);
        let distance_at =
            |s: Real| mesh_distance_brute_force(&a, &motion_a.pose_at(s), &b, &motion_b.pose_at(s));
        let scan = (0..=1500).map(|k| k as Real / 1500.0);
        let lowest = scan.map(distance_at).fold(Real::INFINITY, Real::min);
        let rounding = 1e-12;
        assert!(lowest >= approach.lower - rounding, "case {case}: a sample at {lowest} below {approach:?}");
        match approach.status {
            ApproachStatus::Bracketed => {
                bracketed += 1;
                // upper is reached at the reported time, and no farther than
                // what the scan saw (it is the true minimum to the width).
                let there = distance_at(approach.time);
                assert!(
                    (there - approach.upper).abs() <= rounding,
                    "case {case}: {there} at the time vs {approach:?}"
                );
                assert!(
                    approach.upper <= lowest + 1e-6 * a.radius().min(b.radius()),
                    "case {case}: the scan found {lowest} < {approach:?}"
                );
                // upper is within the width of the true minimum, which is
                // at least lower: within the width of the scan's lowest too.
                assert!(approach.upper - approach.lower <= 1e-6 * a.radius().min(b.radius()));
            }
            ApproachStatus::Contact => {
                // Touching at the time of first contact, and never late:
                // before it, no sample within a quarter of the width (the
                // contract's guaranteed distance with no separation).
                contacts += 1;
                let width = 1e-6 * a.radius().min(b.radius());
                assert!(distance_at(approach.time) <= width + rounding, "case {case}: {approach:?}");
                // (Strictly before: none when touching from the start.)
                let before =
                    (0..1500).map(|k| approach.time * k as Real / 1500.0).filter(|&s| s < approach.time);
                let earliest = before.map(distance_at).fold(Real::INFINITY, Real::min);
                assert!(earliest >= 0.25 * width - rounding, "case {case}: {earliest} before {approach:?}");
            }
            other => panic!("case {case}: {other:?}"),
        }
    }
    assert!(bracketed >= 8 && contacts >= 3, "{bracketed} bracketed, {contacts} contacts");
}

/// Issue 30 §5: a unit box spinning at 1e6 rad/s about z, its corners
/// 0.707 from the axis, beside a wall whose face is 0.8 away: the corners
/// never reach it, and the run decides so at once (it stopped as undecided
/// at step 0).
#[test]
fn a_fast_spin_that_never_reaches_a_wall_is_decided() {
    let scene = nearmiss::scene::Scene::from_ron_str(
        r#"Scene(name: "spin", dt: 0.01, duration: 0.1, bodies: [
            (name: "wall", mesh: Box(half_extents: (0.1, 2.0, 2.0)), position: (0.9, 0.0, 0.0), fixed: true),
            (name: "box", mesh: Box(half_extents: (0.5, 0.5, 0.5)), angular_velocity: (0.0, 0.0, 1e6), kinematic: true),
        ])"#,
    )
    .unwrap();
    let result = nearmiss::run(&scene);
    assert_eq!(result.termination, nearmiss::run::Termination::Completed);
    assert!(result.contacts.is_empty());
    // The same spin with the wall's face at 0.7: a corner reaches it
    // (0.7 < 0.707), at the turn where x = r cos θ = 0.7 first.
    let scene = nearmiss::scene::Scene::from_ron_str(
        r#"Scene(name: "spin", dt: 0.01, duration: 0.1, bodies: [
            (name: "wall", mesh: Box(half_extents: (0.1, 2.0, 2.0)), position: (0.8, 0.0, 0.0), fixed: true),
            (name: "box", mesh: Box(half_extents: (0.5, 0.5, 0.5)), angular_velocity: (0.0, 0.0, 1e6), kinematic: true),
        ])"#,
    )
    .unwrap();
    let contact = nearmiss::run(&scene).first_contact.expect("a corner reaches the wall");
    let r = 0.5f64.hypot(0.5);
    let analytic = (std::f64::consts::FRAC_PI_4 - (0.7 / r).acos()) / 1e6;
    assert!(contact.time <= analytic && analytic - contact.time < 1e-9, "{} vs {analytic}", contact.time);
}

/// Issue 45 §3: a ball flying through a turning ring's hole (inside its
/// hull, so the BVH search advances step by step), 0.246 from the ring at
/// the closest. The proof run grazes the ring's 48 facets at the bracket's
/// width and takes about 2,500 advancement steps: with a budget of 20 a
/// run, it used to end `Undecided` (the budget grew only a hundredfold).
/// Now every run's budget grows until it reaches the steps that decide it,
/// and both budgets give the same bracket.
#[test]
fn a_ball_through_a_turning_ring_is_bracketed() {
    let ring = nearmiss::mesh::torus(1.0, 0.25, 48, 16).unwrap();
    let block = icosphere(0.2, 2).unwrap();
    let tumbling = StepMotion::new(Pose::identity(), Vector::zeros(), Vector::new(0.2, 0.1, 3.0));
    let fixed =
        StepMotion::new(Pose::translation(0.3, 0.0, -2.0), Vector::new(0.0, 0.0, 4.0), Vector::zeros());
    let query = |max_iterations: usize| {
        let mut q = ClosestApproachQuery::new(
            MovingMesh { mesh: &ring, motion: &tumbling },
            MovingMesh { mesh: &block, motion: &fixed },
            1.0,
        );
        q.options.max_iterations = max_iterations;
        closest_approach(&q, &mut MeshCcdScratch::default())
    };
    let full = query(CcdOptions::default().max_iterations);
    let short = query(20);
    assert_eq!(full.status, ApproachStatus::Bracketed, "{full:?}");
    assert_eq!(short.status, ApproachStatus::Bracketed, "{short:?}");
    assert!(short.lower <= full.upper && full.lower <= short.upper, "{short:?} vs {full:?}");
    // Against the exact distance sampled at 4,001 times (the static BVH
    // search, not the CCD's): no sample below `lower`, and `upper` (the
    // distance at `time`, checked by brute force) within the width of the
    // lowest sample or below it.
    let mut scratch = MeshDistanceScratch::default();
    let search = DistanceSearch::new(DistanceKernel::Exact, None);
    let distance_at = |s: Real, scratch: &mut MeshDistanceScratch| {
        mesh_distance(&ring, &tumbling.pose_at(s), &block, &fixed.pose_at(s), &search, scratch).distance
    };
    let lowest =
        (0..=4000).map(|k| distance_at(k as Real / 4000.0, &mut scratch)).fold(Real::INFINITY, Real::min);
    let (rounding, width) = (1e-12, DEFAULT_APPROACH_TOLERANCE * block.radius());
    for approach in [full, short] {
        assert!(lowest >= approach.lower - rounding, "a sample at {lowest} below {approach:?}");
        assert!(approach.upper <= lowest + width, "the scan found {lowest} < {approach:?}");
        let there = mesh_distance_brute_force(
            &ring,
            &tumbling.pose_at(approach.time),
            &block,
            &fixed.pose_at(approach.time),
        );
        assert!((there - approach.upper).abs() <= rounding, "{there} at the time vs {approach:?}");
    }
}

/// A comb of long thin strips in the plane `z = 0` (a gear ring's tooth
/// flanks, as slivers 6 long and 0.17 wide, two to a BVH leaf) and a small
/// cube passing over it diagonally with its bottom face `gap` above the
/// plane: wherever the cube is over a strip its face is parallel to it, so
/// the closest approach is `gap`. The node bounds here are those of long
/// leaves beside a small node (session 38): the bracket must still hold.
#[test]
fn a_small_cube_over_a_comb_of_slivers_is_bracketed() {
    let (mut vertices, mut triangles) = (Vec::new(), Vec::new());
    for k in -10..=10 {
        let y = 0.5 * k as Real;
        let first = vertices.len() as u32;
        for (x, dy) in [(-3.0, -0.085), (3.0, -0.085), (3.0, 0.085), (-3.0, 0.085)] {
            vertices.push(nearmiss::math::Point::new(x, y + dy, 0.0));
        }
        triangles.extend([[first, first + 1, first + 2], [first, first + 2, first + 3]]);
    }
    let comb = TriMesh::new(vertices, triangles).unwrap();
    let cube = box_mesh(&Vector::new(0.05, 0.05, 0.05)).unwrap();
    let fixed = StepMotion::new(Pose::identity(), Vector::zeros(), Vector::zeros());
    for gap in [1e-3, 0.1, 1.15] {
        let start = Pose::translation(-4.0, -3.0, gap + 0.05);
        let moving = StepMotion::new(start, Vector::new(4.0, 3.0, 0.0), Vector::zeros());
        let approach = bracket(&comb, &fixed, &cube, &moving, 2.0, Real::INFINITY);
        assert_eq!(approach.status, ApproachStatus::Bracketed, "gap {gap}: {approach:?}");
        assert!(approach.lower <= gap && gap <= approach.upper * (1.0 + 1e-12), "gap {gap}: {approach:?}");
        assert!(approach.upper - approach.lower <= 1e-6 * cube.radius(), "gap {gap}: {approach:?}");
    }
}

/// A ring gear of `teeth` teeth (bore 0.7, root radius 1, tip 1.2, 0.3
/// thick) about the z axis: an outline of four points a tooth, extruded,
/// its faces strips between the outline and the bore. Not convex, and a
/// triangle's neighbours reach only the next points of the outline: a
/// descent's walks over its triangles can stop on one tooth while another
/// comes closer.
fn ring_gear(teeth: usize) -> TriMesh {
    let (bore, root, tip, half) = (0.7, 1.0, 1.2, 0.15);
    let angles = (0..teeth).flat_map(|k| {
        [(0.0, root), (0.15, tip), (0.35, tip), (0.5, root)]
            .map(move |(f, r)| (std::f64::consts::TAU * (k as Real + f) / teeth as Real, r))
    });
    let mut vertices: Vec<nearmiss::math::Point> = Vec::new();
    // Outline below and above, then the bore below and above.
    for (radius_of, z) in [(true, -half), (true, half), (false, -half), (false, half)] {
        vertices.extend(angles.clone().map(|(angle, r)| {
            let r = if radius_of { r } else { bore };
            nearmiss::math::Point::new(r * angle.cos(), r * angle.sin(), z)
        }));
    }
    let n = 4 * teeth as u32;
    let (outer_low, outer_high, bore_low, bore_high) = (0, n, 2 * n, 3 * n);
    let mut triangles = Vec::new();
    let mut quad = |[p, q, r, s]: [u32; 4]| triangles.extend([[p, q, r], [p, r, s]]);
    for i in 0..n {
        let j = (i + 1) % n;
        quad([outer_low + i, outer_low + j, outer_high + j, outer_high + i]);
        quad([bore_high + i, bore_high + j, bore_low + j, bore_low + i]);
        quad([outer_high + i, outer_high + j, bore_high + j, bore_high + i]);
        quad([bore_low + i, bore_low + j, outer_low + j, outer_low + i]);
    }
    TriMesh::new(vertices, triangles).unwrap()
}

/// A small tumbling box passes the rim of a spinning ring gear: the
/// closest pair moves from tooth to tooth, where the descent's walks (a
/// pair's neighbours at a time) can lose it, and the descent's answer is
/// then its pair's distance, above the meshes' own. The bracket still
/// holds against a dense scan (the static BVH search at 4,001 times), the
/// reported points are `upper` apart at `time`, and the meshes' distance
/// there (by brute force) is within the width below `upper`.
#[test]
fn a_box_past_a_spinning_gear_is_bracketed() {
    let gear = ring_gear(48);
    let block = box_mesh(&Vector::new(0.05, 0.03, 0.04)).unwrap();
    let mut rng = Rng::new(53);
    let (rounding, width) = (1e-12, DEFAULT_APPROACH_TOLERANCE * block.radius());
    let mut scratch = MeshDistanceScratch::default();
    let search = DistanceSearch::new(DistanceKernel::Exact, None);
    let mut closer_runs = 0;
    for case in 0..8 {
        let spinning = StepMotion::new(
            Pose::new(Vector::zeros(), Vector::new(0.0, 0.0, rng.range(0.0, 6.0))),
            Vector::zeros(),
            Vector::new(0.0, 0.0, rng.range(8.0, 20.0)) + rng.in_unit_ball() * 0.3,
        );
        // Across the rim's far side, the box's centre 0.09 to 0.27 above
        // the tips' circle (its corners 0.07 from it).
        let height = 1.2 + 0.07 + rng.range(0.02, 0.2);
        let passing = StepMotion::new(
            Pose::new(Vector::new(-0.8, height, rng.range(-0.1, 0.1)), rng.in_unit_ball() * 3.0),
            Vector::new(1.6, 0.0, 0.0),
            rng.in_unit_ball() * 4.0,
        );
        let approach = bracket(&gear, &spinning, &block, &passing, 1.0, Real::INFINITY);
        // The scan by the static BVH search (not the CCD's), the reported
        // time by brute force.
        let scanned = |s: Real, scratch: &mut MeshDistanceScratch| {
            let (pose_gear, pose_block) = (spinning.pose_at(s), passing.pose_at(s));
            mesh_distance(&gear, &pose_gear, &block, &pose_block, &search, scratch).distance
        };
        let lowest =
            (0..=4000).map(|k| scanned(k as Real / 4000.0, &mut scratch)).fold(Real::INFINITY, Real::min);
        assert_eq!(approach.status, ApproachStatus::Bracketed, "case {case}: {approach:?}");
        closer_runs += approach.runs - 2;
        assert!(lowest >= approach.lower - rounding, "case {case}: a sample at {lowest} below {approach:?}");
        assert!(approach.upper <= lowest + width, "case {case}: the scan found {lowest} < {approach:?}");
        assert!(approach.upper - approach.lower <= width, "case {case}: {approach:?}");
        let closest = approach.closest.unwrap();
        let apart = (closest.point_b - closest.point_a).norm();
        assert!(
            (apart - approach.upper).abs() <= rounding,
            "case {case}: points {apart} apart, {approach:?}"
        );
        let there = mesh_distance_brute_force(
            &gear,
            &spinning.pose_at(approach.time),
            &block,
            &passing.pose_at(approach.time),
        );
        assert!(
            there <= approach.upper + rounding && there >= approach.upper - width,
            "case {case}: {there} at the time, {approach:?}"
        );
    }
    // Most passes go by several teeth, each a local minimum: the runs
    // after the first two each found a point closer than the last
    // descent's answer.
    assert!(closer_runs >= 16, "{closer_runs} runs after the first two");
}

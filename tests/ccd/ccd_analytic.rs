//! Linear-vertex CCD against analytic times of impact.
//!
//! For each case the exact first contact time `t*` is known in closed form;
//! the reported time must satisfy `t* - contact_distance / closing_speed ≤
//! t ≤ t*` (never late, early by at most the tolerance's worth).

use nearmiss::ccd::{
    edge_edge_time_of_impact, edge_edge_time_of_impact_detailed, vertex_face_time_of_impact,
    vertex_face_time_of_impact_detailed, CcdOptions, CcdStatus,
};
use nearmiss::math::{Point, Real};

fn p(x: Real, y: Real, z: Real) -> Point {
    Point::new(x, y, z)
}

fn assert_time(reported: Option<Real>, exact: Real, contact_distance: Real, closing_speed: Real) {
    let t = reported.expect("a contact was expected");
    assert!(t <= exact, "late: {t} > {exact}");
    assert!(t >= exact - contact_distance / closing_speed - 1e-15, "too early: {t} for {exact}");
}

#[test]
fn vertex_falling_onto_a_static_face() {
    let face = [p(0.0, 0.0, 0.0), p(1.0, 0.0, 0.0), p(0.0, 1.0, 0.0)];
    for (height, drop) in [(1.0, 2.0), (0.25, 1.0), (1e-3, 1.0), (0.9, 1.0)] {
        let r = vertex_face_time_of_impact_detailed(
            &p(0.3, 0.3, height),
            &face,
            &p(0.3, 0.3, height - drop),
            &face,
            &CcdOptions::default(),
        );
        assert_time(r.time_of_impact, height / drop, r.contact_distance, drop);
        assert_eq!(r.status, CcdStatus::Converged);
    }
}

#[test]
fn vertex_and_face_closing_on_each_other_while_the_face_deforms() {
    // The face rises by 1 and tilts about the x axis; the vertex, over
    // (0.2, 0.2), falls by 2 from z = 1.5. At time t the face's height at
    // y = 0.2 is t + 0.2·0.5·t and the vertex's 1.5 - 2t: they meet at
    // t = 1.5 / 3.1.
    let face_t0 = [p(0.0, 0.0, 0.0), p(1.0, 0.0, 0.0), p(0.0, 1.0, 0.0)];
    let face_t1 = [p(0.0, 0.0, 1.0), p(1.0, 0.0, 1.0), p(0.0, 1.0, 1.5)];
    let r = vertex_face_time_of_impact_detailed(
        &p(0.2, 0.2, 1.5),
        &face_t0,
        &p(0.2, 0.2, -0.5),
        &face_t1,
        &CcdOptions::default(),
    );
    assert_time(r.time_of_impact, 1.5 / 3.1, r.contact_distance, 2.0);
}

#[test]
fn vertex_passing_beside_the_face_does_not_touch() {
    let face = [p(0.0, 0.0, 0.0), p(1.0, 0.0, 0.0), p(0.0, 1.0, 0.0)];
    // Through the plane at (0.6, 0.6): outside the triangle (x + y > 1), by 0.2/√2.
    let t = vertex_face_time_of_impact(
        &p(0.6, 0.6, 1.0),
        &face,
        &p(0.6, 0.6, -1.0),
        &face,
        &CcdOptions::default(),
    );
    assert_eq!(t, None);
    // Sliding parallel to the face, 1e-3 above it.
    let t = vertex_face_time_of_impact(
        &p(-1.0, 0.2, 1e-3),
        &face,
        &p(2.0, 0.2, 1e-3),
        &face,
        &CcdOptions::default(),
    );
    assert_eq!(t, None);
}

#[test]
fn crossing_edges() {
    // eb moves down through ea from z = 1 at speed 4: contact at 0.25.
    let ea = [p(-1.0, 0.0, 0.0), p(1.0, 0.0, 0.0)];
    let eb_t0 = [p(0.3, -1.0, 1.0), p(0.3, 1.0, 1.0)];
    let eb_t1 = [p(0.3, -1.0, -3.0), p(0.3, 1.0, -3.0)];
    let r = edge_edge_time_of_impact_detailed(&ea, &eb_t0, &ea, &eb_t1, &CcdOptions::default());
    assert_time(r.time_of_impact, 0.25, r.contact_distance, 4.0);
}

#[test]
fn parallel_edges_approaching() {
    // Parallel, overlapping, 0.5 apart, closing at 1: contact at 0.5.
    let ea = [p(0.0, 0.0, 0.0), p(2.0, 0.0, 0.0)];
    let eb_t0 = [p(1.0, 0.5, 0.0), p(3.0, 0.5, 0.0)];
    let eb_t1 = [p(1.0, -0.5, 0.0), p(3.0, -0.5, 0.0)];
    let r = edge_edge_time_of_impact_detailed(&ea, &eb_t0, &ea, &eb_t1, &CcdOptions::default());
    assert_time(r.time_of_impact, 0.5, r.contact_distance, 1.0);
}

#[test]
fn rotating_edge_sweeps_into_a_vertex_of_the_other() {
    // eb's end point moves on a straight line from (1, 1, 0) to (1, -1, 0)
    // while its start stays at (2, 0, 1): the edge sweeps across the end of
    // ea (at (1, 0, 0)) when the moving end passes y = 0, at t = 0.5.
    let ea = [p(-1.0, 0.0, 0.0), p(1.0, 0.0, 0.0)];
    let eb_t0 = [p(2.0, 0.0, 1.0), p(1.0, 1.0, 0.0)];
    let eb_t1 = [p(2.0, 0.0, 1.0), p(1.0, -1.0, 0.0)];
    let r = edge_edge_time_of_impact_detailed(&ea, &eb_t0, &ea, &eb_t1, &CcdOptions::default());
    assert_time(r.time_of_impact, 0.5, r.contact_distance, 2.0);
}

#[test]
fn skew_edges_passing_apart() {
    let ea = [p(-1.0, 0.0, 0.0), p(1.0, 0.0, 0.0)];
    let eb_t0 = [p(-5.0, -1.0, 0.1), p(-5.0, 1.0, 0.1)];
    let eb_t1 = [p(5.0, -1.0, 0.1), p(5.0, 1.0, 0.1)];
    assert_eq!(edge_edge_time_of_impact(&ea, &eb_t0, &ea, &eb_t1, &CcdOptions::default()), None);
}

#[test]
fn initially_touching_and_minimum_separation() {
    let face = [p(0.0, 0.0, 0.0), p(1.0, 0.0, 0.0), p(0.0, 1.0, 0.0)];
    let r = vertex_face_time_of_impact_detailed(
        &p(0.2, 0.2, 0.0),
        &face,
        &p(0.2, 0.2, 1.0),
        &face,
        &CcdOptions::default(),
    );
    assert_eq!((r.time_of_impact, r.status), (Some(0.0), CcdStatus::InitiallyTouching));
    // With a separation of 0.5, a vertex falling from 1 at speed 2 "touches" at 0.25.
    let options = CcdOptions { minimum_separation: 0.5, ..CcdOptions::default() };
    let r =
        vertex_face_time_of_impact_detailed(&p(0.2, 0.2, 1.0), &face, &p(0.2, 0.2, -1.0), &face, &options);
    assert_time(r.time_of_impact, 0.25, r.contact_distance - 0.5, 2.0);
}

#[test]
fn documented_defaults_are_the_real_ones() {
    let o = CcdOptions::default();
    assert_eq!((o.distance_tolerance, o.minimum_separation, o.max_iterations), (1e-6, 0.0, 10_000));
}

#[test]
fn non_finite_input_is_reported_as_contact_at_zero_not_ignored() {
    let face = [p(0.0, 0.0, 0.0), p(1.0, 0.0, 0.0), p(0.0, 1.0, 0.0)];
    for bad in [Real::NAN, Real::INFINITY] {
        let r = vertex_face_time_of_impact_detailed(
            &p(0.2, bad, 1.0),
            &face,
            &p(0.2, 0.2, 2.0),
            &face,
            &CcdOptions::default(),
        );
        assert_eq!((r.time_of_impact, r.status), (Some(0.0), CcdStatus::NonFiniteInput));
        let edge = [p(0.0, 0.0, 0.0), p(1.0, 0.0, bad)];
        let r = edge_edge_time_of_impact_detailed(&edge, &edge, &edge, &edge, &CcdOptions::default());
        assert_eq!((r.time_of_impact, r.status), (Some(0.0), CcdStatus::NonFiniteInput));
    }
}

#[test]
fn a_tiny_query_far_from_the_origin_stays_conservative() {
    // A unit-1e-3 vertex-face query at 1e6 with a tolerance far below the
    // coordinates' rounding: the tolerance is floored, and the time is never late.
    use nearmiss::ccd::ROUNDING_FLOOR_ULPS;
    let o = 1e6;
    let face = [p(o, o, o), p(o + 1e-3, o, o), p(o, o + 1e-3, o)];
    let options = CcdOptions { distance_tolerance: 1e-15, ..CcdOptions::default() };
    let (top, bottom) = (o + 1e-3, o - 1e-3);
    let r = vertex_face_time_of_impact_detailed(
        &p(o + 2e-4, o + 2e-4, top),
        &face,
        &p(o + 2e-4, o + 2e-4, bottom),
        &face,
        &options,
    );
    assert!(r.contact_distance >= ROUNDING_FLOOR_ULPS * Real::EPSILON * top);
    // The rounded end heights differ from o by exact amounts (Sterbenz), so
    // the contact time is their ratio, to within one rounding of the division.
    let exact = (top - o) / (top - bottom);
    assert_time(r.time_of_impact.map(|t| t * (1.0 - Real::EPSILON)), exact, r.contact_distance, top - bottom);
}

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

/// Edge b (half-length `half`, crossing the x axis at height `h`) turned
/// about edge a's line (the x axis) by `angle`: each end point moves on a
/// straight chord, so b's line comes to `h |dir(t)|` of a's, with
/// `|dir(t)|² = 1 − 2t(1 − t)(1 − cos angle)` (b stays in the plane x = 0
/// and its foot from the axis is its centre). The closest points stay
/// inside both edges while the common normal turns with b: the turning
/// the fixed-axis steps cannot follow.
fn turning_edges(h: Real, half: Real, angle: Real) -> [[Point; 2]; 4] {
    let (s, c) = angle.sin_cos();
    let ea = [p(-1.0, 0.0, 0.0), p(1.0, 0.0, 0.0)];
    let eb_t0 = [p(0.0, -half, h), p(0.0, half, h)];
    let eb_t1 = [p(0.0, -half * c - h * s, -half * s + h * c), p(0.0, half * c - h * s, half * s + h * c)];
    [ea, eb_t0, ea, eb_t1]
}

#[test]
fn edges_turning_past_each_other_a_few_tolerances_apart_are_told_apart_in_a_few_steps() {
    // Apart by h cos(angle / 2) at t = 1/2, over twice the contact
    // distance: no contact. The steps along a fixed axis are limited by b's
    // ends swinging through it, about 1e-5 of the step each: they ran out
    // of their 10,000 iterations and reported a contact.
    let (h, angle) = (2e-5, 0.5);
    let [ea0, eb0, ea1, eb1] = turning_edges(h, 1.0, angle);
    let r = edge_edge_time_of_impact_detailed(&ea0, &eb0, &ea1, &eb1, &CcdOptions::default());
    assert!(r.contact_distance < 0.5 * h * (angle / 2.0).cos());
    assert_eq!((r.time_of_impact, r.status), (None, CcdStatus::Separated));
    assert!(r.iterations <= 20, "{} steps", r.iterations);
}

#[test]
fn edges_turning_into_contact() {
    // A minimum separation of 0.99 h is reached where |dir(t)|² = 0.99², on
    // the way down to cos²(angle / 2) at t = 1/2.
    let (h, angle) = (1e-3, 0.5);
    let [ea0, eb0, ea1, eb1] = turning_edges(h, 1.0, angle);
    let m = 0.99 * h;
    let options = CcdOptions { minimum_separation: m, ..CcdOptions::default() };
    let r = edge_edge_time_of_impact_detailed(&ea0, &eb0, &ea1, &eb1, &options);
    let k = (m / h).powi(2);
    let exact = (1.0 - (1.0 - 2.0 * (1.0 - k) / (1.0 - angle.cos())).sqrt()) / 2.0;
    let closing = h * (1.0 - 2.0 * exact) * (1.0 - angle.cos()) / k.sqrt();
    assert_time(r.time_of_impact, exact, r.contact_distance - m, closing);
    assert!(r.iterations <= 20, "{} steps", r.iterations);
}

/// A face turned by `angle` about the x axis, which lies in it; the vertex
/// stays at height `h` above the axis. The ends of the face's edges move on
/// chords: the face spans x and (0, α, β) with α = 1 − t(1 − cos angle),
/// β = t sin angle, and the vertex is `h α / |(α, β)|` from its plane.
fn turning_face(h: Real, angle: Real) -> (Point, [Point; 3], Point, [Point; 3]) {
    let (s, c) = angle.sin_cos();
    let face_t0 = [p(-1.0, -1.0, 0.0), p(1.0, -1.0, 0.0), p(0.0, 1.0, 0.0)];
    let face_t1 = face_t0.map(|f| p(f.x, f.y * c, f.y * s));
    (p(0.0, 0.0, h), face_t0, p(0.0, 0.0, h), face_t1)
}

#[test]
fn a_face_turning_under_a_vertex_touches_it_on_time() {
    // With q = sqrt(h² − m²), the distance reaches m at t = q / (q (1 − cos) + m sin).
    let (h, angle) = (1e-3, 0.4);
    let (v0, f0, v1, f1) = turning_face(h, angle);
    let m = 0.95 * h;
    let options = CcdOptions { minimum_separation: m, ..CcdOptions::default() };
    let r = vertex_face_time_of_impact_detailed(&v0, &f0, &v1, &f1, &options);
    let (s, c) = angle.sin_cos();
    let q = (h * h - m * m).sqrt();
    let exact = q / (q * (1.0 - c) + m * s);
    let (alpha, beta) = (1.0 - exact * (1.0 - c), exact * s);
    let closing = h * (beta / alpha.hypot(beta)) * s / (alpha * alpha + beta * beta);
    assert_time(r.time_of_impact, exact, r.contact_distance - m, closing);
    assert!(r.iterations <= 20, "{} steps", r.iterations);
    // Stopping short of m: no contact, decided in a few steps.
    let options = CcdOptions { minimum_separation: 0.9 * h * c, ..CcdOptions::default() };
    let r = vertex_face_time_of_impact_detailed(&v0, &f0, &v1, &f1, &options);
    assert_eq!((r.time_of_impact, r.status), (None, CcdStatus::Separated));
    assert!(r.iterations <= 20, "{} steps", r.iterations);
}

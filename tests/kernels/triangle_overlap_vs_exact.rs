//! Past contact for triangle pairs: `triangle_intersection` and
//! `triangle_penetration` against the exact rational reference, on the
//! classes of pairs that meet (crossing, coplanar overlapping, touching,
//! degenerate, far from the origin, and the tied pairs).
//!
//! The shared set is checked against `exact::triangle_intersection_polygon`
//! (one triangle clipped by the half-spaces of the other, in rationals: no
//! line, interval or projection shared with the kernel): the same kind
//! (point, segment, polygon), every computed point on both triangles, and
//! every exact vertex on the computed set, each to `SET_ULPS` ulps of the
//! pair's extent. The depth is checked against the exact depth to
//! `DEPTH_ULPS`, and independently of the Minkowski-facet argument: moving
//! `b` by a little more than the depth along the reported direction
//! separates the pair (the exact intersection test says so), a little less
//! does not, and along any sampled direction no shorter move separates it.
//! Every class is also run at the scales 1e-120 and 1e150.

use nearmiss::exact;
use nearmiss::kernels::{triangle_intersection, triangle_penetration, TriangleIntersection};
use nearmiss::math::{Point, Triangle, Vector};
use nearmiss::samples::{pair_extent, tied_pairs, triangle_pairs, InputClass, Rng};
use num_traits::Zero;

/// Tolerance on the shared set's points, in ulps of the pair's extent.
const SET_ULPS: f64 = 64.0;
/// Tolerance on the depth, in ulps of the pair's extent.
const DEPTH_ULPS: f64 = 16.0;
const PAIRS_PER_CLASS: usize = 400;

/// Pairs that meet, by class; each class checked alone so a failure names it.
fn meeting_pairs(class: &str, count: usize, seed: u64) -> Vec<(Triangle, Triangle)> {
    let mut rng = Rng::new(seed);
    let p = Point::new;
    // A random triangle in z = 0 exactly (its coordinates are f64 values,
    // so the plane holds without rounding).
    let flat = |rng: &mut Rng, cx: f64| -> Triangle {
        [0, 1, 2].map(|_| p(cx + rng.range(-0.5, 0.5), rng.range(-0.5, 0.5), 0.0))
    };
    match class {
        "crossing" => triangle_pairs(InputClass::Intersecting, count, seed),
        "crossing-offset-1e6" => triangle_pairs(InputClass::Intersecting, count, seed)
            .into_iter()
            .map(|(a, b)| {
                let shift = Vector::new(1e6, -1e6, 1e6);
                (a.map(|v| v + shift), b.map(|v| v + shift))
            })
            .collect(),
        "coplanar" => (0..count)
            .map(|_| {
                let a = flat(&mut rng, 0.0);
                let cx = rng.range(0.0, 0.6);
                (a, flat(&mut rng, cx))
            })
            .collect(),
        // b rests on a's plane by a vertex, an edge, or crosses it.
        "touching" => (0..count)
            .map(|_| {
                let a = flat(&mut rng, 0.0);
                let base = p(rng.range(-0.3, 0.3), rng.range(-0.3, 0.3), 0.0);
                let up = |rng: &mut Rng| p(rng.range(-0.8, 0.8), rng.range(-0.8, 0.8), rng.range(0.1, 1.0));
                let b = match rng.index(3) {
                    0 => [base, up(&mut rng), up(&mut rng)],
                    1 => [base, p(rng.range(-0.3, 0.3), rng.range(-0.3, 0.3), 0.0), up(&mut rng)],
                    _ => [base, up(&mut rng), p(rng.range(-0.8, 0.8), rng.range(-0.8, 0.8), -0.5)],
                };
                (a, b)
            })
            .collect(),
        // Segments and points: through a triangle, in its plane, or on it.
        "degenerate" => (0..count)
            .map(|_| {
                let a = flat(&mut rng, 0.0);
                let q = p(rng.range(-0.3, 0.3), rng.range(-0.3, 0.3), 0.0);
                let b = match rng.index(4) {
                    0 => [q, q, q],
                    1 => {
                        let d = Vector::new(rng.range(-1.0, 1.0), rng.range(-1.0, 1.0), rng.range(0.2, 1.0));
                        [q - d, q + d, q + d]
                    }
                    2 => [q, p(rng.range(-1.0, 1.0), rng.range(-1.0, 1.0), 0.0), q],
                    _ => {
                        let d = Vector::new(rng.range(-1.0, 1.0), rng.range(-1.0, 1.0), 0.0);
                        [q - d, q, q + d * 0.5]
                    }
                };
                if rng.uniform() < 0.5 {
                    (b, a)
                } else {
                    (a, b)
                }
            })
            .collect(),
        "tied" => tied_pairs()
            .into_iter()
            .filter(|(a, b)| exact::triangle_distance_squared(a, b).is_zero())
            .collect(),
        _ => unreachable!("unknown class {class}"),
    }
}

/// The dimension of the exact shared set: 0 a point, 1 a segment, 2 an area.
fn exact_dimension(polygon: &[exact::RationalVector]) -> usize {
    let first = &polygon[0];
    let Some(second) = polygon.iter().find(|v| !v.sub(first).is_zero()) else {
        return 0;
    };
    let along = second.sub(first);
    if polygon.iter().all(|v| along.cross(&v.sub(first)).is_zero()) {
        1
    } else {
        2
    }
}

/// Twice the polygon's area over its longest span: how wide it is
/// (computed on the polygon scaled to unit span, so nothing overflows).
fn width(vertices: &[Point]) -> f64 {
    let v0 = vertices[0];
    let span = vertices.iter().map(|v| (v - v0).norm()).fold(0.0, f64::max);
    if span == 0.0 {
        return 0.0;
    }
    let unit = |v: &Point| (v - v0) / span;
    let area: Vector = (1..vertices.len().saturating_sub(1))
        .map(|i| unit(&vertices[i]).cross(&unit(&vertices[i + 1])))
        .sum();
    area.norm() * span
}

fn to_point(v: &exact::RationalVector) -> Point {
    Point::new(exact::to_f64(&v.x), exact::to_f64(&v.y), exact::to_f64(&v.z))
}

/// The distance from `x` to the set spanned by `points` (a point, a
/// segment or a convex polygon in order), by a fan of triangles.
fn distance_to_set(x: &Point, points: &[Point]) -> f64 {
    let fan: Vec<Triangle> = match points.len() {
        1 => vec![[points[0]; 3]],
        2 => vec![[points[0], points[1], points[1]]],
        n => (1..n - 1).map(|i| [points[0], points[i], points[i + 1]]).collect(),
    };
    fan.iter()
        .map(|t| exact::to_f64(&exact::point_triangle_distance_squared(x, t)).sqrt())
        .fold(f64::INFINITY, f64::min)
}

/// The class's pairs as generated, then a quarter of them scaled by 1e-120
/// and by 1e150 (new pairs: their coordinates rounded anew).
fn at_every_scale(class: &str, seed: u64) -> Vec<(Triangle, Triangle)> {
    let pairs = meeting_pairs(class, PAIRS_PER_CLASS, seed);
    let scaled = |k: f64| {
        let scale = move |t: &Triangle| t.map(|v| Point::from(v.coords * k));
        pairs.iter().take(PAIRS_PER_CLASS / 4).map(move |(a, b)| (scale(a), scale(b)))
    };
    let extreme: Vec<_> = scaled(1e-120).chain(scaled(1e150)).collect();
    pairs.iter().copied().chain(extreme).collect()
}

fn check_set(class: &str) {
    for (i, (a, b)) in at_every_scale(class, 11).iter().enumerate() {
        let computed = triangle_intersection(a, b);
        let tolerance = SET_ULPS * f64::EPSILON * pair_extent(a, b).max(a[0].coords.amax());
        let meet = exact::triangle_distance_squared(a, b).is_zero();
        assert_eq!(meet, computed != TriangleIntersection::Disjoint, "{class} pair {i}: {computed:?}");
        if !meet {
            continue;
        }
        // Clip by a non-degenerate triangle; both degenerate: the exact
        // set is checked through the points alone.
        let polygon =
            exact::triangle_intersection_polygon(a, b).or_else(|| exact::triangle_intersection_polygon(b, a));
        let points = computed.points();
        for x in points {
            for t in [a, b] {
                let off = exact::to_f64(&exact::point_triangle_distance_squared(x, t)).sqrt();
                assert!(
                    off <= tolerance,
                    "{class} pair {i}: {x:?} is {off:e} off a triangle\na = {a:?}\nb = {b:?}"
                );
            }
        }
        let Some(polygon) = polygon else { continue };
        assert!(!polygon.is_empty(), "{class} pair {i}: the exact clip is empty though the pair meets");
        let kind = match computed {
            TriangleIntersection::Point(_) => 0,
            TriangleIntersection::Segment(_) => 1,
            TriangleIntersection::Polygon(_) => 2,
            TriangleIntersection::Disjoint => unreachable!(),
        };
        // A point may come out as a segment of rounding length (crossings
        // computed at a vertex), a polygon of rounding width as a segment
        // (its crossings rounded together); otherwise the kinds agree.
        let short = matches!(computed, TriangleIntersection::Segment([p, q]) if (p - q).norm() <= tolerance);
        let dimension = exact_dimension(&polygon);
        let vertices: Vec<Point> = polygon.iter().map(to_point).collect();
        let thin = kind == 1 && width(&vertices) <= tolerance;
        assert!(
            kind == dimension || (short && dimension == 0) || (thin && dimension == 2),
            "{class} pair {i}: {computed:?}, exact dimension {dimension} {vertices:?} width {:e} tolerance {tolerance:e}\na = {a:?}\nb = {b:?}", width(&vertices)
        );
        for v in polygon.iter().map(to_point) {
            let off = distance_to_set(&v, points);
            assert!(off <= tolerance, "{class} pair {i}: exact vertex {v:?} is {off:e} from {computed:?}");
        }
    }
}

/// Whether the triangles meet, by the kernel's exact test at any scale
/// (checked against the exact reference by `check_set`).
fn meet(a: &Triangle, b: &Triangle) -> bool {
    triangle_intersection(a, b) != TriangleIntersection::Disjoint
}

fn check_depth(class: &str) {
    let mut rng = Rng::new(5);
    for (i, (a, b)) in at_every_scale(class, 13).iter().enumerate() {
        let computed = triangle_penetration(a, b);
        let Some(expected) = exact::triangle_penetration_depth_squared(a, b) else {
            assert!(computed.is_none(), "{class} pair {i}: depth {computed:?} of a disjoint pair");
            continue;
        };
        let found = computed.unwrap_or_else(|| panic!("{class} pair {i}: no depth though the pair meets"));
        let expected = exact::to_f64(&expected).sqrt();
        let extent = pair_extent(a, b).max(a[0].coords.amax());
        let tolerance = DEPTH_ULPS * f64::EPSILON * extent;
        assert!(
            (found.depth - expected).abs() <= tolerance,
            "{class} pair {i}: depth {:e}, exact {expected:e}\na = {a:?}\nb = {b:?}",
            found.depth
        );
        assert!((found.direction.norm() - 1.0).abs() < 1e-12, "{class} pair {i}: direction not unit");
        // Independent of the facet argument: the exact intersection test.
        let moved = |t: f64, direction: &Vector| b.map(|v| v + direction * t);
        let margin = 1e-9 * extent;
        assert!(
            !meet(a, &moved(found.depth + margin, &found.direction)),
            "{class} pair {i}: moving b by the depth does not separate it"
        );
        if found.depth > 2.0 * margin {
            assert!(
                meet(a, &moved(found.depth - margin, &found.direction)),
                "{class} pair {i}: a shorter move already separates"
            );
        }
        // No sampled direction separates with a shorter move.
        for _ in 0..8 {
            let direction = rng.unit_vector();
            let shorter = (found.depth - margin).max(0.0);
            if shorter > 0.0 {
                assert!(
                    meet(a, &moved(shorter, &direction)),
                    "{class} pair {i}: {direction:?} separates by {shorter:e} < depth {:e}",
                    found.depth
                );
            }
        }
    }
}

#[test]
fn crossing_pairs_share_a_segment() {
    check_set("crossing");
    check_depth("crossing");
}

#[test]
fn crossing_pairs_offset_by_1e6() {
    check_set("crossing-offset-1e6");
    check_depth("crossing-offset-1e6");
}

#[test]
fn coplanar_pairs_share_a_polygon_of_depth_0() {
    check_set("coplanar");
    check_depth("coplanar");
}

#[test]
fn touching_pairs() {
    check_set("touching");
    check_depth("touching");
}

#[test]
fn degenerate_pairs() {
    check_set("degenerate");
    check_depth("degenerate");
}

#[test]
fn tied_pairs_at_every_scale() {
    check_set("tied");
    check_depth("tied");
}

/// A worked case, by hand: a vertical triangle through a horizontal one.
#[test]
fn a_blade_through_a_plate() {
    let p = Point::new;
    let plate = [p(-1.0, -1.0, 0.0), p(3.0, -1.0, 0.0), p(-1.0, 3.0, 0.0)];
    // Apex 0.25 below the plate, its top edge 0.5 above it, in x = 0.
    let blade = [p(0.0, 0.0, -0.25), p(0.0, -0.5, 0.5), p(0.0, 0.5, 0.5)];
    let TriangleIntersection::Segment([s, e]) = triangle_intersection(&plate, &blade) else {
        panic!("expected a segment: {:?}", triangle_intersection(&plate, &blade));
    };
    // At z = 0 the blade spans y in [-1/6, 1/6] (a third of the way up).
    let (low, high) = if s.y < e.y { (s, e) } else { (e, s) };
    approx::assert_relative_eq!(low, p(0.0, -1.0 / 6.0, 0.0), epsilon = 1e-15);
    approx::assert_relative_eq!(high, p(0.0, 1.0 / 6.0, 0.0), epsilon = 1e-15);
    // Lifting the blade by 0.25 separates it; nothing shorter does.
    let depth = triangle_penetration(&plate, &blade).expect("they meet");
    approx::assert_relative_eq!(depth.depth, 0.25, epsilon = 1e-15);
    approx::assert_relative_eq!(depth.direction, Vector::z(), epsilon = 1e-15);
}

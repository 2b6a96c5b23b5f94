//! Exact triangle–triangle intersection test on the f64 inputs.
//!
//! Every decision is the sign of an orientation determinant evaluated exactly
//! by Shewchuk's adaptive predicates (`robust` crate), so the answer is right
//! for touching, coplanar and degenerate triangles, not just "usually". The
//! test rests on one fact: two closed convex sets in a plane or in space meet
//! iff the boundary of one meets the other. So triangles `A` and `B` meet iff
//! an edge of `A` meets `B` or an edge of `B` meets `A`, and a segment meets a
//! triangle iff it crosses its plane inside it, or (when coplanar) an
//! endpoint lies inside it or it meets one of its edges. Coplanar questions
//! are answered in the three coordinate projections: coplanar sets meet iff
//! their projections meet in all three (one of them is injective on the
//! plane, and meeting in 3-D implies meeting in every projection).
//!
//! The witness point returned with a "yes" is computed in floating point: it
//! lies on both triangles up to rounding.

use super::segment_segment::{point_on_segment, segment_segment};
use crate::math::{Point, Real, Triangle};
use robust::{orient2d, orient3d, Coord, Coord3D};

/// A common point of the two triangles (up to rounding), or `None` when they
/// are disjoint. Exact on the f64 inputs.
pub fn triangles_intersect(a: &Triangle, b: &Triangle) -> Option<Point> {
    // Early rejects: one triangle strictly on one side of the other's plane.
    let side_b = b.map(|v| orient(&a[0], &a[1], &a[2], &v));
    if strictly_one_side(&side_b) {
        return None;
    }
    let side_a = a.map(|v| orient(&b[0], &b[1], &b[2], &v));
    if strictly_one_side(&side_a) {
        return None;
    }
    edges_meet_triangle(a, &side_a, b).or_else(|| edges_meet_triangle(b, &side_b, a))
}

/// The first point where an edge of `edges` meets `triangle`; `sides` are
/// the orientations of the vertices of `edges` against `triangle`'s plane.
fn edges_meet_triangle(edges: &Triangle, sides: &[Real; 3], triangle: &Triangle) -> Option<Point> {
    (0..3).find_map(|i| {
        let j = (i + 1) % 3;
        segment_meets_triangle(&edges[i], &edges[j], sides[i], sides[j], triangle)
    })
}

/// Whether segment `[p, q]` meets `triangle`; `side_p`, `side_q` are the
/// exact orientations of `p` and `q` against the triangle's plane.
fn segment_meets_triangle(
    p: &Point,
    q: &Point,
    side_p: Real,
    side_q: Real,
    triangle: &Triangle,
) -> Option<Point> {
    if side_p * side_q > 0.0 {
        return None;
    }
    let [t0, t1, t2] = triangle;
    if side_p != 0.0 || side_q != 0.0 {
        // The segment crosses (or touches) the plane at one point, which is in
        // the triangle iff the line pq sees the three edges with no two
        // strictly opposite orientations.
        let around = [orient(p, q, t0, t1), orient(p, q, t1, t2), orient(p, q, t2, t0)];
        let nonnegative = around.iter().all(|&o| o >= 0.0);
        let nonpositive = around.iter().all(|&o| o <= 0.0);
        if !(nonnegative || nonpositive) {
            return None;
        }
        let crossing = side_p / (side_p - side_q);
        return Some(point_on_segment(p, q, crossing));
    }
    // Coplanar with the triangle's plane, or the triangle is degenerate.
    let degenerate = (0..3).all(|axis| orient_projected(t0, t1, t2, axis) == 0.0);
    if !degenerate {
        for x in [p, q] {
            if (0..3).all(|axis| point_in_triangle_2d(x, triangle, axis)) {
                return Some(*x);
            }
        }
    }
    (0..3).find_map(|i| segments_meet(p, q, &triangle[i], &triangle[(i + 1) % 3]))
}

/// Whether two segments meet in 3-D, with a witness point.
fn segments_meet(p: &Point, q: &Point, r: &Point, s: &Point) -> Option<Point> {
    if orient(p, q, r, s) != 0.0 || !(0..3).all(|axis| segments_meet_2d(p, q, r, s, axis)) {
        return None;
    }
    let closest = segment_segment(p, q, r, s);
    Some(point_on_segment(p, q, closest.s))
}

/// Exact sign-correct orientation of `d` against the plane `(a, b, c)`.
#[inline]
pub(super) fn orient(a: &Point, b: &Point, c: &Point, d: &Point) -> Real {
    let c3 = |p: &Point| Coord3D { x: p.x, y: p.y, z: p.z };
    orient3d(c3(a), c3(b), c3(c), c3(d))
}

fn strictly_one_side(sides: &[Real; 3]) -> bool {
    sides.iter().all(|&s| s > 0.0) || sides.iter().all(|&s| s < 0.0)
}

/// The point with coordinate `axis` dropped.
#[inline]
fn project(p: &Point, axis: usize) -> Coord<Real> {
    Coord { x: p[(axis + 1) % 3], y: p[(axis + 2) % 3] }
}

/// Exact 2-D orientation of `(a, b, c)` projected along `axis`.
#[inline]
pub(super) fn orient_projected(a: &Point, b: &Point, c: &Point, axis: usize) -> Real {
    orient2d(project(a, axis), project(b, axis), project(c, axis))
}

/// Whether `p`, projected along `axis`, lies in the projected (closed)
/// triangle; a projection that collapses to a segment is that segment.
fn point_in_triangle_2d(p: &Point, t: &Triangle, axis: usize) -> bool {
    let area = orient_projected(&t[0], &t[1], &t[2], axis);
    if area == 0.0 {
        return (0..3).any(|i| segments_meet_2d(p, p, &t[i], &t[(i + 1) % 3], axis));
    }
    (0..3).all(|i| orient_projected(&t[i], &t[(i + 1) % 3], p, axis) * area >= 0.0)
}

/// Whether closed segments `[p, q]` and `[r, s]`, projected along `axis`,
/// meet (the classic orientation test, collinear cases by bounding box).
fn segments_meet_2d(p: &Point, q: &Point, r: &Point, s: &Point, axis: usize) -> bool {
    let o1 = orient_projected(p, q, r, axis);
    let o2 = orient_projected(p, q, s, axis);
    let o3 = orient_projected(r, s, p, axis);
    let o4 = orient_projected(r, s, q, axis);
    if o1 * o2 < 0.0 && o3 * o4 < 0.0 {
        return true;
    }
    (o1 == 0.0 && within_box(r, p, q, axis))
        || (o2 == 0.0 && within_box(s, p, q, axis))
        || (o3 == 0.0 && within_box(p, r, s, axis))
        || (o4 == 0.0 && within_box(q, r, s, axis))
}

/// Whether the projection of `x` lies in the bounding box of the projections
/// of `a` and `b` (for `x` collinear with them: on the segment).
fn within_box(x: &Point, a: &Point, b: &Point, axis: usize) -> bool {
    [(axis + 1) % 3, (axis + 2) % 3].iter().all(|&k| a[k].min(b[k]) <= x[k] && x[k] <= a[k].max(b[k]))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn t(v: [[Real; 3]; 3]) -> Triangle {
        v.map(|[x, y, z]| Point::new(x, y, z))
    }

    #[test]
    fn crossing_triangles_meet() {
        let a = t([[0.0, 0.0, 0.0], [2.0, 0.0, 0.0], [0.0, 2.0, 0.0]]);
        let b = t([[0.5, 0.5, -1.0], [0.5, 0.5, 1.0], [3.0, 3.0, 0.0]]);
        let x = triangles_intersect(&a, &b).expect("they cross");
        assert!(x.z.abs() < 1e-15);
    }

    #[test]
    fn separated_by_a_hair_do_not_meet() {
        let a = t([[0.0, 0.0, 0.0], [2.0, 0.0, 0.0], [0.0, 2.0, 0.0]]);
        let b = t([[0.5, 0.5, 1e-300], [0.5, 0.6, 1.0], [3.0, 3.0, 1.0]]);
        assert_eq!(triangles_intersect(&a, &b), None);
    }

    #[test]
    fn coplanar_nested_triangles_meet() {
        let a = t([[0.0, 0.0, 0.0], [4.0, 0.0, 0.0], [0.0, 4.0, 0.0]]);
        let b = t([[0.5, 0.5, 0.0], [1.0, 0.5, 0.0], [0.5, 1.0, 0.0]]);
        assert!(triangles_intersect(&a, &b).is_some());
        assert!(triangles_intersect(&b, &a).is_some());
    }

    #[test]
    fn coplanar_disjoint_triangles_do_not_meet() {
        let a = t([[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]]);
        let b = t([[1.0, 1.0, 0.0], [2.0, 1.0, 0.0], [1.0, 2.0, 0.0]]);
        assert_eq!(triangles_intersect(&a, &b), None);
    }

    #[test]
    fn degenerate_triangles_as_crossing_segments() {
        let a = t([[-1.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 0.0, 0.0]]);
        let b = t([[0.0, -1.0, 0.0], [0.0, 1.0, 0.0], [0.0, 1.0, 0.0]]);
        assert!(triangles_intersect(&a, &b).is_some());
        let c = t([[0.0, -1.0, 1e-9], [0.0, 1.0, 1e-9], [0.0, 1.0, 1e-9]]);
        assert_eq!(triangles_intersect(&a, &c), None);
    }

    #[test]
    fn shared_vertex_touches() {
        let a = t([[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]]);
        let b = t([[1.0, 0.0, 0.0], [2.0, 0.0, 1.0], [2.0, 1.0, 1.0]]);
        assert_eq!(triangles_intersect(&a, &b), Some(Point::new(1.0, 0.0, 0.0)));
    }
}

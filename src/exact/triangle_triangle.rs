//! Exact squared distance between triangles (and the small queries it is
//! made of), on the exact values of the f64 inputs.
//!
//! For disjoint triangles the minimum is attained by a vertex and the other
//! triangle (its face interior, or an edge) or by two edges. Every
//! vertex–edge distance is computed once (18 of them) and shared by the
//! point–triangle and segment–segment minima. The triangles meet iff one of
//! those distances is 0 or an edge crosses the other's plane strictly
//! (endpoints on opposite sides) at a point inside the other triangle.

use super::point_segment::point_segment_squared;
use super::vector::{strictly_inside_unit, Rational, RationalVector};
use crate::math::{Point, Triangle};
use num_traits::{Signed, Zero};

/// Exact squared distance between triangles `a` and `b` (0 when they meet).
/// Degenerate triangles are the segments or points they span.
pub fn triangle_distance_squared(a: &Triangle, b: &Triangle) -> Rational {
    rational_triangle_distance_squared(
        &a.map(|v| RationalVector::from_point(&v)),
        &b.map(|v| RationalVector::from_point(&v)),
    )
}

/// [`triangle_distance_squared`] of triangles with rational vertices (for
/// example posed exactly: [`RationalVector::posed`]).
pub fn rational_triangle_distance_squared(a: &[RationalVector; 3], b: &[RationalVector; 3]) -> Rational {
    if edges_cross_interior(a, b) || edges_cross_interior(b, a) {
        return Rational::zero();
    }
    // vertex_edge[0][i][j]: vertex i of a to edge j of b; [1]: b's vertices to a's edges.
    let vertex_edge = [(a, b), (b, a)].map(|(from, to)| {
        from.each_ref().map(|v| edge_indices().map(|(j, k)| point_segment_squared(v, &to[j], &to[k])))
    });
    let mut best: Option<Rational> = None;
    let mut consider = |candidate: Rational| {
        if best.as_ref().is_none_or(|b| candidate < *b) {
            best = Some(candidate);
        }
    };
    for row in vertex_edge.iter().flatten().flatten() {
        consider(row.clone());
    }
    for (points, triangle) in [(a, b), (b, a)] {
        for p in points.iter() {
            if let Some(d) = face_interior_squared(p, triangle) {
                consider(d);
            }
        }
    }
    for (i, i1) in edge_indices() {
        for (j, j1) in edge_indices() {
            if let Some(d) = edge_interiors_squared(&a[i], &a[i1], &b[j], &b[j1]) {
                consider(d);
            }
        }
    }
    best.unwrap_or_else(Rational::zero)
}

/// Exact squared distance from `p` to `triangle`.
pub fn point_triangle_distance_squared(p: &Point, triangle: &Triangle) -> Rational {
    let p = RationalVector::from_point(p);
    let t = triangle.map(|v| RationalVector::from_point(&v));
    let edges = edge_indices().map(|(j, k)| point_segment_squared(&p, &t[j], &t[k]));
    let edge_min = edges.into_iter().min().unwrap_or_else(Rational::zero);
    match face_interior_squared(&p, &t) {
        Some(face) if face < edge_min => face,
        _ => edge_min,
    }
}

/// Exact squared distance between segments `[p0, p1]` and `[q0, q1]`.
pub fn segment_segment_distance_squared(p0: &Point, p1: &Point, q0: &Point, q1: &Point) -> Rational {
    let [p0, p1, q0, q1] = [p0, p1, q0, q1].map(RationalVector::from_point);
    let ends = [
        point_segment_squared(&p0, &q0, &q1),
        point_segment_squared(&p1, &q0, &q1),
        point_segment_squared(&q0, &p0, &p1),
        point_segment_squared(&q1, &p0, &p1),
    ];
    let end_min = ends.into_iter().min().unwrap_or_else(Rational::zero);
    match edge_interiors_squared(&p0, &p1, &q0, &q1) {
        Some(interior) if interior < end_min => interior,
        _ => end_min,
    }
}

fn edge_indices() -> [(usize, usize); 3] {
    [(0, 1), (1, 2), (2, 0)]
}

/// Squared distance from `p` to its projection on the triangle's plane, if
/// that projection is inside the closed triangle and the triangle has a face.
fn face_interior_squared(p: &RationalVector, t: &[RationalVector; 3]) -> Option<Rational> {
    let normal = t[1].sub(&t[0]).cross(&t[2].sub(&t[0]));
    if normal.is_zero() {
        return None;
    }
    let inside =
        edge_indices().iter().all(|&(j, k)| !t[k].sub(&t[j]).cross(&p.sub(&t[j])).dot(&normal).is_negative());
    if !inside {
        return None;
    }
    let height = normal.dot(&p.sub(&t[0]));
    Some(&height * &height / normal.norm_squared())
}

/// Squared distance between the closest points of two segments' lines, if
/// the lines are not parallel and both closest points are strictly inside
/// their segments.
fn edge_interiors_squared(
    p0: &RationalVector,
    p1: &RationalVector,
    q0: &RationalVector,
    q1: &RationalVector,
) -> Option<Rational> {
    let d1 = p1.sub(p0);
    let d2 = q1.sub(q0);
    let r = p0.sub(q0);
    let n = d1.cross(&d2);
    let n_squared = n.norm_squared();
    if n_squared.is_zero() {
        return None;
    }
    let s = n.dot(&d2.cross(&r)) / &n_squared;
    let t = n.dot(&d1.cross(&r)) / &n_squared;
    if !(strictly_inside_unit(&s) && strictly_inside_unit(&t)) {
        return None;
    }
    // The gap is along n: |n·r| / |n|.
    let along = n.dot(&r);
    Some(&along * &along / n_squared)
}

/// Whether an edge of `edges` has its endpoints strictly on opposite sides
/// of `triangle`'s plane and crosses it inside the triangle.
fn edges_cross_interior(edges: &[RationalVector; 3], triangle: &[RationalVector; 3]) -> bool {
    let normal = triangle[1].sub(&triangle[0]).cross(&triangle[2].sub(&triangle[0]));
    if normal.is_zero() {
        return false;
    }
    let side = edges.each_ref().map(|v| normal.dot(&v.sub(&triangle[0])));
    edge_indices().iter().any(|&(i, j)| {
        if !(&side[i] * &side[j]).is_negative() {
            return false;
        }
        let k = &side[i] / (&side[i] - &side[j]);
        let crossing = edges[i].add_scaled(&edges[j].sub(&edges[i]), &k);
        face_interior_squared(&crossing, triangle).is_some()
    })
}

/// Exact squared distance as the nearest f64 (for reports).
pub fn triangle_distance_f64(a: &Triangle, b: &Triangle) -> f64 {
    super::vector::to_f64(&triangle_distance_squared(a, b)).sqrt()
}

#[cfg(test)]
mod tests {
    use super::super::vector::rational;
    use super::*;

    fn t(v: [[f64; 3]; 3]) -> Triangle {
        v.map(|[x, y, z]| Point::new(x, y, z))
    }

    #[test]
    fn crossing_is_zero_and_separated_is_exact() {
        let a = t([[0.0, 0.0, 0.0], [2.0, 0.0, 0.0], [0.0, 2.0, 0.0]]);
        let crossing = t([[0.5, 0.5, -1.0], [0.5, 0.5, 1.0], [3.0, 3.0, 0.0]]);
        assert!(triangle_distance_squared(&a, &crossing).is_zero());
        let above = t([[0.5, 0.5, 0.25], [0.5, 0.5, 1.0], [3.0, 3.0, 1.0]]);
        assert_eq!(triangle_distance_squared(&a, &above), rational(0.0625));
    }

    /// Posed exactly, a triangle pair's distance is that of the pair placed
    /// by hand: a quarter turn about z (entries 0 and ±1, exact in f64) and
    /// a translation take `b` to where `skew_edges` has it.
    #[test]
    fn exactly_posed_triangles() {
        use crate::math::Vector;
        use nalgebra::Matrix3;
        let a = t([[-1.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, -1.0, -1.0]]);
        // (x, y, z) -> (-y, x, z) + (0, 0, 0.5) takes these to skew_edges' b.
        let b = t([[-1.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 0.0, 2.5]]);
        let quarter = Matrix3::new(0.0, -1.0, 0.0, 1.0, 0.0, 0.0, 0.0, 0.0, 1.0);
        let posed = b.map(|v| RationalVector::posed(&v, &quarter, &Vector::new(0.0, 0.0, 0.5)));
        let a = a.map(|v| RationalVector::from_point(&v));
        assert_eq!(rational_triangle_distance_squared(&a, &posed), rational(0.25));
        // A rotation whose entries are not exact: the posed coordinates are
        // the exact products and sums, not their rounding.
        let (c, s) = (0.6, 0.8);
        let turn = Matrix3::new(c, -s, 0.0, s, c, 0.0, 0.0, 0.0, 1.0);
        let p = RationalVector::posed(&Point::new(0.1, 0.3, 0.0), &turn, &Vector::zeros());
        assert_eq!(p.x, rational(c) * rational(0.1) - rational(s) * rational(0.3));
        assert_ne!(p.x, rational(c * 0.1 - s * 0.3));
    }

    #[test]
    fn skew_edges() {
        let a = t([[-1.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, -1.0, -1.0]]);
        let b = t([[0.0, -1.0, 0.5], [0.0, 1.0, 0.5], [0.0, 0.0, 3.0]]);
        assert_eq!(triangle_distance_squared(&a, &b), rational(0.25));
    }
}

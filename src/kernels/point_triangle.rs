//! Closest point on a triangle to a point.
//!
//! The closest point lies either in the interior of the face (the point's
//! orthogonal projection falls inside the triangle) or on one of the three
//! edges. [`point_face_interior`] answers the first case alone; that is all
//! `triangle_distance` needs, because any vertex–edge closest pair is also
//! found by one of its edge–edge queries. [`point_triangle`] composes it with
//! three point–segment queries for the full answer.
//!
//! The face normal and the three in-plane edge normals are precomputed once
//! per triangle in a [`FacePlane`] and reused for every query point.

use super::compensated;
use super::dispatch::multiversioned;
use super::feature::Feature;
use super::lanes::{F64x, Lane, V3};
use super::segment_segment::point_on_segment;
use crate::math::{Point, Real, Triangle};

/// A triangle's plane: the data shared by all point queries against it.
#[derive(Copy, Clone, Debug)]
pub struct FacePlane<L = Real> {
    /// The triangle's vertices.
    pub vertices: [V3<L>; 3],
    /// The (unnormalised) normal `(v1 - v0) × (v2 - v0)`, FMA-compensated.
    pub normal: V3<L>,
    /// `|normal|²`; zero for a degenerate (collinear) triangle.
    pub normal_squared: L,
    /// `1 / |normal|²` (infinite for a degenerate triangle, never used then).
    pub inverse_normal_squared: L,
    /// `normal × edge_i`: points into the triangle from edge `i`.
    pub edge_normals: [V3<L>; 3],
    /// `edge_normals[i] · v_i`: a point `p` is on the inner side of edge `i`
    /// when `edge_normals[i] · p ≥ edge_offsets[i]`.
    pub edge_offsets: [L; 3],
}

impl<L: Lane> FacePlane<L> {
    /// Precomputes the plane of the triangle `vertices`.
    #[inline(always)]
    pub fn new(vertices: &[V3<L>; 3]) -> FacePlane<L> {
        let [v0, v1, v2] = *vertices;
        let normal = compensated::cross(&(v1 - v0), &(v2 - v0));
        let normal_squared = normal.norm_squared();
        let edge_normals = [normal.cross(&(v1 - v0)), normal.cross(&(v2 - v1)), normal.cross(&(v0 - v2))];
        FacePlane {
            vertices: *vertices,
            normal,
            normal_squared,
            inverse_normal_squared: L::splat(1.0) / normal_squared,
            edge_normals,
            edge_offsets: [edge_normals[0].dot(&v0), edge_normals[1].dot(&v1), edge_normals[2].dot(&v2)],
        }
    }
}

/// The squared distance from `p` to the interior of the face, or `+∞` when
/// the projection of `p` falls outside the triangle or the triangle is
/// degenerate (no face); and the offset of `p` from its projection on the
/// plane (`p - projection`, along the normal).
#[inline(always)]
pub fn point_face_interior<L: Lane>(p: &V3<L>, face: &FacePlane<L>) -> (L, V3<L>) {
    let zero = L::splat(0.0);
    let height = face.normal.dot(&(*p - face.vertices[0]));
    let inside = face.edge_offsets[0].le(face.edge_normals[0].dot(p))
        & face.edge_offsets[1].le(face.edge_normals[1].dot(p))
        & face.edge_offsets[2].le(face.edge_normals[2].dot(p))
        & zero.lt(face.normal_squared);
    let ratio = height * face.inverse_normal_squared;
    (L::select(inside, height * ratio, L::splat(Real::INFINITY)), face.normal * ratio)
}

/// Closest point on a triangle to a point, with its feature.
#[derive(Copy, Clone, Debug, PartialEq)]
pub struct PointTriangle {
    /// The closest point on the triangle.
    pub point: Point,
    /// The feature it lies on.
    pub feature: Feature,
    /// The distance from the query point to it.
    pub distance: Real,
}

/// Closest point on `triangle` to `p`. Degenerate triangles (repeated or
/// collinear vertices) are handled as the union of their edges.
///
/// ```
/// use nearmiss::kernels::{point_triangle, Feature};
/// use nearmiss::math::Point;
/// let t = [Point::new(0.0, 0.0, 0.0), Point::new(2.0, 0.0, 0.0), Point::new(0.0, 2.0, 0.0)];
/// let c = point_triangle(&Point::new(0.5, 0.5, 3.0), &t);
/// assert_eq!((c.distance, c.feature, c.point), (3.0, Feature::Face, Point::new(0.5, 0.5, 0.0)));
/// let c = point_triangle(&Point::new(-1.0, -1.0, 0.0), &t);
/// assert_eq!(c.feature, Feature::Vertex(0));
/// ```
pub fn point_triangle(p: &Point, triangle: &Triangle) -> PointTriangle {
    let face = FacePlane::new(&triangle.each_ref().map(V3::from));
    let (face_squared, offset) = point_face_interior(&V3::from(p), &face);
    let projection = V3::from(p) - offset;
    let mut best =
        PointTriangle { point: projection.to_point(), feature: Feature::Face, distance: face_squared };
    for edge in 0..3u8 {
        let a = &triangle[edge as usize];
        let b = &triangle[(edge as usize + 1) % 3];
        let ab = b - a;
        let s = ((p - a).dot(&ab) / ab.norm_squared()).clamp_unit();
        let s = if ab.norm_squared() > 0.0 { s } else { 0.0 };
        let point = point_on_segment(a, b, s);
        let squared = (p - point).norm_squared();
        if squared < best.distance {
            best = PointTriangle { point, feature: Feature::on_edge(edge, s), distance: squared };
        }
    }
    best.distance = best.distance.sqrt();
    best
}

/// The squared distance from `p` to `triangle`, lane by lane: the face's
/// interior or the nearest edge, by the operations of [`point_triangle`]
/// (so the same value, rounding for rounding), without the point and
/// feature.
#[inline(always)]
fn point_triangle_squared<L: Lane>(p: &V3<L>, triangle: &[V3<L>; 3]) -> L {
    let (mut best, _) = point_face_interior(p, &FacePlane::new(triangle));
    for edge in 0..3 {
        let (a, b) = (triangle[edge], triangle[(edge + 1) % 3]);
        let ab = b - a;
        // A zero-length edge: 0 / 0, which the clamp maps to its start.
        let s = ((*p - a).dot(&ab) / ab.norm_squared()).clamp_unit();
        let point = V3::select(L::splat(1.0).le(s), b, a + ab * s);
        best = best.min((*p - point).norm_squared());
    }
    best
}

multiversioned! {
    /// The least distance from `p` to four triangles (repeat one to query
    /// fewer), in four vector lanes: the least of [`point_triangle`]'s
    /// distances, bit for bit.
    pub(crate) fn nearest_of_four / nearest_of_four_with(p: &Point, triangles: &[Triangle; 4]) -> Real {
        let lanes = |coordinate: fn(&Point) -> Real, corner: usize| {
            F64x(triangles.each_ref().map(|t| coordinate(&t[corner])))
        };
        let corner = |k: usize| V3::new(lanes(|q| q.x, k), lanes(|q| q.y, k), lanes(|q| q.z, k));
        let p = V3::new(F64x::splat(p.x), F64x::splat(p.y), F64x::splat(p.z));
        let squared = point_triangle_squared(&p, &[corner(0), corner(1), corner(2)]);
        squared.0.into_iter().fold(Real::INFINITY, Real::min).sqrt()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::exact;
    use crate::samples::Rng;

    #[test]
    fn the_closest_point_is_on_the_triangle_and_realises_the_distance() {
        // Against the exact reference: the point is on the triangle (exact
        // distance to it ~ 0) and as far from p as the exact distance.
        let mut rng = Rng::new(5);
        for _ in 0..2000 {
            let t = [0, 1, 2].map(|_| Point::from(rng.in_unit_ball()));
            let p = Point::from(rng.in_unit_ball() * 2.0);
            let c = point_triangle(&p, &t);
            let on = exact::to_f64(&exact::point_triangle_distance_squared(&c.point, &t)).sqrt();
            let expected = exact::to_f64(&exact::point_triangle_distance_squared(&p, &t)).sqrt();
            assert!(on <= 1e-15, "{c:?} is {on:e} off the triangle");
            assert!(((p - c.point).norm() - expected).abs() <= 1e-14, "{c:?} vs {expected:e}");
            assert!((c.distance - expected).abs() <= 1e-14);
        }
    }

    #[test]
    fn four_at_once_is_the_least_of_one_at_a_time() {
        // Random triangles, some with a repeated or a collinear corner
        // (zero area: their edges), and points near and far: the four-lane
        // distance is the least of the scalar kernel's, bit for bit, at
        // every instruction-set level.
        let mut rng = Rng::new(48);
        for case in 0..2000 {
            let triangles = [0, 1, 2, 3].map(|k| {
                let mut t = [0, 1, 2].map(|_| Point::from(rng.in_unit_ball()));
                match (case + k) % 7 {
                    0 => t[2] = t[0],
                    1 => t[2] = t[0] + (t[1] - t[0]) * 0.375,
                    2 => t = [t[0]; 3],
                    _ => {}
                }
                t
            });
            let p = Point::from(rng.in_unit_ball() * [0.1, 1.0, 10.0][case % 3]);
            let least =
                triangles.iter().map(|t| point_triangle(&p, t).distance).fold(Real::INFINITY, Real::min);
            for level in crate::kernels::SimdLevel::available() {
                assert_eq!(nearest_of_four_with(level, &p, &triangles), least, "case {case} at {level:?}");
            }
        }
    }
}

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
use super::feature::Feature;
use super::segment_segment::{clamp_unit, point_on_segment};
use crate::math::{Point, Real, Triangle, Vector};

/// A triangle's plane: the data shared by all point queries against it.
#[derive(Copy, Clone, Debug)]
pub struct FacePlane {
    /// Vertex 0.
    pub origin: Point,
    /// The (unnormalised) normal `(v1 - v0) × (v2 - v0)`, FMA-compensated.
    pub normal: Vector,
    /// `|normal|²`; zero for a degenerate (collinear) triangle.
    pub normal_squared: Real,
    /// The triangle's vertices.
    pub vertices: Triangle,
    /// `normal × edge_i`: points into the triangle from edge `i`.
    pub edge_normals: [Vector; 3],
}

impl FacePlane {
    /// Precomputes the plane of `triangle`.
    #[inline(always)]
    pub fn new(triangle: &Triangle) -> FacePlane {
        let [v0, v1, v2] = *triangle;
        let normal = compensated::cross(&(v1 - v0), &(v2 - v0));
        FacePlane {
            origin: v0,
            normal,
            normal_squared: normal.norm_squared(),
            vertices: *triangle,
            edge_normals: [normal.cross(&(v1 - v0)), normal.cross(&(v2 - v1)), normal.cross(&(v0 - v2))],
        }
    }
}

/// The squared distance from `p` to the interior of the face, or `+∞` when
/// the projection of `p` falls outside the triangle or the triangle is
/// degenerate (no face). Returns also the projection.
#[inline(always)]
pub fn point_face_interior(p: &Point, face: &FacePlane) -> (Real, Point) {
    let height = face.normal.dot(&(p - face.origin));
    let inside = (face.edge_normals[0].dot(&(p - face.vertices[0])) >= 0.0)
        & (face.edge_normals[1].dot(&(p - face.vertices[1])) >= 0.0)
        & (face.edge_normals[2].dot(&(p - face.vertices[2])) >= 0.0)
        & (face.normal_squared > 0.0);
    let distance_squared = height * (height / face.normal_squared);
    let projection = p - face.normal * (height / face.normal_squared);
    (if inside { distance_squared } else { Real::INFINITY }, projection)
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
/// assert_eq!((c.distance, c.feature), (3.0, Feature::Face));
/// let c = point_triangle(&Point::new(-1.0, -1.0, 0.0), &t);
/// assert_eq!(c.feature, Feature::Vertex(0));
/// ```
pub fn point_triangle(p: &Point, triangle: &Triangle) -> PointTriangle {
    let face = FacePlane::new(triangle);
    let (face_squared, projection) = point_face_interior(p, &face);
    let mut best = PointTriangle { point: projection, feature: Feature::Face, distance: face_squared };
    for edge in 0..3u8 {
        let a = &triangle[edge as usize];
        let b = &triangle[(edge as usize + 1) % 3];
        let ab = b - a;
        let s = clamp_unit((p - a).dot(&ab) / ab.norm_squared());
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

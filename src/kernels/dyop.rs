//! The seed paper's kernel: distance between nearly intersecting triangles by
//! the Dynamic Origin Point (DyOP) (Sulaiman et al., 2013, "Measuring Distance
//! between Nearly Intersected Objects in Narrow Phase Collision Detection").
//!
//! 1. **Where the DyOP sits** (the paper is informal; this is nearmiss's
//!    reading, kept fixed): per axis, the midpoint of the interval between
//!    the two axis-aligned bounding boxes, `(max(lo_a, lo_b) + min(hi_a, hi_b)) / 2`.
//!    Where the boxes are apart on that axis this is the middle of the gap;
//!    where they overlap it is the middle of the overlap.
//! 2. Of each triangle the two vertices nearest the DyOP are kept (ties go to
//!    the lower vertex index); they span one candidate edge per triangle.
//! 3. The answer is the minimum of the 4 vertex–vertex distances between kept
//!    vertices and the 4 perpendicular distances from each kept vertex to the
//!    other triangle's candidate edge, the latter only where the foot of the
//!    perpendicular falls inside the edge (otherwise it is a vertex–vertex
//!    distance, already counted). The perpendicular uses the chosen
//!    [`PointEdgeFormula`].
//!
//! **This kernel is an approximation.** It never looks at vertex–face or at
//! edge–edge interior pairs, nor at the third vertex, so it can over-estimate
//! the distance (a vertex over the middle of a face; crossing edges), and it
//! reports a positive distance for intersecting triangles. It never
//! under-estimates: every candidate is a distance between points of the two
//! triangles. It is therefore unsafe as the only proximity query of a CCD;
//! nearmiss uses [`super::triangle_distance`] there by default. Measured
//! errors are in `BENCHMARKS.md` and `tests/kernels/dyop_kernel.rs`.

use super::point_segment::{point_segment_distance, PointEdgeFormula};
use super::scale::{
    largest_magnitude, normalising_exponent, scale_by_power_of_two, scale_point, triangle_extent,
    MIN_RELATIVE_SIZE,
};
use crate::math::{Point, Real, Triangle};

/// The seed's DyOP distance between triangles `a` and `b` (an upper bound
/// on the true distance; see the module docs).
///
/// ```
/// use nearmiss::kernels::{dyop_distance, triangle_distance, PointEdgeFormula};
/// use nearmiss::math::Point;
/// // Vertex to vertex: DyOP is exact.
/// let a = [Point::new(0.0, 0.0, 0.0), Point::new(1.0, 0.0, 0.0), Point::new(0.0, 1.0, 0.0)];
/// let b = [Point::new(2.0, 0.0, 0.0), Point::new(3.0, 0.0, 0.0), Point::new(3.0, 1.0, 0.0)];
/// assert_eq!(dyop_distance(&a, &b, PointEdgeFormula::Heron), 1.0);
/// // A vertex over the middle of a face: DyOP over-estimates.
/// let c = [Point::new(0.2, 0.2, 0.1), Point::new(0.2, 0.2, 5.0), Point::new(0.3, 0.2, 5.0)];
/// assert!(dyop_distance(&a, &c, PointEdgeFormula::Vector) > triangle_distance(&a, &c).distance);
/// ```
pub fn dyop_distance(a: &Triangle, b: &Triangle, formula: PointEdgeFormula) -> Real {
    match normalising_exponent(largest_magnitude(a.iter().chain(b))) {
        None => dyop_distance_normalised(a, b, formula),
        // Any scale: computed at a power-of-two normalised one (exact).
        Some(exponent) => {
            let (a, b) = (a.map(|p| scale_point(&p, -exponent)), b.map(|p| scale_point(&p, -exponent)));
            scale_by_power_of_two(dyop_distance_normalised(&a, &b, formula), exponent)
        }
    }
}

/// [`dyop_distance`], or `None` where its accuracy is not stated: a
/// triangle's extent or the distance (unless zero) below
/// [`MIN_RELATIVE_SIZE`](super::MIN_RELATIVE_SIZE) of the largest
/// coordinate magnitude (any uniform scale is fine). A distance of 0 is
/// trusted only if the triangles truly meet (the exact intersection test of
/// [`triangle_distance`](super::triangle_distance)).
pub fn dyop_distance_checked(a: &Triangle, b: &Triangle, formula: PointEdgeFormula) -> Option<Real> {
    let distance = dyop_distance(a, b, formula);
    let limit = MIN_RELATIVE_SIZE * largest_magnitude(a.iter().chain(b));
    let fine_size = |size: Real| size == 0.0 || size >= limit;
    let fine_distance = if distance == 0.0 {
        let exact = super::triangle_distance(a, b);
        exact.distance == 0.0 && exact.within_range
    } else {
        distance >= limit
    };
    (fine_size(triangle_extent(a)) && fine_size(triangle_extent(b)) && fine_distance).then_some(distance)
}

/// [`dyop_distance`] on inputs in the kernels' safe range.
fn dyop_distance_normalised(a: &Triangle, b: &Triangle, formula: PointEdgeFormula) -> Real {
    let origin = dynamic_origin_point(a, b);
    let [a1, a2] = two_nearest(a, &origin);
    let [b1, b2] = two_nearest(b, &origin);
    let vertex_vertex = [(a1, b1), (a1, b2), (a2, b1), (a2, b2)]
        .iter()
        .map(|(p, q)| (p - q).norm())
        .fold(Real::INFINITY, Real::min);
    let vertex_edge = [(a1, b1, b2), (a2, b1, b2), (b1, a1, a2), (b2, a1, a2)]
        .iter()
        .map(|(p, e0, e1)| point_segment_distance(p, e0, e1, formula))
        .fold(Real::INFINITY, Real::min);
    vertex_vertex.min(vertex_edge)
}

/// The DyOP of two triangles: per axis the middle of the gap between their
/// bounding boxes, or of their overlap.
pub fn dynamic_origin_point(a: &Triangle, b: &Triangle) -> Point {
    let bounds = |t: &Triangle, axis: usize| {
        let lo = t[0][axis].min(t[1][axis]).min(t[2][axis]);
        let hi = t[0][axis].max(t[1][axis]).max(t[2][axis]);
        (lo, hi)
    };
    Point::from(nalgebra::Vector3::from_fn(|axis, _| {
        let (lo_a, hi_a) = bounds(a, axis);
        let (lo_b, hi_b) = bounds(b, axis);
        0.5 * (lo_a.max(lo_b) + hi_a.min(hi_b))
    }))
}

/// The two vertices of `t` nearest `origin` (in vertex order): the farthest
/// one is dropped, ties dropping the higher index.
fn two_nearest(t: &Triangle, origin: &Point) -> [Point; 2] {
    let d = t.map(|v| (v - origin).norm_squared());
    let farthest = if d[2] >= d[0] && d[2] >= d[1] {
        2
    } else if d[1] >= d[0] {
        1
    } else {
        0
    };
    match farthest {
        0 => [t[1], t[2]],
        1 => [t[0], t[2]],
        _ => [t[0], t[1]],
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn dyop_is_the_middle_of_the_gap_and_of_the_overlap() {
        let a = [Point::new(0.0, 0.0, 0.0), Point::new(1.0, 0.0, 0.0), Point::new(0.0, 1.0, 0.0)];
        let b = [Point::new(3.0, 0.5, 0.0), Point::new(4.0, 0.5, 0.0), Point::new(3.0, 2.0, 0.0)];
        // x: gap [1, 3] -> 2; y: overlap [0.5, 1] -> 0.75; z: both at 0.
        assert_eq!(dynamic_origin_point(&a, &b), Point::new(2.0, 0.75, 0.0));
    }
}

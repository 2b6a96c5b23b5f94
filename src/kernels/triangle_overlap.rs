//! Past contact for one triangle pair: the set two triangles share and the
//! shortest translation that separates them.
//!
//! **The shared set** ([`triangle_intersection`]). Whether the triangles
//! meet, and in which configuration, is decided exactly (the orientation
//! predicates of [`triangles_intersect`]); only the points are rounded.
//! - Triangles in different planes share a segment (or a point) of the line
//!   where the planes cross: each triangle cuts that line in an interval
//!   (its edges' crossings of the other plane, at the exact signs' ratio)
//!   and the shared segment is the overlap of the two intervals.
//! - Coplanar triangles share a convex polygon (at most six vertices): the
//!   one clipped by the better-conditioned one's edges, in the coordinate
//!   projection where that one is widest (Sutherland–Hodgman, every side
//!   decision exact). Whether the shared set has area is decided exactly
//!   (no edge line of either leaves the other wholly outside); a polygon
//!   whose clipped corners round together (narrower than rounding) comes
//!   out as the segment it is to rounding.
//! - Degenerate triangles are the segments (points) they span.
//!
//! **The penetration depth** ([`triangle_penetration`]): the length of the
//! shortest translation of `b` after which the two triangles only touch.
//! Translating `b` by `d` separates the pair iff `d` leaves the interior of
//! the Minkowski difference `K = A − B`, so the depth is the distance from
//! the origin to `K`'s boundary, attained at a facet. `K` is the convex hull
//! of nine points whose facet normals are among `A`'s normal, `B`'s normal
//! and the nine cross products of an edge of `A` with an edge of `B`; along
//! a unit direction `n`, `K` reaches `h(n) = max_i n·a_i − min_j n·b_j`, and
//! the depth is the least `h` over those 22 directions (each with its
//! opposite). Exact to rounding of the dot products; coplanar triangles
//! (whose `K` is flat) and touching ones have depth 0.

use super::scale::{largest_magnitude, normalising_exponent, scale_point};
use super::segment_segment::point_on_segment;
use super::triangle_intersection::{orient, orient_projected, triangles_intersect};
use crate::math::{Point, Real, Triangle, Vector};

/// The most vertices two coplanar triangles' common polygon can have.
pub(crate) const MAX_OVERLAP_VERTICES: usize = 6;

/// The set two closed triangles share.
#[derive(Copy, Clone, Debug, PartialEq)]
pub enum TriangleIntersection {
    /// They do not meet.
    Disjoint,
    /// They meet in one point (a vertex on the other's face, crossing
    /// edges, or segments crossing).
    Point(Point),
    /// They meet in a segment: triangles in different planes crossing or
    /// touching along a line, or coplanar ones sharing only an edge's part.
    Segment([Point; 2]),
    /// Coplanar triangles overlapping in a convex polygon of positive area.
    Polygon(OverlapPolygon),
}

/// A convex polygon of at most `MAX_OVERLAP_VERTICES` vertices, in order
/// around its boundary.
#[derive(Copy, Clone, Debug, PartialEq)]
pub struct OverlapPolygon {
    vertices: [Point; MAX_OVERLAP_VERTICES],
    len: usize,
}

impl OverlapPolygon {
    /// The vertices, in order around the boundary.
    pub fn vertices(&self) -> &[Point] {
        &self.vertices[..self.len]
    }
}

impl TriangleIntersection {
    /// The points that span the shared set: none, one, the segment's two
    /// ends or the polygon's vertices.
    pub fn points(&self) -> &[Point] {
        match self {
            TriangleIntersection::Disjoint => &[],
            TriangleIntersection::Point(p) => std::slice::from_ref(p),
            TriangleIntersection::Segment(ends) => ends,
            TriangleIntersection::Polygon(polygon) => polygon.vertices(),
        }
    }
}

/// The set triangles `a` and `b` share (see the module docs). Any scale:
/// inputs far from unit size are computed at a power-of-two normalised
/// one (exact), so the predicates neither overflow nor underflow.
pub fn triangle_intersection(a: &Triangle, b: &Triangle) -> TriangleIntersection {
    match normalising_exponent(largest_magnitude(a.iter().chain(b))) {
        None => intersection_normalised(a, b),
        Some(exponent) => {
            let down = |t: &Triangle| t.map(|p| scale_point(&p, -exponent));
            let up = |p: Point| scale_point(&p, exponent);
            match intersection_normalised(&down(a), &down(b)) {
                TriangleIntersection::Disjoint => TriangleIntersection::Disjoint,
                TriangleIntersection::Point(p) => TriangleIntersection::Point(up(p)),
                TriangleIntersection::Segment(ends) => TriangleIntersection::Segment(ends.map(up)),
                TriangleIntersection::Polygon(mut polygon) => {
                    polygon.vertices = polygon.vertices.map(up);
                    TriangleIntersection::Polygon(polygon)
                }
            }
        }
    }
}

/// [`triangle_intersection`] of inputs in the safe range.
fn intersection_normalised(a: &Triangle, b: &Triangle) -> TriangleIntersection {
    let Some(witness) = triangles_intersect(a, b) else {
        return TriangleIntersection::Disjoint;
    };
    match (is_degenerate(a), is_degenerate(b)) {
        (true, true) => spans_overlap(&span(a), &span(b), witness),
        (true, false) => triangle_meets(b, a, witness),
        _ => triangle_meets(a, b, witness),
    }
}

/// The shared set of non-degenerate `flat` and `other` (which meet).
fn triangle_meets(flat: &Triangle, other: &Triangle, witness: Point) -> TriangleIntersection {
    let sides = other.map(|v| orient(&flat[0], &flat[1], &flat[2], &v));
    if sides.iter().all(|&s| s == 0.0) {
        // Clip by the better-conditioned triangle: a sliver's plane and
        // edges are the less reliable (its projected areas are mostly
        // rounding).
        return if is_degenerate(other) || widest_projection(flat).1 >= widest_projection(other).1 {
            coplanar_overlap(flat, other, witness)
        } else {
            coplanar_overlap(other, flat, witness)
        };
    }
    let mut cut_other = [Point::origin(); 2];
    let cut_other = plane_cut(other, &sides, &mut cut_other);
    if is_degenerate(other) {
        // A segment not in the plane crosses it once.
        return TriangleIntersection::Point(cut_other.first().copied().unwrap_or(witness));
    }
    let flat_sides = flat.map(|v| orient(&other[0], &other[1], &other[2], &v));
    let mut cut_flat = [Point::origin(); 2];
    let cut_flat = plane_cut(flat, &flat_sides, &mut cut_flat);
    // Both cuts lie on the line where the planes cross; order them along it.
    let line = normal(flat).cross(&normal(other));
    let key = |p: &Point| (p - flat[0]).dot(&line);
    let (Some((low_f, high_f)), Some((low_o, high_o))) = (extremes(cut_flat, key), extremes(cut_other, key))
    else {
        return TriangleIntersection::Point(witness);
    };
    let start = if key(&low_f) >= key(&low_o) { low_f } else { low_o };
    let end = if key(&high_f) <= key(&high_o) { high_f } else { high_o };
    match key(&start).partial_cmp(&key(&end)) {
        Some(std::cmp::Ordering::Less) if start != end => TriangleIntersection::Segment([start, end]),
        Some(std::cmp::Ordering::Equal | std::cmp::Ordering::Less) => TriangleIntersection::Point(start),
        // The exact test says they meet; rounding put the ends out of order.
        _ => TriangleIntersection::Point(witness),
    }
}

/// Where `triangle` meets the plane its vertices' exact `sides` refer to:
/// its vertices on the plane and its edges' crossings (at most two points
/// when not every vertex is on the plane).
fn plane_cut<'a>(triangle: &Triangle, sides: &[Real; 3], out: &'a mut [Point; 2]) -> &'a [Point] {
    let mut len = 0;
    let mut push = |p: Point| {
        if len < 2 && !out[..len].contains(&p) {
            out[len] = p;
            len += 1;
        }
    };
    for i in 0..3 {
        let j = (i + 1) % 3;
        if sides[i] == 0.0 {
            push(triangle[i]);
        }
        if sides[i] * sides[j] < 0.0 {
            push(point_on_segment(&triangle[i], &triangle[j], sides[i] / (sides[i] - sides[j])));
        }
    }
    &out[..len]
}

/// The points of `points` with the least and the greatest `key`.
fn extremes(points: &[Point], key: impl Fn(&Point) -> Real) -> Option<(Point, Point)> {
    let first = *points.first()?;
    Some(points.iter().fold((first, first), |(low, high), p| {
        (if key(p) < key(&low) { *p } else { low }, if key(p) > key(&high) { *p } else { high })
    }))
}

/// Coplanar `flat` (non-degenerate) and `other`: `other` clipped by the
/// three edges of `flat` in the projection where `flat` is widest.
fn coplanar_overlap(flat: &Triangle, other: &Triangle, witness: Point) -> TriangleIntersection {
    let (axis, _) = widest_projection(flat);
    let orientation = orient_projected(&flat[0], &flat[1], &flat[2], axis).signum();
    if is_degenerate(other) {
        return segment_in_triangle(flat, &span(other), axis, orientation, witness);
    }
    let mut polygon = Clip { vertices: [Point::origin(); CLIP_CAPACITY], len: 3 };
    polygon.vertices[..3].copy_from_slice(other);
    for i in 0..3 {
        let (p, q) = (flat[i], flat[(i + 1) % 3]);
        polygon = polygon.keep_left(|x| orientation * orient_projected(&p, &q, x, axis));
    }
    polygon.dedup();
    match polygon.len {
        0 => TriangleIntersection::Point(witness),
        1 => TriangleIntersection::Point(polygon.vertices[0]),
        _ => {
            let v = &polygon.vertices[..polygon.len];
            // Area or not is decided exactly, not from the rounded points.
            if polygon.len == 2 || !interiors_overlap(flat, other, axis) {
                let far = v
                    .iter()
                    .copied()
                    .max_by(|p, q| (p - v[0]).norm_squared().total_cmp(&(q - v[0]).norm_squared()));
                let along = far.unwrap_or(v[0]) - v[0];
                match extremes(v, |p| (p - v[0]).dot(&along)) {
                    Some((start, end)) => TriangleIntersection::Segment([start, end]),
                    None => TriangleIntersection::Point(witness),
                }
            } else {
                let mut vertices = [Point::origin(); MAX_OVERLAP_VERTICES];
                let len = polygon.len.min(MAX_OVERLAP_VERTICES);
                vertices[..len].copy_from_slice(&v[..len]);
                TriangleIntersection::Polygon(OverlapPolygon { vertices, len })
            }
        }
    }
}

/// Whether coplanar non-degenerate triangles that meet share interior
/// points (a polygon of positive area), exactly: convex sets that meet
/// share only boundary points iff an edge line of one has the other
/// entirely on its outer side (or on the line), every sign exact.
fn interiors_overlap(flat: &Triangle, other: &Triangle, axis: usize) -> bool {
    let separates = |edges: &Triangle, points: &Triangle| {
        let orientation = orient_projected(&edges[0], &edges[1], &edges[2], axis).signum();
        (0..3).any(|i| {
            let (p, q) = (edges[i], edges[(i + 1) % 3]);
            points.iter().all(|x| orientation * orient_projected(&p, &q, x, axis) <= 0.0)
        })
    };
    !separates(flat, other) && !separates(other, flat)
}

/// The part of segment `s` (in `flat`'s plane) inside non-degenerate
/// `flat`: its parameter interval clipped by the three edges' half-planes
/// (every side's sign exact), as a segment or a point.
fn segment_in_triangle(
    flat: &Triangle,
    s: &[Point; 2],
    axis: usize,
    orientation: Real,
    witness: Point,
) -> TriangleIntersection {
    let (mut low, mut high): (Real, Real) = (0.0, 1.0);
    for i in 0..3 {
        let (p, q) = (flat[i], flat[(i + 1) % 3]);
        let side = |x: &Point| orientation * orient_projected(&p, &q, x, axis);
        let (s0, s1) = (side(&s[0]), side(&s[1]));
        match (s0 < 0.0, s1 < 0.0) {
            (true, true) => return TriangleIntersection::Point(witness),
            (true, false) => low = low.max(s0 / (s0 - s1)),
            (false, true) => high = high.min(s0 / (s0 - s1)),
            (false, false) => {}
        }
    }
    let at = |t: Real| point_on_segment(&s[0], &s[1], t);
    if s[0] == s[1] || low >= high {
        TriangleIntersection::Point(if low <= high { at(low) } else { witness })
    } else {
        TriangleIntersection::Segment([at(low), at(high)])
    }
}

/// Room for a triangle clipped by three half-planes (each adds at most one
/// vertex), with one spare.
const CLIP_CAPACITY: usize = MAX_OVERLAP_VERTICES + 1;

/// A polygon being clipped, in a fixed buffer.
struct Clip {
    vertices: [Point; CLIP_CAPACITY],
    len: usize,
}

impl Clip {
    /// The part where `side` is not negative (`side` exact in sign).
    fn keep_left(&self, side: impl Fn(&Point) -> Real) -> Clip {
        let mut out = Clip { vertices: [Point::origin(); CLIP_CAPACITY], len: 0 };
        let mut push = |p: Point| {
            if out.len < CLIP_CAPACITY {
                out.vertices[out.len] = p;
                out.len += 1;
            }
        };
        for i in 0..self.len {
            let (p, q) = (self.vertices[i], self.vertices[(i + 1) % self.len]);
            let (sp, sq) = (side(&p), side(&q));
            if sp >= 0.0 {
                push(p);
            }
            if sp * sq < 0.0 {
                push(point_on_segment(&p, &q, sp / (sp - sq)));
            }
        }
        out
    }

    /// Drops repeated consecutive vertices (the last against the first too).
    fn dedup(&mut self) {
        let mut len = 0;
        for i in 0..self.len {
            let p = self.vertices[i];
            if len == 0 || self.vertices[len - 1] != p {
                self.vertices[len] = p;
                len += 1;
            }
        }
        while len > 1 && self.vertices[len - 1] == self.vertices[0] {
            len -= 1;
        }
        self.len = len;
    }
}

/// Two degenerate triangles (segments or points) that meet.
fn spans_overlap(a: &[Point; 2], b: &[Point; 2], witness: Point) -> TriangleIntersection {
    let collinear = (0..3).all(|axis| {
        orient_projected(&a[0], &a[1], &b[0], axis) == 0.0
            && orient_projected(&a[0], &a[1], &b[1], axis) == 0.0
    });
    if a[0] == a[1] || b[0] == b[1] || !collinear {
        return TriangleIntersection::Point(witness);
    }
    let along = a[1] - a[0];
    let key = |p: &Point| (p - a[0]).dot(&along);
    let low = |s: &[Point; 2]| if key(&s[0]) <= key(&s[1]) { s[0] } else { s[1] };
    let high = |s: &[Point; 2]| if key(&s[0]) <= key(&s[1]) { s[1] } else { s[0] };
    let start = if key(&low(a)) >= key(&low(b)) { low(a) } else { low(b) };
    let end = if key(&high(a)) <= key(&high(b)) { high(a) } else { high(b) };
    if key(&start) < key(&end) {
        TriangleIntersection::Segment([start, end])
    } else {
        TriangleIntersection::Point(start)
    }
}

/// The coordinate axis along which the triangle's projection has the
/// largest area, and that (doubled) area: the normal's components, each
/// computed by the exact-sign 2-D predicate (accurate even for slivers,
/// whose cross product is mostly rounding).
fn widest_projection(t: &Triangle) -> (usize, Real) {
    (0..3)
        .map(|axis| (axis, orient_projected(&t[0], &t[1], &t[2], axis).abs()))
        .fold((2, -1.0), |best, candidate| if candidate.1 > best.1 { candidate } else { best })
}

/// Whether the triangle's vertices are collinear (exactly).
fn is_degenerate(t: &Triangle) -> bool {
    (0..3).all(|axis| orient_projected(&t[0], &t[1], &t[2], axis) == 0.0)
}

/// The two vertices farthest apart: the segment a degenerate triangle spans.
fn span(t: &Triangle) -> [Point; 2] {
    let edges = [(0, 1), (1, 2), (2, 0)];
    let (i, j) = edges
        .into_iter()
        .max_by(|&(i, j), &(k, l)| (t[i] - t[j]).norm_squared().total_cmp(&(t[k] - t[l]).norm_squared()))
        .unwrap_or((0, 1));
    [t[i], t[j]]
}

/// The (unnormalised) normal `(t1 − t0) × (t2 − t0)`.
pub(super) fn normal(t: &Triangle) -> Vector {
    (t[1] - t[0]).cross(&(t[2] - t[0]))
}

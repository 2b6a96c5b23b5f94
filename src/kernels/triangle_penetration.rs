//! The shortest move that separates two overlapping triangles.

use super::scale::{largest_magnitude, normalising_exponent, scale_by_power_of_two, scale_point};
use super::triangle_intersection::triangles_intersect;
use super::triangle_overlap::normal;
use crate::math::{Real, Triangle, Vector};

/// The shortest translation that separates two triangles.
#[derive(Copy, Clone, Debug, PartialEq)]
pub struct TrianglePenetration {
    /// Its length (0 when the triangles only touch, or are coplanar).
    pub depth: Real,
    /// Its unit direction: `b` moved by `depth * direction` (or `a` by the
    /// opposite) touches `a` without crossing it. When `depth` is 0, a
    /// direction in which any move separates them.
    pub direction: Vector,
}

/// The shortest translation that separates `a` and `b`, or `None` when they
/// do not meet (see the module docs). Any scale, as
/// [`triangle_intersection`](super::triangle_intersection).
pub fn triangle_penetration(a: &Triangle, b: &Triangle) -> Option<TrianglePenetration> {
    match normalising_exponent(largest_magnitude(a.iter().chain(b))) {
        None => penetration_normalised(a, b),
        Some(exponent) => {
            let down = |t: &Triangle| t.map(|p| scale_point(&p, -exponent));
            let found = penetration_normalised(&down(a), &down(b))?;
            Some(TrianglePenetration { depth: scale_by_power_of_two(found.depth, exponent), ..found })
        }
    }
}

/// [`triangle_penetration`] of inputs in the safe range.
pub(super) fn penetration_normalised(a: &Triangle, b: &Triangle) -> Option<TrianglePenetration> {
    triangles_intersect(a, b)?;
    // Relative to a0, so that far from the origin the dot products keep
    // the digits of the triangles' own size.
    let origin = a[0];
    let ra = a.map(|p| p - origin);
    let rb = b.map(|p| p - origin);
    let mut best: Option<TrianglePenetration> = None;
    let mut consider = |direction: Vector| {
        let length = direction.norm();
        if length == 0.0 || !length.is_finite() {
            return;
        }
        let n = direction / length;
        let (a_low, a_high) = dot_range(&ra, &n);
        let (b_low, b_high) = dot_range(&rb, &n);
        for (reach, along) in [(a_high - b_low, n), (b_high - a_low, -n)] {
            if best.is_none_or(|b| reach < b.depth) {
                best = Some(TrianglePenetration { depth: reach, direction: along });
            }
        }
    };
    consider(normal(a));
    consider(normal(b));
    for i in 0..3 {
        let edge_a = a[(i + 1) % 3] - a[i];
        for j in 0..3 {
            consider(edge_a.cross(&(b[(j + 1) % 3] - b[j])));
        }
    }
    Some(match best {
        Some(found) => TrianglePenetration { depth: found.depth.max(0.0), ..found },
        // Every candidate vanished: all six vertices on one line (or one
        // point), a flat difference; any perpendicular separates.
        None => TrianglePenetration { depth: 0.0, direction: perpendicular(&ra, &rb) },
    })
}

/// The least and greatest `n · p` over a triangle's vertices.
pub(super) fn dot_range(t: &[Vector; 3], n: &Vector) -> (Real, Real) {
    let d = t.map(|p| p.dot(n));
    (d[0].min(d[1]).min(d[2]), d[0].max(d[1]).max(d[2]))
}

/// A unit vector perpendicular to the line the points lie on.
pub(super) fn perpendicular(a: &[Vector; 3], b: &[Vector; 3]) -> Vector {
    let along = a.iter().chain(b).copied().max_by(|p, q| p.norm_squared().total_cmp(&q.norm_squared()));
    let along = along.unwrap_or_else(Vector::x);
    let axis = (0..3).min_by(|&i, &j| along[i].abs().total_cmp(&along[j].abs())).unwrap_or(0);
    let mut unit = Vector::zeros();
    unit[axis] = 1.0;
    along.cross(&unit).try_normalize(0.0).unwrap_or_else(Vector::z)
}

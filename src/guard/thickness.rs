//! A body's thickness, and the depth a pair is tolerated to (at most half
//! the thinner body).

use crate::math::Real;
use crate::mesh::TriMesh;

/// The most a pair may overlap, as a fraction of the thinner body's
/// thickness (a convex mesh's least width across its faces, another's
/// least box extent), whatever the tolerated depth: `0.5`. A point of one
/// body that deep into a plate is still on its near side.
pub(crate) const THIN_BODY_FRACTION: Real = 0.5;

/// The tolerated depth of the pair `(a, b)`: the guard's
/// (`tolerated_depth`), but at most [`THIN_BODY_FRACTION`] of the thinner
/// body (`thickness`, per body).
pub(crate) fn pair_tolerance(tolerated_depth: Real, thickness: &[Real], a: usize, b: usize) -> Real {
    tolerated_depth.min(THIN_BODY_FRACTION * thickness[a].min(thickness[b]))
}

/// A mesh's thickness, for the tolerated depth of its pairs: the least
/// width of a convex mesh over its faces' normals (the distance between a
/// face's plane and the farthest vertex behind it), the least extent of its
/// box for another.
pub(crate) fn thickness(mesh: &TriMesh) -> Real {
    let (low, high) = mesh.bounds();
    let extent = (high - low).min();
    if !mesh.is_convex() {
        return extent;
    }
    mesh.triangles()
        .iter()
        .filter_map(|t| {
            let [a, b, c] = t.map(|i| mesh.vertices()[i as usize]);
            let normal = (b - a).cross(&(c - a)).try_normalize(0.0)?;
            let behind = mesh.vertices()[mesh.farthest_vertex(&-normal)];
            Some((a - behind).dot(&normal).abs())
        })
        .fold(extent, Real::min)
}

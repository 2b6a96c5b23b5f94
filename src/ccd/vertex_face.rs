//! Continuous collision between a vertex and a triangle whose vertices all
//! move linearly over `t ∈ [0, 1]` (the triangle may deform).

use super::advance::{advance, LinearPair};
use super::options::{CcdOptions, CcdResult};
use super::swept_plane::SweptPlane;
use crate::kernels::point_triangle;
use crate::math::{Point, Real, Triangle};

/// The time of first contact of vertex `v` with triangle `f`, each vertex
/// moving linearly from its `_t0` to its `_t1` position over `t ∈ [0, 1]`.
///
/// `None` means no contact in `[0, 1]`, always correctly: the method only
/// ever steps over intervals it has proven separated. A reported time is
/// never later than the true first contact; it may be early by the time the
/// primitives take to close the contact distance of [`CcdOptions`].
///
/// ```
/// use nearmiss::ccd::{vertex_face_time_of_impact, CcdOptions};
/// use nearmiss::math::Point;
/// let face = [Point::new(0.0, 0.0, 0.0), Point::new(1.0, 0.0, 0.0), Point::new(0.0, 1.0, 0.0)];
/// // A vertex falling from z = 1 to z = -1 through the face: contact at t = 0.5.
/// let t = vertex_face_time_of_impact(
///     &Point::new(0.2, 0.2, 1.0), &face, &Point::new(0.2, 0.2, -1.0), &face, &CcdOptions::default());
/// let t = t.expect("it hits");
/// assert!(t <= 0.5 && t > 0.5 - 1e-5);
/// ```
pub fn vertex_face_time_of_impact(
    v_t0: &Point,
    f_t0: &Triangle,
    v_t1: &Point,
    f_t1: &Triangle,
    options: &CcdOptions,
) -> Option<Real> {
    vertex_face_time_of_impact_detailed(v_t0, f_t0, v_t1, f_t1, options).time_of_impact
}

/// [`vertex_face_time_of_impact`] with the status of the iteration and the
/// contact distance used.
pub fn vertex_face_time_of_impact_detailed(
    v_t0: &Point,
    f_t0: &Triangle,
    v_t1: &Point,
    f_t1: &Triangle,
    options: &CcdOptions,
) -> CcdResult {
    let pair = LinearPair { a_t0: *f_t0, a_t1: *f_t1, b_t0: [*v_t0], b_t1: [*v_t1] };
    // Fixed axes tried over the whole step first: the face normal at each end.
    let normal = |f: &Triangle| (f[1] - f[0]).cross(&(f[2] - f[0]));
    let axes = |p: &LinearPair<3, 1>| [normal(&p.a_t0), normal(&p.a_t1)];
    advance(&pair, options, axes, SweptPlane::of_vertex_face, |face, vertex| {
        let closest = point_triangle(&vertex[0], face);
        (closest.distance, closest.point, vertex[0])
    })
}

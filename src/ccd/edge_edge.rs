//! Continuous collision between two edges whose end points all move
//! linearly over `t ∈ [0, 1]`.

use super::advance::{advance, LinearPair};
use super::options::{CcdOptions, CcdResult};
use super::swept_plane::SweptPlane;
use crate::kernels::segment_segment;
use crate::math::{Point, Real};

/// The time of first contact of edges `ea` and `eb`, each end point moving
/// linearly from its `_t0` to its `_t1` position over `t ∈ [0, 1]`.
///
/// `None` means no contact in `[0, 1]`, always correctly; a reported time is
/// never later than the true first contact (see
/// [`vertex_face_time_of_impact`](super::vertex_face_time_of_impact)).
///
/// ```
/// use nearmiss::ccd::{edge_edge_time_of_impact, CcdOptions};
/// use nearmiss::math::Point;
/// let ea = [Point::new(-1.0, 0.0, 0.0), Point::new(1.0, 0.0, 0.0)];
/// // A crossing edge moving down from z = 1 to z = -3: contact at t = 0.25.
/// let eb_t0 = [Point::new(0.0, -1.0, 1.0), Point::new(0.0, 1.0, 1.0)];
/// let eb_t1 = [Point::new(0.0, -1.0, -3.0), Point::new(0.0, 1.0, -3.0)];
/// let t = edge_edge_time_of_impact(&ea, &eb_t0, &ea, &eb_t1, &CcdOptions::default()).expect("it hits");
/// assert!(t <= 0.25 && t > 0.25 - 1e-5);
/// ```
pub fn edge_edge_time_of_impact(
    ea_t0: &[Point; 2],
    eb_t0: &[Point; 2],
    ea_t1: &[Point; 2],
    eb_t1: &[Point; 2],
    options: &CcdOptions,
) -> Option<Real> {
    edge_edge_time_of_impact_detailed(ea_t0, eb_t0, ea_t1, eb_t1, options).time_of_impact
}

/// [`edge_edge_time_of_impact`] with the status of the iteration and the
/// contact distance used.
pub fn edge_edge_time_of_impact_detailed(
    ea_t0: &[Point; 2],
    eb_t0: &[Point; 2],
    ea_t1: &[Point; 2],
    eb_t1: &[Point; 2],
    options: &CcdOptions,
) -> CcdResult {
    let pair = LinearPair { a_t0: *ea_t0, a_t1: *ea_t1, b_t0: *eb_t0, b_t1: *eb_t1 };
    // Fixed axes tried over the whole step first: the edges' common normal at each end.
    let normal = |a: &[Point; 2], b: &[Point; 2]| (a[1] - a[0]).cross(&(b[1] - b[0]));
    let axes = |p: &LinearPair<2, 2>| [normal(&p.a_t0, &p.b_t0), normal(&p.a_t1, &p.b_t1)];
    advance(&pair, options, axes, SweptPlane::of_edges, |a, b| {
        let c = segment_segment(&a[0], &a[1], &b[0], &b[1]);
        let p = a[0] + (a[1] - a[0]) * c.s;
        let q = b[0] + (b[1] - b[0]) * c.t;
        (c.distance_squared.sqrt(), p, q)
    })
}

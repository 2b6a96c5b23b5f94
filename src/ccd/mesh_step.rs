//! The directional advancement step of a rigid mesh pair: how long no
//! triangle pair can come within `target`, using each pair's own
//! separating direction.
//!
//! The global bound `(d − target) / L` of `mesh_pair.rs` treats every
//! motion as head-on; a body sliding past another (a grazing pass) then
//! crawls in steps of `d / L`. Per triangle pair (both convex), the closest
//! direction `n` at the current time gives the support gap
//!
//! ```text
//! G = min_j n·b_j − max_i n·a_i   (= the pair's distance, up to rounding),
//! ```
//!
//! and along the fixed direction `n` a point moves no faster than
//! `|n·v| + |n × ω| r` (the component of `ω × r` along `n` is `r·(n × ω)`),
//! so the gap stays above `target` for
//!
//! ```text
//! (G − target) / (|n·(v_b − v_a)| + |n × ω_a| r_a + |n × ω_b| r_b),
//! ```
//!
//! with `r` the triangle's largest distance from its body's centre of mass.
//! A translation parallel to the surfaces has no component along `n`, and
//! a spin about `n` none across it: such pairs allow long steps. The
//! pair's global step `(d − target) / (|Δv| + |ω_a| r_a + |ω_b| r_b)`
//! backs it up (for tiny gaps rounding tilts `n`, and `G` is then taken
//! from the vertices, never from `d`). The mesh's step is the smallest over
//! all triangle pairs, found by branch and bound over the BVHs: a node pair
//! cannot limit the step below `(lower bound − target) / L_node`, with the
//! node's own radius about the centre of mass in `L_node`.

use nalgebra::UnitQuaternion;

use crate::kernels::triangle_distance;
use crate::math::{Pose, Real, Triangle, Vector};
use crate::mesh::distance::node_lower_bound;
use crate::mesh::TriMesh;

/// The relative motion of a mesh pair over a step (world frame).
#[derive(Copy, Clone, Debug)]
pub(crate) struct PairMotion {
    /// `v_b − v_a`.
    pub relative_velocity: Vector,
    /// `ω_a`.
    pub angular_velocity_a: Vector,
    /// `ω_b`.
    pub angular_velocity_b: Vector,
}

impl PairMotion {
    /// The largest closing speed of points within `ra` and `rb` of the centres.
    #[inline]
    fn speed(&self, ra: Real, rb: Real) -> Real {
        self.relative_velocity.norm()
            + self.angular_velocity_a.norm() * ra
            + self.angular_velocity_b.norm() * rb
    }
}

/// A time `≤ horizon` before which no triangle pair of `a` and `b` (posed
/// in `a`'s frame by `pos_ab`; `a` turned by `rotation_a` in the world) can
/// come within `target`, given that every pair is farther than `target` now.
/// The search gives up as soon as one triangle pair allows less than
/// `give_up_below`, and then returns 0 (no gain): the minimum over the pairs
/// visited so far would not be a safe step.
#[allow(clippy::too_many_arguments)]
pub(crate) fn directional_step(
    a: &TriMesh,
    b: &TriMesh,
    pos_ab: &Pose,
    rotation_a: &UnitQuaternion<Real>,
    motion: &PairMotion,
    target: Real,
    horizon: Real,
    give_up_below: Real,
    stack: &mut Vec<(u32, u32, Real)>,
) -> Real {
    let pos_ab = *pos_ab;
    let rotation = pos_ab.rotation.to_rotation_matrix().into_inner();
    let abs_rotation = rotation.abs();
    let nodes_a = a.bvh().nodes();
    let nodes_b = b.bvh().nodes();
    // The node's reach from its body's centre of mass (the mesh origin).
    let reach = |n: &crate::mesh::BvhNode| n.center.coords.norm() + n.radius;
    let node_step = |i: u32, j: u32| {
        let (na, nb) = (&nodes_a[i as usize], &nodes_b[j as usize]);
        let gap = node_lower_bound(na, nb, &pos_ab, &rotation, &abs_rotation) - target;
        let speed = motion.speed(reach(na), reach(nb));
        if gap <= 0.0 {
            0.0
        } else if speed > 0.0 {
            gap / speed
        } else {
            Real::INFINITY
        }
    };
    let mut best = horizon;
    stack.clear();
    stack.push((0, 0, node_step(0, 0)));
    while let Some((i, j, bound)) = stack.pop() {
        if bound >= best {
            continue;
        }
        let (na, nb) = (&nodes_a[i as usize], &nodes_b[j as usize]);
        if na.is_leaf() && nb.is_leaf() {
            for tb in nb.first..nb.first + nb.count {
                let local_b = b.triangle(tb as usize);
                let moved: Triangle = local_b.map(|p| pos_ab * p);
                let rb = local_b.iter().map(|p| p.coords.norm()).fold(0.0, Real::max);
                for ta in na.first..na.first + na.count {
                    let local_a = a.triangle(ta as usize);
                    let ra = local_a.iter().map(|p| p.coords.norm()).fold(0.0, Real::max);
                    best = best.min(pair_step(&local_a, ra, &moved, rb, rotation_a, motion, target));
                    if best < give_up_below {
                        // Pairs not yet visited may allow even less: the
                        // minimum so far is not a safe step. Report no gain.
                        return 0.0;
                    }
                }
            }
            continue;
        }
        let split_a = !na.is_leaf() && (nb.is_leaf() || na.radius >= nb.radius);
        let children =
            if split_a { [(na.first, j), (na.first + 1, j)] } else { [(i, nb.first), (i, nb.first + 1)] };
        let steps = children.map(|(ci, cj)| node_step(ci, cj));
        let order = if steps[0] <= steps[1] { [1, 0] } else { [0, 1] };
        for k in order {
            if steps[k] < best {
                stack.push((children[k].0, children[k].1, steps[k]));
            }
        }
    }
    best.max(0.0)
}

/// The step of one triangle pair (`b` already in `a`'s frame), the longer
/// of its directional and its global bound.
fn pair_step(
    ta: &Triangle,
    ra: Real,
    tb: &Triangle,
    rb: Real,
    rotation_a: &UnitQuaternion<Real>,
    motion: &PairMotion,
    target: Real,
) -> Real {
    let closest = triangle_distance(ta, tb);
    let d = closest.distance;
    let global_speed = motion.speed(ra, rb);
    let global = if global_speed > 0.0 { (d - target) / global_speed } else { Real::INFINITY };
    if d <= 0.0 {
        return global;
    }
    let n = (closest.point_b - closest.point_a) / d;
    // The support gap along n, from the vertices.
    let low_b = tb.iter().map(|p| n.dot(&p.coords)).fold(Real::INFINITY, Real::min);
    let high_a = ta.iter().map(|p| n.dot(&p.coords)).fold(Real::NEG_INFINITY, Real::max);
    let gap = low_b - high_a;
    if gap <= target {
        return global;
    }
    let n_world = rotation_a * n;
    let speed = n_world.dot(&motion.relative_velocity).abs()
        + n_world.cross(&motion.angular_velocity_a).norm() * ra
        + n_world.cross(&motion.angular_velocity_b).norm() * rb;
    let directional = if speed > 0.0 { (gap - target) / speed } else { Real::INFINITY };
    directional.max(global)
}

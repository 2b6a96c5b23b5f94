//! The distance of two convex meshes from GJK on their vertex hulls, where
//! GJK's bounds certify it: the triangles holding the closest points, and
//! the exact kernel's distance of that pair. For other meshes, the hulls'
//! gap certifies a pair around the hulls' closest vertices to a
//! tolerance ([`pair_at_hulls`]), or proves a pose farther than a
//! ceiling ([`measure_below`]) without a search.

use super::hull_gap::{convex_distance, first_within, hull_gap, ConvexDistance, HullGap, WarmSimplex};
use super::query::{MeshCcdScratch, MovingMesh};
use crate::math::{Pose, Real};
use crate::mesh::distance::mesh_distance_below;
use crate::mesh::distance::triangle_pair_distance;
use crate::mesh::{mesh_distance_relative, DistanceKernel, DistanceSearch, MeshDistance, TriMesh};
use crate::motion::StepMotion;

/// A descent's GJK probe is certified once its bounds agree to this many
/// ulps of the pair's scale (its centres' distance plus both radii): `64`.
pub(crate) const PROBE_CERTIFICATE_ULPS: Real = 64.0;

/// The exact distance between two convex meshes (`b` at `pos_ab` in `a`'s
/// frame), points in `a`'s frame: GJK on their hulls, certified to
/// [`PROBE_CERTIFICATE_ULPS`] ulps of the pair's scale, names the
/// triangles that hold the closest points, and the exact kernel's distance
/// of that pair, if it is within the certificate's slack of GJK's, is the
/// meshes' distance (no pair can be closer than GJK's lower bound). `None`
/// for other meshes, overlapping hulls, or where GJK does not certify (the
/// caller searches).
pub(crate) fn convex_measure(a: &TriMesh, b: &TriMesh, pos_ab: &Pose) -> Option<MeshDistance> {
    if !(a.is_convex() && b.is_convex()) {
        return None;
    }
    let slack = certificate_slack(a, b, pos_ab);
    let mut warm = WarmSimplex::default();
    let ConvexDistance::Certified(upper) = convex_distance(a, b, pos_ab, &mut warm, slack) else {
        return None;
    };
    let (i, j) = warm.triangles(a, b)?;
    let found = triangle_pair_distance(a, i, b, j, pos_ab);
    (found.distance <= upper + slack).then_some(found)
}

/// How closely GJK's bounds must agree to certify the distance of `a`
/// and `b` (at `pos_ab`): [`PROBE_CERTIFICATE_ULPS`] ulps of the pair's
/// scale, its centres' distance plus both radii.
pub(super) fn certificate_slack(a: &TriMesh, b: &TriMesh, pos_ab: &Pose) -> Real {
    let scale = pos_ab.translation.vector.norm() + a.radius() + b.radius();
    PROBE_CERTIFICATE_ULPS * Real::EPSILON * scale
}

/// The exact distance between the two meshes at time `s`, points in the
/// world frame: for two convex meshes by GJK on their hulls where it
/// certifies a triangle pair ([`convex_measure`]), otherwise by the
/// distance search over both BVHs.
pub(crate) fn measure(
    a: &MovingMesh<'_>,
    b: &MovingMesh<'_>,
    s: Real,
    hint: Option<(usize, usize)>,
    scratch: &mut MeshCcdScratch,
) -> MeshDistance {
    let relative = StepMotion::relative_pose(a.motion, b.motion, s);
    let found = convex_measure(a.mesh, b.mesh, &relative).unwrap_or_else(|| {
        let search = DistanceSearch::new(DistanceKernel::Exact, hint);
        mesh_distance_relative(a.mesh, b.mesh, &relative, &search, &mut scratch.distance)
    });
    in_world(a, s, found)
}

/// Where the vertex hulls of `a` and of `b` (at `pos_ab` in `a`'s frame)
/// are apart, by `gap` (GJK's lower bound, run to convergence, and the
/// hulls' closest vertices): the first triangle pair around those vertices
/// ([`first_within`]) whose distance is within `tolerance` of the gap. No
/// pair is closer than the gap, so that pair is within `tolerance` of the
/// meshes' distance, found among a few dozen triangle pairs where a search
/// measures hundreds to thousands: where the closest points lie on both
/// hulls (a small link beside another, a gear ring's outside). `None` where
/// the hulls touch or no pair there is that near (the closest points inside
/// a hull, in a concavity). Points in `a`'s frame.
///
/// (A walk from the nearest of those pairs to closer ones, tried on the
/// 120 tumbling pairs of `pybullet_data` meshes, certified none that the
/// pairs around the vertices had not, and cost 23 µs a failure.)
pub(crate) fn pair_at_hulls(
    a: &TriMesh,
    b: &TriMesh,
    pos_ab: &Pose,
    gap: &HullGap,
    tolerance: Real,
) -> Option<MeshDistance> {
    if gap.lower.is_nan() || gap.lower <= 0.0 {
        return None;
    }
    let (va, vb) = gap.support?;
    let enough = gap.lower + tolerance;
    let (distance, (i, j)) = first_within((a, va), (b, vb), pos_ab, gap.axis, enough).found?;
    (distance <= enough).then(|| triangle_pair_distance(a, i, b, j, pos_ab))
}

/// [`measure`] where the meshes are closer than `ceiling` at time `s`;
/// `None` where they are not. Where their hulls are at least `ceiling`
/// apart (GJK, a few support queries, or `hulls`, their gap at `s` where
/// the caller has it; the gap holds to the rounding of its dot products, a
/// few ulps of the pair's scale) nothing is searched; otherwise the search
/// starts with `ceiling` as its best, so a pose where the meshes are well
/// beyond it costs a few node pairs instead of a search down to the
/// closest triangles.
pub(crate) fn measure_below(
    a: &MovingMesh<'_>,
    b: &MovingMesh<'_>,
    (s, hulls): (Real, Option<&HullGap>),
    ceiling: Real,
    scratch: &mut MeshCcdScratch,
) -> Option<MeshDistance> {
    let relative = StepMotion::relative_pose(a.motion, b.motion, s);
    let found = match convex_measure(a.mesh, b.mesh, &relative) {
        Some(found) => (found.distance < ceiling).then_some(found)?,
        None => {
            let apart = match hulls {
                Some(gap) => gap.lower,
                None => hull_gap(a.mesh, b.mesh, &relative, None, (ceiling, ceiling)).lower,
            };
            if apart >= ceiling {
                // No pair is closer than the hulls.
                return None;
            }
            let search = DistanceSearch::new(DistanceKernel::Exact, None);
            mesh_distance_below(a.mesh, b.mesh, &relative, &search, ceiling, &mut scratch.distance)?
        }
    };
    Some(in_world(a, s, found))
}

/// `found` (points in `a`'s frame at time `s`) with its points in the world.
pub(crate) fn in_world(a: &MovingMesh<'_>, s: Real, mut found: MeshDistance) -> MeshDistance {
    let pose_a = a.motion.pose_at(s);
    found.point_a = pose_a * found.point_a;
    found.point_b = pose_a * found.point_b;
    found
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::math::Vector;
    use crate::mesh::{
        box_mesh, icosphere, mesh_distance_brute_force, mesh_distance_relative, torus, DistanceKernel,
        DistanceSearch, MeshDistanceScratch,
    };
    use crate::motion::StepMotion;
    use crate::samples::Rng;

    /// Poses of `b` about `a` (in `a`'s frame), turned at random, moved in
    /// along a random direction until `b` is `1e-6..1` (log-uniform) from
    /// `a`, with that exact distance (brute force): none where they overlap.
    fn poses_apart(a: &TriMesh, b: &TriMesh, rng: &mut Rng) -> Option<(Pose, Real)> {
        let rotation = Pose::new(Vector::zeros(), rng.in_unit_ball() * 3.0).rotation;
        let direction = rng.unit_vector();
        let mut pos_ab = Pose::from_parts((direction * (a.radius() + b.radius())).into(), rotation);
        let gap = mesh_distance_brute_force(a, &Pose::identity(), b, &pos_ab);
        pos_ab.translation.vector -= direction * (gap - Real::powf(10.0, -6.0 + 6.0 * rng.uniform()));
        let distance = mesh_distance_brute_force(a, &Pose::identity(), b, &pos_ab);
        (distance > 0.0).then_some((pos_ab, distance))
    }

    #[test]
    fn a_pair_at_the_hulls_is_within_its_tolerance_of_the_distance() {
        // A torus (not convex: its hull spans its hole) against a box and
        // an icosphere at random poses 1e-6..1 apart, both ways round:
        // wherever a pair is named, its distance is the brute force's to
        // the tolerance and never below it (to rounding). Beside the
        // torus's outside the closest points are on both hulls, and most
        // poses are certified.
        let ring = torus(1.0, 0.3, 24, 8).unwrap();
        let others = [box_mesh(&Vector::new(0.3, 0.2, 0.25)).unwrap(), icosphere(0.3, 1).unwrap()];
        let mut rng = Rng::new(53);
        let (mut named, mut tried) = (0, 0);
        for case in 0..300 {
            let other = &others[case % 2];
            let (a, b) = if case % 4 < 2 { (&ring, other) } else { (other, &ring) };
            let Some((pos_ab, exact)) = poses_apart(a, b, &mut rng) else { continue };
            tried += 1;
            let tolerance = 1e-7;
            let gap = hull_gap(a, b, &pos_ab, None, (0.0, Real::INFINITY));
            let Some(found) = pair_at_hulls(a, b, &pos_ab, &gap, tolerance) else { continue };
            named += 1;
            let rounding = 1e-14;
            assert!(
                found.distance >= exact - rounding && found.distance <= exact + tolerance,
                "case {case}: {} named, {exact} exact",
                found.distance
            );
        }
        assert!(tried > 250 && named > tried / 2, "{named} of {tried} named");
    }

    #[test]
    fn no_pair_is_named_over_the_hole_the_hull_spans() {
        // A small box on the torus's axis, 0.5 above its top: the hulls'
        // gap is 0.5 (the hull's flat top spans the hole), the meshes'
        // distance that from the box's bottom edges down to the tube's
        // inner side, far more (above 0.8). No pair around the hulls'
        // closest vertices is within the tolerance of the gap.
        let ring = torus(1.0, 0.3, 32, 16).unwrap();
        let cube = box_mesh(&Vector::new(0.1, 0.1, 0.1)).unwrap();
        let pos_ab = Pose::translation(0.0, 0.0, 0.3 + 0.5 + 0.1);
        let gap = hull_gap(&ring, &cube, &pos_ab, None, (0.0, Real::INFINITY));
        assert!((gap.lower - 0.5).abs() < 1e-9, "{gap:?}");
        let exact = mesh_distance_brute_force(&ring, &Pose::identity(), &cube, &pos_ab);
        assert!(exact > 0.8, "{exact}");
        assert_eq!(pair_at_hulls(&ring, &cube, &pos_ab, &gap, 1e-3), None);
    }

    #[test]
    fn measure_below_says_none_exactly_where_the_meshes_are_not_closer() {
        // The torus against a box and an icosphere at random poses: with a
        // ceiling a part in a million above or below the exact distance,
        // or half or twice it, the measure below it is `None` exactly
        // where the distance is at or above the ceiling (whether the hulls'
        // gap or the search says so), and otherwise the distance.
        let ring = torus(1.0, 0.3, 24, 8).unwrap();
        let others = [box_mesh(&Vector::new(0.3, 0.2, 0.25)).unwrap(), icosphere(0.3, 1).unwrap()];
        let mut rng = Rng::new(59);
        let mut scratch = MeshCcdScratch::default();
        let (mut above, mut below) = (0, 0);
        for case in 0..200 {
            let other = &others[case % 2];
            let (a, b) = if case % 4 < 2 { (&ring, other) } else { (other, &ring) };
            let Some((pos_ab, exact)) = poses_apart(a, b, &mut rng) else { continue };
            let (still, placed) = (StepMotion::fixed(Pose::identity()), StepMotion::fixed(pos_ab));
            let (a, b) = (MovingMesh { mesh: a, motion: &still }, MovingMesh { mesh: b, motion: &placed });
            for ceiling in [0.5, 1.0 - 1e-6, 1.0 + 1e-6, 2.0].map(|f| f * exact) {
                match measure_below(&a, &b, (0.0, None), ceiling, &mut scratch) {
                    None => {
                        above += 1;
                        assert!(exact >= ceiling, "case {case}: none below {ceiling}, {exact} exact");
                    }
                    Some(found) => {
                        below += 1;
                        assert!(exact < ceiling, "case {case}: {} below {ceiling}", found.distance);
                        assert!(
                            (found.distance - exact).abs() <= 1e-14,
                            "case {case}: {} vs {exact}",
                            found.distance
                        );
                    }
                }
            }
        }
        assert!(above > 300 && below > 300, "{above} none, {below} found");
    }

    #[test]
    fn the_convex_measure_is_the_searched_distance() {
        // Boxes and icospheres (up to 1,280 triangles) at random poses,
        // 1e-6 to 1 apart: where GJK certifies, the distance is the BVH
        // search's to a few ulps, and the triangles it names hold points
        // that far apart.
        let meshes = [
            box_mesh(&Vector::new(0.3, 0.2, 0.25)).unwrap(),
            icosphere(0.3, 1).unwrap(),
            icosphere(0.3, 3).unwrap(),
        ];
        let mut rng = Rng::new(29);
        let mut scratch = MeshDistanceScratch::default();
        let mut certified = 0;
        for case in 0..600 {
            let (a, b) = (&meshes[case % 3], &meshes[(case / 3) % 3]);
            let rotation = Pose::new(Vector::zeros(), rng.in_unit_ball() * 3.0).rotation;
            let direction = rng.unit_vector();
            // Placed along a direction, then moved until 1e-6..1 apart.
            let mut pos_ab = Pose::from_parts((direction * (a.radius() + b.radius())).into(), rotation);
            let search = |pos: &Pose, scratch: &mut MeshDistanceScratch| {
                mesh_distance_relative(a, b, pos, &DistanceSearch::new(DistanceKernel::Exact, None), scratch)
            };
            let gap = search(&pos_ab, &mut scratch).distance;
            let wanted = Real::powf(10.0, -6.0 + 6.0 * rng.uniform());
            pos_ab.translation.vector -= direction * (gap - wanted);
            let searched = search(&pos_ab, &mut scratch);
            if searched.distance <= 0.0 {
                continue;
            }
            let Some(found) = convex_measure(a, b, &pos_ab) else { continue };
            certified += 1;
            let ulps = certificate_slack(a, b, &pos_ab);
            assert!(
                (found.distance - searched.distance).abs() <= 2.0 * ulps,
                "case {case}: {} vs {}",
                found.distance,
                searched.distance
            );
            assert!(((found.point_b - found.point_a).norm() - found.distance).abs() <= 2.0 * ulps);
        }
        assert!(certified > 500, "{certified} of 600 certified");
    }
}

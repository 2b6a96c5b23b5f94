//! The distance of two convex meshes from GJK on their vertex hulls, where
//! GJK's bounds certify it: the triangles holding the closest points, and
//! the exact kernel's distance of that pair.

use super::hull_gap::{convex_distance, ConvexDistance, WarmSimplex};
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

/// [`measure`] where the meshes are closer than `ceiling` at time `s`;
/// `None` where they are not. The search starts with `ceiling` as its
/// best, so a pose where the meshes are well beyond it costs a few node
/// pairs instead of a search down to the closest triangles.
pub(crate) fn measure_below(
    a: &MovingMesh<'_>,
    b: &MovingMesh<'_>,
    s: Real,
    ceiling: Real,
    scratch: &mut MeshCcdScratch,
) -> Option<MeshDistance> {
    let relative = StepMotion::relative_pose(a.motion, b.motion, s);
    let found = match convex_measure(a.mesh, b.mesh, &relative) {
        Some(found) => (found.distance < ceiling).then_some(found)?,
        None => {
            let search = DistanceSearch::new(DistanceKernel::Exact, None);
            mesh_distance_below(a.mesh, b.mesh, &relative, &search, ceiling, &mut scratch.distance)?
        }
    };
    Some(in_world(a, s, found))
}

/// `found` (points in `a`'s frame at time `s`) with its points in the world.
pub(super) fn in_world(a: &MovingMesh<'_>, s: Real, mut found: MeshDistance) -> MeshDistance {
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
        box_mesh, icosphere, mesh_distance_relative, DistanceKernel, DistanceSearch, MeshDistanceScratch,
    };
    use crate::samples::Rng;

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

//! The signed distance between two meshes: how far apart they are, or how
//! deep they overlap, as one number with what it stands for.
//!
//! Apart, it is the distance between the surfaces ([`mesh_distance`]).
//! Where the surfaces meet, or one closed mesh lies wholly inside another,
//! it is minus the depth: exact for two convex meshes
//! ([`convex_penetration`]: the shortest separating move), the deepest
//! [`local_depths`] component's lower end for closed meshes that are not
//! both convex (a point at least that deep exists; the bracket is kept);
//! for a closed mesh wholly inside another, its deepest vertex (with the
//! same bracket). Surfaces that meet where a mesh is open (no inside) give
//! 0 and say so.

use super::distance::{mesh_distance, DistanceSearch, MeshDistance, MeshDistanceScratch};
use super::intersection::{mesh_intersection, MeshIntersection, MeshIntersectionScratch};
use super::local_depth::{local_depths, whole_patch_depth, LocalDepth};
use super::penetration::{convex_penetration_with, MeshPenetration, PenetrationScratch};
use super::point_query::{point_signed_distance, PointQueryScratch};
use super::trimesh::TriMesh;
use crate::math::{Pose, Real};

/// Two meshes' signed distance: `value` and what it stands for.
#[derive(Clone, Debug, PartialEq)]
pub struct SignedDistance {
    /// The distance when apart (0 when touching); minus the depth when
    /// overlapping (see [`Overlap`] for which depth).
    pub value: Real,
    /// How the meshes stand.
    pub overlap: Overlap,
}

/// How two meshes stand, for [`SignedDistance`].
#[derive(Clone, Debug, PartialEq)]
pub enum Overlap {
    /// Apart (or touching: `value` 0); the closest points.
    Apart(MeshDistance),
    /// Two convex solids overlapping: the exact depth.
    Convex(MeshPenetration),
    /// Closed surfaces crossing: each component's local depth, deepest
    /// first (`value` is minus the first's `lower`).
    Local(Vec<LocalDepth>),
    /// A closed mesh wholly inside another, surfaces apart (not both
    /// convex): `value` is minus its deepest vertex's depth, which is
    /// within `[lower, upper]` of the true depth as in [`LocalDepth`].
    Inside {
        /// Which mesh is inside: `'a'` or `'b'`.
        which: char,
        /// The deepest vertex's depth.
        lower: Real,
        /// No point of it is deeper.
        upper: Real,
    },
    /// Surfaces crossing where a mesh is not closed: there is no inside,
    /// so no depth (`value` 0).
    OpenCrossing(MeshIntersection),
}

/// Reusable buffers of [`signed_distance`].
#[derive(Clone, Debug, Default)]
pub struct SignedDistanceScratch {
    distance: MeshDistanceScratch,
    intersection: MeshIntersectionScratch,
    penetration: PenetrationScratch,
    points: PointQueryScratch,
}

/// The signed distance between mesh `a` at `pose_a` and mesh `b` at
/// `pose_b` (see the module).
pub fn signed_distance(
    a: &TriMesh,
    pose_a: &Pose,
    b: &TriMesh,
    pose_b: &Pose,
    scratch: &mut SignedDistanceScratch,
) -> SignedDistance {
    let apart = mesh_distance(a, pose_a, b, pose_b, &DistanceSearch::default(), &mut scratch.distance);
    overlap_of(a, pose_a, b, pose_b, apart, scratch)
}

/// The signed distance of two meshes whose surface distance `apart` is
/// known (from any search at these poses).
pub fn overlap_of(
    a: &TriMesh,
    pose_a: &Pose,
    b: &TriMesh,
    pose_b: &Pose,
    apart: MeshDistance,
    scratch: &mut SignedDistanceScratch,
) -> SignedDistance {
    match overlap_beyond(a, pose_a, b, pose_b, apart.distance, scratch) {
        Some((value, overlap)) => SignedDistance { value, overlap },
        None => SignedDistance { value: apart.distance, overlap: Overlap::Apart(apart) },
    }
}

/// The signed value and overlap of two meshes whose surfaces are
/// `surface_distance` apart, or `None` when they do not overlap (the value
/// is then that distance).
pub(crate) fn overlap_beyond(
    a: &TriMesh,
    pose_a: &Pose,
    b: &TriMesh,
    pose_b: &Pose,
    surface_distance: Real,
    scratch: &mut SignedDistanceScratch,
) -> Option<(Real, Overlap)> {
    let both_convex = a.is_convex() && b.is_convex();
    if surface_distance > 0.0 {
        // Apart surfaces overlap only if one mesh holds the other: then a
        // vertex of it is inside the other (first inside its box, which
        // rules most pairs out at the cost of a transform).
        for (which, (inner, inner_pose), (outer, outer_pose)) in
            [('b', (b, pose_b), (a, pose_a)), ('a', (a, pose_a), (b, pose_b))]
        {
            let vertex = outer_pose.inv_mul(inner_pose) * inner.vertices()[0];
            let (low, high) = outer.bounds();
            let in_box = (0..3).all(|k| low[k] <= vertex[k] && vertex[k] <= high[k]);
            if !in_box
                || !outer.is_closed()
                || point_signed_distance(outer, &vertex, &mut scratch.points).distance >= 0.0
            {
                continue;
            }
            if both_convex {
                if let Ok(Some(depth)) =
                    convex_penetration_with(a, pose_a, b, pose_b, &mut scratch.penetration)
                {
                    return Some((negated(depth.depth), Overlap::Convex(depth)));
                }
            }
            let (lower, upper) = whole_patch_depth(inner, inner_pose, outer, outer_pose, &mut scratch.points);
            return Some((negated(lower), Overlap::Inside { which, lower, upper }));
        }
        return None;
    }
    if both_convex {
        return match convex_penetration_with(a, pose_a, b, pose_b, &mut scratch.penetration) {
            Ok(Some(depth)) if depth.depth > 0.0 => Some((negated(depth.depth), Overlap::Convex(depth))),
            _ => None,
        };
    }
    let mut curve = MeshIntersection::default();
    mesh_intersection(a, pose_a, b, pose_b, &mut curve, &mut scratch.intersection);
    if curve.length() == 0.0 {
        // Touching without crossing.
        return None;
    }
    Some(match local_depths(a, pose_a, b, pose_b, &curve) {
        Ok(depths) => (negated(depths.first().map_or(0.0, |d| d.lower)), Overlap::Local(depths)),
        Err(_) => (0.0, Overlap::OpenCrossing(curve)),
    })
}

/// Minus a depth, 0 written as 0 (not −0).
fn negated(depth: Real) -> Real {
    if depth == 0.0 {
        0.0
    } else {
        -depth
    }
}

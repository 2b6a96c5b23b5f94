//! A lower bound on the distance between two meshes from the convex hulls
//! of their vertices, by GJK (Gilbert–Johnson–Keerthi): the cheap test that
//! lets a pair whose meshes stay apart over a step skip the BVH search.
//!
//! ## Why it is a bound whatever GJK does
//! A mesh lies inside the convex hull of its vertices, so two meshes are at
//! least as far apart as their hulls, and for any unit direction `n` the
//! hulls are at least
//!
//! ```text
//! gap(n) = min_b n·b − max_a n·a
//! ```
//!
//! apart (the gap between their shadows on `n`). The maxima are the
//! maxima over every vertex (no hull is built; `TriMesh::farthest_vertex`
//! finds them from a table of directions, the vertex a whole scan finds),
//! so each `gap(n)` holds exactly, up to the rounding of the dot products. GJK only proposes the directions: each
//! iteration's direction towards the closest point of its simplex; the
//! bound is the best gap seen. For convex meshes (boxes, icospheres) GJK
//! converges to the meshes' own distance; for others, to their hulls'.
//!
//! GJK starts from the pair's last simplex where there is one
//! ([`WarmSimplex`]: the CCD's advancement, the re-arm and the trace carry
//! it from query to query): a pair whose closest features have not changed
//! is settled at the first iteration. Where it starts changes only how soon the bound comes, not that it is
//! one.
//!
//! The search stops as soon as it has what the caller needs: a gap above
//! `enough` (the pair can be skipped), or a point of the hulls' difference
//! within `close` of the origin (the hulls come that close, so no
//! direction can prove more than `close`), or converged.
//!
//! For two convex meshes the same GJK also gives their distance from above
//! (the distance between a point of each hull), so [`convex_distance`]
//! certifies a distance where the two bounds meet: the trace's sample of
//! convex pairs, warm-started from the pair's last simplex.

use super::simplex::{Facing, Simplex};
use crate::kernels::triangle_distance;
use crate::math::{Pose, Real, Vector};
use crate::mesh::TriMesh;

/// GJK iterations at most. A warm-started query takes one to three; 24 is
/// ample for the polytopes of a few thousand vertices GJK meets here (it
/// converges in a few iterations per face of the final simplex).
pub(crate) const HULL_GAP_MAX_ITERATIONS: usize = 24;

/// GJK stops once its upper bound (the distance to its simplex) and its
/// best gap agree to this fraction: the bound is then within 1e-9 of the
/// hulls' distance, far below any contact distance.
pub(crate) const HULL_GAP_RELATIVE_TOLERANCE: Real = 1e-9;

/// The answer of [`hull_gap`].
#[derive(Copy, Clone, Debug, PartialEq)]
pub(crate) struct HullGap {
    /// A lower bound on the distance between the two meshes (negative or
    /// `-inf` when none better was found, e.g. the hulls overlap).
    pub lower: Real,
    /// The unit direction (in `a`'s frame, from `a` towards `b`) that gave
    /// `lower`, a good start for the pair's next query.
    pub axis: Option<Vector>,
    /// The vertices of `a` and `b` that gave `lower` (a's highest and b's
    /// lowest along `axis`): for convex meshes, corners of the closest
    /// features.
    pub support: Option<(usize, usize)>,
    /// GJK iterations made.
    pub iterations: usize,
}

/// A lower bound on the distance between mesh `a` (in its own frame) and
/// mesh `b` at `pos_ab` (relative to `a`), found by GJK starting from
/// `start` (a direction from `a` towards `b`; default: the line between
/// their frames' origins). Stops once the bound exceeds `enough` or the
/// hulls are proven within `close` (see the module).
pub(crate) fn hull_gap(
    a: &TriMesh,
    b: &TriMesh,
    pos_ab: &Pose,
    start: Option<Vector>,
    bounds: (Real, Real),
) -> HullGap {
    hull_gap_from(a, b, pos_ab, start, bounds, &mut WarmSimplex::default())
}

/// [`hull_gap`] starting from the simplex `warm` left by the pair's last
/// query (its vertex pairs at the new pose; `start` where it is empty or
/// spans the origin), which it updates: a pair whose closest features are
/// those of its last query is settled at the first iteration. The bound is
/// the best gap seen, whatever the start.
pub(crate) fn hull_gap_from(
    a: &TriMesh,
    b: &TriMesh,
    pos_ab: &Pose,
    start: Option<Vector>,
    (close, enough): (Real, Real),
    warm: &mut WarmSimplex,
) -> HullGap {
    let support = |v: &Vector| difference_support(a, b, pos_ab, v);
    let mut v = match start {
        Some(axis) if axis.norm_squared() > 0.0 => axis,
        _ => first_direction(pos_ab),
    };
    let mut answer = HullGap { lower: Real::NEG_INFINITY, axis: None, support: None, iterations: 0 };
    // Whether `v` is the closest point of the simplex (else the start).
    let mut on_simplex = false;
    let mut simplex = warm.simplex(a, b, pos_ab);
    if simplex.len > 0 {
        let closest = simplex.closest_to_origin();
        if simplex.len > 0 && closest.norm_squared() > 0.0 && closest.norm_squared().is_finite() {
            v = closest;
            on_simplex = true;
        } else {
            simplex = Simplex::default();
        }
    }
    while answer.iterations < HULL_GAP_MAX_ITERATIONS {
        answer.iterations += 1;
        let norm = v.norm();
        if norm == 0.0 || !norm.is_finite() {
            break;
        }
        let (w, vertices) = support(&v);
        let gap = v.dot(&w) / norm;
        if gap > answer.lower {
            answer.lower = gap;
            answer.axis = Some(v / norm);
            answer.support = Some((vertices.0 as usize, vertices.1 as usize));
        }
        if answer.lower > enough {
            break;
        }
        if on_simplex {
            // `v` is a point of the hulls' difference: they come this close.
            if norm <= close || norm - answer.lower <= HULL_GAP_RELATIVE_TOLERANCE * norm {
                break;
            }
            if simplex.points[..simplex.len].contains(&w) {
                break;
            }
        }
        simplex.push(w, vertices);
        let closer = simplex.closest_to_origin();
        if on_simplex && closer.norm_squared() >= v.norm_squared() {
            // No progress (rounding at a face): the bound stands.
            break;
        }
        v = closer;
        on_simplex = true;
    }
    warm.keep(&simplex);
    answer
}

/// The point of the hulls' difference `b − a` (b at `pos_ab` in a's frame)
/// farthest along `-v`: b's lowest vertex along `v` minus a's highest, and
/// the two vertices.
#[inline]
fn difference_support(a: &TriMesh, b: &TriMesh, pos_ab: &Pose, v: &Vector) -> (Vector, (u32, u32)) {
    let in_b = pos_ab.rotation.inverse_transform_vector(v);
    let lowest_b = b.farthest_vertex(&-in_b);
    let highest_a = a.farthest_vertex(v);
    (difference_point(a, b, pos_ab, (highest_a as u32, lowest_b as u32)), (highest_a as u32, lowest_b as u32))
}

/// The point `b[j] − a[i]` of the hulls' difference (in a's frame).
#[inline]
fn difference_point(a: &TriMesh, b: &TriMesh, pos_ab: &Pose, (i, j): (u32, u32)) -> Vector {
    pos_ab.rotation * b.vertices()[j as usize].coords + pos_ab.translation.vector
        - a.vertices()[i as usize].coords
}

/// GJK's first direction without a hint: the line between the frames'
/// origins (any axis when they coincide).
fn first_direction(pos_ab: &Pose) -> Vector {
    let translation = pos_ab.translation.vector;
    if translation.norm_squared() > 0.0 {
        translation
    } else {
        Vector::x()
    }
}

/// GJK's simplex on two meshes' vertex hulls at the end of a query, as the
/// vertex pairs (a's, b's) that span it: the pair's next query starts from
/// it (opaque; [`WarmSimplex::default`] is a cold start).
#[derive(Copy, Clone, Debug, Default, PartialEq)]
pub struct WarmSimplex {
    pairs: [(u32, u32); 3],
    len: usize,
}

impl WarmSimplex {
    /// The simplex's points at `pos_ab`; empty when a vertex index is not
    /// the meshes' (a simplex of other meshes).
    fn simplex(&self, a: &TriMesh, b: &TriMesh, pos_ab: &Pose) -> Simplex {
        let mut simplex = Simplex::default();
        let (na, nb) = (a.vertices().len(), b.vertices().len());
        if self.pairs[..self.len].iter().all(|&(i, j)| (i as usize) < na && (j as usize) < nb) {
            for &pair in &self.pairs[..self.len] {
                simplex.push(difference_point(a, b, pos_ab, pair), pair);
            }
        }
        simplex
    }

    /// Keeps `simplex`'s vertex pairs (at most three: four span the origin).
    fn keep(&mut self, simplex: &Simplex) {
        self.len = simplex.len.min(3);
        self.pairs[..self.len].copy_from_slice(&simplex.pairs[..self.len]);
    }

    /// A triangle of `a` that has every vertex of `a` in the simplex as a
    /// corner, and one of `b` likewise (`None` when a mesh has none, e.g.
    /// a box face's diagonal): for a certified simplex, triangles that hold
    /// the closest points, so their distance is the meshes'.
    pub(crate) fn triangles(&self, a: &TriMesh, b: &TriMesh) -> Option<(usize, usize)> {
        let pairs = &self.pairs[..self.len];
        let holding = |mesh: &TriMesh, corner: fn(&(u32, u32)) -> u32| {
            let first = corner(pairs.first()?) as usize;
            mesh.triangles_at(first).iter().map(|&t| t as usize).find(|&t| {
                let vertices = mesh.triangles()[t];
                pairs.iter().all(|pair| vertices.contains(&corner(pair)))
            })
        };
        Some((holding(a, |pair| pair.0)?, holding(b, |pair| pair.1)?))
    }
}

/// How a [`convex_distance`] query ended.
#[derive(Copy, Clone, Debug, PartialEq)]
pub(crate) enum ConvexDistance {
    /// Certified: GJK's upper bound (the distance between a point of each
    /// hull) is within the slack of its lower bound (a gap along a
    /// direction); the value is the upper bound.
    Certified(Real),
    /// Not certified within [`HULL_GAP_MAX_ITERATIONS`], or GJK stopped
    /// without progress (rounding at a face), or the hulls overlap or touch:
    /// the caller finds the distance another way.
    Undecided,
}

/// The distance between two convex meshes (`a` in its own frame, `b` at
/// `pos_ab`), by GJK started from the pair's last simplex `warm` (updated):
/// certified once GJK's upper and lower bounds agree within `slack`.
///
/// Why the value is the meshes' distance: the lower bound is a gap between
/// the two vertex sets' shadows on a direction, which no pair of points of
/// the meshes can beat (see the module); the upper bound is the distance
/// between a point of each vertex hull, and for meshes that are the
/// boundaries of their hulls ([`TriMesh::is_convex`], to
/// [`CONVEX_SURFACE_TOLERANCE`](crate::mesh::CONVEX_SURFACE_TOLERANCE) of
/// their radius) the closest points of two disjoint hulls lie on the
/// meshes. So the meshes' distance lies between the two, and the upper
/// bound is within `slack` (plus the rounding of the bounds) of it. The
/// caller checks convexity: for other meshes the upper bound may be below
/// their distance.
///
/// A pair whose closest features are those of its last query is certified
/// at the first iteration: two supports and the closest point of a simplex
/// of at most three points. Otherwise GJK goes on from there.
pub(crate) fn convex_distance(
    a: &TriMesh,
    b: &TriMesh,
    pos_ab: &Pose,
    warm: &mut WarmSimplex,
    slack: Real,
) -> ConvexDistance {
    let mut simplex = warm.simplex(a, b, pos_ab);
    if simplex.len == 0 {
        let (w, pair) = difference_support(a, b, pos_ab, &first_direction(pos_ab));
        simplex.push(w, pair);
    }
    let mut v = simplex.closest_to_origin();
    let mut lower = Real::NEG_INFINITY;
    let mut answer = ConvexDistance::Undecided;
    for _ in 0..HULL_GAP_MAX_ITERATIONS {
        let upper = v.norm();
        // Overlapping or touching hulls (no positive distance to certify),
        // or a non-finite pose.
        if simplex.len == 0 || !(upper > 0.0 && upper.is_finite()) {
            break;
        }
        let (w, pair) = difference_support(a, b, pos_ab, &v);
        lower = lower.max(v.dot(&w) / upper);
        if upper - lower <= slack {
            answer = ConvexDistance::Certified(upper);
            break;
        }
        if simplex.pairs[..simplex.len].contains(&pair) {
            break;
        }
        simplex.push(w, pair);
        let closer = simplex.closest_to_origin();
        if closer.norm_squared() >= v.norm_squared() {
            break;
        }
        v = closer;
    }
    warm.keep(&simplex);
    answer
}

/// What [`first_within`] found: a triangle pair's distance and triangles
/// (`None` when the vertices have no triangles), and how many pairs it
/// evaluated.
#[derive(Copy, Clone, Debug, PartialEq)]
pub(crate) struct Around {
    pub found: Option<(Real, (usize, usize))>,
    pub evaluated: usize,
}

/// The first of the triangle pairs around two vertices (those of `a` that
/// have vertex `va` as a corner against those of `b` around `vb`, `b`
/// placed at `pos_ab` in `a`'s frame; exact kernel) whose distance is at
/// most `enough`, or else the closest of them (the first of equals).
///
/// Where the hulls' closest vertices are, for convex meshes, the closest
/// triangle pair is among these. No triangle pair is closer than the
/// meshes, so the first pair found within a lower bound on their distance
/// (plus a slack) is within that slack of the closest: the search stops
/// there. With `axis` (the hulls' closest direction, from `a` towards
/// `b`), the triangles facing along it are tried first: the closest
/// features' faces, where they are faces.
pub(crate) fn first_within(
    (a, va): (&TriMesh, usize),
    (b, vb): (&TriMesh, usize),
    pos_ab: &Pose,
    axis: Option<Vector>,
    enough: Real,
) -> Around {
    let facing_a = Facing::around(a, va, &Pose::identity(), axis);
    let facing_b = Facing::around(b, vb, pos_ab, axis.map(|n| -n));
    let mut around = Around { found: None, evaluated: 0 };
    for j in facing_b.order(b.triangles_at(vb)) {
        let posed = b.triangle(j).map(|p| pos_ab * p);
        for i in facing_a.order(a.triangles_at(va)) {
            around.evaluated += 1;
            let d = triangle_distance(&a.triangle(i), &posed).distance;
            if around.found.is_none_or(|(b, _)| d < b) {
                around.found = Some((d, (i, j)));
            }
            if d <= enough {
                return around;
            }
        }
    }
    around
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::math::Point;
    use crate::mesh::{box_mesh, icosphere};
    use nalgebra::{Translation3, UnitQuaternion};

    fn unit_box() -> TriMesh {
        box_mesh(&Vector::new(1.0, 1.0, 1.0)).expect("a box")
    }

    /// An icosphere of radius 0.7 (`subdivisions`), the unit box and an
    /// icosahedron of radius 0.4.
    fn sphere_box_icosahedron(subdivisions: u32) -> [TriMesh; 3] {
        [
            icosphere(0.7, subdivisions).expect("an icosphere"),
            unit_box(),
            icosphere(0.4, 0).expect("an icosahedron"),
        ]
    }

    #[test]
    fn two_boxes_face_to_face_give_their_gap() {
        let (a, b) = (unit_box(), unit_box());
        // Centres 2.5 apart along x: the faces are 0.5 apart.
        let pose = Pose::from_parts(Translation3::new(2.5, 0.3, -0.2), UnitQuaternion::identity());
        // Asked for a bound just below the distance, it finds one.
        let gap = hull_gap(&a, &b, &pose, None, (0.5 - 1e-12, 0.5 - 1e-12));
        assert!(gap.lower > 0.5 - 1e-12 && gap.lower <= 0.5 + 1e-15, "{gap:?}");
        // Asked for more than the distance, it stops on an upper bound.
        let gap = hull_gap(&a, &b, &pose, None, (0.6, 0.6));
        assert!(gap.lower <= 0.5 + 1e-15, "{gap:?}");
    }

    #[test]
    fn a_rotated_box_corner_to_face() {
        let (a, b) = (unit_box(), unit_box());
        // b turned so that a corner points at a's +x face: the corner lies
        // sqrt(3) from b's centre.
        let rotation =
            UnitQuaternion::rotation_between(&Vector::new(-1.0, -1.0, -1.0), &Vector::new(-1.0, 0.0, 0.0))
                .expect("a rotation");
        let pose = Pose::from_parts(Translation3::new(1.0 + 3f64.sqrt() + 0.25, 0.0, 0.0), rotation);
        let gap = hull_gap(&a, &b, &pose, Some(Vector::new(0.0, 1.0, 0.0)), (0.25 - 1e-9, 0.25 - 1e-9));
        assert!(gap.lower > 0.25 - 1e-9 && gap.lower <= 0.25 + 1e-12, "{gap:?}");
    }

    #[test]
    fn overlapping_boxes_give_no_positive_bound() {
        let (a, b) = (unit_box(), unit_box());
        let pose = Pose::from_parts(Translation3::new(1.5, 0.0, 0.0), UnitQuaternion::identity());
        let gap = hull_gap(&a, &b, &pose, None, (0.0, 0.0));
        assert!(gap.lower <= 0.0, "{gap:?}");
    }

    #[test]
    fn stops_once_the_bound_is_enough() {
        let (a, b) = (unit_box(), unit_box());
        let pose = Pose::from_parts(Translation3::new(10.0, 0.0, 0.0), UnitQuaternion::identity());
        let gap = hull_gap(&a, &b, &pose, None, (1.0, 1.0));
        assert_eq!(gap.iterations, 1);
        assert!(gap.lower > 1.0);
    }

    /// The bound never exceeds the meshes' distance (the exact triangle
    /// search), over random poses of two icospheres and a box.
    #[test]
    fn never_above_the_mesh_distance() {
        let meshes = sphere_box_icosahedron(1);
        let mut rng = crate::samples::Rng::new(7);
        let mut scratch = crate::mesh::MeshDistanceScratch::default();
        for k in 0..300 {
            let (a, b) = (&meshes[k % 3], &meshes[(k / 3) % 3]);
            let axis = rng.in_unit_ball();
            let rotation = UnitQuaternion::from_scaled_axis(axis * 3.0);
            let offset = rng.in_unit_ball() * 4.0;
            let pose = Pose::from_parts(Translation3::from(offset), rotation);
            let exact = crate::mesh::mesh_distance_relative(
                a,
                b,
                &pose,
                &crate::mesh::DistanceSearch::new(crate::mesh::DistanceKernel::Exact, None),
                &mut scratch,
            )
            .distance;
            // Asked for more than the distance: never above it.
            let gap = hull_gap(a, b, &pose, None, (exact + 0.1, exact + 0.1));
            assert!(gap.lower <= exact + 1e-12, "case {k}: bound {} above distance {exact}", gap.lower);
            // Convex meshes whose bounding spheres are apart (so neither is
            // inside the other): asked for a bound just below their
            // distance, GJK finds one.
            if offset.norm() > a.radius() + b.radius() {
                let wanted = exact - 1e-9 * (1.0 + exact);
                let gap = hull_gap(a, b, &pose, None, (wanted, wanted));
                assert!(gap.lower > wanted, "case {k}: bound {} below {wanted}", gap.lower);
                assert!(gap.lower <= exact + 1e-12, "case {k}: bound {} above distance {exact}", gap.lower);
            }
        }
    }

    /// Warm-started from the last simplex along a tumbling motion (the
    /// CCD's advancement and re-arm), the bound is never above the meshes'
    /// distance and, asked for one just below it, finds one as a cold start
    /// does, mostly at the first iteration; a simplex of other meshes (its
    /// vertex indices out of range) is a cold start.
    #[test]
    fn a_warm_start_gives_the_same_bounds_sooner() {
        let meshes = sphere_box_icosahedron(2);
        let search = crate::mesh::DistanceSearch::new(crate::mesh::DistanceKernel::Exact, None);
        let mut scratch = crate::mesh::MeshDistanceScratch::default();
        let mut rng = crate::samples::Rng::new(5);
        let (mut warm_iterations, mut cold_iterations, mut samples) = (0, 0, 0);
        for k in 0..36 {
            let (a, b) = (&meshes[k % 3], &meshes[(k / 3) % 3]);
            let (start, spin) = (rng.in_unit_ball() * 4.0, rng.in_unit_ball() * 2.0);
            let (velocity, turn) = (rng.in_unit_ball(), rng.in_unit_ball() * 2.0);
            let mut warm = WarmSimplex::default();
            for step in 0..24 {
                let s = step as Real * 0.05;
                let rotation = UnitQuaternion::from_scaled_axis(spin + turn * s);
                let offset = start + velocity * s;
                let pose = Pose::from_parts(Translation3::from(offset), rotation);
                let exact = crate::mesh::mesh_distance_relative(a, b, &pose, &search, &mut scratch).distance;
                if offset.norm() <= a.radius() + b.radius() + 0.05 {
                    // Near or inside each other: only "never above".
                    let gap = hull_gap_from(a, b, &pose, None, (0.0, exact + 0.1), &mut warm);
                    assert!(gap.lower <= exact + 1e-12, "case {k} step {step}: {} above {exact}", gap.lower);
                    continue;
                }
                let wanted = exact - 1e-9 * (1.0 + exact);
                let gap = hull_gap_from(a, b, &pose, None, (wanted, wanted), &mut warm);
                let cold = hull_gap(a, b, &pose, None, (wanted, wanted));
                for (name, gap) in [("warm", gap), ("cold", cold)] {
                    assert!(gap.lower > wanted, "case {k} step {step} {name}: {} below {wanted}", gap.lower);
                    assert!(
                        gap.lower <= exact + 1e-12,
                        "case {k} step {step} {name}: {} above {exact}",
                        gap.lower
                    );
                }
                warm_iterations += gap.iterations;
                cold_iterations += cold.iterations;
                samples += 1;
            }
        }
        assert!(samples > 400, "{samples} samples apart");
        assert!(
            2 * warm_iterations < cold_iterations,
            "warm {warm_iterations} against cold {cold_iterations} iterations"
        );
        // A simplex naming vertices that mesh b does not have is not used.
        let (a, b) = (&meshes[0], &meshes[2]);
        let pose = Pose::from_parts(Translation3::new(3.0, 0.2, 0.1), UnitQuaternion::identity());
        let mut foreign = WarmSimplex { pairs: [(0, 100), (1, 101), (2, 102)], len: 3 };
        let gap = hull_gap_from(a, b, &pose, None, (0.0, 0.0), &mut foreign);
        let cold = hull_gap(a, b, &pose, None, (0.0, 0.0));
        assert_eq!(gap, cold);
        assert!(foreign.pairs[..foreign.len]
            .iter()
            .all(|&(i, j)| (i as usize) < a.vertices().len() && (j as usize) < b.vertices().len()));
    }

    /// Two convex meshes' certified distance is the exact triangle search's
    /// to the slack, cold and warm-started along a tumbling motion (the
    /// trace's use), the triangles it names hold the closest points, and
    /// it is undecided (not a wrong value) where the meshes overlap.
    #[test]
    fn the_convex_distance_is_the_mesh_distance() {
        let meshes = [
            icosphere(0.7, 2).expect("an icosphere"),
            unit_box(),
            icosphere(0.4, 0).expect("an icosahedron"),
            box_mesh(&Vector::new(2.0, 0.1, 0.5)).expect("a plank"),
        ];
        let search = crate::mesh::DistanceSearch::new(crate::mesh::DistanceKernel::Exact, None);
        let mut scratch = crate::mesh::MeshDistanceScratch::default();
        let mut rng = crate::samples::Rng::new(11);
        let (mut certified, mut overlapping) = (0, 0);
        for k in 0..48 {
            let (a, b) = (&meshes[k % 4], &meshes[(k / 4) % 4]);
            let (start, spin) = (rng.in_unit_ball() * 5.0, rng.in_unit_ball() * 2.0);
            let (velocity, turn) = (rng.in_unit_ball() * 2.0, rng.in_unit_ball() * 3.0);
            let mut warm = WarmSimplex::default();
            for step in 0..12 {
                let s = step as Real * 0.25;
                let rotation = UnitQuaternion::from_scaled_axis(spin + turn * s);
                let pose = Pose::from_parts(Translation3::from(start + velocity * s), rotation);
                let exact = crate::mesh::mesh_distance_relative(a, b, &pose, &search, &mut scratch);
                let scale = pose.translation.vector.norm() + a.radius() + b.radius();
                let slack = 64.0 * Real::EPSILON * scale;
                let mut cold = WarmSimplex::default();
                for (name, simplex) in [("warm", &mut warm), ("cold", &mut cold)] {
                    match convex_distance(a, b, &pose, simplex, slack) {
                        ConvexDistance::Certified(d) => {
                            certified += 1;
                            assert!(
                                (d - exact.distance).abs() <= slack,
                                "case {k} step {step} {name}: {d} against {}",
                                exact.distance
                            );
                            if let Some((i, j)) = simplex.triangles(a, b) {
                                let pair = crate::mesh::triangle_pair_distance(a, i, b, j, &pose).distance;
                                assert!(pair <= d + slack && pair >= exact.distance - slack);
                            }
                        }
                        ConvexDistance::Undecided => overlapping += usize::from(exact.distance == 0.0),
                    }
                }
            }
        }
        // Most samples are apart and certified; some overlap (the scan's
        // distance is zero there).
        assert!(certified > 700 && overlapping > 10, "{certified} certified, {overlapping} overlapping");
    }

    /// Meshes that are not convex are never taken as convex, and the convex
    /// primitives are, whichever way their triangles face.
    #[test]
    fn which_meshes_are_convex() {
        assert!(unit_box().is_convex());
        assert!(icosphere(1.0, 3).expect("an icosphere").is_convex());
        let turned_inside_out = |mesh: TriMesh| {
            let triangles = mesh.triangles().iter().map(|&[p, q, r]| [p, r, q]).collect();
            TriMesh::new(mesh.vertices().to_vec(), triangles).expect("a mesh")
        };
        assert!(turned_inside_out(unit_box()).is_convex());
        // An icosphere with one vertex pushed in below its neighbours (which
        // lie about 0.05 of the radius below it): a dent.
        let ball = icosphere(1.0, 2).expect("an icosphere");
        let mut dented = ball.vertices().to_vec();
        dented[5] *= 0.9;
        assert!(!TriMesh::new(dented, ball.triangles().to_vec()).expect("a mesh").is_convex());
        // Open meshes bound no solid.
        assert!(!crate::mesh::single_triangle(
            Point::origin(),
            Point::new(1.0, 0.0, 0.0),
            Point::new(0.0, 1.0, 0.0)
        )
        .expect("a triangle")
        .is_convex());
        let open = ball.triangles()[1..].to_vec();
        assert!(!TriMesh::new(ball.vertices().to_vec(), open).expect("a mesh").is_convex());
    }

    /// The certified distance holds at the ends of the sizes a scene may
    /// give (1e±30): the same pairs scaled by 2^±90 (about 1e±27) give the
    /// exact search's distance, scaled, to the slack.
    #[test]
    fn the_convex_distance_holds_at_extreme_sizes() {
        let search = crate::mesh::DistanceSearch::new(crate::mesh::DistanceKernel::Exact, None);
        let mut scratch = crate::mesh::MeshDistanceScratch::default();
        for k in [2f64.powi(-90), 1.0, 2f64.powi(90)] {
            let a = icosphere(0.7 * k, 2).expect("an icosphere");
            let b = box_mesh(&(Vector::new(0.5, 0.3, 0.2) * k)).expect("a box");
            let mut rng = crate::samples::Rng::new(5);
            let mut certified = 0;
            for case in 0..40 {
                let rotation = UnitQuaternion::from_scaled_axis(rng.in_unit_ball() * 3.0);
                let offset = rng.in_unit_ball() * 3.0 * k;
                let pose = Pose::from_parts(Translation3::from(offset), rotation);
                let exact =
                    crate::mesh::mesh_distance_relative(&a, &b, &pose, &search, &mut scratch).distance;
                let slack = 64.0 * Real::EPSILON * (offset.norm() + a.radius() + b.radius());
                if let ConvexDistance::Certified(d) =
                    convex_distance(&a, &b, &pose, &mut WarmSimplex::default(), slack)
                {
                    certified += 1;
                    assert!((d - exact).abs() <= slack, "scale {k:e} case {case}: {d:e} against {exact:e}");
                }
            }
            assert!(certified >= 20, "scale {k:e}: {certified} of 40 certified");
        }
    }
}

//! How deep two closed meshes overlap, locally, at each component of their
//! intersection curve: for meshes that need not be convex.
//!
//! ## The definition
//! The surfaces of two closed meshes `A` and `B` cross along closed curves.
//! A *component* is a connected piece of that curve: crossing triangle
//! pairs linked where they share a triangle of one mesh and their triangles
//! of the other are neighbours (share an edge). The part of `A`'s surface
//! inside `B` next to a component is its *patch*: the vertices of `A`
//! inside `B` reached from the component's triangles through `A`'s edges
//! without leaving `B` (and the same with the meshes' roles swapped). The
//! component's **local depth** is how far the deepest point of those
//! patches lies from the other mesh's surface: for two spheres that
//! overlap by `δ`, `δ`; for a box corner pushed into a slab, the corner's
//! depth; for a ring dipped into a slab, how deep it dips.
//!
//! ## What is computed, and how close it is
//! The depth is measured at the patches' vertices (each vertex's signed
//! distance to the other mesh, [`point_signed_distance`]), so what is
//! returned is a bracket: `lower`, the deepest vertex (a point of the patch
//! that deep exists), and `upper`: for each mesh's patch its deepest
//! vertex plus `h`, the longest edge of a triangle touching the patch or
//! the component, but never more than half the other solid's narrowest
//! width (along its frame's axes: no point inside a solid is farther from
//! its surface). The bracket holds the true deepest point of the patches'
//! triangles because the distance to a surface changes by at most the
//! distance moved (a point of a triangle wholly inside lies within `h` of
//! a vertex; a point of a crossing triangle within `h` of the curve, where
//! the depth is 0).
//! Under refinement `h` goes to 0 and the bracket closes on the depth of
//! the smooth shapes the meshes approximate, instead of shrinking to 0
//! as a depth measured at the curve would (tested on spheres and a torus
//! against their analytic depths).
//!
//! Not covered: a mesh wholly inside another (no curve; for convex meshes
//! [`convex_penetration`](super::convex_penetration) says it), and meshes
//! that are not closed (no inside).

use std::collections::HashMap;

use super::intersection::MeshIntersection;
use super::point_query::{point_signed_distance, PointQueryScratch};
use super::trimesh::{MeshError, TriMesh};
use crate::math::{Point, Pose, Real};

/// Which mesh a point belongs to.
#[derive(Copy, Clone, Debug, PartialEq, Eq)]
pub enum Side {
    /// Mesh `a`.
    A,
    /// Mesh `b`.
    B,
}

/// The local depth at one component of the intersection curve (see the
/// module).
#[derive(Clone, Debug, PartialEq)]
pub struct LocalDepth {
    /// The deepest vertex's depth: the patches reach at least this deep.
    pub lower: Real,
    /// No point of the patches is deeper than this (`lower` plus the
    /// longest edge of the triangles involved).
    pub upper: Real,
    /// The deepest vertex (world frame), and whose it is.
    pub deepest: Point,
    /// The mesh the deepest vertex belongs to.
    pub side: Side,
    /// Where that vertex is nearest the other mesh's surface (world frame).
    pub nearest: Point,
    /// The component's crossing pairs (indices into the
    /// [`MeshIntersection`]'s `pairs`).
    pub pairs: Vec<usize>,
    /// The component's curve length.
    pub curve_length: Real,
}

/// The local depth at each component of `intersection` (found by
/// [`mesh_intersection`](super::mesh_intersection) for the same meshes and
/// poses), deepest first; an error if either mesh is not closed.
pub fn local_depths(
    a: &TriMesh,
    pose_a: &Pose,
    b: &TriMesh,
    pose_b: &Pose,
    intersection: &MeshIntersection,
) -> Result<Vec<LocalDepth>, MeshError> {
    for mesh in [a, b] {
        if !mesh.is_closed() {
            mesh.check_closed()?;
        }
    }
    let components = components(a, b, intersection);
    let mut scratch = PointQueryScratch::default();
    let mut depths: Vec<LocalDepth> = components
        .into_iter()
        .map(|pairs| {
            // Depth 0 on the curve itself, until a vertex inside is found.
            let on_curve =
                intersection.pairs[pairs[0]].shared.points().first().copied().unwrap_or_else(Point::origin);
            let sides = [Side::A, Side::B].map(|side| {
                let mut found =
                    Deepest { depth: 0.0, vertex: on_curve, side, nearest: on_curve, longest_edge: 0.0 };
                let seeds = pairs.iter().map(|&k| {
                    let pair = &intersection.pairs[k];
                    if side == Side::A {
                        pair.triangle_a
                    } else {
                        pair.triangle_b
                    }
                });
                let patch = match side {
                    Side::A => Patch { side, mine: a, my_pose: pose_a, other: b, other_pose: pose_b },
                    Side::B => Patch { side, mine: b, my_pose: pose_b, other: a, other_pose: pose_a },
                };
                patch.walk(seeds, &mut scratch, &mut found);
                // No point inside a solid is farther from its surface than
                // half the solid's narrowest width (along a frame axis).
                let (low, high) = patch.other.bounds();
                let half_width = (high - low).min() / 2.0;
                (found, (found.depth + found.longest_edge).min(half_width).max(found.depth))
            });
            let [(deep_a, upper_a), (deep_b, upper_b)] = sides;
            let found = if deep_b.depth > deep_a.depth { deep_b } else { deep_a };
            let curve_length = pairs
                .iter()
                .filter_map(|&k| match intersection.pairs[k].shared {
                    crate::kernels::TriangleIntersection::Segment([p, q]) => Some((q - p).norm()),
                    _ => None,
                })
                .sum();
            LocalDepth {
                lower: found.depth,
                upper: upper_a.max(upper_b),
                deepest: found.vertex,
                side: found.side,
                nearest: found.nearest,
                pairs,
                curve_length,
            }
        })
        .collect();
    depths.sort_by(|x, y| y.lower.total_cmp(&x.lower));
    Ok(depths)
}

/// How deep closed mesh `inner` at `inner_pose`, wholly inside `outer`
/// (surfaces apart), lies: its deepest vertex's depth and the bound above
/// it, as [`LocalDepth`]'s `lower` and `upper` with the whole surface as
/// the patch.
pub(crate) fn whole_patch_depth(
    inner: &TriMesh,
    inner_pose: &Pose,
    outer: &TriMesh,
    outer_pose: &Pose,
    scratch: &mut PointQueryScratch,
) -> (Real, Real) {
    let start = inner_pose * inner.vertices()[0];
    let mut found = Deepest { depth: 0.0, vertex: start, side: Side::A, nearest: start, longest_edge: 0.0 };
    let patch =
        Patch { side: Side::A, mine: inner, my_pose: inner_pose, other: outer, other_pose: outer_pose };
    patch.walk(0..inner.triangles().len(), scratch, &mut found);
    let (low, high) = outer.bounds();
    let half_width = (high - low).min() / 2.0;
    (found.depth, (found.depth + found.longest_edge).min(half_width).max(found.depth))
}

/// The deepest vertex found so far (world frame) and the longest edge seen.
#[derive(Copy, Clone, Debug)]
struct Deepest {
    depth: Real,
    vertex: Point,
    side: Side,
    nearest: Point,
    longest_edge: Real,
}

/// One mesh's patch inside the other.
struct Patch<'m> {
    side: Side,
    mine: &'m TriMesh,
    my_pose: &'m Pose,
    other: &'m TriMesh,
    other_pose: &'m Pose,
}

impl Patch<'_> {
    /// Walks the patch from the crossing triangles `seeds` (of `mine`):
    /// every vertex inside `other` reached through `mine`'s edges without
    /// leaving it is measured; the longest edge of the seeds and of the
    /// triangles around those vertices is kept.
    fn walk(&self, seeds: impl Iterator<Item = usize>, scratch: &mut PointQueryScratch, found: &mut Deepest) {
        let (mine, vertices) = (self.mine, self.mine.vertices());
        let to_other = self.other_pose.inv_mul(self.my_pose);
        let longest_edge = |t: usize| {
            let [p, q, r] = mine.triangle(t);
            (q - p).norm().max((r - q).norm()).max((p - r).norm())
        };
        let mut seen = vec![false; vertices.len()];
        let mut queue: Vec<u32> = Vec::new();
        for t in seeds {
            found.longest_edge = found.longest_edge.max(longest_edge(t));
            queue.extend(mine.triangles()[t]);
        }
        while let Some(v) = queue.pop() {
            if std::mem::replace(&mut seen[v as usize], true) {
                continue;
            }
            let at = point_signed_distance(self.other, &(to_other * vertices[v as usize]), scratch);
            if at.distance >= 0.0 {
                continue;
            }
            let around = mine.triangles_at(v as usize);
            for &t in around {
                found.longest_edge = found.longest_edge.max(longest_edge(t as usize));
                queue.extend(mine.triangles()[t as usize].iter().filter(|&&w| !seen[w as usize]));
            }
            if -at.distance > found.depth {
                found.depth = -at.distance;
                found.vertex = self.my_pose * vertices[v as usize];
                found.side = self.side;
                found.nearest = self.other_pose * at.closest;
            }
        }
    }
}

/// The components of the intersection curve: crossing pairs linked where
/// they share one mesh's triangle and the other mesh's triangles share an
/// edge (or a vertex, where the curve passes through it).
fn components(a: &TriMesh, b: &TriMesh, intersection: &MeshIntersection) -> Vec<Vec<usize>> {
    let pairs = &intersection.pairs;
    let mut parent: Vec<usize> = (0..pairs.len()).collect();
    fn root(parent: &mut [usize], mut i: usize) -> usize {
        while parent[i] != i {
            parent[i] = parent[parent[i]];
            i = parent[i];
        }
        i
    }
    let neighbours = |mesh: &TriMesh, s: usize, t: usize| {
        let (x, y) = (mesh.triangles()[s], mesh.triangles()[t]);
        x.iter().any(|v| y.contains(v))
    };
    for (side, mesh_other) in [(Side::A, b), (Side::B, a)] {
        let mut by_triangle: HashMap<usize, Vec<usize>> = HashMap::new();
        for (k, pair) in pairs.iter().enumerate() {
            let key = if side == Side::A { pair.triangle_a } else { pair.triangle_b };
            by_triangle.entry(key).or_default().push(k);
        }
        for group in by_triangle.values() {
            for (n, &i) in group.iter().enumerate() {
                for &j in &group[n + 1..] {
                    let (ti, tj) = if side == Side::A {
                        (pairs[i].triangle_b, pairs[j].triangle_b)
                    } else {
                        (pairs[i].triangle_a, pairs[j].triangle_a)
                    };
                    if neighbours(mesh_other, ti, tj) {
                        let (ri, rj) = (root(&mut parent, i), root(&mut parent, j));
                        parent[ri] = rj;
                    }
                }
            }
        }
    }
    let mut groups: HashMap<usize, Vec<usize>> = HashMap::new();
    for k in 0..pairs.len() {
        let r = root(&mut parent, k);
        groups.entry(r).or_default().push(k);
    }
    let mut components: Vec<Vec<usize>> = groups.into_values().collect();
    components.sort_by_key(|c| c[0]);
    components
}

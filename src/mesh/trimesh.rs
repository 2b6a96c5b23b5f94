//! The validated triangle mesh.

use super::bvh::{MeshBvh, NodeVertices, BVH_LEAF_SIZE};
use super::convex_features::ConvexFeatures;
use super::distance::SLAB_TRIANGLES;
use super::mass::MassProperties;
use super::support::{self, SupportTable};
use crate::math::{Point, Real, Triangle, Vector};

/// The largest coordinate magnitude a mesh may have: `1e30`, the scene's
/// usable range too, so that the products the kernels and mass properties
/// form (up to fifth powers of a size) stay finite.
pub const MAX_COORDINATE: Real = 1e30;

/// What makes a list of vertices and triangles unusable as a mesh.
#[non_exhaustive]
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum MeshError {
    /// No triangles at all.
    #[error("the mesh has no triangles")]
    Empty,
    /// A triangle refers to a vertex that does not exist.
    #[error("triangle {triangle} refers to vertex {index}, but there are only {vertices} vertices")]
    IndexOutOfRange {
        /// The triangle (0-based).
        triangle: usize,
        /// The bad vertex index (0-based).
        index: usize,
        /// How many vertices there are.
        vertices: usize,
    },
    /// A vertex coordinate is NaN or infinite.
    #[error("vertex {vertex} has a coordinate that is not a finite number")]
    NonFinite {
        /// The vertex (0-based).
        vertex: usize,
    },
    /// A vertex coordinate is beyond [`MAX_COORDINATE`] in magnitude.
    #[error("vertex {vertex} has a coordinate beyond ±{MAX_COORDINATE:e}, the usable range (products of coordinates must stay finite)")]
    OutOfRange {
        /// The vertex (0-based).
        vertex: usize,
    },
    /// The surface is not closed and consistently oriented, which a volume
    /// (mass properties from a density) needs. Vertices count from 1, as in
    /// OBJ files.
    #[error("the mesh is not a closed surface: {0}")]
    NotClosed(String),
}

/// A triangle mesh with its bounding volume hierarchy.
///
/// Vertices are in the mesh's own frame; a body places the mesh with its
/// pose and rotates it about the frame's origin. Triangles are stored in the
/// order of the BVH's leaves.
#[derive(Clone, Debug)]
pub struct TriMesh {
    vertices: Vec<Point>,
    triangles: Vec<[u32; 3]>,
    bvh: MeshBvh,
    radius: Real,
    /// The triangles around each vertex: those of vertex `v` are
    /// `incident[incident_start[v]..incident_start[v + 1]]`.
    incident_start: Vec<u32>,
    incident: Vec<u32>,
    /// The farthest-vertex table (`None` for small meshes, scanned whole),
    /// built at the first call of [`TriMesh::farthest_vertex`]: a mesh that
    /// never needs one (a large non-convex asset) never pays for it.
    support: std::sync::OnceLock<Option<SupportTable>>,
    /// The box of the vertices in the mesh's frame: smallest and largest corners.
    bounds: (Point, Point),
    /// Whether the mesh is the boundary of its vertices' hull (see
    /// [`TriMesh::is_convex`]), decided at the first call.
    convex: std::sync::OnceLock<bool>,
    /// Faces and edges for the separating-axis depth of convex meshes,
    /// built at the first call.
    convex_features: std::sync::OnceLock<ConvexFeatures>,
    /// `1` when the triangles face outward (positive enclosed volume),
    /// `-1` when the mesh is inside out; decided at the first call.
    orientation: std::sync::OnceLock<Real>,
    /// Whether [`TriMesh::check_closed`] passes, decided at the first call.
    closed: std::sync::OnceLock<bool>,
    /// The triangles of exactly zero area, ascending (see
    /// [`TriMesh::zero_area_triangles`]).
    zero_area: Vec<u32>,
    /// Faces the file's reader dropped (see [`TriMesh::dropped_faces`]).
    dropped_faces: usize,
    /// The distinct vertices of each small BVH node (see
    /// [`TriMesh::small_node_vertices`]).
    node_vertices: NodeVertices,
}

/// How far a vertex may lie outside a triangle's plane, as a fraction of
/// the mesh's radius, for [`TriMesh::is_convex`]: about twenty times the
/// rounding of the plane test (the fourth corner of a box's split face, a
/// rotated convex OBJ), and within what the trace's certificate allows for
/// rounding (64 ulps of the pair's scale): a mesh taken as convex is its
/// hull's boundary to that rounding. Default `4e-15`.
pub(crate) const CONVEX_SURFACE_TOLERANCE: Real = 4e-15;

impl TriMesh {
    /// Validates the mesh and builds its BVH.
    ///
    /// Rejected: no triangles, an index out of range, a non-finite
    /// coordinate or one beyond [`MAX_COORDINATE`]. Triangles of zero area
    /// (repeated or collinear vertices, as real meshes hold them) are kept
    /// and take part as the segments or points they are: the distance
    /// kernels, the CCD and the inside tests treat them exactly, and they
    /// add nothing to a volume. [`TriMesh::zero_area_triangles`] counts them.
    pub fn new(vertices: Vec<Point>, triangles: Vec<[u32; 3]>) -> Result<TriMesh, MeshError> {
        if triangles.is_empty() {
            return Err(MeshError::Empty);
        }
        check_coordinates(&vertices)?;
        for (triangle, indices) in triangles.iter().enumerate() {
            for &index in indices {
                if index as usize >= vertices.len() {
                    return Err(MeshError::IndexOutOfRange {
                        triangle,
                        index: index as usize,
                        vertices: vertices.len(),
                    });
                }
            }
        }
        let (bvh, triangles) = MeshBvh::build(&vertices, triangles);
        let mut incident_start = vec![0u32; vertices.len() + 1];
        for &v in triangles.iter().flatten() {
            incident_start[v as usize + 1] += 1;
        }
        for v in 0..vertices.len() {
            incident_start[v + 1] += incident_start[v];
        }
        let mut filled = incident_start.clone();
        let mut incident = vec![0u32; 3 * triangles.len()];
        for (t, triangle) in triangles.iter().enumerate() {
            for &v in triangle {
                incident[filled[v as usize] as usize] = t as u32;
                filled[v as usize] += 1;
            }
        }
        let node_vertices = NodeVertices::of(&bvh, &triangles, SLAB_TRIANGLES);
        Ok(TriMesh::assemble(vertices, triangles, (bvh, node_vertices), (incident_start, incident)))
    }

    /// The mesh from checked vertices, triangles in its BVH's order, the BVH
    /// with its small nodes' vertices, and the triangles around each
    /// vertex; what follows from them is computed here (the rest at first
    /// use).
    fn assemble(
        vertices: Vec<Point>,
        triangles: Vec<[u32; 3]>,
        (bvh, node_vertices): (MeshBvh, NodeVertices),
        (incident_start, incident): (Vec<u32>, Vec<u32>),
    ) -> TriMesh {
        let zero_area = (0..triangles.len() as u32)
            .filter(|&t| {
                let [a, b, c] = triangles[t as usize].map(|i| vertices[i as usize]);
                has_zero_area(&a, &b, &c)
            })
            .collect();
        let radius = vertices.iter().map(|v| v.coords.norm()).fold(0.0, Real::max);
        // Triangles exist and index vertices: there is a first vertex.
        let bounds =
            vertices.iter().fold((vertices[0], vertices[0]), |(low, high), v| (low.inf(v), high.sup(v)));
        TriMesh {
            vertices,
            triangles,
            bvh,
            radius,
            incident_start,
            incident,
            support: std::sync::OnceLock::new(),
            bounds,
            convex: std::sync::OnceLock::new(),
            convex_features: std::sync::OnceLock::new(),
            orientation: std::sync::OnceLock::new(),
            closed: std::sync::OnceLock::new(),
            zero_area,
            dropped_faces: 0,
            node_vertices,
        }
    }

    /// How many triangles have exactly zero area (repeated or collinear
    /// vertices, decided with exact predicates). They are kept: each takes
    /// part as the segment or point it spans.
    pub fn zero_area_triangles(&self) -> usize {
        self.zero_area.len()
    }

    /// Whether triangle `t` has exactly zero area (its normal is zero: it
    /// bounds no volume and has no side).
    pub fn is_zero_area(&self, t: usize) -> bool {
        !self.zero_area.is_empty() && self.zero_area.binary_search(&(t as u32)).is_ok()
    }

    /// How many faces the file's reader dropped because they had fewer than
    /// three vertices (an OBJ `f` line of one or two: a point or a line,
    /// not a face); 0 for a mesh made from arrays.
    pub fn dropped_faces(&self) -> usize {
        self.dropped_faces
    }

    /// The mesh, noting that its reader dropped `count` faces.
    pub(crate) fn with_dropped_faces(mut self, count: usize) -> TriMesh {
        self.dropped_faces = count;
        self
    }

    /// The triangles that have vertex `v` as a corner.
    pub fn triangles_at(&self, v: usize) -> &[u32] {
        &self.incident[self.incident_start[v] as usize..self.incident_start[v + 1] as usize]
    }

    /// The first vertex farthest along `direction` (the first largest dot
    /// product, as a scan over every vertex finds it; its index), found by
    /// the mesh's table of directions (see the `support` module) for
    /// meshes of `SUPPORT_TABLE_MIN_VERTICES`
    /// vertices or more.
    #[inline]
    pub fn farthest_vertex(&self, direction: &Vector) -> usize {
        match self.support_table().as_ref().and_then(|table| table.candidates(direction)) {
            Some(candidates) => support::farthest_of(&self.vertices, candidates, direction),
            None => support::farthest_by_scan(&self.vertices, direction),
        }
    }

    /// Builds the farthest-vertex table now (see
    /// [`TriMesh::farthest_vertex`]), which the first query that needs it
    /// otherwise builds.
    pub(crate) fn prepare_farthest_vertex(&self) {
        self.support_table();
    }

    /// The farthest-vertex table (`None` for a mesh too small for one),
    /// built at the first call.
    fn support_table(&self) -> &Option<SupportTable> {
        self.support.get_or_init(|| SupportTable::build(&self.vertices))
    }

    /// Bytes the mesh holds on the heap: vertices, triangles, BVH (with its
    /// small nodes' vertices), the triangles around each vertex, and the
    /// farthest-vertex table (once built).
    pub fn heap_bytes(&self) -> usize {
        std::mem::size_of_val(self.vertices.as_slice())
            + std::mem::size_of_val(self.triangles.as_slice())
            + std::mem::size_of_val(self.bvh.nodes())
            + self.node_vertices.bytes()
            + 4 * (self.incident_start.len() + self.incident.len())
            + self.support.get().and_then(Option::as_ref).map_or(0, SupportTable::bytes)
            + 4 * self.zero_area.len()
    }

    /// The vertices, in the mesh's frame.
    pub fn vertices(&self) -> &[Point] {
        &self.vertices
    }

    /// The triangles as vertex indices, in BVH leaf order.
    pub fn triangles(&self) -> &[[u32; 3]] {
        &self.triangles
    }

    /// Triangle `i` as points in the mesh's frame.
    #[inline]
    pub fn triangle(&self, i: usize) -> Triangle {
        // Spelled out: `array::map` here was left out of line in some
        // builds (a call per vertex in the distance search's inner loop).
        let [a, b, c] = self.triangles[i];
        [self.vertices[a as usize], self.vertices[b as usize], self.vertices[c as usize]]
    }

    /// The bounding volume hierarchy.
    pub fn bvh(&self) -> &MeshBvh {
        &self.bvh
    }

    /// The distinct vertices (indices into [`TriMesh::vertices`]) of the
    /// triangles under BVH node `k`, where it holds at most
    /// [`SLAB_TRIANGLES`] of them; `None` where it holds more. The table is
    /// built with the BVH.
    #[inline]
    pub(crate) fn small_node_vertices(&self, k: u32) -> Option<&[u32]> {
        self.node_vertices.of_node(k)
    }

    /// The distinct vertices of leaf node `k`'s triangles: every leaf
    /// (at most [`BVH_LEAF_SIZE`] triangles) is a small node, so they are
    /// listed.
    #[inline]
    pub(crate) fn leaf_vertices(&self, k: u32) -> &[u32] {
        const _: () = assert!(BVH_LEAF_SIZE as u32 <= SLAB_TRIANGLES);
        self.small_node_vertices(k).expect("a leaf's vertices are listed with the tree")
    }

    /// The box of the vertices in the mesh's frame: smallest and largest corners.
    pub fn bounds(&self) -> (Point, Point) {
        self.bounds
    }

    /// The largest distance of a vertex from the frame's origin (the centre
    /// of rotation): bounds the speed of any point of the rotating mesh.
    pub fn radius(&self) -> Real {
        self.radius
    }

    /// Whether the mesh is closed (see [`TriMesh::check_closed`]) and every
    /// vertex lies on the same side of every triangle's plane, within
    /// `CONVEX_SURFACE_TOLERANCE` of the radius: then the surface is the
    /// boundary of its vertices' convex hull, and the closest points of two
    /// such hulls (apart) lie on the meshes. Decided once per mesh
    /// ([`TriMesh::convex_within`]).
    pub fn is_convex(&self) -> bool {
        *self.convex.get_or_init(|| self.convex_within(CONVEX_SURFACE_TOLERANCE))
    }

    /// The faces and edges of a convex mesh for
    /// [`convex_penetration`](super::convex_penetration), built once.
    pub(crate) fn convex_features(&self) -> &ConvexFeatures {
        self.convex_features.get_or_init(|| ConvexFeatures::of(&self.vertices, &self.triangles))
    }

    /// Whether the surface is closed and consistently oriented
    /// ([`TriMesh::check_closed`] passes), decided once.
    pub fn is_closed(&self) -> bool {
        *self.closed.get_or_init(|| self.check_closed().is_ok())
    }

    /// `1` when the triangles face outward (the signed volume they enclose
    /// is not negative), `-1` when the mesh is inside out.
    pub(crate) fn orientation(&self) -> Real {
        *self.orientation.get_or_init(|| {
            let volume: Real = (0..self.triangles.len())
                .map(|t| {
                    let [p, q, r] = self.triangle(t);
                    p.coords.dot(&q.coords.cross(&r.coords))
                })
                .sum();
            if volume < 0.0 {
                -1.0
            } else {
                1.0
            }
        })
    }

    /// Whether the mesh is closed and every vertex lies on the same side of
    /// every triangle's plane (all on the inner side, or all on the outer
    /// side for a mesh turned inside out) within `fraction` of the radius;
    /// a triangle whose normal rounds to zero is not convex. Decided by the
    /// farthest vertex along each triangle's normal and against it.
    pub fn convex_within(&self, fraction: Real) -> bool {
        if !self.is_closed() {
            return false;
        }
        let slack = fraction * self.radius;
        let (mut outward, mut inward) = (true, true);
        for t in 0..self.triangles.len() {
            let [p, q, r] = self.triangle(t);
            let normal = (q - p).cross(&(r - p));
            let length = normal.norm();
            let beyond = |n: Vector| {
                let far = self.vertices[self.farthest_vertex(&n)];
                far.coords.dot(&n) - p.coords.dot(&n) > slack * length
            };
            outward = outward && !beyond(normal);
            inward = inward && !beyond(-normal);
            if !(length > 0.0 && (outward || inward)) {
                return false;
            }
        }
        true
    }

    /// Checks that the surface is closed and consistently oriented: every
    /// edge is shared by exactly two triangles that run along it in
    /// opposite directions. The error names the first edge that is not.
    pub fn check_closed(&self) -> Result<(), MeshError> {
        // Each edge of each triangle as (its lower vertex, its higher one;
        // the vertex it runs from, the triangle), packed in two words and
        // sorted: the uses of one edge are adjacent, those running from
        // the lower vertex first, each by triangle number. One sort and
        // one pass (a 57,640-face gear ring in about 6 ms).
        let mut edges: Vec<(u64, u64)> = Vec::with_capacity(3 * self.triangles.len());
        for (t, tri) in self.triangles.iter().enumerate() {
            for k in 0..3 {
                let (from, to) = (tri[k] as u64, tri[(k + 1) % 3] as u64);
                edges.push((from.min(to) << 32 | from.max(to), from << 32 | t as u64));
            }
        }
        edges.sort_unstable();
        let (high, low) = (|word: u64| (word >> 32) as u32, |word: u64| word as u32);
        let from_of = |edge: &(u64, u64)| high(edge.1);
        let triangles = |uses: &[(u64, u64)]| {
            uses.iter().map(|e| (low(e.1) + 1).to_string()).collect::<Vec<_>>().join(", ")
        };
        // The edges in order of their vertex numbers, each way along one
        // in order of the vertex it runs from: the first problem is the
        // one with the lowest numbers, the same every run.
        for uses in edges.chunk_by(|x, y| x.0 == y.0) {
            let (first, second) = (high(uses[0].0), low(uses[0].0));
            let split = uses.partition_point(|e| from_of(e) == first);
            let (up, down) = uses.split_at(split);
            for (along, back, (from, to)) in [(up, down, (first, second)), (down, up, (second, first))] {
                // A collapsed edge (first = second) runs both ways at once.
                let back = if first == second { along } else { back };
                let (a, b) = (from + 1, to + 1);
                let message = if along.len() > 1 {
                    format!(
                        "triangles {} all run from vertex {a} to vertex {b} (an edge shared by more than two faces, a duplicated face, or faces oriented inconsistently)",
                        triangles(along)
                    )
                } else if along.len() == 1 && back.is_empty() {
                    format!(
                        "the edge between vertices {a} and {b} belongs to triangle {} only (an open edge: a missing face)",
                        triangles(along)
                    )
                } else {
                    continue;
                };
                return Err(MeshError::NotClosed(format!("{message}; triangles count from 1")));
            }
        }
        Ok(())
    }

    /// Volume, centre of mass and inertia at unit density, if the mesh
    /// encloses a positive volume (closed, outward-facing triangles; see
    /// [`TriMesh::check_closed`]).
    pub fn mass_properties(&self) -> Option<MassProperties> {
        MassProperties::of_surface(&self.vertices, &self.triangles)
    }

    /// The mesh scaled uniformly about its origin (an error if the scaling
    /// takes a coordinate out of range).
    pub fn scaled(&self, factor: Real) -> Result<TriMesh, MeshError> {
        let scaled =
            TriMesh::new(self.vertices.iter().map(|v| v * factor).collect(), self.triangles.clone())?;
        Ok(scaled.with_dropped_faces(self.dropped_faces))
    }

    /// The same mesh moved so that `origin` becomes the frame's origin (for
    /// a point of the mesh's hull, whose moved vertices stay in range; the
    /// mesh as it is where rounding says not).
    pub fn recentered(&self, origin: &Point) -> TriMesh {
        let shift: Vector = origin.coords;
        let vertices = self.vertices.iter().map(|v| v - shift).collect();
        match TriMesh::new(vertices, self.triangles.clone()) {
            Ok(moved) => moved.with_dropped_faces(self.dropped_faces),
            Err(_) => self.clone(),
        }
    }

    /// The mesh in the frame whose origin is its point `about` (vertices
    /// minus `about`), for a body that turns about that point
    /// ([`StepMotion::between_about`](crate::motion::StepMotion::between_about)).
    /// An error where a moved vertex leaves the usable range.
    ///
    /// The triangles keep their order (a witness triangle's index is the
    /// same in both) and the tree its shape: its nodes move with the
    /// vertices, each widened by the rounding of the move.
    pub fn pivoted(&self, about: &Point) -> Result<TriMesh, MeshError> {
        let shift: Vector = about.coords;
        let vertices: Vec<Point> = self.vertices.iter().map(|v| v - shift).collect();
        check_coordinates(&vertices)?;
        let bvh = self.bvh.translated(&shift);
        let incident = (self.incident_start.clone(), self.incident.clone());
        // The same triangles in the same tree: the same nodes' vertices.
        let tree = (bvh, self.node_vertices.clone());
        Ok(TriMesh::assemble(vertices, self.triangles.clone(), tree, incident)
            .with_dropped_faces(self.dropped_faces))
    }
}

impl TriMesh {
    /// The same mesh as parry's `TriMesh` (for comparisons with the peer
    /// and rapier's colliders) without its zero-area triangles, which parry
    /// gives a normal of NaN; `None` if parry refuses it.
    pub fn to_parry(&self) -> Option<parry3d_f64::shape::TriMesh> {
        let vertices = self.vertices.iter().map(crate::math::to_parry).collect();
        let triangles = self.triangles_with_area().collect();
        parry3d_f64::shape::TriMesh::new(vertices, triangles).ok()
    }

    /// The triangles of non-zero area, as vertex indices.
    pub fn triangles_with_area(&self) -> impl Iterator<Item = [u32; 3]> + '_ {
        (0..self.triangles.len()).filter(|&t| !self.is_zero_area(t)).map(|t| self.triangles[t])
    }
}

/// Every coordinate finite and within [`MAX_COORDINATE`].
fn check_coordinates(vertices: &[Point]) -> Result<(), MeshError> {
    if let Some(vertex) = vertices.iter().position(|v| !v.coords.iter().all(|c| c.is_finite())) {
        return Err(MeshError::NonFinite { vertex });
    }
    if let Some(vertex) = vertices.iter().position(|v| v.coords.amax() > MAX_COORDINATE) {
        return Err(MeshError::OutOfRange { vertex });
    }
    Ok(())
}

/// Whether a triangle has exactly zero area: all three coordinate-plane
/// projections are degenerate (exact orientation predicates).
fn has_zero_area(a: &Point, b: &Point, c: &Point) -> bool {
    let orient = |i: usize, j: usize| {
        let p = |q: &Point| robust::Coord { x: q[i], y: q[j] };
        robust::orient2d(p(a), p(b), p(c))
    };
    orient(0, 1) == 0.0 && orient(1, 2) == 0.0 && orient(2, 0) == 0.0
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn primitives_are_closed_and_a_lone_triangle_or_a_flipped_face_is_not() {
        use crate::mesh::{box_mesh, icosphere, single_triangle, tetrahedron};
        for mesh in [box_mesh(&Vector::new(1.0, 2.0, 3.0)), icosphere(1.0, 2), tetrahedron(1.0)] {
            assert_eq!(mesh.unwrap().check_closed(), Ok(()));
        }
        let lone = single_triangle(Point::origin(), Point::new(1.0, 0.0, 0.0), Point::new(0.0, 1.0, 0.0));
        assert!(matches!(lone.unwrap().check_closed(), Err(MeshError::NotClosed(_))));
        let tetra = tetrahedron(1.0).unwrap();
        let mut triangles = tetra.triangles().to_vec();
        triangles[0].swap(1, 2);
        let flipped = TriMesh::new(tetra.vertices().to_vec(), triangles).unwrap();
        assert!(matches!(flipped.check_closed(), Err(MeshError::NotClosed(m)) if m.contains("all run from")));
    }

    /// The message names the edge with the lowest vertex numbers, and the
    /// triangles on it (a tetrahedron, worked out by hand).
    #[test]
    fn the_first_open_or_shared_edge_is_named() {
        let tetra = crate::mesh::tetrahedron(1.0).unwrap();
        let vertices = tetra.vertices().to_vec();
        // Closed: every directed edge has its reverse in another face.
        let faces = vec![[0, 1, 2], [0, 3, 1], [1, 3, 2], [2, 3, 0]];
        let closed = TriMesh::new(vertices.clone(), faces.clone()).unwrap();
        assert_eq!(closed.check_closed(), Ok(()));
        // Without [1, 3, 2], the edges 1→2, 3→1 and 2→3 lose their
        // reverses: the first by vertex numbers is {1, 2} (2 and 3 counting
        // from 1), in the face that holds 1→2.
        let open = TriMesh::new(vertices.clone(), vec![faces[0], faces[1], faces[3]]).unwrap();
        let holding = |mesh: &TriMesh, from: u32, to: u32| -> Vec<usize> {
            let runs = |t: &[u32; 3]| (0..3).any(|k| t[k] == from && t[(k + 1) % 3] == to);
            mesh.triangles().iter().enumerate().filter(|(_, t)| runs(t)).map(|(k, _)| k + 1).collect()
        };
        let t = holding(&open, 1, 2)[0];
        let expected = format!("the edge between vertices 2 and 3 belongs to triangle {t} only (an open edge: a missing face); triangles count from 1");
        assert_eq!(open.check_closed(), Err(MeshError::NotClosed(expected)));
        // [0, 1, 2] twice: 0→1, 1→2 and 2→0 each run in two faces; {0, 1} first.
        let doubled = TriMesh::new(vertices, vec![faces[0], faces[1], faces[2], faces[3], faces[0]]).unwrap();
        let both = holding(&doubled, 0, 1);
        let expected = format!("triangles {}, {} all run from vertex 1 to vertex 2 (an edge shared by more than two faces, a duplicated face, or faces oriented inconsistently); triangles count from 1", both[0], both[1]);
        assert_eq!(doubled.check_closed(), Err(MeshError::NotClosed(expected)));
    }

    fn unit_triangle() -> Vec<Point> {
        vec![Point::new(0.0, 0.0, 0.0), Point::new(1.0, 0.0, 0.0), Point::new(0.0, 1.0, 0.0)]
    }

    #[test]
    fn rejects_bad_meshes_with_the_reason() {
        assert_eq!(TriMesh::new(unit_triangle(), vec![]).unwrap_err(), MeshError::Empty);
        assert_eq!(
            TriMesh::new(unit_triangle(), vec![[0, 1, 3]]).unwrap_err(),
            MeshError::IndexOutOfRange { triangle: 0, index: 3, vertices: 3 }
        );
        let mut nan = unit_triangle();
        nan[2].y = Real::NAN;
        assert_eq!(TriMesh::new(nan, vec![[0, 1, 2]]).unwrap_err(), MeshError::NonFinite { vertex: 2 });
        let mut huge = unit_triangle();
        huge[1].z = -1e31;
        assert_eq!(TriMesh::new(huge, vec![[0, 1, 2]]).unwrap_err(), MeshError::OutOfRange { vertex: 1 });
    }

    #[test]
    fn keeps_and_counts_zero_area_triangles() {
        let collinear = vec![Point::new(0.0, 0.0, 0.0), Point::new(1.0, 1.0, 1.0), Point::new(3.0, 3.0, 3.0)];
        let segment = TriMesh::new(collinear, vec![[0, 1, 2], [0, 0, 2], [1, 1, 1]]).unwrap();
        assert_eq!(segment.zero_area_triangles(), 3);
        assert_eq!(segment.dropped_faces(), 0);
        let needle = vec![Point::new(0.0, 0.0, 0.0), Point::new(1.0, 0.0, 0.0), Point::new(0.5, 1e-300, 0.0)];
        assert_eq!(TriMesh::new(needle, vec![[0, 1, 2]]).unwrap().zero_area_triangles(), 0);
    }

    #[test]
    fn accepts_a_needle() {
        let needle = vec![Point::new(0.0, 0.0, 0.0), Point::new(1.0, 0.0, 0.0), Point::new(0.5, 1e-12, 0.0)];
        assert!(TriMesh::new(needle, vec![[0, 1, 2]]).is_ok());
    }
}

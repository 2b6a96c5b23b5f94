//! What a convex mesh offers the separating-axis test: its faces' outward
//! normals and its solid edges with the arcs of their normals, built once
//! per mesh in its own frame.

use crate::math::{Point, Real, Vector};

/// Adjacent triangles whose unit normals differ by less than this are
/// coplanar: their shared edge is not an edge of the solid. Default
/// `1e-12`.
pub(crate) const FLAT_EDGE_TOLERANCE: Real = 1e-12;

/// What a convex mesh offers the separating-axis test, built once per mesh
/// (in its own frame).
#[derive(Clone, Debug)]
pub(crate) struct ConvexFeatures {
    /// A point strictly inside the solid (the vertices' mean).
    pub(super) interior: Point,
    /// Each triangle's outward unit normal and a point of it.
    pub(super) faces: Vec<(Vector, Point)>,
    /// Each edge between non-coplanar triangles: a point, its direction,
    /// and the outward unit normals of its two triangles.
    pub(super) edges: Vec<FeatureEdge>,
}

#[derive(Copy, Clone, Debug)]
pub(super) struct FeatureEdge {
    pub(super) point: Point,
    pub(super) direction: Vector,
    /// The outward normals of its two triangles: its arc's ends.
    pub(super) normals: [Vector; 2],
    /// `normals[1] × normals[0]`.
    pub(super) normals_cross: Vector,
    /// The box of its arc on the unit sphere.
    pub(super) arc_box: ArcBox,
}

impl FeatureEdge {
    pub(super) fn new(point: Point, direction: Vector, normals: [Vector; 2]) -> FeatureEdge {
        FeatureEdge {
            point,
            direction,
            normals,
            normals_cross: normals[1].cross(&normals[0]),
            arc_box: ArcBox::of(&normals[0], &normals[1]),
        }
    }
}

/// Where a great-circle arc between unit vectors can be: the box of its
/// ends and the meeting point of the tangents at its ends (the arc lies in
/// that triangle), widened by [`ARC_BOX_SLACK`] for rounding.
#[derive(Copy, Clone, Debug)]
pub(super) struct ArcBox {
    pub(super) low: Vector,
    pub(super) high: Vector,
}

/// How much an arc's box is widened, in absolute units on the unit
/// sphere: far above the rounding of its corners (a few ulps), far below
/// any arc that matters. Default `1e-9`.
const ARC_BOX_SLACK: Real = 1e-9;

/// An arc whose half angle has a cosine below this (ends all but
/// opposite: the two triangles of a knife edge) gets the whole sphere's
/// box: its tangents meet too far out to bound it usefully. Default `1e-6`.
const WIDE_ARC_COSINE: Real = 1e-6;

impl ArcBox {
    pub(super) fn of(a: &Vector, b: &Vector) -> ArcBox {
        let sum = a + b;
        let length = sum.norm();
        // Half the arc's angle is below 90° (its ends are not opposite):
        // the tangents meet at the midpoint over the cosine of that half.
        let cosine = if length > 0.0 { (sum / length).dot(a) } else { 0.0 };
        if cosine <= WIDE_ARC_COSINE {
            return ArcBox {
                low: Vector::repeat(-1.0 - ARC_BOX_SLACK),
                high: Vector::repeat(1.0 + ARC_BOX_SLACK),
            };
        }
        let apex = sum / (length * cosine);
        let low = a.inf(b).inf(&apex) - Vector::repeat(ARC_BOX_SLACK);
        let high = a.sup(b).sup(&apex) + Vector::repeat(ARC_BOX_SLACK);
        ArcBox { low, high }
    }

    #[inline]
    pub(super) fn overlaps_in_y_z(&self, other: &ArcBox) -> bool {
        self.low.y <= other.high.y
            && other.low.y <= self.high.y
            && self.low.z <= other.high.z
            && other.low.z <= self.high.z
    }
}

impl ConvexFeatures {
    /// The features of the mesh of `vertices` and `triangles`, which must be
    /// convex ([`TriMesh::is_convex`](super::TriMesh::is_convex)).
    pub(crate) fn of(vertices: &[Point], triangles: &[[u32; 3]]) -> ConvexFeatures {
        let interior =
            Point::from(vertices.iter().map(|v| v.coords).sum::<Vector>() / vertices.len() as Real);
        let faces: Vec<(Vector, Point)> = triangles
            .iter()
            .map(|t| {
                let [p, q, r] = t.map(|k| vertices[k as usize]);
                let n = (q - p).cross(&(r - p)).normalize();
                // Outward: away from the interior (convex, so one test decides).
                (if n.dot(&(p - interior)) < 0.0 { -n } else { n }, p)
            })
            .collect();
        let mut edges = Vec::new();
        let mut seen = std::collections::HashMap::new();
        for (t, triangle) in triangles.iter().enumerate() {
            for k in 0..3 {
                let (from, to) = (triangle[k], triangle[(k + 1) % 3]);
                let key = (from.min(to), from.max(to));
                match seen.remove(&key) {
                    None => {
                        seen.insert(key, t);
                    }
                    Some(other) => {
                        let normals = [faces[other].0, faces[t].0];
                        if (normals[0] - normals[1]).norm() > FLAT_EDGE_TOLERANCE {
                            let (p, q) = (vertices[from as usize], vertices[to as usize]);
                            edges.push(FeatureEdge::new(p, q - p, normals));
                        }
                    }
                }
            }
        }
        edges.sort_by(|e, f| e.arc_box.low.x.total_cmp(&f.arc_box.low.x));
        ConvexFeatures { interior, faces, edges }
    }
}

//! GJK's simplex: the closest point of a segment, triangle or tetrahedron
//! to the origin, and which of its points are kept.

use crate::math::{Pose, Real, Vector};
use crate::mesh::TriMesh;

/// The triangles around a vertex, ordered by how squarely they face a
/// direction (their unit normal along it, most first); kept on the stack
/// for up to [`Facing::MOST`] triangles, more are taken in their order.
#[derive(Copy, Clone, Debug)]
pub(super) struct Facing {
    pub(super) order: [u32; Facing::MOST],
    pub(super) len: usize,
}

impl Facing {
    const MOST: usize = 16;

    /// The triangles of `mesh` around `vertex`, posed by `pose`, facing
    /// `direction` (none: in their order).
    pub(super) fn around(mesh: &TriMesh, vertex: usize, pose: &Pose, direction: Option<Vector>) -> Facing {
        let triangles = mesh.triangles_at(vertex);
        let mut facing = Facing { order: [0; Facing::MOST], len: 0 };
        let Some(direction) = direction.filter(|_| triangles.len() <= Facing::MOST) else {
            return facing;
        };
        let mut score = [0.0; Facing::MOST];
        for (k, &t) in triangles.iter().enumerate() {
            let [p, q, r] = mesh.triangle(t as usize);
            let normal = pose.rotation * (q - p).cross(&(r - p));
            // A zero-area triangle (no normal) faces nowhere: last.
            let length = normal.norm();
            let along = if length > 0.0 { normal.dot(&direction) / length } else { Real::NEG_INFINITY };
            // Insertion by score, highest first (stable: equals keep their order).
            let mut at = k;
            while at > 0 && score[at - 1] < along {
                score[at] = score[at - 1];
                facing.order[at] = facing.order[at - 1];
                at -= 1;
            }
            score[at] = along;
            facing.order[at] = t;
        }
        facing.len = triangles.len();
        facing
    }

    /// The triangles in facing order (`triangles`, the same set, when not ordered).
    pub(super) fn order<'t>(&'t self, triangles: &'t [u32]) -> impl Iterator<Item = usize> + 't {
        let ordered = if self.len > 0 { &self.order[..self.len] } else { triangles };
        ordered.iter().map(|&t| t as usize)
    }
}

/// GJK's simplex: up to four points of the hulls' difference, each with
/// the vertices (a's, b's) it is the difference of.
#[derive(Copy, Clone, Debug, Default)]
pub(super) struct Simplex {
    pub(super) points: [Vector; 4],
    pub(super) pairs: [(u32, u32); 4],
    pub(super) len: usize,
}

impl Simplex {
    pub(super) fn push(&mut self, w: Vector, pair: (u32, u32)) {
        self.points[self.len] = w;
        self.pairs[self.len] = pair;
        self.len += 1;
    }

    /// The point of the simplex closest to the origin; the simplex keeps
    /// only the points that span it (empty when the origin is inside: the
    /// hulls overlap, and the zero vector is returned).
    pub(super) fn closest_to_origin(&mut self) -> Vector {
        let (p, pairs) = (self.points, self.pairs);
        let (closest, kept) = match self.len {
            1 => (p[0], Kept::of(&[0])),
            2 => closest_on_segment(p[0], p[1]),
            3 => closest_on_triangle(p[0], p[1], p[2]),
            _ => closest_on_tetrahedron(&p),
        };
        self.len = 0;
        for k in kept.indices() {
            self.push(p[k], pairs[k]);
        }
        closest
    }
}

/// Which of a simplex's points span the closest point (indices, in order).
#[derive(Copy, Clone, Debug, Default)]
pub(super) struct Kept {
    pub(super) indices: [usize; 3],
    pub(super) len: usize,
}

impl Kept {
    pub(super) fn of(indices: &[usize]) -> Kept {
        let mut kept = Kept::default();
        for &k in indices {
            kept.indices[kept.len] = k;
            kept.len += 1;
        }
        kept
    }

    pub(super) fn indices(&self) -> impl Iterator<Item = usize> + '_ {
        self.indices[..self.len].iter().copied()
    }

    /// The same points, renumbered through `map`.
    pub(super) fn mapped(self, map: [usize; 3]) -> Kept {
        let mut kept = self;
        for k in &mut kept.indices[..kept.len] {
            *k = map[*k];
        }
        kept
    }
}

/// The point of segment `[a, b]` closest to the origin.
pub(super) fn closest_on_segment(a: Vector, b: Vector) -> (Vector, Kept) {
    let ab = b - a;
    let length2 = ab.norm_squared();
    let t = if length2 > 0.0 { -a.dot(&ab) / length2 } else { 0.0 };
    if t <= 0.0 {
        (a, Kept::of(&[0]))
    } else if t >= 1.0 {
        (b, Kept::of(&[1]))
    } else {
        (a + ab * t, Kept::of(&[0, 1]))
    }
}

/// The point of triangle `abc` closest to the origin, by its Voronoi
/// regions (vertices, edges, face).
pub(super) fn closest_on_triangle(a: Vector, b: Vector, c: Vector) -> (Vector, Kept) {
    let (ab, ac) = (b - a, c - a);
    let (d1, d2) = (-ab.dot(&a), -ac.dot(&a));
    if d1 <= 0.0 && d2 <= 0.0 {
        return (a, Kept::of(&[0]));
    }
    let (d3, d4) = (-ab.dot(&b), -ac.dot(&b));
    if d3 >= 0.0 && d4 <= d3 {
        return (b, Kept::of(&[1]));
    }
    let vc = d1 * d4 - d3 * d2;
    if vc <= 0.0 && d1 >= 0.0 && d3 <= 0.0 {
        return (a + ab * (d1 / (d1 - d3)), Kept::of(&[0, 1]));
    }
    let (d5, d6) = (-ab.dot(&c), -ac.dot(&c));
    if d6 >= 0.0 && d5 <= d6 {
        return (c, Kept::of(&[2]));
    }
    let vb = d5 * d2 - d1 * d6;
    if vb <= 0.0 && d2 >= 0.0 && d6 <= 0.0 {
        return (a + ac * (d2 / (d2 - d6)), Kept::of(&[0, 2]));
    }
    let va = d3 * d6 - d5 * d4;
    if va <= 0.0 && d4 - d3 >= 0.0 && d5 - d6 >= 0.0 {
        let t = (d4 - d3) / ((d4 - d3) + (d5 - d6));
        return (b + (c - b) * t, Kept::of(&[1, 2]));
    }
    let sum = va + vb + vc;
    if sum.is_nan() || sum <= 0.0 {
        // A degenerate triangle: the best of its edges.
        let edges = [closest_on_segment(a, b), closest_on_segment(a, c), closest_on_segment(b, c)];
        let maps = [[0, 1, 0], [0, 2, 0], [1, 2, 0]];
        let (k, (point, kept)) = edges
            .into_iter()
            .enumerate()
            .min_by(|x, y| x.1 .0.norm_squared().total_cmp(&y.1 .0.norm_squared()))
            .expect("three edges");
        return (point, kept.mapped(maps[k]));
    }
    (a + ab * (vb / sum) + ac * (vc / sum), Kept::of(&[0, 1, 2]))
}

/// The point of tetrahedron `p` closest to the origin: the closest over the
/// faces the origin lies outside of, or the origin itself when inside
/// (returned with no point kept).
pub(super) fn closest_on_tetrahedron(p: &[Vector; 4]) -> (Vector, Kept) {
    const FACES: [([usize; 3], usize); 4] = [([0, 1, 2], 3), ([0, 1, 3], 2), ([0, 2, 3], 1), ([1, 2, 3], 0)];
    let mut best: Option<(Vector, Kept)> = None;
    for (face, opposite) in FACES {
        let [i, j, k] = face;
        let normal = (p[j] - p[i]).cross(&(p[k] - p[i]));
        // The origin and the opposite vertex on different sides (or a flat
        // tetrahedron): the face may hold the closest point.
        if normal.dot(&-p[i]) * normal.dot(&(p[opposite] - p[i])) <= 0.0 {
            let (point, kept) = closest_on_triangle(p[i], p[j], p[k]);
            if best.is_none_or(|(b, _)| point.norm_squared() < b.norm_squared()) {
                best = Some((point, kept.mapped(face)));
            }
        }
    }
    best.unwrap_or((Vector::zeros(), Kept::default()))
}

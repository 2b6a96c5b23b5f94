//! Primitive meshes, centred on their frame's origin (the centre of
//! rotation), triangles facing outward.

use std::collections::HashMap;

use super::trimesh::{MeshError, TriMesh};
use crate::math::{Point, Real, Vector};

/// The most subdivisions an icosphere may have: 20 × 4⁷ = 327,680 triangles.
pub const MAX_ICOSPHERE_SUBDIVISIONS: u32 = 7;

/// An axis-aligned box with the given half extents (12 triangles).
pub fn box_mesh(half_extents: &Vector) -> Result<TriMesh, MeshError> {
    let h = half_extents;
    let vertices: Vec<Point> = (0..8)
        .map(|i| {
            let sign = |bit: usize| if i & bit == 0 { -1.0 } else { 1.0 };
            Point::new(sign(1) * h.x, sign(2) * h.y, sign(4) * h.z)
        })
        .collect();
    // Each face: the four corners whose coordinate along `axis` has `bit` set
    // (or not), split into two triangles.
    let mut triangles = Vec::with_capacity(12);
    for axis in 0..3 {
        let bit = 1 << axis;
        let (u, w) = (1 << ((axis + 1) % 3), 1 << ((axis + 2) % 3));
        for side in [0, bit] {
            let quad = [side, side | u, side | u | w, side | w];
            triangles.push(outward(&vertices, [quad[0], quad[1], quad[2]]));
            triangles.push(outward(&vertices, [quad[0], quad[2], quad[3]]));
        }
    }
    TriMesh::new(vertices, triangles)
}

/// A regular tetrahedron whose vertices lie at `circumradius` from the
/// origin (4 triangles).
pub fn tetrahedron(circumradius: Real) -> Result<TriMesh, MeshError> {
    let s = circumradius / Real::sqrt(3.0);
    let vertices =
        vec![Point::new(s, s, s), Point::new(s, -s, -s), Point::new(-s, s, -s), Point::new(-s, -s, s)];
    let triangles = [[0, 1, 2], [0, 1, 3], [0, 2, 3], [1, 2, 3]].map(|t| outward(&vertices, t)).to_vec();
    TriMesh::new(vertices, triangles)
}

/// An icosahedron subdivided `subdivisions` times, vertices on the sphere of
/// `radius` (20 × 4^subdivisions triangles). From one subdivision on it has
/// vertices exactly at `±radius` on each axis.
pub fn icosphere(radius: Real, subdivisions: u32) -> Result<TriMesh, MeshError> {
    let phi = (1.0 + Real::sqrt(5.0)) / 2.0;
    let mut unit: Vec<Vector> = Vec::new();
    for a in [-1.0, 1.0] {
        for b in [-phi, phi] {
            unit.push(Vector::new(0.0, a, b));
            unit.push(Vector::new(a, b, 0.0));
            unit.push(Vector::new(b, 0.0, a));
        }
    }
    // The faces are the triples of mutually adjacent vertices (edge length 2).
    let adjacent = |i: usize, j: usize| ((unit[i] - unit[j]).norm_squared() - 4.0).abs() < 1e-9;
    let mut corners: Vec<Point> = unit.iter().map(|v| Point::from(v.normalize())).collect();
    let mut triangles = Vec::with_capacity(20 << (2 * subdivisions));
    for i in 0..12 {
        for j in i + 1..12 {
            for k in j + 1..12 {
                if adjacent(i, j) && adjacent(j, k) && adjacent(i, k) {
                    triangles.push(outward(&corners, [i as u32, j as u32, k as u32]));
                }
            }
        }
    }
    for _ in 0..subdivisions {
        let mut midpoints: HashMap<(u32, u32), u32> = HashMap::new();
        let mut midpoint = |a: u32, b: u32, corners: &mut Vec<Point>| {
            *midpoints.entry((a.min(b), a.max(b))).or_insert_with(|| {
                let m = (corners[a as usize].coords + corners[b as usize].coords) / 2.0;
                corners.push(Point::from(m.normalize()));
                (corners.len() - 1) as u32
            })
        };
        let mut finer = Vec::with_capacity(triangles.len() * 4);
        for [a, b, c] in triangles {
            let ab = midpoint(a, b, &mut corners);
            let bc = midpoint(b, c, &mut corners);
            let ca = midpoint(c, a, &mut corners);
            finer.extend([[a, ab, ca], [b, bc, ab], [c, ca, bc], [ab, bc, ca]]);
        }
        triangles = finer;
    }
    let vertices = corners.iter().map(|p| p * radius).collect();
    TriMesh::new(vertices, triangles)
}

/// A torus about the z axis: its tube's centre circle of radius `major`
/// in the plane z = 0, the tube of radius `minor` (`minor < major`),
/// `around` segments along the centre circle and `across` around the tube
/// (each at least 3), vertices on the true torus; `2 · around · across`
/// triangles facing outward. Not convex: its hole is outside it.
pub fn torus(major: Real, minor: Real, around: u32, across: u32) -> Result<TriMesh, MeshError> {
    let (n, m) = (around.max(3), across.max(3));
    let tau = std::f64::consts::TAU;
    let mut vertices = Vec::with_capacity((n * m) as usize);
    for i in 0..n {
        let u = tau * Real::from(i) / Real::from(n);
        for j in 0..m {
            let w = tau * Real::from(j) / Real::from(m);
            let ring = major + minor * w.cos();
            vertices.push(Point::new(ring * u.cos(), ring * u.sin(), minor * w.sin()));
        }
    }
    let index = |i: u32, j: u32| (i % n) * m + (j % m);
    let mut triangles = Vec::with_capacity((2 * n * m) as usize);
    for i in 0..n {
        for j in 0..m {
            // Outward: (along the circle) × (around the tube) points away
            // from the tube's centre.
            triangles.push([index(i, j), index(i + 1, j), index(i + 1, j + 1)]);
            triangles.push([index(i, j), index(i + 1, j + 1), index(i, j + 1)]);
        }
    }
    TriMesh::new(vertices, triangles)
}

/// One triangle with the given vertices (a surface with no volume).
pub fn single_triangle(a: Point, b: Point, c: Point) -> Result<TriMesh, MeshError> {
    TriMesh::new(vec![a, b, c], vec![[0, 1, 2]])
}

/// A needle (sliver) triangle: base `length` along x, apex `width` away along
/// y, centroid at the origin.
pub fn needle(length: Real, width: Real) -> Result<TriMesh, MeshError> {
    let third = width / 3.0;
    single_triangle(
        Point::new(-length / 2.0, -third, 0.0),
        Point::new(length / 2.0, -third, 0.0),
        Point::new(0.0, width - third, 0.0),
    )
}

/// The triangle `t`, reordered if needed so its normal points away from the
/// origin (for convex shapes centred on the origin).
fn outward(vertices: &[Point], t: [u32; 3]) -> [u32; 3] {
    let [a, b, c] = t.map(|i| vertices[i as usize]);
    let normal = (b - a).cross(&(c - a));
    if normal.dot(&(a.coords + b.coords + c.coords)) < 0.0 {
        [t[0], t[2], t[1]]
    } else {
        t
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use approx::assert_relative_eq;

    #[test]
    fn icosphere_counts_and_axis_vertices() {
        for s in 0..4 {
            let mesh = icosphere(2.0, s).unwrap();
            assert_eq!(mesh.triangles().len(), 20 << (2 * s));
            // Euler: V - E + F = 2 with E = 3F/2.
            assert_eq!(mesh.vertices().len() as i64, 2 + (mesh.triangles().len() as i64) / 2);
            for v in mesh.vertices() {
                assert_relative_eq!(v.coords.norm(), 2.0, max_relative = 1e-15);
            }
        }
        let mesh = icosphere(2.0, 1).unwrap();
        for axis in 0..3 {
            for sign in [-2.0, 2.0] {
                let mut tip = Point::origin();
                tip[axis] = sign;
                assert!(mesh.vertices().contains(&tip), "no vertex at {tip}");
            }
        }
    }

    #[test]
    fn closed_primitives_face_outward() {
        // A closed outward mesh has positive volume equal to the analytic one.
        let cube = box_mesh(&Vector::new(1.0, 2.0, 3.0)).unwrap();
        assert_relative_eq!(cube.mass_properties().unwrap().volume, 48.0, max_relative = 1e-14);
        let tet = tetrahedron(Real::sqrt(3.0)).unwrap();
        // Edge 2√2: volume a³/(6√2) = 8/3.
        assert_relative_eq!(tet.mass_properties().unwrap().volume, 8.0 / 3.0, max_relative = 1e-14);
        // A torus: volume 2π²Rr² for the true one, a little less inscribed.
        let ring = torus(1.0, 0.25, 96, 48).unwrap();
        assert!(ring.check_closed().is_ok() && !ring.is_convex());
        let exact = 2.0 * std::f64::consts::PI.powi(2) * 0.0625;
        let volume = ring.mass_properties().unwrap().volume;
        assert!(volume < exact && volume > 0.99 * exact, "{volume} vs {exact}");
        let sphere = icosphere(1.0, 5).unwrap();
        let volume = sphere.mass_properties().unwrap().volume;
        assert!(
            volume < 4.0 / 3.0 * std::f64::consts::PI && volume > 0.99 * 4.0 / 3.0 * std::f64::consts::PI
        );
    }
}

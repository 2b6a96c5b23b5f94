//! Between nearmiss's triangle meshes and rapier's collider shapes: the
//! mesh the guard sweeps for a rapier body, and the collider rapier sees
//! for a scene's mesh.

use rapier3d_f64::prelude::{Collider, ColliderBuilder, ColliderSet, RigidBody};

use super::GuardError;
use crate::math::{from_parry, to_parry, Point, Real, Vector};
use crate::mesh::TriMesh;

/// The shape rapier is given for a nearmiss mesh.
#[derive(Copy, Clone, Debug, PartialEq, Eq)]
pub enum ColliderShape {
    /// The convex hull of the mesh's vertices: the mesh is convex (boxes,
    /// icospheres, tetrahedra, a convex OBJ), so this is the same solid.
    ConvexHull,
    /// The triangle mesh itself (a non-convex or open mesh).
    TriMesh,
}

impl ColliderShape {
    /// Its name in reports.
    pub fn name(self) -> &'static str {
        match self {
            ColliderShape::ConvexHull => "convex hull",
            ColliderShape::TriMesh => "triangle mesh",
        }
    }
}

/// How far a vertex may lie outside a face's plane, relative to the mesh's
/// radius, for the mesh to count as convex: rounding of the vertices, not
/// shape.
pub const CONVEXITY_TOLERANCE: Real = 1e-9;

/// Whether a closed mesh is convex: every vertex on the same side of every
/// face's plane (within [`CONVEXITY_TOLERANCE`] of the radius;
/// [`TriMesh::convex_within`]). An open mesh (a plate of triangles, a single
/// triangle) is not a solid: `false`.
pub fn is_convex(mesh: &TriMesh) -> bool {
    mesh.convex_within(CONVEXITY_TOLERANCE)
}

/// The collider rapier is given for `mesh` (vertices in the body frame):
/// its convex hull where the mesh is convex (unless `triangle_mesh`),
/// otherwise the triangle mesh.
pub fn collider_for(
    mesh: &TriMesh,
    triangle_mesh: bool,
) -> Result<(ColliderBuilder, ColliderShape), GuardError> {
    let points: Vec<_> = mesh.vertices().iter().map(to_parry).collect();
    if !triangle_mesh && is_convex(mesh) {
        if let Some(hull) = ColliderBuilder::convex_hull(&points) {
            return Ok((hull, ColliderShape::ConvexHull));
        }
    }
    ColliderBuilder::trimesh(points, mesh.triangles().to_vec())
        .map(|builder| (builder, ColliderShape::TriMesh))
        .map_err(|error| GuardError::Shape { body: String::new(), message: error.to_string() })
}

/// The most segments around a ball's equator (or a cylinder's rim) the
/// guard tessellates it with (`2 × 512 × 256` triangles at most for a
/// ball): round shapes needing more (radius above about 650 contact skins)
/// are refused.
pub const MAX_BALL_SEGMENTS: u32 = 512;

/// A ball's circumscribed polyhedron: a UV sphere whose faces all lie at
/// least `radius` from the centre (so the polyhedron contains the ball and a
/// guarded polyhedron that touches nothing means a ball that touches
/// nothing), fine enough that its vertices stand at most `excess` outside
/// the ball. `None` when that needs more than [`MAX_BALL_SEGMENTS`].
pub fn circumscribed_ball(radius: Real, excess: Real) -> Option<(Vec<Point>, Vec<[u32; 3]>)> {
    let mut segments = 8u32;
    while segments <= MAX_BALL_SEGMENTS {
        let ball = parry3d_f64::shape::Ball::new(radius);
        let (points, triangles) = ball.to_trimesh(segments, segments / 2);
        let points: Vec<Point> = points.iter().copied().map(from_parry).collect();
        // The nearest face plane to the centre sets the scale that pushes
        // every face out to the ball.
        let nearest = triangles
            .iter()
            .filter_map(|t| {
                let [a, b, c] = t.map(|i| points[i as usize]);
                let normal = (b - a).cross(&(c - a)).try_normalize(0.0)?;
                Some(normal.dot(&a.coords).abs())
            })
            .fold(Real::INFINITY, Real::min);
        if nearest.is_finite() && nearest > 0.0 {
            let scale = radius / nearest;
            if radius * (scale - 1.0) <= excess {
                return Some((points.iter().map(|p| Point::from(p.coords * scale)).collect(), triangles));
            }
        }
        segments *= 2;
    }
    None
}

/// A capsule's circumscribed polyhedron: the convex hull of its ball's
/// circumscribed polyhedron ([`circumscribed_ball`]) at both ends of its
/// segment, which is the polyhedron swept along the segment and so contains
/// the capsule (vertices at most `excess` outside it).
fn circumscribed_capsule(
    capsule: &parry3d_f64::shape::Capsule,
    excess: Real,
) -> Option<(Vec<Point>, Vec<[u32; 3]>)> {
    let (ball, _) = circumscribed_ball(capsule.radius, excess)?;
    let ends = [capsule.segment.a, capsule.segment.b].map(from_parry);
    let points: Vec<_> =
        ends.iter().flat_map(|end| ball.iter().map(move |p| to_parry(&(p + end.coords)))).collect();
    let (points, triangles) = parry3d_f64::transformation::convex_hull(&points);
    Some((points.into_iter().map(from_parry).collect(), triangles))
}

/// A cylinder's circumscribed prism: the regular polygons of its caps
/// drawn around its circles (the polygon's sides tangent to them), fine
/// enough that its vertices stand at most `excess` outside it.
fn circumscribed_cylinder(
    cylinder: &parry3d_f64::shape::Cylinder,
    excess: Real,
) -> Option<(Vec<Point>, Vec<[u32; 3]>)> {
    let mut sides = 8u32;
    while sides <= MAX_BALL_SEGMENTS {
        // The inscribed polygon's sides are `cos(π / n)` of the radius from
        // the axis: scaling by its inverse makes them tangent.
        let scale = 1.0 / (std::f64::consts::PI / sides as Real).cos();
        if cylinder.radius * (scale - 1.0) <= excess {
            let (points, triangles) = cylinder.to_trimesh(sides);
            // parry's cylinder runs along y.
            let points = points.into_iter().map(|p| Point::new(p.x * scale, p.y, p.z * scale)).collect();
            return Some((points, triangles));
        }
        sides *= 2;
    }
    None
}

/// The triangles of one shape at `frame` (in its body's frame), appended to
/// `vertices` and `triangles`, or why it has none. `excess`: how far a
/// ball's polyhedron may stand outside it.
fn append_shape(
    shape: &dyn parry3d_f64::shape::Shape,
    frame: &parry3d_f64::math::Pose,
    excess: Real,
    vertices: &mut Vec<Point>,
    triangles: &mut Vec<[u32; 3]>,
) -> Result<(), String> {
    if let Some(compound) = shape.as_compound() {
        for (pose, part) in compound.shapes() {
            append_shape(part.as_ref(), &(*frame * *pose), excess, vertices, triangles)?;
        }
        return Ok(());
    }
    let (points, indices): (Vec<Point>, Vec<[u32; 3]>) = if let Some(mesh) = shape.as_trimesh() {
        (mesh.vertices().iter().copied().map(from_parry).collect(), mesh.indices().to_vec())
    } else if let Some(polyhedron) = shape.as_convex_polyhedron() {
        let (points, indices) = polyhedron.to_trimesh();
        (points.iter().copied().map(from_parry).collect(), indices)
    } else if let Some(cuboid) = shape.as_cuboid() {
        let (points, indices) = cuboid.to_trimesh();
        (points.iter().copied().map(from_parry).collect(), indices)
    } else if let Some(ball) = shape.as_ball() {
        circumscribed_ball(ball.radius, excess).ok_or_else(|| too_round(ball.radius, excess))?
    } else if let Some(capsule) = shape.as_capsule() {
        circumscribed_capsule(capsule, excess).ok_or_else(|| too_round(capsule.radius, excess))?
    } else if let Some(cylinder) = shape.as_cylinder() {
        circumscribed_cylinder(cylinder, excess).ok_or_else(|| too_round(cylinder.radius, excess))?
    } else {
        return Err(format!(
            "a collider's shape ({:?}) is not one the guard sweeps: triangle meshes, convex polyhedra, cuboids, balls, capsules, cylinders and compounds of them",
            shape.shape_type()
        ));
    };
    let first = u32::try_from(vertices.len()).map_err(|_| "too many vertices".to_string())?;
    vertices.extend(points.into_iter().map(|p| from_parry(frame.transform_point(to_parry(&p)))));
    triangles.extend(indices.into_iter().map(|t| t.map(|i| i + first)));
    Ok(())
}

/// Why a round shape has no polyhedron.
fn too_round(radius: Real, excess: Real) -> String {
    format!(
        "a round shape of radius {radius} needs more than {MAX_BALL_SEGMENTS} segments to stay within {excess:e} of its polyhedron"
    )
}

/// The triangles of one collider in its body's frame, appended to
/// `vertices` and `triangles`, or why it has none.
fn append_collider(
    collider: &Collider,
    excess: Real,
    vertices: &mut Vec<Point>,
    triangles: &mut Vec<[u32; 3]>,
) -> Result<(), String> {
    let frame = collider.position_wrt_parent().copied().unwrap_or_default();
    append_shape(collider.shape(), &frame, excess, vertices, triangles)
}

/// The mesh the guard sweeps for `body`: the triangles of all its
/// colliders (a ball's circumscribed polyhedron, at most `excess` outside
/// it), relative to its centre of mass (returned too, body frame).
pub fn mesh_of_body(
    body: &RigidBody,
    colliders: &ColliderSet,
    name: &str,
    excess: Real,
) -> Result<(TriMesh, Vector), GuardError> {
    let shape_error = |message: String| GuardError::Shape { body: name.to_string(), message };
    let mut vertices = Vec::new();
    let mut triangles = Vec::new();
    for &handle in body.colliders() {
        let Some(collider) = colliders.get(handle) else { continue };
        append_collider(collider, excess, &mut vertices, &mut triangles).map_err(shape_error)?;
    }
    if triangles.is_empty() {
        return Err(shape_error("the body has no collider".into()));
    }
    let center = from_parry(body.local_center_of_mass()).coords;
    for v in &mut vertices {
        *v -= center;
    }
    let mesh = TriMesh::new(vertices, triangles).map_err(|error| shape_error(error.to_string()))?;
    Ok((mesh, center))
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Every face plane of `(points, triangles)` at least `distance(normal)`
    /// from the origin along its outward normal.
    fn faces_beyond(points: &[Point], triangles: &[[u32; 3]], support: impl Fn(&Vector) -> Real) {
        for t in triangles {
            let [a, b, c] = t.map(|i| points[i as usize]);
            let Some(normal) = (b - a).cross(&(c - a)).try_normalize(0.0) else { continue };
            let normal = if normal.dot(&a.coords) < 0.0 { -normal } else { normal };
            let h = support(&normal);
            assert!(
                normal.dot(&a.coords) >= h - 1e-12 * h.abs().max(1.0),
                "a face inside the shape: {normal:?}"
            );
        }
    }

    #[test]
    fn capsules_and_cylinders_are_inside_their_polyhedra() {
        let capsule = parry3d_f64::shape::Capsule::new_y(0.3, 0.1);
        let (points, triangles) = circumscribed_capsule(&capsule, 0.001).expect("fine enough");
        // The capsule's support: the segment's end farther along n, plus r.
        faces_beyond(&points, &triangles, |n| 0.3 * n.y.abs() + 0.1);
        let farthest = points
            .iter()
            .map(|p| (p.coords - Vector::y() * p.y.clamp(-0.3, 0.3)).norm())
            .fold(0.0, Real::max);
        assert!(farthest - 0.1 <= 0.001, "{farthest}");
        let cylinder = parry3d_f64::shape::Cylinder::new(0.3, 0.1);
        let (points, triangles) = circumscribed_cylinder(&cylinder, 0.001).expect("fine enough");
        faces_beyond(&points, &triangles, |n| 0.3 * n.y.abs() + 0.1 * (n.x * n.x + n.z * n.z).sqrt());
        let farthest = points.iter().map(|p| (p.x * p.x + p.z * p.z).sqrt()).fold(0.0, Real::max);
        assert!(farthest - 0.1 <= 0.001, "{farthest}");
    }

    #[test]
    fn a_balls_polyhedron_contains_it_and_stands_out_at_most_the_excess() {
        for (radius, excess) in [(0.5, 0.00125), (0.05, 0.00125), (3.0, 0.01), (1e-3, 1e-6)] {
            let (points, triangles) = circumscribed_ball(radius, excess).expect("fine enough");
            for t in &triangles {
                let [a, b, c] = t.map(|i| points[i as usize]);
                let Some(normal) = (b - a).cross(&(c - a)).try_normalize(0.0) else { continue };
                // Every face plane at least the radius from the centre (to
                // rounding): the ball is inside.
                assert!(normal.dot(&a.coords).abs() >= radius * (1.0 - 1e-12), "r {radius}");
            }
            let farthest = points.iter().map(|p| p.coords.norm()).fold(0.0, Real::max);
            assert!(farthest - radius <= excess, "r {radius}: vertices {} outside", farthest - radius);
        }
        assert!(circumscribed_ball(1.0, 1e-9).is_none(), "too fine is refused");
    }
}

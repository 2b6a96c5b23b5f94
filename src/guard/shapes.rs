//! Between nearmiss's triangle meshes and rapier's collider shapes: the
//! mesh the guard sweeps for a rapier body, and the collider rapier sees
//! for a scene's mesh.

use rapier3d_f64::prelude::ColliderBuilder;

use super::bodies::RapierBodies;
use super::parts::ColliderPart;
use super::views::ShapePart;
use super::GuardError;
use crate::math::{from_parry, to_parry, Point, Pose, Real, Vector};
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
pub(crate) const CONVEXITY_TOLERANCE: Real = 1e-9;

/// Whether a closed mesh is convex: every vertex on the same side of every
/// face's plane (within `CONVEXITY_TOLERANCE` of the radius;
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
    // Zero-area triangles left out: parry would give them a normal of NaN.
    ColliderBuilder::trimesh(points, mesh.triangles_with_area().collect())
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
    ends: [Point; 2],
    radius: Real,
    excess: Real,
) -> Option<(Vec<Point>, Vec<[u32; 3]>)> {
    let (ball, _) = circumscribed_ball(radius, excess)?;
    let points: Vec<_> =
        ends.iter().flat_map(|end| ball.iter().map(move |p| to_parry(&(p + end.coords)))).collect();
    let (points, triangles) = parry3d_f64::transformation::convex_hull(&points);
    Some((points.into_iter().map(from_parry).collect(), triangles))
}

/// A cylinder's circumscribed prism: the regular polygons of its caps
/// drawn around its circles (the polygon's sides tangent to them), fine
/// enough that its vertices stand at most `excess` outside it.
fn circumscribed_cylinder(
    half_height: Real,
    radius: Real,
    excess: Real,
) -> Option<(Vec<Point>, Vec<[u32; 3]>)> {
    let mut sides = 8u32;
    while sides <= MAX_BALL_SEGMENTS {
        // The inscribed polygon's sides are `cos(π / n)` of the radius from
        // the axis: scaling by its inverse makes them tangent.
        let scale = 1.0 / (std::f64::consts::PI / sides as Real).cos();
        if radius * (scale - 1.0) <= excess {
            let (points, triangles) =
                parry3d_f64::shape::Cylinder::new(half_height, radius).to_trimesh(sides);
            // parry's cylinder runs along y.
            let points = points.into_iter().map(|p| Point::new(p.x * scale, p.y, p.z * scale)).collect();
            return Some((points, triangles));
        }
        sides *= 2;
    }
    None
}

/// How far a half-space collider's box reaches, in rapier's length units:
/// `1e4`. The guard sweeps a half-space as the box below its plane that is
/// twice this wide (centred under the collider's origin) and this deep:
/// bodies farther out along the plane are not guarded against it.
pub(crate) const HALF_SPACE_EXTENT: Real = 1e4;

/// The box below a half-space's plane (through the origin, outward unit
/// `normal`): [`HALF_SPACE_EXTENT`] `× length_unit` to each side and deep.
fn half_space_box(normal: &Vector, length_unit: Real) -> (Vec<Point>, Vec<[u32; 3]>) {
    let extent = HALF_SPACE_EXTENT * length_unit;
    let half = Vector::new(extent, extent, extent / 2.0);
    let (points, triangles) =
        parry3d_f64::shape::Cuboid::new(crate::math::vector_to_parry(&half)).to_trimesh();
    // The box's top face (z = 0 after the shift) on the plane, turned so
    // that z is the normal.
    let turn = nalgebra::UnitQuaternion::rotation_between(&Vector::z(), normal).unwrap_or_else(|| {
        nalgebra::UnitQuaternion::from_axis_angle(&Vector::x_axis(), std::f64::consts::PI)
    });
    let points = points
        .into_iter()
        .map(|p| Point::from(turn * (from_parry(p).coords - Vector::z() * half.z)))
        .collect();
    (points, triangles)
}

/// `points` and `triangles` with equal points merged (a heightfield's
/// triangles come each with its own three).
fn welded(points: &[Point], indices: &[[u32; 3]]) -> (Vec<Point>, Vec<[u32; 3]>) {
    let mut index = std::collections::HashMap::new();
    let mut unique = Vec::new();
    let remap: Vec<u32> = points
        .iter()
        .map(|p| {
            let key = [p.x.to_bits(), p.y.to_bits(), p.z.to_bits()];
            *index.entry(key).or_insert_with(|| {
                unique.push(*p);
                (unique.len() - 1) as u32
            })
        })
        .collect();
    (unique, indices.iter().map(|t| t.map(|i| remap[i as usize])).collect())
}

/// The triangles of one shape at `frame` (in its body's frame), appended to
/// `vertices` and `triangles`, or why it has none. `excess`: how far a
/// ball's polyhedron may stand outside it; `length_unit`: rapier's, for a
/// half-space's box.
fn append_shape(
    shape: &ShapePart,
    frame: &Pose,
    (excess, length_unit): (Real, Real),
    vertices: &mut Vec<Point>,
    triangles: &mut Vec<[u32; 3]>,
) -> Result<(), String> {
    let (points, indices) = match shape {
        ShapePart::Compound(parts) => {
            for (pose, part) in parts {
                append_shape(part, &(frame * pose), (excess, length_unit), vertices, triangles)?;
            }
            return Ok(());
        }
        ShapePart::Triangles(points, indices) => welded(points, indices),
        ShapePart::HalfSpace { normal } => half_space_box(normal, length_unit),
        &ShapePart::Ball(radius) => circumscribed_ball(radius, excess).ok_or_else(|| too_round(radius, excess))?,
        &ShapePart::Capsule { a, b, radius } => {
            circumscribed_capsule([a, b], radius, excess).ok_or_else(|| too_round(radius, excess))?
        }
        &ShapePart::Cylinder { half_height, radius } => {
            circumscribed_cylinder(half_height, radius, excess).ok_or_else(|| too_round(radius, excess))?
        }
        ShapePart::Other(kind) => {
            return Err(format!(
                "its shape ({kind}) is not one the guard sweeps (triangle meshes, convex polyhedra, cuboids, heightfields, half-spaces, balls, capsules, cylinders and compounds of them): give the body a triangle mesh of it (`ColliderBuilder::trimesh`), or leave the body out of the guarded list"
            ))
        }
    };
    let first = u32::try_from(vertices.len()).map_err(|_| "too many vertices".to_string())?;
    vertices.extend(points.iter().map(|p| frame * p));
    triangles.extend(indices.into_iter().map(|t| t.map(|i| i + first)));
    Ok(())
}

/// Why a round shape has no polyhedron.
fn too_round(radius: Real, excess: Real) -> String {
    format!(
        "a round shape of radius {radius} needs more than {MAX_BALL_SEGMENTS} segments to stay within {excess:e} of its polyhedron"
    )
}

/// The mesh the guard sweeps for the body `handle`: the triangles of its
/// solid colliders (enabled, not sensors; of all its colliders when it has
/// no solid one, whose pairs rapier then never solves), a ball's
/// circumscribed polyhedron at most `excess` outside it, a half-space's box
/// in units of `length_unit`, relative to its centre of mass (returned
/// too, body frame). `name`: the body in messages.
pub fn mesh_of_body<B: RapierBodies>(
    bodies: &B,
    colliders: &B::Colliders,
    handle: B::Handle,
    name: &str,
    (excess, length_unit): (Real, Real),
) -> Result<(TriMesh, Vector), GuardError<B::Handle>> {
    let shape_error = |message: String| GuardError::Shape { body: name.to_string(), message };
    let body = bodies.view(handle).ok_or(GuardError::UnknownBody(handle))?;
    let parts = bodies.shapes(colliders, handle);
    let any_solid = parts.iter().any(|part| part.solid);
    let mut vertices = Vec::new();
    let mut triangles = Vec::new();
    for ColliderPart { name: collider, frame, shape, solid } in &parts {
        if *solid || !any_solid {
            append_shape(shape, frame, (excess, length_unit), &mut vertices, &mut triangles)
                .map_err(|message| shape_error(format!("{collider}: {message}")))?;
        }
    }
    if triangles.is_empty() {
        return Err(shape_error("the body has no collider".into()));
    }
    for v in &mut vertices {
        *v -= body.center;
    }
    let mesh = TriMesh::new(vertices, triangles).map_err(|error| shape_error(error.to_string()))?;
    Ok((mesh, body.center))
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
        let ends = [Point::new(0.0, -0.3, 0.0), Point::new(0.0, 0.3, 0.0)];
        let (points, triangles) = circumscribed_capsule(ends, 0.1, 0.001).expect("fine enough");
        // The capsule's support: the segment's end farther along n, plus r.
        faces_beyond(&points, &triangles, |n| 0.3 * n.y.abs() + 0.1);
        let farthest = points
            .iter()
            .map(|p| (p.coords - Vector::y() * p.y.clamp(-0.3, 0.3)).norm())
            .fold(0.0, Real::max);
        assert!(farthest - 0.1 <= 0.001, "{farthest}");
        let (points, triangles) = circumscribed_cylinder(0.3, 0.1, 0.001).expect("fine enough");
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

//! A contact picture worked out before drawing: the contact's frame, the
//! three views, where the surfaces cross, the caption; and each view drawn
//! in its panel.

use super::{
    direction_name, draw_triad, draw_wireframe, Encounter, View, Zoom, BLUE_BODY, CROSSING, MIN_ZOOM, NORMAL,
    ORANGE_BODY, PANEL_ASPECT, PANEL_MARGINS, ZOOM,
};
use crate::plot::FAMILY;
use crate::text;
use nearmiss::math::{Point, Real, Vector};
use nearmiss::mesh::{
    mesh_intersection, signed_distance, MeshIntersection, MeshIntersectionScratch, SignedDistanceScratch,
    TriMesh,
};
use plotters::prelude::*;

/// What a picture of an encounter shows, worked out before drawing: the
/// three views, the caption, where the surfaces cross.
pub(super) struct Picture<'e> {
    encounter: &'e Encounter<'e>,
    meshes: (&'e TriMesh, &'e TriMesh),
    names: (&'e str, &'e str),
    /// The closest points.
    points: (Point, Point),
    /// The midpoint of the closest points, and the contact's normal.
    center: Point,
    normal: Vector,
    /// Where the surfaces cross, and its length.
    curve: Vec<[Point; 2]>,
    crossing_length: Real,
    pub(super) views: [View; 3],
    pub(super) caption: String,
}

/// Where the views look from: the contact's frame and the whole view's
/// size and offset (see [`Picture::of`]).
struct Framing {
    center: Point,
    normal: Vector,
    right: Vector,
    depth: Vector,
    whole: Real,
    whole_offset: (Real, Real),
    /// The smaller contact triangle's reach from the centre, with room.
    small_triangle: Real,
}

impl Framing {
    fn of(encounter: &Encounter<'_>, (mesh_a, mesh_b): (&TriMesh, &TriMesh)) -> Framing {
        let closest = encounter.closest;
        let (pose_a, pose_b) = encounter.poses;
        let (pa, pb) = (closest.point_a, closest.point_b);
        let triangle_a = mesh_a.triangle(closest.triangle_a).map(|p| pose_a * p);
        let face_normal = (triangle_a[1] - triangle_a[0]).cross(&(triangle_a[2] - triangle_a[0]));
        let normal = [pb - pa, face_normal, Vector::z()]
            .into_iter()
            .find(|v| v.norm() > 0.0 && v.norm().is_finite())
            .map_or(Vector::z(), |v| v.normalize());
        let center = Point::from((pa.coords + pb.coords) / 2.0);
        let vertices: Vec<Point> = [(mesh_a, &pose_a), (mesh_b, &pose_b)]
            .iter()
            .flat_map(|(mesh, pose)| mesh.vertices().iter().map(move |v| *pose * v))
            .collect();
        let spread =
            |axis: &Vector| vertices.iter().map(|p| (p - center).dot(axis).abs()).fold(0.0, Real::max);
        // The side view looks across the wider of the two directions across
        // the normal.
        let first = normal.cross(&if normal.x.abs() < 0.9 { Vector::x() } else { Vector::y() }).normalize();
        let second = normal.cross(&first);
        let (right, depth) =
            if spread(&first) >= spread(&second) { (first, second) } else { (second, first) };
        // The whole view is centred on both bodies' extent in its plane (not
        // on the contact, which would leave half the panel empty), and holds it.
        let extent = |axis: &Vector| {
            vertices
                .iter()
                .map(|p| (p - center).dot(axis))
                .fold((Real::INFINITY, Real::NEG_INFINITY), |(lo, hi), v| (lo.min(v), hi.max(v)))
        };
        let ((x0, x1), (y0, y1)) = (extent(&right), extent(&normal));
        let whole_offset = ((x0 + x1) / 2.0, (y0 + y1) / 2.0);
        let whole = ((x1 - x0) / 2.0).max((y1 - y0) / 2.0 * PANEL_ASPECT).max(Real::MIN_POSITIVE) * 1.08;
        // Zoomed: the smaller contact triangle whole (the larger may be a whole
        // floor), and at least 1/ZOOM of the whole view and a few contact
        // distances around the contact.
        let triangle_b = mesh_b.triangle(closest.triangle_b).map(|p| pose_b * p);
        let reach = |t: &[Point; 3]| t.iter().map(|p| (p - center).norm()).fold(0.0, Real::max);
        let small_triangle = reach(&triangle_a).min(reach(&triangle_b)) * 1.25;
        Framing { center, normal, right, depth, whole, whole_offset, small_triangle }
    }
}

impl<'e> Picture<'e> {
    pub(super) fn of(
        encounter: &'e Encounter<'e>,
        meshes: (&'e TriMesh, &'e TriMesh),
        names: (&'e str, &'e str),
    ) -> Picture<'e> {
        let (mesh_a, mesh_b) = meshes;
        let closest = encounter.closest;
        let (pose_a, pose_b) = encounter.poses;
        let Framing { center, normal, right, depth, whole, whole_offset, small_triangle } =
            Framing::of(encounter, meshes);
        // Where the surfaces cross (bodies that overlap), drawn over both; the
        // zoomed views then hold the whole curve.
        let mut crossing = MeshIntersection::default();
        mesh_intersection(
            mesh_a,
            &pose_a,
            mesh_b,
            &pose_b,
            &mut crossing,
            &mut MeshIntersectionScratch::default(),
        );
        let curve: Vec<[Point; 2]> = crossing.segments().copied().collect();
        // Zoomed views of an overlap are centred on the curve and hold it whole.
        let curve_center = (!curve.is_empty()).then(|| {
            Point::from(curve.iter().flatten().map(|p| p.coords).sum::<Vector>() / (2 * curve.len()) as Real)
        });
        let curve_reach =
            |middle: &Point| curve.iter().flatten().map(|p| (p - middle).norm()).fold(0.0, Real::max);
        let overlap_depth = (!curve.is_empty())
            .then(|| {
                signed_distance(mesh_a, &pose_a, mesh_b, &pose_b, &mut SignedDistanceScratch::default()).value
            })
            .filter(|v| *v < 0.0);
        let (zoom, zoom_center) =
            zoom_framing(encounter.zoom, whole, small_triangle, (center, curve_center), curve_reach);
        let views = [
            View {
                title: "side view (normal up)".into(),
                center,
                right,
                up: normal,
                half_width: whole,
                offset: whole_offset,
                up_name: "along the normal",
            },
            View {
                title: "side view, zoomed".into(),
                center,
                right,
                up: normal,
                half_width: zoom,
                offset: ((zoom_center - center).dot(&right), (zoom_center - center).dot(&normal)),
                up_name: "along the normal",
            },
            View {
                title: "down the normal, zoomed".into(),
                center,
                right,
                up: depth,
                half_width: zoom,
                offset: ((zoom_center - center).dot(&right), (zoom_center - center).dot(&depth)),
                up_name: "across the normal",
            },
        ];
        let caption = format!(
            "{}: t = {}   {} (triangle {} {})  /  {} (triangle {} {})   {}",
            encounter.label,
            text::time(encounter.time),
            names.0,
            closest.triangle_a,
            closest.feature_a,
            names.1,
            closest.triangle_b,
            closest.feature_b,
            match overlap_depth {
                Some(v) => format!("{}; overlapping, depth {}", encounter.detail, text::approx(-v, 3)),
                None => encounter.detail.clone(),
            }
        );
        Picture {
            encounter,
            meshes,
            names,
            points: (closest.point_a, closest.point_b),
            center,
            normal,
            crossing_length: crossing.length(),
            curve,
            views,
            caption,
        }
    }

    /// The legend under the caption.
    pub(super) fn legend(&self) -> String {
        let (names, encounter) = (self.names, self.encounter);
        if self.curve.is_empty() {
            format!(
                "blue: {}   orange: {}   red: {}, from {} towards {}   grey: the world's axes   lengths in scene units, from the midpoint",
                names.0, names.1, encounter.arrow, names.0, names.1
            )
        } else {
            format!(
                "blue: {}   orange: {}   green: where their surfaces cross ({} long)   red: {}   grey: the world's axes",
                names.0,
                names.1,
                text::approx(self.crossing_length, 3),
                encounter.arrow
            )
        }
    }

    /// One view in its panel.
    pub(super) fn draw_panel<DB: DrawingBackend>(
        &self,
        view: &View,
        panel: &DrawingArea<DB, plotters::coord::Shift>,
    ) -> Result<(), String> {
        let error = |e: &dyn std::fmt::Display| e.to_string();
        let (mesh_a, mesh_b) = self.meshes;
        let (pose_a, pose_b) = self.encounter.poses;
        let closest = self.encounter.closest;
        let (pa, pb) = self.points;
        let (center, normal, curve) = (self.center, self.normal, &self.curve);
        // Equal scales on both axes: the plotting area's aspect ratio.
        let (width, height) = panel.dim_in_pixel();
        let w = view.half_width;
        let h = w * (height.saturating_sub(PANEL_MARGINS.1).max(1) as Real)
            / (width.saturating_sub(PANEL_MARGINS.0).max(1) as Real);
        let (cx, cy) = view.offset;
        let mut chart = ChartBuilder::on(panel)
            .caption(&view.title, (FAMILY, 18).into_font())
            .margin(10)
            .margin_right(22)
            .x_label_area_size(45)
            .y_label_area_size(70)
            .build_cartesian_2d(cx - w..cx + w, cy - h..cy + h)
            .map_err(|e| error(&e))?;
        // Tick values with a few digits, rounding noise next to zero
        // (-5.55e-17) written as 0.
        let tick = |v: &Real| text::approx(if v.abs() < 1e-9 * w { 0.0 } else { *v }, 3);
        chart
            .configure_mesh()
            .disable_mesh()
            .label_style((FAMILY, 13).into_font())
            .axis_desc_style((FAMILY, 14).into_font())
            .x_labels(3)
            .y_labels(5)
            .x_label_formatter(&tick)
            .y_label_formatter(&tick)
            .x_desc(format!("along {}", direction_name(&view.right)))
            .y_desc(format!("{} {}", view.up_name, direction_name(&view.up)))
            .draw()
            .map_err(|e| error(&e))?;
        for (mesh, pose, color, contact_triangle) in [
            (mesh_a, &pose_a, BLUE_BODY, closest.triangle_a),
            (mesh_b, &pose_b, ORANGE_BODY, closest.triangle_b),
        ] {
            draw_wireframe(&mut chart, view, mesh, pose, color).map_err(|e| error(&e))?;
            let t = mesh.triangle(contact_triangle).map(|p| view.project(&(*pose * p)));
            chart.draw_series([Polygon::new(t.to_vec(), color.mix(0.45).filled())]).map_err(|e| error(&e))?;
        }
        chart
            .draw_series(curve.iter().map(|[p, q]| {
                PathElement::new(vec![view.project(p), view.project(q)], CROSSING.stroke_width(3))
            }))
            .map_err(|e| error(&e))?;
        let (a, b) = (view.project(&pa), view.project(&pb));
        chart
            .draw_series([Circle::new(a, 5, BLUE_BODY.filled()), Circle::new(b, 5, ORANGE_BODY.filled())])
            .map_err(|e| error(&e))?;
        let tip = view.project(&(center + normal * (w * 0.4)));
        let base = view.project(&center);
        chart
            .draw_series([PathElement::new(vec![base, tip], NORMAL.stroke_width(3))])
            .map_err(|e| error(&e))?;
        draw_triad(&mut chart, view, (cx + 0.72 * w, cy + h - 0.28 * w), 0.2 * w).map_err(|e| error(&e))?;
        Ok(())
    }
}

/// The zoomed views' half width and middle (see the module): what they
/// should hold (the smaller closest triangle, four contact distances or
/// four times the gap, the whole crossing curve, with room) brought
/// between [`ZOOM`] and [`MIN_ZOOM`] times closer than the whole view's
/// `whole`, so that they always zoom and never zoom past the features;
/// a gap's two closest points are held whatever its size. Centred on the
/// crossing curve where it fits, else on the closest points (`center`).
/// `curve_reach`: the curve's largest distance from a point.
fn zoom_framing(
    zoom: Zoom,
    whole: Real,
    small_triangle: Real,
    (center, curve_center): (Point, Option<Point>),
    curve_reach: impl Fn(&Point) -> Real,
) -> (Real, Point) {
    let curve = curve_center.map(|middle| (middle, curve_reach(&middle) * 1.1));
    let wanted = match zoom {
        Zoom::Contact(distance) | Zoom::Gap(distance) => small_triangle.max(4.0 * distance),
    }
    .max(curve.map_or(0.0, |(_, reach)| reach));
    let half_width = match zoom {
        // The closest points are half the gap either side of the middle:
        // half width 0.75 of the gap holds both with room.
        Zoom::Gap(distance) => wanted.clamp(whole / ZOOM, whole / MIN_ZOOM).max(0.75 * distance),
        Zoom::Contact(_) => wanted.clamp(whole / ZOOM, whole / MIN_ZOOM),
    };
    match curve {
        Some((middle, reach)) if reach <= half_width => (half_width, middle),
        _ => (half_width, center),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_zoomed_views_always_zoom_and_hold_what_matters() {
        let center = Point::origin();
        let none = |_: &Point| 0.0;
        // Two triangles whose closest triangle is as large as the whole
        // view: still MIN_ZOOM closer.
        let (w, middle) = zoom_framing(Zoom::Contact(1e-9), 0.54, 0.6, (center, None), none);
        assert_eq!((w, middle), (0.54 / MIN_ZOOM, center));
        // A fine mesh: its small triangle, up to ZOOM closer.
        assert_eq!(zoom_framing(Zoom::Contact(1e-9), 2.0, 0.15, (center, None), none).0, 0.2);
        assert_eq!(zoom_framing(Zoom::Contact(1e-9), 2.0, 0.3, (center, None), none).0, 0.3);
        // A near miss whose gap is large: both closest points in view.
        let (w, _) = zoom_framing(Zoom::Gap(1.0), 2.0, 0.1, (center, None), none);
        assert!((0.6..=2.0).contains(&w), "{w}");
        // A crossing curve that fits: centred on it; one that does not:
        // on the closest points.
        let curve_middle = Point::new(0.05, 0.0, 0.0);
        let (w, middle) = zoom_framing(Zoom::Contact(1e-9), 2.0, 0.1, (center, Some(curve_middle)), |_| 0.2);
        assert_eq!((w, middle), (0.2 * 1.1, curve_middle));
        let (w, middle) = zoom_framing(Zoom::Contact(1e-9), 2.0, 0.1, (center, Some(curve_middle)), |_| 1.5);
        assert_eq!((w, middle), (2.0 / MIN_ZOOM, center));
    }
}

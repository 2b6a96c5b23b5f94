//! `contact_<n>.png` and `nearest_near_miss.png`: a picture of a contact, or of
//! the run's nearest near miss, so that a user sees at a glance which
//! feature of which body hit (or passed) which (the `plot` feature).
//!
//! Three orthographic wireframe views of the two meshes at their poses at
//! that time, all centred on the midpoint of the two closest points, with
//! `n` the direction from body a's closest point towards body b's (the
//! contact normal; where the points coincide, triangle a's normal):
//! 1. from the side (n up), both bodies whole;
//! 2. the same, zoomed on the closest points (a contact: the smaller
//!    closest triangle whole, at least a tenth of the whole view and four
//!    contact distances; a near miss: four times its distance);
//! 3. looking down n onto the closest points, zoomed alike.
//!
//! Body a is drawn in blue, body b in orange; the two closest triangles
//! are filled, the closest points are dots and n a red arrow; where the
//! bodies overlap, the curve where their surfaces cross is drawn in green
//! (its length in the legend). The caption
//! gives the time, the bodies, their triangles and features, the distance
//! and the contact distance (a near miss: the certified lower bound).

use std::path::Path;

use plotters::prelude::*;

use crate::plot::{draw_png, PlotError, FAMILY};
use crate::text;
use nearmiss::math::{Point, Pose, Real, Vector};
use nearmiss::mesh::{
    mesh_intersection, signed_distance, MeshDistance, MeshIntersection, MeshIntersectionScratch,
    SignedDistanceScratch, TriMesh,
};
use nearmiss::run::Contact;
use nearmiss::run::NearMiss;

/// Contacts pictured per run: the first ones, and any the scene's `plot`
/// names (`contacts: [12, 40]`).
pub const PICTURED_CONTACTS: usize = 3;

/// The contacts (1-based numbers) pictured in a run of `contacts`
/// contacts: the first [`PICTURED_CONTACTS`] and those `named` that
/// happened, in order, each once.
pub fn pictured(contacts: usize, named: &[usize]) -> Vec<usize> {
    let mut numbers: Vec<usize> = (1..=contacts.min(PICTURED_CONTACTS))
        .chain(named.iter().copied().filter(|&n| n >= 1 && n <= contacts))
        .collect();
    numbers.sort_unstable();
    numbers.dedup();
    numbers
}

/// The zoomed views magnify the whole view this many times (and show at
/// least a few contact distances around the contact).
pub const ZOOM: Real = 10.0;

const BLUE_BODY: RGBColor = RGBColor(31, 119, 180);
const ORANGE_BODY: RGBColor = RGBColor(230, 120, 20);
const NORMAL: RGBColor = RGBColor(200, 30, 30);
/// The curve where two overlapping bodies' surfaces cross.
const CROSSING: RGBColor = RGBColor(20, 150, 60);

/// One orthographic view: the plane spanned by `right` and `up` (unit,
/// orthogonal) through `center` (the contact), showing `half_width`
/// either side of `offset` (the view's middle, in the plane's coordinates).
struct View {
    title: String,
    center: Point,
    right: Vector,
    up: Vector,
    half_width: Real,
    offset: (Real, Real),
    /// What the vertical axis is, in words.
    up_name: &'static str,
}

impl View {
    fn project(&self, p: &Point) -> (Real, Real) {
        let d = p - self.center;
        (d.dot(&self.right), d.dot(&self.up))
    }
}

/// What a picture shows: two bodies at one instant, their closest points
/// and the direction between them (a contact, or a near miss).
pub struct Encounter<'a> {
    /// The caption's start: `contact 2`, `nearest near miss`.
    pub label: String,
    /// When.
    pub time: Real,
    /// The closest points (world frame), triangles and features.
    pub closest: &'a MeshDistance,
    /// The meshes' frames at `time`.
    pub poses: (Pose, Pose),
    /// What the zoomed views show.
    pub zoom: Zoom,
    /// The caption's end: `distance 1e-9 (contact distance 1e-6)`.
    pub detail: String,
    /// What the red arrow is: `the contact normal`, `the gap's direction`.
    pub arrow: &'static str,
}

/// What the zoomed views of an [`Encounter`] show.
#[derive(Copy, Clone, Debug)]
pub enum Zoom {
    /// A contact of this contact distance: the smaller closest triangle
    /// whole, at least a tenth of the whole view and four contact
    /// distances.
    Contact(Real),
    /// A gap of this distance: four times it around the closest points.
    Gap(Real),
}

impl<'a> Encounter<'a> {
    /// Contact `n` (1-based) of a run.
    pub fn of_contact(contact: &'a Contact, n: usize) -> Encounter<'a> {
        Encounter {
            label: format!("contact {n}"),
            time: contact.time,
            closest: &contact.closest,
            poses: (contact.pose_a, contact.pose_b),
            zoom: Zoom::Contact(contact.contact_distance),
            detail: format!(
                "distance {} (contact distance {})",
                text::approx(contact.closest.distance, 3),
                text::approx(contact.contact_distance, 3)
            ),
            arrow: "the contact normal",
        }
    }

    /// A near miss of a run, `label` saying which.
    pub fn of_near_miss(miss: &'a NearMiss, label: &str) -> Encounter<'a> {
        Encounter {
            label: label.to_string(),
            time: miss.time,
            closest: &miss.closest,
            poses: (miss.pose_a, miss.pose_b),
            zoom: Zoom::Gap(miss.distance),
            detail: format!(
                "distance {} (never closer than {})",
                text::approx(miss.distance, 6),
                text::approx(miss.lower, 6)
            ),
            arrow: "the gap's direction",
        }
    }
}

/// Draws contact `n` (1-based) of a run between `mesh_a` and `mesh_b` to
/// `path`; `names` are the two bodies' names.
pub fn draw_contact(
    contact: &Contact,
    n: usize,
    meshes: (&TriMesh, &TriMesh),
    names: (&str, &str),
    path: &Path,
) -> Result<(), PlotError> {
    draw_encounter(&Encounter::of_contact(contact, n), meshes, names, path)
}

/// Draws `encounter` of `mesh_a` and `mesh_b` to `path`; `names` are the
/// two bodies' names.
pub fn draw_encounter(
    encounter: &Encounter<'_>,
    meshes: (&TriMesh, &TriMesh),
    names: (&str, &str),
    path: &Path,
) -> Result<(), PlotError> {
    let picture = Picture::of(encounter, meshes, names);
    draw_png(path, |root| {
        let error = |e: &dyn std::fmt::Display| e.to_string();
        let (top, rest) = root.split_vertically(70);
        top.draw(&Text::new(picture.caption.clone(), (20, 12), (FAMILY, 18).into_font()))
            .map_err(|e| error(&e))?;
        top.draw(&Text::new(picture.legend(), (20, 42), (FAMILY, 16).into_font())).map_err(|e| error(&e))?;
        let panels = rest.split_evenly((1, 3));
        for (view, panel) in picture.views.iter().zip(panels.iter()) {
            picture.draw_panel(view, panel)?;
        }
        Ok(())
    })
}

/// What a picture of an encounter shows, worked out before drawing: the
/// three views, the caption, where the surfaces cross.
struct Picture<'e> {
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
    views: [View; 3],
    caption: String,
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
    /// The bodies' largest extent along `right` or the normal.
    spread: Real,
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
        Framing {
            center,
            normal,
            right,
            depth,
            whole,
            whole_offset,
            spread: spread(&right).max(spread(&normal)),
            small_triangle,
        }
    }
}

impl<'e> Picture<'e> {
    fn of(
        encounter: &'e Encounter<'e>,
        meshes: (&'e TriMesh, &'e TriMesh),
        names: (&'e str, &'e str),
    ) -> Picture<'e> {
        let (mesh_a, mesh_b) = meshes;
        let closest = encounter.closest;
        let (pose_a, pose_b) = encounter.poses;
        let Framing { center, normal, right, depth, whole, whole_offset, spread, small_triangle } =
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
        let zoom_center = curve_center.unwrap_or(center);
        let curve_reach = curve.iter().flatten().map(|p| (p - zoom_center).norm()).fold(0.0, Real::max) * 1.1;
        let overlap_depth = (!curve.is_empty())
            .then(|| {
                signed_distance(mesh_a, &pose_a, mesh_b, &pose_b, &mut SignedDistanceScratch::default()).value
            })
            .filter(|v| *v < 0.0);
        let zoom = curve_reach.min(whole).max(match encounter.zoom {
            // On the gap: both closest points, the gap a quarter of the view.
            Zoom::Gap(distance) => (4.0 * distance).min(whole),
            Zoom::Contact(contact_distance) => {
                (spread / ZOOM).max(small_triangle).min(whole).max(4.0 * contact_distance)
            }
        });
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
    fn legend(&self) -> String {
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
    fn draw_panel<DB: DrawingBackend>(
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

/// The plotting area's width over its height in a panel (1200 × 800 less
/// the caption, in thirds, less the axes' label areas): the whole view
/// fits its bodies' height times this into its half-width.
const PANEL_ASPECT: Real = 330.0 / 620.0;

/// A panel's width and height less its plotting area (label areas,
/// margins and the title), in pixels.
const PANEL_MARGINS: (u32, u32) = (112, 110);

/// A direction in words: `+x`, `−z`, or its components when it is not
/// along a world axis.
fn direction_name(v: &Vector) -> String {
    for (k, axis) in ["x", "y", "z"].iter().enumerate() {
        if v[k].abs() > 1.0 - 1e-9 {
            return format!("{}{axis}", if v[k] > 0.0 { "+" } else { "−" });
        }
    }
    let c = |x: Real| text::approx(if x.abs() < 5e-3 { 0.0 } else { x }, 2);
    format!("({}, {}, {})", c(v.x), c(v.y), c(v.z))
}

/// A panel's chart: plane coordinates, both axes linear.
type PanelChart<'a, DB> = ChartContext<
    'a,
    DB,
    Cartesian2d<plotters::coord::types::RangedCoordf64, plotters::coord::types::RangedCoordf64>,
>;

/// The world's axes as seen in `view`: a grey arrow for each of x, y and
/// z from `at`, `length` long when it lies in the view's plane (shorter as
/// it points out of it; a dot when it points straight out).
fn draw_triad<DB: DrawingBackend>(
    chart: &mut PanelChart<'_, DB>,
    view: &View,
    at: (Real, Real),
    length: Real,
) -> Result<(), DrawingAreaErrorKind<DB::ErrorType>> {
    let grey = RGBColor(90, 90, 90);
    let axes = [("x", Vector::x()), ("y", Vector::y()), ("z", Vector::z())];
    let in_plane = |axis: &Vector| (axis.dot(&view.right), axis.dot(&view.up));
    // An axis along the line of sight is labelled on the side no arrow takes.
    let (sx, sy) =
        axes.iter().map(|(_, a)| in_plane(a)).fold((0.0, 0.0), |(x, y), (dx, dy)| (x - dx, y - dy));
    let free = if sx.hypot(sy) > 1e-6 { (sx / sx.hypot(sy), sy / sx.hypot(sy)) } else { (-1.0, 0.0) };
    for (name, axis) in axes {
        let (dx, dy) = in_plane(&axis);
        let tip = (at.0 + dx * length, at.1 + dy * length);
        if dx.hypot(dy) < 0.1 {
            // Along the line of sight: towards the viewer or away.
            let towards = axis.dot(&view.right.cross(&view.up)) > 0.0;
            chart.draw_series([Circle::new(at, 3, grey.filled())])?;
            let label = format!("{name} {}", if towards { "out" } else { "in" });
            // Text hangs right and down from its anchor: about 1.3 lengths
            // wide and half a length high.
            let anchor = (
                at.0 + free.0 * 0.5 * length - if free.0 < 0.0 { 1.3 * length } else { 0.0 },
                at.1 + free.1 * 0.5 * length + if free.1 > 0.0 { 0.5 * length } else { 0.0 },
            );
            chart.draw_series([Text::new(label, anchor, (FAMILY, 13).into_font().color(&grey))])?;
            continue;
        }
        chart.draw_series([PathElement::new(vec![at, tip], grey.stroke_width(2))])?;
        let label = (tip.0 + 0.12 * length * dx.signum(), tip.1 + 0.12 * length * dy.signum());
        chart.draw_series([Text::new(name.to_string(), label, (FAMILY, 13).into_font().color(&grey))])?;
    }
    Ok(())
}

/// Every edge of `mesh` at `pose`, projected into `view` (edges wholly
/// outside the view are left out).
fn draw_wireframe<DB: DrawingBackend>(
    chart: &mut PanelChart<'_, DB>,
    view: &View,
    mesh: &TriMesh,
    pose: &Pose,
    color: RGBColor,
) -> Result<(), DrawingAreaErrorKind<DB::ErrorType>> {
    let projected: Vec<(Real, Real)> = mesh.vertices().iter().map(|v| view.project(&(pose * v))).collect();
    let limit = view.half_width * 3.0;
    let inside = |p: &(Real, Real)| p.0.abs() <= limit && p.1.abs() <= limit;
    let edges = mesh.triangles().iter().flat_map(|t| {
        [(t[0], t[1]), (t[1], t[2]), (t[2], t[0])]
            .into_iter()
            .map(|(i, j)| (projected[i as usize], projected[j as usize]))
            .filter(|(p, q)| inside(p) || inside(q) || crosses(p, q, limit))
    });
    let style = color.mix(0.6).stroke_width(1);
    chart.draw_series(edges.map(|(p, q)| PathElement::new(vec![p, q], style)))?;
    Ok(())
}

/// Whether the segment `p`–`q` may cross the square of half-width `limit`
/// (its bounding box overlaps it).
fn crosses(p: &(Real, Real), q: &(Real, Real), limit: Real) -> bool {
    p.0.min(q.0) <= limit && p.0.max(q.0) >= -limit && p.1.min(q.1) <= limit && p.1.max(q.1) >= -limit
}

//! `contact_<n>.png` and `nearest_near_miss.png`: a picture of a contact, or of
//! the run's nearest near miss, so that a user sees at a glance which
//! feature of which body hit (or passed) which (the `plot` feature).
//!
//! Three orthographic wireframe views of the two meshes at their poses at
//! that time, all centred on the midpoint of the two closest points, with
//! `n` the direction from body a's closest point towards body b's (the
//! contact normal; where the points coincide, triangle a's normal):
//! 1. from the side (n up), both bodies whole;
//! 2. the same, zoomed on the closest points: the smaller closest
//!    triangle, four contact distances (a near miss: four times its gap)
//!    and any crossing curve, with room, but between 4 and 10 times closer
//!    than the whole view (`MIN_ZOOM`, `ZOOM`), so that it always zooms;
//!    a near miss's two closest points are always in view;
//! 3. looking down n onto the closest points, zoomed alike.
//!
//! Body a is drawn in blue, body b in orange; the two closest triangles
//! are filled, the closest points are dots and n a red arrow; where the
//! bodies overlap, the curve where their surfaces cross is drawn in green
//! (its length in the legend). The caption
//! gives the time, the bodies, their triangles and features, the distance
//! and the contact distance (a near miss: the certified lower bound).

mod picture;

use std::path::Path;

use plotters::prelude::*;

use crate::plot::{draw_png, PlotError, FAMILY};
use crate::text;
use nearmiss::math::{Point, Pose, Real, Vector};
use nearmiss::mesh::{MeshDistance, TriMesh};
use nearmiss::run::Contact;
use nearmiss::run::NearMiss;
use picture::Picture;

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

/// The zoomed views magnify the whole view at most this many times: `10`
/// (more only where a near miss's gap needs it).
pub const ZOOM: Real = 10.0;

/// The zoomed views magnify the whole view at least this many times: `4`
/// (a coarse mesh's closest triangle may be as large as the bodies; the
/// zoomed views then show the features around the contact, not the same
/// picture again).
pub const MIN_ZOOM: Real = 4.0;

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
    /// A contact of this contact distance (see the module).
    Contact(Real),
    /// A gap of this distance (see the module).
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

//! PNG charts with plotters (the `plot` cargo feature, on by default).
//!
//! Text is drawn with ab_glyph from the DejaVu Sans font shipped in
//! `assets/fonts/` and compiled into the binary, so no system font library
//! is needed. Log axes plot `log10` of the values on a linear axis, labelled
//! in powers of ten. Files are rendered under a temporary name and renamed.

use std::path::Path;
use std::sync::Once;

use plotters::prelude::*;
use plotters::style::text_anchor::{HPos, Pos, VPos};

use nearmiss::math::Real;

/// The font every chart uses, compiled in.
const FONT: &[u8] = include_bytes!("../../assets/fonts/DejaVuSans.ttf");
/// The name the font is registered under.
pub(crate) const FAMILY: &str = "nearmiss-sans";

/// Series colours (contact marks are red).
const PALETTE: [RGBColor; 12] = [
    RGBColor(31, 119, 180),
    RGBColor(255, 127, 14),
    RGBColor(44, 160, 44),
    RGBColor(0, 0, 0),
    RGBColor(148, 103, 189),
    RGBColor(23, 190, 207),
    RGBColor(140, 86, 75),
    RGBColor(227, 119, 194),
    RGBColor(127, 127, 127),
    RGBColor(188, 189, 34),
    RGBColor(70, 70, 160),
    RGBColor(200, 120, 40),
];

/// The height of a tick (`Chart::ticks`), a fraction of the plot's.
pub const TICK_HEIGHT: Real = 0.04;

/// Chart size in pixels: readable at 1200 × 800.
pub const CHART_SIZE: (u32, u32) = (1200, 800);

/// One data series.
#[derive(Clone, Debug, Default)]
pub struct Series {
    /// The legend entry.
    pub label: String,
    /// The points `(x, y)`; non-finite points and, on log axes, points not
    /// above zero are left out.
    pub points: Vec<(Real, Real)>,
    /// Join the points with a line (otherwise markers only).
    pub line: bool,
    /// A text drawn beside each point (empty: none).
    pub point_labels: Vec<String>,
}

/// A chart: axes, series and vertical marks.
#[derive(Clone, Debug, Default)]
pub struct Chart {
    /// The title.
    pub title: String,
    /// The x axis label, with units.
    pub x_label: String,
    /// The y axis label, with units.
    pub y_label: String,
    /// Logarithmic x axis.
    pub log_x: bool,
    /// Logarithmic y axis.
    pub log_y: bool,
    /// The series.
    pub series: Vec<Series>,
    /// Vertical lines `(x, label)`, e.g. the first contact times.
    pub marks: Vec<(Real, String)>,
    /// Short unlabelled ticks on the x axis, e.g. every contact time: a
    /// thousand stay readable where a thousand lines would not.
    pub ticks: Vec<Real>,
}

/// Why a chart could not be written.
#[derive(Debug, thiserror::Error)]
pub enum PlotError {
    /// No series had a point that can be drawn.
    #[error("nothing to plot: no finite point (on a log axis: no positive value)")]
    Empty,
    /// plotters or the file system failed.
    #[error("cannot draw {path}: {message}")]
    Draw {
        /// The file.
        path: String,
        /// What failed.
        message: String,
    },
}

fn register_font() {
    static ONCE: Once = Once::new();
    ONCE.call_once(|| {
        // The font is compiled in and known to parse; a failure would only
        // leave text undrawn.
        let _ = plotters::style::register_font(FAMILY, FontStyle::Normal, FONT);
    });
}

/// The value as drawn on an axis.
fn axis_value(v: Real, log: bool) -> Option<Real> {
    let drawn = if log { (v > 0.0).then(|| v.log10())? } else { v };
    drawn.is_finite().then_some(drawn)
}

/// Rows of mark labels above the data (`Chart::marks`), at most.
const MARK_ROWS: usize = 4;

/// A mark label's row height, a fraction of the padded data's height.
const MARK_ROW_HEIGHT: Real = 0.07;

/// Linear ticks nearer 0 than this fraction of the axis's span are
/// rounding noise of the tick positions and written `0`. Default `1e-9`.
const ZERO_TICK_FRACTION: Real = 1e-9;

/// A tick label (`span`: the axis's length, in drawn units).
fn tick(v: Real, log: bool, span: Real) -> String {
    if !log && v.abs() <= ZERO_TICK_FRACTION * span {
        return "0".into();
    }
    if log {
        let power = 10f64.powf(v);
        if (v - v.round()).abs() < 1e-9 && !(0.0..=3.0).contains(&v.round()) {
            format!("1e{}", v.round() as i64)
        } else {
            crate::text::approx(power, 2)
        }
    } else {
        crate::text::approx(v, 4)
    }
}

/// Where a chart's data goes: each series' points on the axes' scales
/// (with their indices), the padded ranges, and the band of mark labels
/// above the data.
struct Framed {
    drawn: Vec<Vec<(Real, Real, usize)>>,
    x: (Real, Real),
    y: (Real, Real),
    /// The lowest value drawn, and the top of the data under the marks'
    /// band.
    data_low: Real,
    data_top: Real,
    /// The marks' label rows: their height and count.
    row_height: Real,
    rows: usize,
}

impl Framed {
    fn of(chart: &Chart) -> Result<Framed, PlotError> {
        let drawn: Vec<Vec<(Real, Real, usize)>> = chart
            .series
            .iter()
            .map(|s| {
                s.points
                    .iter()
                    .enumerate()
                    .filter_map(|(k, &(x, y))| {
                        Some((axis_value(x, chart.log_x)?, axis_value(y, chart.log_y)?, k))
                    })
                    .collect()
            })
            .collect();
        let all = || drawn.iter().flatten();
        let mut xs =
            all().map(|p| p.0).chain(chart.marks.iter().filter_map(|m| axis_value(m.0, chart.log_x)));
        let first = xs.next().ok_or(PlotError::Empty)?;
        let (mut x0, mut x1) = xs.fold((first, first), |(lo, hi), x| (lo.min(x), hi.max(x)));
        let (mut y0, mut y1) =
            all().fold((Real::INFINITY, Real::NEG_INFINITY), |(lo, hi), p| (lo.min(p.1), hi.max(p.1)));
        if !y0.is_finite() {
            return Err(PlotError::Empty);
        }
        let data_low = y0;
        let pad = |lo: &mut Real, hi: &mut Real| {
            let span = (*hi - *lo).max(if chart.log_y { 1.0 } else { 1e-12_f64.max(hi.abs() * 1e-3) });
            *lo -= span * 0.05;
            *hi += span * 0.05;
        };
        pad(&mut x0, &mut x1);
        pad(&mut y0, &mut y1);
        // The marks' labels get a band of their own above the data, a row
        // each (up to MARK_ROWS), so the data never runs through them.
        let rows = chart.marks.len().min(MARK_ROWS);
        let data_top = y1;
        let row_height = (y1 - y0) * MARK_ROW_HEIGHT;
        y1 += row_height * rows as Real;
        Ok(Framed { drawn, x: (x0, x1), y: (y0, y1), data_low, data_top, row_height, rows })
    }
}

/// Renders the chart to a PNG file at `path`.
pub fn render(chart: &Chart, path: &Path) -> Result<(), PlotError> {
    let Framed { drawn, x: (x0, x1), y: (y0, y1), data_low, data_top, row_height, rows } = Framed::of(chart)?;
    let (legend, legend_width) = legend_of(chart);

    draw_png(path, |root| {
        let error = |e: &dyn std::fmt::Display| e.to_string();
        let font = |size: u32| (FAMILY, size).into_font();
        // The title over the whole width; under it the plot and the legend.
        let body = root.margin(12, 0, 0, 0).titled(&chart.title, font(30)).map_err(|e| error(&e))?;
        let (area, side) = body.split_horizontally(CHART_SIZE.0 - legend_width);
        let mut context = ChartBuilder::on(&area)
            .margin(20)
            .x_label_area_size(60)
            .y_label_area_size(110)
            .build_cartesian_2d(x0..x1, y0..y1)
            .map_err(|e| error(&e))?;
        let (log_x, log_y) = (chart.log_x, chart.log_y);
        context
            .configure_mesh()
            .x_desc(&chart.x_label)
            .y_desc(&chart.y_label)
            .label_style(font(18))
            .axis_desc_style(font(22))
            .x_label_formatter(&|v| tick(*v, log_x, x1 - x0))
            .y_label_formatter(&|v| tick(*v, log_y, y1 - y0))
            .draw()
            .map_err(|e| error(&e))?;
        // Values below 0 on a linear axis: the 0 line drawn across.
        if !log_y && data_low < 0.0 {
            let gray = RGBColor(90, 90, 90).stroke_width(1);
            context
                .draw_series([PathElement::new(vec![(x0, 0.0), (x1, 0.0)], gray)])
                .map_err(|e| error(&e))?;
        }
        let red = RGBColor(200, 30, 30);
        let tick_top = y0 + (y1 - y0) * TICK_HEIGHT;
        let ticks = chart.ticks.iter().filter_map(|t| axis_value(*t, log_x));
        context
            .draw_series(ticks.map(|x| PathElement::new(vec![(x, y0), (x, tick_top)], red.stroke_width(1))))
            .map_err(|e| error(&e))?;
        for (k, (mark, label)) in chart.marks.iter().enumerate() {
            let Some(x) = axis_value(*mark, log_x) else { continue };
            // The first mark's row on top; each line rises to its own row,
            // so a later mark's line stops below the earlier labels.
            let y = data_top + row_height * ((rows - k % rows) as Real - 0.5);
            let style = ShapeStyle::from(&RGBColor(200, 30, 30)).stroke_width(2);
            let line_top = y + row_height * 0.3;
            context.draw_series(LineSeries::new([(x, y0), (x, line_top)], style)).map_err(|e| error(&e))?;
            // Labels go beside the line, on the side with more room.
            let right_half = x > (x0 + x1) / 2.0;
            let anchor = Pos::new(if right_half { HPos::Right } else { HPos::Left }, VPos::Center);
            let shift = (x1 - x0) * 0.005 * if right_half { -1.0 } else { 1.0 };
            let style = font(18).color(&RGBColor(200, 30, 30)).pos(anchor);
            context.draw_series([Text::new(label.clone(), (x + shift, y), style)]).map_err(|e| error(&e))?;
        }
        let mut labelled = std::collections::HashSet::new();
        for (index, (series, points)) in chart.series.iter().zip(&drawn).enumerate() {
            let color = PALETTE[index % PALETTE.len()].to_rgba();
            let style = ShapeStyle::from(&color).stroke_width(2);
            let coordinates: Vec<(Real, Real)> = points.iter().map(|p| (p.0, p.1)).collect();
            if series.line {
                context.draw_series(LineSeries::new(coordinates.clone(), style)).map_err(|e| error(&e))?;
            } else {
                context
                    .draw_series(coordinates.iter().map(|&p| Circle::new(p, 5, style.filled())))
                    .map_err(|e| error(&e))?;
            }
            if series.line && coordinates.len() <= 60 {
                context
                    .draw_series(coordinates.iter().map(|&p| Circle::new(p, 3, style.filled())))
                    .map_err(|e| error(&e))?;
            }
            // Point labels above and right of their points, each text once
            // (series of one sweep share their labels: `dt = 0.01`).
            for &(x, y, k) in points {
                if let Some(text) = series.point_labels.get(k).filter(|t| !t.is_empty()) {
                    if !labelled.insert(text.clone()) {
                        continue;
                    }
                    let style = font(15).color(&color).pos(Pos::new(HPos::Left, VPos::Bottom));
                    context
                        .draw_series([EmptyElement::at((x, y)) + Text::new(text.clone(), (6, -6), style)])
                        .map_err(|e| error(&e))?;
                }
            }
        }
        draw_legend(&side, &legend, font(18)).map_err(|e| error(&e))?;
        Ok(())
    })
}

/// The legend: each labelled series (label, colour, drawn as a line), in
/// a column right of the plot, where neither the data nor the marks'
/// labels can run under it; and the column's width in pixels.
fn legend_of(chart: &Chart) -> (Vec<(String, RGBAColor, bool)>, u32) {
    let legend: Vec<(String, RGBAColor, bool)> = chart
        .series
        .iter()
        .enumerate()
        .filter(|(_, s)| !s.label.is_empty())
        .map(|(index, s)| (s.label.clone(), PALETTE[index % PALETTE.len()].to_rgba(), s.line))
        .collect();
    let legend_width = legend
        .iter()
        .map(|(label, ..)| label.chars().count() as u32 * LEGEND_CHAR_WIDTH + LEGEND_TEXT_AT + 15)
        .max()
        .unwrap_or(0)
        .min(CHART_SIZE.0 / 4);
    (legend, legend_width)
}

/// A legend character's width at the legend's font size, pixels (DejaVu
/// Sans at 18 px averages under 10).
const LEGEND_CHAR_WIDTH: u32 = 10;

/// Where a legend entry's text starts, right of its swatch, pixels.
const LEGEND_TEXT_AT: u32 = 38;

/// The legend's entries `(label, colour, drawn as a line)` down the side
/// column, level with the top of the plot; a label too long for the column
/// wraps at spaces.
fn draw_legend<DB: DrawingBackend>(
    side: &DrawingArea<DB, plotters::coord::Shift>,
    entries: &[(String, RGBAColor, bool)],
    font: FontDesc<'_>,
) -> Result<(), DrawingAreaErrorKind<DB::ErrorType>> {
    let columns =
        ((side.dim_in_pixel().0.saturating_sub(LEGEND_TEXT_AT + 10)) / LEGEND_CHAR_WIDTH).max(8) as usize;
    let mut y = 40;
    for (label, colour, line) in entries {
        if *line {
            side.draw(&PathElement::new(vec![(0, y), (28, y)], colour.stroke_width(3)))?;
        } else {
            side.draw(&Circle::new((14, y), 5, colour.filled()))?;
        }
        for text in wrap(label, columns) {
            side.draw(&Text::new(text, (LEGEND_TEXT_AT as i32, y - 10), font.clone()))?;
            y += 22;
        }
        y += 8;
    }
    Ok(())
}

/// `text` in lines of at most `columns` characters, broken at spaces (a
/// word longer than a line stands alone).
fn wrap(text: &str, columns: usize) -> Vec<String> {
    let mut lines: Vec<String> = Vec::new();
    for word in text.split(' ') {
        match lines.last_mut() {
            Some(line) if line.chars().count() + 1 + word.chars().count() <= columns => {
                line.push(' ');
                line.push_str(word);
            }
            _ => lines.push(word.to_string()),
        }
    }
    lines
}

/// Draws a [`CHART_SIZE`] PNG at `path`: `draw` paints on a white canvas
/// (its errors as text), rendered under a temporary name first (per
/// process, so that concurrent runs into one folder never share it) and
/// renamed.
pub(crate) fn draw_png(
    path: &Path,
    draw: impl FnOnce(&DrawingArea<BitMapBackend<'_>, plotters::coord::Shift>) -> Result<(), String>,
) -> Result<(), PlotError> {
    register_font();
    let error = |message: String| PlotError::Draw { path: path.display().to_string(), message };
    let name = path.file_name().map(|n| n.to_string_lossy().into_owned()).unwrap_or_default();
    let temporary = path.with_file_name(format!(".{name}.{}.tmp.png", std::process::id()));
    {
        let root = BitMapBackend::new(&temporary, CHART_SIZE).into_drawing_area();
        root.fill(&WHITE).map_err(|e| error(e.to_string()))?;
        draw(&root).map_err(error)?;
        root.present().map_err(|e| error(e.to_string()))?;
    }
    std::fs::rename(&temporary, path).map_err(|e| error(e.to_string()))
}

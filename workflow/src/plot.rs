//! Plots an engineer reads instead of tables (SVG, no system fonts needed): ship surge speed,
//! ship and anchor displacement, peak joint tension along the line against the load
//! limits, and the energy terms. Several runs are overlaid.

use std::path::{Path, PathBuf};

use kanestop_chain::BodyKind;
use kanestop_runtime::forces::WORK_TERMS;
use kanestop_runtime::model::{LoadLimits, Model};
use kanestop_runtime::simulate::{RunResult, Sample, Stop};
use plotters::prelude::*;
use plotters::style::text_anchor::{HPos, Pos, VPos};

use crate::output::write_atomically;
use crate::{Error, Result};

/// Ten distinguishable colours (the common "category10" set).
const PALETTE: [RGBColor; 10] = [
    RGBColor(31, 119, 180),
    RGBColor(214, 39, 40),
    RGBColor(44, 160, 44),
    RGBColor(148, 103, 189),
    RGBColor(255, 127, 14),
    RGBColor(23, 190, 207),
    RGBColor(140, 86, 75),
    RGBColor(227, 119, 194),
    RGBColor(127, 127, 127),
    RGBColor(188, 189, 34),
];

/// The line pattern of a curve.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Pattern {
    Solid,
    Dashed,
    Dotted,
}

/// The look of the i-th curve of a chart: ten colours, then the same ten dashed, then
/// dotted, so thirty curves are told apart before any look repeats.
fn look(i: usize) -> (RGBColor, Pattern) {
    let pattern = match (i / PALETTE.len()) % 3 {
        0 => Pattern::Solid,
        1 => Pattern::Dashed,
        _ => Pattern::Dotted,
    };
    (PALETTE[i % PALETTE.len()], pattern)
}

/// Type sizes, px as drawn. A chart is about 1 000 px wide and read at about 16 cm in a
/// report, so 14 px is about 8 pt there.
const TITLE_FONT: f64 = 22.0;
/// A panel's own title.
const PANEL_TITLE_FONT: f64 = 18.0;
/// Axis descriptions.
const AXIS_FONT: f64 = 15.0;
/// Tick labels and legend entries.
const TICK_FONT: f64 = 14.0;

/// A sans-serif font drawn at `px`: plotters' SVG backend writes a size s as s / 1.24 px.
pub(crate) fn sans(px: f64) -> (&'static str, f64) {
    ("sans-serif", px * 1.24)
}

/// A point marked on a curve, in the curve's colour.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Mark {
    /// Where a run failed (its last good state): a cross.
    Failure,
    /// The paper's stopping time (Table 3): a triangle on the time axis.
    Paper,
}

impl Mark {
    /// What the mark stands for, as its legend entry says.
    fn label(self) -> &'static str {
        match self {
            Mark::Failure => "run failed here",
            Mark::Paper => "paper's stopping time (Table 3)",
        }
    }
}

/// One named curve; a non-finite point breaks the line.
struct Curve {
    label: String,
    points: Vec<(f64, f64)>,
    /// Its index for [`look`].
    look: usize,
    /// A reference line (a load limit): thin and dashed.
    reference: bool,
    /// A reference line the axis always takes in (the limits of a utilisation chart);
    /// otherwise one far above the curves is left out of the axis and named in the legend.
    in_view: bool,
    /// Points marked on the curve.
    marks: Vec<((f64, f64), Mark)>,
}

impl Curve {
    fn new(label: impl Into<String>, look: usize, points: Vec<(f64, f64)>) -> Self {
        Curve { label: label.into(), points, look, reference: false, in_view: false, marks: Vec::new() }
    }

    /// A load limit: thin, dashed, `in_view` as above.
    fn limit(label: impl Into<String>, look: usize, points: Vec<(f64, f64)>, in_view: bool) -> Self {
        Curve { reference: true, in_view, ..Curve::new(label, look, points) }
    }

    /// The stretches of the curve with finite points inside `y` (a reference line is cut
    /// where it leaves the axis).
    fn pieces(&self, y: (f64, f64)) -> Vec<Vec<(f64, f64)>> {
        let mut pieces = vec![Vec::new()];
        for &(a, b) in &self.points {
            let inside = a.is_finite() && b.is_finite() && (!self.reference || (b >= y.0 && b <= y.1));
            if inside {
                pieces.last_mut().unwrap().push((a, b));
            } else if !pieces.last().unwrap().is_empty() {
                pieces.push(Vec::new());
            }
        }
        pieces.retain(|p| !p.is_empty());
        pieces
    }

    /// How it is drawn: its colour, its pattern (a limit's dashed) and its width.
    fn stroke(&self) -> (RGBColor, Pattern, u32) {
        let (color, pattern) = look(self.look);
        if self.reference {
            (color, Pattern::Dashed, 1)
        } else {
            (color, pattern, 2)
        }
    }

    /// Its legend text on the axis `y`: none for a curve with no point to draw; a limit above
    /// the axis says so.
    fn legend_label(&self, y: (f64, f64)) -> Option<String> {
        let finite = self.points.iter().filter(|(a, b)| a.is_finite() && b.is_finite()).count();
        if finite == 0 || self.label.is_empty() {
            return None;
        }
        let shown: usize = self.pieces(y).iter().map(Vec::len).sum();
        Some(match (self.reference, shown) {
            (true, 0) => format!("{} (above the axis)", self.label),
            (true, s) if s < finite => format!("{} (partly above the axis)", self.label),
            _ => self.label.clone(),
        })
    }
}

/// What a legend entry shows beside its text.
#[derive(Clone, Copy, Debug, PartialEq)]
enum Swatch {
    Line(RGBColor, Pattern, u32),
    Mark(Mark),
}

/// A legend entry: a swatch and its text (wrapped to lines of [`LEGEND_CHARS`]).
#[derive(Clone, Debug, PartialEq)]
struct Entry {
    label: String,
    swatch: Swatch,
}

/// The longest line of a legend entry, characters; a longer text wraps at a space.
const LEGEND_CHARS: usize = 44;
/// A legend line's height, px.
const LEGEND_LINE: u32 = TICK_FONT as u32 + 6;

/// The legend of `curves` drawn on the axis `y`: one entry per label (the first curve's
/// look), then one per kind of mark.
fn entries(curves: &[Curve], y: (f64, f64)) -> Vec<Entry> {
    let mut out: Vec<Entry> = Vec::new();
    for c in curves {
        if let Some(label) = c.legend_label(y) {
            let (color, pattern, width) = c.stroke();
            let entry = Entry { label, swatch: Swatch::Line(color, pattern, width) };
            // One entry per label and look (two runs of one name keep two).
            if !out.contains(&entry) {
                out.push(entry);
            }
        }
    }
    for mark in [Mark::Failure, Mark::Paper] {
        if curves.iter().any(|c| c.marks.iter().any(|m| m.1 == mark)) {
            out.push(Entry { label: mark.label().to_string(), swatch: Swatch::Mark(mark) });
        }
    }
    out
}

/// `text` in lines of at most `width` characters, broken at spaces (a longer word is a line
/// of its own).
pub(crate) fn wrap(text: &str, width: usize) -> Vec<String> {
    let mut lines: Vec<String> = Vec::new();
    for word in text.split(' ') {
        match lines.last_mut() {
            Some(line) if line.chars().count() + 1 + word.chars().count() <= width => {
                line.push(' ');
                line.push_str(word);
            }
            _ => lines.push(word.to_string()),
        }
    }
    lines
}

/// A legend's layout: each entry's column and first line, and a column's width, px. Text
/// width is estimated at 0.6 em a character (sans-serif, generous).
struct LegendLayout {
    /// (column, line) of each entry, in order.
    places: Vec<(usize, usize)>,
    columns: usize,
    column_width: u32,
}

/// The legend's height, px, for `height` px of figure: the plot's, less the space above its
/// first entry (the title's, at most [`LEGEND_TOP`]).
const LEGEND_TOP: u32 = 60;

/// Lays `entries` out top down in columns of the lines that `height` px hold (after
/// [`LEGEND_TOP`]); an entry whose lines do not fit below the last starts the next column.
fn legend_layout(entries: &[Entry], height: u32) -> LegendLayout {
    let widest = entries.iter().flat_map(|e| wrap(&e.label, LEGEND_CHARS)).map(|l| l.chars().count()).max();
    let column_width = 48 + (0.6 * TICK_FONT * widest.unwrap_or(0) as f64).ceil() as u32;
    let per_column = (height.saturating_sub(LEGEND_TOP) / LEGEND_LINE).max(1) as usize;
    let (mut column, mut line) = (0usize, 0usize);
    let mut places = Vec::new();
    for e in entries {
        let lines = wrap(&e.label, LEGEND_CHARS).len();
        if line > 0 && line + lines > per_column {
            (column, line) = (column + 1, 0);
        }
        places.push((column, line));
        line += lines;
    }
    LegendLayout { places, columns: column + 1, column_width }
}

/// The legend's width, px, beside a figure `height` px tall (none without entries).
fn legend_width(entries: &[Entry], height: u32) -> u32 {
    if entries.is_empty() {
        return 0;
    }
    let layout = legend_layout(entries, height);
    layout.columns as u32 * layout.column_width + 12
}

/// Draws `entries` in `area` (the strip beside a figure `height` px tall, its top level with
/// the figure's), laid out as [`legend_width`] sized it.
fn draw_legend<DB: DrawingBackend>(
    area: &DrawingArea<DB, plotters::coord::Shift>,
    entries: &[Entry],
    height: u32,
) -> Result<(), String> {
    let err = |e: DrawingAreaErrorKind<DB::ErrorType>| e.to_string();
    let layout = legend_layout(entries, height);
    let text = sans(TICK_FONT).into_font().color(&BLACK).pos(Pos::new(HPos::Left, VPos::Center));
    for (entry, &(column, line)) in entries.iter().zip(&layout.places) {
        let x = 4 + (column as u32 * layout.column_width) as i32;
        let y = LEGEND_TOP as i32 + (line as u32 * LEGEND_LINE) as i32 + LEGEND_LINE as i32 / 2;
        match entry.swatch {
            Swatch::Line(color, pattern, stroke) => {
                let style = ShapeStyle { color: color.to_rgba(), filled: false, stroke_width: stroke };
                let dashes: &[(i32, i32)] = match pattern {
                    Pattern::Solid => &[(0, 28)],
                    Pattern::Dashed => &[(0, 10), (15, 28)],
                    Pattern::Dotted => &[(0, 3), (8, 11), (16, 19), (24, 27)],
                };
                for &(a, b) in dashes {
                    area.draw(&PathElement::new(vec![(x + a, y), (x + b, y)], style)).map_err(err)?;
                }
            }
            Swatch::Mark(mark) => draw_mark(area, (x + 14, y), mark, RGBColor(70, 70, 70)).map_err(err)?,
        }
        for (i, line) in wrap(&entry.label, LEGEND_CHARS).iter().enumerate() {
            area.draw(&Text::new(line.clone(), (x + 38, y + (i as u32 * LEGEND_LINE) as i32), text.clone()))
                .map_err(err)?;
        }
    }
    Ok(())
}

/// A mark at pixel `at`.
fn draw_mark<DB: DrawingBackend>(
    area: &DrawingArea<DB, plotters::coord::Shift>,
    at: (i32, i32),
    mark: Mark,
    color: RGBColor,
) -> Result<(), DrawingAreaErrorKind<DB::ErrorType>> {
    match mark {
        Mark::Failure => area.draw(&Cross::new(at, 6, color.stroke_width(3))),
        Mark::Paper => area.draw(&TriangleMarker::new(at, 7, color.filled())),
    }
}

/// The axes' ranges: x over every curve and mark, y over the data curves, their marks and the reference
/// lines (load limits) that lie within 2.5 × the data's largest value (a limit far above the
/// data must not flatten it; the legend names it), from zero when `from_zero`, padded by 5 %.
fn bounds(curves: &[Curve], from_zero: bool) -> ((f64, f64), (f64, f64)) {
    let finite =
        |c: &Curve| c.points.iter().copied().filter(|(a, b)| a.is_finite() && b.is_finite()).collect::<Vec<_>>();
    let mut x = (f64::INFINITY, f64::NEG_INFINITY);
    let mut y = (if from_zero { 0.0 } else { f64::INFINITY }, if from_zero { 0.0 } else { f64::NEG_INFINITY });
    for c in curves {
        // A curve's marks are in view (the paper's stopping time after the run's stop).
        let marks = c.marks.iter().map(|m| m.0).filter(|(a, b)| a.is_finite() && b.is_finite());
        for (a, b) in finite(c).into_iter().chain(marks) {
            x = (x.0.min(a), x.1.max(a));
            if !c.reference {
                y = (y.0.min(b), y.1.max(b));
            }
        }
    }
    if !x.0.is_finite() {
        return ((0.0, 1.0), (0.0, 1.0));
    }
    if !(y.0.is_finite() && y.1.is_finite()) {
        y = (0.0, 1.0);
    }
    let reach = y.1 + 1.5 * (y.1 - y.0).max(y.1.abs());
    for c in curves.iter().filter(|c| c.reference) {
        let top = finite(c).iter().map(|p| p.1).filter(|&v| c.in_view || v <= reach).fold(f64::NEG_INFINITY, f64::max);
        y.1 = y.1.max(top);
    }
    let pad = 0.05 * (y.1 - y.0).max(1e-9 * y.1.abs().max(1.0));
    ((x.0, x.1.max(x.0 + 1e-9)), (if from_zero && y.0 >= 0.0 { 0.0 } else { y.0 - pad }, y.1 + pad))
}

/// The corner of the plot with the fewest of `points`, for the legend (on a log axis, give
/// the logarithms of the points and of the bounds).
fn emptiest_corner(points: &[(f64, f64)], (x0, x1): (f64, f64), (y0, y1): (f64, f64)) -> SeriesLabelPosition {
    let corners = [
        (SeriesLabelPosition::UpperRight, true, true),
        (SeriesLabelPosition::UpperLeft, false, true),
        (SeriesLabelPosition::LowerRight, true, false),
        (SeriesLabelPosition::LowerLeft, false, false),
    ];
    let count = |right: bool, upper: bool| {
        points
            .iter()
            .filter(|(a, b)| {
                let (u, v) = ((a - x0) / (x1 - x0), (b - y0) / (y1 - y0));
                (if right { u > 0.6 } else { u < 0.4 }) && (if upper { v > 0.55 } else { v < 0.45 })
            })
            .count()
    };
    corners.into_iter().min_by_key(|&(_, r, u)| count(r, u)).map(|c| c.0).unwrap_or(SeriesLabelPosition::UpperRight)
}

/// Size of a chart's plot, pixels (its legend is beside it).
const SIZE: (u32, u32) = (900, 540);

/// A chart of one panel, its legend beside it, as SVG text; `regions` names stretches of
/// the x axis (the line's members along the distance from the anchor, m).
fn chart(
    title: &str,
    x_label: &str,
    y_label: &str,
    curves: &[Curve],
    from_zero: bool,
    regions: &[(String, f64, f64)],
) -> Result<String, String> {
    let (_, y) = bounds(curves, from_zero);
    let legend = entries(curves, y);
    let side = legend_width(&legend, SIZE.1);
    let mut svg = String::new();
    {
        let root = SVGBackend::with_string(&mut svg, (SIZE.0 + side, SIZE.1)).into_drawing_area();
        root.fill(&WHITE).map_err(|e| e.to_string())?;
        let (plot, beside) = root.split_horizontally(SIZE.0);
        panel(&plot, title, TITLE_FONT, x_label, y_label, curves, from_zero, regions)?;
        draw_legend(&beside, &legend, SIZE.1)?;
        root.present().map_err(|e| e.to_string())?;
    }
    Ok(svg)
}

/// Panels stacked or in a grid, each `(title, curves)`, sharing the axis labels and one
/// legend beside them (a label's first look), as SVG.
fn panels(
    title: &str,
    x_label: &str,
    y_label: &str,
    panels: &[(String, Vec<Curve>)],
    columns: usize,
) -> Result<String, String> {
    let columns = columns.clamp(1, panels.len().max(1));
    let rows = panels.len().div_ceil(columns).max(1);
    let (w, h) = (SIZE.0.max(450 * columns as u32), if rows == 1 { SIZE.1 } else { 300 * rows as u32 + 40 });
    let mut legend: Vec<Entry> = Vec::new();
    for (_, curves) in panels {
        for e in entries(curves, bounds(curves, false).1) {
            if !legend.contains(&e) {
                legend.push(e);
            }
        }
    }
    // Marks last, as in one panel's legend.
    legend.sort_by_key(|e| matches!(e.swatch, Swatch::Mark(_)));
    let side = legend_width(&legend, h);
    let mut svg = String::new();
    {
        let root = SVGBackend::with_string(&mut svg, (w + side, h)).into_drawing_area();
        root.fill(&WHITE).map_err(|e| e.to_string())?;
        let (left, beside) = root.split_horizontally(w);
        let grid = left.titled(title, sans(TITLE_FONT)).map_err(|e| e.to_string())?;
        let areas = grid.split_evenly((rows, columns));
        for (area, (sub, curves)) in areas.iter().zip(panels) {
            panel(area, sub, PANEL_TITLE_FONT, x_label, y_label, curves, false, &[])?;
        }
        draw_legend(&beside, &legend, h)?;
        root.present().map_err(|e| e.to_string())?;
    }
    Ok(svg)
}

/// Draws one panel: axes with a light grid, the regions' bounds and names, the curves and
/// their marks (the legend is drawn beside the panel, by the caller).
#[allow(clippy::too_many_arguments)]
fn panel<DB: DrawingBackend>(
    area: &DrawingArea<DB, plotters::coord::Shift>,
    title: &str,
    title_size: f64,
    x_label: &str,
    y_label: &str,
    curves: &[Curve],
    from_zero: bool,
    regions: &[(String, f64, f64)],
) -> Result<(), String> {
    let err = |e: DrawingAreaErrorKind<DB::ErrorType>| e.to_string();
    let ((x0, x1), (y0, y1)) = bounds(curves, from_zero);
    let mut c = ChartBuilder::on(area)
        .caption(title, sans(title_size))
        .margin(12)
        .x_label_area_size(50)
        .y_label_area_size(78)
        .build_cartesian_2d(x0..x1, y0..y1)
        .map_err(err)?;
    c.configure_mesh()
        .x_desc(x_label)
        .y_desc(y_label)
        .label_style(sans(TICK_FONT))
        .axis_desc_style(sans(AXIS_FONT))
        .light_line_style(RGBColor(244, 244, 244))
        .bold_line_style(RGBColor(220, 220, 220))
        .x_label_formatter(&|v| tidy(*v))
        .y_label_formatter(&|v| tidy(*v))
        .draw()
        .map_err(err)?;
    // Pixels on `area` from the chart's, which are the backend's.
    let base = area.get_base_pixel();
    // The members along the line: a grey bound between two, the name at the top of each
    // wide enough to hold it.
    let grey = RGBColor(150, 150, 150);
    let name = sans(TICK_FONT).into_font().color(&grey).pos(Pos::new(HPos::Center, VPos::Top));
    for (i, (label, from, to)) in regions.iter().enumerate() {
        if i > 0 {
            c.draw_series(DashedLineSeries::new([(*from, y0), (*from, y1)], 4, 4, grey.stroke_width(1)))
                .map_err(err)?;
        }
        let (a, b) = (c.backend_coord(&(*from, y1)), c.backend_coord(&(*to, y1)));
        if (b.0 - a.0) as f64 > 0.6 * TICK_FONT * label.chars().count() as f64 + 4.0 {
            let at = c.backend_coord(&(0.5 * (from + to), y1));
            area.draw(&Text::new(label.clone(), (at.0 - base.0, at.1 - base.1 + 4), name.clone())).map_err(err)?;
        }
    }
    for curve in curves {
        let (color, pattern, width) = curve.stroke();
        let style = ShapeStyle { color: color.to_rgba(), filled: false, stroke_width: width };
        for piece in curve.pieces((y0, y1)) {
            match pattern {
                Pattern::Solid => c.draw_series(LineSeries::new(piece, style)),
                Pattern::Dashed => c.draw_series(DashedLineSeries::new(piece, 8, 5, style)),
                Pattern::Dotted => c.draw_series(DashedLineSeries::new(piece, 2, 4, style)),
            }
            .map_err(err)?;
        }
        for &(at, mark) in &curve.marks {
            if at.0.is_finite() && at.1.is_finite() && (x0..=x1).contains(&at.0) && (y0..=y1).contains(&at.1) {
                let p = c.backend_coord(&at);
                draw_mark(area, (p.0 - base.0, p.1 - base.1), mark, color).map_err(err)?;
            }
        }
    }
    Ok(())
}

/// The files [`write_plots`] writes into its folder.
pub const FILES: [&str; 5] =
    ["ship-speed.svg", "displacement.svg", "peak-tension.svg", "utilisation.svg", "energy.svg"];

/// Writes ship-speed.svg, displacement.svg (ship above, anchor below), peak-tension.svg,
/// utilisation.svg (peak tension over break load along the line) and energy.svg (a panel per
/// run) for the runs into `dir`, each whole or not at all; every chart is drawn before the
/// first is written. A run with no samples (refused before its first step) has no curves; a
/// failed run is named so and its end marked, and the paper's stopping time is marked on
/// the speed chart. Returns the files written.
pub fn write_plots(runs: &[(&Model, &RunResult)], dir: &Path) -> Result<Vec<PathBuf>> {
    let (ship, anchor) = displacement_curves(runs);
    let energy: Vec<(String, Vec<Curve>)> = runs
        .iter()
        .filter(|(_, r)| !r.samples.is_empty())
        .map(|(m, r)| (run_label(m, r), energy_curves(m, r)))
        .collect();
    // Each panel is named by its run (one run's too: "case01", or how it failed).
    let energy_title = "Energy terms";
    let columns = if energy.len() > 1 { 2 } else { 1 };
    // The members of the lines, drawn when every run's line has the first's over the same
    // stretches (lines laid out otherwise are compared by distance along the line).
    let regions = match runs.first() {
        Some((m, _)) if same_members(runs.iter().map(|(m, _)| *m)) => members(m),
        _ => Vec::new(),
    };
    let charts = [
        (FILES[0], chart("Ship surge speed", "t (s)", "surge speed (m/s)", &speed_curves(runs), false, &[])),
        (
            FILES[1],
            panels(
                "Ship and anchor displacement",
                "t (s)",
                "displacement (m)",
                &[("ship".to_string(), ship), ("anchor (drag distance)".to_string(), anchor)],
                1,
            ),
        ),
        (
            FILES[2],
            chart("Peak joint tension along the line", ALONG, "tension (kN)", &tension_curves(runs), true, &regions),
        ),
        (
            FILES[3],
            chart(
                "Utilisation along the line: peak tension / break load",
                ALONG,
                "utilisation (%)",
                &utilisation_curves(runs),
                true,
                &regions,
            ),
        ),
        (FILES[4], panels(energy_title, "t (s)", "energy (MJ)", &energy, columns)),
    ];
    let mut svgs = Vec::new();
    for (file, svg) in charts {
        svgs.push((file, svg.map_err(|message| Error::Plot { chart: file.to_string(), message })?));
    }
    std::fs::create_dir_all(dir).map_err(Error::io("create", dir))?;
    let mut files = Vec::new();
    for (file, svg) in svgs {
        let path = dir.join(file);
        write_atomically(&path, svg.as_bytes()).map_err(Error::io("write", &path))?;
        files.push(path);
    }
    Ok(files)
}

/// A run's name in a legend, with how it ended when that is not the ship stopping: "failed
/// at 0.31 s", or "not stopped by 60 s".
fn run_label(m: &Model, r: &RunResult) -> String {
    let name = &m.scene.meta.name;
    match (&r.stop, r.stopping_time) {
        (Stop::Failed(_), _) => format!("{name} (failed at {} s)", tidy_time(r.t_end)),
        (Stop::EndTime, None) => format!("{name} (not stopped by {} s)", tidy_time(r.t_end)),
        _ => name.clone(),
    }
}

/// A time to two decimals, as short as it reads.
fn tidy_time(t: f64) -> String {
    tidy((t * 100.0).round() / 100.0)
}

/// The failure mark at a failed run's last point.
fn failure_mark(r: &RunResult, points: &[(f64, f64)]) -> Vec<((f64, f64), Mark)> {
    match (&r.stop, points.last()) {
        (Stop::Failed(_), Some(&last)) => vec![(last, Mark::Failure)],
        _ => Vec::new(),
    }
}

/// The ship's surge speed of each run, the paper's stopping time marked on the time axis.
fn speed_curves(runs: &[(&Model, &RunResult)]) -> Vec<Curve> {
    runs.iter()
        .enumerate()
        .map(|(i, (m, r))| {
            let n = m.body_count();
            let points: Vec<(f64, f64)> = r.samples.iter().map(|s| (s.t, s.bodies[n - 1].vx)).collect();
            let mut curve = Curve::new(run_label(m, r), i, points);
            curve.marks = failure_mark(r, &curve.points);
            // Table 3's time for one of its cases only, as every report (a variant extending
            // a case inherits its `meta.paper_stopping_time`).
            if let Some(t) = kanestop_runtime::paper::stopping_time(&m.scene) {
                curve.marks.push(((t, 0.0), Mark::Paper));
            }
            curve
        })
        .collect()
}

/// The ship's and the anchor's displacement of each run that has samples, one colour per
/// run, named once in the figure's legend.
fn displacement_curves(runs: &[(&Model, &RunResult)]) -> (Vec<Curve>, Vec<Curve>) {
    let (mut ship, mut anchor) = (Vec::new(), Vec::new());
    for (i, (m, r)) in runs.iter().enumerate() {
        let Some(first) = r.samples.first() else { continue };
        let n = m.body_count();
        let (s0, a0) = (first.bodies[n - 1].x, first.bodies[0].x);
        for (curves, body, origin) in [(&mut ship, n - 1, s0), (&mut anchor, 0, a0)] {
            let points: Vec<(f64, f64)> = r.samples.iter().map(|s| (s.t, s.bodies[body].x - origin)).collect();
            let mut curve = Curve::new(run_label(m, r), i, points);
            curve.marks = failure_mark(r, &curve.points);
            curves.push(curve);
        }
    }
    (ship, anchor)
}

/// The x axis of the charts along the line.
const ALONG: &str = "distance along the line from the anchor (m)";

/// The distance along the line from the anchor's shackle (joint 2) to each joint k = 2 … N
/// (index k − 2), m: the unstretched lengths of the bodies between, B_2 … B_{k−1}. The
/// position of the joint's tension on the charts along the line, so that lines of other
/// element counts or stages compare at the same place.
fn joint_distances(m: &Model) -> Vec<f64> {
    let bodies = &m.chain.bodies;
    let mut s = vec![0.0];
    for body in &bodies[1..bodies.len() - 1] {
        s.push(s[s.len() - 1] + body.length());
    }
    s
}

/// The member a body of the line belongs to, for the regions and the limits: the rod's
/// limits are the cable's.
fn member(kind: BodyKind) -> &'static str {
    match kind {
        BodyKind::ChainLink => "chain",
        BodyKind::Cable { .. } => "cable",
        BodyKind::Rod | BodyKind::Ship | BodyKind::Anchor => "rod",
    }
}

/// The line's members along the distance axis: each name with the stretch its bodies
/// (B_2 … B_{N−1}) cover, as (name, from, to) in m.
fn members(m: &Model) -> Vec<(String, f64, f64)> {
    let s = joint_distances(m);
    let mut out: Vec<(String, f64, f64)> = Vec::new();
    for (i, body) in m.chain.bodies[1..m.chain.bodies.len() - 1].iter().enumerate() {
        let (name, from, to) = (member(body.kind), s[i], s[i + 1]);
        match out.last_mut() {
            Some(last) if last.0 == name => last.2 = to,
            _ => out.push((name.to_string(), from, to)),
        }
    }
    out
}

/// Whether every line has the first's members over the same stretches (to a millimetre):
/// then one set of member regions serves all the runs.
fn same_members<'a>(mut models: impl Iterator<Item = &'a Model>) -> bool {
    let Some(first) = models.next() else { return true };
    let a = members(first);
    models.all(|m| {
        let b = members(m);
        a.len() == b.len()
            && a.iter().zip(&b).all(|(p, q)| p.0 == q.0 && (p.1 - q.1).abs() < 1e-3 && (p.2 - q.2).abs() < 1e-3)
    })
}

/// Whether every line has the first's members over the same stretches and the same load
/// limits: then the first run's limits are every run's, and need no scene's name.
fn same_limits(runs: &[(&Model, &RunResult)]) -> bool {
    let limits = |m: &Model| [BodyKind::ChainLink, BodyKind::Rod].map(|k| m.member_limits(k));
    same_members(runs.iter().map(|(m, _)| *m)) && runs.iter().all(|(m, _)| limits(m) == limits(runs[0].0))
}

/// A limit along the line as a step: flat over each body of the line (B_2 … B_{N−1}) at
/// `value` of its kind, a vertical jump where it changes, a gap over a body that has none.
fn step(m: &Model, value: impl Fn(BodyKind) -> Option<f64>) -> Vec<(f64, f64)> {
    let s = joint_distances(m);
    let mut points = Vec::new();
    for (i, body) in m.chain.bodies[1..m.chain.bodies.len() - 1].iter().enumerate() {
        match value(body.kind) {
            Some(v) => points.extend([(s[i], v), (s[i + 1], v)]),
            None => points.push((f64::NAN, f64::NAN)),
        }
    }
    points
}

/// The member whose limit governs joint k (the weaker of its two bodies'): "chain" or
/// "cable" (the rod is of the cable), with that limit, N.
fn governing(m: &Model, k: usize, pick: fn(LoadLimits) -> Option<f64>) -> Option<(&'static str, f64)> {
    [m.chain.bodies[k - 2].kind, m.chain.bodies[k - 1].kind]
        .into_iter()
        .filter_map(|kind| {
            let name = match kind {
                BodyKind::ChainLink => "chain",
                BodyKind::Cable { .. } | BodyKind::Rod => "cable",
                BodyKind::Anchor | BodyKind::Ship => return None,
            };
            pick(m.member_limits(kind)).map(|v| (name, v))
        })
        .min_by(|a, b| a.1.total_cmp(&b.1))
}

/// A limit's legend text: its members and values, "chain proof load 2709 kN", or "break
/// load: chain 3866, cable 2520 kN" where members differ.
fn limit_label(m: &Model, what: &str, pick: fn(LoadLimits) -> Option<f64>) -> String {
    let mut seen: Vec<(&str, f64)> = Vec::new();
    for k in 2..=m.body_count() {
        if let Some(g) = governing(m, k, pick) {
            if !seen.contains(&g) {
                seen.push(g);
            }
        }
    }
    match seen.as_slice() {
        [] => what.to_string(),
        [(name, v)] => format!("{name} {what} {:.0} kN", v / 1e3),
        _ => {
            let parts: Vec<String> = seen.iter().map(|(name, v)| format!("{name} {:.0}", v / 1e3)).collect();
            format!("{what}: {} kN", parts.join(", "))
        }
    }
}

/// The peak tension along the line of each run (kN), and the first run's proof and break
/// loads as steps named by member; the axis follows the peaks, a limit above it is named in
/// the legend.
fn tension_curves(runs: &[(&Model, &RunResult)]) -> Vec<Curve> {
    let mut curves: Vec<Curve> = runs
        .iter()
        .enumerate()
        .filter(|(_, (_, r))| r.ran())
        .map(|(i, (m, r))| {
            let s = joint_distances(m);
            let points = r.peak_tensions.iter().zip(s).map(|(p, s)| (s, p.tension / 1e3)).collect();
            Curve::new(format!("{} peak", run_label(m, r)), i, points)
        })
        .collect();
    if let Some((m, _)) = runs.first() {
        // The first run's limits, over its own line; named by its scene where another
        // run's line is laid out otherwise or has other limits.
        let whose = if same_limits(runs) { String::new() } else { format!("{}: ", m.scene.meta.name) };
        let limit = |what: &str, look: usize, pick: fn(LoadLimits) -> Option<f64>| {
            let points = step(m, |kind| pick(m.member_limits(kind)).map(|v| v / 1e3));
            Curve::limit(format!("{whose}{}", limit_label(m, what, pick)), look, points, false)
        };
        curves.push(limit("proof load", 4, |l| l.proof));
        curves.push(limit("break load", 1, |l| l.breaking));
    }
    curves
}

/// The peak tension over each joint's break load along the line (%), and the first run's
/// proof load over break load, the axis taking both limits in (a utilisation is read against
/// them).
fn utilisation_curves(runs: &[(&Model, &RunResult)]) -> Vec<Curve> {
    let mut curves: Vec<Curve> = runs
        .iter()
        .enumerate()
        .filter(|(_, (_, r))| r.ran())
        .map(|(i, (m, r))| {
            let points = r
                .peak_tensions
                .iter()
                .zip(joint_distances(m))
                .enumerate()
                .map(|(j, (p, s))| (s, m.joint_limits(j + 2).breaking.map_or(f64::NAN, |b| 100.0 * p.tension / b)))
                .collect();
            Curve::new(run_label(m, r), i, points)
        })
        .collect();
    if let Some((m, _)) = runs.first() {
        // Over each body, its member's proof load against its break load (the chain's).
        let proof = step(m, |kind| {
            let l = m.member_limits(kind);
            Some(100.0 * l.proof? / l.breaking?)
        });
        let whose = if same_limits(runs) { String::new() } else { format!("{}: ", m.scene.meta.name) };
        curves.push(Curve::limit(format!("{whose}chain proof load"), 4, proof, true));
        // Every run's break load is its 100 %: over the longest line.
        let longest = runs.iter().filter_map(|(m, _)| joint_distances(m).last().copied()).fold(0.0, f64::max);
        curves.push(Curve::limit("break load (100 %)", 1, vec![(0.0, 100.0), (longest, 100.0)], true));
    }
    curves
}

/// The energy terms of one run (Eq. 63), named as the run's summary names them: kinetic
/// (the entrained water's included), the potential energy change of the line and anchor,
/// the energy stored in the ship's heave and pitch (its weight's potential less the
/// hydrostatic work, which all but cancel), each other work term the scene has (a term that
/// is zero throughout is left out), and the balance's drift. A term keeps its colour in
/// every panel.
fn energy_curves(m: &Model, r: &RunResult) -> Vec<Curve> {
    let Some(first) = r.samples.first() else { return Vec::new() };
    let n = m.body_count();
    let ship_weight = m.chain.bodies[n - 1].mass * m.scene.environment.gravity;
    let ship_potential = |s: &Sample| ship_weight * (s.bodies[n - 1].z - first.bodies[n - 1].z);
    let series =
        |f: &dyn Fn(&Sample) -> f64| -> Vec<(f64, f64)> { r.samples.iter().map(|s| (s.t, f(s) / 1e6)).collect() };
    let hydrostatic = WORK_TERMS.iter().position(|t| *t == "hydrostatic");
    let mut curves = vec![
        Curve::new("kinetic (with the entrained water)", 0, series(&|s| s.energy.kinetic + s.energy.added_kinetic)),
        Curve::new(
            "potential energy change of the line and anchor",
            6,
            series(&|s| s.energy.potential - first.energy.potential - ship_potential(s)),
        ),
        Curve::new(
            "ship heave and pitch (stored)",
            9,
            series(&|s| ship_potential(s) - hydrostatic.map_or(0.0, |h| s.energy.work[h])),
        ),
    ];
    // The other terms' looks, fixed per term (the panels' legend is shared).
    let looks = [2, 3, 4, 5, 1, 7, 10, 0, 12];
    for (i, term) in WORK_TERMS.iter().enumerate() {
        if Some(i) == hydrostatic || r.samples.iter().all(|s| s.energy.work[i] == 0.0) {
            continue;
        }
        let look = looks.get(i).copied().unwrap_or(13 + i);
        curves.push(Curve::new(
            format!("work of {}", crate::summary::work_term_words(term)),
            look,
            series(&|s| s.energy.work[i]),
        ));
    }
    curves.push(Curve::new("balance drift E − E_0", 18, series(&|s| s.energy.balance() - r.energy0)));
    curves
}

/// One curve of a [`log_log`] chart.
#[derive(Clone, Debug)]
pub struct LogCurve {
    /// The legend entry; `None` draws the curve without one.
    pub label: Option<String>,
    /// Its colour, as an index into the palette.
    pub color: usize,
    /// The points, positive in both coordinates, in drawing order.
    pub points: Vec<(f64, f64)>,
}

/// One panel of a [`log_log`] chart: its y axis's description and its curves.
pub struct LogPanel<'a> {
    /// The y axis's description, with its unit.
    pub y_desc: &'a str,
    /// The curves (lines with a marker at each point).
    pub curves: Vec<LogCurve>,
}

/// A log–log chart of `panels` side by side over one x axis description, as SVG text: each
/// quantity on an axis of its own unit; a panel's legend (its labelled curves) in its corner
/// with the fewest points.
pub fn log_log(title: &str, x_desc: &str, panels: &[LogPanel]) -> Result<String> {
    log_log_svg(title, x_desc, panels).map_err(|message| Error::Plot { chart: title.to_string(), message })
}

fn log_log_svg(title: &str, x_desc: &str, panels: &[LogPanel]) -> Result<String, String> {
    let mut svg = String::new();
    {
        let width = if panels.len() > 1 { 620 * panels.len() as u32 } else { 900 };
        let root = SVGBackend::with_string(&mut svg, (width, 560)).into_drawing_area();
        root.fill(&WHITE).map_err(|e| e.to_string())?;
        let area = root.titled(title, sans(TITLE_FONT)).map_err(|e| e.to_string())?;
        for (area, panel) in area.split_evenly((1, panels.len().max(1))).iter().zip(panels) {
            log_panel(area, x_desc, panel)?;
        }
        root.present().map_err(|e| e.to_string())?;
    }
    Ok(svg)
}

/// One panel of [`log_log`] drawn on `root`.
fn log_panel<DB: DrawingBackend>(
    root: &DrawingArea<DB, plotters::coord::Shift>,
    x_desc: &str,
    panel: &LogPanel,
) -> Result<(), String> {
    let curves = &panel.curves;
    let (mut x0, mut x1, mut y0, mut y1) = (f64::MAX, f64::MIN, f64::MAX, f64::MIN);
    for &(x, y) in curves.iter().flat_map(|c| &c.points) {
        (x0, x1, y0, y1) = (x0.min(x), x1.max(x), y0.min(y), y1.max(y));
    }
    if curves.iter().all(|c| c.points.is_empty()) {
        (x0, x1, y0, y1) = (1e-3, 1.0, 1e-9, 1.0);
    }
    let logs: Vec<(f64, f64)> = curves.iter().flat_map(|c| &c.points).map(|&(x, y)| (x.log10(), y.log10())).collect();
    let (lx0, lx1, ly0, ly1) = ((x0 * 0.8).log10(), (x1 * 1.25).log10(), (y0 * 0.5).log10(), (y1 * 2.0).log10());
    let mut c = ChartBuilder::on(root)
        .margin(12)
        .x_label_area_size(50)
        .y_label_area_size(86)
        .build_cartesian_2d((x0 * 0.8..x1 * 1.25).log_scale(), (y0 * 0.5..y1 * 2.0).log_scale())
        .map_err(|e| e.to_string())?;
    // plotters' log axes crowd key points near 1 (a grey band of grid, labels printed
    // over each other): no grid of its own, labels only at 1, 2, 5 × 10^n (x) and at
    // decades (y), each once; the grid is drawn below at those values.
    let (xr, yr) = (c.x_range(), c.y_range());
    let seen = std::cell::RefCell::new(Vec::<String>::new());
    let once = |text: String| {
        let mut seen = seen.borrow_mut();
        if text.is_empty() || seen.contains(&text) {
            String::new()
        } else {
            seen.push(text.clone());
            text
        }
    };
    let y_text = |v: &f64| once(log_tick(*v, &[1.0]).map(|v| format!("{v:.0e}")).unwrap_or_default());
    c.configure_mesh()
        .disable_mesh()
        .x_desc(x_desc)
        .y_desc(panel.y_desc)
        .label_style(sans(TICK_FONT))
        .axis_desc_style(sans(AXIS_FONT))
        .x_labels(10)
        .x_label_formatter(&|_| String::new())
        .y_labels(40)
        .y_label_formatter(&y_text)
        .draw()
        .map_err(|e| e.to_string())?;
    let grid = ShapeStyle { color: RGBColor(225, 225, 225).to_rgba(), filled: false, stroke_width: 1 };
    // The x labels at every 1, 2, 5 × 10^n, under their grid lines (plotters' own key
    // points skip some: 0.05 went unlabelled).
    let tick = sans(TICK_FONT).into_font().color(&BLACK).pos(Pos::new(HPos::Center, VPos::Top));
    for x in log_ticks(xr.start, xr.end, &[1.0, 2.0, 5.0]) {
        c.draw_series(LineSeries::new([(x, yr.start), (x, yr.end)], grid)).map_err(|e| e.to_string())?;
        // The backend's pixel, as the panel's own (it may sit right of and below others).
        let ((px, py), (bx, by)) = (c.backend_coord(&(x, yr.start)), root.get_base_pixel());
        root.draw(&Text::new(tidy(x), (px - bx, py - by + 8), tick.clone())).map_err(|e| e.to_string())?;
    }
    for y in log_ticks(yr.start, yr.end, &[1.0]) {
        c.draw_series(LineSeries::new([(xr.start, y), (xr.end, y)], grid)).map_err(|e| e.to_string())?;
    }
    for curve in curves.iter().filter(|c| !c.points.is_empty()) {
        let color = PALETTE[curve.color % PALETTE.len()];
        let series =
            c.draw_series(LineSeries::new(curve.points.clone(), color.stroke_width(2))).map_err(|e| e.to_string())?;
        if let Some(label) = &curve.label {
            series
                .label(label.clone())
                .legend(move |(x, y)| PathElement::new(vec![(x, y), (x + 18, y)], color.stroke_width(2)));
        }
        c.draw_series(curve.points.iter().map(|&p| Circle::new(p, 3, color.filled()))).map_err(|e| e.to_string())?;
    }
    if curves.iter().any(|c| c.label.is_some() && !c.points.is_empty()) {
        c.configure_series_labels()
            .position(emptiest_corner(&logs, (lx0, lx1), (ly0, ly1)))
            .label_font(sans(TICK_FONT))
            .background_style(WHITE.mix(0.85))
            .border_style(BLACK)
            .draw()
            .map_err(|e| e.to_string())?;
    }
    Ok(())
}

/// `v` when it is m × 10^n for an m of `mantissas` (to 0.1 %), rounded to that value.
fn log_tick(v: f64, mantissas: &[f64]) -> Option<f64> {
    if !(v.is_finite() && v > 0.0) {
        return None;
    }
    let decade = 10f64.powf(v.log10().floor());
    mantissas.iter().chain(&[10.0]).map(|m| m * decade).find(|t| ((v - t) / t).abs() < 1e-3)
}

/// The values m × 10^n in [lo, hi] for m in `mantissas`.
fn log_ticks(lo: f64, hi: f64, mantissas: &[f64]) -> Vec<f64> {
    let mut ticks = Vec::new();
    if !(lo > 0.0 && hi > lo && hi.is_finite()) {
        return ticks;
    }
    let mut n = lo.log10().floor() as i32;
    while 10f64.powi(n) <= hi {
        for m in mantissas {
            let t = m * 10f64.powi(n);
            if t >= lo && t <= hi {
                ticks.push(t);
            }
        }
        n += 1;
    }
    ticks
}

/// A number as short as it reads: 5 not 5.0, 0.25, 2e-3 below 0.01.
fn tidy(v: f64) -> String {
    if v != 0.0 && v.abs() < 0.01 {
        return format!("{v:.0e}");
    }
    let r = (v * 1e6).round() / 1e6;
    format!("{r}")
}

#[cfg(test)]
mod tests {
    use super::*;

    fn reference(points: Vec<(f64, f64)>) -> Curve {
        Curve::limit("limit", 1, points, false)
    }

    #[test]
    fn a_limit_far_above_the_data_does_not_flatten_it() {
        // Regression: the peak-tension axis ran to the 4 000 kN break load; 400 kN peaks were a line.
        let data = Curve::new("peak", 0, vec![(2.0, 395.0), (46.0, 430.0)]);
        let flat = |v: f64| (2..=46).flat_map(|k| [(k as f64 - 0.5, v), (k as f64 + 0.5, v)]).collect();
        let far = reference(flat(3866.0));
        let ((_, _), (y0, y1)) = bounds(&[data, far], true);
        assert_eq!(y0, 0.0);
        assert!(y1 < 500.0, "{y1}");
        let data = Curve::new("util", 0, vec![(2.0, 10.0), (46.0, 38.6)]);
        let near = reference(flat(70.0));
        let (_, (_, y1)) = bounds(&[data, near], true);
        assert!(y1 > 70.0, "a limit near the data is on the axis: {y1}");
    }

    fn case1() -> Model {
        let scene = kanestop_runtime::scene::Scene::from_toml(kanestop_runtime::paper::DEFAULT_SCENE, "case01.toml");
        Model::new(&scene.unwrap()).unwrap()
    }

    #[test]
    fn a_limit_is_a_step_not_a_slope() {
        // Regression: the proof/break load changing from chain to cable was drawn as a slope.
        let m = case1();
        let points = step(&m, |kind| Some(if kind == BodyKind::ChainLink { 2.0 } else { 1.0 }));
        // 15 chain links of 1 m, then the cable: flat to 15 m, a jump, flat on.
        assert_eq!(points[..4], [(0.0, 2.0), (1.0, 2.0), (1.0, 2.0), (2.0, 2.0)]);
        assert_eq!(points[28..32], [(14.0, 2.0), (15.0, 2.0), (15.0, 1.0), (17.0, 1.0)]);
        let gap = step(&m, |kind| (kind == BodyKind::ChainLink).then_some(1.0));
        assert!(gap[30].0.is_nan(), "a body without a limit breaks the line");
    }

    #[test]
    fn lines_laid_out_otherwise_are_told_apart() {
        let (a, b) = (case1(), case1());
        assert!(same_members([&a, &b].into_iter()));
        let mut scene = b.scene.clone();
        scene.cable.stages[0].element_length = 2.5;
        let longer = Model::new(&scene).unwrap();
        assert!(!same_members([&a, &longer].into_iter()), "a first stage of 2.5 m elements, not 2 m");
        // Another cable grade: the same members (drawn), other limits (named by scene).
        let mut scene = a.scene.clone();
        scene.cable.break_load *= 2.0;
        let stronger = Model::new(&scene).unwrap();
        assert!(same_members([&a, &stronger].into_iter()), "the same stretches");
        let limits = |m: &Model| [BodyKind::ChainLink, BodyKind::Rod].map(|k| m.member_limits(k));
        assert!(limits(&a) != limits(&stronger) && limits(&a) == limits(&b));
    }

    #[test]
    fn the_line_is_drawn_by_distance_from_the_anchor() {
        // Case 1: joint 2 at the anchor's shackle, joint N = 46 at the fairlead, 15 m of chain,
        // 152 m of cable and the 1 m rod between: 168 m in all; the members over those stretches.
        let m = case1();
        let s = joint_distances(&m);
        assert_eq!((s.len(), s[0], s[15]), (45, 0.0, 15.0));
        assert!((s[44] - 168.0).abs() < 1e-9, "{}", s[44]);
        let names: Vec<_> = members(&m).into_iter().map(|(n, a, b)| (n, a.round(), b.round())).collect();
        assert_eq!(names, [("chain".into(), 0.0, 15.0), ("cable".into(), 15.0, 167.0), ("rod".into(), 167.0, 168.0)]);
    }

    #[test]
    fn thirty_curves_look_different() {
        // Regression: colours repeated after ten curves.
        let looks: Vec<_> = (0..30).map(look).collect();
        for (i, a) in looks.iter().enumerate() {
            assert!(looks[i + 1..].iter().all(|b| b != a), "curve {i} looks like a later one");
        }
    }

    #[test]
    fn log_axis_labels_are_decades_and_1_2_5() {
        // Regression: missing or overprinted log-axis labels.
        assert_eq!(log_tick(0.2, &[1.0, 2.0, 5.0]), Some(0.2));
        assert_eq!(log_tick(0.3, &[1.0, 2.0, 5.0]), None);
        assert_eq!(log_tick(1e-4 * 1.0000001, &[1.0]), Some(1e-4));
        assert_eq!(log_ticks(0.08, 3.0, &[1.0, 2.0, 5.0]).len(), 5, "0.1 0.2 0.5 1 2");
        let curve = LogCurve { label: Some("rk4".into()), color: 0, points: vec![(0.1, 1e-2), (0.9, 1e-8)] };
        let svg = log_log("t", "wall time (s)", &[LogPanel { y_desc: "error", curves: vec![curve] }]).unwrap();
        for label in ["0.1", "0.2", "0.5", "1e-4"] {
            assert_eq!(svg.matches(&format!(">\n{label}\n</text>")).count(), 1, "{label} printed once");
        }
    }
    /// The x positions of the SVG's text elements whose content is `label`.
    fn text_x(svg: &str, label: &str) -> Vec<f64> {
        svg.split("<text ")
            .skip(1)
            .filter(|t| t.split('>').nth(1).is_some_and(|c| c.trim().trim_end_matches("</text").trim() == label))
            .map(|t| t.split("x=\"").nth(1).unwrap().split('"').next().unwrap().parse().unwrap())
            .collect()
    }

    #[test]
    fn the_legend_is_beside_the_plot_not_on_it() {
        // Regression: the legend sat on the curves (19 runs' over joints 35–46, the energy
        // panels' over the kinetic energy), and ran off the image with many entries.
        let curves: Vec<Curve> =
            (0..19).map(|i| Curve::new(format!("case{i:02}"), i, vec![(0.0, 0.0), (10.0, i as f64)])).collect();
        let svg = chart("t", "x", "y", &curves, false, &[]).unwrap();
        for i in 0..19 {
            let xs = text_x(&svg, &format!("case{i:02}"));
            assert_eq!(xs.len(), 1, "case{i:02} named once");
            assert!(xs[0] > SIZE.0 as f64, "case{i:02} at x = {} is on the plot", xs[0]);
        }
        // Taller than its plot: a second column, still beside it.
        let many: Vec<Curve> =
            (0..40).map(|i| Curve::new(format!("run {i}"), i, vec![(0.0, 0.0), (1.0, 1.0)])).collect();
        let legend = entries(&many, (0.0, 1.0));
        assert_eq!(legend_layout(&legend, SIZE.1).columns, 2, "two columns");
        let svg = chart("t", "x", "y", &many, false, &[]).unwrap();
        let width: f64 = svg.split("width=\"").nth(1).unwrap().split('"').next().unwrap().parse().unwrap();
        for i in 0..40 {
            let x = text_x(&svg, &format!("run {i}"))[0];
            assert!(x > SIZE.0 as f64 && x < width - 40.0, "run {i} at {x} of {width}");
        }
        // Every column count the layout gives is the one drawn: each entry's text inside
        // the image, for 1 to 60 entries, some wrapped.
        for n in 1..=60 {
            let curves: Vec<Curve> = (0..n)
                .map(|i| {
                    let label = if i % 7 == 3 {
                        format!("run {i} with a name long enough to wrap in two")
                    } else {
                        format!("run {i}")
                    };
                    Curve::new(label, i, vec![(0.0, 0.0), (1.0, 1.0)])
                })
                .collect();
            let svg = chart("t", "x", "y", &curves, false, &[]).unwrap();
            let width: f64 = svg.split("width=\"").nth(1).unwrap().split('"').next().unwrap().parse().unwrap();
            let height: f64 = svg.split("height=\"").nth(1).unwrap().split('"').next().unwrap().parse().unwrap();
            let texts: Vec<(f64, f64)> = svg
                .split("<text ")
                .skip(1)
                .map(|t| {
                    let attr = |a: &str| {
                        t.split(&format!("{a}=\"")).nth(1).unwrap().split('"').next().unwrap().parse::<f64>().unwrap()
                    };
                    (attr("x"), attr("y"))
                })
                .collect();
            assert!(
                texts.iter().all(|&(x, y)| x < width - 30.0 && y < height - 5.0),
                "{n} entries: a text outside {width}×{height}"
            );
        }
        // Panels share one legend, each label once.
        let panel_curves = || vec![Curve::new("kinetic", 0, vec![(0.0, 1.0), (1.0, 0.0)])];
        let svg = panels("e", "t", "E", &[("a".into(), panel_curves()), ("b".into(), panel_curves())], 2).unwrap();
        assert_eq!(text_x(&svg, "kinetic").len(), 1);
    }

    #[test]
    fn a_long_legend_text_wraps_at_a_space() {
        let lines = wrap("break load: chain 3866, cable 2520, rod 2520, something else kN", LEGEND_CHARS);
        assert!(lines.len() == 2 && lines.iter().all(|l| l.chars().count() <= LEGEND_CHARS), "{lines:?}");
        assert_eq!(lines.join(" "), "break load: chain 3866, cable 2520, rod 2520, something else kN");
        assert_eq!(wrap("case01", LEGEND_CHARS), ["case01"]);
    }

    #[test]
    fn marks_are_drawn_and_named_once() {
        let mut failed = Curve::new("taut (failed at 0.31 s)", 0, vec![(0.0, 3.0), (0.31, 2.8)]);
        failed.marks = vec![((0.31, 2.8), Mark::Failure)];
        let mut paper = Curve::new("case01", 1, vec![(0.0, 3.0), (19.8, 0.0)]);
        paper.marks = vec![((20.01, 0.0), Mark::Paper)];
        let legend = entries(&[failed, paper], (0.0, 3.0));
        let labels: Vec<&str> = legend.iter().map(|e| e.label.as_str()).collect();
        assert_eq!(labels, ["taut (failed at 0.31 s)", "case01", Mark::Failure.label(), Mark::Paper.label()]);
        let (mut failed, mut paper) =
            (Curve::new("a", 0, vec![(0.0, 3.0), (0.31, 2.8)]), Curve::new("b", 1, vec![(0.0, 3.0), (19.8, 0.0)]));
        failed.marks = vec![((0.31, 2.8), Mark::Failure)];
        paper.marks = vec![((20.01, 0.0), Mark::Paper)];
        let svg = chart("t", "x", "y", &[failed, paper], false, &[]).unwrap();
        // The triangle is a polygon filled in the run's colour (palette 1, #D62728) on the
        // plot, though the paper's time is after the run's stop (the axis takes it in); the
        // legend's swatch is grey.
        let triangles: Vec<f64> = svg
            .split("<polygon ")
            .skip(1)
            .map(|p| p.split("/>").next().unwrap())
            .filter(|p| p.contains("fill=\"#D62728\""))
            .map(|p| p.split("points=\"").nth(1).unwrap().split(',').next().unwrap().parse().unwrap())
            .collect();
        assert_eq!(triangles.len(), 1, "{svg}");
        assert!(triangles[0] < SIZE.0 as f64, "on the plot: x = {}", triangles[0]);
    }
}

//! Heat maps of a two-axis grid sweep: one output (stopping distance, stopping time, peak
//! break utilisation, …) coloured over the two grid axes, with the design-check boundary
//! drawn: cells whose row fails a check are hatched, and a thick line runs between passing
//! and failing cells. SVG (plotters, no system fonts needed), one file per output.
//!
//! Each axis value is one column or row of cells, in spec order, whatever its spacing (a
//! log range stays readable). With sampling on top of the grid a cell holds several rows:
//! it shows the mean of the rows that have the output and is hatched when any of its rows
//! fails a check.

use std::path::{Path, PathBuf};

use plotters::prelude::*;
use plotters::style::text_anchor::{HPos, Pos, VPos};
use toml::Value;

use super::{Spec, SweepRow};
use crate::batch::Status;
use crate::output::write_atomically;
use crate::plot::sans;
use crate::record::RunSummary;
use crate::{Error, Result};

/// An output a heat map can show.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Output {
    /// The ship's surge displacement to its stop, m.
    StoppingDistance,
    /// The first zero of the ship's surge speed, s.
    StoppingTime,
    /// The largest break utilisation among the line's peak tensions (peak tension / break
    /// load), 1.
    PeakUtilisation,
    /// The largest joint tension, kN.
    PeakTension,
    /// How far the anchor was dragged, m.
    AnchorDrag,
    /// The ship's surge displacement at the end of the run, m.
    ShipDisplacement,
}

/// The outputs drawn unless told otherwise.
pub const DEFAULT_OUTPUTS: [Output; 3] = [Output::StoppingDistance, Output::StoppingTime, Output::PeakUtilisation];

impl Output {
    /// Every output, in the order `--heatmap` lists them.
    pub const ALL: [Output; 6] = [
        Output::StoppingDistance,
        Output::StoppingTime,
        Output::PeakUtilisation,
        Output::PeakTension,
        Output::AnchorDrag,
        Output::ShipDisplacement,
    ];

    /// Its name on the command line and in the file name (`heatmap-NAME.svg`).
    pub fn name(self) -> &'static str {
        match self {
            Output::StoppingDistance => "stopping_distance",
            Output::StoppingTime => "stopping_time",
            Output::PeakUtilisation => "peak_utilisation",
            Output::PeakTension => "peak_tension",
            Output::AnchorDrag => "anchor_drag_distance",
            Output::ShipDisplacement => "ship_displacement",
        }
    }

    /// The output of name `name`, or an error naming the valid names.
    pub fn parse(name: &str) -> Result<Output> {
        Output::ALL.into_iter().find(|o| o.name() == name).ok_or_else(|| Error::Argument {
            name: "--heatmap",
            value: name.to_string(),
            expected: "one of stopping_distance, stopping_time, peak_utilisation, peak_tension, \
                       anchor_drag_distance, ship_displacement (comma-separated), or none"
                .into(),
        })
    }

    /// Its words and unit, for the colour scale.
    fn describe(self) -> &'static str {
        match self {
            Output::StoppingDistance => "stopping distance (m)",
            Output::StoppingTime => "stopping time (s)",
            Output::PeakUtilisation => "peak tension / break load",
            Output::PeakTension => "peak tension (kN)",
            Output::AnchorDrag => "anchor drag distance (m)",
            Output::ShipDisplacement => "ship displacement (m)",
        }
    }

    /// Its value in a row's summary, in the unit of its colour scale: m for the distances, s for
    /// the stopping time, kN for the peak tension, 1 for the utilisation.
    pub fn of(self, s: &RunSummary) -> Option<f64> {
        match self {
            Output::StoppingDistance => s.stopping_distance,
            Output::StoppingTime => s.stopping_time.filter(|_| s.stopping_distance.is_some()),
            Output::PeakUtilisation => s.max_break_utilisation(),
            Output::PeakTension => s.peak_tension.map(|p| p.tension * 1e-3),
            Output::AnchorDrag => Some(s.anchor_drag_distance.abs()),
            Output::ShipDisplacement => Some(s.ship_displacement),
        }
    }

    /// The limit of the spec's design check on this output, in its unit, with the check's
    /// name: drawn on the colour scale. None where the check is an input of the sweep (its
    /// limit differs from row to row).
    fn limit(self, spec: &Spec) -> Option<(f64, &'static str)> {
        let c = spec.base.checks.as_ref()?;
        let own = |name: &str, v: Option<f64>| v.filter(|_| !check_is_input(spec, name));
        match self {
            Output::StoppingDistance => {
                own("max_stopping_distance", c.max_stopping_distance).map(|v| (v, "max_stopping_distance"))
            }
            Output::StoppingTime => own("max_stopping_time", c.max_stopping_time).map(|v| (v, "max_stopping_time")),
            Output::PeakUtilisation => own("safety_factor", c.safety_factor).map(|f| (1.0 / f, "1 / safety_factor")),
            Output::AnchorDrag => own("max_anchor_drag", c.max_anchor_drag).map(|v| (v, "max_anchor_drag")),
            Output::PeakTension | Output::ShipDisplacement => None,
        }
    }
}

/// Parses `--heatmap` values (`none` for no heat map), before any run.
pub fn parse_outputs(names: &[String]) -> Result<Vec<Output>> {
    if names.is_empty() {
        return Ok(DEFAULT_OUTPUTS.to_vec());
    }
    if names.iter().any(|n| n == "none") {
        return Ok(Vec::new());
    }
    let mut out: Vec<Output> = Vec::new();
    for n in names {
        let o = Output::parse(n.trim())?;
        if !out.contains(&o) {
            out.push(o);
        }
    }
    Ok(out)
}

/// Why a spec has no heat map (none when it has one): it needs exactly two grid axes of
/// numbers, each with at least two values.
pub fn unsupported(spec: &Spec) -> Option<String> {
    if spec.axes.len() != 2 {
        return Some(format!("a heat map needs exactly two grid axes; the spec has {}", spec.axes.len()));
    }
    for a in &spec.axes {
        if a.values.iter().any(|v| number(v).is_none()) {
            return Some(format!("axis {} is not numeric", a.path));
        }
        if a.values.len() < 2 {
            return Some(format!("axis {} has a single value", a.path));
        }
    }
    None
}

fn number(v: &Value) -> Option<f64> {
    match v {
        Value::Float(x) => Some(*x),
        Value::Integer(i) => Some(*i as f64),
        _ => None,
    }
}

/// One cell of the grid: the mean output of its rows that have it, and whether its rows
/// passed their checks (none: no check, or no row ran).
#[derive(Clone, Debug, Default, PartialEq)]
struct Cell {
    value: Option<f64>,
    /// How many runs gave the value (its mean's samples).
    runs: usize,
    /// How many rows the cell has (runs that gave no value included).
    rows: usize,
    pass: Option<bool>,
    /// The checks its rows failed, in words.
    failed: Vec<&'static str>,
    /// How many of the runs that gave the value ended at the end time with the ship still
    /// moving: their value is the run's up to then (a peak, a drag distance), not the stop's.
    unstopped: usize,
}

/// A check's name in a cell, short.
fn check_word(name: &str) -> &'static str {
    match name {
        "max_stopping_distance" => "distance",
        "max_stopping_time" => "time",
        "max_anchor_drag" => "anchor drag",
        "safety_factor" => "safety factor",
        "max_proof_utilisation" => "proof load",
        _ => "check",
    }
}

/// The cells, `[x][y]` over axis 0 (x) and axis 1 (y).
/// A row's stopping time, s (none where the ship did not stop, or the row did not run).
fn stopping_time(r: &SweepRow) -> Option<f64> {
    r.summary.as_ref().and_then(|s| s.stopping_time)
}

fn cells(spec: &Spec, rows: &[SweepRow], output: Output) -> Vec<Vec<Cell>> {
    let (ax, ay) = (&spec.axes[0], &spec.axes[1]);
    let mut sums = vec![vec![(0.0, 0usize, Cell::default()); ay.values.len()]; ax.values.len()];
    for r in rows {
        let at = |a: &super::spec::Axis| {
            let v = r.inputs.0.iter().find(|(p, _)| *p == a.path).map(|(_, v)| v)?;
            a.values.iter().position(|x| x == v)
        };
        let (Some(i), Some(j)) = (at(ax), at(ay)) else { continue };
        let cell = &mut sums[i][j];
        cell.2.rows += 1;
        if let Some(v) = r.summary.as_ref().and_then(|s| output.of(s)).filter(|v| v.is_finite()) {
            cell.0 += v;
            cell.1 += 1;
            // Cut short: at the end time with no stop (a run kept going after its stop,
            // `stop_when_ship_stops = false`, has one).
            cell.2.unstopped += usize::from(r.status == Status::EndTime && stopping_time(r).is_none());
        }
        if let Some(p) = r.checks_pass {
            cell.2.pass = Some(cell.2.pass.unwrap_or(true) && p);
        }
        let Some(s) = r.summary.as_ref().filter(|_| r.checks_pass == Some(false)) else { continue };
        // A failing row none of whose [checks] failed failed on a break load (as the sweep's
        // summary counts it).
        let failed: Vec<&str> = s.checks.iter().filter(|c| !c.pass).map(|c| check_word(&c.name)).collect();
        let broke = (s.break_load_exceeded() || failed.is_empty()).then_some("break load");
        for word in broke.into_iter().chain(failed) {
            if !cell.2.failed.contains(&word) {
                cell.2.failed.push(word);
            }
        }
    }
    sums.into_iter()
        .map(|col| {
            col.into_iter().map(|(s, n, cell)| Cell { value: (n > 0).then(|| s / n as f64), runs: n, ..cell }).collect()
        })
        .collect()
}

/// Viridis, sampled at nine points and interpolated: dark blue (low) to yellow (high),
/// readable in grey and by the colour-blind.
fn viridis(t: f64) -> RGBColor {
    const STOPS: [(u8, u8, u8); 9] = [
        (68, 1, 84),
        (71, 44, 122),
        (59, 81, 139),
        (44, 113, 142),
        (33, 144, 141),
        (39, 173, 129),
        (92, 200, 99),
        (170, 220, 50),
        (253, 231, 37),
    ];
    let t = if t.is_finite() { t.clamp(0.0, 1.0) } else { 0.0 };
    let x = t * (STOPS.len() - 1) as f64;
    let k = (x.floor() as usize).min(STOPS.len() - 2);
    let f = x - k as f64;
    let mix = |a: u8, b: u8| (a as f64 + f * (b as f64 - a as f64)).round() as u8;
    let (a, b) = (STOPS[k], STOPS[k + 1]);
    RGBColor(mix(a.0, b.0), mix(a.1, b.1), mix(a.2, b.2))
}

/// `v` in scientific notation to `digits` significant digits, without trailing zeros
/// (`1.6e5`, `2e4`).
fn scientific_text(v: f64, digits: usize) -> String {
    let s = format!("{v:.*e}", digits.max(1) - 1);
    let (m, e) = s.split_once('e').unwrap_or((&s, "0"));
    let m = if m.contains('.') { m.trim_end_matches('0').trim_end_matches('.') } else { m };
    format!("{m}e{e}")
}

/// A value for a tick or a cell: up to 4 significant digits, scientific when large or small.
fn short(v: f64) -> String {
    short_in(v, 0.0)
}

/// [`short`] with enough digits to tell values `span` apart, a twentieth of it shown (all
/// cells of a map over 0.17077–0.17111 read "0.171" with 4 digits; at most 10).
fn short_in(v: f64, span: f64) -> String {
    let a = v.abs();
    // The digits from v's first to the resolution's: 0.171 to 1.7e-5 is 5.
    let needed =
        if span > 0.0 && a > 0.0 { a.log10().floor() as i32 - (span / 20.0).log10().floor() as i32 + 1 } else { 0 };
    let sig = needed.clamp(4, 10);
    if sig > 4 {
        let e = a.log10().floor() as i32;
        if (-2..5).contains(&e) {
            let decimals = (sig - 1 - e).max(0) as usize;
            // Every value to the same place (0.17080 beside 0.17077, not 0.1708).
            return format!("{v:.decimals$}");
        }
        return scientific_text(v, sig as usize);
    }
    if v != 0.0 && !(1e-2..1e5).contains(&a) {
        return scientific_text(v, 4);
    }
    let digits = if a >= 1000.0 {
        0
    } else if a >= 100.0 {
        1
    } else if a >= 10.0 {
        2
    } else {
        3
    };
    let s = format!("{v:.digits$}");
    if s.contains('.') {
        s.trim_end_matches('0').trim_end_matches('.').to_string()
    } else {
        s
    }
}

/// Chart size, pixels.
const SIZE: (u32, u32) = (1000, 760);
/// The title's type size, px as drawn.
const TITLE_FONT: f64 = 20.0;
/// The legend's height below the chart, px: six rows, the first on two lines.
const LEGEND_HEIGHT: u32 = 196;

/// The heat map of `output` over the spec's two grid axes, as SVG text (the spec must have
/// them: see [`unsupported`]).
pub fn heat_map(spec: &Spec, rows: &[SweepRow], output: Output) -> std::result::Result<String, String> {
    let grid = cells(spec, rows, output);
    let values: Vec<f64> = grid.iter().flatten().filter_map(|c| c.value).collect();
    let limit = output.limit(spec);
    let (lo, hi) = scale_range(&values);
    let mut svg = String::new();
    {
        let root = SVGBackend::with_string(&mut svg, SIZE).into_drawing_area();
        root.fill(&WHITE).map_err(|e| e.to_string())?;
        // The title on one line when it fits the width (0.55 em a character), else on two.
        let what = format!("{}: {}", spec.name, output.describe());
        let over = format!("over {} and {}", spec.axes[0].path, spec.axes[1].path);
        let one = format!("{what} {over}");
        let lines = if 0.55 * TITLE_FONT * one.chars().count() as f64 <= SIZE.0 as f64 - 40.0 {
            vec![one]
        } else {
            vec![what, over]
        };
        let head = 14 + 28 * lines.len() as u32;
        let (top, root) = root.split_vertically(head);
        let font = sans(TITLE_FONT).into_font().color(&BLACK).pos(Pos::new(HPos::Center, VPos::Top));
        for (k, line) in lines.into_iter().enumerate() {
            top.draw(&Text::new(line, (SIZE.0 as i32 / 2, 8 + 28 * k as i32), font.clone()))
                .map_err(|e| e.to_string())?;
        }
        let (body, legend) = root.split_vertically(SIZE.1 - head - LEGEND_HEIGHT);
        let (main, scale) = body.split_horizontally(SIZE.0 - 170);
        draw_cells(&main, spec, &grid, (lo, hi))?;
        draw_scale(&scale, output, (lo, hi), limit, !values.is_empty())?;
        draw_legend(&legend, spec, &grid, limit, (lo, hi))?;
        root.present().map_err(|e| e.to_string())?;
    }
    Ok(svg)
}

/// The colour scale's ends over the cells' `values`: their least and greatest; around the one
/// value when all are equal, from 0 for a value ≥ 0 within the margin of 0 (every output but
/// the ship's displacement is a magnitude, and a scale of those all 0 from −0.05 read as a
/// negative distance); 0 to 1 without values.
fn scale_range(values: &[f64]) -> (f64, f64) {
    let (lo, hi) = values.iter().fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), &v| (a.min(v), b.max(v)));
    if !lo.is_finite() {
        return (0.0, 1.0);
    }
    if hi - lo > 1e-12 * hi.abs().max(1.0) {
        return (lo, hi);
    }
    let margin = 0.05 * lo.abs().max(1.0);
    (if lo >= 0.0 { (lo - margin).max(0.0) } else { lo - margin }, hi + margin)
}

// Long by design: one chart's drawing, cell by cell, reads best in one place.
fn draw_cells<DB: DrawingBackend>(
    area: &DrawingArea<DB, plotters::coord::Shift>,
    spec: &Spec,
    grid: &[Vec<Cell>],
    (lo, hi): (f64, f64),
) -> std::result::Result<(), String> {
    let err = |e: DrawingAreaErrorKind<DB::ErrorType>| e.to_string();
    let (nx, ny) = (grid.len(), grid.first().map_or(0, Vec::len));
    // Cell (i, j) spans [i − ½, i + ½] × [j − ½, j + ½]: the ticks fall on whole numbers, the
    // cells' centres, and name the axis values there.
    let (ax, ay) = (&spec.axes[0], &spec.axes[1]);
    // One style per axis: all scientific when any value needs it (not 80000 beside 1.6e5).
    let scientific =
        |a: &super::spec::Axis| a.values.iter().filter_map(number).any(|v| v != 0.0 && !(1e-2..1e5).contains(&v.abs()));
    let (sx, sy) = (scientific(ax), scientific(ay));
    let tick = |a: &super::spec::Axis, sci: bool, v: f64| {
        let i = v.round();
        if (v - i).abs() > 1e-9 || i < 0.0 {
            return String::new();
        }
        a.values
            .get(i as usize)
            .and_then(number)
            .map(|v| if sci { scientific_text(v, 4) } else { short(v) })
            .unwrap_or_default()
    };
    let mut c = ChartBuilder::on(area)
        .margin(12)
        .x_label_area_size(50)
        .y_label_area_size(80)
        .build_cartesian_2d(-0.5..nx as f64 - 0.5, -0.5..ny as f64 - 0.5)
        .map_err(err)?;
    c.configure_mesh()
        .disable_mesh()
        .x_labels(nx.min(12))
        .y_labels(ny.min(12))
        .x_desc(kanestop_runtime::scene::labelled(&ax.path))
        .y_desc(kanestop_runtime::scene::labelled(&ay.path))
        .label_style(sans(14.0))
        .axis_desc_style(sans(15.0))
        .x_label_formatter(&|v| tick(ax, sx, *v))
        .y_label_formatter(&|v| tick(ay, sy, *v))
        .draw()
        .map_err(err)?;
    let annotate = nx * ny <= 225;
    // A cell's size, px, for fitting its text.
    let (cell_px, row_px) = {
        let (a, b) = (c.backend_coord(&(0.0, 0.0)), c.backend_coord(&(1.0, 1.0)));
        ((b.0 - a.0).abs() as f64, ((a.1 - b.1).abs() as f64).max(1.0))
    };
    let name_failures = nx <= 8 && ny <= 8;
    for (i, col) in grid.iter().enumerate() {
        for (j, cell) in col.iter().enumerate() {
            let (x, y) = (i as f64 - 0.5, j as f64 - 0.5);
            let fill = match cell.value {
                Some(v) => viridis((v - lo) / (hi - lo)),
                None => RGBColor(200, 200, 200),
            };
            c.draw_series(std::iter::once(Rectangle::new([(x, y), (x + 1.0, y + 1.0)], fill.filled()))).map_err(err)?;
            if cell.pass == Some(false) {
                c.draw_series(
                    hatch(x, y).into_iter().map(|seg| PathElement::new(seg, WHITE.mix(0.55).stroke_width(2))),
                )
                .map_err(err)?;
            }
            if annotate {
                // A mean over part of its rows (the others did not stop, or failed) is starred.
                let star = if cell.value.is_some() && cell.runs < cell.rows { "*" } else { "" };
                // A value of a run cut short by the end time is daggered.
                let dagger = if cell.unstopped > 0 { "†" } else { "" };
                let text =
                    cell.value.map(|v| format!("{}{star}{dagger}", short_in(v, hi - lo))).unwrap_or_else(|| "—".into());
                let light = cell.value.is_some_and(|v| (v - lo) / (hi - lo) < 0.6);
                let colour = if light { WHITE } else { BLACK };
                let centred = Pos::new(HPos::Center, VPos::Center);
                let style = TextStyle::from((sans(15.0).0, sans(15.0).1, FontStyle::Bold).into_font())
                    .color(&colour)
                    .pos(centred);
                c.draw_series(std::iter::once(Text::new(text, (x + 0.5, y + 0.5), style))).map_err(err)?;
                if name_failures && !cell.failed.is_empty() {
                    // Below the value, in lines that fit the cell (0.6 em a character).
                    let small = TextStyle::from(sans(CELL_NOTE_FONT).into_font()).color(&colour).pos(centred);
                    let fits = ((cell_px / (0.6 * CELL_NOTE_FONT)) as usize).max(8);
                    let line_h = 1.25 * CELL_NOTE_FONT / row_px;
                    for (k, line) in
                        crate::plot::wrap(&format!("fails: {}", cell.failed.join(", ")), fits).into_iter().enumerate()
                    {
                        let at = (x + 0.5, y + 0.5 - 0.16 - k as f64 * line_h);
                        c.draw_series(std::iter::once(Text::new(line, at, small.clone()))).map_err(err)?;
                    }
                }
            }
        }
    }
    let red = RGBColor(230, 30, 30);
    c.draw_series(boundary(grid).into_iter().map(|e| PathElement::new(e, red.stroke_width(5)))).map_err(err)?;
    Ok(())
}

/// A cell note's type size, px as drawn.
const CELL_NOTE_FONT: f64 = 12.0;

/// Diagonal hatching lines of the unit cell at (x, y), in data coordinates.
fn hatch(x: f64, y: f64) -> Vec<Vec<(f64, f64)>> {
    (1..8)
        .map(|k| {
            let c = -1.0 + 0.25 * k as f64;
            if c >= 0.0 {
                vec![(x + c, y), (x + 1.0, y + 1.0 - c)]
            } else {
                vec![(x, y - c), (x + 1.0 + c, y + 1.0)]
            }
        })
        .collect()
}

/// The colour scale: the gradient with its value axis on the right, and the check's limit
/// on it (a red line).
fn draw_scale<DB: DrawingBackend>(
    area: &DrawingArea<DB, plotters::coord::Shift>,
    output: Output,
    (lo, hi): (f64, f64),
    limit: Option<(f64, &'static str)>,
    any_value: bool,
) -> std::result::Result<(), String> {
    let err = |e: DrawingAreaErrorKind<DB::ErrorType>| e.to_string();
    // No cell has a value: a grey bar with no numbers, not a scale of 0 to 1 made up.
    let describe = if any_value { output.describe().to_string() } else { format!("{}: no values", output.describe()) };
    let mut c = ChartBuilder::on(area)
        .margin_top(12)
        .margin_bottom(62)
        .margin_right(8)
        .y_label_area_size(0)
        .right_y_label_area_size(100)
        .build_cartesian_2d(0.0..1.0, lo..hi)
        .map_err(err)?
        .set_secondary_coord(0.0..1.0, lo..hi);
    c.configure_mesh().disable_mesh().disable_x_axis().disable_y_axis().draw().map_err(err)?;
    c.configure_secondary_axes()
        .y_desc(describe)
        .label_style(sans(14.0))
        .axis_desc_style(sans(15.0))
        .y_labels(if any_value { 10 } else { 0 })
        .y_label_formatter(&|v| short_in(*v, hi - lo))
        .draw()
        .map_err(err)?;
    let steps = 100;
    let band = (hi - lo) / steps as f64;
    c.draw_series((0..steps).map(|k| {
        let v = lo + k as f64 * band;
        let colour = if any_value { viridis((v + 0.5 * band - lo) / (hi - lo)) } else { RGBColor(200, 200, 200) };
        Rectangle::new([(0.0, v), (1.0, v + band)], colour.filled())
    }))
    .map_err(err)?;
    if let Some((l, _)) = limit.filter(|(l, _)| any_value && (lo..=hi).contains(l)) {
        let red = RGBColor(230, 30, 30);
        c.draw_series(std::iter::once(PathElement::new(vec![(0.0, l), (1.0, l)], red.stroke_width(4)))).map_err(err)?;
    }
    Ok(())
}

/// The legend below the chart: hatching, the boundary line, no value, the checks.
fn draw_legend<DB: DrawingBackend>(
    area: &DrawingArea<DB, plotters::coord::Shift>,
    spec: &Spec,
    grid: &[Vec<Cell>],
    limit: Option<(f64, &'static str)>,
    (lo, hi): (f64, f64),
) -> std::result::Result<(), String> {
    let err = |e: DrawingAreaErrorKind<DB::ErrorType>| e.to_string();
    let font = sans(14.0).into_font().color(&BLACK);
    let red = RGBColor(230, 30, 30);
    let (x0, y0) = (100, 8);
    // Hatched swatch.
    area.draw(&Rectangle::new([(x0, y0), (x0 + 26, y0 + 18)], RGBColor(59, 81, 139).filled())).map_err(err)?;
    for k in 0..4 {
        let d = 7 * k;
        area.draw(&PathElement::new(vec![(x0 + d, y0 + 18), (x0 + d + 8, y0)], WHITE.stroke_width(2))).map_err(err)?;
    }
    let names = describe_checks(spec);
    let cells = grid.iter().flatten();
    let (fail, empty, total) = (
        cells.clone().filter(|c| c.pass == Some(false)).count(),
        cells.clone().filter(|c| c.value.is_none()).count(),
        cells.count(),
    );
    // On as many lines as the checks' names need (0.55 em a character), 18 px apart.
    let fits = ((SIZE.0 as f64 - f64::from(x0) - 46.0) / (0.55 * 14.0)) as usize;
    let hatched = crate::plot::wrap(&format!("hatched: fails a design check ({names}); {fail} of {total} cells"), fits);
    for (k, line) in hatched.iter().enumerate() {
        area.draw(&Text::new(line.clone(), (x0 + 36, y0 + 2 + 18 * k as i32), font.clone())).map_err(err)?;
    }
    let y1 = y0 + 28 + 18 * (hatched.len() as i32 - 1);
    // Without values there is no scale to place the limit on.
    let any_value = grid.iter().flatten().any(|c| c.value.is_some());
    let limit_words = match limit.filter(|_| any_value) {
        Some((v, name)) if (lo..=hi).contains(&v) => format!("; on the scale: {name} = {}", short(v)),
        Some((v, name)) => format!("; {name} = {} is off the scale", short(v)),
        None => String::new(),
    };
    let line = if !boundary(grid).is_empty() {
        area.draw(&PathElement::new(vec![(x0, y1 + 9), (x0 + 26, y1 + 9)], red.stroke_width(5))).map_err(err)?;
        format!("red line: the design-check boundary, between passing and failing cells{limit_words}")
    } else {
        format!("no design-check boundary: no passing cell beside a failing one{limit_words}")
    };
    area.draw(&Text::new(line, (x0 + 36, y1 + 2), font.clone())).map_err(err)?;
    let y2 = y1 + 28;
    area.draw(&Rectangle::new([(x0, y2), (x0 + 26, y2 + 18)], RGBColor(200, 200, 200).filled())).map_err(err)?;
    area.draw(&Text::new(
        format!(
            "grey, —: no value (the ship did not stop, or the row failed or was invalid); {empty} of {total} cells"
        ),
        (x0 + 36, y2 + 2),
        font.clone(),
    ))
    .map_err(err)?;
    // Sampled inputs on the grid: a cell is a mean, and says over how many runs; one over
    // part of its runs is starred. A value of a run the end time cut short is daggered.
    let rows = grid.iter().flatten().map(|c| c.rows).max().unwrap_or(0);
    let partial = grid.iter().flatten().filter(|c| c.value.is_some() && c.runs < c.rows).count();
    let cut = grid.iter().flatten().filter(|c| c.unstopped > 0).count();
    let notes = [
        (rows > 1).then(|| format!("each cell: the mean over its {rows} runs (the sampled inputs at that grid point)")),
        (partial > 0).then(|| {
            format!("*: the mean of the runs that gave a value; the others did not stop or failed ({partial} of {total} cells)")
        }),
        (cut > 0).then(|| {
            format!("†: the ship had not stopped at solver.end_time: the value is the run's up to then ({cut} of {total} cells)")
        }),
    ];
    for (k, note) in notes.into_iter().flatten().enumerate() {
        area.draw(&Text::new(note, (x0 + 36, y2 + 28 * (k as i32 + 1)), font.clone())).map_err(err)?;
    }
    Ok(())
}

/// Whether the design check `name` is an input of the sweep (an axis or an uncertain input
/// on `checks.NAME`): its limit differs from row to row.
fn check_is_input(spec: &Spec, name: &str) -> bool {
    let path = format!("checks.{name}");
    spec.axes.iter().map(|a| &a.path).chain(spec.uncertain.iter().map(|u| &u.path)).any(|p| *p == path)
}

/// The design-check boundary: the cell edges between a passing and a failing neighbour, in
/// the cells' coordinates (cell (i, j) spans i − 0.5 … i + 0.5).
fn boundary(grid: &[Vec<Cell>]) -> Vec<Vec<(f64, f64)>> {
    let mut edges = Vec::new();
    let (nx, ny) = (grid.len(), grid.first().map_or(0, Vec::len));
    for i in 0..nx {
        for j in 0..ny {
            let p = grid[i][j].pass;
            let differs = |q: Option<bool>| p.is_some() && q.is_some() && p != q;
            let (x, y) = (i as f64 + 0.5, j as f64 + 0.5);
            if i + 1 < nx && differs(grid[i + 1][j].pass) {
                edges.push(vec![(x, y - 1.0), (x, y)]);
            }
            if j + 1 < ny && differs(grid[i][j + 1].pass) {
                edges.push(vec![(x - 1.0, y), (x, y)]);
            }
        }
    }
    edges
}

/// The rows' design checks in words, e.g. `max_stopping_distance 40, safety_factor 1.5`; a
/// check that is an input of the sweep is named so (`max_stopping_distance by axis`).
fn describe_checks(spec: &Spec) -> String {
    let c = spec.base.checks.clone().unwrap_or_default();
    let parts: Vec<String> = [
        ("max_stopping_distance", c.max_stopping_distance),
        ("max_stopping_time", c.max_stopping_time),
        ("max_anchor_drag", c.max_anchor_drag),
        ("safety_factor", c.safety_factor),
        ("max_proof_utilisation", c.max_proof_utilisation),
    ]
    .into_iter()
    .filter_map(|(n, v)| match (check_is_input(spec, n), v) {
        (true, _) => Some(format!("{n} by row")),
        (false, Some(v)) => Some(format!("{n} {}", short(v))),
        (false, None) => None,
    })
    .collect();
    if parts.is_empty() {
        "none set but the break loads".into()
    } else {
        format!("{} and the break loads", parts.join(", "))
    }
}

/// The file of heat map `o` in the sweep's folder: `heatmap-NAME.svg`.
pub fn file_name(o: Output) -> String {
    format!("heatmap-{}.svg", o.name())
}

/// Draws every heat map of `outputs` (nothing when the spec has no two numeric grid axes),
/// then writes them into `dir` as `heatmap-NAME.svg`, each whole or not at all. Returns the
/// files written.
pub fn write(spec: &Spec, rows: &[SweepRow], outputs: &[Output], dir: &Path) -> Result<Vec<PathBuf>> {
    if unsupported(spec).is_some() {
        return Ok(Vec::new());
    }
    let mut charts = Vec::new();
    for &o in outputs {
        let file = file_name(o);
        let svg = heat_map(spec, rows, o).map_err(|message| Error::Plot { chart: file.clone(), message })?;
        charts.push((dir.join(file), svg));
    }
    let mut files = Vec::new();
    for (path, svg) in charts {
        write_atomically(&path, svg.as_bytes()).map_err(Error::io("write", &path))?;
        files.push(path);
    }
    Ok(files)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn ticks_and_names() {
        assert_eq!(short(500000.0), "5e5");
        assert_eq!(short(750000.0), "7.5e5");
        assert_eq!(short(2.5), "2.5");
        assert_eq!(short(40.0), "40");
        assert_eq!(short(27.004), "27");
        assert_eq!(short(0.171), "0.171");
        assert_eq!(scientific_text(20000.0, 4), "2e4");
        assert_eq!(scientific_text(160000.0, 4), "1.6e5");
        // Regression: every cell of a map over 0.17077–0.17111 read "0.171".
        assert_eq!(short_in(0.170768, 0.000345), "0.17077");
        assert_eq!(short_in(0.1708, 0.000345), "0.17080", "to the same place as its neighbours");
        assert_eq!(short_in(0.171113, 0.000345), "0.17111");
        assert_eq!(short_in(27.004, 10.0), "27", "a wide span keeps 4 digits");
        assert_eq!(short_in(500123.0, 20.0), "5.00123e5");
        // Regression: "fails: distance, anchor drag" ran into the next cell.
        let lines = crate::plot::wrap("fails: distance, anchor drag", 20);
        assert_eq!(lines, ["fails: distance,", "anchor drag"]);
        for o in Output::ALL {
            assert_eq!(Output::parse(o.name()).unwrap(), o);
        }
        assert!(Output::parse("speed").unwrap_err().to_string().contains("stopping_distance"));
        assert_eq!(parse_outputs(&[]).unwrap(), DEFAULT_OUTPUTS);
        assert!(parse_outputs(&["none".into()]).unwrap().is_empty());
    }

    #[test]
    fn the_scale_of_one_value_stays_on_its_side_of_zero() {
        assert_eq!(scale_range(&[0.0, 0.0]), (0.0, 0.05), "an all-zero distance is no negative one");
        assert_eq!(scale_range(&[20.0]), (19.0, 21.0));
        assert_eq!(scale_range(&[-2.0]), (-2.1, -1.9));
        assert_eq!(scale_range(&[1.0, 3.0]), (1.0, 3.0));
        assert_eq!(scale_range(&[]), (0.0, 1.0));
    }

    #[test]
    fn a_check_swept_by_an_axis_is_named_so_and_has_no_one_limit() {
        let case01 =
            kanestop_runtime::scene::Scene::from_toml(kanestop_runtime::paper::DEFAULT_SCENE, "case01").unwrap();
        let spec =
            |text: &str| Spec::from_toml(text, Path::new("s.toml"), Path::new(""), Some(case01.clone())).unwrap();
        let axes = "[[axis]]\npath = \"ship.mass\"\nvalues = [4e5, 5e5]\n";
        // Regression: the legend said "(no [checks] set)" of a sweep whose axis set the check.
        let swept = spec(&format!(
            "{axes}[[axis]]\npath = \"checks.max_stopping_distance\"\nvalues = [20.0, 40.0]\n[checks]\nsafety_factor = 1.5\n"
        ));
        assert_eq!(describe_checks(&swept), "max_stopping_distance by row, safety_factor 1.5 and the break loads");
        assert_eq!(Output::StoppingDistance.limit(&swept), None, "a limit per row is none on the scale");
        assert_eq!(Output::PeakUtilisation.limit(&swept), Some((1.0 / 1.5, "1 / safety_factor")));
        let none = spec(&format!("{axes}[[axis]]\npath = \"anchor.mass\"\nvalues = [3e4, 4e4]\n"));
        assert_eq!(describe_checks(&none), "none set but the break loads");
    }

    #[test]
    fn the_boundary_runs_between_passing_and_failing_cells_only() {
        let cell = |pass: Option<bool>| Cell { pass, ..Cell::default() };
        // Regression: the legend showed the red line of a map whose cells all failed.
        let all_fail = vec![vec![cell(Some(false)); 2]; 2];
        assert!(boundary(&all_fail).is_empty());
        assert!(boundary(&[vec![cell(Some(true)), cell(None)]]).is_empty(), "no value is no side");
        // One passing corner of four: its two inner edges.
        let mut corner = all_fail;
        corner[0][0] = cell(Some(true));
        assert_eq!(boundary(&corner), [vec![(0.5, -0.5), (0.5, 0.5)], vec![(-0.5, 0.5), (0.5, 0.5)]]);
    }

    #[test]
    fn viridis_runs_dark_to_light() {
        let lum = |c: RGBColor| 0.3 * c.0 as f64 + 0.59 * c.1 as f64 + 0.11 * c.2 as f64;
        let l: Vec<f64> = (0..=10).map(|k| lum(viridis(k as f64 / 10.0))).collect();
        assert!(l.windows(2).all(|w| w[1] > w[0]), "{l:?}");
    }

    #[test]
    fn hatching_stays_in_its_cell() {
        for seg in hatch(2.0, 3.0) {
            for (x, y) in seg {
                assert!((2.0..=3.0).contains(&x) && (3.0..=4.0).contains(&y), "({x}, {y})");
            }
        }
    }
}

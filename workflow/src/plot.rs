//! Plots an engineer reads instead of tables (SVG, no system fonts needed): ship surge speed,
//! ship and anchor displacement, peak joint tension along the line against the load
//! limits, and the energy terms. Several runs are overlaid.

use std::path::{Path, PathBuf};

use kanestop_runtime::forces::WORK_TERMS;
use kanestop_runtime::model::{LoadLimits, Model};
use kanestop_runtime::simulate::RunResult;
use plotters::prelude::*;

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
}

impl Curve {
    fn new(label: impl Into<String>, look: usize, points: Vec<(f64, f64)>) -> Self {
        Curve { label: label.into(), points, look, reference: false, in_view: false }
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
}

/// The axes' ranges: x over every curve, y over the data curves and over the reference
/// lines (load limits) that lie within 2.5 × the data's largest value (a limit far above the
/// data must not flatten it; the legend names it), from zero when `from_zero`, padded by 5 %.
fn bounds(curves: &[Curve], from_zero: bool) -> ((f64, f64), (f64, f64)) {
    let finite =
        |c: &Curve| c.points.iter().copied().filter(|(a, b)| a.is_finite() && b.is_finite()).collect::<Vec<_>>();
    let mut x = (f64::INFINITY, f64::NEG_INFINITY);
    let mut y = (if from_zero { 0.0 } else { f64::INFINITY }, if from_zero { 0.0 } else { f64::NEG_INFINITY });
    for c in curves {
        for (a, b) in finite(c) {
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

/// Chart size, pixels.
const SIZE: (u32, u32) = (900, 540);

/// A chart of one panel as SVG text.
fn chart(title: &str, x_label: &str, y_label: &str, curves: &[Curve], from_zero: bool) -> Result<String, String> {
    let mut svg = String::new();
    {
        let root = SVGBackend::with_string(&mut svg, SIZE).into_drawing_area();
        root.fill(&WHITE).map_err(|e| e.to_string())?;
        panel(&root, title, x_label, y_label, curves, 22, from_zero)?;
        root.present().map_err(|e| e.to_string())?;
    }
    Ok(svg)
}

/// Panels stacked or in a grid, each `(title, curves)`, sharing the axis labels, as SVG.
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
    let mut svg = String::new();
    {
        let root = SVGBackend::with_string(&mut svg, (w, h)).into_drawing_area();
        root.fill(&WHITE).map_err(|e| e.to_string())?;
        let root = root.titled(title, ("sans-serif", 22)).map_err(|e| e.to_string())?;
        let areas = root.split_evenly((rows, columns));
        for (area, (sub, curves)) in areas.iter().zip(panels) {
            panel(area, sub, x_label, y_label, curves, 16, false)?;
        }
        root.present().map_err(|e| e.to_string())?;
    }
    Ok(svg)
}

/// Draws one panel: axes with a light grid, the curves, a legend in the upper right.
fn panel<DB: DrawingBackend>(
    area: &DrawingArea<DB, plotters::coord::Shift>,
    title: &str,
    x_label: &str,
    y_label: &str,
    curves: &[Curve],
    title_size: u32,
    from_zero: bool,
) -> Result<(), String> {
    let err = |e: DrawingAreaErrorKind<DB::ErrorType>| e.to_string();
    let ((x0, x1), (y0, y1)) = bounds(curves, from_zero);
    let mut c = ChartBuilder::on(area)
        .caption(title, ("sans-serif", title_size))
        .margin(12)
        .x_label_area_size(44)
        .y_label_area_size(70)
        .build_cartesian_2d(x0..x1, y0..y1)
        .map_err(err)?;
    c.configure_mesh()
        .x_desc(x_label)
        .y_desc(y_label)
        .light_line_style(RGBColor(244, 244, 244))
        .bold_line_style(RGBColor(220, 220, 220))
        .x_label_formatter(&|v| tidy(*v))
        .y_label_formatter(&|v| tidy(*v))
        .draw()
        .map_err(err)?;
    let mut labelled = false;
    for curve in curves {
        let (color, pattern) = look(curve.look);
        let pattern = if curve.reference { Pattern::Dashed } else { pattern };
        let width = if curve.reference { 1 } else { 2 };
        let style = ShapeStyle { color: color.to_rgba(), filled: false, stroke_width: width };
        let pieces = curve.pieces((y0, y1));
        let shown: usize = pieces.iter().map(Vec::len).sum();
        let finite = curve.points.iter().filter(|(a, b)| a.is_finite() && b.is_finite()).count();
        let label = match (curve.reference, shown) {
            (true, 0) if finite > 0 => format!("{} (above the axis)", curve.label),
            (true, s) if s < finite => format!("{} (partly above the axis)", curve.label),
            _ => curve.label.clone(),
        };
        if finite == 0 {
            continue;
        }
        let mut first = true;
        for piece in pieces.into_iter().chain(shown.eq(&0).then(Vec::new)) {
            let series = match pattern {
                Pattern::Solid => c.draw_series(LineSeries::new(piece, style)),
                Pattern::Dashed => c.draw_series(DashedLineSeries::new(piece, 8, 5, style)),
                Pattern::Dotted => c.draw_series(DashedLineSeries::new(piece, 2, 4, style)),
            }
            .map_err(err)?;
            if std::mem::take(&mut first) && !label.is_empty() {
                labelled = true;
                series.label(label.clone());
                match pattern {
                    Pattern::Solid => series.legend(move |(x, y)| PathElement::new(vec![(x, y), (x + 20, y)], style)),
                    Pattern::Dashed => series.legend(move |(x, y)| {
                        EmptyElement::at((x, y))
                            + PathElement::new(vec![(0, 0), (8, 0)], style)
                            + PathElement::new(vec![(12, 0), (20, 0)], style)
                    }),
                    Pattern::Dotted => series.legend(move |(x, y)| {
                        EmptyElement::at((x, y))
                            + PathElement::new(vec![(0, 0), (3, 0)], style)
                            + PathElement::new(vec![(8, 0), (11, 0)], style)
                            + PathElement::new(vec![(16, 0), (19, 0)], style)
                    }),
                };
            }
        }
    }
    if labelled {
        c.configure_series_labels()
            .position(emptiest_corner(
                &curves.iter().flat_map(|c| c.points.clone()).collect::<Vec<_>>(),
                (x0, x1),
                (y0, y1),
            ))
            .background_style(WHITE.mix(0.85))
            .border_style(RGBColor(180, 180, 180))
            .draw()
            .map_err(err)?;
    }
    Ok(())
}

/// The files [`write_plots`] writes into its folder.
pub const FILES: [&str; 5] =
    ["ship-speed.svg", "displacement.svg", "peak-tension.svg", "utilisation.svg", "energy.svg"];

/// Writes ship-speed.svg, displacement.svg (ship above, anchor below), peak-tension.svg,
/// utilisation.svg (peak tension over break load along the line) and energy.svg (a panel per
/// run) for the runs into `dir`, each whole or not at all; every chart is drawn before the
/// first is written. A run with no samples (refused before its first step) has no curves.
/// Returns the files written.
pub fn write_plots(runs: &[(&Model, &RunResult)], dir: &Path) -> Result<Vec<PathBuf>> {
    let (ship, anchor) = displacement_curves(runs);
    let energy: Vec<(String, Vec<Curve>)> = runs
        .iter()
        .filter(|(_, r)| !r.samples.is_empty())
        .map(|(m, r)| (m.scene.meta.name.clone(), energy_curves(r)))
        .collect();
    let energy_title = match runs {
        [(m, _)] => format!("Energy terms, {}", m.scene.meta.name),
        _ => "Energy terms".to_string(),
    };
    let columns = if energy.len() > 1 { 2 } else { 1 };
    let charts = [
        (FILES[0], chart("Ship surge speed", "t (s)", "surge speed (m/s)", &speed_curves(runs), false)),
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
            chart(
                "Peak joint tension along the line",
                "joint k (B_k−1 – B_k)",
                "tension (kN)",
                &tension_curves(runs),
                true,
            ),
        ),
        (
            FILES[3],
            chart(
                "Utilisation along the line: peak tension / break load",
                "joint k (B_k−1 – B_k)",
                "utilisation (%)",
                &utilisation_curves(runs),
                true,
            ),
        ),
        (FILES[4], panels(&energy_title, "t (s)", "energy (MJ)", &energy, columns)),
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

/// The ship's surge speed of each run.
fn speed_curves(runs: &[(&Model, &RunResult)]) -> Vec<Curve> {
    runs.iter()
        .enumerate()
        .map(|(i, (m, r))| {
            let n = m.body_count();
            Curve::new(m.scene.meta.name.clone(), i, r.samples.iter().map(|s| (s.t, s.bodies[n - 1].vx)).collect())
        })
        .collect()
}

/// The ship's and the anchor's displacement of each run that has samples, one colour per run.
fn displacement_curves(runs: &[(&Model, &RunResult)]) -> (Vec<Curve>, Vec<Curve>) {
    let (mut ship, mut anchor) = (Vec::new(), Vec::new());
    for (i, (m, r)) in runs.iter().enumerate() {
        let Some(first) = r.samples.first() else { continue };
        let n = m.body_count();
        let (s0, a0) = (first.bodies[n - 1].x, first.bodies[0].x);
        let name = &m.scene.meta.name;
        ship.push(Curve::new(
            format!("{name} ship"),
            i,
            r.samples.iter().map(|s| (s.t, s.bodies[n - 1].x - s0)).collect(),
        ));
        anchor.push(Curve::new(
            format!("{name} anchor"),
            i,
            r.samples.iter().map(|s| (s.t, s.bodies[0].x - a0)).collect(),
        ));
    }
    (ship, anchor)
}

/// A load limit along the line as a step: flat over each joint k (k ± ½), a vertical jump
/// where it changes, a gap at a joint that has none.
fn step(n: usize, value: impl Fn(usize) -> Option<f64>) -> Vec<(f64, f64)> {
    let mut points = Vec::new();
    for k in 2..=n {
        match value(k) {
            Some(v) => points.extend([(k as f64 - 0.5, v), (k as f64 + 0.5, v)]),
            None => points.push((f64::NAN, f64::NAN)),
        }
    }
    points
}

/// The peak tension along the line of each run (kN), and the first run's proof and break
/// loads as steps; the axis follows the peaks, a limit above it is named in the legend.
fn tension_curves(runs: &[(&Model, &RunResult)]) -> Vec<Curve> {
    let mut curves: Vec<Curve> = runs
        .iter()
        .enumerate()
        .filter(|(_, (_, r))| r.steps > 0)
        .map(|(i, (m, r))| {
            let points = r.peak_tensions.iter().enumerate().map(|(j, p)| ((j + 2) as f64, p.tension / 1e3)).collect();
            Curve::new(format!("{} peak", m.scene.meta.name), i, points)
        })
        .collect();
    if let Some((m, _)) = runs.first() {
        let n = m.body_count();
        // The legend says what the limit is (it is often above the axis): its value, or the
        // range of its values along the line (chain and cable differ).
        let limit = |label: &str, look: usize, pick: fn(LoadLimits) -> Option<f64>| {
            let points = step(n, |k| pick(m.joint_limits(k)).map(|v| v / 1e3));
            let values = points.iter().map(|p| p.1).filter(|v| v.is_finite());
            let (lo, hi) = values.fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), v| (a.min(v), b.max(v)));
            let label = match (lo.is_finite(), lo == hi) {
                (false, _) => label.to_string(),
                (true, true) => format!("{label} {lo:.0} kN"),
                (true, false) => format!("{label} {lo:.0}–{hi:.0} kN"),
            };
            Curve { label, points, look, reference: true, in_view: false }
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
        .filter(|(_, (_, r))| r.steps > 0)
        .map(|(i, (m, r))| {
            let points = r
                .peak_tensions
                .iter()
                .enumerate()
                .map(|(j, p)| {
                    let k = j + 2;
                    (k as f64, m.joint_limits(k).breaking.map_or(f64::NAN, |b| 100.0 * p.tension / b))
                })
                .collect();
            Curve::new(m.scene.meta.name.clone(), i, points)
        })
        .collect();
    if let Some((m, _)) = runs.first() {
        let n = m.body_count();
        // Not drawn where the proof load is above the joint's break load (the chain's at the
        // chain–cable joint, where the cable is the weaker member): the break load governs.
        let proof = step(n, |k| {
            let l = m.joint_limits(k);
            Some(100.0 * l.proof? / l.breaking?).filter(|&u| u <= 100.0)
        });
        curves.push(Curve { label: "proof load".into(), points: proof, look: 4, reference: true, in_view: true });
        curves.push(Curve {
            label: "break load (100 %)".into(),
            points: step(n, |_| Some(100.0)),
            look: 1,
            reference: true,
            in_view: true,
        });
    }
    curves
}

/// The energy terms of one run (Eq. 63): kinetic, potential change, each work term, and the
/// balance's drift.
fn energy_curves(r: &RunResult) -> Vec<Curve> {
    let Some(first) = r.samples.first() else { return Vec::new() };
    let series = |f: &dyn Fn(&kanestop_runtime::simulate::Sample) -> f64| -> Vec<(f64, f64)> {
        r.samples.iter().map(|s| (s.t, f(s) / 1e6)).collect()
    };
    let mut curves = vec![
        Curve::new("kinetic", 0, series(&|s| s.energy.kinetic + s.energy.added_kinetic)),
        Curve::new("potential energy change", 1, series(&|s| s.energy.potential - first.energy.potential)),
    ];
    for (i, term) in WORK_TERMS.iter().enumerate() {
        curves.push(Curve::new(format!("work: {term}"), 2 + i, series(&|s| s.energy.work[i])));
    }
    curves.push(Curve::new("balance drift E − E_0", 2 + WORK_TERMS.len(), series(&|s| s.energy.balance() - r.energy0)));
    curves
}

/// One curve of a [`log_log`] chart.
#[derive(Clone, Debug, PartialEq)]
pub struct LogCurve {
    /// The legend entry; `None` draws the curve without one.
    pub label: Option<String>,
    /// Its colour, as an index into the palette.
    pub color: usize,
    /// Thin (a secondary quantity) or thick.
    pub thin: bool,
    /// The points, positive in both coordinates, in drawing order.
    pub points: Vec<(f64, f64)>,
}

/// A log–log chart of `curves` (lines with a marker at each point) as SVG text, the legend in
/// the corner with the fewest points; `widths` names what a thick and a thin line stand for, as two more
/// legend entries in grey.
pub fn log_log(
    title: &str,
    x_desc: &str,
    y_desc: &str,
    curves: &[LogCurve],
    widths: Option<(&str, &str)>,
) -> Result<String> {
    log_log_svg(title, x_desc, y_desc, curves, widths)
        .map_err(|message| Error::Plot { chart: title.to_string(), message })
}

fn log_log_svg(
    title: &str,
    x_desc: &str,
    y_desc: &str,
    curves: &[LogCurve],
    widths: Option<(&str, &str)>,
) -> Result<String, String> {
    let mut svg = String::new();
    {
        let root = SVGBackend::with_string(&mut svg, (900, 540)).into_drawing_area();
        root.fill(&WHITE).map_err(|e| e.to_string())?;
        let (mut x0, mut x1, mut y0, mut y1) = (f64::MAX, f64::MIN, f64::MAX, f64::MIN);
        for &(x, y) in curves.iter().flat_map(|c| &c.points) {
            (x0, x1, y0, y1) = (x0.min(x), x1.max(x), y0.min(y), y1.max(y));
        }
        if curves.iter().all(|c| c.points.is_empty()) {
            (x0, x1, y0, y1) = (1e-3, 1.0, 1e-9, 1.0);
        }
        let logs: Vec<(f64, f64)> =
            curves.iter().flat_map(|c| &c.points).map(|&(x, y)| (x.log10(), y.log10())).collect();
        let (lx0, lx1, ly0, ly1) = ((x0 * 0.8).log10(), (x1 * 1.25).log10(), (y0 * 0.5).log10(), (y1 * 2.0).log10());
        let mut c = ChartBuilder::on(&root)
            .caption(title, ("sans-serif", 22))
            .margin(12)
            .x_label_area_size(44)
            .y_label_area_size(80)
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
        let x_text = |v: &f64| once(log_tick(*v, &[1.0, 2.0, 5.0]).map(tidy).unwrap_or_default());
        let y_text = |v: &f64| once(log_tick(*v, &[1.0]).map(|v| format!("{v:.0e}")).unwrap_or_default());
        c.configure_mesh()
            .disable_mesh()
            .x_desc(x_desc)
            .y_desc(y_desc)
            .x_labels(40)
            .y_labels(40)
            .x_label_formatter(&x_text)
            .y_label_formatter(&y_text)
            .draw()
            .map_err(|e| e.to_string())?;
        let grid = ShapeStyle { color: RGBColor(225, 225, 225).to_rgba(), filled: false, stroke_width: 1 };
        for x in log_ticks(xr.start, xr.end, &[1.0, 2.0, 5.0]) {
            c.draw_series(LineSeries::new([(x, yr.start), (x, yr.end)], grid)).map_err(|e| e.to_string())?;
        }
        for y in log_ticks(yr.start, yr.end, &[1.0]) {
            c.draw_series(LineSeries::new([(xr.start, y), (xr.end, y)], grid)).map_err(|e| e.to_string())?;
        }
        for curve in curves.iter().filter(|c| !c.points.is_empty()) {
            let color = PALETTE[curve.color % PALETTE.len()];
            let style =
                ShapeStyle { color: color.to_rgba(), filled: false, stroke_width: if curve.thin { 1 } else { 2 } };
            let series = c.draw_series(LineSeries::new(curve.points.clone(), style)).map_err(|e| e.to_string())?;
            if let Some(label) = &curve.label {
                series
                    .label(label.clone())
                    .legend(move |(x, y)| PathElement::new(vec![(x, y), (x + 18, y)], color.stroke_width(2)));
            }
            c.draw_series(curve.points.iter().map(|&p| Circle::new(p, 3, color.filled())))
                .map_err(|e| e.to_string())?;
        }
        if let Some((thick, thin)) = widths {
            for (label, width) in [(thick, 2), (thin, 1)] {
                let grey = RGBColor(110, 110, 110);
                c.draw_series(LineSeries::new(std::iter::empty::<(f64, f64)>(), grey.stroke_width(width)))
                    .map_err(|e| e.to_string())?
                    .label(label)
                    .legend(move |(x, y)| PathElement::new(vec![(x, y), (x + 18, y)], grey.stroke_width(width)));
            }
        }
        c.configure_series_labels()
            .position(emptiest_corner(&logs, (lx0, lx1), (ly0, ly1)))
            .background_style(WHITE.mix(0.85))
            .border_style(BLACK)
            .draw()
            .map_err(|e| e.to_string())?;
        root.present().map_err(|e| e.to_string())?;
    }
    Ok(svg)
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
        Curve { label: "limit".into(), points, look: 1, reference: true, in_view: false }
    }

    #[test]
    fn a_limit_far_above_the_data_does_not_flatten_it() {
        // Regression: the peak-tension axis ran to the 4 000 kN break load; 400 kN peaks were a line.
        let data = Curve::new("peak", 0, vec![(2.0, 395.0), (46.0, 430.0)]);
        let far = reference(step(46, |_| Some(3866.0)));
        let ((_, _), (y0, y1)) = bounds(&[data, far], true);
        assert_eq!(y0, 0.0);
        assert!(y1 < 500.0, "{y1}");
        let data = Curve::new("util", 0, vec![(2.0, 10.0), (46.0, 38.6)]);
        let near = reference(step(46, |_| Some(70.0)));
        let (_, (_, y1)) = bounds(&[data, near], true);
        assert!(y1 > 70.0, "a limit near the data is on the axis: {y1}");
    }

    #[test]
    fn a_limit_is_a_step_not_a_slope() {
        // Regression: the proof/break load changing from chain to cable was drawn as a slope.
        let points = step(4, |k| Some(if k < 3 { 2.0 } else { 1.0 }));
        assert_eq!(points, [(1.5, 2.0), (2.5, 2.0), (2.5, 1.0), (3.5, 1.0), (3.5, 1.0), (4.5, 1.0)]);
        let gap = step(3, |k| (k == 2).then_some(1.0));
        assert!(gap[2].0.is_nan(), "a joint without a limit breaks the line");
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
        let curve =
            LogCurve { label: Some("rk4".into()), color: 0, thin: false, points: vec![(0.1, 1e-2), (0.9, 1e-8)] };
        let svg = log_log("t", "wall time (s)", "error", &[curve], None).unwrap();
        for label in ["0.1", "0.2", "0.5", "1e-4"] {
            assert_eq!(svg.matches(&format!(">\n{label}\n</text>")).count(), 1, "{label} printed once");
        }
    }
}

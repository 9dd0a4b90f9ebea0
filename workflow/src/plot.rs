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

/// One named curve.
struct Curve {
    label: String,
    points: Vec<(f64, f64)>,
    dashed: bool,
}

fn bounds(curves: &[Curve]) -> ((f64, f64), (f64, f64)) {
    let mut x = (f64::INFINITY, f64::NEG_INFINITY);
    let mut y = (f64::INFINITY, f64::NEG_INFINITY);
    for c in curves {
        for &(a, b) in &c.points {
            x = (x.0.min(a), x.1.max(a));
            y = (y.0.min(b), y.1.max(b));
        }
    }
    if !x.0.is_finite() {
        return ((0.0, 1.0), (0.0, 1.0));
    }
    let pad = 0.05 * (y.1 - y.0).max(1e-9);
    ((x.0, x.1.max(x.0 + 1e-9)), (y.0 - pad, y.1 + pad))
}

fn chart(title: &str, x_label: &str, y_label: &str, curves: &[Curve]) -> Result<String, String> {
    // plotters' errors carry the backend's type; their text is what a user can act on.
    let mut svg = String::new();
    {
        let root = SVGBackend::with_string(&mut svg, (900, 540)).into_drawing_area();
        root.fill(&WHITE).map_err(|e| e.to_string())?;
        let ((x0, x1), (y0, y1)) = bounds(curves);
        let mut c = ChartBuilder::on(&root)
            .caption(title, ("sans-serif", 22))
            .margin(12)
            .x_label_area_size(44)
            .y_label_area_size(70)
            .build_cartesian_2d(x0..x1, y0..y1)
            .map_err(|e| e.to_string())?;
        c.configure_mesh().x_desc(x_label).y_desc(y_label).draw().map_err(|e| e.to_string())?;
        for (i, curve) in curves.iter().enumerate() {
            let color = PALETTE[i % PALETTE.len()];
            let style =
                ShapeStyle { color: color.to_rgba(), filled: false, stroke_width: if curve.dashed { 1 } else { 2 } };
            c.draw_series(LineSeries::new(curve.points.iter().copied(), style))
                .map_err(|e| e.to_string())?
                .label(curve.label.clone())
                .legend(move |(x, y)| PathElement::new(vec![(x, y), (x + 18, y)], color.stroke_width(2)));
        }
        c.configure_series_labels()
            .background_style(WHITE.mix(0.85))
            .border_style(BLACK)
            .draw()
            .map_err(|e| e.to_string())?;
        root.present().map_err(|e| e.to_string())?;
    }
    Ok(svg)
}

/// Writes ship-speed.svg, displacement.svg, peak-tension.svg and energy.svg for the runs
/// into `dir`, each whole or not at all; every chart is drawn before the first is written.
/// A run with no samples (refused before its first step) has no curves. Returns the files
/// written.
pub fn write_plots(runs: &[(&Model, &RunResult)], dir: &Path) -> Result<Vec<PathBuf>> {
    let charts = [
        ("ship-speed.svg", chart("Ship surge speed", "t (s)", "surge speed (m/s)", &speed_curves(runs))),
        (
            "displacement.svg",
            chart("Ship and anchor displacement", "t (s)", "displacement (m)", &displacement_curves(runs)),
        ),
        (
            "peak-tension.svg",
            chart("Peak joint tension along the line", "joint k (B_k−1 – B_k)", "tension (kN)", &tension_curves(runs)),
        ),
    ];
    let energy = runs.first().map(|(m, r)| {
        let title = format!("Energy terms, {}", m.scene.meta.name);
        ("energy.svg", chart(&title, "t (s)", "energy (MJ)", &energy_curves(r)))
    });
    let mut svgs = Vec::new();
    for (file, svg) in charts.into_iter().chain(energy) {
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
        .map(|(m, r)| {
            let n = m.body_count();
            Curve {
                label: m.scene.meta.name.clone(),
                points: r.samples.iter().map(|s| (s.t, s.bodies[n - 1].vx)).collect(),
                dashed: false,
            }
        })
        .collect()
}

/// The ship's (solid) and the anchor's (dashed) displacement of each run that has samples.
fn displacement_curves(runs: &[(&Model, &RunResult)]) -> Vec<Curve> {
    let mut curves = Vec::new();
    for (m, r) in runs {
        let Some(first) = r.samples.first() else { continue };
        let n = m.body_count();
        let (s0, a0) = (first.bodies[n - 1].x, first.bodies[0].x);
        curves.push(Curve {
            label: format!("{} ship", m.scene.meta.name),
            points: r.samples.iter().map(|s| (s.t, s.bodies[n - 1].x - s0)).collect(),
            dashed: false,
        });
        curves.push(Curve {
            label: format!("{} anchor", m.scene.meta.name),
            points: r.samples.iter().map(|s| (s.t, s.bodies[0].x - a0)).collect(),
            dashed: true,
        });
    }
    curves
}

/// The peak tension along the line of each run, and the first run's proof and break loads.
fn tension_curves(runs: &[(&Model, &RunResult)]) -> Vec<Curve> {
    let mut curves: Vec<Curve> = runs
        .iter()
        .map(|(m, r)| Curve {
            label: format!("{} peak", m.scene.meta.name),
            points: r.peak_tensions.iter().enumerate().map(|(i, p)| ((i + 2) as f64, p.tension / 1e3)).collect(),
            dashed: false,
        })
        .collect();
    if let Some((m, _)) = runs.first() {
        let n = m.body_count();
        let limit_curve = |label: &str, pick: fn(LoadLimits) -> Option<f64>| Curve {
            label: label.into(),
            points: (2..=n).filter_map(|k| pick(m.joint_limits(k)).map(|v| (k as f64, v / 1e3))).collect(),
            dashed: true,
        };
        curves.push(limit_curve("proof load", |l| l.proof));
        curves.push(limit_curve("break load", |l| l.breaking));
    }
    curves
}

/// The energy terms of one run (Eq. 63): kinetic, potential change, each work term, and the
/// balance's drift.
fn energy_curves(r: &RunResult) -> Vec<Curve> {
    let Some(first) = r.samples.first() else { return Vec::new() };
    let mut curves = vec![
        Curve {
            label: "kinetic".into(),
            points: r.samples.iter().map(|s| (s.t, (s.energy.kinetic + s.energy.added_kinetic) / 1e6)).collect(),
            dashed: false,
        },
        Curve {
            label: "potential − E_G(0)".into(),
            points: r.samples.iter().map(|s| (s.t, (s.energy.potential - first.energy.potential) / 1e6)).collect(),
            dashed: false,
        },
    ];
    for (i, term) in WORK_TERMS.iter().enumerate() {
        curves.push(Curve {
            label: format!("work: {term}"),
            points: r.samples.iter().map(|s| (s.t, s.energy.work[i] / 1e6)).collect(),
            dashed: true,
        });
    }
    curves.push(Curve {
        label: "balance − E_0".into(),
        points: r.samples.iter().map(|s| (s.t, (s.energy.balance() - r.energy0) / 1e6)).collect(),
        dashed: false,
    });
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

/// A log–log chart of `curves` (lines with a marker at each point) as SVG text.
pub fn log_log(title: &str, x_desc: &str, y_desc: &str, curves: &[LogCurve]) -> Result<String> {
    log_log_svg(title, x_desc, y_desc, curves).map_err(|message| Error::Plot { chart: title.to_string(), message })
}

fn log_log_svg(title: &str, x_desc: &str, y_desc: &str, curves: &[LogCurve]) -> Result<String, String> {
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
        let mut c = ChartBuilder::on(&root)
            .caption(title, ("sans-serif", 22))
            .margin(12)
            .x_label_area_size(44)
            .y_label_area_size(80)
            .build_cartesian_2d((x0 * 0.8..x1 * 1.25).log_scale(), (y0 * 0.5..y1 * 2.0).log_scale())
            .map_err(|e| e.to_string())?;
        c.configure_mesh()
            .x_desc(x_desc)
            .y_desc(y_desc)
            .x_label_formatter(&|v| format!("{v:.2}"))
            .y_label_formatter(&|v| format!("{v:.0e}"))
            .draw()
            .map_err(|e| e.to_string())?;
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
        c.configure_series_labels()
            .background_style(WHITE.mix(0.85))
            .border_style(BLACK)
            .draw()
            .map_err(|e| e.to_string())?;
        root.present().map_err(|e| e.to_string())?;
    }
    Ok(svg)
}

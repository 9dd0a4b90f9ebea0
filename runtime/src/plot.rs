//! Plots an engineer reads instead of tables (SVG, no system fonts needed): ship surge speed,
//! ship and anchor displacement, peak joint tension along the line against the load
//! limits, and the energy terms. Several runs are overlaid.

use std::path::{Path, PathBuf};

use plotters::prelude::*;

use crate::model::Model;
use crate::report::{joint_limits, write_atomically};
use crate::simulate::RunResult;

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
/// into `dir`, each whole or not at all. Returns the files written.
pub fn write_plots(runs: &[(&Model, &RunResult)], dir: &Path) -> Result<Vec<PathBuf>, String> {
    std::fs::create_dir_all(dir).map_err(|e| format!("cannot create {}: {e}", dir.display()))?;
    let name = |m: &Model| m.scene.meta.name.clone();
    let mut files = Vec::new();
    let mut emit = |file: &str, svg: String| -> Result<(), String> {
        let path = dir.join(file);
        write_atomically(&path, svg.as_bytes()).map_err(|e| format!("cannot write {}: {e}", path.display()))?;
        files.push(path);
        Ok(())
    };

    let speed: Vec<Curve> = runs
        .iter()
        .map(|(m, r)| {
            let n = m.body_count();
            Curve {
                label: name(m),
                points: r.samples.iter().map(|s| (s.t, s.bodies[n - 1].vx)).collect(),
                dashed: false,
            }
        })
        .collect();
    emit("ship-speed.svg", chart("Ship surge speed", "t (s)", "surge speed (m/s)", &speed)?)?;

    let mut displacement = Vec::new();
    for (m, r) in runs {
        let n = m.body_count();
        let (s0, a0) = (r.samples[0].bodies[n - 1].x, r.samples[0].bodies[0].x);
        displacement.push(Curve {
            label: format!("{} ship", name(m)),
            points: r.samples.iter().map(|s| (s.t, s.bodies[n - 1].x - s0)).collect(),
            dashed: false,
        });
        displacement.push(Curve {
            label: format!("{} anchor", name(m)),
            points: r.samples.iter().map(|s| (s.t, s.bodies[0].x - a0)).collect(),
            dashed: true,
        });
    }
    emit("displacement.svg", chart("Ship and anchor displacement", "t (s)", "displacement (m)", &displacement)?)?;

    let mut tension: Vec<Curve> = runs
        .iter()
        .map(|(m, r)| Curve {
            label: format!("{} peak", name(m)),
            points: r.peak_tensions.iter().enumerate().map(|(i, p)| ((i + 2) as f64, p.tension / 1e3)).collect(),
            dashed: false,
        })
        .collect();
    if let Some((m, _)) = runs.first() {
        let n = m.body_count();
        let limit_curve = |label: &str, pick: fn((Option<f64>, Option<f64>)) -> Option<f64>| Curve {
            label: label.into(),
            points: (2..=n).filter_map(|k| pick(joint_limits(m, k)).map(|v| (k as f64, v / 1e3))).collect(),
            dashed: true,
        };
        tension.push(limit_curve("proof load", |l| l.0));
        tension.push(limit_curve("break load", |l| l.1));
    }
    emit(
        "peak-tension.svg",
        chart("Peak joint tension along the line", "joint k (B_k−1 – B_k)", "tension (kN)", &tension)?,
    )?;

    if let Some((m, r)) = runs.first() {
        let mut energy = vec![
            Curve {
                label: "kinetic".into(),
                points: r.samples.iter().map(|s| (s.t, (s.energy.kinetic + s.energy.added_kinetic) / 1e6)).collect(),
                dashed: false,
            },
            Curve {
                label: "potential − E_G(0)".into(),
                points: r
                    .samples
                    .iter()
                    .map(|s| (s.t, (s.energy.potential - r.samples[0].energy.potential) / 1e6))
                    .collect(),
                dashed: false,
            },
        ];
        for (i, term) in crate::forces::WORK_TERMS.iter().enumerate() {
            energy.push(Curve {
                label: format!("work: {term}"),
                points: r.samples.iter().map(|s| (s.t, s.energy.work[i] / 1e6)).collect(),
                dashed: true,
            });
        }
        energy.push(Curve {
            label: "balance − E_0".into(),
            points: r.samples.iter().map(|s| (s.t, (s.energy.balance() - r.energy0) / 1e6)).collect(),
            dashed: false,
        });
        emit("energy.svg", chart(&format!("Energy terms, {}", name(m)), "t (s)", "energy (MJ)", &energy)?)?;
    }
    Ok(files)
}

/// Work–precision chart of an accuracy study: stopping-time error (and trajectory error,
/// dashed) against wall time, log–log, one curve per method.
pub fn work_precision(study: &crate::accuracy::AccuracyStudy) -> Result<String, String> {
    let mut svg = String::new();
    {
        let root = SVGBackend::with_string(&mut svg, (900, 540)).into_drawing_area();
        root.fill(&WHITE).map_err(|e| e.to_string())?;
        let points = |m: &str, pick: fn(&crate::accuracy::AccuracyRow) -> Option<f64>| -> Vec<(f64, f64)> {
            study
                .rows
                .iter()
                .filter(|r| r.method == m)
                .filter_map(|r| pick(r).filter(|e| *e > 0.0).map(|e| (r.wall_time, e)))
                .collect()
        };
        let all: Vec<(f64, f64)> = ["rk4", "dp5", "sdirk4"]
            .iter()
            .flat_map(|m| points(m, |r| r.stopping_time_error).into_iter().chain(points(m, |r| r.trajectory_error)))
            .collect();
        let (mut x0, mut x1, mut y0, mut y1) = (f64::MAX, f64::MIN, f64::MAX, f64::MIN);
        for &(x, y) in &all {
            (x0, x1, y0, y1) = (x0.min(x), x1.max(x), y0.min(y), y1.max(y));
        }
        if all.is_empty() {
            (x0, x1, y0, y1) = (1e-3, 1.0, 1e-9, 1.0);
        }
        let mut c = ChartBuilder::on(&root)
            .caption(format!("Error against run time, {}", study.scene), ("sans-serif", 22))
            .margin(12)
            .x_label_area_size(44)
            .y_label_area_size(80)
            .build_cartesian_2d((x0 * 0.8..x1 * 1.25).log_scale(), (y0 * 0.5..y1 * 2.0).log_scale())
            .map_err(|e| e.to_string())?;
        c.configure_mesh()
            .x_desc("wall time (s)")
            .y_desc("error: stopping time (s), trajectory (m, thin)")
            .x_label_formatter(&|v| format!("{v:.2}"))
            .y_label_formatter(&|v| format!("{v:.0e}"))
            .draw()
            .map_err(|e| e.to_string())?;
        for (i, m) in ["rk4", "dp5", "sdirk4"].iter().enumerate() {
            let color = PALETTE[i];
            for (dashed, pick) in [
                (false, (|r: &crate::accuracy::AccuracyRow| r.stopping_time_error) as fn(&_) -> _),
                (true, |r: &crate::accuracy::AccuracyRow| r.trajectory_error),
            ] {
                let mut pts = points(m, pick);
                pts.sort_by(|a, b| a.0.total_cmp(&b.0));
                if pts.is_empty() {
                    continue;
                }
                let style =
                    ShapeStyle { color: color.to_rgba(), filled: false, stroke_width: if dashed { 1 } else { 2 } };
                let series = c.draw_series(LineSeries::new(pts.clone(), style)).map_err(|e| e.to_string())?;
                if !dashed {
                    series
                        .label(m.to_string())
                        .legend(move |(x, y)| PathElement::new(vec![(x, y), (x + 18, y)], color.stroke_width(2)));
                }
                c.draw_series(pts.iter().map(|&p| Circle::new(p, 3, color.filled()))).map_err(|e| e.to_string())?;
            }
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

//! Many scenes at once: every scene of a folder run in parallel (rayon), one result row
//! each, written as a terminal table, CSV and JSON. On request each run is repeated with a
//! refined setting (RK4: dt/2; adaptive methods: rtol and atol/10) and the difference is its
//! error estimate.

use std::path::{Path, PathBuf};

use rayon::prelude::*;
use serde::{Deserialize, Serialize};

use crate::kernel::Kernel;
use crate::model::Model;
use crate::report::{break_exceedances, write_atomically};
use crate::scene::{IntegratorKind, Scene};
use crate::simulate::{self, RunResult, Stop};

/// One scene's outcome.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct BatchRow {
    /// Scene name (`meta.name`), or the file name when the scene did not load.
    pub case: String,
    /// The scene file.
    pub file: String,
    /// "stopped", "end time", "failed" or "invalid".
    pub status: String,
    /// The integrator: "rk4", "dp5" or "sdirk4" ("" when the scene did not load).
    pub method: String,
    /// Number of bodies.
    pub bodies: Option<usize>,
    /// First zero of the ship's surge speed, s.
    pub stopping_time: Option<f64>,
    /// Table 3's value, s.
    pub paper_stopping_time: Option<f64>,
    /// (stopping time − paper) / paper.
    pub relative_difference: Option<f64>,
    /// Largest joint tension, N.
    pub peak_tension: Option<f64>,
    /// The joint k (between B_{k−1} and B_k) where it occurred.
    pub peak_joint: Option<usize>,
    /// When it occurred, s.
    pub peak_time: Option<f64>,
    /// Joints whose peak exceeded their break load.
    pub break_exceedances: usize,
    /// When the anchor first slid, s.
    pub anchor_start: Option<f64>,
    /// Largest relative drift of the energy balance.
    pub energy_drift: Option<f64>,
    /// Wall-clock time of the run, s.
    pub wall_time: f64,
    /// |t_stop − t_stop,refined|, s: the stopping time's error estimate (with
    /// `estimate`, when both runs stopped the ship).
    pub stop_error_estimate: Option<f64>,
    /// Largest centroid position difference from the refined run at the common output
    /// times, m (with `estimate`, when neither run failed).
    pub trajectory_error_estimate: Option<f64>,
    /// Error or diagnostic, if any.
    pub message: String,
}

/// The scene files of a folder (`*.toml`), sorted by name.
pub fn scene_files(dir: &Path) -> std::io::Result<Vec<PathBuf>> {
    let mut files: Vec<PathBuf> = std::fs::read_dir(dir)?
        .filter_map(|e| e.ok().map(|e| e.path()))
        .filter(|p| p.extension().is_some_and(|x| x == "toml"))
        .collect();
    files.sort();
    Ok(files)
}

/// The row of one finished run.
pub fn row(file: &Path, model: &Model, result: &RunResult) -> BatchRow {
    let paper = model.scene.meta.paper_stopping_time;
    // A run refused before its first step has no peak and no drift to report.
    let ran = result.steps > 0;
    let peak = result.peak_tension().filter(|_| ran);
    let (status, message) = match &result.stop {
        Stop::ShipStopped => ("stopped", String::new()),
        Stop::EndTime => ("end time", String::new()),
        Stop::Failed(f) => ("failed", one_line(&f.to_string())),
    };
    BatchRow {
        case: model.scene.meta.name.clone(),
        file: file.display().to_string(),
        status: status.into(),
        method: method_name(model.scene.solver.integrator).into(),
        bodies: Some(model.body_count()),
        stopping_time: result.stopping_time,
        paper_stopping_time: paper,
        relative_difference: result.stopping_time.zip(paper).map(|(t, p)| (t - p) / p),
        peak_tension: peak.map(|p| p.1.tension),
        peak_joint: peak.map(|p| p.0),
        peak_time: peak.map(|p| p.1.t),
        break_exceedances: break_exceedances(model, result).len(),
        anchor_start: result.anchor_start(),
        energy_drift: ran.then_some(result.max_energy_drift),
        wall_time: result.wall_time.as_secs_f64(),
        stop_error_estimate: None,
        trajectory_error_estimate: None,
        message,
    }
}

/// "rk4", "dp5" or "sdirk4".
pub fn method_name(kind: IntegratorKind) -> &'static str {
    match kind {
        IntegratorKind::Rk4 => "rk4",
        IntegratorKind::Dp5 => "dp5",
        IntegratorKind::Sdirk4 => "sdirk4",
    }
}

/// The same scene integrated more accurately: RK4 at dt/2, an adaptive method at a tenth of
/// its tolerances (same observation interval), on the same output times.
pub fn refined(scene: &Scene) -> Scene {
    let mut s = scene.clone();
    match s.solver.integrator {
        IntegratorKind::Rk4 => s.solver.dt /= 2.0,
        IntegratorKind::Dp5 | IntegratorKind::Sdirk4 => {
            s.solver.rtol /= 10.0;
            s.solver.atol /= 10.0;
        }
    }
    s
}

/// Fills the error estimates of `row` from the refined run.
fn estimate(row: &mut BatchRow, result: &RunResult, fine: &RunResult) {
    let failed = |r: &RunResult| matches!(r.stop, Stop::Failed(_));
    if failed(result) || failed(fine) {
        return;
    }
    row.stop_error_estimate = result.stopping_time.zip(fine.stopping_time).map(|(a, b)| (a - b).abs());
    row.trajectory_error_estimate = Some(simulate::trajectory_difference(result, fine));
}

/// Adjusts a loaded scene before it runs (e.g. command-line solver overrides); an error
/// marks the scene invalid.
pub type Configure<'a> = &'a (dyn Fn(&mut Scene) -> Result<(), String> + Sync);

/// Runs every file in parallel; `configure` adjusts each scene, `kernel` builds each run's
/// kernel and `done` is called (from any thread) as each run finishes; with `error_estimate`
/// each run is repeated [`refined`] to estimate its error. Rows come back in file order.
pub fn run_all(
    files: &[PathBuf],
    configure: Configure,
    kernel: &(dyn Fn(&Model) -> Box<dyn Kernel> + Sync),
    error_estimate: bool,
    done: &(dyn Fn(&BatchRow) + Sync),
) -> Vec<BatchRow> {
    files
        .par_iter()
        .map(|file| {
            let model = Scene::load(file).map_err(|e| e.to_string()).and_then(|mut s| {
                configure(&mut s)?;
                Model::new(&s).map_err(|e| e.to_string())
            });
            let row = match model {
                Ok(model) => {
                    let result = simulate::run(&model, kernel(&model));
                    let mut row = row(file, &model, &result);
                    if error_estimate {
                        match Model::new(&refined(&model.scene)) {
                            Ok(fine) => estimate(&mut row, &result, &simulate::run(&fine, kernel(&fine))),
                            Err(e) => row.message = one_line(&format!("no error estimate: {e}")),
                        }
                    }
                    row
                }
                Err(message) => BatchRow {
                    case: file.file_stem().map(|s| s.to_string_lossy().into_owned()).unwrap_or_default(),
                    file: file.display().to_string(),
                    status: "invalid".into(),
                    method: String::new(),
                    bodies: None,
                    stopping_time: None,
                    paper_stopping_time: None,
                    relative_difference: None,
                    peak_tension: None,
                    peak_joint: None,
                    peak_time: None,
                    break_exceedances: 0,
                    anchor_start: None,
                    energy_drift: None,
                    wall_time: 0.0,
                    stop_error_estimate: None,
                    trajectory_error_estimate: None,
                    message: one_line(&message),
                },
            };
            done(&row);
            row
        })
        .collect()
}

/// A message on one line: its lines, trimmed, joined by " | ".
fn one_line(text: &str) -> String {
    text.lines().map(str::trim).filter(|l| !l.is_empty()).collect::<Vec<_>>().join(" | ")
}

fn opt(v: Option<f64>, scale: f64, digits: usize) -> String {
    v.map(|v| format!("{:.*}", digits, v * scale)).unwrap_or_else(|| "—".into())
}

/// The rows as a terminal table.
pub fn table(rows: &[BatchRow]) -> String {
    let estimates = rows.iter().any(|r| r.stop_error_estimate.is_some() || r.trajectory_error_estimate.is_some());
    let mut out = format!(
        "{:<15} {:>3} {:<6} {:<9} {:>9} {:>9} {:>8} {:>11} {:>6} {:>8} {:>9} {:>8}",
        "case",
        "N",
        "method",
        "status",
        "stop (s)",
        "paper (s)",
        "diff %",
        "peak (kN)",
        "joint",
        "anchor s",
        "drift",
        "wall (s)"
    );
    if estimates {
        out.push_str(&format!(" {:>9} {:>9}", "±stop s", "±traj m"));
    }
    out.push('\n');
    let e = |v: Option<f64>| v.map(|v| format!("{v:.1e}")).unwrap_or_else(|| "—".into());
    for r in rows {
        out.push_str(&format!(
            "{:<15} {:>3} {:<6} {:<9} {:>9} {:>9} {:>8} {:>11} {:>6} {:>8} {:>9} {:>8.2}",
            r.case,
            r.bodies.map(|n| n.to_string()).unwrap_or_default(),
            r.method,
            r.status,
            opt(r.stopping_time, 1.0, 3),
            opt(r.paper_stopping_time, 1.0, 3),
            opt(r.relative_difference, 100.0, 2),
            opt(r.peak_tension, 1e-3, 1),
            r.peak_joint.map(|k| k.to_string()).unwrap_or_default(),
            opt(r.anchor_start, 1.0, 3),
            r.energy_drift.map(|d| format!("{d:.1e}")).unwrap_or_default(),
            r.wall_time
        ));
        if estimates {
            out.push_str(&format!(" {:>9} {:>9}", e(r.stop_error_estimate), e(r.trajectory_error_estimate)));
        }
        out.push('\n');
        if !r.message.is_empty() {
            out.push_str(&format!("           {}\n", r.message));
        }
    }
    out
}

/// The rows as CSV.
pub fn csv(rows: &[BatchRow]) -> String {
    let mut out = String::from(
        "case,file,status,bodies,stopping_time,paper_stopping_time,relative_difference,peak_tension,peak_joint,peak_time,break_exceedances,anchor_start,energy_drift,wall_time,message,method,stop_error_estimate,trajectory_error_estimate\n",
    );
    let o = |v: Option<f64>| v.map(|v| format!("{v}")).unwrap_or_default();
    for r in rows {
        out.push_str(&format!(
            "{},{},{},{},{},{},{},{},{},{},{},{},{},{},\"{}\",{},{},{}\n",
            r.case,
            r.file,
            r.status,
            r.bodies.map(|n| n.to_string()).unwrap_or_default(),
            o(r.stopping_time),
            o(r.paper_stopping_time),
            o(r.relative_difference),
            o(r.peak_tension),
            r.peak_joint.map(|k| k.to_string()).unwrap_or_default(),
            o(r.peak_time),
            r.break_exceedances,
            o(r.anchor_start),
            o(r.energy_drift),
            r.wall_time,
            r.message.replace('"', "'"),
            r.method,
            o(r.stop_error_estimate),
            o(r.trajectory_error_estimate),
        ));
    }
    out
}

/// Writes `batch.csv` and `batch.json` into `dir` (created if needed), each whole or not at all.
pub fn write(rows: &[BatchRow], dir: &Path) -> std::io::Result<(PathBuf, PathBuf)> {
    std::fs::create_dir_all(dir)?;
    let (c, j) = (dir.join("batch.csv"), dir.join("batch.json"));
    write_atomically(&c, csv(rows).as_bytes())?;
    let json = serde_json::to_string_pretty(rows).map_err(std::io::Error::other)?;
    write_atomically(&j, json.as_bytes())?;
    Ok((c, j))
}

/// What a validation against Table 3 found.
#[derive(Clone, Debug, PartialEq)]
pub struct Validation {
    /// Rows that failed a check, with the reason.
    pub problems: Vec<String>,
    /// Kendall's τ between the simulated and the paper's stopping times (1: same order).
    pub kendall_tau: Option<f64>,
    /// Pairs of cases the simulation orders differently from Table 3.
    pub discordant: Vec<(String, String)>,
}

/// Checks rows against the paper: stopping time within `tolerance` (relative) of Table 3,
/// energy drift below 0.5 %, no break load exceeded, no failed run; and compares the order
/// of the cases by stopping time with Table 3's.
pub fn validate(rows: &[BatchRow], tolerance: f64) -> Validation {
    let mut problems = Vec::new();
    for r in rows {
        if r.status != "stopped" {
            problems.push(format!("{}: {} {}", r.case, r.status, r.message));
            continue;
        }
        if let Some(d) = r.relative_difference.filter(|d| d.abs() > tolerance) {
            problems.push(format!("{}: stopping time differs from Table 3 by {:+.2} %", r.case, 100.0 * d));
        }
        if let Some(e) = r.energy_drift.filter(|&e| e > 0.005) {
            problems.push(format!("{}: energy balance drift {e:.2e} > 0.5 %", r.case));
        }
        if r.break_exceedances > 0 {
            problems.push(format!("{}: break load exceeded at {} joint(s)", r.case, r.break_exceedances));
        }
    }
    let paired: Vec<(&BatchRow, f64, f64)> =
        rows.iter().filter_map(|r| Some((r, r.stopping_time?, r.paper_stopping_time?))).collect();
    let (mut concordant, mut discordant) = (0usize, Vec::new());
    for i in 0..paired.len() {
        for j in i + 1..paired.len() {
            let (a, b) = (&paired[i], &paired[j]);
            if (a.1 - b.1) * (a.2 - b.2) > 0.0 {
                concordant += 1;
            } else {
                discordant.push((a.0.case.clone(), b.0.case.clone()));
            }
        }
    }
    let pairs = concordant + discordant.len();
    let kendall_tau = (pairs > 0).then(|| (concordant as f64 - discordant.len() as f64) / pairs as f64);
    Validation { problems, kendall_tau, discordant }
}

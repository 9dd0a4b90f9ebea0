//! Many scenes at once: every scene of a folder run in parallel ([`crate::parallel`]), one
//! result row each, written as a terminal table, CSV and JSON. On request each run is repeated with a
//! refined setting ([`refined`]: dt/2, adaptive methods also rtol and atol/10) and the
//! differences are its error estimates (stopping time, trajectory, peak tension).

use std::path::{Path, PathBuf};

use kanestop_runtime::model::Model;
use kanestop_runtime::scene::{Method, Scene};
use kanestop_runtime::simulate::{self, RunResult, Stop};
use serde::{Deserialize, Serialize};

use crate::checks::{self, break_exceedances};
use crate::kernels::KernelFactory;
use crate::output::{self, csv_field, csv_quoted, CsvNumber};
use crate::{diagnostic, parallel, Result};

/// How a row's run ended.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
pub enum Status {
    /// The ship stopped.
    #[serde(rename = "stopped")]
    Stopped,
    /// The end time came first.
    #[serde(rename = "end time")]
    EndTime,
    /// A numerical failure, or a step refused before the run.
    #[serde(rename = "failed")]
    Failed,
    /// The scene did not load or admits no model.
    #[serde(rename = "invalid")]
    Invalid,
}

impl Status {
    /// The name every output uses: `stopped`, `end time`, `failed` or `invalid`.
    pub fn name(self) -> &'static str {
        match self {
            Status::Stopped => "stopped",
            Status::EndTime => "end time",
            Status::Failed => "failed",
            Status::Invalid => "invalid",
        }
    }

    /// The status of a finished run.
    pub fn of(stop: &Stop) -> Status {
        match stop {
            Stop::ShipStopped => Status::Stopped,
            Stop::EndTime => Status::EndTime,
            Stop::Failed(_) => Status::Failed,
        }
    }

    /// True when the run or the scene went wrong.
    pub fn is_problem(self) -> bool {
        matches!(self, Status::Failed | Status::Invalid)
    }
}

impl std::fmt::Display for Status {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(self.name())
    }
}

/// One scene's outcome.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct BatchRow {
    /// Scene name (`meta.name`), or the file name when the scene did not load.
    pub case: String,
    /// The scene file.
    pub file: String,
    /// How the run ended.
    pub status: Status,
    /// The integrator (none when the scene did not load).
    #[serde(with = "method_or_empty")]
    pub method: Option<Method>,
    /// Number of bodies.
    pub bodies: Option<usize>,
    /// RK4's step, or the adaptive methods' observation interval, s (none when the scene did
    /// not load).
    #[serde(default)]
    pub dt: Option<f64>,
    /// The adaptive methods' relative tolerance (none for RK4, which takes a fixed step).
    #[serde(default)]
    pub rtol: Option<f64>,
    /// The adaptive methods' absolute tolerance, in the state's units (none for RK4).
    #[serde(default)]
    pub atol: Option<f64>,
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
    /// The ship's surge displacement when it stopped, m (none when it did not stop). Added
    /// 2026-12-07, as `run --json` and `sweep.csv` have it.
    #[serde(default)]
    pub stopping_distance: Option<f64>,
    /// The anchor's drag distance at the end of the run, m (none for a scene that did not
    /// run). Added 2026-12-07.
    #[serde(default)]
    pub anchor_drag_distance: Option<f64>,
    /// The peak tension over its joint's break load (none where that joint has none, or
    /// the run has no peak). Added 2026-12-07.
    #[serde(default)]
    pub peak_break_utilisation: Option<f64>,
    /// Largest relative drift of the energy balance.
    pub energy_drift: Option<f64>,
    /// Wall-clock time of the run, s.
    pub wall_time: f64,
    /// CPU time of the run on its own thread, s (none where the platform does not say, or
    /// for a scene that did not run): the cost to judge by on a shared machine.
    #[serde(default)]
    pub cpu_time: Option<f64>,
    /// Right-hand-side evaluations of the run (none for a scene that did not load).
    #[serde(default)]
    pub rhs_evaluations: Option<u64>,
    /// Whether every design check passed: the break loads, which every run that took a step
    /// and did not fail is held to, and the scene's `[checks]` ([`checks::verdict`]; none when
    /// no check was made: no `[checks]`, and a scene that did not load or a run refused or
    /// failed with no break load exceeded); a failed check is named in `message`.
    #[serde(default)]
    pub checks_pass: Option<bool>,
    /// |t_stop − t_stop,refined|, s: the stopping time's error estimate (with
    /// `estimate`, when both runs stopped the ship).
    pub stop_error_estimate: Option<f64>,
    /// Largest centroid position difference from the refined run at the common output
    /// times, m (with `estimate`, when neither run failed).
    pub trajectory_error_estimate: Option<f64>,
    /// |peak tension − the refined run's|, N: the peak's error estimate (with `estimate`,
    /// when neither run failed). A snap load shorter than the method's steps shows here.
    #[serde(default)]
    pub peak_error_estimate: Option<f64>,
    /// Error or diagnostic, if any.
    pub message: String,
}

/// The scene files `batch` runs: each path a scene file, or a folder whose `*.toml` files
/// (sorted by name) it stands for; in the order given. A path that does not exist, a folder
/// without a scene, or a file given twice (directly or through its folder) is an error
/// naming it.
pub fn scene_files_of(paths: &[PathBuf]) -> Result<Vec<PathBuf>> {
    let bad = |path: &Path, expected: &str| crate::Error::Argument {
        name: "SCENES",
        value: path.display().to_string(),
        expected: expected.to_string(),
    };
    let mut files: Vec<PathBuf> = Vec::new();
    let mut seen = std::collections::HashSet::new();
    for path in paths {
        let these = if path.is_dir() {
            let found =
                scene_files(path).map_err(|cause| crate::Error::Io { action: "read", path: path.clone(), cause })?;
            if found.is_empty() {
                return Err(bad(path, "a folder without a *.toml scene"));
            }
            found
        } else if path.is_file() {
            vec![path.clone()]
        } else {
            return Err(bad(path, "no such file or folder (a scene file, or a folder of them)"));
        };
        for f in these {
            if !seen.insert(f.canonicalize().unwrap_or_else(|_| f.clone())) {
                return Err(bad(&f, "given twice (directly or through its folder): each scene once"));
            }
            files.push(f);
        }
    }
    Ok(files)
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
    let paper = kanestop_runtime::paper::stopping_time(&model.scene);
    // A run that did not get past its start has no peak to report; one refused before its
    // first step no drift either (as `run --json`).
    let ran = result.ran();
    let peak = result.peak_tension().filter(|_| ran);
    let outcomes = model.scene.checks.as_ref().map(|c| checks::evaluate(c, model, result)).unwrap_or_default();
    // The break-load check applies to every scene, `[checks]` or not (as in `run`).
    let over = break_exceedances(model, result);
    let failures = checks::failures_of(model.scene.checks.as_ref(), &outcomes, &over);
    let message = match &result.stop {
        Stop::Failed(f) => one_line(&diagnostic::describe(model, f)),
        Stop::ShipStopped | Stop::EndTime if !failures.is_empty() => {
            format!("check failed: {}", failures.join("; "))
        }
        Stop::ShipStopped | Stop::EndTime => String::new(),
    };
    let adaptive = model.scene.solver.integrator != Method::Rk4;
    BatchRow {
        case: model.scene.meta.name.clone(),
        file: file.display().to_string(),
        status: Status::of(&result.stop),
        method: Some(model.scene.solver.integrator),
        bodies: Some(model.body_count()),
        dt: Some(model.scene.solver.dt),
        rtol: adaptive.then_some(model.scene.solver.rtol),
        atol: adaptive.then_some(model.scene.solver.atol),
        stopping_time: result.stopping_time,
        paper_stopping_time: paper,
        relative_difference: result.stopping_time.zip(paper).map(|(t, p)| (t - p) / p),
        peak_tension: peak.map(|p| p.1.tension),
        peak_joint: peak.map(|p| p.0),
        peak_time: peak.map(|p| p.1.t),
        break_exceedances: over.len(),
        anchor_start: result.anchor_start(),
        stopping_distance: result.stopping_distance,
        anchor_drag_distance: result.observed().then(|| result.displacement(0)),
        peak_break_utilisation: peak.and_then(|(k, p)| model.joint_limits(k).breaking.map(|b| p.tension / b)),
        energy_drift: result.observed().then_some(result.max_energy_drift),
        wall_time: result.wall_time.as_secs_f64(),
        cpu_time: result.cpu_time.map(|d| d.as_secs_f64()),
        rhs_evaluations: Some(result.rhs_evaluations),
        checks_pass: checks::verdict(&outcomes, &over, checks::break_loads_held(model, result)),
        stop_error_estimate: None,
        trajectory_error_estimate: None,
        peak_error_estimate: None,
        message,
    }
}

/// The same scene integrated more accurately and observed twice as often, on the same
/// output times: RK4 at dt/2; an adaptive method at a tenth of its tolerances and half its
/// observation interval dt (where the anchor's events and the checks are looked at, and its
/// longest step; the peak tensions are looked at after every step of either method).
///
/// The output interval becomes the coarse run's own (a whole number of its steps, as the
/// stepper rounds it), so that every output time of the coarse run is one of the refined
/// run's and the trajectories are compared at all of them.
pub fn refined(scene: &Scene) -> Scene {
    let mut s = scene.clone();
    let stride = (s.solver.output_interval / s.solver.dt).round().max(1.0);
    s.solver.output_interval = stride * s.solver.dt;
    s.solver.dt /= 2.0;
    if s.solver.integrator != Method::Rk4 {
        s.solver.rtol /= 10.0;
        s.solver.atol /= 10.0;
    }
    s
}

/// Fills the error estimates of `row` (of `result`) from the refined run `fine` of
/// `fine_model`; where the design checks' verdict of the two runs differs, says so in the
/// message: the verdict is not resolved at this step or tolerance.
fn estimate(row: &mut BatchRow, result: &RunResult, fine_model: &Model, fine: &RunResult) {
    let failed = |r: &RunResult| matches!(r.stop, Stop::Failed(_));
    if failed(result) || failed(fine) {
        return;
    }
    row.stop_error_estimate = result.stopping_time.zip(fine.stopping_time).map(|(a, b)| (a - b).abs());
    row.trajectory_error_estimate = Some(simulate::trajectory_difference(result, fine));
    let peak = |r: &RunResult| r.peak_tension().map(|(_, p)| p.tension);
    row.peak_error_estimate = peak(result).zip(peak(fine)).map(|(a, b)| (a - b).abs());
    let (coarse, refined) = (row.checks_pass.unwrap_or(true), checks::verdict_of(fine_model, fine).unwrap_or(true));
    if coarse != refined {
        let word = |pass: bool| if pass { "pass" } else { "fail" };
        let note = format!(
            "the checks {} here but {} in the refined run (peak {:.0} against {:.0} kN): not resolved at this step or tolerance",
            word(coarse),
            word(refined),
            peak(result).unwrap_or(0.0) / 1e3,
            peak(fine).unwrap_or(0.0) / 1e3
        );
        append(&mut row.message, &note);
    }
}

/// Appends `note` to a row's message, after "; " when it has one.
fn append(message: &mut String, note: &str) {
    if !message.is_empty() {
        message.push_str("; ");
    }
    message.push_str(note);
}

/// Edits a scene file's tables before the scene is checked (command-line solver overrides,
/// laid on the file so that they can mend it, as `run` lays them: [`Scene::load_edited`]);
/// an error of the edited scene marks it invalid.
pub type Configure<'a> = &'a (dyn Fn(&mut toml::Value) + Sync);

/// Runs every file in parallel; `configure` edits each file's tables before its scene is
/// checked, `kernel` builds each run's kernel and `done` is called (from any thread) as each
/// run finishes; with `error_estimate` each run is repeated [`refined`] to estimate its
/// error. Rows come back in file order.
pub fn run_all(
    files: &[PathBuf],
    configure: Configure,
    kernel: KernelFactory,
    error_estimate: bool,
    done: &(dyn Fn(&BatchRow) + Sync),
) -> Vec<BatchRow> {
    parallel::map(files, |file| {
        let model = Scene::load_edited(file, configure)
            .map_err(|e| e.to_string())
            .and_then(|s| Model::new(&s).map_err(|e| e.to_string()));
        let row = match model {
            Ok(model) => {
                let result = simulate::run_checked(&model, kernel(&model), kernel(&model));
                let mut row = row(file, &model, &result);
                if error_estimate {
                    // The refined scene is checked as a scene (its dt/2 may pass the step
                    // count's limit).
                    let fine = refined(&model.scene);
                    let problems: Vec<String> = fine.problems().iter().map(|p| p.to_string()).collect();
                    let fine = if problems.is_empty() {
                        Model::new(&fine).map_err(|e| e.to_string())
                    } else {
                        Err(format!("the refined scene is invalid: {}", problems.join("; ")))
                    };
                    match fine {
                        Ok(fine) => estimate(&mut row, &result, &fine, &simulate::run(&fine, kernel(&fine))),
                        Err(e) => append(&mut row.message, &one_line(&format!("no error estimate: {e}"))),
                    }
                }
                row
            }
            Err(message) => BatchRow {
                case: file.file_stem().map(|s| s.to_string_lossy().into_owned()).unwrap_or_default(),
                file: file.display().to_string(),
                status: Status::Invalid,
                method: None,
                bodies: None,
                dt: None,
                rtol: None,
                atol: None,
                stopping_time: None,
                paper_stopping_time: None,
                relative_difference: None,
                peak_tension: None,
                peak_joint: None,
                peak_time: None,
                break_exceedances: 0,
                anchor_start: None,
                stopping_distance: None,
                anchor_drag_distance: None,
                peak_break_utilisation: None,
                energy_drift: None,
                wall_time: 0.0,
                cpu_time: None,
                rhs_evaluations: None,
                checks_pass: None,
                stop_error_estimate: None,
                trajectory_error_estimate: None,
                peak_error_estimate: None,
                message: one_line(&message),
            },
        };
        done(&row);
        row
    })
}

/// A message on one line: its lines, trimmed, joined by " | ".
fn one_line(text: &str) -> String {
    text.lines().map(str::trim).filter(|l| !l.is_empty()).collect::<Vec<_>>().join(" | ")
}

fn opt(v: Option<f64>, scale: f64, digits: usize) -> String {
    v.map(|v| format!("{:.*}", digits, v * scale)).unwrap_or_else(|| "—".into())
}

/// A row's checks as the table and the CSV write them: `pass`, `fail`, or empty (none).
fn checks_word(pass: Option<bool>) -> &'static str {
    match pass {
        Some(true) => "pass",
        Some(false) => "fail",
        None => "",
    }
}

/// A method at a step, as `--methods` takes it and the table names it: `rk4@0.01`.
pub fn method_at(method: Method, dt: f64) -> String {
    format!("{}@{dt}", method.name())
}

/// Each row's method as the table and the validation name it: its name, and `@dt` where the
/// batch ran a file by that method more than once (`--methods rk4@0.01,rk4@0.005`), or ""
/// when the scene did not load. The validation orders rows of one label against each other.
pub fn method_labels(rows: &[BatchRow]) -> Vec<String> {
    let mut runs = std::collections::HashMap::new();
    for r in rows {
        if let Some(m) = r.method {
            *runs.entry((r.file.as_str(), m.name())).or_insert(0usize) += 1;
        }
    }
    let twice: Vec<&str> = runs.iter().filter(|(_, &n)| n > 1).map(|(&(_, m), _)| m).collect();
    rows.iter()
        .map(|r| {
            let name = r.method.map(Method::name).unwrap_or_default();
            match (r.method, r.dt.filter(|_| twice.contains(&name))) {
                (Some(m), Some(dt)) => method_at(m, dt),
                _ => name.to_string(),
            }
        })
        .collect()
}

/// Each row's name in the terminal table: its `case`, and where another row of the same
/// method label ([`method_labels`]) has the same (edited copies of one scene keep its
/// `meta.name`), its file's name too, or its whole path where the file names are alike as
/// well. Rows of one scene by several `--methods` are told apart by their method column.
fn case_labels(rows: &[BatchRow]) -> Vec<String> {
    let file_name = |r: &BatchRow| {
        Path::new(&r.file).file_name().map_or_else(|| r.file.clone(), |n| n.to_string_lossy().into_owned())
    };
    let methods = method_labels(rows);
    let shared = |key: &dyn Fn(usize) -> String, i: usize| (0..rows.len()).filter(|&o| key(o) == key(i)).count() > 1;
    (0..rows.len())
        .map(|i| {
            let r = &rows[i];
            if !shared(&|o| format!("{}\n{}", rows[o].case, methods[o]), i) {
                r.case.clone()
            } else if !shared(&|o| format!("{}\n{}\n{}", rows[o].case, methods[o], file_name(&rows[o])), i) {
                format!("{} ({})", r.case, file_name(r))
            } else {
                format!("{} ({})", r.case, r.file)
            }
        })
        .collect()
}

/// The rows as a terminal table.
pub fn table(rows: &[BatchRow]) -> String {
    let estimates = rows.iter().any(|r| {
        r.stop_error_estimate.is_some() || r.trajectory_error_estimate.is_some() || r.peak_error_estimate.is_some()
    });
    let labels = case_labels(rows);
    let methods = method_labels(rows);
    let width = labels.iter().map(|l| l.chars().count()).fold(15, usize::max);
    let m_width = methods.iter().map(|l| l.chars().count()).fold(6, usize::max);
    let mut out = format!(
        "{:<width$} {:>3} {:<m_width$} {:<9} {:>6} {:>9} {:>9} {:>8} {:>11} {:>6} {:>9} {:>9} {:>8} {:>9} {:>8}",
        "case",
        "N",
        "method",
        "status",
        "checks",
        "stop (s)",
        "paper (s)",
        "diff %",
        "peak (kN)",
        "joint",
        "slide (s)",
        "drift",
        "cpu (s)",
        "evals",
        "wall (s)"
    );
    if estimates {
        out.push_str(&format!(" {:>9} {:>9} {:>9}", "±stop s", "±traj m", "±peak kN"));
    }
    out.push('\n');
    let e = |v: Option<f64>| v.map(|v| format!("{v:.1e}")).unwrap_or_else(|| "—".into());
    for ((r, label), method) in rows.iter().zip(&labels).zip(&methods) {
        out.push_str(&format!(
            "{:<width$} {:>3} {:<m_width$} {:<9} {:>6} {:>9} {:>9} {:>8} {:>11} {:>6} {:>9} {:>9} {:>8} {:>9} {:>8.2}",
            label,
            r.bodies.map(|n| n.to_string()).unwrap_or_default(),
            method,
            r.status.name(),
            r.checks_pass.map_or("—", |p| checks_word(Some(p))),
            opt(r.stopping_time, 1.0, 3),
            opt(r.paper_stopping_time, 1.0, 3),
            opt(r.relative_difference, 100.0, 2),
            opt(r.peak_tension, 1e-3, 1),
            r.peak_joint.map(|k| k.to_string()).unwrap_or_default(),
            opt(r.anchor_start, 1.0, 3),
            r.energy_drift.map(|d| format!("{d:.1e}")).unwrap_or_default(),
            opt(r.cpu_time, 1.0, 2),
            r.rhs_evaluations.map(|n| n.to_string()).unwrap_or_default(),
            r.wall_time
        ));
        if estimates {
            let peak = r.peak_error_estimate.map(|v| format!("{:.1}", v / 1e3)).unwrap_or_else(|| "—".into());
            out.push_str(&format!(
                " {:>9} {:>9} {:>9}",
                e(r.stop_error_estimate),
                e(r.trajectory_error_estimate),
                peak
            ));
        }
        out.push('\n');
        if !r.message.is_empty() {
            out.push_str(&format!("           {}\n", r.message));
        }
    }
    out
}

/// What a run's `energy_drift` is, in the units files of `batch` and `sweep` alike.
pub const ENERGY_DRIFT_MEANING: &str =
    "largest energy-balance drift |E - E_0|/K, K the largest kinetic energy so far, \
                                        the entrained water's included (a fraction)";

/// The columns of `batch.csv` in order, each with its unit ("" for a number without one, a
/// count or text) and what it holds: the header and the units sidecar, `batch.units.csv`.
pub const COLUMNS: [(&str, &str, &str); 28] = [
    ("case", "", "scene name (meta.name), or the file name when the scene did not load"),
    ("file", "", "the scene file"),
    ("status", "", "how the run ended: stopped, end time, failed, invalid"),
    ("bodies", "", "number of bodies N"),
    ("stopping_time", "s", "first zero of the ship's surge speed"),
    ("paper_stopping_time", "s", "Table 3's stopping time (paper cases)"),
    ("relative_difference", "", "(stopping_time - paper_stopping_time) / paper_stopping_time (a fraction)"),
    ("peak_tension", "N", "largest joint tension"),
    ("peak_joint", "", "the joint k (between bodies k-1 and k) of the largest tension"),
    ("peak_time", "s", "when the largest tension occurred"),
    ("break_exceedances", "", "joints whose peak tension exceeded their break load"),
    ("anchor_start", "s", "when the anchor first slid"),
    ("energy_drift", "", ENERGY_DRIFT_MEANING),
    ("wall_time", "s", "wall-clock time of the run"),
    ("message", "", "error, diagnostic or failed check"),
    ("method", "", "integrator: rk4, dp5, sdirk4"),
    ("stop_error_estimate", "s", "|stopping time - the refined run's| (--error-estimate)"),
    ("trajectory_error_estimate", "m", "largest centroid position difference from the refined run (--error-estimate)"),
    ("checks", "", "design checks (break loads and [checks]): pass, fail, empty when none was made"),
    ("cpu_time", "s", "CPU time of the run on its own thread"),
    ("rhs_evaluations", "", "right-hand-side evaluations"),
    ("peak_error_estimate", "N", "|peak tension - the refined run's| (--error-estimate)"),
    ("dt", "s", "rk4's step, or the adaptive methods' observation interval"),
    ("rtol", "", "the adaptive methods' relative tolerance (empty for rk4)"),
    ("atol", "", "the adaptive methods' absolute tolerance, in the state's units (empty for rk4)"),
    ("stopping_distance", "m", "ship's surge displacement when it stopped"),
    ("anchor_drag_distance", "m", "anchor's drag distance at the end of the run"),
    ("peak_break_utilisation", "", "peak_tension over its joint's break load (a fraction)"),
];

/// The rows as CSV, the columns of [`COLUMNS`].
pub fn csv(rows: &[BatchRow]) -> String {
    let mut out = COLUMNS.map(|c| c.0).join(",");
    out.push('\n');
    let o = |v: Option<f64>| v.map(|v| CsvNumber(v).to_string()).unwrap_or_default();
    for r in rows {
        out.push_str(&format!(
            "{},{},{},{},{},{},{},{},{},{},{},{},{},{},{},{},{},{},{},{},{},{},{},{},{},{},{},{}\n",
            csv_field(&r.case),
            csv_field(&r.file),
            r.status.name(),
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
            csv_quoted(&r.message),
            r.method.map(Method::name).unwrap_or_default(),
            o(r.stop_error_estimate),
            o(r.trajectory_error_estimate),
            checks_word(r.checks_pass),
            o(r.cpu_time),
            r.rhs_evaluations.map(|n| n.to_string()).unwrap_or_default(),
            o(r.peak_error_estimate),
            o(r.dt),
            o(r.rtol),
            o(r.atol),
            o(r.stopping_distance),
            o(r.anchor_drag_distance),
            o(r.peak_break_utilisation),
        ));
    }
    out
}

/// The files [`write()`] writes into its folder.
pub const FILES: [&str; 3] = ["batch.csv", "batch.json", "batch.units.csv"];

/// Writes `batch.csv`, `batch.json` and `batch.units.csv` into `dir` (created if needed), each
/// whole or not at all. Returns the three files.
pub fn write(rows: &[BatchRow], dir: &Path) -> Result<[PathBuf; 3]> {
    let json = serde_json::to_string_pretty(rows).expect("rows serialise: plain numbers and strings");
    output::write_into(dir, FILES, [csv(rows), json, output::units_csv(COLUMNS)])
}

/// A row's method as its name, or "" when the scene did not load (the JSON contract).
mod method_or_empty {
    use kanestop_runtime::scene::Method;
    use serde::{Deserialize, Deserializer, Serializer};

    pub fn serialize<S: Serializer>(method: &Option<Method>, s: S) -> Result<S::Ok, S::Error> {
        s.serialize_str(method.map(Method::name).unwrap_or_default())
    }

    pub fn deserialize<'de, D: Deserializer<'de>>(d: D) -> Result<Option<Method>, D::Error> {
        let name = String::deserialize(d)?;
        if name.is_empty() {
            Ok(None)
        } else {
            name.parse().map(Some).map_err(serde::de::Error::custom)
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use kanestop_runtime::generated::GeneratedKernel;
    use kanestop_runtime::paper::DEFAULT_SCENE;

    /// Case 1's model and its run to `end_time`, s.
    fn case1_run(end_time: f64) -> (Model, RunResult) {
        let mut scene = Scene::from_toml(DEFAULT_SCENE, "case01.toml").unwrap();
        scene.solver.end_time = end_time;
        let model = Model::new(&scene).unwrap();
        let result = simulate::run(&model, Box::new(GeneratedKernel::new(&model.chain).unwrap()));
        (model, result)
    }

    #[test]
    fn rows_of_one_scene_name_are_told_apart_by_their_files() {
        let (model, result) = case1_run(0.01);
        let rows: Vec<BatchRow> = ["a/case01.toml", "a/heavy.toml", "b/heavy.toml"]
            .iter()
            .map(|f| row(Path::new(f), &model, &result))
            .collect();
        assert_eq!(case_labels(&rows), ["case01 (case01.toml)", "case01 (a/heavy.toml)", "case01 (b/heavy.toml)"]);
        assert_eq!(case_labels(&rows[..1]), ["case01"]);
        // One file by two methods: the method column tells them apart.
        let mut by_dp5 = rows[0].clone();
        by_dp5.method = Some(Method::Dp5);
        assert_eq!(case_labels(&[rows[0].clone(), by_dp5.clone()]), ["case01", "case01"]);
        // One file by one method at two steps: the method column says the step, for every
        // row of that method (`--methods rk4@0.002,rk4@0.001,dp5`).
        let finer = BatchRow { dt: Some(0.001), ..rows[0].clone() };
        let other = BatchRow { file: "b.toml".into(), case: "b".into(), ..rows[0].clone() };
        let both = [rows[0].clone(), finer, by_dp5, other];
        assert_eq!(method_labels(&both), ["rk4@0.002", "rk4@0.001", "dp5", "rk4@0.002"]);
        assert_eq!(case_labels(&both), ["case01", "case01", "case01", "b"]);
        // The column widens to the longest name, and the rows stay aligned.
        let text = table(&rows);
        let lines: Vec<&str> = text.lines().collect();
        assert!(lines[0].starts_with(&format!("{:<21} ", "case")), "{text}");
        assert!(lines[3].starts_with("case01 (b/heavy.toml)  46 rk4"), "{text}");
        // A name or file with a comma or a quote is one CSV field (RFC 4180), as is a message
        // with quotes (they were unquoted, and shifted the row's columns).
        let named = BatchRow {
            case: "case 1, heavy \"ship\"".into(),
            file: "a,b.toml".into(),
            message: "use integrator = \"dp5\"".into(),
            ..rows[0].clone()
        };
        let text = csv(&[named]);
        let line = text.lines().nth(1).unwrap();
        assert!(line.starts_with("\"case 1, heavy \"\"ship\"\"\",\"a,b.toml\",end time,"), "{line}");
        assert!(line.contains(",\"use integrator = \"\"dp5\"\"\",rk4,"), "{line}");
    }

    #[test]
    fn a_verdict_that_differs_in_the_refined_run_is_said_to_be_unresolved() {
        let (model, coarse) = case1_run(0.05);
        let mut row = row(Path::new("case01.toml"), &model, &coarse);
        // No [checks]: the break loads' check, which every scene has, passed.
        assert_eq!(row.checks_pass, Some(true));
        // The refined run's peak at the fairlead above the cable's break load (2 520 kN).
        let mut fine = coarse.clone();
        let last = fine.peak_tensions.len() - 1;
        fine.peak_tensions[last].tension = 3.0e6;
        estimate(&mut row, &coarse, &model, &fine);
        let (a, b) = (coarse.peak_tension().unwrap().1.tension, 3.0e6);
        assert_eq!(row.peak_error_estimate, Some((a - b).abs()));
        assert!(
            row.message.ends_with(&format!(
                "the checks pass here but fail in the refined run (peak {:.0} against 3000 kN): not resolved at this step or tolerance",
                a / 1e3
            )),
            "{}",
            row.message
        );
        // The same verdict: nothing said.
        let mut same = super::row(Path::new("case01.toml"), &model, &coarse);
        estimate(&mut same, &coarse, &model, &coarse);
        assert_eq!((same.message.as_str(), same.peak_error_estimate), ("", Some(0.0)));
    }
}

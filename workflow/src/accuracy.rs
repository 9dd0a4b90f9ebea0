//! Error against run time: a work–precision study of the integrators on one scene.
//!
//! The reference solution is the tightest run (Dormand–Prince at rtol = 1e-10); its own
//! error is estimated against a run at rtol = 1e-9. Each method is then run over a range of
//! step sizes (RK4) or tolerances (DP5, SDIRK4), and every run is compared with the
//! reference: stopping time, final ship and anchor displacement, peak tension, and the
//! largest position error of any body at the common output times (the trajectory error).
//! Costs are medians of repeated runs: each run's CPU time on its own thread (what the
//! verdicts judge by: on a shared machine wall time counts the waits for a core) beside
//! its wall time, and the right-hand-side evaluations. Where the platform gives no CPU time
//! the verdicts fall back to wall time.
//!
//! The anchor's sliding friction takes the normal force implicitly (docs/model-choices.md),
//! so every method integrates the same equations whatever its step or observation interval,
//! and the errors below are integration errors.

use std::path::{Path, PathBuf};

use kanestop_runtime::kernel::Kernel;
use kanestop_runtime::model::Model;
use kanestop_runtime::scene::{fmt_value, Method, Scene, MIN_ATOL};
use kanestop_runtime::simulate::{self, FailureKind, RunResult, Stop};
use serde::{Deserialize, Serialize};

use crate::output::units_csv;
use crate::plot::{log_log, LogCurve, LogPanel};
use crate::{Error, Result};

/// One run of the study.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct AccuracyRow {
    /// The integrator.
    pub method: Method,
    /// dt (s) for RK4, rtol for the adaptive methods.
    pub setting: f64,
    /// "stopped", or why not.
    pub status: String,
    /// |t_stop − t_stop,ref|, s.
    pub stopping_time_error: Option<f64>,
    /// |Δx_ship − Δx_ship,ref| at the stop, m.
    pub ship_displacement_error: Option<f64>,
    /// |Δx_anchor − Δx_anchor,ref| at the stop, m.
    pub anchor_displacement_error: Option<f64>,
    /// |peak − peak_ref| / peak_ref of the largest joint tension.
    pub peak_tension_error: Option<f64>,
    /// Largest |position − reference| of any body's centroid at the common output times, m.
    pub trajectory_error: Option<f64>,
    /// Median wall time, s.
    pub wall_time: f64,
    /// Median CPU time of the run's thread, s (none where the platform does not say).
    #[serde(default)]
    pub cpu_time: Option<f64>,
    /// Right-hand-side evaluations.
    pub rhs_evaluations: u64,
    /// On the work–precision front of the study: no other run has both a smaller
    /// stopping-time error and a smaller [`AccuracyRow::cost`].
    pub best: bool,
}

impl AccuracyRow {
    /// What the verdicts judge by, s: the CPU time, or the wall time where there is none.
    pub fn cost(&self) -> f64 {
        self.cpu_time.unwrap_or(self.wall_time)
    }
}

/// The whole study.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct AccuracyStudy {
    /// The scene's name.
    pub scene: String,
    /// Stopping time of the reference solution, s.
    pub reference_stopping_time: f64,
    /// Its estimated error: difference with the next-tightest run, s.
    pub reference_error: f64,
    /// Its estimated trajectory error, m.
    pub reference_trajectory_error: f64,
    /// The adaptive runs' absolute tolerance as a multiple of their rtol.
    pub atol_ratio: f64,
    /// One row per setting of the plan, in its order.
    pub rows: Vec<AccuracyRow>,
}

/// The adaptive runs' atol / rtol unless told otherwise: the ratio of the scenes' default
/// tolerances (rtol 1e-6, atol 1e-8).
pub const DEFAULT_ATOL_RATIO: f64 = 1e-2;

fn configured(base: &Scene, method: Method, dt: f64, rtol: f64, atol_ratio: f64) -> Scene {
    let mut s = base.clone();
    s.solver.integrator = method;
    s.solver.dt = dt;
    s.solver.rtol = rtol;
    s.solver.atol = rtol * atol_ratio;
    // A common output grid for every run: 0.04 s is a multiple of every dt used.
    s.solver.output_interval = 0.04;
    s.solver.stop_when_ship_stops = true;
    s
}

/// A run repeated: the last result, the median wall time and the median CPU time (s; none
/// when a repeat had none). `done` is called after each repeat.
fn run(
    scene: &Scene,
    kernel: &dyn Fn(&Model) -> Box<dyn Kernel>,
    repeats: usize,
    done: &dyn Fn(),
) -> Result<(RunResult, f64, Option<f64>)> {
    let model = Model::new(scene)?;
    let (mut walls, mut cpus) = (Vec::new(), Some(Vec::new()));
    let mut last = None;
    for _ in 0..repeats.max(1) {
        let r = simulate::run(&model, kernel(&model));
        walls.push(r.wall_time.as_secs_f64());
        cpus = cpus.zip(r.cpu_time).map(|(mut v, c)| {
            v.push(c.as_secs_f64());
            v
        });
        last = Some(r);
        done();
    }
    let median = |mut v: Vec<f64>| {
        v.sort_by(f64::total_cmp);
        v[v.len() / 2]
    };
    let last = last.expect("at least one repeat");
    Ok((last, median(walls), cpus.map(median)))
}

/// How many runs [`study`] makes for `plan` and `repeats`: the reference and its check,
/// then every setting `repeats` times.
pub fn run_count(plan: &[Setting], repeats: usize) -> usize {
    2 + plan.len() * repeats.max(1)
}

fn displacement(r: &RunResult, body: usize) -> f64 {
    let (first, last) = (r.samples.first().unwrap(), r.samples.last().unwrap());
    let k = if body == usize::MAX { first.bodies.len() - 1 } else { body };
    last.bodies[k].x - first.bodies[k].x
}

/// The largest joint tension at the common output times (each run's own peak depends on
/// its observation grid, so peaks are compared on the shared one), N.
fn peak(r: &RunResult) -> f64 {
    r.samples.iter().flat_map(|s| s.tensions.iter().copied()).fold(0.0, f64::max)
}

/// One setting of the study: method, dt (s) and rtol.
pub type Setting = (Method, f64, f64);

/// The default sweep: RK4 at dt = 4, 2, 1, 0.5 ms; DP5 at rtol = 1e-3 … 1e-8; SDIRK4 at
/// 1e-4 … 1e-6 (adaptive methods observed every 0.02 s).
pub fn default_plan() -> Vec<Setting> {
    [0.004, 0.002, 0.001, 0.0005]
        .iter()
        .map(|&dt| (Method::Rk4, dt, 1e-6))
        .chain([1e-3, 1e-4, 1e-5, 1e-6, 1e-7, 1e-8].iter().map(|&tol| (Method::Dp5, 0.02, tol)))
        .chain([1e-4, 1e-5, 1e-6].iter().map(|&tol| (Method::Sdirk4, 0.02, tol)))
        .collect()
}

/// The most timed repetitions of a setting: the median of more says nothing new.
pub const MAX_REPEATS: usize = 100;

/// Checks a study's arguments before any run: `repeats` in [1, [`MAX_REPEATS`]], and
/// `atol_ratio` such that every adaptive setting's atol (ratio × rtol) is a scene's, in
/// [[`MIN_ATOL`], 1].
pub fn check(plan: &[Setting], atol_ratio: f64, repeats: usize) -> Result<()> {
    if !(1..=MAX_REPEATS).contains(&repeats) {
        return Err(Error::Argument {
            name: "--repeats",
            value: repeats.to_string(),
            expected: format!("in [1, {MAX_REPEATS}]"),
        });
    }
    let rtols = plan.iter().filter(|s| s.0 != Method::Rk4).map(|s| s.2);
    let (lo, hi) = rtols.fold((f64::INFINITY, 0.0f64), |(lo, hi), r| (lo.min(r), hi.max(r)));
    let (min, max) = if hi > 0.0 { (MIN_ATOL / lo, 1.0 / hi) } else { (0.0, f64::INFINITY) };
    if !(atol_ratio.is_finite() && atol_ratio > 0.0 && (min..=max).contains(&atol_ratio)) {
        return Err(Error::Argument {
            name: "--atol-ratio",
            value: fmt_value(atol_ratio),
            expected: format!(
                "in [{min:e}, {max:e}] (atol = ratio × rtol, within a scene's [{MIN_ATOL:e}, 1] for the study's rtol \
                 {lo:e} to {hi:e})"
            ),
        });
    }
    Ok(())
}

/// Runs the study on `scene` over `plan` with kernels from `kernel`; the adaptive runs take
/// atol = `atol_ratio` × rtol (the reference always [`DEFAULT_ATOL_RATIO`]); `repeats`
/// timed repetitions per setting. `progress` is called after each run with what ran (e.g.
/// `dp5 1e-6`); [`run_count`] runs in all.
pub fn study(
    scene: &Scene,
    plan: &[Setting],
    atol_ratio: f64,
    kernel: &dyn Fn(&Model) -> Box<dyn Kernel>,
    repeats: usize,
    progress: &dyn Fn(&str),
) -> Result<AccuracyStudy> {
    check(plan, atol_ratio, repeats)?;
    let reference_run = |rtol: f64| {
        let label = format!("reference dp5 {rtol:e}");
        run(&configured(scene, Method::Dp5, 0.02, rtol, DEFAULT_ATOL_RATIO), kernel, 1, &|| progress(&label))
    };
    let (reference, ..) = reference_run(1e-10)?;
    let (check, ..) = reference_run(1e-9)?;
    let t_ref = match (&reference.stop, reference.stopping_time) {
        (Stop::ShipStopped, Some(t)) => t,
        (Stop::Failed(f), _) => return Err(Error::NoReference(format!("it failed at t = {:.3} s: {}", f.t, f.kind))),
        _ => {
            return Err(Error::NoReference(format!(
                "it reached its end time {:.3} s with the ship still moving; the study measures the stopping time \
                 (raise solver.end_time, or choose a scene whose ship stops)",
                reference.t_end
            )))
        }
    };
    let mut rows = Vec::new();
    for &(method, dt, rtol) in plan {
        let setting = if method == Method::Rk4 { dt } else { rtol };
        let label = format!("{method} {setting:e}");
        let (r, wall, cpu) =
            run(&configured(scene, method, dt, rtol, atol_ratio), kernel, repeats, &|| progress(&label))?;
        let stopped = matches!(r.stop, Stop::ShipStopped);
        let status = match &r.stop {
            Stop::ShipStopped => "stopped".to_string(),
            Stop::EndTime => "end time".to_string(),
            Stop::Failed(f) if matches!(f.kind, FailureKind::StepAboveLimit { .. }) => "refused".to_string(),
            Stop::Failed(f) => format!("failed at {:.3} s", f.t),
        };
        // Only a stopped run is compared at the stop (a run refused before its first step
        // has no sample at all).
        let when = |v: &dyn Fn() -> f64| stopped.then(v);
        rows.push(AccuracyRow {
            method,
            setting,
            status,
            stopping_time_error: r.stopping_time.filter(|_| stopped).map(|t| (t - t_ref).abs()),
            ship_displacement_error: when(&|| {
                (displacement(&r, usize::MAX) - displacement(&reference, usize::MAX)).abs()
            }),
            anchor_displacement_error: when(&|| (displacement(&r, 0) - displacement(&reference, 0)).abs()),
            peak_tension_error: when(&|| (peak(&r) - peak(&reference)).abs() / peak(&reference)),
            trajectory_error: (!r.samples.is_empty()).then(|| simulate::trajectory_difference(&r, &reference)),
            wall_time: wall,
            cpu_time: cpu,
            rhs_evaluations: r.rhs_evaluations,
            best: false,
        });
    }
    mark_front(&mut rows);
    Ok(AccuracyStudy {
        scene: scene.meta.name.clone(),
        reference_stopping_time: t_ref,
        reference_error: (check.stopping_time.unwrap_or(f64::NAN) - t_ref).abs(),
        reference_trajectory_error: simulate::trajectory_difference(&check, &reference),
        atol_ratio,
        rows,
    })
}

/// Marks the rows no other row beats in both stopping-time error and cost (CPU time).
fn mark_front(rows: &mut [AccuracyRow]) {
    let points: Vec<Option<(f64, f64)>> = rows.iter().map(|r| r.stopping_time_error.map(|e| (e, r.cost()))).collect();
    for (i, row) in rows.iter_mut().enumerate() {
        row.best = points[i].is_some_and(|(e, w)| {
            !points.iter().enumerate().any(|(j, p)| j != i && p.is_some_and(|(e2, w2)| e2 < e && w2 < w))
        });
    }
}

/// The run of another method that matches `base`'s stopping-time accuracy, with the
/// cost ratio base / run ([`AccuracyRow::cost`]: CPU time, both medians of the same study).
#[derive(Clone, Debug, PartialEq)]
pub struct MatchedRun<'a> {
    /// The matching run.
    pub run: &'a AccuracyRow,
    /// Cost (CPU time) of the base run over this one's.
    pub speedup: f64,
    /// Right-hand-side evaluations of the base run over this one's.
    pub evaluation_ratio: f64,
}

/// For the row of `method` at `setting` (e.g. RK4 at 2 ms), the run of each other method
/// that reaches its stopping-time error robustly: the loosest setting of that method from
/// which every tighter setting in the study reaches it too. An error that is not monotone
/// in the tolerance (it can cross zero) would otherwise let a lucky loose run win.
pub fn matched(s: &AccuracyStudy, method: Method, setting: f64) -> Option<(&AccuracyRow, Vec<MatchedRun<'_>>)> {
    let base = s.rows.iter().find(|r| r.method == method && (r.setting - setting).abs() <= 1e-12 * setting)?;
    let target = base.stopping_time_error?;
    let mut methods: Vec<Method> = Vec::new();
    for r in s.rows.iter().filter(|r| r.method != method) {
        if !methods.contains(&r.method) {
            methods.push(r.method);
        }
    }
    let runs = methods
        .into_iter()
        .filter_map(|m| {
            let mut rows: Vec<&AccuracyRow> = s.rows.iter().filter(|r| r.method == m).collect();
            // Tightest first; walk toward looser settings while they still reach the target.
            rows.sort_by(|a, b| a.setting.total_cmp(&b.setting));
            rows.iter().take_while(|r| r.stopping_time_error.is_some_and(|e| e <= target)).last().copied()
        })
        .map(|run| MatchedRun {
            run,
            speedup: base.cost() / run.cost(),
            evaluation_ratio: base.rhs_evaluations as f64 / run.rhs_evaluations.max(1) as f64,
        })
        .collect();
    Some((base, runs))
}

fn e(v: Option<f64>) -> String {
    v.map(|v| format!("{v:.2e}")).unwrap_or_else(|| "—".into())
}

/// Whether every run that made a step has its CPU time (a run refused before its first step
/// has none, and no cost to compare).
fn by_cpu_time(s: &AccuracyStudy) -> bool {
    s.rows.iter().filter(|r| r.rhs_evaluations > 0).all(|r| r.cpu_time.is_some())
}

/// The study as a terminal table.
pub fn table(s: &AccuracyStudy) -> String {
    let mut out = format!(
        "reference: DP5 rtol 1e-10, stopping time {:.9} s (estimated error {:.1e} s, trajectory {:.1e} m)\n",
        s.reference_stopping_time, s.reference_error, s.reference_trajectory_error
    );
    out.push_str(&format!("adaptive runs: observed every 0.02 s, atol = {:e} × rtol\n", s.atol_ratio));
    out.push_str(
        "errors against the reference: stopping time (s), ship and anchor displacement at the stop (m), \
         peak tension (relative), trajectory (largest position error, m)\n",
    );
    out.push_str(&format!(
        "{:<7} {:>9} {:<9} {:>10} {:>10} {:>10} {:>10} {:>10} {:>9} {:>9} {:>9} {:>4}\n",
        "method",
        "dt/rtol",
        "status",
        "err t_stop",
        "ship x",
        "anchor x",
        "peak T",
        "trajectory",
        "CPU s",
        "RHS",
        "wall s",
        "best"
    ));
    for r in &s.rows {
        out.push_str(&format!(
            "{:<7} {:>9.1e} {:<9} {:>10} {:>10} {:>10} {:>10} {:>10} {:>9} {:>9} {:>9.3} {:>4}\n",
            r.method.to_string(),
            r.setting,
            r.status,
            e(r.stopping_time_error),
            e(r.ship_displacement_error),
            e(r.anchor_displacement_error),
            e(r.peak_tension_error),
            e(r.trajectory_error),
            r.cpu_time.map(|c| format!("{c:.3}")).unwrap_or_else(|| "—".into()),
            r.rhs_evaluations,
            r.wall_time,
            if r.best { "*" } else { "" }
        ));
    }
    let by = if by_cpu_time(s) { "CPU time" } else { "wall time (no CPU time here)" };
    out.push_str(&format!("best: * = no other run is both more accurate in stopping time and cheaper in {by}\n"));
    if let Some((base, runs)) = matched(s, Method::Rk4, 0.002) {
        let target = base.stopping_time_error.unwrap_or(f64::NAN);
        out.push_str(&format!(
            "matched: the paper's RK4 at dt = 2 ms errs by {target:.2e} s in {:.3} s CPU ({} RHS, {:.3} s wall)\n",
            base.cost(),
            base.rhs_evaluations,
            base.wall_time
        ));
        for m in &runs {
            out.push_str(&format!(
                "         {} at {:.0e} and every tighter setting reach it ({:.2e} s) in {:.3} s CPU: {:.2}x RK4's speed in CPU time, {:.2}x in RHS evaluations ({:.3} s wall)\n",
                m.run.method,
                m.run.setting,
                m.run.stopping_time_error.unwrap_or(f64::NAN),
                m.run.cost(),
                m.speedup,
                m.evaluation_ratio,
                m.run.wall_time
            ));
        }
        if runs.is_empty() {
            out.push_str("         no adaptive run of the plan reaches it\n");
        }
    } else if let Some(base) = s.rows.iter().find(|r| r.method == Method::Rk4 && r.setting == 0.002) {
        out.push_str(&format!(
            "matched: none: the paper's RK4 at dt = 2 ms did not stop the ship ({}), so there is no accuracy of its to match\n",
            base.status
        ));
    }
    out
}

/// The files the study writes into its folder.
pub const FILES: [&str; 4] = ["accuracy.csv", "accuracy.json", "accuracy.svg", "accuracy.units.csv"];

/// The columns of `accuracy.csv` in order, each with its unit and what it holds (the header
/// and `accuracy.units.csv`); the errors are against the reference run's (docs/integrators.md).
pub const COLUMNS: [(&str, &str, &str); 11] = [
    ("method", "", "integrator: rk4, dp5, sdirk4"),
    ("setting", "", "dt in s for rk4; rtol, dimensionless, for dp5 and sdirk4"),
    ("status", "", "stopped, or why not"),
    ("stopping_time_error", "s", "|stopping time - the reference's|"),
    ("ship_displacement_error", "m", "|ship displacement at the stop - the reference's|"),
    ("anchor_displacement_error", "m", "|anchor displacement at the stop - the reference's|"),
    ("peak_tension_error", "", "|peak tension - the reference's| / the reference's (a fraction)"),
    ("trajectory_error", "m", "largest |centroid position - the reference's| of any body at the common output times"),
    ("wall_time", "s", "median wall time of the run"),
    ("rhs_evaluations", "", "right-hand-side evaluations"),
    ("cpu_time", "s", "median CPU time of the run's thread"),
];

/// Writes accuracy.csv, accuracy.json, accuracy.svg (stopping-time error against CPU time,
/// log–log, one curve per method) and accuracy.units.csv (the CSV's units) into `dir`.
pub fn write(s: &AccuracyStudy, dir: &Path) -> Result<[PathBuf; 4]> {
    let o = |v: Option<f64>| v.map(|v| format!("{v:e}")).unwrap_or_default();
    let mut csv = COLUMNS.map(|c| c.0).join(",");
    csv.push('\n');
    for r in &s.rows {
        csv.push_str(&format!(
            "{},{:e},{},{},{},{},{},{},{},{},{}\n",
            r.method,
            r.setting,
            r.status,
            o(r.stopping_time_error),
            o(r.ship_displacement_error),
            o(r.anchor_displacement_error),
            o(r.peak_tension_error),
            o(r.trajectory_error),
            r.wall_time,
            r.rhs_evaluations,
            o(r.cpu_time)
        ));
    }
    // Charts first: a chart that cannot be drawn leaves no file of the study behind.
    let chart = work_precision(s)?;
    let json = serde_json::to_string_pretty(s).expect("a study serialises: numbers and names");
    crate::output::write_into(dir, FILES, [csv, json, chart, units_csv(COLUMNS)])
}

/// The work–precision chart: the stopping-time error (s) and, beside it, the trajectory
/// error (m) against CPU time (wall time where a run has none), log–log, one colour per
/// method.
pub fn work_precision(s: &AccuracyStudy) -> Result<String> {
    let cpu = by_cpu_time(s);
    // The methods' colours named once, in the first panel's legend.
    let panel = |y_desc, legend: bool, pick: fn(&AccuracyRow) -> Option<f64>| {
        let curves = Method::ALL
            .into_iter()
            .enumerate()
            .map(|(color, method)| {
                let mut points: Vec<(f64, f64)> = s
                    .rows
                    .iter()
                    .filter(|r| r.method == method)
                    .filter_map(|r| pick(r).filter(|e| *e > 0.0).map(|e| (r.cost(), e)))
                    .collect();
                points.sort_by(|a, b| a.0.total_cmp(&b.0));
                LogCurve { label: legend.then(|| method.to_string()), color, points }
            })
            .collect();
        LogPanel { y_desc, curves }
    };
    log_log(
        &format!("Error against run time, {}", s.scene),
        if cpu { "CPU time (s)" } else { "wall time (s)" },
        &[
            panel("stopping-time error (s)", true, |r| r.stopping_time_error),
            panel("trajectory error (m)", false, |r| r.trajectory_error),
        ],
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    fn row(method: Method, setting: f64, error: f64, wall_time: f64) -> AccuracyRow {
        AccuracyRow {
            method,
            setting,
            status: "stopped".into(),
            stopping_time_error: Some(error),
            ship_displacement_error: None,
            anchor_displacement_error: None,
            peak_tension_error: None,
            trajectory_error: None,
            wall_time,
            cpu_time: Some(wall_time),
            rhs_evaluations: 1,
            best: false,
        }
    }

    #[test]
    fn a_lucky_loose_run_does_not_match() {
        let rows = vec![
            row(Method::Rk4, 0.002, 4e-5, 0.30),
            row(Method::Dp5, 1e-4, 1e-4, 0.08),
            row(Method::Dp5, 5e-5, 1e-6, 0.10), // reaches the target, but 1e-5 below it does not
            row(Method::Dp5, 1e-5, 5e-5, 0.15),
            row(Method::Dp5, 1e-6, 5e-6, 0.20),
            row(Method::Dp5, 1e-7, 5e-7, 0.30),
            row(Method::Sdirk4, 1e-5, 1e-3, 1.0), // never reaches it
        ];
        let s = AccuracyStudy {
            scene: "t".into(),
            reference_stopping_time: 20.0,
            reference_error: 1e-9,
            reference_trajectory_error: 1e-9,
            atol_ratio: DEFAULT_ATOL_RATIO,
            rows,
        };
        let (base, runs) = matched(&s, Method::Rk4, 0.002).unwrap();
        assert_eq!(base.wall_time, 0.30);
        assert_eq!(runs.len(), 1, "{runs:?}");
        assert_eq!((runs[0].run.method, runs[0].run.setting), (Method::Dp5, 1e-6));
        assert!((runs[0].speedup - 1.5).abs() < 1e-12);
        // Each error on an axis of its own unit.
        let svg = work_precision(&s).unwrap();
        assert!(svg.contains("stopping-time error (s)") && svg.contains("trajectory error (m)"));
    }
}

//! Sensitivity: d(output)/d(ln p) of the stopping time, stopping distance and peak tension
//! against every continuous physical parameter of a scene (every nonzero real field outside
//! `[meta]`, `[solver]` and `[checks]`), by central differences p·(1 ± h), the runs in
//! parallel; ranked by |effect on the stopping time| (on the peak tension when the base run
//! does not stop: it has no stopping time to move). With parameter uncertainties (σ of
//! ln p) a first-order output band: σ_out² = Σ (effect · σ_ln p)².
//!
//! A parameter at or near the edge of its valid range (the rod's hinge at the ship's stern,
//! the laid line's horizontal projection, a line length the catenary start cannot lay) has a
//! side at p·(1 ± h) whose scene is refused. Its step is then cut to h / [`RETRY_DIVISOR`];
//! where one side is still refused, the effect is a one-sided difference of the other side
//! against the base ([`Difference`]). Which scenes run is decided before any run, from the
//! scenes' checks alone ([`probes`]).

use std::sync::atomic::{AtomicBool, Ordering};

use kanestop_runtime::model::Model;
use kanestop_runtime::scene::{Scene, SceneError, Solver};
use kanestop_runtime::simulate::{self, FailureKind, Stop};
use serde::Serialize;
use toml::Value;

use crate::kernels::KernelFactory;
use crate::output::{self, CsvNumber};
use crate::record::RunSummary;
use crate::{parallel, Result};

/// The default relative step h: p·(1 ± 0.05).
pub const DEFAULT_STEP: f64 = 0.05;

/// The files `report sensitivity` writes into its folder.
pub const FILES: [&str; 3] = ["sensitivity.csv", "sensitivity.json", "sensitivity.units.csv"];

/// The columns of `sensitivity.csv` in order, each with its unit and what it holds (the
/// header and `sensitivity.units.csv`): the effects are d(output)/d(ln p), in the output's
/// unit (the change for a 100 % change of the parameter, to first order).
pub const COLUMNS: [(&str, &str, &str); 9] = [
    (
        "rank",
        "",
        "rank by |d_stopping_time| (by its bound where a perturbed run did not stop by the end time; by \
         |d_peak_tension| when the base run did not stop)",
    ),
    ("parameter", "", "the scene field's dotted path"),
    ("value", "", "the parameter's value in the scene, in its field's unit, which differs by row (docs/scenes.md)"),
    ("d_stopping_time", "s", "d(stopping time)/d(ln p)"),
    ("d_stopping_distance", "m", "d(stopping distance)/d(ln p)"),
    ("d_peak_tension", "N", "d(peak tension)/d(ln p)"),
    ("message", "", "why a perturbed run gave nothing, or why the step was cut or one-sided"),
    ("difference", "", "how the effects were differenced: central, forward, backward"),
    ("step", "", "the relative step h of the differences"),
];

/// Where a side at p·(1 ± h) is refused, the step is cut to h / this.
pub const RETRY_DIVISOR: f64 = 5.0;

/// The outputs differentiated.
pub const OUTPUTS: [&str; 3] = ["stopping_time", "stopping_distance", "peak_tension"];

/// How an effect was differenced, at the relative step h of its row.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
#[serde(rename_all = "lowercase")]
pub enum Difference {
    /// (f(p(1 + h)) − f(p(1 − h))) / ln((1 + h)/(1 − h)): error O(h²).
    Central,
    /// (f(p(1 + h)) − f(p)) / ln(1 + h), where p·(1 − h) is refused: error O(h).
    Forward,
    /// (f(p) − f(p(1 − h))) / −ln(1 − h), where p·(1 + h) is refused: error O(h).
    Backward,
}

impl Difference {
    /// ln of the ratio of p's two values the difference takes, at the relative step h: the
    /// effect is (f(above) − f(below)) / span.
    fn span(self, h: f64) -> f64 {
        match self {
            Difference::Central => ((1.0 + h) / (1.0 - h)).ln(),
            Difference::Forward => (1.0 + h).ln(),
            Difference::Backward => -(1.0 - h).ln(),
        }
    }

    /// The step as the table shows it: ±h, +h or −h.
    fn signed_step(self, h: f64) -> String {
        let sign = match self {
            Difference::Central => "±",
            Difference::Forward => "+",
            Difference::Backward => "−",
        };
        format!("{sign}{h}")
    }
}

/// One parameter's effects.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Sensitivity {
    /// The dotted path, e.g. `environment.seabed_friction`.
    pub parameter: String,
    /// Its value in the scene.
    pub value: f64,
    /// d(stopping time)/d(ln p), s; none when a perturbed run did not stop the ship.
    pub stopping_time: Option<f64>,
    /// d(stopping distance)/d(ln p), m.
    pub stopping_distance: Option<f64>,
    /// d(peak tension)/d(ln p), N.
    pub peak_tension: Option<f64>,
    /// Why a perturbed run gave nothing, or why the step was cut or one-sided.
    pub message: String,
    /// How the effects were differenced; none when every perturbed scene was refused.
    pub difference: Option<Difference>,
    /// The relative step h the effects were differenced at (the study's, or cut by
    /// [`RETRY_DIVISOR`]); none with `difference`.
    pub step: Option<f64>,
    /// Where one perturbed run did not stop the ship by the end time T (the base did): the
    /// bound on d(stopping time)/d(ln p) that gives, s: (T − t_below)/span when p·(1 + h)
    /// did not stop (the effect is above it), (t_above − T)/span when p·(1 − h) did not
    /// (below it). Ranks the row, which has no `stopping_time`; said in `message`.
    #[serde(skip)]
    pub stopping_time_bound: Option<f64>,
}

/// A sensitivity study of one scene.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Study {
    /// The scene's name.
    pub scene: String,
    /// The relative step h.
    pub step: f64,
    /// The base run's stopping time, stopping distance and peak tension.
    pub base: [Option<f64>; 3],
    /// The parameters, ranked by |d(stopping time)/d(ln p)| (largest first), or by
    /// |d(peak tension)/d(ln p)| when the base run did not stop ([`ranked_by`]).
    pub rows: Vec<Sensitivity>,
    /// The runs made: the base and one or two per parameter.
    pub runs: usize,
    /// The output the rows are ranked by: `stopping_time`, or `peak_tension` when the base
    /// run has no stop to move ([`ranked_by`]).
    pub ranked_by: &'static str,
}

/// Every continuous physical parameter of `scene`: (dotted path, value), in file order.
pub fn parameters(scene: &Scene) -> Vec<(String, f64)> {
    fn walk(prefix: &str, v: &Value, out: &mut Vec<(String, f64)>) {
        match v {
            Value::Table(t) => {
                for (k, v) in t {
                    let p = if prefix.is_empty() { k.clone() } else { format!("{prefix}.{k}") };
                    walk(&p, v, out);
                }
            }
            Value::Array(a) => {
                for (i, v) in a.iter().enumerate() {
                    walk(&format!("{prefix}[{i}]"), v, out);
                }
            }
            Value::Float(x) if *x != 0.0 => out.push((prefix.to_string(), *x)),
            _ => {}
        }
    }
    let mut out = Vec::new();
    if let Value::Table(t) = scene.to_value() {
        for (k, v) in &t {
            if !["meta", "solver", "checks"].contains(&k.as_str()) {
                walk(k, v, &mut out);
            }
        }
    }
    out
}

/// A parameter's perturbed scenes, chosen from the scenes' checks before any run (built by
/// [`probes`] alone, so that its scenes always match its difference).
#[derive(Clone, Debug)]
pub struct Probe {
    /// The dotted path.
    parameter: String,
    /// Its value in the scene.
    value: f64,
    /// The difference and its relative step, or none: every perturbed scene refused.
    difference: Option<(Difference, f64)>,
    /// The scenes to run: p·(1 + h) and p·(1 − h) (central), the one side (one-sided), none.
    scenes: Vec<Scene>,
    /// Why the step was cut or one-sided, or why there is no difference; empty otherwise.
    note: String,
}

/// The perturbed scenes of every parameter of `scene` at the relative step `step`: central
/// at h where both sides are valid scenes; else at h / [`RETRY_DIVISOR`], central where both
/// sides are valid there, one-sided where one is.
pub fn probes(scene: &Scene, step: f64) -> Vec<Probe> {
    // The scene at p·(1 + sign h), or why it is refused: its out-of-range values (the
    // perturbed field's, or another field's range that depends on it).
    let side = |path: &str, value: f64, h: f64, sign: f64| {
        scene.with_overrides(&[(path, Value::Float(value * (1.0 + sign * h)))]).map_err(|e| {
            let why = match e {
                SceneError::Invalid { problems, .. } => {
                    problems.iter().map(ToString::to_string).collect::<Vec<_>>().join("; ")
                }
                e => e.to_string().lines().map(str::trim).filter(|l| !l.is_empty()).collect::<Vec<_>>().join(" "),
            };
            format!("at {}{h} refused: {why}", if sign > 0.0 { "+" } else { "−" })
        })
    };
    parameters(scene)
        .into_iter()
        .map(|(parameter, value)| {
            let mut probe = Probe { parameter, value, difference: None, scenes: Vec::new(), note: String::new() };
            let path = probe.parameter.as_str();
            let refused_at_h = match (side(path, value, step, 1.0), side(path, value, step, -1.0)) {
                (Ok(up), Ok(down)) => {
                    probe.difference = Some((Difference::Central, step));
                    probe.scenes = vec![up, down];
                    return probe;
                }
                (Err(m), _) | (_, Err(m)) => m,
            };
            let h = step / RETRY_DIVISOR;
            let (up, down) = (side(path, value, h, 1.0), side(path, value, h, -1.0));
            let (difference, note) = match (&up, &down) {
                (Ok(_), Ok(_)) => (Difference::Central, format!("central at ±{h}; {refused_at_h}")),
                (Ok(_), Err(m)) => (Difference::Forward, format!("one-sided at +{h}; {m}")),
                (Err(m), Ok(_)) => (Difference::Backward, format!("one-sided at −{h}; {m}")),
                (Err(m), Err(_)) => {
                    probe.note = format!("no effect: refused at ±{step} and ±{h}; {m}");
                    return probe;
                }
            };
            probe.difference = Some((difference, h));
            probe.scenes = [up, down].into_iter().flatten().collect();
            probe.note = note;
            probe
        })
        .collect()
}

/// The runs a study of `probes` makes: the base and each probe's scenes.
pub fn run_count(probes: &[Probe]) -> usize {
    1 + probes.iter().map(|p| p.scenes.len()).sum::<usize>()
}

fn outputs(s: &RunSummary) -> [Option<f64>; 3] {
    [s.stopping_time, s.stopping_distance, s.peak_tension.map(|p| p.tension)]
}

/// Checks the relative step: in (0, 0.5).
pub fn check_step(step: f64) -> Result<()> {
    // Below 1e-6 the perturbed runs differ by round-off, not by the parameter.
    if (1e-6..0.5).contains(&step) {
        return Ok(());
    }
    Err(crate::Error::Argument {
        name: "--step",
        value: step.to_string(),
        expected: "in [1e-6, 0.5), e.g. 0.05".into(),
    })
}

/// Runs the base scene and the probes' scenes (from [`probes`] at `step`), `jobs` at a time.
pub fn study(
    scene: &Scene,
    step: f64,
    probes: &[Probe],
    kernel: KernelFactory,
    jobs: Option<usize>,
    done: &(dyn Fn() + Sync),
) -> Result<Study> {
    study_cancellable(scene, step, probes, kernel, jobs, done, &AtomicBool::new(false)).expect("nothing cancels it")
}

/// [`study`], stopped once `cancel` is set (Python's Ctrl-C): the runs going stop at their
/// next step, those not started are not, and the study is None.
pub fn study_cancellable(
    scene: &Scene,
    step: f64,
    probes: &[Probe],
    kernel: KernelFactory,
    jobs: Option<usize>,
    done: &(dyn Fn() + Sync),
    cancel: &AtomicBool,
) -> Option<Result<Study>> {
    // Long by design: the base, the probes' runs and each row's difference read best in the
    // order they happen.
    if let Err(e) = check_step(step) {
        return Some(Err(e));
    }
    // The base first: when it fails, no probe is worth running.
    let base_failed = |message: String, refused: bool| crate::Error::BaseRun { message, refused };
    let model = match Model::new(scene) {
        Ok(m) => m,
        Err(e) => return Some(Err(base_failed(e.to_string(), true))),
    };
    // Checked as `run` checks it: a failing base gets the same diagnosis.
    let result = simulate::run_checked_cancellable(&model, kernel(&model), kernel(&model), cancel).ok()?;
    let summary = RunSummary::of(&model, &result);
    done();
    if let Some(f) = &summary.failure {
        let refused = matches!(&result.stop, Stop::Failed(f) if matches!(f.kind, FailureKind::StepAboveLimit { .. }));
        return Some(Err(base_failed(f.message.clone(), refused)));
    }
    let base = outputs(&summary);
    let scenes: Vec<&Scene> = probes.iter().flat_map(|p| &p.scenes).collect();
    // A perturbed run that failed gives no effect (its partial outputs are no sample of the
    // parameter's), only its diagnostic; one that ran to the end time without stopping the
    // ship gives none for the stop either, but a bound ([`not_stopped`]).
    let runs = parallel::map_jobs(jobs, &scenes, |s| {
        if cancel.load(Ordering::Relaxed) {
            return Err("cancelled".to_string());
        }
        let r = Model::new(s).map_err(|e| e.to_string()).and_then(|model| {
            let result = simulate::run_cancellable(&model, kernel(&model), cancel).map_err(|_| "cancelled")?;
            let summary = RunSummary::of(&model, &result);
            match &summary.failure {
                Some(f) => Err(format!("failed: {}", f.message)),
                None => Ok(outputs(&summary)),
            }
        });
        done();
        r
    });
    let runs = match runs {
        _ if cancel.load(Ordering::Relaxed) => return None,
        Ok(runs) => runs,
        Err(e) => return Some(Err(e)),
    };
    let mut next = 0;
    let base_stop = base[0];
    let mut rows: Vec<Sensitivity> = probes
        .iter()
        .map(|probe| {
            let mine = &runs[next..next + probe.scenes.len()];
            next += probe.scenes.len();
            let mut row = Sensitivity {
                parameter: probe.parameter.clone(),
                value: probe.value,
                stopping_time: None,
                stopping_distance: None,
                peak_tension: None,
                message: probe.note.clone(),
                difference: probe.difference.map(|(d, _)| d),
                step: probe.difference.map(|(_, h)| h),
                stopping_time_bound: None,
            };
            let Some((difference, h)) = probe.difference else { return row };
            // The run above p and the run below p (the base for a one-sided difference).
            let base = Ok(base);
            let (above, below) = match difference {
                Difference::Central => (mine.first(), mine.last()),
                Difference::Forward => (mine.first(), Some(&base)),
                Difference::Backward => (Some(&base), mine.last()),
            };
            let sides = (above.unwrap_or(&base), below.unwrap_or(&base));
            difference_into(&mut row, sides, difference.span(h), base_stop, &scene.solver);
            row
        })
        .collect();
    let ranked = ranked_by(&base);
    let key = |r: &Sensitivity| ranked(r).map(f64::abs).unwrap_or(-1.0);
    rows.sort_by(|a, b| key(b).total_cmp(&key(a)));
    let ranked_by = if ranks_by_stop(&base) { "stopping_time" } else { "peak_tension" };
    Some(Ok(Study { scene: scene.meta.name.clone(), step, base, rows, runs: 1 + scenes.len(), ranked_by }))
}

/// A perturbed run's outputs, or why it gave none (its scene refused, the run failed).
type Probed = std::result::Result<[Option<f64>; 3], String>;

/// Sets the row's effects from the runs above and below p (`sides`; the base for one of
/// them in a one-sided difference), `span` the ln of their parameters' ratio; a side that
/// gave nothing is named in the message with why, and a stop past the end time is bounded
/// ([`not_stopped`]).
fn difference_into(
    row: &mut Sensitivity,
    sides: (&Probed, &Probed),
    span: f64,
    base_stop: Option<f64>,
    solver: &Solver,
) {
    let h = row.step.unwrap_or_default();
    match sides {
        (Ok(a), Ok(b)) => {
            let e = |k: usize| a[k].zip(b[k]).map(|(a, b)| (a - b) / span);
            row.stopping_time = e(0);
            row.stopping_distance = e(1);
            row.peak_tension = e(2);
            if let Some(note) = not_stopped(row, base_stop, (a[0], b[0]), span, solver) {
                row.message = if row.message.is_empty() { note } else { format!("{}; {note}", row.message) };
            }
        }
        (a, b) => {
            // Each side that gave nothing, named.
            if let Err(m) = a {
                add_note(row, &format!("p·(1 + {h})"), m);
            }
            if let Err(m) = b {
                add_note(row, &format!("p·(1 − {h})"), m);
            }
        }
    }
}

/// Adds to a row's message what its `side` (`p·(1 + h)`) said, on one line.
fn add_note(row: &mut Sensitivity, side: &str, message: &str) {
    let m = message.lines().map(str::trim).filter(|l| !l.is_empty()).collect::<Vec<_>>().join(" ");
    let m = format!("{side}: {m}");
    row.message = if row.message.is_empty() { m } else { format!("{}; {m}", row.message) };
}

/// Where the base stopped the ship (at `base_stop`, s) and a perturbed run that did not fail
/// did not stop it by the end of `solver`'s run ([`Solver::last_time`], s): sets the row's
/// [`Sensitivity::stopping_time_bound`] from the stopping times above and below p (`stops`,
/// none for a run that did not stop) and returns what to say of it. A stop that moved past
/// the end time is a large effect, not a missing one.
fn not_stopped(
    row: &mut Sensitivity,
    base_stop: Option<f64>,
    stops: (Option<f64>, Option<f64>),
    span: f64,
    solver: &Solver,
) -> Option<String> {
    base_stop?;
    let h = row.step.unwrap_or_default();
    // The runs went on to their last step, not always the end time itself.
    let (end_time, end) = (solver.end_time, solver.last_time());
    let (side, bound) = match stops {
        (None, Some(below)) => (format!("p·(1 + {h})"), Some((end - below) / span)),
        (Some(above), None) => (format!("p·(1 − {h})"), Some((above - end) / span)),
        (None, None) => (format!("p·(1 ± {h})"), None),
        (Some(_), Some(_)) => return None,
    };
    row.stopping_time_bound = bound;
    let effect = match bound {
        Some(b) if b >= 0.0 => format!("d_stopping_time > {b:+.3} s, ranked by that bound"),
        Some(b) => format!("d_stopping_time < {b:+.3} s, ranked by that bound"),
        None => "no stopping-time effect".to_string(),
    };
    Some(format!(
        "{side} did not stop the ship by solver.end_time = {end_time} s: {effect}; raise end_time for the effects"
    ))
}

/// Whether the base run's outputs have a stop to move, by which the rows are then ranked: a
/// ship that did not stop has none, and one at rest at the start stopped at t = 0, where
/// nothing moves it either.
fn ranks_by_stop(base: &[Option<f64>; 3]) -> bool {
    base[0].is_some_and(|t| t > 0.0)
}

/// The effect the rows are ranked by, given the base run's outputs: on the stopping time, or
/// on the peak tension when the base did not stop (no stopping time to move: every stop
/// effect is none, and a ranking by them would be the file order).
pub fn ranked_by(base: &[Option<f64>; 3]) -> fn(&Sensitivity) -> Option<f64> {
    if ranks_by_stop(base) {
        |r| r.stopping_time.or(r.stopping_time_bound)
    } else {
        |r| r.peak_tension
    }
}

/// A first-order band: each output's standard deviation from the uncertain inputs' σ.
#[derive(Clone, Debug, PartialEq)]
pub struct Band {
    /// σ of the stopping time (s), stopping distance (m) and peak tension (N).
    pub sd: [f64; 3],
    /// Per output, the uncertain inputs whose effect on it is unknown though the base run
    /// gave it (a perturbed run did not stop or failed): that output has no band.
    pub unknown: [Vec<String>; 3],
    /// The inputs that are no parameter of the study (ignored).
    pub missing: Vec<String>,
}

/// The first-order standard deviation of each output, from each parameter's σ of ln p
/// (`(path, sigma_ln)`): σ_out² = Σ (effect · σ_ln p)². An effect the study could not
/// difference is never taken as zero: its output is marked unknown ([`Band::unknown`]).
pub fn band(study: &Study, sigmas: &[(String, f64)]) -> Band {
    let mut var = [0.0; 3];
    let mut unknown: [Vec<String>; 3] = Default::default();
    let mut missing = Vec::new();
    for (path, s) in sigmas {
        match study.rows.iter().find(|r| &r.parameter == path) {
            Some(r) => {
                for (k, e) in [r.stopping_time, r.stopping_distance, r.peak_tension].iter().enumerate() {
                    match e {
                        Some(e) => var[k] += (e * s).powi(2),
                        None if study.base[k].is_some() => unknown[k].push(path.clone()),
                        None => {}
                    }
                }
            }
            None => missing.push(path.clone()),
        }
    }
    Band { sd: var.map(f64::sqrt), unknown, missing }
}

/// The study as a terminal table: a row a parameter, its step (±h central, +h or −h
/// one-sided), and under a row why its step was cut or one-sided or why it has no effect.
pub fn table(study: &Study) -> String {
    let d = |v: Option<f64>, scale: f64, digits: usize| {
        v.map(|v| format!("{:+.*}", digits, v * scale)).unwrap_or_else(|| "—".into())
    };
    let mut out = format!(
        "sensitivity of {} (central differences at p·(1 ± {})): d(output)/d(ln p)\n{:<4} {:<42} {:>16} {:>7} {:>12} {:>12} {:>12}\n",
        study.scene, study.step, "rank", "parameter", "value", "step", "stop (s)", "dist (m)", "peak (kN)"
    );
    if !ranks_by_stop(&study.base) {
        out.push_str(
            "note: the base run has no stop to move (it did not stop by its end time, or its ship was at rest at the \
             start): ranked by the effect on the peak tension\n",
        );
    }
    for (i, r) in study.rows.iter().enumerate() {
        let step = r.difference.zip(r.step).map_or_else(|| "—".to_string(), |(d, h)| d.signed_step(h));
        out.push_str(&format!(
            "{:<4} {:<42} {:>16} {:>7} {:>12} {:>12} {:>12}\n",
            i + 1,
            r.parameter,
            value_with_unit(&r.parameter, r.value),
            step,
            d(r.stopping_time, 1.0, 3),
            d(r.stopping_distance, 1.0, 3),
            d(r.peak_tension, 1e-3, 1)
        ));
        if !r.message.is_empty() {
            out.push_str(&format!("     {}\n", r.message));
        }
    }
    out
}

/// A parameter's value to six significant digits, with an exponent below 1e-3 or from 1e7
/// (`1.05e-6`, not `0.000001`), and its unit: `1.05e-6 m²/s`, `148 m`, `0.3`.
fn value_with_unit(path: &str, v: f64) -> String {
    let rounded: f64 = format!("{v:.5e}").parse().unwrap_or(v);
    let number = if rounded != 0.0 && !(1e-3..1e7).contains(&rounded.abs()) {
        format!("{rounded:e}")
    } else {
        format!("{rounded}")
    };
    match kanestop_runtime::scene::unit(path) {
        Some(u) if !u.is_empty() => format!("{number} {u}"),
        _ => number,
    }
}

/// The study as CSV, in rank order (`difference` and `step` last: columns added after the
/// first release).
pub fn csv(study: &Study) -> String {
    let o = |v: Option<f64>| v.map(|v| CsvNumber(v).to_string()).unwrap_or_default();
    let mut out = COLUMNS.map(|c| c.0).join(",");
    out.push('\n');
    for (i, r) in study.rows.iter().enumerate() {
        let difference = match r.difference {
            Some(Difference::Central) => "central",
            Some(Difference::Forward) => "forward",
            Some(Difference::Backward) => "backward",
            None => "",
        };
        out.push_str(&format!(
            "{},{},{},{},{},{},{},{},{}\n",
            i + 1,
            r.parameter,
            CsvNumber(r.value),
            o(r.stopping_time),
            o(r.stopping_distance),
            o(r.peak_tension),
            output::csv_quoted(&r.message),
            difference,
            o(r.step)
        ));
    }
    out
}

/// Writes `sensitivity.csv`, `sensitivity.json` and `sensitivity.units.csv` (the CSV's
/// units) into `dir` (created if needed), each whole or not at all. Returns the three files.
pub fn write(study: &Study, dir: &std::path::Path) -> Result<[std::path::PathBuf; 3]> {
    let json = serde_json::to_string_pretty(study).expect("a study serialises: numbers and names");
    output::write_into(dir, FILES, [csv(study), json, output::units_csv(COLUMNS)])
}

#[cfg(test)]
mod tests {
    use super::*;

    fn case1() -> Scene {
        Scene::from_toml(kanestop_runtime::paper::DEFAULT_SCENE, "case01.toml").unwrap()
    }

    /// Cancelled once the base has run, the study runs no probe and is None; not cancelled,
    /// it is the study.
    #[test]
    fn a_cancelled_study_runs_no_more_probes() {
        let mut scene = case1();
        scene.solver.end_time = 0.02;
        let probes = probes(&scene, 0.05);
        let kernel = crate::kernels::factory(crate::kernels::KernelChoice::Generated);
        let (cancel, runs) = (AtomicBool::new(false), std::sync::atomic::AtomicUsize::new(0));
        let done = || {
            runs.fetch_add(1, Ordering::Relaxed);
            cancel.store(true, Ordering::Relaxed);
        };
        assert!(study_cancellable(&scene, 0.05, &probes, &kernel, Some(1), &done, &cancel).is_none());
        assert_eq!(runs.load(Ordering::Relaxed), 1, "only the base ran");
        let whole = study_cancellable(&scene, 0.05, &probes, &kernel, Some(1), &|| {}, &AtomicBool::new(false));
        assert!(whole.is_some_and(|s| s.is_ok_and(|s| s.runs > 1)));
    }

    fn row(parameter: &str, stopping_time: Option<f64>) -> Sensitivity {
        Sensitivity {
            parameter: parameter.into(),
            value: 1.0,
            stopping_time,
            stopping_distance: stopping_time,
            peak_tension: Some(1e3),
            message: String::new(),
            difference: Some(Difference::Central),
            step: Some(0.05),
            stopping_time_bound: None,
        }
    }

    /// A perturbed run that did not stop by the end time bounds the effect, which ranks the
    /// row, instead of ranking it last as if it had none.
    #[test]
    fn a_stop_moved_past_the_end_time_is_a_large_effect_not_a_missing_one() {
        let span = Difference::Central.span(0.05);
        let mut solver = case1().solver;
        solver.end_time = 20.5;
        let end = solver.last_time();
        let mut heavier = row("ship.mass", None);
        // p·(1 + h) did not stop by 20.5 s; p·(1 − h) stopped at 18.9 s.
        let note = not_stopped(&mut heavier, Some(19.8), (None, Some(18.9)), span, &solver).unwrap();
        let bound = (end - 18.9) / span;
        assert_eq!(heavier.stopping_time_bound, Some(bound));
        assert!(
            note.starts_with("p·(1 + 0.05) did not stop the ship by solver.end_time = 20.5 s: d_stopping_time > +15.9"),
            "{note}"
        );
        let mut lighter = row("anchor.mass", None);
        not_stopped(&mut lighter, Some(19.8), (Some(19.0), None), span, &solver).unwrap();
        assert_eq!(lighter.stopping_time_bound, Some((19.0 - end) / span));
        let both = not_stopped(&mut row("x", None), Some(19.8), (None, None), span, &solver).unwrap();
        assert!(
            both.starts_with("p·(1 ± 0.05) did not stop the ship by solver.end_time = 20.5 s: no stopping-time effect")
        );
        // Both stopped, or the base did not: nothing to say.
        assert_eq!(not_stopped(&mut row("x", None), Some(19.8), (Some(20.0), Some(19.0)), span, &solver), None);
        assert_eq!(not_stopped(&mut row("x", None), None, (None, Some(19.0)), span, &solver), None);
        // An end time between two steps: the runs went on to the last step before it.
        solver.end_time = 20.501;
        let mut late = row("ship.mass", None);
        not_stopped(&mut late, Some(19.8), (None, Some(18.9)), span, &solver).unwrap();
        assert_eq!(late.stopping_time_bound, Some(bound));
        // Ranked by the bound, above a row of a smaller known effect.
        let ranked = ranked_by(&[Some(19.8), Some(27.0), Some(4e5)]);
        assert_eq!(ranked(&heavier), Some(bound));
        assert_eq!(ranked(&row("rod.radius", Some(0.1))), Some(0.1));
        // The band: the unknown effect marks the stopping outputs as unknown, never as zero.
        let study = Study {
            scene: "case01".into(),
            step: 0.05,
            base: [Some(19.8), Some(27.0), Some(4e5)],
            rows: vec![heavier, row("rod.radius", Some(0.1))],
            runs: 5,
            ranked_by: "stopping_time",
        };
        let sigmas = [("ship.mass".to_string(), 0.1), ("rod.radius".to_string(), 0.2), ("nope".to_string(), 0.1)];
        let b = band(&study, &sigmas);
        assert_eq!(b.unknown, [vec!["ship.mass".to_string()], vec!["ship.mass".to_string()], vec![]]);
        assert_eq!((b.sd[2], b.missing.as_slice()), ((1e4f64 + 4e4).sqrt(), &["nope".to_string()][..]));
    }

    /// A side that failed gives no effect and is named with its diagnostic; both, both.
    #[test]
    fn a_failed_perturbed_run_gives_no_effect_and_says_why() {
        let span = Difference::Central.span(0.05);
        let ran: Probed = Ok([Some(19.0), Some(26.0), Some(4e5)]);
        let failed: Probed = Err("failed: numerical failure at t = 3.1 s\n  body: B_4".into());
        let blank = || Sensitivity { peak_tension: None, ..row("ship.mass", None) };
        let mut one = blank();
        difference_into(&mut one, (&failed, &ran), span, Some(19.8), &case1().solver);
        assert_eq!((one.stopping_time, one.peak_tension, one.stopping_time_bound), (None, None, None));
        assert_eq!(one.message, "p·(1 + 0.05): failed: numerical failure at t = 3.1 s body: B_4");
        let mut both = blank();
        difference_into(&mut both, (&failed, &failed), span, Some(19.8), &case1().solver);
        assert!(both.message.contains("p·(1 + 0.05): failed") && both.message.contains("; p·(1 − 0.05): failed"));
        let mut fine = blank();
        difference_into(
            &mut fine,
            (&ran, &Ok([Some(18.0), Some(25.0), Some(3.9e5)])),
            span,
            Some(19.8),
            &case1().solver,
        );
        assert_eq!(fine.stopping_time, Some(1.0 / span));
    }

    #[test]
    fn values_read_with_their_units_and_significant_digits() {
        assert_eq!(value_with_unit("environment.kinematic_viscosity", 1.05e-6), "1.05e-6 m²/s");
        assert_eq!(value_with_unit("initial.horizontal_projection", 148.0), "148 m");
        assert_eq!(value_with_unit("chain.mass_per_length", 143.57162241), "143.572 kg/m");
        assert_eq!(value_with_unit("environment.seabed_friction", 0.3), "0.3");
        assert_eq!(value_with_unit("environment.seabed_stiffness", 5e6), "5000000 N/m³");
        assert_eq!(value_with_unit("chain.break_load", 3.866e7), "3.866e7 N");
        assert_eq!(value_with_unit("ship.hinge_x", -25.0), "-25 m");
    }

    #[test]
    fn each_difference_is_exact_for_an_output_linear_in_ln_p() {
        // f = c ln p + f0: every difference gives c whatever h (the spans are ln ratios).
        let (c, f0, p) = (-3.7, 12.0, 2.5);
        let f = |p: f64| c * p.ln() + f0;
        for h in [0.05, 0.01, 0.2] {
            let (up, down) = (f(p * (1.0 + h)), f(p * (1.0 - h)));
            for (d, above, below) in
                [(Difference::Central, up, down), (Difference::Forward, up, f(p)), (Difference::Backward, f(p), down)]
            {
                let e = (above - below) / d.span(h);
                assert!((e - c).abs() < 1e-12, "{d:?} at {h}: {e}");
            }
        }
    }

    #[test]
    fn parameters_at_the_edge_of_their_range_get_a_smaller_or_one_sided_step() {
        let probes = probes(&case1(), DEFAULT_STEP);
        let h = DEFAULT_STEP / RETRY_DIVISOR;
        let find = |p: &str| probes.iter().find(|x| x.parameter == p).unwrap_or_else(|| panic!("{p}"));
        for (p, difference, step) in [
            ("anchor.mass", Difference::Central, DEFAULT_STEP),
            // x_L has a valid range of about ±1.3 % at case 1 (146, 151.84] m, and a line
            // length moves that range.
            ("initial.horizontal_projection", Difference::Central, h),
            ("cable.stages[1].element_length", Difference::Central, h),
            // The rod's hinge at the stern, the rod as long as the hinge is high.
            ("ship.hinge_x", Difference::Backward, h),
            ("ship.length", Difference::Forward, h),
            ("rod.length", Difference::Backward, h),
            ("ship.hinge_z", Difference::Forward, h),
        ] {
            let probe = find(p);
            assert_eq!(probe.difference, Some((difference, step)), "{p}: {}", probe.note);
            let sides = if difference == Difference::Central { 2 } else { 1 };
            assert_eq!(probe.scenes.len(), sides, "{p}");
            assert_eq!(probe.note.is_empty(), step == DEFAULT_STEP, "{p}: {}", probe.note);
        }
        // The refused side is named with the range it broke.
        assert!(find("ship.hinge_x").note.contains("at +0.01 refused: ship.hinge_x = -25.25: must be in [-25, 25] m"));
        // Every parameter of case 1 has an effect; the run count follows the probes.
        assert!(probes.iter().all(|p| p.difference.is_some()), "a parameter without a step");
        let sides: usize = probes.iter().map(|p| p.scenes.len()).sum();
        assert_eq!(run_count(&probes), 1 + sides);
    }

    #[test]
    fn a_parameter_refused_on_both_sides_at_every_step_has_no_difference() {
        // x_L near the top of its valid range (146, 151.84] m at case 1's line: at ±40 % and
        // at ±8 % both sides leave the range.
        let mut scene = case1();
        scene.initial.horizontal_projection = Some(151.8);
        let probes = probes(&scene, 0.4);
        let probe = probes.iter().find(|p| p.parameter == "initial.horizontal_projection").unwrap();
        assert_eq!(probe.difference, None);
        assert!(probe.scenes.is_empty());
        assert!(probe.note.starts_with("no effect: refused at ±0.4 and ±0.08"), "{}", probe.note);
    }
}

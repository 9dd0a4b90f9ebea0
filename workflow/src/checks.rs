//! What a run's results say against the line's load limits and the design checks of a
//! scene or sweep (`[checks]`: stopping distance and time, anchor drag, safety factor on the
//! break load, proof-load utilisation).

use kanestop_runtime::design::DesignChecks;
use kanestop_runtime::model::Model;
use kanestop_runtime::simulate::{RunResult, Stop};
use serde::{Deserialize, Serialize};

/// A joint whose peak tension exceeded its break load.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Exceedance {
    /// The joint k (between B_{k−1} and B_k).
    pub joint: usize,
    /// Its peak tension, N.
    pub peak: f64,
    /// Its break load, N.
    pub limit: f64,
}

/// Joints whose peak tension exceeded their break load.
pub fn break_exceedances(model: &Model, result: &RunResult) -> Vec<Exceedance> {
    result
        .peak_tensions
        .iter()
        .enumerate()
        .filter_map(|(i, p)| {
            let joint = i + 2;
            let limit = model.joint_limits(joint).breaking?;
            (p.tension > limit).then_some(Exceedance { joint, peak: p.tension, limit })
        })
        .collect()
}

/// The break-load check in words, when it failed: "break load exceeded at K joint(s); worst:
/// joint J, P kN > B kN" (the worst by utilisation), as `run` and `batch` print it.
pub fn break_failure(over: &[Exceedance]) -> Option<String> {
    let w = over.iter().max_by(|a, b| (a.peak / a.limit).total_cmp(&(b.peak / b.limit)))?;
    Some(format!(
        "break load exceeded at {} joint(s); worst: joint {}, {:.0} kN > {:.0} kN",
        over.len(),
        w.joint,
        w.peak / 1e3,
        w.limit / 1e3
    ))
}

/// One design check of a run: its value, its limit and whether it passed.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct CheckOutcome {
    /// The check's field in `[checks]`, e.g. `max_stopping_distance`.
    pub name: String,
    /// What the run gave (for the tension checks: the worst joint's utilisation, times the
    /// safety factor for `safety_factor`); none when it does not exist (the ship did not stop).
    pub value: Option<f64>,
    /// The limit it is held to (1 for the tension checks, which are utilisations).
    pub limit: f64,
    /// The joint k of the worst utilisation (tension checks).
    pub joint: Option<usize>,
    /// Whether it passed.
    pub pass: bool,
}

/// Every design check of `checks` against the finished run `result` of `model`, in the
/// order of the `[checks]` fields. Empty when no check is set.
pub fn evaluate(checks: &DesignChecks, model: &Model, result: &RunResult) -> Vec<CheckOutcome> {
    let mut out = Vec::new();
    let mut upper = |name: &str, value: Option<f64>, limit: Option<f64>, joint: Option<usize>, scale: f64| {
        if let Some(limit) = limit {
            let value = value.map(|v| v * scale);
            let pass = value.is_some_and(|v| v <= limit);
            out.push(CheckOutcome { name: name.to_string(), value, limit, joint, pass });
        }
    };
    let stopped = result.stop == Stop::ShipStopped;
    let ship = model.body_count() - 1;
    let displacement = |body: usize| match (result.samples.first(), result.samples.last()) {
        (Some(a), Some(b)) => b.bodies[body].x - a.bodies[body].x,
        _ => 0.0,
    };
    let distance = stopped.then(|| displacement(ship));
    upper("max_stopping_distance", distance, checks.max_stopping_distance, None, 1.0);
    let time = result.stopping_time.filter(|_| stopped);
    upper("max_stopping_time", time, checks.max_stopping_time, None, 1.0);
    let failed = matches!(result.stop, Stop::Failed(_));
    let drag = (!failed).then(|| displacement(0).abs());
    upper("max_anchor_drag", drag, checks.max_anchor_drag, None, 1.0);
    let ran = result.steps > 0 && !failed;
    let worst = |limit: fn(&Model, usize) -> Option<f64>| -> Option<(usize, f64)> {
        result
            .peak_tensions
            .iter()
            .enumerate()
            .filter_map(|(i, p)| limit(model, i + 2).map(|l| (i + 2, p.tension / l)))
            .max_by(|a, b| a.1.total_cmp(&b.1))
            .filter(|_| ran)
    };
    if let Some(sf) = checks.safety_factor {
        let w = worst(|m, k| m.joint_limits(k).breaking);
        upper("safety_factor", w.map(|w| w.1), Some(1.0), w.map(|w| w.0), sf);
    }
    if let Some(max) = checks.max_proof_utilisation {
        let w = worst(|m, k| m.joint_limits(k).proof);
        upper("max_proof_utilisation", w.map(|w| w.1), Some(max), w.map(|w| w.0), 1.0);
    }
    out
}

/// A `[checks]` outcome in words: `max_stopping_distance 41.2 > 40` (failed),
/// `max_stopping_distance 27 ≤ 40` (passed), or the check without a value (the run did not
/// reach it, e.g. the ship did not stop).
pub fn outcome_words(o: &CheckOutcome) -> String {
    match o.value {
        Some(v) => format!("{} {v:.4} {} {}", o.name, if o.pass { "≤" } else { ">" }, o.limit),
        None => format!("{} (no value: the run did not reach it) > {}", o.name, o.limit),
    }
}

/// The design checks' verdict: false when a break load was exceeded (`exceedances`, a check
/// every scene has) or an outcome of `[checks]` failed, true when `[checks]` gave outcomes
/// and all passed, none when the scene has no `[checks]` and no break load was exceeded.
pub fn verdict(outcomes: &[CheckOutcome], exceedances: &[Exceedance]) -> Option<bool> {
    if !exceedances.is_empty() {
        return Some(false);
    }
    (!outcomes.is_empty()).then(|| outcomes.iter().all(|o| o.pass))
}

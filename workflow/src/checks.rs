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
    /// `safety_factor` only: the factor the run achieved, the break load over the peak
    /// tension at the worst joint (the factor set divided by `value`; passes when at least
    /// the factor set); none for the other checks, and when the run gave no value or no
    /// tension (a value of 0). Added
    /// 2026-12-07: `value` alone, utilisation × factor, read as a factor of 0.22.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub achieved: Option<f64>,
}

/// Every design check of `checks` against the finished run `result` of `model`, in the
/// order of the `[checks]` fields. Empty when no check is set.
pub fn evaluate(checks: &DesignChecks, model: &Model, result: &RunResult) -> Vec<CheckOutcome> {
    let mut out = Vec::new();
    let mut upper = |name: &str, value: Option<f64>, limit: Option<f64>, joint: Option<usize>, scale: f64| {
        if let Some(limit) = limit {
            let value = value.map(|v| v * scale);
            let pass = value.is_some_and(|v| v <= limit);
            // Utilisation × factor is the value; the factor itself over it is what was achieved.
            // No tension (v = 0) achieves no finite factor: none, as where the run gave no value.
            let achieved = value.filter(|v| name == "safety_factor" && *v > 0.0).map(|v| scale / v);
            out.push(CheckOutcome { name: name.to_string(), value, limit, joint, pass, achieved });
        }
    };
    // At the ship's stop, also in a run that went on past it (`stop_when_ship_stops = false`).
    upper("max_stopping_distance", result.stopping_distance, checks.max_stopping_distance, None, 1.0);
    upper("max_stopping_time", result.stopping_time, checks.max_stopping_time, None, 1.0);
    let failed = matches!(result.stop, Stop::Failed(_));
    let drag = (!failed).then(|| result.displacement(0).abs());
    upper("max_anchor_drag", drag, checks.max_anchor_drag, None, 1.0);
    let ran = result.ran() && !failed;
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

/// A `[checks]` outcome in words, as the scene sets it and in the engineer's terms, with
/// its own verdict: `max_stopping_distance = 40 m: stopped in 41.20 m (FAIL)`,
/// `safety_factor = 7: 5.85 achieved on the break load at joint 33 (utilisation × 7 = 1.196 > 1)
/// (FAIL)` (the factor the run achieved, break load over peak tension, and the utilisation
/// times the factor that the outcome holds against 1),
/// `max_stopping_time = 30 s: no value as the run did not reach it (FAIL)`. `checks` is what
/// `o` was evaluated against.
pub fn outcome_words(o: &CheckOutcome, checks: &DesignChecks) -> String {
    let verdict = if o.pass { "pass" } else { "FAIL" };
    let at = o.joint.map(|j| format!(" at joint {j}")).unwrap_or_default();
    let unit = match o.name.as_str() {
        "max_stopping_distance" | "max_anchor_drag" => " m",
        "max_stopping_time" => " s",
        _ => "",
    };
    // The safety factor's outcome holds utilisation × factor against 1: say the factor set.
    let required = checks.safety_factor.unwrap_or(f64::NAN);
    let set = match o.name.as_str() {
        "safety_factor" => format!("{} = {required}", o.name),
        _ => format!("{} = {}{unit}", o.name, o.limit),
    };
    let gave = match (o.name.as_str(), o.value) {
        (_, None) => "no value as the run did not reach it".to_string(),
        (_, Some(v)) if !v.is_finite() => format!("{v} (not finite)"),
        ("max_stopping_distance", Some(v)) => format!("stopped in {} m", shown(v, o.limit, 2)),
        ("max_stopping_time", Some(v)) => format!("stopped in {} s", shown(v, o.limit, 3)),
        ("max_anchor_drag", Some(v)) => format!("dragged {} m", shown(v, o.limit, 2)),
        ("safety_factor", Some(v)) => {
            // The factor achieved, and the value the record holds against 1 (`run --json`,
            // sweep.csv's check_safety_factor_value), so the two read as one.
            let achieved = if v > 0.0 { shown(required / v, required, 2) } else { "∞ (no tension)".into() };
            let against = if o.pass { "≤" } else { ">" };
            format!(
                "{achieved} achieved on the break load{at} (utilisation × {required} = {} {against} 1)",
                shown(v, 1.0, 3)
            )
        }
        ("max_proof_utilisation", Some(v)) => format!("{} of the proof load{at}", shown(v, o.limit, 3)),
        (_, Some(v)) => format!("{}{at}", shown(v, o.limit, 3)),
    };
    format!("{set}: {gave} ({verdict})")
}

/// `v` to `decimals` places, or to as many more (up to 9) as it takes not to read as `limit`
/// when it is not: "20.004" against a limit of 20, not "20.00" beside a FAIL.
fn shown(v: f64, limit: f64, decimals: usize) -> String {
    let mut places = decimals;
    while places < 9 && v != limit && format!("{v:.places$}") == format!("{limit:.places$}") {
        places += 1;
    }
    format!("{v:.places$}")
}

/// The failed design checks of the run `result` of `model` in words, the break loads first
/// ([`break_failure`]), then each failed `[checks]` limit ([`outcome_words`]); empty when
/// none failed. A row's message says them after "check failed: " (`batch`, `sweep`).
pub fn failures(model: &Model, result: &RunResult) -> Vec<String> {
    let outcomes = model.scene.checks.as_ref().map(|c| evaluate(c, model, result)).unwrap_or_default();
    failures_of(model.scene.checks.as_ref(), &outcomes, &break_exceedances(model, result))
}

/// [`failures`] from the `outcomes` of `checks` and the break loads' `exceedances`, where the
/// caller has them already.
pub fn failures_of(
    checks: Option<&DesignChecks>,
    outcomes: &[CheckOutcome],
    exceedances: &[Exceedance],
) -> Vec<String> {
    let failed = checks.map(|c| outcomes.iter().filter(|o| !o.pass).map(|o| outcome_words(o, c)).collect::<Vec<_>>());
    break_failure(exceedances).into_iter().chain(failed.unwrap_or_default()).collect()
}

/// The design checks' [`verdict`] of the run `result` of `model`: its `[checks]` evaluated
/// and its break loads.
pub fn verdict_of(model: &Model, result: &RunResult) -> Option<bool> {
    let outcomes = model.scene.checks.as_ref().map(|c| evaluate(c, model, result)).unwrap_or_default();
    verdict(&outcomes, &break_exceedances(model, result), break_loads_held(model, result))
}

/// Whether the run `result` of `model` was held to its break loads: it ran ([`RunResult::ran`]:
/// took a step, or its ship was at rest at the start and is judged on the state at t = 0),
/// did not fail, and some joint has one (the paper's every joint). The break-load check is then a
/// check of the run, passed or failed, as `run`'s summary says it, whether the scene has
/// `[checks]` or not. A failed run has passed nothing (as [`evaluate`]'s tension checks); a
/// break load it exceeded before its failure fails it all the same ([`verdict`]).
pub fn break_loads_held(model: &Model, result: &RunResult) -> bool {
    result.ran()
        && !matches!(result.stop, Stop::Failed(_))
        && (2..=model.body_count()).any(|k| model.joint_limits(k).breaking.is_some())
}

/// The design checks' verdict: false when a break load was exceeded (`exceedances`) or an
/// outcome of `[checks]` failed; true when nothing failed and some check was made (the
/// break loads, `held`, or `[checks]`); none when no check was made (no `[checks]`, and a
/// run that failed or was refused with no break load exceeded).
pub fn verdict(outcomes: &[CheckOutcome], exceedances: &[Exceedance], held: bool) -> Option<bool> {
    if !exceedances.is_empty() {
        return Some(false);
    }
    (held || !outcomes.is_empty()).then(|| outcomes.iter().all(|o| o.pass))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn outcome(name: &str, value: Option<f64>, limit: f64, joint: Option<usize>, pass: bool) -> CheckOutcome {
        CheckOutcome { name: name.into(), value, limit, joint, pass, achieved: None }
    }

    /// One verdict over the break loads and `[checks]`: false on an exceeded break load
    /// whatever `[checks]` say, true when nothing failed and some check was made (the break
    /// loads of a run that took a step count, `[checks]` or not), none when none was made.
    #[test]
    fn the_verdict_counts_the_break_loads_as_a_check() {
        let over = [Exceedance { joint: 46, peak: 3.0e6, limit: 2.52e6 }];
        let (pass, fail) =
            (outcome("max_anchor_drag", Some(1.0), 100.0, None, true), outcome("x", None, 1.0, None, false));
        assert_eq!(verdict(&[], &over, true), Some(false));
        assert_eq!(verdict(std::slice::from_ref(&pass), &over, true), Some(false));
        assert_eq!(verdict(&[], &[], true), Some(true));
        assert_eq!(verdict(std::slice::from_ref(&pass), &[], true), Some(true));
        assert_eq!(verdict(&[pass.clone(), fail.clone()], &[], true), Some(false));
        assert_eq!(verdict(&[], &[], false), None);
        assert_eq!(verdict(&[pass], &[], false), Some(true));
        assert_eq!(verdict(&[fail], &[], false), Some(false));
    }

    /// The safety factor is said as the factor the run achieved (break load over peak
    /// tension), and with the utilisation × required factor the outcome holds against 1.
    #[test]
    fn the_safety_factor_is_said_as_achieved() {
        let checks = DesignChecks { safety_factor: Some(7.0), ..Default::default() };
        // Utilisation 430.7/2520 = 0.1709: 7 × that = 1.196 > 1 fails; the factor is 5.85.
        let u = 430.7 / 2520.0;
        let failed = outcome("safety_factor", Some(7.0 * u), 1.0, Some(46), false);
        assert_eq!(
            outcome_words(&failed, &checks),
            "safety_factor = 7: 5.85 achieved on the break load at joint 46 (utilisation × 7 = 1.196 > 1) (FAIL)"
        );
        let checks = DesignChecks { safety_factor: Some(1.5), ..Default::default() };
        let passed = outcome("safety_factor", Some(1.5 * u), 1.0, Some(46), true);
        assert_eq!(
            outcome_words(&passed, &checks),
            "safety_factor = 1.5: 5.85 achieved on the break load at joint 46 (utilisation × 1.5 = 0.256 ≤ 1) (pass)"
        );
    }

    #[test]
    fn each_check_is_said_with_its_unit_and_its_own_verdict() {
        let checks = DesignChecks { safety_factor: Some(1.5), ..Default::default() };
        let cases = [
            (
                outcome("max_stopping_distance", Some(26.997), 20.0, None, false),
                "max_stopping_distance = 20 m: stopped in 27.00 m (FAIL)",
            ),
            (
                outcome("max_stopping_time", Some(19.8084), 30.0, None, true),
                "max_stopping_time = 30 s: stopped in 19.808 s (pass)",
            ),
            (
                outcome("max_anchor_drag", Some(22.381), 100.0, None, true),
                "max_anchor_drag = 100 m: dragged 22.38 m (pass)",
            ),
            (
                outcome("max_proof_utilisation", Some(0.85), 0.9, Some(12), true),
                "max_proof_utilisation = 0.9: 0.850 of the proof load at joint 12 (pass)",
            ),
            (
                outcome("max_stopping_time", None, 30.0, None, false),
                "max_stopping_time = 30 s: no value as the run did not reach it (FAIL)",
            ),
            (
                outcome("safety_factor", None, 1.0, None, false),
                "safety_factor = 1.5: no value as the run did not reach it (FAIL)",
            ),
        ];
        for (o, words) in cases {
            assert_eq!(outcome_words(&o, &checks), words);
        }
    }

    /// A value that rounds to its limit is shown with the places that tell them apart.
    #[test]
    fn a_value_next_to_its_limit_does_not_read_as_the_limit() {
        let checks = DesignChecks { safety_factor: Some(7.0), ..Default::default() };
        let o = outcome("max_stopping_distance", Some(20.0004), 20.0, None, false);
        assert_eq!(outcome_words(&o, &checks), "max_stopping_distance = 20 m: stopped in 20.0004 m (FAIL)");
        let o = outcome("max_stopping_distance", Some(20.0), 20.0, None, true);
        assert_eq!(outcome_words(&o, &checks), "max_stopping_distance = 20 m: stopped in 20.00 m (pass)");
        // A factor of 6.9999 against 7: value = 7 / 6.9999 > 1.
        let o = outcome("safety_factor", Some(7.0 / 6.9999), 1.0, Some(3), false);
        assert_eq!(
            outcome_words(&o, &checks),
            "safety_factor = 7: 6.9999 achieved on the break load at joint 3 (utilisation × 7 = 1.00001 > 1) (FAIL)"
        );
        let o = outcome("max_anchor_drag", Some(f64::NAN), 100.0, None, false);
        assert_eq!(outcome_words(&o, &checks), "max_anchor_drag = 100 m: NaN (not finite) (FAIL)");
    }
}

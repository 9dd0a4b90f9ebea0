//! The paper cases of a batch against Table 3: values within a tolerance, the same order.

use crate::batch::{self, BatchRow, Status};

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
/// of the cases by stopping time with Table 3's (over the pairs of one method label, as
/// [`batch::method_labels`] gives it, whose Table 3 times differ).
pub fn validate(rows: &[BatchRow], tolerance: f64) -> Validation {
    // With several method labels a case is named with its label (a scene that did not load
    // has none).
    let labels = batch::method_labels(rows);
    let several = labels.iter().filter(|l| !l.is_empty()).collect::<std::collections::BTreeSet<_>>().len() > 1;
    let name = |i: usize| match several && !labels[i].is_empty() {
        true => format!("{} ({})", rows[i].case, labels[i]),
        false => rows[i].case.clone(),
    };
    let mut problems = Vec::new();
    for (i, r) in rows.iter().enumerate() {
        let case = name(i);
        if r.status != Status::Stopped {
            problems.push(format!("{case}: {} {}", r.status, r.message));
            continue;
        }
        if let Some(d) = r.relative_difference.filter(|d| d.abs() > tolerance) {
            problems.push(format!("{case}: stopping time differs from Table 3 by {:+.2} %", 100.0 * d));
        }
        if let Some(e) = r.energy_drift.filter(|&e| e > 0.005) {
            problems.push(format!("{case}: energy balance drift {e:.2e} > 0.5 %"));
        }
        if r.break_exceedances > 0 {
            problems.push(format!("{case}: break load exceeded at {} joint(s)", r.break_exceedances));
        }
    }
    let paired: Vec<(usize, f64, f64)> =
        rows.iter().enumerate().filter_map(|(i, r)| Some((i, r.stopping_time?, r.paper_stopping_time?))).collect();
    let (mut concordant, mut discordant) = (0usize, Vec::new());
    for i in 0..paired.len() {
        for j in i + 1..paired.len() {
            let (a, b) = (&paired[i], &paired[j]);
            // One case twice (its file copied, or run by several `--methods`): Table 3 gives
            // the pair no order to keep. Cases run by different methods, or one method at
            // different steps, are not ordered against each other: each is held to Table 3's
            // order on its own.
            if a.2 == b.2 || labels[a.0] != labels[b.0] {
                continue;
            }
            if (a.1 - b.1) * (a.2 - b.2) > 0.0 {
                concordant += 1;
            } else {
                discordant.push((name(a.0), name(b.0)));
            }
        }
    }
    let pairs = concordant + discordant.len();
    let kendall_tau = (pairs > 0).then(|| (concordant as f64 - discordant.len() as f64) / pairs as f64);
    Validation { problems, kendall_tau, discordant }
}

#[cfg(test)]
mod tests {
    use super::*;
    use kanestop_runtime::scene::Method;

    fn row(case: &str, t: f64, paper: f64) -> BatchRow {
        BatchRow {
            case: case.into(),
            file: format!("{case}.toml"),
            status: Status::Stopped,
            method: None,
            bodies: Some(46),
            dt: Some(0.002),
            rtol: None,
            atol: None,
            stopping_time: Some(t),
            paper_stopping_time: Some(paper),
            relative_difference: Some((t - paper) / paper),
            peak_tension: None,
            peak_joint: None,
            peak_time: None,
            break_exceedances: 0,
            anchor_start: None,
            stopping_distance: None,
            anchor_drag_distance: None,
            peak_break_utilisation: None,
            energy_drift: Some(1e-6),
            wall_time: 0.1,
            cpu_time: None,
            rhs_evaluations: None,
            checks_pass: Some(true),
            stop_error_estimate: None,
            trajectory_error_estimate: None,
            peak_error_estimate: None,
            message: String::new(),
        }
    }

    #[test]
    fn one_case_twice_is_no_pair_out_of_order() {
        // Case 1 by two methods (or a copy of its file) and case 2: all in Table 3's order.
        let rows = [row("case01", 19.81, 20.01), row("case01", 19.79, 20.01), row("case02", 23.5, 23.65)];
        let v = validate(&rows, 0.05);
        assert_eq!((v.kendall_tau, v.discordant.len(), v.problems.len()), (Some(1.0), 0, 0));
        // A pair out of Table 3's order is still found.
        let rows = [row("case01", 24.0, 20.01), row("case01", 19.8, 20.01), row("case02", 23.5, 23.65)];
        let v = validate(&rows, 0.5);
        assert_eq!(v.discordant, [("case01".to_string(), "case02".to_string())]);
        assert_eq!(v.kendall_tau, Some(0.0));
        // Two methods, each in Table 3's order (case 1 by DP5 after case 2 by RK4, were they
        // compared): no pair across them is compared, and a pair out
        // of order is named with its method.
        let by = |case: &str, t: f64, paper: f64, m: Method| BatchRow { method: Some(m), ..row(case, t, paper) };
        let rows = [
            by("case01", 19.9, 20.01, Method::Rk4),
            by("case02", 23.5, 23.65, Method::Rk4),
            by("case01", 23.6, 20.01, Method::Dp5),
            by("case02", 23.7, 23.65, Method::Dp5),
        ];
        let v = validate(&rows, 0.5);
        assert_eq!((v.kendall_tau, v.discordant.len()), (Some(1.0), 0));
        let rows = [
            by("case01", 19.9, 20.01, Method::Rk4),
            by("case01", 24.0, 20.01, Method::Dp5),
            by("case02", 23.5, 23.65, Method::Dp5),
        ];
        let v = validate(&rows, 0.5);
        assert_eq!(v.discordant, [("case01 (dp5)".to_string(), "case02 (dp5)".to_string())]);
        // One method at two steps (`--methods rk4@0.01,rk4@0.005`): each step on its own,
        // and a pair out of order named with its step.
        let at = |case: &str, t: f64, paper: f64, dt: f64| BatchRow {
            method: Some(Method::Rk4),
            dt: Some(dt),
            file: format!("{case}.toml"),
            ..row(case, t, paper)
        };
        let rows = [
            at("case01", 23.6, 20.01, 0.01),
            at("case01", 19.9, 20.01, 0.005),
            at("case02", 23.7, 23.65, 0.01),
            at("case02", 23.5, 23.65, 0.005),
        ];
        let v = validate(&rows, 0.5);
        assert_eq!((v.kendall_tau, v.discordant.len()), (Some(1.0), 0));
        let rows = [at("case01", 24.0, 20.01, 0.01), at("case01", 19.9, 20.01, 0.005), at("case02", 23.7, 23.65, 0.01)];
        let v = validate(&rows, 0.5);
        assert_eq!(v.discordant, [("case01 (rk4@0.01)".to_string(), "case02 (rk4@0.01)".to_string())]);
        // A scene that did not load (no method) is named alone, and makes no label of its own.
        let invalid = BatchRow { status: Status::Invalid, method: None, dt: None, ..row("bad", 1.0, 2.0) };
        let v = validate(&[by("case01", 19.9, 20.01, Method::Rk4), invalid], 0.5);
        assert_eq!(v.problems.len(), 1, "{:?}", v.problems);
        assert!(v.problems[0].starts_with("bad: invalid"), "{:?}", v.problems);
        assert_eq!(v.kendall_tau, None);
    }
}

//! The one-screen summary of a run: what an engineer reads first.

use std::fmt::Write as _;

use kanestop_runtime::kernel::AnchorDof;
use kanestop_runtime::model::Model;
use kanestop_runtime::scene::{Layout, Method};
use kanestop_runtime::simulate::{FailureKind, RunResult, Stop};

use crate::checks::{break_exceedances, break_failure};

/// The one-screen summary of a run: the outcome, the anchor, the peak tension, the checks,
/// where the ship's energy went and the cost.
pub fn summary(model: &Model, result: &RunResult) -> String {
    summary_with(model, result, false)
}

/// The summary; `verbose` adds the solver internals (physics, bodies, catenary residuals,
/// stability eigenvalues, final state). The initial state (x_L, h_L, the tensions of the
/// laid line, the water depth) is always shown: a variant that changes the depth changes
/// them (until 2026-12-07 only `--verbose` showed it).
pub fn summary_with(model: &Model, result: &RunResult, verbose: bool) -> String {
    let mut out = Lines::default();
    let s = &model.scene;
    out.line("scene", format!("{} — {}", s.meta.name, s.meta.description));
    scene_lines(&mut out, model, result, verbose);
    outcome_lines(&mut out, model, result);
    tension_lines(&mut out, model, result);
    energy_share_line(&mut out, model, result);
    run_lines(&mut out, model, result, verbose);
    if verbose {
        final_lines(&mut out, model, result);
    }
    out.0
}

/// Where the ship's kinetic energy went: each work term as a share of the initial kinetic
/// energy (negative where the term gave energy back), the kinetic energy left and the
/// potential energy's change, largest first: they add up to 100 % but for the balance's drift
/// (shares below 0.05 % are not named). The drift is relative to the largest kinetic energy,
/// as `solver.max_energy_drift`; for a ship that only slows, the one at t = 0.
///
/// The ship's hydrostatic work holds its whole buoyancy times its heave, which its weight's
/// potential energy all but cancels: the two are named together, as the energy stored in
/// the ship's heave and pitch (a few tenths of a per cent at most), and the potential
/// energy change is the rest of the system's (line and anchor).
fn energy_share_line(out: &mut Lines, model: &Model, result: &RunResult) {
    let (Some(first), Some(last)) = (result.samples.first(), result.samples.last()) else { return };
    let k0 = first.energy.kinetic + first.energy.added_kinetic;
    if k0 <= 0.0 {
        return;
    }
    let n = model.body_count();
    let ship_weight = model.chain.bodies[n - 1].mass * model.scene.environment.gravity;
    let ship_potential = ship_weight * (last.bodies[n - 1].z - first.bodies[n - 1].z);
    let mut shares: Vec<(f64, String)> = last
        .energy
        .work_terms()
        .map(|(name, w)| match name {
            "hydrostatic" => ((ship_potential - w) / k0, "ship heave and pitch (hydrostatics with its weight)".into()),
            _ => (-w / k0, work_term_words(name).to_string()),
        })
        .collect();
    shares.push(((last.energy.kinetic + last.energy.added_kinetic) / k0, "still kinetic".into()));
    let line_potential = last.energy.potential - first.energy.potential - ship_potential;
    shares.push((line_potential / k0, "potential energy change of the line and anchor".into()));
    shares.retain(|(f, _)| f.abs() >= 0.0005);
    shares.sort_by(|a, b| b.0.total_cmp(&a.0));
    let parts: Vec<String> = shares.iter().map(|(f, what)| format!("{:.1} % {what}", 100.0 * f)).collect();
    out.line(
        "energy",
        format!(
            "of {:.3} MJ kinetic at t = 0: {}; energy balance drift {:.1e} of {}",
            k0 / 1e6,
            parts.join(", "),
            result.max_energy_drift,
            if result.energy_scale > k0 {
                format!("the largest kinetic energy, {:.3} MJ", result.energy_scale / 1e6)
            } else {
                "the kinetic energy at t = 0".to_string()
            }
        ),
    );
}

/// A work term of `WORK_TERMS` in the words the summary and the charts use.
pub(crate) fn work_term_words(name: &str) -> &str {
    match name {
        "anchor_friction" => "anchor friction",
        "line_friction" => "line friction on the seabed",
        "anchor_drag" => "anchor water drag",
        "line_drag" => "line drag",
        "hull_resistance" => "hull resistance",
        "seabed" => "seabed contact",
        "added_mass" => "entrained water",
        other => other,
    }
}

/// Labelled lines: the label in a column of ten.
#[derive(Default)]
struct Lines(String);

impl Lines {
    fn line(&mut self, label: &str, text: impl std::fmt::Display) {
        let _ = writeln!(self.0, "{label:<10}{text}");
    }
}

/// What was simulated: the scene, its physics, bodies, initial state and catenary.
fn scene_lines(out: &mut Lines, model: &Model, result: &RunResult, verbose: bool) {
    let s = &model.scene;
    if verbose {
        body_lines(out, model, result);
    }
    let (t_h, t_t) = model.initial_tensions();
    out.line(
        "initial",
        format!(
            "x_L = {}, h_L = {} m, T_h = {}, T_t = {} at the top, {} depth {:.3} m, {:.2} m of cable on the seabed ({:.2} m of the catenary), ship {} m/s",
            fmt_projection(model),
            s.initial.vertical_projection,
            fmt_tension(t_h),
            fmt_tension(t_t),
            // Without water the depth is the seabed's below the still-water plane's place.
            if s.environment.water { "water" } else { "seabed" },
            model.water_depth(),
            // A line laid at the touchdown's end reads a rounding's −0.00.
            model.grounded_cable_length().max(0.0),
            model.catenary.grounded_length().max(0.0),
            s.initial.ship_speed
        ),
    );
    if !verbose {
        return;
    }
    let residual = match result.initial_residual {
        Some(r) => format!(
            "; at rest, max |a| {:.2e} m/s² on the line (B_{}), {:.2e} m/s² beside the rod (B_{})",
            r.line.0, r.line.1, r.top.0, r.top.1
        ),
        None => String::new(),
    };
    out.line("catenary", format!("cable ends {:.1e} m from (x_L, h_L){residual}", model.cable_end_error()));
}

/// The physics the loads include and the bodies (`--verbose`).
fn body_lines(out: &mut Lines, model: &Model, result: &RunResult) {
    let s = &model.scene;
    out.line("physics", &result.physics);
    let stages: Vec<String> =
        s.cable.stages.iter().map(|st| format!("{}×{} m", st.elements, st.element_length)).collect();
    out.line(
        "bodies",
        format!(
            "N = {}: anchor {:.1} t, {} chain links × {} m, cable {} = {:.1} m, rod {} m, ship {:.1} t",
            model.body_count(),
            s.anchor.mass / 1e3,
            s.chain.elements,
            s.chain.element_length,
            stages.join(" + "),
            s.cable_length(),
            s.rod.length,
            s.ship.mass / 1e3
        ),
    );
}

/// x_L as the scene gives it, or as the line's horizontal or top tension lays it.
fn fmt_projection(model: &Model) -> String {
    let by = |field: &str| format!("{:.4} m (laid by initial.{field})", model.catenary.horizontal);
    match model.scene.initial.layout() {
        Some(Layout::Tension(_)) => by("horizontal_tension"),
        Some(Layout::TopTension(_)) => by("top_tension"),
        Some(Layout::Projection(x)) => format!("{x} m"),
        None => format!("{} m", model.catenary.horizontal),
    }
}

/// A tension (N) to a tenth of a newton below 10 kN, else in kN.
fn fmt_tension(t: f64) -> String {
    if t.abs() < 1e4 {
        format!("{t:.1} N")
    } else {
        format!("{:.2} kN", t / 1e3)
    }
}

/// How it was integrated and what it cost; `verbose` adds the stability limit.
fn run_lines(out: &mut Lines, model: &Model, result: &RunResult, verbose: bool) {
    let solver = &model.scene.solver;
    // An adaptive method's dt is its observation interval, not its step.
    let (method, intervals) = match solver.integrator {
        Method::Rk4 => (format!("rk4, dt = {} s", solver.dt), "steps"),
        m => (
            format!("{m} (rtol {:e}, atol {:e}), observed every {} s", solver.rtol, solver.atol, solver.dt),
            "observation intervals",
        ),
    };
    out.line(
        "run",
        format!(
            "{method}, kernel {}{}, loads {}: {:.3} s simulated in {}{:.3} s wall ({} {intervals}, {} right-hand-side evaluations)",
            result.kernel,
            result.kernel_form.map(|f| format!(" ({f})")).unwrap_or_default(),
            result.load_code.as_ref().map_or("by the force modules".to_string(), |s| format!("generated ({s})")),
            result.t_end,
            result.cpu_time.map(|c| format!("{:.3} s CPU, ", c.as_secs_f64())).unwrap_or_default(),
            result.wall_time.as_secs_f64(),
            result.steps,
            result.rhs_evaluations
        ),
    );
    if let Some(l) = result.stability.filter(|_| verbose) {
        out.line(
            "stability",
            format!(
                "RK4 step limit at t = 0: {:.3e} s (fastest mode {:.3e} ± {:.3e}i 1/s; stiffest hinge B_{}){}",
                l.rk4_dt,
                l.lambda.re,
                l.lambda.im.abs(),
                l.body,
                if l.settled {
                    ""
                } else {
                    "; an estimate: Arnoldi's method had not settled in the Krylov space a line this long affords, \
                     so no step is refused by it"
                }
            ),
        );
    }
}

/// Why the run ended, with the stopping distance, against the paper when the scene is a
/// paper case, and the anchor with its drag distance.
fn outcome_lines(out: &mut Lines, model: &Model, result: &RunResult) {
    let paper = |t: f64| match kanestop_runtime::paper::stopping_time(&model.scene) {
        Some(p) => format!("   paper (Table 3): {p:.3} s, difference {:+.2} %", 100.0 * (t - p) / p),
        None => String::new(),
    };
    let n = model.body_count();
    let moved = |k: usize| result.displacement(k);
    match &result.stop {
        Stop::ShipStopped if result.stopping_time == Some(0.0) => {
            out.line("stopped", "t = 0 s: the ship was at rest at the start (initial.ship_speed = 0)".to_string())
        }
        Stop::ShipStopped => {
            let t = result.stopping_time.unwrap_or(result.t_end);
            out.line(
                "stopped",
                format!("t = {t:.3} s after {:.2} m (ship surge speed reached zero){}", moved(n - 1), paper(t)),
            )
        }
        Stop::EndTime => out.line(
            "ended",
            match result.stopping_time {
                Some(0.0) => "end time reached; the ship was at rest at the start (initial.ship_speed = 0)".to_string(),
                Some(t) => format!(
                    "end time reached; ship surge speed first zero at t = {t:.3} s after {:.2} m{}",
                    result.stopping_distance.unwrap_or(f64::NAN),
                    paper(t)
                ),
                None => format!(
                    "end time {:.3} s reached; the ship did not stop (moved {:.2} m)",
                    result.t_end,
                    moved(n - 1)
                ),
            },
        ),
        Stop::Failed(f) => {
            let text = crate::diagnostic::describe(model, f);
            let first = text.lines().next().unwrap_or_default();
            let label = if matches!(f.kind, FailureKind::StepAboveLimit { .. }) { "REFUSED" } else { "FAILED" };
            out.line(label, format!("{first} (diagnostic on standard error)"))
        }
    }
    if result.samples.is_empty() {
        return;
    }
    let anchor = match (model.anchor, result.anchor_start()) {
        (_, Some(t)) => format!(
            "started to slide at t = {t:.3} s; dragged {:.2} m ({} stick–slip switch{})",
            moved(0),
            result.anchor_events.len(),
            if result.anchor_events.len() == 1 { "" } else { "es" }
        ),
        (AnchorDof::Stuck, None) => "held by friction throughout".to_string(),
        (AnchorDof::Free, None) => format!("free (no seabed friction); moved {:.2} m", moved(0)),
    };
    out.line("anchor", anchor);
}

/// The peak tension with its utilisation and where, and the break-load check.
fn tension_lines(out: &mut Lines, model: &Model, result: &RunResult) {
    if !result.ran() {
        return;
    }
    let Some((k, peak)) = result.peak_tension() else { return };
    let limits = model.joint_limits(k);
    let limit = |name: &str, v: Option<f64>| {
        v.map(|v| format!("; {:.0} % of {name} load {:.0} kN", 100.0 * peak.tension / v, v / 1e3)).unwrap_or_default()
    };
    out.line(
        "tension",
        format!(
            "peak {:.1} kN at joint {k} ({} – {}) at t = {:.3} s{}{}",
            peak.tension / 1e3,
            model.chain.bodies[k - 2].kind,
            model.chain.bodies[k - 1].kind,
            peak.t,
            limit("break", limits.breaking),
            limit("proof", limits.proof)
        ),
    );
    if let Some(later) = crate::record::early_peak(model, result) {
        let after = match later {
            Some(p) => format!(
                "; after {:.1} s the largest sampled tension is {:.1} kN at joint {} at t = {:.3} s",
                kanestop_runtime::simulate::early_window(model.scene.solver.dt),
                p.tension / 1e3,
                p.joint,
                p.t
            ),
            None => String::new(),
        };
        out.line(
            "",
            format!(
                "at the engagement: the model starts the ship at {} m/s on a line at rest and takes the line up at \
                 once, a snap a net's give would soften (docs/model-choices.md, \"Initial speeds\"){after}",
                model.scene.initial.ship_speed
            ),
        );
    }
    if limits.breaking.is_some() || limits.proof.is_some() {
        // The paper's convention, easy to miss in a percentage (docs/model-choices.md).
        out.line(
            "",
            "(the element's tension is the pair's, two chains or cable ends: against one's loads, as in the \
             paper's scenes, a utilisation is twice one line's; docs/model-choices.md)",
        );
    }
    let over = break_exceedances(model, result);
    let utilisation = |j: usize| {
        let p = result.peak_tensions[j - 2].tension;
        model.joint_limits(j).breaking.map(|b| p / b)
    };
    let worst =
        (2..=model.body_count()).filter_map(|j| utilisation(j).map(|u| (j, u))).max_by(|a, b| a.1.total_cmp(&b.1));
    let breaking = match (break_failure(&over), worst) {
        (Some(failure), _) => Some((false, failure)),
        // A failed run has passed no check: its peak is the failure's, not the run's.
        (None, Some((j, u))) if crate::checks::break_loads_held(model, result) => {
            Some((true, format!("no break load exceeded (highest utilisation {:.0} % at joint {j})", 100.0 * u)))
        }
        (None, _) => None,
    };
    // The scene's own `[checks]`, a line each with its value and verdict (exit 4 when one
    // fails), under one verdict with the break loads'.
    let outcomes = model.scene.checks.as_ref().map(|c| (c, crate::checks::evaluate(c, model, result)));
    let verdict = |pass: bool| if pass { "PASS" } else { "FAIL" };
    match (breaking, outcomes.filter(|(_, o)| !o.is_empty())) {
        (Some((pass, words)), None) => out.line("checks", format!("{}: {words}", verdict(pass))),
        (breaking, Some((c, outcomes))) => {
            let failed =
                outcomes.iter().filter(|o| !o.pass).count() + breaking.as_ref().map_or(0, |b| usize::from(!b.0));
            let total = outcomes.len() + usize::from(breaking.is_some());
            out.line("checks", format!("{}: {failed} of {total} failed", verdict(failed == 0)));
            if let Some((pass, words)) = breaking {
                out.line("", format!("break loads: {words} ({})", if pass { "pass" } else { "FAIL" }));
            }
            for o in &outcomes {
                out.line("", crate::checks::outcome_words(o, c));
            }
        }
        (None, None) => {}
    }
}

/// `v` to `digits` decimals (with its sign when `sign`), a value that rounds to zero as
/// zero: `+0.000`, not the `-0.000` of a round-off below zero.
fn fixed(v: f64, digits: usize, sign: bool) -> String {
    let text = if sign { format!("{v:+.digits$}") } else { format!("{v:.digits$}") };
    if text.trim_start_matches(['+', '-']).chars().all(|c| c == '0' || c == '.') {
        if sign {
            format!("{:+.digits$}", 0.0)
        } else {
            format!("{:.digits$}", 0.0)
        }
    } else {
        text
    }
}

/// The final state and where the energy went.
fn final_lines(out: &mut Lines, model: &Model, result: &RunResult) {
    let (Some(first), Some(last)) = (result.samples.first(), result.samples.last()) else { return };
    let n = model.body_count();
    let ship = &last.bodies[n - 1];
    out.line(
        "final",
        format!(
            "t = {:.3} s: ship moved {} m (surge {} m/s, heave {} m, pitch {} rad); anchor moved {} m",
            last.t,
            fixed(ship.x - first.bodies[n - 1].x, 3, true),
            fixed(ship.vx, 3, true),
            fixed(ship.z, 4, true),
            fixed(ship.theta, 5, true),
            fixed(last.bodies[0].x - first.bodies[0].x, 3, true)
        ),
    );
    let e = &last.energy;
    let works: Vec<String> = e.work_terms().map(|(name, v)| format!("{name} {}", fixed(v / 1e6, 3, false))).collect();
    out.line(
        "balance",
        format!(
            "E_0 = {:.4} MJ; kinetic {:.4}, entrained water {:.4}, potential {:.4} MJ; work done (MJ): {}; max balance drift {:.2e} of the largest kinetic energy {:.4e} J",
            result.energy0 / 1e6,
            e.kinetic / 1e6,
            e.added_kinetic / 1e6,
            e.potential / 1e6,
            works.join(", "),
            result.max_energy_drift,
            result.energy_scale
        ),
    );
}

#[cfg(test)]
mod tests {
    use super::fixed;

    #[test]
    fn a_round_off_below_zero_prints_as_zero() {
        assert_eq!(fixed(-1e-7, 4, true), "+0.0000");
        assert_eq!(fixed(-1e-7, 3, false), "0.000");
        assert_eq!(fixed(-0.0, 3, false), "0.000");
        assert_eq!(fixed(-0.0021, 3, false), "-0.002");
        assert_eq!(fixed(2.998, 3, true), "+2.998");
        assert_eq!(fixed(-2.998, 3, true), "-2.998");
    }
}

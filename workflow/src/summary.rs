//! The one-screen summary of a run: what an engineer reads first.

use std::fmt::Write as _;

use kanestop_runtime::kernel::AnchorDof;
use kanestop_runtime::model::Model;
use kanestop_runtime::simulate::{RunResult, Stop};

use crate::checks::break_exceedances;

/// The one-screen summary of a run.
pub fn summary(model: &Model, result: &RunResult) -> String {
    let mut out = Lines::default();
    scene_lines(&mut out, model, result);
    run_lines(&mut out, model, result);
    outcome_lines(&mut out, model, result);
    tension_lines(&mut out, model, result);
    final_lines(&mut out, model, result);
    out.0
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
fn scene_lines(out: &mut Lines, model: &Model, result: &RunResult) {
    let s = &model.scene;
    out.line("scene", format!("{} — {}", s.meta.name, s.meta.description));
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
    out.line(
        "initial",
        format!(
            "x_L = {} m, h_L = {} m, water depth {:.3} m, {:.2} m of cable on the seabed, ship {} m/s",
            s.initial.horizontal_projection,
            s.initial.vertical_projection,
            model.water_depth(),
            model.catenary.grounded_length(),
            s.initial.ship_speed
        ),
    );
    let residual = match result.initial_residual {
        Some(r) => format!(
            "; at rest, max |a| {:.2e} m/s² on the line (B_{}), {:.2e} m/s² beside the rod (B_{})",
            r.line.0, r.line.1, r.top.0, r.top.1
        ),
        None => String::new(),
    };
    out.line("catenary", format!("cable ends {:.1e} m from (x_L, h_L){residual}", model.cable_end_error()));
}

/// How it was integrated: the solver, its stability limit, the cost.
fn run_lines(out: &mut Lines, model: &Model, result: &RunResult) {
    let solver = &model.scene.solver;
    out.line(
        "solver",
        format!(
            "{}, dt = {} s, end time {} s, kernel {}",
            solver.integrator, solver.dt, solver.end_time, result.kernel
        ),
    );
    if let Some(l) = result.stability {
        out.line(
            "stability",
            format!(
                "RK4 step limit at t = 0: {:.3e} s (fastest mode {:.3e} ± {:.3e}i 1/s; stiffest hinge B_{})",
                l.rk4_dt,
                l.lambda.re,
                l.lambda.im.abs(),
                l.body
            ),
        );
    }
    out.line(
        "run",
        format!(
            "{:.3} s simulated in {:.3} s wall ({} steps, {} right-hand-side evaluations)",
            result.t_end,
            result.wall_time.as_secs_f64(),
            result.steps,
            result.rhs_evaluations
        ),
    );
}

/// Why the run ended, against the paper where the scene names Table 3's value, and the anchor.
fn outcome_lines(out: &mut Lines, model: &Model, result: &RunResult) {
    let paper = |t: f64| match model.scene.meta.paper_stopping_time {
        Some(p) => format!("   paper (Table 3): {p:.3} s, difference {:+.2} %", 100.0 * (t - p) / p),
        None => String::new(),
    };
    match &result.stop {
        Stop::ShipStopped => {
            let t = result.stopping_time.unwrap_or(result.t_end);
            out.line("stopped", format!("ship surge speed reached zero at t = {t:.3} s{}", paper(t)))
        }
        Stop::EndTime => out.line(
            "stopped",
            match result.stopping_time {
                Some(t) => format!("end time reached; ship surge speed first zero at t = {t:.3} s{}", paper(t)),
                None => "end time reached; the ship did not stop".to_string(),
            },
        ),
        Stop::Failed(f) => {
            let text = crate::diagnostic::describe(model, f);
            let first = text.lines().next().unwrap_or_default();
            out.line("FAILED", format!("{first} (diagnostic on standard error)"))
        }
    }
    let anchor = match (model.anchor, result.anchor_start()) {
        (_, Some(t)) => {
            format!("started to slide at t = {t:.3} s ({} stick–slip switches)", result.anchor_events.len())
        }
        (AnchorDof::Stuck, None) => "held by friction throughout".to_string(),
        (AnchorDof::Free, None) => "free (no seabed friction)".to_string(),
    };
    out.line("anchor", anchor);
}

/// The peak tension against its joint's limits, and any break load exceeded.
fn tension_lines(out: &mut Lines, model: &Model, result: &RunResult) {
    let Some((k, peak)) = result.peak_tension() else { return };
    let limits = model.joint_limits(k);
    let limit = |name: &str, v: Option<f64>| {
        v.map(|v| format!(", {name} {:.0} kN ({:.0} %)", v / 1e3, 100.0 * peak.tension / v)).unwrap_or_default()
    };
    out.line(
        "tension",
        format!(
            "peak {:.1} kN at joint {k} ({} – {}) at t = {:.3} s{}{}",
            peak.tension / 1e3,
            model.chain.bodies[k - 2].kind,
            model.chain.bodies[k - 1].kind,
            peak.t,
            limit("proof", limits.proof),
            limit("break", limits.breaking)
        ),
    );
    let over = break_exceedances(model, result);
    if let Some(worst) = over.iter().max_by(|a, b| (a.peak / a.limit).total_cmp(&(b.peak / b.limit))) {
        out.line(
            "WARNING",
            format!(
                "break load exceeded at {} joint(s); worst: joint {}, {:.0} kN > {:.0} kN",
                over.len(),
                worst.joint,
                worst.peak / 1e3,
                worst.limit / 1e3
            ),
        );
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
            "t = {:.3} s: ship moved {:+.3} m (surge {:+.3} m/s, heave {:+.4} m, pitch {:+.5} rad); anchor moved {:+.3} m",
            last.t,
            ship.x - first.bodies[n - 1].x,
            ship.vx,
            ship.z,
            ship.theta,
            last.bodies[0].x - first.bodies[0].x
        ),
    );
    let e = &last.energy;
    let works: Vec<String> = e.work_terms().map(|(name, v)| format!("{name} {:.3}", v / 1e6)).collect();
    out.line(
        "energy",
        format!(
            "E_0 = {:.4} MJ; kinetic {:.4}, entrained water {:.4}, potential {:.4} MJ; work done (MJ): {}; max balance drift {:.2e}",
            result.energy0 / 1e6,
            e.kinetic / 1e6,
            e.added_kinetic / 1e6,
            e.potential / 1e6,
            works.join(", "),
            result.max_energy_drift
        ),
    );
}

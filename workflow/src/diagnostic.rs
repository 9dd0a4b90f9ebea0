//! A numerical failure in words: what was detected, where, the likely cause and what to try.
//!
//! The runtime reports a [`Failure`] as data (time, body, kind); this module names the body
//! ("cable stage 1 (B_18, 27.7 kg, 2.00 m)"), words what was detected and advises which
//! scene field or flag to change for the method the scene uses.

use kanestop_runtime::integrate::StepError;
use kanestop_runtime::model::Model;
use kanestop_runtime::scene::{Method, MAX_STEPS};
use kanestop_runtime::simulate::{Failure, FailureKind, StaticResidual, SPIKE_FACTOR};
use kanestop_runtime::stability::{StabilityError, StabilityLimit};

/// The diagnostic of `failure` in `model`'s run, on several lines: `numerical failure at t =
/// …`, or `refused before the run: …` for a step above the stability limit (bad input, not a
/// failure of the integration).
pub fn describe(model: &Model, failure: &Failure) -> String {
    // Not a numerical failure: `run_cancellable` returns it as `Cancelled`; a caller of
    // `Stepper::start_cancellable` that describes it is told so, without advice.
    if failure.kind == FailureKind::Stability(StabilityError::Cancelled) {
        return "cancelled before the run: the start-up stability analysis was stopped on request".to_string();
    }
    let refused = matches!(failure.kind, FailureKind::StepAboveLimit { .. });
    let (what, cause, suggestion) = match &failure.kind {
        FailureKind::StepAboveLimit { dt, limit } => refusal(*dt, limit),
        kind @ FailureKind::TensionChatter { first_rough, .. } => {
            let (cause, suggestion) = chatter(model, failure.t, *first_rough);
            (what(kind), cause, suggestion)
        }
        kind => {
            let swinging = match kind {
                FailureKind::ForceSpike { swinging, .. } => *swinging,
                _ => failure.body,
            };
            // Without water the ship falls freely from the start: its residual is that fall,
            // not a geometry to fix ([`advice`] says so).
            let (cause, suggestion) = match failure.initial_residual.as_deref() {
                Some(r)
                    if model.scene.environment.water
                        && r.line.0.max(r.top.0) > NOT_STATIC * model.scene.environment.gravity =>
                {
                    not_static(model, failure, swinging, r)
                }
                _ => advice(model, failure, swinging),
            };
            (what(kind), cause, suggestion)
        }
    };
    let head = if refused {
        "refused before the run".to_string()
    } else {
        format!("numerical failure at t = {:.4} s", failure.t)
    };
    format!(
        "{head}: {what}\n  body: {}\n  likely cause: {cause}\n  suggestion: {suggestion}",
        body_name(model, failure.body)
    )
}

/// An initial static residual above this many g, in a run that fails early, is diagnosed as
/// a bad initial state rather than a step too large (case 1 of the paper: 0.34 g, the first
/// cable element bridging the chain's height; the refused h_L = 60 m scene: 0.81 g on the
/// line and 12 g beside the rod).
pub const NOT_STATIC: f64 = 0.5;

/// The cause and suggestion of an early failure from an initial state far from static, its
/// fastest mode at body `k`: the geometry is the likely cause and checked first; a geometry
/// that is as meant (a line laid taut by `initial.top_tension` starts with its vertical rod
/// swinging, docs/model-choices.md) needs the start's transient integrated more finely, as
/// [`advice`] says for the scene's method.
fn not_static(model: &Model, failure: &Failure, k: usize, r: &StaticResidual) -> (String, String) {
    let t = failure.t;
    let cause = format!(
        "the initial state is not static: the run failed {t:.3} s after the start, and at rest (t = 0, anchor held) \
         the line accelerates up to {:.2e} m/s² (B_{}) and {:.2e} m/s² beside the rod (B_{}); the initial \
         geometry is the likely cause",
        r.line.0, r.line.1, r.top.0, r.top.1
    );
    let (_, finer) = advice(model, failure, k);
    let suggestion = format!(
        "check the initial geometry (initial.horizontal_projection, horizontal_tension or top_tension, \
         initial.vertical_projection, the cable stages, rod.length and ship.hinge_z) and the line's weights; if \
         they are as meant, follow the start's transient more finely: {finer}"
    );
    (cause, suggestion)
}

/// "auxiliary rod (B_45, 13.9 kg, 1.00 m)" for body k (1-based).
pub fn body_name(model: &Model, k: usize) -> String {
    let body = &model.chain.bodies[k - 1];
    format!("{} (B_{k}, {:.1} kg, {:.2} m)", body.kind, body.mass, body.length())
}

/// What a run-time failure detected.
fn what(kind: &FailureKind) -> String {
    match kind {
        FailureKind::StepAboveLimit { dt, limit } => refusal(*dt, limit).0,
        FailureKind::Stability(e) => e.to_string(),
        FailureKind::Rhs(e) => e.to_string(),
        FailureKind::Step(e) => e.to_string(),
        FailureKind::NonFiniteState => "non-finite state".to_string(),
        FailureKind::EnergyRunaway { drift, limit, scale } => format!(
            "energy runaway: |E − E_0|/K = {drift:.3e} exceeds solver.max_energy_drift = {} (K = {:.4e} J, \
             the largest kinetic energy before this step)",
            // As a scene writes it: 0.005, 1e-9 (not 0.000000001).
            if *limit >= 1e-3 { format!("{limit}") } else { format!("{limit:e}") },
            scale
        ),
        FailureKind::ForceSpike { joint, force, bound, .. } => format!(
            "constraint-force spike: joint {joint} (B_{} – B_{joint}) carries {force:.3e} N, above {SPIKE_FACTOR} × \
             the line's largest break load ({bound:.3e} N in all; the model has no breaking, so a tension that rose \
             to this smoothly, not in a jump, is a line far too weak for the scene rather than a step too long)",
            joint - 1
        ),
        FailureKind::TensionChatter { joint, ratio, rough, window, .. } => format!(
            "tension chatter: the tension at joint {joint} (B_{} – B_{joint}) jumps from step to step (second \
             difference {ratio:.2} of its size), and the line's tensions did so at {rough} of the last {window} \
             steps: the step no longer resolves them",
            joint - 1
        ),
    }
}

/// The refusal of an RK4 step `dt` (s) above the stability limit: (what, cause, suggestion).
fn refusal(dt: f64, limit: &StabilityLimit) -> (String, String, String) {
    let (re, im) = (limit.lambda.re, limit.lambda.im.abs());
    let what = format!(
        "solver.dt = {dt} s is above this scene's RK4 stability limit at t = 0 of {:.3e} s: valid range 0 < dt ≤ {:.3e} s",
        limit.rk4_dt, limit.rk4_dt
    );
    let cause = format!(
        "the fastest mode of the linearised equations at t = 0 (eigenvalue {re:.3e} ± {im:.3e}i 1/s, period \
         {:.3e} s) would grow without bound at this step",
        if im > 0.0 { 2.0 * std::f64::consts::PI / im } else { f64::INFINITY }
    );
    let suggestion = format!(
        "set solver.dt ≤ {:.1e} s, or integrator = \"dp5\" (adapts its step) or \"sdirk4\" (stiff); the limit is \
         the start's: a line that tightens or presses into the seabed may need a smaller step later, which the \
         run's checks report",
        LIMIT_MARGIN * limit.rk4_dt
    );
    (what, cause, suggestion)
}

/// The cause and suggestion of RK4's tensions chattering at `t` (s), the run's first rough
/// step `first_rough` steps before: a mode faster than the linearised equations had at
/// t = 0 (the limit RK4's step was checked against), as the line tightens or, on a seabed,
/// presses into it. A step a little inside that mode's limit is enough, so the suggestion
/// halves it (k_z × 1e4: 1 ms chatters, 0.5 ms runs cleanly).
fn chatter(model: &Model, t: f64, first_rough: u64) -> (String, String) {
    let solver = &model.scene.solver;
    let dt = solver.dt;
    let stiffer = if model.scene.environment.seabed {
        "the seabed's contact stiffens as the line is pressed into it, and a tightening line's modes quicken \
         with its tension"
    } else {
        "a tightening line's modes quicken with its tension"
    };
    let from = (t - first_rough as f64 * dt).max(0.0);
    let cause = format!(
        "the explicit step dt = {dt} s is at the edge of a mode faster than any at t = 0, where its stability limit \
         was checked: {stiffer}; the tensions were first rough at t = {from:.3} s, and the peaks taken from them since \
         are suspect"
    );
    let kept = format!("the first {:.3} s up to the failure are kept", (t - dt).max(0.0));
    let floor = solver.end_time / MAX_STEPS;
    let suggestion = if dt / 2.0 >= floor {
        format!("halve solver.dt (try {:.1e} s, and again if the tensions still chatter) or use integrator = \"dp5\"; {kept}", dt / 2.0)
    } else {
        format!("use integrator = \"dp5\" (solver.dt is at its smallest for end_time {} s); {kept}", solver.end_time)
    };
    (cause, suggestion)
}

/// RK4's cause and suggestion, from its stability limit at the last good state where the run
/// computed it ([`Failure::last_limit`]): below `dt`, the mode stiffened during the run and a
/// step within that limit and at most half the failed one is advised (case 1 blown up at
/// 15 ms: 6.3 ms at t = 1.455 s, so 5.6 ms, which completes; at 20 ms: 10 ms); at or above
/// it, the linearisation does not explain the blow-up, and a much finer step is advised
/// ([`rk4_suggestion`]).
fn rk4_advice(failure: &Failure, dt: f64, end_time: f64, mode: &str, kept: &str) -> (String, String) {
    let cause = format!("the explicit step dt = {dt} s is beyond the stability limit of {mode}");
    let last = format!("the last good state (t = {:.3} s)", (failure.t - dt).max(0.0));
    match failure.last_limit.as_deref() {
        Some(l) if l.rk4_dt < dt => {
            let cause = format!(
                "{cause}, which stiffened during the run: RK4's limit at {last} is {:.3e} s (its stiffest hinge at \
                 B_{}), below the step",
                l.rk4_dt, l.body
            );
            // The state is the blown-up run's, maybe before its stiffest (case 1 at 20 ms fails
            // at 1.38 s, before the peak tension, where the limit is 15.2 ms; 15 ms fails too):
            // at most half the step.
            let within = (LIMIT_MARGIN * l.rk4_dt).min(dt / 2.0);
            let suggestion = if within >= end_time / MAX_STEPS {
                format!(
                    "reduce solver.dt to {within:.1e} s (at most {LIMIT_MARGIN} of that limit and half the step; a \
                     state still to come may need less) or use integrator = \"dp5\"; {kept}"
                )
            } else {
                rk4_suggestion(dt, end_time, kept)
            };
            (cause, suggestion)
        }
        Some(l) => (
            format!(
                "{cause}, though RK4's linearised limit at {last} is {:.3e} s, above the step: the blow-up came \
                 with a change the linearisation does not see (a seabed contact made or lost, a snap load)",
                l.rk4_dt
            ),
            rk4_suggestion(dt, end_time, kept),
        ),
        None => (cause, rk4_suggestion(dt, end_time, kept)),
    }
}

/// The share of a stability limit advised as the step: the start's refusal advises the same.
const LIMIT_MARGIN: f64 = 0.9;

/// Reduce the step 16-fold, never below the smallest step a scene may ask for
/// (end_time / `MAX_STEPS`); at that floor, the adaptive methods instead.
fn rk4_suggestion(dt: f64, end_time: f64, kept: &str) -> String {
    let floor = end_time / MAX_STEPS;
    if dt / 16.0 >= floor {
        format!("reduce solver.dt (try {:.1e} s) or use integrator = \"dp5\"; {kept}", dt / 16.0)
    } else if dt > floor {
        format!("reduce solver.dt (try {floor:.1e} s, the smallest for end_time {end_time} s) or use integrator = \"dp5\"; {kept}")
    } else {
        format!(
            "a smaller step is not sensible (solver.dt ≥ end_time / {MAX_STEPS:e}): use integrator = \"dp5\" or \"sdirk4\", or check the initial state; {kept}"
        )
    }
}

/// A failing body between two others this many times lighter than the heaviest, or more, is
/// diagnosed as a light element swinging between heavy neighbours (case 1: a cable element is
/// 18 048 times lighter than the ship); a heavier one is not, nor an end of the line.
const LIGHT: f64 = 3.0;

/// The likely cause and what to try for `failure`, whose unstable mode lives at body `k`
/// (1-based), for the scene's method.
fn advice(model: &Model, failure: &Failure, k: usize) -> (String, String) {
    let t = failure.t;
    let body = &model.chain.bodies[k - 1];
    let solver = &model.scene.solver;
    let dt = solver.dt;
    let ratio = model.chain.bodies.iter().map(|b| b.mass).fold(0.0, f64::max) / body.mass;
    // Not a light element: an end of the line (the anchor, the ship), or a body nearly as
    // heavy as the heaviest. What stiffened is a load on it (a tension, the seabed's contact
    // or drag, growing with the motion).
    let grown = "a stiffness that grew with the motion, such as the line's tension, its contact with the seabed or \
                 its drag";
    let mode = if k == 1 || k == model.body_count() {
        format!("the stiffest mode, at an end of the line (not a light element between heavy neighbours): {grown}")
    } else if ratio < LIGHT {
        format!(
            "the stiffest mode, at a body within {LIGHT}× of the heaviest's mass (not a light element between heavy \
             neighbours): {grown}"
        )
    } else {
        let ratio = if ratio < 1e6 { format!("{ratio:.0}") } else { format!("{ratio:.2e}") };
        format!(
            "the stiffest mode: a light element swinging between heavy neighbours under high tension (mass ratio \
             {ratio}:1 with the heaviest body)"
        )
    };
    let kept = if t - dt > 0.0 {
        format!("the first {:.3} s up to the failure are kept", t - dt)
    } else {
        "it failed in the first interval, so only the initial state is kept".to_string()
    };
    let shrank =
        matches!(failure.kind, FailureKind::Step(StepError::StepSizeCollapse { .. } | StepError::TooManySteps { .. }));
    let tolerances = format!(
        "the tolerances (solver.rtol = {}, solver.atol = {})",
        kanestop_runtime::scene::fmt_value(solver.rtol),
        kanestop_runtime::scene::fmt_value(solver.atol)
    );
    let (cause, suggestion) = match solver.integrator {
        Method::Rk4 => rk4_advice(failure, dt, solver.end_time, &mode, &kept),
        // The steps shrank to nothing: tighter tolerances would only shrink them sooner.
        Method::Dp5 if shrank => (
            format!("the error-controlled steps could not follow {mode}"),
            format!("use integrator = \"sdirk4\" (stiff), or loosen {tolerances}; {kept}"),
        ),
        Method::Dp5 => (
            format!("the error-controlled steps could not follow {mode}"),
            format!("tighten solver.rtol (now {}) or use integrator = \"sdirk4\"; {kept}", solver.rtol),
        ),
        Method::Sdirk4 if shrank => (
            format!("the implicit method's Newton iterations or error control failed on {mode}"),
            format!("loosen {tolerances}, or reduce solver.dt (now {dt} s, its longest step); {kept}"),
        ),
        Method::Sdirk4 => (
            format!("the implicit method's Newton iterations or error control failed on {mode}"),
            format!("tighten solver.rtol (now {}) or reduce solver.dt (now {dt} s); {kept}", solver.rtol),
        ),
    };
    if model.scene.environment.water {
        return (cause, suggestion);
    }
    // Without water nothing holds the ship up (no hydrostatics, Eqs. 53–58): it falls onto
    // the line, which is what stiffens it (tests/cli.rs runs such a scene).
    (
        format!(
            "without water (environment.water = false) nothing holds the ship up: it falls freely and drops its \
             weight onto the line; then {cause}"
        ),
        format!("for a ship afloat, environment.water = true; as it is, {suggestion}"),
    )
}

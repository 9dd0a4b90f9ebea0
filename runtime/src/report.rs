//! Reports read results; they compute nothing physical.
//!
//! [`summary`] is the one-screen text of a run; [`csv`] the time history. Files are
//! written whole or not at all ([`write_atomically`]).

use std::fmt::Write as _;
use std::io::Write as _;
use std::path::Path;

use kanestop_codegen::BodyKind;

use crate::forces::WORK_TERMS;
use crate::kernel::AnchorDof;
use crate::model::Model;
use crate::simulate::{RunResult, Stop};

/// Load limits of the joint between B_{k−1} and B_k: (proof load, break load) in N, the
/// weaker of the two bodies' (chain: Table 1; cable and rod: the cable's break load).
pub fn joint_limits(model: &Model, k: usize) -> (Option<f64>, Option<f64>) {
    let s = &model.scene;
    let limits = |kind: BodyKind| match kind {
        BodyKind::ChainLink => (Some(s.chain.proof_load), Some(s.chain.break_load)),
        BodyKind::Cable { .. } | BodyKind::Rod => (None, Some(s.cable.break_load)),
        BodyKind::Anchor | BodyKind::Ship => (None, None),
    };
    let (a, b) = (limits(model.chain.bodies[k - 2].kind), limits(model.chain.bodies[k - 1].kind));
    let min = |x: Option<f64>, y: Option<f64>| match (x, y) {
        (Some(x), Some(y)) => Some(x.min(y)),
        (x, None) => x,
        (None, y) => y,
    };
    (min(a.0, b.0), min(a.1, b.1))
}

/// Joints whose peak tension exceeded their break load (k, peak N, limit N).
pub fn break_exceedances(model: &Model, result: &RunResult) -> Vec<(usize, f64, f64)> {
    result
        .peak_tensions
        .iter()
        .enumerate()
        .filter_map(|(i, p)| {
            let k = i + 2;
            joint_limits(model, k).1.filter(|&limit| p.tension > limit).map(|limit| (k, p.tension, limit))
        })
        .collect()
}

/// The one-screen summary of a run.
pub fn summary(model: &Model, result: &RunResult) -> String {
    let s = &model.scene;
    let mut out = String::new();
    let n = model.body_count();
    let w = |out: &mut String, label: &str, text: String| {
        let _ = writeln!(out, "{label:<10}{text}");
    };
    w(&mut out, "scene", format!("{} — {}", s.meta.name, s.meta.description));
    w(&mut out, "physics", result.physics.clone());
    let stages: Vec<String> =
        s.cable.stages.iter().map(|st| format!("{}×{} m", st.elements, st.element_length)).collect();
    w(
        &mut out,
        "bodies",
        format!(
            "N = {n}: anchor {:.1} t, {} chain links × {} m, cable {} = {:.1} m, rod {} m, ship {:.1} t",
            s.anchor.mass / 1e3,
            s.chain.elements,
            s.chain.element_length,
            stages.join(" + "),
            s.cable_length(),
            s.rod.length,
            s.ship.mass / 1e3
        ),
    );
    w(
        &mut out,
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
    let end = model.cable_end_error();
    let residual = match result.initial_residual {
        Some(r) => format!(
            "; at rest, max |a| {:.2e} m/s² on the line (B_{}), {:.2e} m/s² beside the rod (B_{})",
            r.line.0, r.line.1, r.top.0, r.top.1
        ),
        None => String::new(),
    };
    w(&mut out, "catenary", format!("cable ends {end:.1e} m from (x_L, h_L){residual}"));
    w(
        &mut out,
        "solver",
        format!(
            "{}, dt = {} s, end time {} s, kernel {}",
            format!("{:?}", s.solver.integrator).to_lowercase(),
            s.solver.dt,
            s.solver.end_time,
            result.kernel
        ),
    );
    if let Some(l) = result.stability {
        w(
            &mut out,
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
    w(
        &mut out,
        "run",
        format!(
            "{:.3} s simulated in {:.3} s wall ({} steps, {} right-hand-side evaluations)",
            result.t_end,
            result.wall_time.as_secs_f64(),
            result.steps,
            result.rhs_evaluations
        ),
    );
    let paper = |t: f64| match s.meta.paper_stopping_time {
        Some(p) => format!("   paper (Table 3): {p:.3} s, difference {:+.2} %", 100.0 * (t - p) / p),
        None => String::new(),
    };
    match &result.stop {
        Stop::ShipStopped => {
            let t = result.stopping_time.unwrap_or(result.t_end);
            w(&mut out, "stopped", format!("ship surge speed reached zero at t = {t:.3} s{}", paper(t)))
        }
        Stop::EndTime => w(
            &mut out,
            "stopped",
            match result.stopping_time {
                Some(t) => format!("end time reached; ship surge speed first zero at t = {t:.3} s{}", paper(t)),
                None => "end time reached; the ship did not stop".to_string(),
            },
        ),
        Stop::Failed(f) => w(&mut out, "FAILED", f.to_string().replace('\n', "\n          ")),
    }
    let anchor = match (model.anchor, result.anchor_start()) {
        (_, Some(t)) => {
            format!("started to slide at t = {t:.3} s ({} stick–slip switches)", result.anchor_events.len())
        }
        (AnchorDof::Stuck, None) => "held by friction throughout".to_string(),
        (AnchorDof::Free, None) => "free (no seabed friction)".to_string(),
    };
    w(&mut out, "anchor", anchor);
    if let Some((k, peak)) = result.peak_tension() {
        let (proof, brk) = joint_limits(model, k);
        let limit = |name: &str, v: Option<f64>| {
            v.map(|v| format!(", {name} {:.0} kN ({:.0} %)", v / 1e3, 100.0 * peak.tension / v)).unwrap_or_default()
        };
        w(
            &mut out,
            "tension",
            format!(
                "peak {:.1} kN at joint {k} ({} – {}) at t = {:.3} s{}{}",
                peak.tension / 1e3,
                model.chain.bodies[k - 2].kind,
                model.chain.bodies[k - 1].kind,
                peak.t,
                limit("proof", proof),
                limit("break", brk)
            ),
        );
        let over = break_exceedances(model, result);
        if let Some((k, p, l)) = over.iter().max_by(|a, b| (a.1 / a.2).total_cmp(&(b.1 / b.2))) {
            w(
                &mut out,
                "WARNING",
                format!(
                    "break load exceeded at {} joint(s); worst: joint {k}, {:.0} kN > {:.0} kN",
                    over.len(),
                    p / 1e3,
                    l / 1e3
                ),
            );
        }
    }
    if let Some(last) = result.samples.last() {
        let ship = &last.bodies[n - 1];
        let first = &result.samples[0].bodies;
        w(
            &mut out,
            "final",
            format!(
                "t = {:.3} s: ship moved {:+.3} m (surge {:+.3} m/s, heave {:+.4} m, pitch {:+.5} rad); anchor moved {:+.3} m",
                last.t,
                ship.x - first[n - 1].x,
                ship.vx,
                ship.z,
                ship.theta,
                last.bodies[0].x - first[0].x
            ),
        );
        let e = &last.energy;
        let works: Vec<String> = e.work_terms().map(|(name, v)| format!("{name} {:.3}", v / 1e6)).collect();
        w(
            &mut out,
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
    out
}

/// The CSV time history: t, anchor state, the energy terms, then x, z, θ, vx, vz, ω of every
/// body, then the tension at every joint.
pub fn csv(result: &RunResult) -> String {
    let mut out = String::from("t,anchor_sliding,E_kinetic,E_added_kinetic,E_potential");
    for name in WORK_TERMS {
        let _ = write!(out, ",W_{name}");
    }
    out.push_str(",E_balance");
    let n = result.samples.first().map_or(0, |s| s.bodies.len());
    for k in 1..=n {
        for q in ["x", "z", "theta", "vx", "vz", "omega"] {
            let _ = write!(out, ",{q}_{k}");
        }
    }
    for k in 2..=n {
        let _ = write!(out, ",T_{k}");
    }
    out.push('\n');
    for s in &result.samples {
        let e = &s.energy;
        let _ = write!(
            out,
            "{},{},{:e},{:e},{:e}",
            s.t,
            (s.anchor == AnchorDof::Free) as u8,
            e.kinetic,
            e.added_kinetic,
            e.potential
        );
        for w in e.work {
            let _ = write!(out, ",{w:e}");
        }
        let _ = write!(out, ",{:e}", e.balance());
        for b in &s.bodies {
            let _ = write!(out, ",{:e},{:e},{:e},{:e},{:e},{:e}", b.x, b.z, b.theta, b.vx, b.vz, b.omega);
        }
        for t in &s.tensions {
            let _ = write!(out, ",{t:e}");
        }
        out.push('\n');
    }
    out
}

/// Writes the CSV time history to `path`, whole or not at all.
pub fn write_csv(result: &RunResult, path: &Path) -> std::io::Result<()> {
    write_atomically(path, csv(result).as_bytes())
}

/// Writes `bytes` to a temporary file beside `path`, then renames it into place, so a
/// reader never sees a partial file and a failed write leaves any old file untouched.
pub fn write_atomically(path: &Path, bytes: &[u8]) -> std::io::Result<()> {
    let dir = path.parent().filter(|p| !p.as_os_str().is_empty()).unwrap_or(Path::new("."));
    let name = path.file_name().ok_or_else(|| std::io::Error::other("output path has no file name"))?;
    let tmp = dir.join(format!(".{}.tmp{}", name.to_string_lossy(), std::process::id()));
    let result = (|| {
        let mut f = std::fs::File::create(&tmp)?;
        f.write_all(bytes)?;
        f.sync_all()?;
        std::fs::rename(&tmp, path)
    })();
    if result.is_err() {
        let _ = std::fs::remove_file(&tmp);
    }
    result
}

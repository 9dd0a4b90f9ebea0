//! Reports read results; they compute nothing physical.
//!
//! [`summary`] is the one-screen text of a run; [`write_csv`] the time history. Files are
//! written whole or not at all ([`write_atomically`]).

use std::fmt::Write as _;
use std::io::Write as _;
use std::path::Path;

use crate::forces::PHYSICS;
use crate::kernel::AnchorDof;
use crate::model::Model;
use crate::simulate::{RunResult, Stop};

/// The one-screen summary of a run.
pub fn summary(model: &Model, result: &RunResult) -> String {
    let s = &model.scene;
    let mut out = String::new();
    let n = model.body_count();
    let w = |out: &mut String, label: &str, text: String| {
        let _ = writeln!(out, "{label:<10}{text}");
    };
    w(&mut out, "scene", format!("{} — {}", s.meta.name, s.meta.description));
    w(&mut out, "physics", PHYSICS.to_string());
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
    let anchor = match model.anchor {
        AnchorDof::Stuck => "held on the seabed (stick–slip friction not modelled yet)",
        AnchorDof::Free => "free to slide (frictionless)",
    };
    w(&mut out, "anchor", anchor.to_string());
    w(
        &mut out,
        "solver",
        format!(
            "{:?}, dt = {} s, end time {} s, kernel {}",
            s.solver.integrator, s.solver.dt, s.solver.end_time, result.kernel
        )
        .to_lowercase(),
    );
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
    let paper = s.meta.paper_stopping_time.map(|t| format!(" (paper, Table 3: {t:.3} s)")).unwrap_or_default();
    match &result.stop {
        Stop::ShipStopped => w(
            &mut out,
            "stopped",
            format!("ship surge speed reached zero at t = {:.3} s{paper}", result.stopping_time.unwrap()),
        ),
        Stop::EndTime => w(
            &mut out,
            "stopped",
            match result.stopping_time {
                Some(t) => format!("end time reached; ship surge speed first zero at t = {t:.3} s{paper}"),
                None => format!("end time reached; the ship did not stop{paper}"),
            },
        ),
        Stop::Failed(f) => w(&mut out, "FAILED", f.to_string().replace('\n', "\n          ")),
    }
    if let Some(last) = result.samples.last() {
        let ship = &last.bodies[n - 1];
        let anchor = &last.bodies[0];
        let first = &result.samples[0].bodies;
        w(
            &mut out,
            "final",
            format!(
                "t = {:.3} s: ship x = {:+.3} m, z = {:+.3} m, surge {:+.3} m/s, pitch {:+.4} rad; anchor moved {:+.3} m",
                last.t,
                ship.x,
                ship.z,
                ship.vx,
                ship.theta,
                anchor.x - first[0].x
            ),
        );
        w(
            &mut out,
            "energy",
            format!(
                "E_0 = {:.4e} J, E = {:.4e} J (kinetic {:.4e}, potential {:.4e}), max drift {:.2e}",
                result.energy0,
                last.energy.total(),
                last.energy.kinetic,
                last.energy.potential,
                result.max_energy_drift
            ),
        );
    }
    out
}

/// The CSV time history: t, the energy terms, then x, z, θ, vx, vz, ω of every body.
pub fn csv(result: &RunResult) -> String {
    let mut out = String::from("t,E_kinetic,E_potential,E_total");
    let n = result.samples.first().map_or(0, |s| s.bodies.len());
    for k in 1..=n {
        for q in ["x", "z", "theta", "vx", "vz", "omega"] {
            let _ = write!(out, ",{q}_{k}");
        }
    }
    out.push('\n');
    for s in &result.samples {
        let _ = write!(out, "{},{:e},{:e},{:e}", s.t, s.energy.kinetic, s.energy.potential, s.energy.total());
        for b in &s.bodies {
            let _ = write!(out, ",{:e},{:e},{:e},{:e},{:e},{:e}", b.x, b.z, b.theta, b.vx, b.vz, b.omega);
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

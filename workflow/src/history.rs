//! The time history of a run as CSV.

use std::fmt::Write as _;
use std::path::Path;

use kanestop_runtime::forces::WORK_TERMS;
use kanestop_runtime::kernel::AnchorDof;
use kanestop_runtime::simulate::RunResult;

use crate::output::write_atomically;

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

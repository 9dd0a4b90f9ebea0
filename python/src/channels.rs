//! The names of `result.channels`, in one place (docs/python.md lists them).
//!
//! Role names first (`t`, `ship_x`, `ship_vx`, `anchor_x`, `anchor_sliding`,
//! `tension_fairlead`, `tension_anchor`), then the energy terms, then every body's
//! `x_k`, `z_k`, `theta_k`, `vx_k`, `vz_k`, `omega_k` (k = 1 anchor … N ship) and every
//! joint's tension `T_k` (k = 2 … N, between B_{k−1} and B_k), as the CSV history has them.

use kanestop_runtime::forces::REPORTED_WORK;
use kanestop_runtime::kernel::AnchorDof;
use kanestop_runtime::simulate::{RunResult, Sample};

/// Per-body quantities, in column order.
const BODY: [&str; 6] = ["x", "z", "theta", "vx", "vz", "omega"];

/// Every channel of `result`, as (name, one value per sample).
pub fn channels(result: &RunResult) -> Vec<(String, Vec<f64>)> {
    let s = &result.samples;
    let n = s.first().map_or(0, |s| s.bodies.len());
    let col = |f: &dyn Fn(&Sample) -> f64| s.iter().map(f).collect::<Vec<f64>>();
    let mut out: Vec<(String, Vec<f64>)> = Vec::with_capacity(16 + 7 * n);
    out.push(("t".into(), col(&|s| s.t)));
    if n > 0 {
        out.push(("ship_x".into(), col(&|s| s.bodies[n - 1].x)));
        out.push(("ship_vx".into(), col(&|s| s.bodies[n - 1].vx)));
        out.push(("anchor_x".into(), col(&|s| s.bodies[0].x)));
    }
    out.push(("anchor_sliding".into(), col(&|s| f64::from(u8::from(s.anchor == AnchorDof::Free)))));
    if n > 1 {
        out.push(("tension_fairlead".into(), col(&|s| s.tensions[n - 2])));
        out.push(("tension_anchor".into(), col(&|s| s.tensions[0])));
    }
    out.push(("E_kinetic".into(), col(&|s| s.energy.kinetic)));
    out.push(("E_added_kinetic".into(), col(&|s| s.energy.added_kinetic)));
    out.push(("E_potential".into(), col(&|s| s.energy.potential)));
    for (i, name) in REPORTED_WORK.iter().enumerate() {
        out.push((format!("W_{name}"), col(&|s| s.energy.reported_work()[i].1)));
    }
    out.push(("E_balance".into(), col(&|s| s.energy.balance())));
    for k in 0..n {
        for (j, q) in BODY.iter().enumerate() {
            let value = |s: &Sample| {
                let b = &s.bodies[k];
                [b.x, b.z, b.theta, b.vx, b.vz, b.omega][j]
            };
            out.push((format!("{q}_{}", k + 1), col(&value)));
        }
    }
    for k in 2..=n {
        out.push((format!("T_{k}"), col(&|s| s.tensions[k - 2])));
    }
    out
}

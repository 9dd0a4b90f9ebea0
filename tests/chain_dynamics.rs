//! Dynamics of small chains with the reference kernel and RK4: known periods, energy
//! conservation, measured convergence order and momentum conservation.

mod common;

use std::f64::consts::{FRAC_PI_2, PI};

use common::*;
use kanestop_runtime::kernel::AnchorDof;

#[test]
fn single_pendulum_small_angle_period() {
    // One 2 m rod hinged to a stuck anchor: T = 2π √(I_o / (m g L/2)) = 2π √(2L / 3g).
    let len = 2.0;
    let chain = rod_chain(1e4, &[(len, 10.0)]);
    let amplitude = 1e-3;
    let q = [FRAC_PI_2 + amplitude, 0.0]; // hanging straight down is θ = π/2
    let u = [0.0, 0.0];
    let exact = 2.0 * PI * (2.0 * len / (3.0 * G)).sqrt();
    let dt = 1e-3;
    let mut crossings = Vec::new();
    let mut prev = (0.0, amplitude);
    integrate(&chain, AnchorDof::Stuck, &q, &u, dt, (6.0 * exact / dt) as usize, |t, y, _| {
        let x = y[0] - FRAC_PI_2;
        if prev.1 < 0.0 && x >= 0.0 {
            crossings.push(prev.0 + (t - prev.0) * (-prev.1) / (x - prev.1));
        }
        prev = (t, x);
    });
    assert!(crossings.len() >= 5, "{} upward crossings", crossings.len());
    let period = (crossings.last().unwrap() - crossings[0]) / (crossings.len() - 1) as f64;
    let rel = (period - exact).abs() / exact;
    assert!(rel < 1e-4, "period {period} s vs {exact} s: relative error {rel:e}");
}

/// Five bodies: a stuck anchor and four rods of different masses, released from a bent shape.
fn hanging_chain() -> (kanestop_runtime::chain::Chain, [f64; 5], [f64; 5]) {
    let chain = rod_chain(2e4, &[(1.0, 140.0), (2.0, 14.0), (1.5, 60.0), (1.0, 30.0)]);
    let q = [0.9, 0.4, -0.5, 0.7, 0.0];
    let u = [0.0, 0.3, -0.2, 0.1, 0.0];
    (chain, q, u)
}

#[test]
fn hanging_chain_conserves_energy() {
    let (chain, q, u) = hanging_chain();
    let mut e0 = None;
    let mut worst: f64 = 0.0;
    let dt = 1e-4;
    integrate(&chain, AnchorDof::Stuck, &q, &u, dt, (10.0 / dt) as usize, |_, _, bodies| {
        let e = energy(&chain, bodies);
        let e0 = *e0.get_or_insert(e);
        worst = worst.max((e - e0).abs() / e0.abs());
    });
    assert!(worst < 1e-8, "relative energy drift {worst:e} over 10 s");
}

#[test]
fn rk4_converges_at_fourth_order_on_the_chain() {
    let (chain, q, u) = hanging_chain();
    let t_end = 2.0;
    let run = |dt: f64| integrate(&chain, AnchorDof::Stuck, &q, &u, dt, (t_end / dt).round() as usize, |_, _, _| {});
    let fine = run(2.5e-4);
    let err = |dt: f64| -> f64 { run(dt).iter().zip(&fine).map(|(a, b)| (a - b).abs()).fold(0.0, f64::max) };
    let (e1, e2) = (err(4e-3), err(2e-3));
    let ratio = e1 / e2;
    assert!((12.0..20.0).contains(&ratio), "errors {e1:e}, {e2:e}: ratio {ratio} (16 for fourth order)");
}

#[test]
fn free_anchor_conserves_horizontal_momentum() {
    // Frictionless anchor, gravity only: no external horizontal force acts.
    let (chain, q, mut u) = hanging_chain();
    u[4] = 0.5; // the anchor slides
    let momentum = |bodies: &[kanestop_runtime::kernel::BodyState]| -> (f64, f64) {
        let p: f64 = chain.bodies.iter().zip(bodies).map(|(b, s)| b.mass * s.vx).sum();
        let scale: f64 = chain.bodies.iter().zip(bodies).map(|(b, s)| b.mass * s.vx.abs()).sum();
        (p, scale)
    };
    let mut p0 = None;
    let mut worst: f64 = 0.0;
    integrate(&chain, AnchorDof::Free, &q, &u, 1e-4, 20_000, |_, _, bodies| {
        let (p, scale) = momentum(bodies);
        let p0 = *p0.get_or_insert((p, scale));
        worst = worst.max((p - p0.0).abs() / p0.1);
    });
    assert!(worst < 1e-10, "relative change of horizontal momentum {worst:e}");
}

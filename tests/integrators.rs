//! The integrators, measured: orders of convergence on a linear problem and on a small
//! gravity-only chain through the public API, dense output, error control, FSAL, stiff
//! stability, and the errors (step-size collapse, invalid tolerances).

mod common;

use common::{rod_chain, G};
use kanestop_runtime::dynamics::{Dynamics, WORK_COUNT};
use kanestop_runtime::forces::Forces;
use kanestop_runtime::integrate::{
    Adaptive, AdaptiveIntegrator, Dp5, Integrator, OdeSystem, RhsError, Rk4, Sdirk4, StepError,
};
use kanestop_runtime::kernel::{AnchorDof, BodyAcceleration};
use kanestop_runtime::reference::ReferenceKernel;

/// y'' = −ω² y as (y, y'), y(0) = 1, y'(0) = 0.
struct Oscillator {
    omega: f64,
}

impl Oscillator {
    fn exact(&self, t: f64) -> [f64; 2] {
        [(self.omega * t).cos(), -self.omega * (self.omega * t).sin()]
    }
}

impl OdeSystem for Oscillator {
    fn dim(&self) -> usize {
        2
    }
    fn rhs(&mut self, _t: f64, y: &[f64], dy: &mut [f64]) -> Result<(), RhsError> {
        dy[0] = y[1];
        dy[1] = -self.omega * self.omega * y[0];
        Ok(())
    }
}

/// A linear system with eigenvalues λ1 (stiff) and λ2 (slow): y' = M y, M = P diag(λ) P⁻¹
/// with P = [[1, 1], [1, −1]].
struct StiffLinear {
    l1: f64,
    l2: f64,
    evaluations: u64,
}

impl StiffLinear {
    fn new(l1: f64, l2: f64) -> Self {
        StiffLinear { l1, l2, evaluations: 0 }
    }
    /// y(0) = (2, 0): both modes excited with weight 1.
    fn exact(&self, t: f64) -> [f64; 2] {
        let (a, b) = ((self.l1 * t).exp(), (self.l2 * t).exp());
        [a + b, a - b]
    }
}

impl OdeSystem for StiffLinear {
    fn dim(&self) -> usize {
        2
    }
    fn rhs(&mut self, _t: f64, y: &[f64], dy: &mut [f64]) -> Result<(), RhsError> {
        self.evaluations += 1;
        let (p, m) = (0.5 * (self.l1 + self.l2), 0.5 * (self.l1 - self.l2));
        dy[0] = p * y[0] + m * y[1];
        dy[1] = m * y[0] + p * y[1];
        Ok(())
    }
}

/// ẏ = y², y(0) = 1: y = 1/(1 − t) blows up at t = 1.
struct BlowUp;

impl OdeSystem for BlowUp {
    fn dim(&self) -> usize {
        1
    }
    fn rhs(&mut self, _t: f64, y: &[f64], dy: &mut [f64]) -> Result<(), RhsError> {
        dy[0] = y[0] * y[0];
        Ok(())
    }
}

/// A stiff component relaxing onto a moving nonlinear manifold: y1' = −y1²,
/// y2' = λ (y2 − y1²) − 2 y1³. With e = y2 − y1², e' = λ e, so from y(0) = (1, 1 + e0)
/// y1 = 1/(1 + t), y2 = y1² + e0 e^{λt}. J = [[−2 y1, 0], [−2λ y1 − 6 y1², λ]] changes along
/// the solution, in its large entry too.
struct StiffManifold {
    lambda: f64,
}

impl StiffManifold {
    const E0: f64 = 1.0;
    fn exact(&self, t: f64) -> [f64; 2] {
        let y1 = 1.0 / (1.0 + t);
        [y1, y1 * y1 + Self::E0 * (self.lambda * t).exp()]
    }
}

impl OdeSystem for StiffManifold {
    fn dim(&self) -> usize {
        2
    }
    fn rhs(&mut self, _t: f64, y: &[f64], dy: &mut [f64]) -> Result<(), RhsError> {
        dy[0] = -y[0] * y[0];
        dy[1] = self.lambda * (y[1] - y[0] * y[0]) - 2.0 * y[0].powi(3);
        Ok(())
    }
}

/// The run driver's use of an adaptive method: `count` observation intervals of `dt` from
/// (t0, y), each after [`Integrator::reset`] (→ [`AdaptiveIntegrator::invalidate`]).
fn intervals(method: &mut dyn Integrator, sys: &mut dyn OdeSystem, y: &mut [f64], t0: f64, dt: f64, count: usize) {
    for i in 0..count {
        method.reset();
        method.step(sys, t0 + i as f64 * dt, y, dt).unwrap();
    }
}

fn fixed(method: &mut dyn Integrator, sys: &mut dyn OdeSystem, y0: &[f64], t_end: f64, steps: usize) -> Vec<f64> {
    let mut y = y0.to_vec();
    let h = t_end / steps as f64;
    for i in 0..steps {
        method.step(sys, i as f64 * h, &mut y, h).unwrap();
    }
    y
}

fn max_diff(a: &[f64], b: &[f64]) -> f64 {
    a.iter().zip(b).map(|(x, y)| (x - y).abs()).fold(0.0, f64::max)
}

/// Observed orders log2(e(h)/e(h/2)) for step counts n, 2n, 4n.
fn orders(errors: &[f64]) -> Vec<f64> {
    errors.windows(2).map(|w| (w[0] / w[1]).log2()).collect()
}

// ---------------------------------------------------------------- linear problem

#[test]
fn rk4_is_fourth_order_on_the_oscillator() {
    let mut osc = Oscillator { omega: 2.0 };
    let exact = osc.exact(3.0);
    let errs: Vec<f64> = [30, 60, 120]
        .iter()
        .map(|&n| max_diff(&fixed(&mut Rk4::new(2), &mut osc, &[1.0, 0.0], 3.0, n), &exact))
        .collect();
    for p in orders(&errs) {
        assert!((p - 4.0).abs() < 0.15, "RK4 order {p} (errors {errs:?})");
    }
}

#[test]
fn dp5_is_fifth_order_in_fixed_steps() {
    let mut osc = Oscillator { omega: 2.0 };
    let exact = osc.exact(3.0);
    let errs: Vec<f64> = [60, 120, 240]
        .iter()
        .map(|&n| max_diff(&fixed(&mut Dp5::new(2, 1e-6, 1e-9).unwrap(), &mut osc, &[1.0, 0.0], 3.0, n), &exact))
        .collect();
    for p in orders(&errs) {
        assert!((p - 5.0).abs() < 0.2, "DP5 order {p} (errors {errs:?})");
    }
}

#[test]
fn sdirk4_is_fourth_order_in_fixed_steps() {
    let mut osc = Oscillator { omega: 2.0 };
    let exact = osc.exact(3.0);
    let errs: Vec<f64> = [60, 120, 240]
        .iter()
        // In fixed steps the tolerances only stop Newton: tight, so its error stays below the method's.
        .map(|&n| max_diff(&fixed(&mut Sdirk4::new(2, 1e-13, 1e-13).unwrap(), &mut osc, &[1.0, 0.0], 3.0, n), &exact))
        .collect();
    for p in orders(&errs) {
        assert!((p - 4.0).abs() < 0.25, "SDIRK4 order {p} (errors {errs:?})");
    }
}

/// The continuous extension is of order 4: its error inside a step is O(h⁵).
#[test]
fn dp5_dense_output_is_fourth_order() {
    let osc = Oscillator { omega: 2.0 };
    let dense_error = |n: usize| {
        let mut sys = Oscillator { omega: 2.0 };
        let mut dp = Dp5::new(2, 1e-6, 1e-9).unwrap();
        let (mut y, h) = (vec![1.0, 0.0], 3.0 / n as f64);
        let mut worst: f64 = 0.0;
        for i in 0..n {
            let t0 = i as f64 * h;
            // The interpolant's own error: measured against the exact solution through the
            // step's start value, i.e. minus the global error carried in.
            let carried = [y[0] - osc.exact(t0)[0], y[1] - osc.exact(t0)[1]];
            dp.step(&mut sys, t0, &mut y, h).unwrap();
            for theta in [0.21, 0.5, 0.77] {
                let d = dp.dense(theta);
                let e = osc.exact(t0 + theta * h);
                // The carried error propagates (to first order) like the solution itself.
                let (c, s) = ((osc.omega * theta * h).cos(), (osc.omega * theta * h).sin());
                let prop = [c * carried[0] + s / osc.omega * carried[1], -osc.omega * s * carried[0] + c * carried[1]];
                worst = worst.max((d[0] - e[0] - prop[0]).abs()).max((d[1] - e[1] - prop[1]).abs());
            }
        }
        worst
    };
    let errs = [dense_error(30), dense_error(60), dense_error(120)];
    for p in orders(&errs) {
        assert!(p > 4.6 && p < 5.4, "dense-output local order {p}, want ≈ 5 (errors {errs:?})");
    }
    // The endpoints reproduce the step.
    let mut sys = Oscillator { omega: 2.0 };
    let mut dp = Dp5::new(2, 1e-6, 1e-9).unwrap();
    let mut y = vec![1.0, 0.0];
    dp.step(&mut sys, 0.0, &mut y, 0.1).unwrap();
    assert_eq!(dp.dense(1.0), y);
    assert_eq!(dp.dense(0.0), vec![1.0, 0.0]);
}

#[test]
fn dp5_error_follows_the_tolerance_and_steps_scale_as_a_fifth_order_method() {
    let osc = Oscillator { omega: 2.0 };
    let exact = osc.exact(10.0);
    let mut rows = Vec::new();
    for tol in [1e-5, 1e-6, 1e-7, 1e-8, 1e-9, 1e-10] {
        let mut sys = Oscillator { omega: 2.0 };
        let mut dp = Dp5::new(2, tol, tol).unwrap();
        let mut y = vec![1.0, 0.0];
        let h0 = dp.initial_step(&mut sys, 0.0, &y).unwrap();
        dp.integrate_to(&mut sys, 0.0, &mut y, 10.0, h0).unwrap();
        let err = max_diff(&y, &exact);
        rows.push((tol, err, dp.stats().accepted as f64));
        // Global error within two decades of the tolerance (10 s, ~3 periods).
        assert!(err < 100.0 * tol, "tol {tol:e}: error {err:e}");
    }
    // Steps ∝ tol^(−1/5) for a fifth-order method: fit the slope over the sweep.
    let (first, last) = (rows[0], rows[rows.len() - 1]);
    let slope = (last.2 / first.2).ln() / (first.0 / last.0).ln();
    assert!((slope - 0.2).abs() < 0.04, "steps ∝ tol^(−{slope:.3}) (want 1/5): {rows:?}");
}

#[test]
fn dp5_uses_six_evaluations_per_accepted_step_fsal() {
    let mut sys = StiffLinear::new(-1.0, -2.0);
    let mut dp = Dp5::new(2, 1e-8, 1e-10).unwrap();
    let mut y = vec![2.0, 0.0];
    dp.integrate_to(&mut sys, 0.0, &mut y, 5.0, 1e-3).unwrap();
    let s = dp.stats();
    assert_eq!(sys.evaluations, s.rhs_evaluations);
    // One first evaluation, then 6 per attempt.
    assert_eq!(s.rhs_evaluations, 1 + 6 * (s.accepted + s.rejected), "{s:?}");
    assert!(max_diff(&y, &sys.exact(5.0)) < 1e-8);
}

#[test]
fn adaptive_wrapper_works_behind_the_fixed_step_interface() {
    let mut osc = Oscillator { omega: 2.0 };
    let mut method = Adaptive::new(Dp5::new(2, 1e-9, 1e-12).unwrap());
    let y = fixed(&mut method, &mut osc, &[1.0, 0.0], 5.0, 10);
    assert!(max_diff(&y, &osc.exact(5.0)) < 1e-7);
}

#[test]
fn adaptive_wrapper_interpolates_inside_its_last_interval_and_nowhere_else() {
    // One call over [0, 2] takes many sub-steps; the interpolant anywhere inside matches the
    // exact solution to the tolerance, outside the span (and for RK4) there is none.
    for method in [
        Box::new(Adaptive::new(Dp5::new(2, 1e-8, 1e-10).unwrap())) as Box<dyn Integrator>,
        Box::new(Adaptive::new(Sdirk4::new(2, 1e-8, 1e-10).unwrap())),
    ] {
        let mut method = method;
        let mut osc = Oscillator { omega: 2.0 };
        let mut y = [1.0, 0.0];
        method.step(&mut osc, 0.0, &mut y, 2.0).unwrap();
        let mut out = [0.0; 2];
        let mut worst: f64 = 0.0;
        for i in 0..=200 {
            let t = 2.0 * i as f64 / 200.0;
            assert!(method.dense_state(t, &mut out), "no interpolant at t = {t}");
            worst = worst.max(max_diff(&out, &osc.exact(t)));
        }
        assert!(worst < 1e-6, "interpolation error {worst:e}");
        assert!(!method.dense_state(2.1, &mut out) && !method.dense_state(-0.1, &mut out));
    }
    let (mut osc, mut y, mut out) = (Oscillator { omega: 2.0 }, [1.0, 0.0], [0.0; 2]);
    let mut rk4 = Rk4::new(2);
    rk4.step(&mut osc, 0.0, &mut y, 0.01).unwrap();
    assert!(!rk4.dense_state(0.005, &mut out));
}

#[test]
fn dynamics_answers_a_repeated_state_without_solving_again() {
    let (mut sys, y) = chain_system();
    let n = 4;
    let (q, u) = (&y[..n], &y[n..2 * n]);
    let (mut a, mut b) = (vec![0.0; n], vec![0.0; n]);
    sys.accelerations(q, u, &mut a).unwrap();
    sys.accelerations(q, u, &mut b).unwrap();
    assert_eq!((a.clone(), sys.evaluations()), (b.clone(), 1));
    // Body accelerations (the driver's observation) are kinematics: the next stage at the
    // same state is still answered from memory.
    let mut acc = vec![BodyAcceleration::default(); n];
    sys.body_accelerations(q, u, &a, &mut acc);
    sys.accelerations(q, u, &mut b).unwrap();
    assert_eq!((a.clone(), sys.evaluations()), (b.clone(), 1));
    // A different state, or the same state under another anchor state, is solved.
    let mut u2 = u.to_vec();
    u2[0] = 0.1;
    sys.accelerations(q, &u2, &mut b).unwrap();
    assert_eq!(sys.evaluations(), 2);
    sys.accelerations(q, u, &mut b).unwrap();
    sys.slide_anchor(0.0);
    sys.accelerations(q, u, &mut b).unwrap();
    assert_eq!(sys.evaluations(), 4);
    assert_ne!(a[n - 1], b[n - 1], "the freed anchor accelerates");
}

// ---------------------------------------------------------------- stiff problem

#[test]
fn sdirk4_is_stable_and_cheap_where_explicit_methods_need_tiny_steps() {
    // Eigenvalues −1e6 and −1 on [0, 10].
    let mut sys = StiffLinear::new(-1e6, -1.0);
    let mut sd = Sdirk4::new(2, 1e-6, 1e-9).unwrap();
    let mut y = vec![2.0, 0.0];
    sd.integrate_to(&mut sys, 0.0, &mut y, 10.0, 1e-8).unwrap();
    let exact = sys.exact(10.0);
    let s = sd.stats();
    assert!(max_diff(&y, &exact) < 1e-8, "SDIRK4 error {:e}", max_diff(&y, &exact));
    assert!(s.accepted < 300, "SDIRK4 took {} steps: {s:?}", s.accepted);
    assert!(s.rhs_evaluations < 5_000, "{s:?}");

    // DOPRI5 at the same tolerance is held at its stability limit, |hλ| ≲ 3.3.
    let mut sys = StiffLinear::new(-1e6, -1.0);
    let mut dp = Dp5::new(2, 1e-6, 1e-9).unwrap();
    let mut y = vec![2.0, 0.0];
    dp.integrate_to(&mut sys, 0.0, &mut y, 0.05, 1e-8).unwrap();
    let d = dp.stats();
    let mean_h = 0.05 / d.accepted as f64;
    assert!(mean_h < 4e-6, "DOPRI5 mean step {mean_h:e}");
    assert!(d.rhs_evaluations > 50 * s.rhs_evaluations, "explicit {d:?} vs implicit {s:?}");

    // Fixed steps of 0.1 s: SDIRK4 damps the stiff mode (L-stable), RK4 explodes.
    let mut sys = StiffLinear::new(-1e6, -1.0);
    let y = fixed(&mut Sdirk4::new(2, 1e-6, 1e-9).unwrap(), &mut sys, &[2.0, 0.0], 2.0, 20);
    assert!(max_diff(&y, &sys.exact(2.0)) < 1e-4, "SDIRK4 fixed {y:?}");
    let y = fixed(&mut Rk4::new(2), &mut sys, &[2.0, 0.0], 2.0, 20);
    assert!(y[0].is_nan() || y[0].abs() >= 1e6, "RK4 at hλ = −1e5 should blow up: {y:?}");
}

/// invalidate() before every interval keeps J and its LU: J is only Newton's approximation.
#[test]
fn sdirk4_keeps_its_jacobian_and_lu_across_invalidate() {
    let (dt, count) = (0.01, 1000);
    let mut sys = StiffManifold { lambda: -1e4 };
    let mut method = Adaptive::new(Sdirk4::new(2, 1e-6, 1e-9).unwrap());
    method.method.control.h_max = dt;
    let mut y = vec![1.0, 1.0 + StiffManifold::E0];
    intervals(&mut method, &mut sys, &mut y, 0.0, dt, count);
    let s = method.method.stats();
    let exact = sys.exact(dt * count as f64);
    let err = max_diff(&y, &exact);
    assert!(err < 1e-7, "error {err:e} at t = 10: {y:?} vs {exact:?}, {s:?}");
    // With J formed where y1 was y1_J, Newton's first correction carries an error e1 in y1
    // into y2 as 2hγλ(y1 − y1_J) e1/(1 − hγλ) ≈ 2(y1 − y1_J) e1 (hγ|λ| ≫ 1). The tolerance
    // scales go as y1 and y1², so in their norm the contraction reaches 1 (divergence: J is
    // refreshed) once y1 has fallen to 2/3 of y1_J. From 1 to 1/11: at most 1 + ⌈ln 11/ln 1.5⌉
    // Jacobians, against one per interval (1000) when invalidate() dropped J.
    assert!(s.jacobians <= 1 + (11f64.ln() / 1.5f64.ln()).ceil() as u64, "{s:?}");
    // The LU too outlives invalidate(): refactored when h changes, not once per interval.
    assert!(s.factorisations < count as u64 / 2, "{s:?}");
}

/// The run driver's y = (q, u, W) without its claim that W are quadrature components.
struct NoHint(Dynamics);

impl OdeSystem for NoHint {
    fn dim(&self) -> usize {
        self.0.dim()
    }
    fn rhs(&mut self, t: f64, y: &[f64], dy: &mut [f64]) -> Result<(), RhsError> {
        self.0.rhs(t, y, dy)
    }
}

/// The accumulators' columns of J are zero: skipping them changes nothing but the count of
/// evaluations, WORK_COUNT fewer per Jacobian.
#[test]
fn sdirk4_skips_the_jacobian_columns_of_quadrature_components() {
    let run = |sys: &mut dyn OdeSystem, y: &mut Vec<f64>| {
        let mut sd = Sdirk4::new(y.len(), 1e-8, 1e-8).unwrap();
        // J refreshed after every step whose Newton needed a second iteration: many to count.
        sd.refresh_theta = 0.0;
        sd.integrate_to(sys, 0.0, y, CHAIN_T, 1e-3).unwrap();
        sd.stats()
    };
    let (plain, mut y_plain) = chain_system();
    let full = run(&mut NoHint(plain), &mut y_plain);
    let (mut dynamics, mut y_hint) = chain_system();
    assert_eq!(dynamics.quadrature_components(), WORK_COUNT);
    let hinted = run(&mut dynamics, &mut y_hint);
    assert_eq!(y_plain, y_hint, "the same trajectory");
    assert_eq!(full.jacobians, hinted.jacobians);
    assert!(full.jacobians > 10, "{full:?}");
    assert_eq!(full.rhs_evaluations - hinted.rhs_evaluations, WORK_COUNT as u64 * full.jacobians);
}

/// A system that changes under a kept J (an anchor switch): the first Newton failure
/// refreshes J at the same h; `forget_jacobian` saves that failed attempt.
#[test]
fn sdirk4_refreshes_a_jacobian_the_system_outgrew() {
    let (dt1, dt2) = (0.1, 0.01);
    let run = |forget: bool| {
        let mut sys = StiffLinear::new(-1e4, -1.0);
        let mut method = Adaptive::new(Sdirk4::new(2, 1e-6, 1e-10).unwrap());
        method.method.control.h_max = dt1;
        let mut y = vec![2.0, 0.0];
        intervals(&mut method, &mut sys, &mut y, 0.0, dt1, 10);
        let before = method.method.stats();
        // The slow mode becomes stiff: with the old J (λ2 = −1) Newton's contraction is
        // hγ|Δλ2|/(1 + hγ) ≈ 2.5 at h = dt2, it diverges.
        sys.l2 = -1e3;
        if forget {
            method.method.forget_jacobian();
        }
        intervals(&mut method, &mut sys, &mut y, 1.0, dt2, 1);
        // b(t) = e^{−1} e^{λ2 (t − 1)}, a(t) = e^{−1e4 t} ≈ 0.
        let b = (-1.0f64).exp() * (sys.l2 * dt2).exp();
        let err = max_diff(&y, &[b, -b]);
        assert!(err < 1e-10, "error {err:e} after the switch: {y:?}, b = {b:e}");
        intervals(&mut method, &mut sys, &mut y, 1.0 + dt2, dt2, 9);
        (y, before, method.method.stats())
    };
    let (y_lazy, before, lazy) = run(false);
    // One J for the first system: it is linear, so Newton converges at once.
    assert_eq!(before.jacobians, 1, "{before:?}");
    // One more for the second, formed after a failed attempt.
    assert_eq!(lazy.jacobians, 2, "{lazy:?}");
    let (y_told, _, told) = run(true);
    assert_eq!(told.jacobians, 2, "{told:?}");
    assert_eq!(lazy.rejected, told.rejected + 1, "lazy {lazy:?}, told {told:?}");
    assert!(lazy.rhs_evaluations > told.rhs_evaluations);
    assert_eq!(y_lazy, y_told, "the retry starts where forget_jacobian does");
}

// ---------------------------------------------------------------- errors

#[test]
fn step_size_collapse_is_an_error_with_its_time() {
    let mut dp = Dp5::new(1, 1e-8, 1e-8).unwrap();
    let mut y = vec![1.0];
    match dp.integrate_to(&mut BlowUp, 0.0, &mut y, 2.0, 1e-3) {
        Err(e @ StepError::StepSizeCollapse { t, .. }) => {
            assert!((t - 1.0).abs() < 1e-2, "collapse at {t}");
            let msg = e.to_string();
            assert!(msg.contains("step-size collapse") && msg.contains("stiff or singular"), "{msg}");
        }
        other => panic!("expected a step-size collapse, got {other:?} (y = {y:?})"),
    }
    let mut sd = Sdirk4::new(1, 1e-8, 1e-8).unwrap();
    let mut y = vec![1.0];
    assert!(matches!(sd.integrate_to(&mut BlowUp, 0.0, &mut y, 2.0, 1e-3), Err(StepError::StepSizeCollapse { .. })));
}

#[test]
fn zero_negative_and_non_finite_tolerances_are_refused() {
    for (rtol, atol) in [(0.0, 0.0), (-1e-6, 1e-6), (1e-6, -1.0), (f64::NAN, 1e-6), (1e-6, f64::INFINITY)] {
        let e = Dp5::new(3, rtol, atol).unwrap_err();
        assert!(matches!(e, StepError::InvalidTolerance(_)), "{rtol}, {atol}: {e}");
        assert!(Sdirk4::new(3, rtol, atol).is_err());
    }
    assert!(Dp5::new(3, 0.0, 1e-9).is_ok());
    let mut dp = Dp5::new(2, 1e-6, 1e-6).unwrap();
    let mut y = vec![1.0, 0.0];
    assert!(matches!(
        dp.step_adaptive(&mut Oscillator { omega: 1.0 }, 0.0, &mut y, 0.0),
        Err(StepError::InvalidStep(_))
    ));
}

// ---------------------------------------------------------------- a gravity-only chain

/// Anchor held, three rods swinging under gravity: y = (q, u, W) through `Dynamics`.
fn chain_system() -> (Dynamics, Vec<f64>) {
    let chain = rod_chain(1e4, &[(2.0, 20.0), (1.5, 15.0), (1.0, 10.0)]);
    let n = chain.len();
    let dynamics =
        Dynamics::new(Box::new(ReferenceKernel::new(&chain)), Forces::gravity_only(&chain, G), AnchorDof::Stuck);
    let q = [0.6, -0.5, 0.4, 0.0];
    assert_eq!(q.len(), n);
    let y: Vec<f64> = q.iter().copied().chain([0.0; 4]).chain([0.0; WORK_COUNT]).collect();
    (dynamics, y)
}

const CHAIN_T: f64 = 1.5;

fn chain_reference() -> Vec<f64> {
    let (mut sys, mut y) = chain_system();
    let mut dp = Dp5::new(y.len(), 1e-13, 1e-13).unwrap();
    dp.integrate_to(&mut sys, 0.0, &mut y, CHAIN_T, 1e-4).unwrap();
    y
}

/// Error in (q, u) only: the work accumulators of gravity alone are zero.
fn chain_error(y: &[f64], reference: &[f64]) -> f64 {
    max_diff(&y[..8], &reference[..8])
}

#[test]
fn measured_orders_on_a_gravity_only_chain() {
    let reference = chain_reference();
    let (_, y0) = chain_system();
    let dim = y0.len();
    let run = |method: &mut dyn Integrator, steps: usize| {
        let (mut sys, _) = chain_system();
        chain_error(&fixed(method, &mut sys, &y0, CHAIN_T, steps), &reference)
    };
    let rk4: Vec<f64> = [300, 600, 1200].iter().map(|&n| run(&mut Rk4::new(dim), n)).collect();
    let dp5: Vec<f64> = [100, 200, 400].iter().map(|&n| run(&mut Dp5::new(dim, 1e-6, 1e-9).unwrap(), n)).collect();
    let (p_rk4, p_dp5) = (orders(&rk4), orders(&dp5));
    eprintln!("chain: RK4 errors {rk4:?} orders {p_rk4:?}; DP5 errors {dp5:?} orders {p_dp5:?}");
    for p in p_rk4 {
        assert!((p - 4.0).abs() < 0.3, "RK4 order on the chain {p} ({rk4:?})");
    }
    for p in p_dp5 {
        assert!((p - 5.0).abs() < 0.3, "DP5 order on the chain {p} ({dp5:?})");
    }
    // docs/integrators.md's table of measured orders quotes these runs.
    let quoted = |e: &[f64], p: &[f64]| {
        let e: Vec<String> = e.iter().map(|x| format!("{x:.1e}")).collect();
        let p: Vec<String> = p.iter().map(|x| format!("{x:.2}")).collect();
        format!("errors {}: orders {}", e.join(", "), p.join(", "))
    };
    let doc =
        std::fs::read_to_string(std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("docs/integrators.md")).unwrap();
    for q in [quoted(&rk4, &orders(&rk4)), quoted(&dp5, &orders(&dp5))] {
        assert!(doc.contains(&q), "docs/integrators.md's measured orders should say: {q}");
    }
}

#[test]
fn adaptive_methods_meet_their_tolerance_on_the_chain() {
    let reference = chain_reference();
    let (_, y0) = chain_system();
    for tol in [1e-6, 1e-9] {
        let (mut sys, mut y) = chain_system();
        let mut dp = Dp5::new(y0.len(), tol, tol).unwrap();
        let h = dp.initial_step(&mut sys, 0.0, &y).unwrap();
        dp.integrate_to(&mut sys, 0.0, &mut y, CHAIN_T, h).unwrap();
        let e = chain_error(&y, &reference);
        assert!(e < 50.0 * tol, "DP5 tol {tol:e}: error {e:e}, {:?}", dp.stats());

        let (mut sys, mut y) = chain_system();
        let mut sd = Sdirk4::new(y0.len(), tol, tol).unwrap();
        let h = sd.initial_step(&mut sys, 0.0, &y).unwrap();
        sd.integrate_to(&mut sys, 0.0, &mut y, CHAIN_T, h).unwrap();
        let e = chain_error(&y, &reference);
        assert!(e < 50.0 * tol, "SDIRK4 tol {tol:e}: error {e:e}, {:?}", sd.stats());
    }
}

//! Time integration of ẏ = F(t, y). Integrators know nothing about ships: they see an
//! [`OdeSystem`] only.

pub mod adaptive;
pub mod dp5;
pub mod sdirk4;

pub use adaptive::{AdaptiveIntegrator, AdaptiveStats, DenseStep, StepControl, StepError, StepOutcome, Tolerances};
pub use dp5::Dp5;
pub use sdirk4::{NewtonError, Sdirk4};

/// The right-hand side could not be evaluated; defined with the kernels that produce it.
pub use crate::kernel::RhsError;

/// A first-order system ẏ = F(t, y).
pub trait OdeSystem {
    /// Length of y.
    fn dim(&self) -> usize;
    /// Writes F(t, y) into `dy`.
    fn rhs(&mut self, t: f64, y: &[f64], dy: &mut [f64]) -> Result<(), RhsError>;

    /// How many trailing components of y the right-hand side does not depend on
    /// (∂F/∂y_j = 0 for j ≥ dim − k): integrals carried along, such as work accumulators,
    /// known as quadrature variables. An implicit method skips their columns of a difference
    /// Jacobian. The default, 0, claims nothing; a wrong claim slows Newton or stops it
    /// converging.
    fn quadrature_components(&self) -> usize {
        0
    }

    /// Called by an adaptive method after each error-controlled step it accepts inside the
    /// span it was asked to cross (not at the span's end, which its caller sees): the states
    /// between a driver's observations, e.g. for the peaks of a quantity. DP5 has just
    /// evaluated the right-hand side there (its last stage). The default does nothing.
    fn accepted(&mut self, _t: f64, _y: &[f64]) -> Result<(), RhsError> {
        Ok(())
    }
}

/// A one-step method.
pub trait Integrator {
    /// Advances `y` from `t` to `t + dt`.
    fn step(&mut self, system: &mut dyn OdeSystem, t: f64, y: &mut [f64], dt: f64) -> Result<(), StepError>;

    /// Forgets anything cached from earlier steps (e.g. a first-same-as-last derivative):
    /// called after the system changed without the state changing (an anchor switch, a new
    /// friction force). Caches are keyed by (t, y), so a step from a state the method did not
    /// produce needs no reset.
    fn reset(&mut self) {}

    /// The state at time t inside the last `step` call, from the method's continuous
    /// extension, into `out`. False when the method has none (RK4) or t is outside that
    /// call's span: then a state inside a step is found by integrating to it.
    fn dense_state(&self, _t: f64, _out: &mut [f64]) -> bool {
        false
    }
}

/// The classic fourth-order Runge–Kutta method with a fixed step (the paper's method).
#[derive(Clone, Debug, Default)]
pub struct Rk4 {
    k1: Vec<f64>,
    k2: Vec<f64>,
    k3: Vec<f64>,
    k4: Vec<f64>,
    tmp: Vec<f64>,
}

impl Rk4 {
    /// An RK4 stepper with stage storage for systems of dimension `dim` (resized on the
    /// first step if the state's length differs).
    pub fn new(dim: usize) -> Self {
        Rk4 { k1: vec![0.0; dim], k2: vec![0.0; dim], k3: vec![0.0; dim], k4: vec![0.0; dim], tmp: vec![0.0; dim] }
    }
}

impl Integrator for Rk4 {
    fn step(&mut self, sys: &mut dyn OdeSystem, t: f64, y: &mut [f64], dt: f64) -> Result<(), StepError> {
        let n = y.len();
        if self.k1.len() != n {
            *self = Rk4::new(n);
        }
        let h2 = 0.5 * dt;
        // Every buffer has length n here, so the zips below visit exactly 0..n.
        sys.rhs(t, y, &mut self.k1)?;
        for ((tmp, &yi), &k1) in self.tmp.iter_mut().zip(y.iter()).zip(&self.k1) {
            *tmp = yi + h2 * k1;
        }
        sys.rhs(t + h2, &self.tmp, &mut self.k2)?;
        for ((tmp, &yi), &k2) in self.tmp.iter_mut().zip(y.iter()).zip(&self.k2) {
            *tmp = yi + h2 * k2;
        }
        sys.rhs(t + h2, &self.tmp, &mut self.k3)?;
        for ((tmp, &yi), &k3) in self.tmp.iter_mut().zip(y.iter()).zip(&self.k3) {
            *tmp = yi + dt * k3;
        }
        sys.rhs(t + dt, &self.tmp, &mut self.k4)?;
        let ks = self.k1.iter().zip(&self.k2).zip(&self.k3).zip(&self.k4);
        for (yi, (((&k1, &k2), &k3), &k4)) in y.iter_mut().zip(ks) {
            *yi += dt / 6.0 * (k1 + 2.0 * k2 + 2.0 * k3 + k4);
        }
        Ok(())
    }
}

/// An adaptive method behind the fixed-step [`Integrator`] interface: `step(t, y, dt)`
/// integrates [t, t + dt] with as many error-controlled sub-steps as the tolerances need,
/// remembering the step size between calls, and keeps the sub-steps' interpolants so that
/// the driver locates events inside [t, t + dt] on them ([`Integrator::dense_state`]).
#[derive(Clone, Debug)]
pub struct Adaptive<M> {
    /// The error-controlled method doing the sub-steps.
    pub method: M,
    /// The step to try next; `None` before the first step (then the whole interval is tried).
    pub h_next: Option<f64>,
    /// Interpolants of the last `step` call's sub-steps, in order: the first `used` of them
    /// (the vectors are reused from call to call).
    dense: Vec<DenseStep>,
    used: usize,
}

impl<M: AdaptiveIntegrator> Adaptive<M> {
    /// Wraps `method`; while [`Adaptive::h_next`] is `None`, the first call tries the whole
    /// interval `dt` as one sub-step.
    pub fn new(method: M) -> Self {
        Adaptive { method, h_next: None, dense: Vec::new(), used: 0 }
    }
}

impl<M: AdaptiveIntegrator> Integrator for Adaptive<M> {
    fn step(&mut self, sys: &mut dyn OdeSystem, t: f64, y: &mut [f64], dt: f64) -> Result<(), StepError> {
        let h = self.h_next.unwrap_or(dt);
        let Adaptive { method, dense, used, .. } = self;
        *used = 0;
        let next = method.integrate_to_with(sys, t, y, t + dt, h, &mut |m| {
            if *used == dense.len() {
                dense.push(DenseStep::default());
            }
            m.save_dense(&mut dense[*used]);
            *used += 1;
        });
        if next.is_err() {
            self.used = 0;
        }
        self.h_next = Some(next?);
        Ok(())
    }

    fn reset(&mut self) {
        self.method.invalidate();
    }

    fn dense_state(&self, t: f64, out: &mut [f64]) -> bool {
        let steps = &self.dense[..self.used];
        let (Some(first), Some(last)) = (steps.first(), steps.last()) else { return false };
        let slack = 1e-12 * (last.t0 + last.h).abs().max(1.0);
        if !(first.t0 - slack..=last.t0 + last.h + slack).contains(&t) {
            return false;
        }
        // The last sub-step starting at or before t.
        let k = steps.partition_point(|s| s.t0 <= t).max(1) - 1;
        steps[k].at(t, out);
        true
    }
}

/// Test problems the methods' tests share.
#[cfg(test)]
pub(crate) mod test_problems {
    use super::{Integrator, OdeSystem, RhsError};

    /// ẏ = −y.
    pub struct Decay;

    impl OdeSystem for Decay {
        fn dim(&self) -> usize {
            1
        }
        fn rhs(&mut self, _t: f64, y: &[f64], dy: &mut [f64]) -> Result<(), RhsError> {
            dy[0] = -y[0];
            Ok(())
        }
    }

    /// Error at t = 1 of `steps` fixed steps of `method` on ẏ = −y from y = 1.
    pub fn decay_error(method: &mut dyn Integrator, steps: usize) -> f64 {
        let (mut y, dt) = ([1.0], 1.0 / steps as f64);
        for i in 0..steps {
            method.step(&mut Decay, i as f64 * dt, &mut y, dt).expect("a step of ẏ = −y");
        }
        (y[0] - (-1.0f64).exp()).abs()
    }
}

#[cfg(test)]
mod tests {
    use super::test_problems::decay_error;
    use super::*;

    #[test]
    fn rk4_is_fourth_order() {
        // Halving the step divides the error by 2⁴ = 16.
        let ratio = decay_error(&mut Rk4::new(1), 20) / decay_error(&mut Rk4::new(1), 40);
        assert!((ratio - 16.0).abs() < 1.0, "ratio {ratio}");
    }

    #[test]
    fn an_adaptive_step_shows_the_system_its_inner_accepted_states() {
        use super::test_problems::Decay;
        /// ẏ = −y, recording where `accepted` is called and with what.
        #[derive(Default)]
        struct Watched(Vec<(f64, f64)>);
        impl OdeSystem for Watched {
            fn dim(&self) -> usize {
                1
            }
            fn rhs(&mut self, t: f64, y: &[f64], dy: &mut [f64]) -> Result<(), RhsError> {
                Decay.rhs(t, y, dy)
            }
            fn accepted(&mut self, t: f64, y: &[f64]) -> Result<(), RhsError> {
                self.0.push((t, y[0]));
                Ok(())
            }
        }
        let mut rk4 = Watched::default();
        Rk4::new(1).step(&mut rk4, 0.0, &mut [1.0], 0.1).unwrap();
        assert!(rk4.0.is_empty(), "RK4 has no inner steps");
        let mut dp = Adaptive::new(Dp5::new(1, 1e-10, 1e-12).unwrap());
        let (mut sys, mut y) = (Watched::default(), [1.0]);
        dp.step(&mut sys, 2.0, &mut y, 1.0).unwrap();
        // Several sub-steps at this tolerance; their ends inside (2, 3), increasing, each the
        // solution e^−(t−2) to the tolerance and the interpolant's state there.
        let seen = std::mem::take(&mut sys.0);
        assert!(seen.len() >= 3, "{seen:?}");
        assert!(seen.windows(2).all(|w| w[0].0 < w[1].0) && seen[0].0 > 2.0 && seen[seen.len() - 1].0 < 3.0);
        let mut state = [0.0];
        for &(t, v) in &seen {
            assert!((v - (2.0 - t).exp()).abs() < 1e-9, "t = {t}: {v}");
            assert!(dp.dense_state(t, &mut state) && state[0] == v, "t = {t}");
        }
        // A second call shows its own.
        dp.step(&mut sys, 3.0, &mut y, 1.0).unwrap();
        assert!(!sys.0.is_empty() && sys.0.iter().all(|&(t, _)| t > 3.0 && t < 4.0), "{:?}", sys.0);
    }
}

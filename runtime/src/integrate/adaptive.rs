//! What the adaptive methods share: tolerances, the step-size controller, the outcome of one
//! accepted step and the errors an adaptive step can end in.

use super::sdirk4::NewtonError;
use super::{OdeSystem, RhsError};

/// Error tolerances: a component's error is measured against atol_i + rtol·max(|y0_i|, |y1_i|).
#[derive(Clone, Debug, PartialEq)]
pub struct Tolerances {
    /// Relative tolerance (≥ 0).
    pub rtol: f64,
    /// Absolute tolerance per component (≥ 0), or one value for all (length 1).
    pub atol: Vec<f64>,
}

impl Tolerances {
    /// Checks the values: finite, not negative, and not both zero (a zero tolerance cannot be met).
    pub fn new(rtol: f64, atol: f64) -> Result<Self, StepError> {
        Self::with_vector(rtol, vec![atol])
    }

    /// As [`Tolerances::new`] with one absolute tolerance per component.
    pub fn with_vector(rtol: f64, atol: Vec<f64>) -> Result<Self, StepError> {
        let bad = |what: String| Err(StepError::InvalidTolerance(what));
        if !rtol.is_finite() || rtol < 0.0 {
            return bad(format!("rtol = {rtol}: must be finite and ≥ 0"));
        }
        if atol.is_empty() {
            return bad("atol is empty: give one value or one per component".into());
        }
        for (i, &a) in atol.iter().enumerate() {
            if !a.is_finite() || a < 0.0 {
                return bad(format!("atol[{i}] = {a}: must be finite and ≥ 0"));
            }
            if a == 0.0 && rtol == 0.0 {
                return bad(format!("rtol = 0 and atol[{i}] = 0: at least one tolerance must be > 0"));
            }
        }
        if rtol > 0.0 && rtol < 1e-14 {
            return bad(format!("rtol = {rtol:e}: below 1e-14 it cannot be met in double precision"));
        }
        Ok(Tolerances { rtol, atol })
    }

    /// The absolute tolerance of component i (the single value when only one is given).
    #[inline]
    pub fn atol(&self, i: usize) -> f64 {
        if self.atol.len() == 1 {
            self.atol[0]
        } else {
            self.atol[i]
        }
    }

    /// The scale of component i for the error norm.
    #[inline]
    pub fn scale(&self, i: usize, y0: f64, y1: f64) -> f64 {
        self.atol(i) + self.rtol * y0.abs().max(y1.abs())
    }

    /// RMS norm of `err` scaled by the tolerances, and the component with the largest share.
    pub fn norm(&self, err: &[f64], y0: &[f64], y1: &[f64]) -> (f64, usize) {
        let mut sum = 0.0;
        let (mut worst, mut worst_i) = (-1.0, 0);
        for i in 0..err.len() {
            let e = err[i] / self.scale(i, y0[i], y1[i]);
            let e2 = e * e;
            sum += e2;
            // A non-finite error is the worst there is.
            let key = if e2.is_finite() { e2 } else { f64::INFINITY };
            if key > worst {
                worst = key;
                worst_i = i;
            }
        }
        let n = err.len().max(1) as f64;
        let norm = (sum / n).sqrt();
        (if norm.is_nan() { f64::INFINITY } else { norm }, worst_i)
    }
}

/// Step-size control: h_new = h · clamp(safety · err^(−α) · err_old^β, fac_min, fac_max)
/// (Gustafsson's PI controller with α = 1/(q+1) − 0.75β, q the lower order of the pair),
/// bounded by [h_min, h_max].
#[derive(Clone, Debug, PartialEq)]
pub struct StepControl {
    /// Safety factor on the optimal step (0.9).
    pub safety: f64,
    /// Smallest factor of one change (0.2).
    pub fac_min: f64,
    /// Largest factor of one change (10).
    pub fac_max: f64,
    /// β of the PI controller (0.04 as in Hairer's dopri5; 0 is the plain I controller).
    pub beta: f64,
    /// Step-size floor: a step that must go below it is a [`StepError::StepSizeCollapse`], s.
    /// The effective floor is max(h_min, 64 ε |t|), so that t + h ≠ t.
    pub h_min: f64,
    /// Largest step, s.
    pub h_max: f64,
    /// Consecutive rejections of one step after which it is given up.
    pub max_rejections: u32,
}

impl Default for StepControl {
    fn default() -> Self {
        StepControl {
            safety: 0.9,
            fac_min: 0.2,
            fac_max: 10.0,
            beta: 0.04,
            h_min: 1e-12,
            h_max: f64::INFINITY,
            max_rejections: 60,
        }
    }
}

impl StepControl {
    /// The effective floor at time t.
    pub fn floor(&self, t: f64) -> f64 {
        self.h_min.max(64.0 * f64::EPSILON * t.abs())
    }
}

/// One accepted adaptive step.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct StepOutcome {
    /// The step taken: the state is now at t + h.
    pub h: f64,
    /// The step the controller suggests next.
    pub h_next: f64,
    /// Attempts rejected before this one was accepted.
    pub rejected: u32,
    /// Scaled error norm of the accepted step (≤ 1).
    pub error: f64,
    /// Right-hand-side evaluations spent in this call (attempts and Jacobians included).
    pub rhs_evaluations: u64,
}

/// Counters over the life of an adaptive integrator.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct AdaptiveStats {
    /// Accepted steps.
    pub accepted: u64,
    /// Rejected attempts (error test or Newton failure).
    pub rejected: u64,
    /// Right-hand-side evaluations, Jacobians and starting-step estimates included.
    pub rhs_evaluations: u64,
    /// Finite-difference Jacobians (stiff methods).
    pub jacobians: u64,
    /// LU factorisations (stiff methods).
    pub factorisations: u64,
    /// Newton iterations (stiff methods).
    pub newton_iterations: u64,
}

/// Why a step failed (adaptive or fixed).
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum StepError {
    /// The right-hand side failed.
    #[error(transparent)]
    Rhs(#[from] RhsError),
    /// The error test (or, for implicit methods, Newton) kept failing until the step would
    /// have to go below the floor.
    #[error(
        "step-size collapse at t = {t:.6} s: the step fell to {h:.3e} s, below the floor {h_min:.3e} s \
         ({reason}; scaled error {error:.3e}, largest in state component {component}): the problem is \
         stiff or singular here, or the tolerances tighter than the steps can meet"
    )]
    StepSizeCollapse {
        /// Start of the step, s.
        t: f64,
        /// The step that would have been tried next, s.
        h: f64,
        /// The floor, s.
        h_min: f64,
        /// Scaled error norm of the last attempt (∞ for a non-finite state or no convergence).
        error: f64,
        /// The state component with the largest error of the last attempt.
        component: usize,
        /// What kept failing.
        reason: String,
    },
    /// One call of [`AdaptiveIntegrator::integrate_to`] took more than
    /// [`MAX_RHS_PER_INTERVAL`] right-hand sides: the steps shrank far below the interval
    /// without collapsing (a stiff term the method resolves step by tiny step).
    #[error(
        "step-size stall at t = {t:.6} s: {steps} accepted steps and {rhs} right-hand sides, the last step \
         {h:.3e} s long, did not reach t = {t1:.6} s: the problem is stiff or singular here, or the tolerances \
         tighter than the steps can meet"
    )]
    TooManySteps {
        /// Where the steps had reached, s.
        t: f64,
        /// The end of the interval, s.
        t1: f64,
        /// The accepted steps taken.
        steps: u64,
        /// The right-hand sides evaluated.
        rhs: u64,
        /// The last step, s.
        h: f64,
    },
    /// A tolerance is zero, negative or not finite.
    #[error("invalid tolerance: {0}")]
    InvalidTolerance(String),
    /// The step requested is not positive and finite.
    #[error("invalid step h = {0}: must be finite and > 0")]
    InvalidStep(f64),
    /// Hairer's starting step came out non-finite or zero: f(t, y) is not finite.
    #[error("non-finite derivative at t = {t}: no starting step")]
    NoStartingStep {
        /// s.
        t: f64,
    },
    /// A fixed SDIRK4 step: the iteration matrix I − hγJ is singular.
    #[error("SDIRK4: I − hγJ is singular at t = {t} with h = {h}")]
    SingularIterationMatrix {
        /// Start of the step, s.
        t: f64,
        /// The step, s.
        h: f64,
    },
    /// A fixed SDIRK4 step: Newton failed with a Jacobian formed at the step's start.
    #[error("SDIRK4 at t = {t}, h = {h}: {reason}; reduce the step")]
    NewtonFailed {
        /// Start of the step, s.
        t: f64,
        /// The step, s.
        h: f64,
        /// How Newton failed.
        reason: NewtonError,
    },
}

/// A detached copy of one accepted step's continuous extension:
/// y(t0 + θh) = `interpolate`(coefficients, θ), θ ∈ [0, 1]. An adaptive driver keeps one per
/// sub-step of an interval, so that events are located on the interpolants afterwards.
#[derive(Clone, Debug)]
pub struct DenseStep {
    /// Start of the step, s.
    pub t0: f64,
    /// Its length, s.
    pub h: f64,
    /// The method's coefficient vectors, each as long as the state.
    pub coefficients: Vec<Vec<f64>>,
    /// The method's interpolation formula.
    pub interpolate: fn(&[Vec<f64>], f64, &mut [f64]),
}

impl Default for DenseStep {
    /// An empty step, to be [`DenseStep::set`].
    fn default() -> Self {
        DenseStep { t0: 0.0, h: 0.0, coefficients: Vec::new(), interpolate: |_, _, _| {} }
    }
}

impl DenseStep {
    /// The interpolant at time t (clamped to the step), into `out`.
    pub fn at(&self, t: f64, out: &mut [f64]) {
        (self.interpolate)(&self.coefficients, ((t - self.t0) / self.h).clamp(0.0, 1.0), out);
    }

    /// Sets this copy from a method's step, reusing its vectors.
    pub fn set(&mut self, t0: f64, h: f64, coefficients: &[Vec<f64>], interpolate: fn(&[Vec<f64>], f64, &mut [f64])) {
        (self.t0, self.h, self.interpolate) = (t0, h, interpolate);
        self.coefficients.resize_with(coefficients.len(), Vec::new);
        for (to, from) in self.coefficients.iter_mut().zip(coefficients) {
            to.clear();
            to.extend_from_slice(from);
        }
    }
}

/// An adaptive one-step method with dense output over its last accepted step.
pub trait AdaptiveIntegrator {
    /// Takes one accepted step from (t, y) trying `h_try` first; `y` becomes the state at
    /// t + outcome.h. The step is never longer than `h_try`, so a driver reaches an output
    /// time exactly by passing h_try = min(h_suggested, t_out − t).
    fn step_adaptive(
        &mut self,
        sys: &mut dyn OdeSystem,
        t: f64,
        y: &mut [f64],
        h_try: f64,
    ) -> Result<StepOutcome, StepError>;

    /// The interpolant of the last accepted step at θ ∈ [0, 1] (t = t0 + θh), into `out`.
    fn dense_into(&self, theta: f64, out: &mut [f64]);

    /// Copies the last accepted step's interpolant into `into` (nothing before a step).
    fn save_dense(&self, into: &mut DenseStep);

    /// (t0, h) of the last accepted step, if any.
    fn last_step(&self) -> Option<(f64, f64)>;

    /// Forgets cached derivatives (FSAL): call after changing the system (an anchor switch,
    /// a new friction force) or the state outside the integrator.
    fn invalidate(&mut self);

    /// Counters so far.
    fn stats(&self) -> AdaptiveStats;

    /// The interpolant at time t inside the last accepted step.
    fn dense_at(&self, t: f64, out: &mut [f64]) {
        if let Some((t0, h)) = self.last_step() {
            self.dense_into(((t - t0) / h).clamp(0.0, 1.0), out);
        }
    }

    /// Integrates from t0 to t1 (> t0) with as many steps as the tolerances need, the last
    /// one clipped to land on t1. Returns the step to try next time (unclipped).
    fn integrate_to(
        &mut self,
        sys: &mut dyn OdeSystem,
        t0: f64,
        y: &mut [f64],
        t1: f64,
        h_try: f64,
    ) -> Result<f64, StepError> {
        self.integrate_to_with(sys, t0, y, t1, h_try, &mut |_| {})
    }

    /// As [`AdaptiveIntegrator::integrate_to`], calling `accepted` after every accepted step
    /// (e.g. to keep its dense output), and the system's [`OdeSystem::accepted`] after each
    /// that ends inside (t0, t1).
    fn integrate_to_with(
        &mut self,
        sys: &mut dyn OdeSystem,
        t0: f64,
        y: &mut [f64],
        t1: f64,
        h_try: f64,
        accepted: &mut dyn FnMut(&Self),
    ) -> Result<f64, StepError> {
        if !(h_try.is_finite() && h_try > 0.0) {
            return Err(StepError::InvalidStep(h_try));
        }
        let mut t = t0;
        let mut h = h_try;
        let span = t1 - t0;
        let tol = 1e-14 * span.abs().max(t1.abs());
        let (mut steps, mut rhs) = (0u64, 0u64);
        while t1 - t > tol {
            if rhs >= MAX_RHS_PER_INTERVAL {
                return Err(StepError::TooManySteps { t, t1, steps, rhs, h });
            }
            let remaining = t1 - t;
            let clipped = h >= remaining;
            let out = self.step_adaptive(sys, t, y, h.min(remaining))?;
            (steps, rhs) = (steps + 1, rhs + out.rhs_evaluations);
            accepted(self);
            t = if clipped && out.h == remaining { t1 } else { t + out.h };
            if t1 - t > tol {
                sys.accepted(t, y)?;
            }
            // A clipped last step says nothing about the step size the problem allows.
            h = if clipped && out.rejected == 0 { h.max(out.h_next) } else { out.h_next };
        }
        Ok(h)
    }
}

/// The most right-hand sides one call of [`AdaptiveIntegrator::integrate_to`] (a run's
/// observation interval `solver.dt`, at most 1 s, or the part of it up to an anchor switch)
/// takes before it fails with [`StepError::TooManySteps`], the difference Jacobians of
/// SDIRK4 included (4N each): some 5–20 s of CPU at N = 46. A drag coefficient of 1e15 made SDIRK4 take 7.9 million
/// for case 1's first 2 ms, and a run of 1 s seem to hang; the dp5 run of case 1 with a
/// coefficient of 1e9, stiff but completed, takes at most about 60 000 an interval.
pub const MAX_RHS_PER_INTERVAL: u64 = 2_000_000;

/// Hairer's starting step (HNW I, II.4): from ‖y0‖, ‖f0‖ and one explicit Euler probe.
pub fn initial_step(
    sys: &mut dyn OdeSystem,
    tol: &Tolerances,
    order: u32,
    t: f64,
    y: &[f64],
    h_max: f64,
) -> Result<f64, StepError> {
    let n = y.len();
    let mut f0 = vec![0.0; n];
    sys.rhs(t, y, &mut f0)?;
    let sk = |i: usize| tol.atol(i) + tol.rtol * y[i].abs();
    let rms = |v: &dyn Fn(usize) -> f64| ((0..n).map(|i| v(i).powi(2)).sum::<f64>() / n.max(1) as f64).sqrt();
    let d0 = rms(&|i| y[i] / sk(i));
    let d1 = rms(&|i| f0[i] / sk(i));
    let mut h0 = if d0 < 1e-5 || d1 < 1e-5 { 1e-6 } else { 0.01 * d0 / d1 };
    h0 = h0.min(h_max);
    let y1: Vec<f64> = (0..n).map(|i| y[i] + h0 * f0[i]).collect();
    let mut f1 = vec![0.0; n];
    sys.rhs(t + h0, &y1, &mut f1)?;
    let d2 = rms(&|i| (f1[i] - f0[i]) / sk(i)) / h0;
    let h1 =
        if d1.max(d2) <= 1e-15 { (h0 * 1e-3).max(1e-6) } else { (0.01 / d1.max(d2)).powf(1.0 / (order as f64 + 1.0)) };
    let h = (100.0 * h0).min(h1).min(h_max);
    if h.is_finite() && h > 0.0 {
        Ok(h)
    } else {
        Err(StepError::NoStartingStep { t })
    }
}

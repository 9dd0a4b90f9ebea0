//! An L-stable singly diagonally implicit Runge–Kutta method for stiff problems: the
//! 5-stage, stiffly accurate SDIRK of order 4 with an embedded order-3 solution and γ = 1/4
//! (Hairer & Wanner, *Solving ODEs II*, IV.6, Table 6.5, "SDIRK4").
//!
//! - The Jacobian J = ∂f/∂y is formed by forward differences: n + 1 right-hand-side
//!   evaluations, fewer when the system declares trailing components f does not depend on
//!   ([`OdeSystem::quadrature_components`]: their columns are zero and not evaluated).
//! - Every stage solves z = s + hγ f(t + c h, y + z) by simplified Newton iterations with one
//!   LU factorisation of (I − hγJ) (nalgebra), shared by all five stages.
//! - The local error y − ŷ is filtered through (I − hγJ)⁻¹ (Hairer & Wanner IV.8, for
//!   stiff components), then controlled like DOPRI5 with exponent 1/4.
//! - Dense output: the cubic Hermite interpolant on (y0, f0, y1, f1) (order 3).
//!
//! Stiffly accurate (y1 is the last stage) and L-stable: very stiff modes are damped in one
//! step, whatever h.
//!
//! # When J and the LU are formed
//!
//! J only steers the simplified Newton iterations and filters the error estimate: the
//! stages are converged to the tolerance κ whatever J, so an old J costs iterations, not
//! accuracy. A difference Jacobian costs about n evaluations and its LU O(n³), against a few
//! evaluations per stage for Newton, so both are kept as long as Newton contracts well (the
//! strategy of Hairer's RADAU5):
//!
//! - J is formed before the first step, then only when it has shown to be poor:
//!   - an accepted step's Newton iterations contracted more slowly than
//!     [`Sdirk4::refresh_theta`] (θ = ‖Δ_{m+1}‖/‖Δ_m‖ at a stage's last iteration, the
//!     largest over the stages): the next step forms J at its start;
//!   - Newton failed (diverged: θ ≥ 0.99, or not converged in [`Sdirk4::max_newton`]
//!     iterations) with
//!     a J formed elsewhere: J is formed at the step's start and the step retried with the
//!     same h. Only a failure with this current J halves h.
//!
//!   There is no age limit: θ measures J's quality where it matters, for the current state,
//!   system and hγ, while a refresh on a schedule costs n evaluations whether J has degraded
//!   or not. An error-test rejection keeps J too: the retry has a smaller hγ, for which J's
//!   error weighs less.
//! - [`AdaptiveIntegrator::invalidate`] (the state or the system may have changed) forgets
//!   the first-same-as-last derivative, which belongs to the state, and demotes J to an
//!   approximation formed elsewhere: if the system did change (an anchor switch), the
//!   second rule above refreshes J at the first Newton failure.
//!   [`Sdirk4::forget_jacobian`] forms J anew at the next step, for a caller that knows
//!   the system changed drastically (saving the failed attempt).
//! - The LU of (I − hγJ) is kept while J and hγ are unchanged: an accepted step's proposal
//!   to grow h by less than 20 % is suppressed so that the next step reuses it.

use nalgebra::{DMatrix, DVector, Dyn, LU};

use super::adaptive::{
    initial_step, AdaptiveIntegrator, AdaptiveStats, DenseStep, StepControl, StepError, StepOutcome, Tolerances,
};
use super::{Integrator, OdeSystem, RhsError};

/// Cubic Hermite interpolation at θ from d = (y0, h f0, y1, h f1) of one step.
fn hermite(d: &[Vec<f64>], theta: f64, out: &mut [f64]) {
    let (t2, t3) = (theta * theta, theta * theta * theta);
    let (h00, h10, h01, h11) = (2.0 * t3 - 3.0 * t2 + 1.0, t3 - 2.0 * t2 + theta, -2.0 * t3 + 3.0 * t2, t3 - t2);
    for i in 0..d[0].len().min(out.len()) {
        out[i] = h00 * d[0][i] + h10 * d[1][i] + h01 * d[2][i] + h11 * d[3][i];
    }
}

const GAMMA: f64 = 0.25;
const C: [f64; 5] = [0.25, 0.75, 11.0 / 20.0, 0.5, 1.0];
/// Strictly lower part of A.
const A: [[f64; 4]; 5] = [
    [0.0, 0.0, 0.0, 0.0],
    [0.5, 0.0, 0.0, 0.0],
    [17.0 / 50.0, -1.0 / 25.0, 0.0, 0.0],
    [371.0 / 1360.0, -137.0 / 2720.0, 15.0 / 544.0, 0.0],
    [25.0 / 24.0, -49.0 / 48.0, 125.0 / 16.0, -85.0 / 12.0],
];
/// b − b̂ (b is the last row of A with γ; b̂ = (59/48, −17/96, 225/32, −85/12, 0)).
const D: [f64; 5] = [-3.0 / 16.0, -27.0 / 32.0, 25.0 / 32.0, 0.0, 0.25];

/// How the Jacobian held relates to the step about to be attempted.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum JacobianState {
    /// None is held, or the one held is to be replaced before the next attempt.
    Refresh,
    /// Formed at another state, or before the system changed: an approximation.
    Old,
    /// Formed at the current step's start for the current system: refreshing it cannot
    /// cure a Newton failure.
    Current,
}

/// How the simplified Newton iterations of one stage failed.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum NewtonError {
    /// The update became non-finite.
    #[error("non-finite Newton update in stage {stage}")]
    NonFinite {
        /// The stage, 1 … 5.
        stage: usize,
    },
    /// The contraction θ = ‖Δ_{m+1}‖/‖Δ_m‖ reached 0.99.
    #[error("Newton diverges in stage {stage} (contraction {theta:.2})")]
    Diverges {
        /// The stage, 1 … 5.
        stage: usize,
        /// The last contraction.
        theta: f64,
    },
    /// [`Sdirk4::max_newton`] iterations did not reach the tolerance κ.
    #[error("Newton not converged in {iterations} iterations in stage {stage}")]
    NotConverged {
        /// The iteration limit.
        iterations: u32,
        /// The stage, 1 … 5.
        stage: usize,
    },
}

/// Why the stage equations were not solved.
enum NewtonFailure {
    Rhs(RhsError),
    /// Diverged, too slow, or non-finite.
    NoConvergence(NewtonError),
}

/// Scratch vectors of the stage solves, each as long as the state.
#[derive(Clone, Debug, Default)]
struct StageWork {
    /// The stage increment z = Y_i − y.
    z: Vec<f64>,
    /// Its known part Σ_{j<i} a_ij h k_j.
    s: Vec<f64>,
    /// The Newton correction.
    delta: Vec<f64>,
    ytmp: Vec<f64>,
    ftmp: Vec<f64>,
}

impl StageWork {
    fn new(dim: usize) -> Self {
        let z = || vec![0.0; dim];
        StageWork { z: z(), s: z(), delta: z(), ytmp: z(), ftmp: z() }
    }
}

impl From<RhsError> for NewtonFailure {
    fn from(e: RhsError) -> Self {
        NewtonFailure::Rhs(e)
    }
}

/// The SDIRK4 method with a finite-difference Jacobian and simplified Newton iterations.
#[derive(Clone, Debug)]
pub struct Sdirk4 {
    dim: usize,
    tol: Tolerances,
    /// Step-size control; public so a driver can set h_min/h_max.
    pub control: StepControl,
    /// Newton iterations per stage before the attempt counts as not converged.
    pub max_newton: u32,
    /// Newton stops when the estimated remaining error is below κ (in tolerance units);
    /// min(0.03, √rtol) by default (Hairer's choice in RADAU5).
    pub kappa: f64,
    /// Smallest magnitude a component is perturbed by in the difference Jacobian, relative
    /// to √ε: 1 suits angles in rad and speeds in m/s. (Much smaller increments lose the
    /// Jacobian to round-off when |f| is large.)
    pub jacobian_scale: f64,
    /// Newton contraction θ above which the step after an accepted one forms a new J (0.3).
    /// RADAU5 uses 0.001 where Jacobians are cheap and advises 0.1 where they are costly; a
    /// difference Jacobian costs n + 1 evaluations, the Newton work of several steps, while at
    /// θ = 0.3 an iteration still gains half a decade. On the run driver (n = 98), 0.1 cost
    /// 1.5× the evaluations of 0.3 on the k_z × 1e4 seabed at rtol 1e-3 (as many on case 1),
    /// 0.5 about as many as 0.3.
    pub refresh_theta: f64,
    jac: DMatrix<f64>,
    jac_state: JacobianState,
    lu: Option<LU<f64, Dyn, Dyn>>,
    lu_hgamma: f64,
    /// h·f(Y_i) of the stages.
    hk: [Vec<f64>; 5],
    work: StageWork,
    /// Scratch for the difference Jacobian.
    ftmp: Vec<f64>,
    rhs_vec: DVector<f64>,
    err: Vec<f64>,
    f0: Vec<f64>,
    /// (t, y, f) at the end of the last step.
    end: Option<(f64, Vec<f64>)>,
    dense: [Vec<f64>; 4],
    last: Option<(f64, f64)>,
    facold: f64,
    eta_old: f64,
    /// Newton's contraction at each stage's last iteration, the largest over the stages (the
    /// refresh test). The last ratio estimates the rate best: the first can include the
    /// transient growth of a non-normal iteration, such as through the coupling q̇ = u.
    theta_max: f64,
    stats: AdaptiveStats,
}

impl Sdirk4 {
    /// An SDIRK4 integrator for systems of dimension `dim` with the given tolerances.
    pub fn new(dim: usize, rtol: f64, atol: f64) -> Result<Self, StepError> {
        Ok(Self::with_tolerances(dim, Tolerances::new(rtol, atol)?))
    }

    /// As [`Sdirk4::new`] with checked [`Tolerances`] (e.g. one atol per component); the
    /// Newton tolerance κ is min(0.03, √rtol), at least 1e-4.
    pub fn with_tolerances(dim: usize, tol: Tolerances) -> Self {
        let z = || vec![0.0; dim];
        let kappa = 0.03f64.min(tol.rtol.sqrt()).max(1e-4);
        Sdirk4 {
            dim,
            tol,
            control: StepControl::default(),
            max_newton: 7,
            kappa,
            jacobian_scale: 1.0,
            refresh_theta: 0.3,
            jac: DMatrix::zeros(dim, dim),
            jac_state: JacobianState::Refresh,
            lu: None,
            lu_hgamma: f64::NAN,
            hk: [z(), z(), z(), z(), z()],
            work: StageWork::new(dim),
            ftmp: z(),
            rhs_vec: DVector::zeros(dim),
            err: z(),
            f0: z(),
            end: None,
            dense: [z(), z(), z(), z()],
            last: None,
            facold: 1e-4,
            eta_old: 1.0,
            theta_max: 0.0,
            stats: AdaptiveStats::default(),
        }
    }

    /// The tolerances the error test uses.
    pub fn tolerances(&self) -> &Tolerances {
        &self.tol
    }

    /// Hairer's starting step for (t, y).
    pub fn initial_step(&mut self, sys: &mut dyn OdeSystem, t: f64, y: &[f64]) -> Result<f64, StepError> {
        self.stats.rhs_evaluations += 2;
        initial_step(sys, &self.tol, 3, t, y, self.control.h_max)
    }

    /// Forms J anew before the next step. Not needed for correctness: after
    /// [`AdaptiveIntegrator::invalidate`] a J that no longer fits is refreshed at the first
    /// Newton failure; a caller that knows the system changed drastically saves that attempt.
    pub fn forget_jacobian(&mut self) {
        self.jac_state = JacobianState::Refresh;
    }

    /// The interpolant of the last accepted step at θ as a new vector.
    pub fn dense(&self, theta: f64) -> Vec<f64> {
        let mut out = vec![0.0; self.dim];
        self.dense_into(theta, &mut out);
        out
    }

    fn resize(&mut self, n: usize) {
        if self.dim != n {
            let (control, max_newton, kappa, jacobian_scale, refresh_theta) =
                (self.control.clone(), self.max_newton, self.kappa, self.jacobian_scale, self.refresh_theta);
            *self = Self {
                control,
                max_newton,
                kappa,
                jacobian_scale,
                refresh_theta,
                ..Self::with_tolerances(n, self.tol.clone())
            };
        }
    }

    fn eval(&mut self, sys: &mut dyn OdeSystem, t: f64, y: &[f64], out: &mut [f64]) -> Result<(), RhsError> {
        self.stats.rhs_evaluations += 1;
        sys.rhs(t, y, out)
    }

    /// f0 = f(t, y): from the end of the last step when y is that state, else evaluated.
    fn start(&mut self, sys: &mut dyn OdeSystem, t: f64, y: &[f64]) -> Result<(), RhsError> {
        let hit = matches!(&self.end, Some((te, ye)) if *te == t && ye.as_slice() == y);
        if !hit {
            // f0 is about to belong to (t, y), not to the last step's end.
            self.end = None;
            let mut f0 = std::mem::take(&mut self.f0);
            let r = self.eval(sys, t, y, &mut f0);
            self.f0 = f0;
            r?;
            // A new start point: the Jacobian no longer belongs to it.
            self.demote_jacobian();
        }
        Ok(())
    }

    /// A current J becomes an approximation formed elsewhere.
    fn demote_jacobian(&mut self) {
        if self.jac_state == JacobianState::Current {
            self.jac_state = JacobianState::Old;
        }
    }

    /// J at (t, y) by forward differences with the increment √ε·max(|y_j|, `jacobian_scale`)
    /// and a fresh f(t, y) as the base point; the columns of the system's quadrature
    /// components are zero without evaluation.
    fn jacobian(&mut self, sys: &mut dyn OdeSystem, t: f64, y: &[f64]) -> Result<(), RhsError> {
        let n = self.dim;
        let active = n - sys.quadrature_components().min(n);
        self.jac.columns_mut(active, n - active).fill(0.0);
        let mut f0 = std::mem::take(&mut self.f0);
        let mut ft = std::mem::take(&mut self.ftmp);
        let mut yp = y.to_vec();
        let result: Result<(), RhsError> = (|| {
            self.eval(sys, t, y, &mut f0)?;
            for j in 0..active {
                let delta = f64::EPSILON.sqrt() * y[j].abs().max(self.jacobian_scale);
                yp[j] = y[j] + delta;
                self.eval(sys, t, &yp, &mut ft)?;
                yp[j] = y[j];
                for i in 0..n {
                    self.jac[(i, j)] = (ft[i] - f0[i]) / delta;
                }
            }
            Ok(())
        })();
        self.f0 = f0;
        self.ftmp = ft;
        result?;
        self.stats.jacobians += 1;
        self.jac_state = JacobianState::Current;
        self.lu = None;
        Ok(())
    }

    /// LU of (I − hγJ); false if singular.
    fn factor(&mut self, h: f64) -> bool {
        let hg = h * GAMMA;
        if self.lu.is_some() && self.lu_hgamma == hg {
            return true;
        }
        let n = self.dim;
        let mut m = &self.jac * (-hg);
        for i in 0..n {
            m[(i, i)] += 1.0;
        }
        let lu = m.lu();
        self.stats.factorisations += 1;
        if !lu.is_invertible() {
            self.lu = None;
            return false;
        }
        self.lu = Some(lu);
        self.lu_hgamma = hg;
        true
    }

    fn solve_in_place(&mut self, v: &mut [f64]) {
        self.rhs_vec.as_mut_slice().copy_from_slice(v);
        let ok = self.lu.as_ref().expect("factored").solve_mut(&mut self.rhs_vec);
        debug_assert!(ok);
        v.copy_from_slice(self.rhs_vec.as_slice());
    }

    /// Solves the five stage equations for a step h from (t, y); y1 = y + z (last stage).
    fn stages(&mut self, sys: &mut dyn OdeSystem, t: f64, y: &[f64], h: f64) -> Result<(), NewtonFailure> {
        self.theta_max = 0.0;
        let mut w = std::mem::take(&mut self.work);
        let mut result = Ok(());
        for st in 0..5 {
            result = self.stage(sys, t, y, h, st, &mut w);
            if result.is_err() {
                break;
            }
        }
        self.work = w;
        result
    }

    /// Stage `st` (0-based): predictor, Newton, and h k_st = (z − s)/γ.
    fn stage(
        &mut self,
        sys: &mut dyn OdeSystem,
        t: f64,
        y: &[f64],
        h: f64,
        st: usize,
        w: &mut StageWork,
    ) -> Result<(), NewtonFailure> {
        // Known part s = Σ_{j<st} a_ij h k_j and a predictor for z.
        for i in 0..self.dim {
            let mut acc = 0.0;
            for (j, a) in A[st].iter().enumerate().take(st) {
                acc += a * self.hk[j][i];
            }
            w.s[i] = acc;
            let last = if st == 0 { h * self.f0[i] } else { self.hk[st - 1][i] };
            w.z[i] = acc + GAMMA * last;
        }
        let (eta, theta) = self.newton(sys, t, y, h, st, w)?;
        self.eta_old = eta;
        self.theta_max = self.theta_max.max(theta);
        for i in 0..self.dim {
            self.hk[st][i] = (w.z[i] - w.s[i]) / GAMMA;
        }
        Ok(())
    }

    /// Simplified Newton on z = s + hγ f(t + c h, y + z) for stage `st` from the predictor in
    /// `w.z`; returns (η, θ) of the last iteration.
    #[allow(clippy::needless_range_loop)] // loops run over 0..self.dim on several buffers: kept for identical rounding
    fn newton(
        &mut self,
        sys: &mut dyn OdeSystem,
        t: f64,
        y: &[f64],
        h: f64,
        st: usize,
        w: &mut StageWork,
    ) -> Result<(f64, f64), NewtonFailure> {
        let n = self.dim;
        let hg = h * GAMMA;
        let stage = st + 1;
        let mut norm_prev = f64::NAN;
        let mut eta = self.eta_old.max(f64::EPSILON).powf(0.8);
        let mut theta = 0.0;
        for m in 0..self.max_newton {
            for i in 0..n {
                w.ytmp[i] = y[i] + w.z[i];
            }
            self.eval(sys, t + C[st] * h, &w.ytmp, &mut w.ftmp)?;
            self.stats.newton_iterations += 1;
            for i in 0..n {
                w.delta[i] = w.s[i] + hg * w.ftmp[i] - w.z[i];
            }
            self.solve_in_place(&mut w.delta);
            let mut sum = 0.0;
            for i in 0..n {
                w.z[i] += w.delta[i];
                let sc = self.tol.scale(i, y[i], y[i]);
                sum += (w.delta[i] / sc).powi(2);
            }
            let norm = (sum / n.max(1) as f64).sqrt();
            if !norm.is_finite() {
                return Err(NewtonFailure::NoConvergence(NewtonError::NonFinite { stage }));
            }
            if m > 0 {
                theta = norm / norm_prev;
                if theta >= 0.99 {
                    return Err(NewtonFailure::NoConvergence(NewtonError::Diverges { stage, theta }));
                }
                eta = theta / (1.0 - theta);
            }
            norm_prev = norm;
            if eta * norm <= self.kappa || norm <= 1e-12 {
                return Ok((eta, theta));
            }
        }
        Err(NewtonFailure::NoConvergence(NewtonError::NotConverged { iterations: self.max_newton, stage }))
    }

    /// Filtered error estimate of the solved stages into `err`.
    fn error_estimate(&mut self) {
        let mut err = std::mem::take(&mut self.err);
        for (i, e) in err.iter_mut().enumerate() {
            *e = D.iter().zip(&self.hk).map(|(d, hk)| d * hk[i]).sum();
        }
        self.solve_in_place(&mut err);
        self.err = err;
    }

    fn accept(&mut self, t: f64, y: &mut [f64], h: f64) {
        for (i, yi) in y.iter_mut().enumerate() {
            let y1 = *yi + self.work.z[i];
            self.dense[0][i] = *yi;
            self.dense[1][i] = h * self.f0[i];
            self.dense[2][i] = y1;
            self.dense[3][i] = self.hk[4][i];
            *yi = y1;
        }
        // f(y1) = k_5 (stiffly accurate); the next step starts from it.
        for (f, hk) in self.f0.iter_mut().zip(&self.hk[4]) {
            *f = hk / h;
        }
        self.end = Some((t + h, y.to_vec()));
        self.last = Some((t, h));
        self.stats.accepted += 1;
        // J belongs to the old start at best: kept while Newton contracts well.
        if self.theta_max > self.refresh_theta {
            self.jac_state = JacobianState::Refresh;
        } else {
            self.demote_jacobian();
        }
    }

    /// The outcome of an accepted step h with scaled error `err` after `rejected` attempts,
    /// and the PI controller's next step (its memory updated).
    fn outcome(&mut self, h: f64, err: f64, rejected: u32, evals0: u64) -> StepOutcome {
        let ctl = &self.control;
        let alpha = 0.25 - 0.75 * ctl.beta;
        let fac = if err == 0.0 { ctl.fac_max } else { ctl.safety * err.powf(-alpha) * self.facold.powf(ctl.beta) };
        let fac_max = if rejected > 0 { 1.0 } else { ctl.fac_max };
        let fac = fac.clamp(ctl.fac_min, fac_max);
        // Keep h (and the LU) for small increases.
        let h_next = if (1.0..1.2).contains(&fac) { h } else { (h * fac).min(ctl.h_max) };
        self.facold = err.max(1e-4);
        StepOutcome { h, h_next, rejected, error: err, rhs_evaluations: self.stats.rhs_evaluations - evals0 }
    }

    fn ynew(&self, y: &[f64]) -> Vec<f64> {
        y.iter().zip(&self.work.z).map(|(a, b)| a + b).collect()
    }
}

impl AdaptiveIntegrator for Sdirk4 {
    fn step_adaptive(
        &mut self,
        sys: &mut dyn OdeSystem,
        t: f64,
        y: &mut [f64],
        h_try: f64,
    ) -> Result<StepOutcome, StepError> {
        if !(h_try.is_finite() && h_try > 0.0) {
            return Err(StepError::InvalidStep(h_try));
        }
        self.resize(y.len());
        let evals0 = self.stats.rhs_evaluations;
        self.start(sys, t, y)?;
        let ctl = self.control.clone();
        let mut h = h_try.min(ctl.h_max);
        let mut rejected = 0u32;
        let (mut last_err, mut last_comp, mut reason) = (f64::NAN, 0, String::new());
        loop {
            let floor = ctl.floor(t);
            if (h < floor && h < h_try) || rejected > ctl.max_rejections {
                return Err(StepError::StepSizeCollapse {
                    t,
                    h,
                    h_min: floor,
                    error: last_err,
                    component: last_comp,
                    reason: format!("{rejected} consecutive failures, the last: {reason}"),
                });
            }
            if self.jac_state == JacobianState::Refresh {
                self.jacobian(sys, t, y)?;
            }
            if !self.factor(h) {
                reason = "singular iteration matrix I − hγJ".into();
                rejected += 1;
                self.stats.rejected += 1;
                h *= 0.5;
                continue;
            }
            // Newton did not converge, or an iterate lay beyond the model's range: the step
            // was too long, or J is from elsewhere.
            let failed = match self.stages(sys, t, y, h) {
                Err(NewtonFailure::Rhs(e)) if !e.at_trial_state() => return Err(e.into()),
                Err(NewtonFailure::Rhs(e)) => format!("at a trial stage: {e}"),
                Err(NewtonFailure::NoConvergence(why)) => why.to_string(),
                Ok(()) => String::new(),
            };
            if !failed.is_empty() {
                rejected += 1;
                self.stats.rejected += 1;
                (last_err, last_comp, reason) = (f64::INFINITY, 0, failed);
                if self.jac_state == JacobianState::Current {
                    h *= 0.5;
                } else {
                    // A J from elsewhere first: refresh it at this start and retry.
                    self.jac_state = JacobianState::Refresh;
                }
                continue;
            }
            self.error_estimate();
            let y1 = self.ynew(y);
            let (err, comp) = self.tol.norm(&self.err, y, &y1);
            if err <= 1.0 {
                self.accept(t, y, h);
                return Ok(self.outcome(h, err, rejected, evals0));
            }
            rejected += 1;
            self.stats.rejected += 1;
            (last_err, last_comp, reason) = (err, comp, "error test failed".into());
            let fac = if err.is_finite() { (ctl.safety * err.powf(-0.25)).max(ctl.fac_min) } else { ctl.fac_min };
            h *= fac.min(1.0);
        }
    }

    fn dense_into(&self, theta: f64, out: &mut [f64]) {
        hermite(&self.dense, theta, out);
    }

    fn save_dense(&self, into: &mut DenseStep) {
        if let Some((t0, h)) = self.last {
            into.set(t0, h, &self.dense, hermite);
        }
    }

    fn last_step(&self) -> Option<(f64, f64)> {
        self.last
    }

    /// Forgets the first-same-as-last derivative and demotes J to an approximation; J and
    /// its LU are kept (see the module documentation).
    fn invalidate(&mut self) {
        self.end = None;
        self.demote_jacobian();
    }

    fn stats(&self) -> AdaptiveStats {
        self.stats
    }
}

impl Integrator for Sdirk4 {
    /// One SDIRK4 step of exactly `dt`, without error control. J follows the adaptive policy
    /// (module documentation): a Newton failure with a J formed elsewhere is retried with J
    /// formed at (t, y), and with that J it is an error.
    fn step(&mut self, sys: &mut dyn OdeSystem, t: f64, y: &mut [f64], dt: f64) -> Result<(), StepError> {
        self.resize(y.len());
        self.start(sys, t, y)?;
        loop {
            if self.jac_state == JacobianState::Refresh {
                self.jacobian(sys, t, y)?;
            }
            if !self.factor(dt) {
                return Err(StepError::SingularIterationMatrix { t, h: dt });
            }
            match self.stages(sys, t, y, dt) {
                Ok(()) => break,
                Err(NewtonFailure::Rhs(e)) => return Err(e.into()),
                Err(NewtonFailure::NoConvergence(_)) if self.jac_state != JacobianState::Current => {
                    self.jac_state = JacobianState::Refresh;
                }
                Err(NewtonFailure::NoConvergence(reason)) => {
                    return Err(StepError::NewtonFailed { t, h: dt, reason });
                }
            }
        }
        self.accept(t, y, dt);
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::integrate::test_problems::{decay_error, Decay};

    /// ẏ = A y with eigenvalues −1 and −10⁴: y1' = −y1, y2' = −10⁴ (y2 − y1).
    struct Stiff;
    impl OdeSystem for Stiff {
        fn dim(&self) -> usize {
            2
        }
        fn rhs(&mut self, _t: f64, y: &[f64], dy: &mut [f64]) -> Result<(), RhsError> {
            dy[0] = -y[0];
            dy[1] = -1e4 * (y[1] - y[0]);
            Ok(())
        }
    }

    fn fixed_error(steps: usize) -> f64 {
        // Tight tolerances: in fixed-step mode they only stop Newton.
        decay_error(&mut Sdirk4::new(1, 1e-12, 1e-14).expect("tolerances"), steps)
    }

    #[test]
    fn fixed_steps_are_fourth_order() {
        let ratio = fixed_error(10) / fixed_error(20);
        assert!((ratio - 16.0).abs() < 2.0, "ratio {ratio}");
    }

    #[test]
    fn a_large_step_on_a_stiff_system_stays_bounded() {
        // h = 0.5 is 5000 times RK4's limit on the fast mode (≈ 2.8e-4): L-stability damps it.
        let mut sd = Sdirk4::new(2, 1e-12, 1e-14).expect("tolerances");
        let mut y = [1.0, 0.0];
        for i in 0..4 {
            Integrator::step(&mut sd, &mut Stiff, 0.5 * i as f64, &mut y, 0.5).expect("step");
        }
        // After t = 2 the fast mode has decayed: y2 ≈ y1 ≈ e^{−2}.
        let slow = (-2.0f64).exp();
        assert!((y[0] - slow).abs() < 1e-2 && (y[1] - slow).abs() < 1e-2, "{y:?} vs {slow}");
    }

    #[test]
    fn adaptive_steps_on_a_stiff_system_are_few_and_accurate() {
        let mut sd = Sdirk4::new(2, 1e-6, 1e-8).expect("tolerances");
        let mut y = [1.0, 0.0];
        sd.integrate_to(&mut Stiff, 0.0, &mut y, 1.0, 1e-4).expect("integrates");
        let slow = (-1.0f64).exp();
        assert!((y[0] - slow).abs() < 1e-4 && (y[1] - slow).abs() < 1e-4, "{y:?}");
        // An explicit method would need ≥ 1/2.8e-4 ≈ 3600 steps.
        assert!(sd.stats().accepted < 200, "{:?}", sd.stats());
    }

    #[test]
    fn dense_output_matches_the_step_ends() {
        let mut sd = Sdirk4::new(1, 1e-10, 1e-12).expect("tolerances");
        let mut y = [1.0];
        let out = sd.step_adaptive(&mut Decay, 0.0, &mut y, 0.02).expect("step");
        let mut at = [0.0];
        sd.dense_into(0.0, &mut at);
        assert_eq!(at[0], 1.0);
        sd.dense_into(1.0, &mut at);
        assert_eq!(at[0], y[0]);
        sd.dense_into(0.5, &mut at);
        assert!((at[0] - (-0.5 * out.h).exp()).abs() < 1e-8, "{} at h = {}", at[0], out.h);
    }

    #[test]
    fn invalid_tolerances_and_steps_are_refused() {
        assert!(matches!(Sdirk4::new(1, 1e-20, 1e-9), Err(StepError::InvalidTolerance(_))));
        assert!(matches!(Sdirk4::new(1, 1e-6, -1.0), Err(StepError::InvalidTolerance(_))));
        let mut sd = Sdirk4::new(1, 1e-6, 1e-9).expect("tolerances");
        assert_eq!(
            sd.step_adaptive(&mut Decay, 0.0, &mut [1.0], f64::INFINITY),
            Err(StepError::InvalidStep(f64::INFINITY))
        );
    }

    #[test]
    fn newton_errors_keep_their_words() {
        let e = StepError::NewtonFailed { t: 1.0, h: 0.5, reason: NewtonError::Diverges { stage: 3, theta: 1.5 } };
        assert_eq!(
            e.to_string(),
            "SDIRK4 at t = 1, h = 0.5: Newton diverges in stage 3 (contraction 1.50); reduce the step"
        );
    }
}

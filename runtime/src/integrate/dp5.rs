//! Dormand–Prince 5(4) (DOPRI5, Hairer, Nørsett & Wanner, *Solving ODEs I*, II.5): an
//! explicit embedded pair of orders 5 and 4, local extrapolation (the fifth-order solution is
//! carried), FSAL (the seventh stage is the next step's first), a PI step-size controller and
//! Hairer's continuous extension of order 4 (`contd5`) as dense output.

use super::adaptive::{
    initial_step, AdaptiveIntegrator, AdaptiveStats, DenseStep, StepControl, StepError, StepOutcome, Tolerances,
};
use super::{Integrator, OdeSystem, RhsError};

// Butcher tableau.
const C2: f64 = 1.0 / 5.0;
const C3: f64 = 3.0 / 10.0;
const C4: f64 = 4.0 / 5.0;
const C5: f64 = 8.0 / 9.0;
const A21: f64 = 1.0 / 5.0;
const A31: f64 = 3.0 / 40.0;
const A32: f64 = 9.0 / 40.0;
const A41: f64 = 44.0 / 45.0;
const A42: f64 = -56.0 / 15.0;
const A43: f64 = 32.0 / 9.0;
const A51: f64 = 19372.0 / 6561.0;
const A52: f64 = -25360.0 / 2187.0;
const A53: f64 = 64448.0 / 6561.0;
const A54: f64 = -212.0 / 729.0;
const A61: f64 = 9017.0 / 3168.0;
const A62: f64 = -355.0 / 33.0;
const A63: f64 = 46732.0 / 5247.0;
const A64: f64 = 49.0 / 176.0;
const A65: f64 = -5103.0 / 18656.0;
const A71: f64 = 35.0 / 384.0;
const A73: f64 = 500.0 / 1113.0;
const A74: f64 = 125.0 / 192.0;
const A75: f64 = -2187.0 / 6784.0;
const A76: f64 = 11.0 / 84.0;
// y5 − y4 (error estimate).
const E1: f64 = 71.0 / 57600.0;
const E3: f64 = -71.0 / 16695.0;
const E4: f64 = 71.0 / 1920.0;
const E5: f64 = -17253.0 / 339200.0;
const E6: f64 = 22.0 / 525.0;
const E7: f64 = -1.0 / 40.0;
// Dense output (Hairer's contd5).
const D1: f64 = -12715105075.0 / 11282082432.0;
const D3: f64 = 87487479700.0 / 32700410799.0;
const D4: f64 = -10690763975.0 / 1880347072.0;
const D5: f64 = 701980252875.0 / 199316789632.0;
const D6: f64 = -1453857185.0 / 822651844.0;
const D7: f64 = 69997945.0 / 29380423.0;

/// Hairer's continuous extension of order 4 at θ from the coefficients `r` of one step.
fn contd5(r: &[Vec<f64>], theta: f64, out: &mut [f64]) {
    let s1 = 1.0 - theta;
    for i in 0..r[0].len().min(out.len()) {
        out[i] = r[0][i] + theta * (r[1][i] + s1 * (r[2][i] + theta * (r[3][i] + s1 * r[4][i])));
    }
}

/// A cached derivative f(t, y).
#[derive(Clone, Debug, Default)]
struct Cached {
    valid: bool,
    t: f64,
    y: Vec<f64>,
    f: Vec<f64>,
}

impl Cached {
    fn matches(&self, t: f64, y: &[f64]) -> bool {
        self.valid && self.t == t && self.y == y
    }
    fn set(&mut self, t: f64, y: &[f64], f: &[f64]) {
        self.valid = true;
        self.t = t;
        self.y.clear();
        self.y.extend_from_slice(y);
        self.f.clear();
        self.f.extend_from_slice(f);
    }
}

/// The Dormand–Prince 5(4) pair.
///
/// Adaptive use: [`AdaptiveIntegrator::step_adaptive`] (one accepted step, error control),
/// [`AdaptiveIntegrator::integrate_to`], and [`AdaptiveIntegrator::dense_into`] on the last
/// accepted step. Fixed-step use: [`Integrator::step`] takes one DP5 step of the given size
/// without error control (for order studies and for the existing fixed-step driver).
#[derive(Clone, Debug)]
pub struct Dp5 {
    dim: usize,
    tol: Tolerances,
    /// Step-size control; public so a driver can set h_min/h_max.
    pub control: StepControl,
    k: [Vec<f64>; 7],
    ytmp: Vec<f64>,
    ynew: Vec<f64>,
    err: Vec<f64>,
    /// f at the end of the last step (FSAL) and at the start of the last step (bisection
    /// re-integrates from the same start).
    end: Cached,
    start: Cached,
    rcont: [Vec<f64>; 5],
    last: Option<(f64, f64)>,
    facold: f64,
    stats: AdaptiveStats,
}

impl Dp5 {
    /// A DP5 integrator for systems of dimension `dim` with the given tolerances.
    pub fn new(dim: usize, rtol: f64, atol: f64) -> Result<Self, StepError> {
        Ok(Self::with_tolerances(dim, Tolerances::new(rtol, atol)?))
    }

    /// As [`Dp5::new`] with checked [`Tolerances`] (e.g. one atol per component).
    pub fn with_tolerances(dim: usize, tol: Tolerances) -> Self {
        let z = || vec![0.0; dim];
        Dp5 {
            dim,
            tol,
            control: StepControl::default(),
            k: [z(), z(), z(), z(), z(), z(), z()],
            ytmp: z(),
            ynew: z(),
            err: z(),
            end: Cached::default(),
            start: Cached::default(),
            rcont: [z(), z(), z(), z(), z()],
            last: None,
            facold: 1e-4,
            stats: AdaptiveStats::default(),
        }
    }

    /// The tolerances the error test uses.
    pub fn tolerances(&self) -> &Tolerances {
        &self.tol
    }

    /// Hairer's starting step for (t, y) (two right-hand-side evaluations).
    pub fn initial_step(&mut self, sys: &mut dyn OdeSystem, t: f64, y: &[f64]) -> Result<f64, StepError> {
        self.stats.rhs_evaluations += 2;
        initial_step(sys, &self.tol, 4, t, y, self.control.h_max)
    }

    /// The interpolant of the last accepted step at θ as a new vector.
    pub fn dense(&self, theta: f64) -> Vec<f64> {
        let mut out = vec![0.0; self.dim];
        self.dense_into(theta, &mut out);
        out
    }

    fn resize(&mut self, n: usize) {
        if self.dim != n {
            *self = Self { control: self.control.clone(), ..Self::with_tolerances(n, self.tol.clone()) };
        }
    }

    fn rhs(&mut self, sys: &mut dyn OdeSystem, t: f64, y: &[f64], out: usize) -> Result<(), RhsError> {
        self.stats.rhs_evaluations += 1;
        // `out` indexes self.k; y is never one of the k.
        let mut k = std::mem::take(&mut self.k[out]);
        let r = sys.rhs(t, y, &mut k);
        self.k[out] = k;
        r
    }

    /// k1 = f(t, y), from the caches when they match.
    fn first_stage(&mut self, sys: &mut dyn OdeSystem, t: f64, y: &[f64]) -> Result<(), RhsError> {
        if self.end.matches(t, y) {
            self.k[0].copy_from_slice(&self.end.f);
        } else if self.start.matches(t, y) {
            self.k[0].copy_from_slice(&self.start.f);
        } else {
            self.rhs(sys, t, y, 0)?;
        }
        self.start.set(t, y, &self.k[0]);
        Ok(())
    }

    /// Stages 2–7 and the error vector of one attempt of size h from (t, y); k1 is set.
    /// The candidate is in `ynew`.
    #[allow(clippy::needless_range_loop)] // y and seven k vectors share i: kept as written for identical rounding
    fn attempt(&mut self, sys: &mut dyn OdeSystem, t: f64, y: &[f64], h: f64) -> Result<(), RhsError> {
        let n = self.dim;
        macro_rules! stage {
            ($out:expr, $c:expr, $($a:expr => $j:expr),+) => {{
                for i in 0..n {
                    self.ytmp[i] = y[i] + h * (0.0 $(+ $a * self.k[$j][i])+);
                }
                let ytmp = std::mem::take(&mut self.ytmp);
                let r = self.rhs(sys, t + $c * h, &ytmp, $out);
                self.ytmp = ytmp;
                r?;
            }};
        }
        stage!(1, C2, A21 => 0);
        stage!(2, C3, A31 => 0, A32 => 1);
        stage!(3, C4, A41 => 0, A42 => 1, A43 => 2);
        stage!(4, C5, A51 => 0, A52 => 1, A53 => 2, A54 => 3);
        stage!(5, 1.0, A61 => 0, A62 => 1, A63 => 2, A64 => 3, A65 => 4);
        for i in 0..n {
            self.ynew[i] = y[i]
                + h * (A71 * self.k[0][i]
                    + A73 * self.k[2][i]
                    + A74 * self.k[3][i]
                    + A75 * self.k[4][i]
                    + A76 * self.k[5][i]);
        }
        let ynew = std::mem::take(&mut self.ynew);
        let r = self.rhs(sys, t + h, &ynew, 6);
        self.ynew = ynew;
        r?;
        for i in 0..n {
            self.err[i] = h
                * (E1 * self.k[0][i]
                    + E3 * self.k[2][i]
                    + E4 * self.k[3][i]
                    + E5 * self.k[4][i]
                    + E6 * self.k[5][i]
                    + E7 * self.k[6][i]);
        }
        Ok(())
    }

    /// Accepts the attempt: dense output, FSAL cache, y ← ynew.
    #[allow(clippy::needless_range_loop)] // y, ynew, k and rcont share i: kept as written for identical rounding
    fn accept(&mut self, t: f64, y: &mut [f64], h: f64) {
        let n = self.dim;
        for i in 0..n {
            let ydiff = self.ynew[i] - y[i];
            let bspl = h * self.k[0][i] - ydiff;
            self.rcont[0][i] = y[i];
            self.rcont[1][i] = ydiff;
            self.rcont[2][i] = bspl;
            self.rcont[3][i] = ydiff - h * self.k[6][i] - bspl;
            self.rcont[4][i] = h
                * (D1 * self.k[0][i]
                    + D3 * self.k[2][i]
                    + D4 * self.k[3][i]
                    + D5 * self.k[4][i]
                    + D6 * self.k[5][i]
                    + D7 * self.k[6][i]);
        }
        y.copy_from_slice(&self.ynew);
        self.end.set(t + h, y, &self.k[6]);
        self.last = Some((t, h));
        self.stats.accepted += 1;
    }
}

impl AdaptiveIntegrator for Dp5 {
    // Long by design: one step's attempts, their error test and the step control read best in
    // one place, as in Hairer's DOPRI5.
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
        self.first_stage(sys, t, y)?;
        let ctl = self.control.clone();
        let alpha = 0.2 - 0.75 * ctl.beta;
        let mut h = h_try.min(ctl.h_max);
        let mut rejected = 0u32;
        let (mut last_err, mut last_comp) = (f64::NAN, 0);
        // The last failure, when a stage's right-hand side failed rather than the error test.
        let mut trial: Option<RhsError> = None;
        let why = |rejected: u32, trial: &Option<RhsError>| match trial {
            Some(e) => format!("{rejected} consecutive failures, the last at a trial stage: {e}"),
            None => format!("{rejected} consecutive error-test failures"),
        };
        loop {
            let floor = ctl.floor(t);
            if h < floor && h < h_try {
                return Err(StepError::StepSizeCollapse {
                    t,
                    h,
                    h_min: floor,
                    error: last_err,
                    component: last_comp,
                    reason: why(rejected, &trial),
                });
            }
            if let Err(e) = self.attempt(sys, t, y, h) {
                // A trial stage beyond the model's range: the step was too long.
                if !e.at_trial_state() {
                    return Err(e.into());
                }
                rejected += 1;
                self.stats.rejected += 1;
                (last_err, last_comp, trial) = (f64::INFINITY, 0, Some(e));
                if rejected > ctl.max_rejections {
                    let reason = format!("{} (the limit)", why(rejected, &trial));
                    return Err(StepError::StepSizeCollapse {
                        t,
                        h,
                        h_min: floor,
                        error: last_err,
                        component: 0,
                        reason,
                    });
                }
                h *= ctl.fac_min;
                continue;
            }
            let (err, comp) = self.tol.norm(&self.err, y, &self.ynew);
            if err <= 1.0 {
                let fac =
                    if err == 0.0 { ctl.fac_max } else { ctl.safety * err.powf(-alpha) * self.facold.powf(ctl.beta) };
                let fac_max = if rejected > 0 { 1.0 } else { ctl.fac_max };
                let h_next = (h * fac.clamp(ctl.fac_min, fac_max)).min(ctl.h_max);
                self.facold = err.max(1e-4);
                self.accept(t, y, h);
                return Ok(StepOutcome {
                    h,
                    h_next,
                    rejected,
                    error: err,
                    rhs_evaluations: self.stats.rhs_evaluations - evals0,
                });
            }
            rejected += 1;
            self.stats.rejected += 1;
            (last_err, last_comp, trial) = (err, comp, None);
            if rejected > ctl.max_rejections {
                return Err(StepError::StepSizeCollapse {
                    t,
                    h,
                    h_min: floor,
                    error: err,
                    component: comp,
                    reason: format!("{} (the limit)", why(rejected, &trial)),
                });
            }
            let fac = if err.is_finite() { (ctl.safety * err.powf(-0.2)).max(ctl.fac_min) } else { ctl.fac_min };
            h *= fac.min(1.0);
        }
    }

    fn dense_into(&self, theta: f64, out: &mut [f64]) {
        contd5(&self.rcont, theta, out);
    }

    fn save_dense(&self, into: &mut DenseStep) {
        if let Some((t0, h)) = self.last {
            into.set(t0, h, &self.rcont, contd5);
        }
    }

    fn last_step(&self) -> Option<(f64, f64)> {
        self.last
    }

    fn invalidate(&mut self) {
        self.end.valid = false;
        self.start.valid = false;
    }

    fn stats(&self) -> AdaptiveStats {
        self.stats
    }
}

impl Integrator for Dp5 {
    /// One DP5 step of exactly `dt`, without error control.
    fn step(&mut self, sys: &mut dyn OdeSystem, t: f64, y: &mut [f64], dt: f64) -> Result<(), StepError> {
        self.resize(y.len());
        self.first_stage(sys, t, y)?;
        self.attempt(sys, t, y, dt)?;
        self.accept(t, y, dt);
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::integrate::test_problems::{decay_error, Decay};

    /// Error at t = 1 of `steps` fixed DP5 steps on ẏ = −y from y = 1.
    fn fixed_error(steps: usize) -> f64 {
        decay_error(&mut Dp5::new(1, 1e-6, 1e-9).expect("tolerances"), steps)
    }

    /// ẏ = −1e3 (y − 1) from y = 0, whose right-hand side fails beyond |y| = 3 (a state beyond
    /// a model's range): a long first try overshoots at a trial stage.
    struct Guarded;

    impl OdeSystem for Guarded {
        fn dim(&self) -> usize {
            1
        }
        fn rhs(&mut self, _t: f64, y: &[f64], dy: &mut [f64]) -> Result<(), RhsError> {
            if y[0].abs() > 3.0 {
                return Err(RhsError::NonFiniteAcceleration);
            }
            dy[0] = -1e3 * (y[0] - 1.0);
            Ok(())
        }
    }

    /// Regression: a trial stage beyond the model's range failed the run (case 1 with a drag
    /// coefficient of 1e9 under dp5); it is a rejected step, tried shorter. Ill-posed friction,
    /// the model's own at any step, still fails at once.
    #[test]
    fn a_trial_stage_beyond_the_model_s_range_rejects_the_step() {
        let mut dp = Dp5::new(1, 1e-8, 1e-10).expect("tolerances");
        let mut y = [0.0];
        let out = dp.step_adaptive(&mut Guarded, 0.0, &mut y, 0.1).expect("a shorter step");
        assert!(out.rejected >= 1 && out.h < 0.1, "{} rejected, h = {}", out.rejected, out.h);
        dp.integrate_to(&mut Guarded, out.h, &mut y, 0.05, out.h_next).expect("integrates");
        assert!((y[0] - (1.0 - (-50.0f64).exp())).abs() < 1e-6, "{}", y[0]);

        struct IllPosed;
        impl OdeSystem for IllPosed {
            fn dim(&self) -> usize {
                1
            }
            fn rhs(&mut self, _t: f64, y: &[f64], dy: &mut [f64]) -> Result<(), RhsError> {
                if y[0] > 0.5 {
                    return Err(RhsError::IllPosedFriction { factor: -1.0 });
                }
                dy[0] = 1.0;
                Ok(())
            }
        }
        let e = dp.integrate_to(&mut IllPosed, 0.0, &mut [0.0], 1.0, 0.1).unwrap_err();
        assert!(matches!(e, StepError::Rhs(RhsError::IllPosedFriction { .. })), "{e}");
    }

    /// Regression: a stiff term resolved step by tiny step made a run seem to hang (SDIRK4 on
    /// a drag coefficient of 1e15); an interval stops at `MAX_RHS_PER_INTERVAL` right-hand
    /// sides with a step-size stall.
    #[test]
    fn an_interval_stalled_on_tiny_steps_fails_within_its_budget() {
        struct Stiff;
        impl OdeSystem for Stiff {
            fn dim(&self) -> usize {
                1
            }
            fn rhs(&mut self, t: f64, y: &[f64], dy: &mut [f64]) -> Result<(), RhsError> {
                dy[0] = -1e9 * (y[0] - t.cos());
                Ok(())
            }
        }
        let mut dp = Dp5::new(1, 1e-6, 1e-9).expect("tolerances");
        let e = dp.integrate_to(&mut Stiff, 0.0, &mut [1.0], 1.0, 1e-3).unwrap_err();
        let StepError::TooManySteps { t, t1, rhs, h, .. } = e else { panic!("{e}") };
        assert!(t < 1.0 && t1 == 1.0 && h < 1e-8, "t = {t}, h = {h}");
        assert!((crate::integrate::adaptive::MAX_RHS_PER_INTERVAL
            ..crate::integrate::adaptive::MAX_RHS_PER_INTERVAL + 100)
            .contains(&rhs));
        assert!(e.to_string().starts_with("step-size stall at t = "), "{e}");
    }

    #[test]
    fn fixed_steps_are_fifth_order() {
        // Halving the step divides the error by 2⁵ = 32.
        let ratio = fixed_error(16) / fixed_error(32);
        assert!((ratio - 32.0).abs() < 3.0, "ratio {ratio}");
    }

    #[test]
    fn adaptive_steps_meet_the_tolerance() {
        for tol in [1e-4, 1e-8] {
            let mut dp = Dp5::new(1, tol, tol).expect("tolerances");
            let mut y = [1.0];
            dp.integrate_to(&mut Decay, 0.0, &mut y, 2.0, 0.1).expect("integrates");
            let err = (y[0] - (-2.0f64).exp()).abs();
            assert!(err < 10.0 * tol && err > 0.0, "tol {tol}: error {err}");
        }
    }

    #[test]
    fn dense_output_is_accurate_inside_the_step() {
        let mut dp = Dp5::new(1, 1e-10, 1e-12).expect("tolerances");
        let mut y = [1.0];
        let out = dp.step_adaptive(&mut Decay, 0.0, &mut y, 0.05).expect("step");
        let mut mid = [0.0];
        for theta in [0.0, 0.25, 0.5, 0.9, 1.0] {
            dp.dense_into(theta, &mut mid);
            let exact = (-theta * out.h).exp();
            assert!((mid[0] - exact).abs() < 1e-9, "θ = {theta}: {} vs {exact}", mid[0]);
        }
        dp.dense_into(1.0, &mut mid);
        assert_eq!(mid[0], y[0], "the interpolant ends on the step's solution");
    }

    #[test]
    fn invalid_tolerances_and_steps_are_refused() {
        assert!(matches!(Dp5::new(1, -1e-6, 1e-9), Err(StepError::InvalidTolerance(_))));
        assert!(matches!(Dp5::new(1, 0.0, 0.0), Err(StepError::InvalidTolerance(_))));
        assert!(matches!(Dp5::new(1, f64::NAN, 1e-9), Err(StepError::InvalidTolerance(_))));
        let mut dp = Dp5::new(1, 1e-6, 1e-9).expect("tolerances");
        assert_eq!(dp.step_adaptive(&mut Decay, 0.0, &mut [1.0], 0.0), Err(StepError::InvalidStep(0.0)));
    }
}

//! A numerical failure as data: when, which body, and what was detected. The words (the
//! cause, which flag or scene field to change) belong to the reports
//! (`kanestop_workflow::diagnostic::describe`).

use crate::integrate::{RhsError, StepError};
use crate::model::Model;
use crate::simulate::result::StaticResidual;
use crate::stability::{StabilityError, StabilityLimit};

/// What went wrong and where; a run that fails keeps its samples up to the last good step.
#[derive(Clone, Debug, PartialEq)]
pub struct Failure {
    /// Time of the first bad step (the end of the interval that failed), s; 0 for a run
    /// refused before it started.
    pub t: f64,
    /// The body most involved (1-based, B_k): the outer body of a spiking or chattering joint, the
    /// stiffest hinge of a refused step, otherwise the body turning fastest relative to its
    /// neighbour at the last good state (where an unstable mode lives).
    pub body: usize,
    /// What was detected.
    pub kind: FailureKind,
    /// For a failure within [`EARLY_FAILURE_TIME`] of the start (or 20 steps, whichever is
    /// longer) of a run that evaluated it ([`super::run_checked`]): how far the initial state
    /// was from static, the likelier cause than the step.
    pub initial_residual: Option<Box<StaticResidual>>,
    /// For RK4's energy runaway, non-finite state or force spike: its stability limit at the
    /// last good state, as at t = 0 ([`crate::stability::limit`]; none where it could not be
    /// computed or is an unsettled estimate). Below `solver.dt`, the mode stiffened during the run (case 1 at 15 ms: 6.3 ms
    /// at t = 1.455 s, against 36.5 ms at the start); at or above it, the blow-up came with
    /// something the linearisation does not see (a contact switching, a snap load).
    pub last_limit: Option<Box<StabilityLimit>>,
}

/// A failure this soon after the start, s (or within 20 steps), is diagnosed with the
/// initial state's static residual.
pub const EARLY_FAILURE_TIME: f64 = 0.5;

/// The start's window for a step or observation interval `dt` (s): [`EARLY_FAILURE_TIME`]
/// or 20 steps, whichever is longer, s.
pub fn early_window(dt: f64) -> f64 {
    EARLY_FAILURE_TIME.max(20.0 * dt)
}

/// True when a failure at `t` (s) with step or observation interval `dt` (s) is early.
pub fn is_early(t: f64, dt: f64) -> bool {
    t <= early_window(dt)
}

/// What a [`Failure`] detected. The short `Display` names the kind, for debugging only.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum FailureKind {
    /// RK4's fixed step `solver.dt` is above the initial state's stability limit: refused
    /// before the run.
    #[error("RK4 step above the stability limit")]
    StepAboveLimit {
        /// The step asked for, s.
        dt: f64,
        /// The limit and its mode.
        limit: StabilityLimit,
    },
    /// The stability limit could not be computed.
    #[error("stability limit: {0}")]
    Stability(#[from] StabilityError),
    /// The right-hand side failed while observing a state.
    #[error("right-hand side: {0}")]
    Rhs(#[from] RhsError),
    /// The integrator failed.
    #[error("step: {0}")]
    Step(#[from] StepError),
    /// The state after a step has a NaN or infinite component.
    #[error("non-finite state")]
    NonFiniteState,
    /// |E − E_0|/K of the energy balance (Eq. 63) exceeds `solver.max_energy_drift`, K the
    /// largest kinetic energy before the step ([`super::health::drift_scale`]).
    #[error("energy runaway")]
    EnergyRunaway {
        /// The relative drift (possibly not finite).
        drift: f64,
        /// `solver.max_energy_drift`.
        limit: f64,
        /// K, the drift's scale: the largest kinetic energy before the step, J.
        scale: f64,
    },
    /// A joint force above [`super::SPIKE_FACTOR`] × the line's largest break load.
    #[error("constraint-force spike")]
    ForceSpike {
        /// The joint k (between B_{k−1} and B_k), 2 … N.
        joint: usize,
        /// |F^H_k|, N (Eq. 52).
        force: f64,
        /// The bound it exceeds, N.
        bound: f64,
        /// The body turning fastest at the last good state, where the likely unstable mode
        /// lives (1-based).
        swinging: usize,
    },
    /// RK4's joint tensions chatter: rough (second difference over three steps above
    /// [`super::health::CHATTER_RATIO`] of their size) at `rough` of the last `window` steps,
    /// [`super::health::ChatterWatch`]. The step no longer resolves a mode that stiffened
    /// after t = 0; the tensions and their peaks are noise.
    #[error("tension chatter")]
    TensionChatter {
        /// The joint k (between B_{k−1} and B_k), 2 … N, roughest at the failing step.
        joint: usize,
        /// Its second difference over its scale at that step.
        ratio: f64,
        /// Rough steps among the last `window`.
        rough: u32,
        /// The steps counted.
        window: u32,
        /// How many steps before the failing one the run's first rough step was: its
        /// tensions and their peaks are suspect from then.
        first_rough: u64,
    },
}

impl std::fmt::Display for Failure {
    /// A short form for debugging: the kind, the time and the body.
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "{} at t = {} s (B_{})", self.kind, self.t, self.body)
    }
}

impl Failure {
    /// A failure detected at `t` after the last good state `last_good` = (q, u, W).
    pub fn at(model: &Model, t: f64, last_good: &[f64], kind: FailureKind) -> Self {
        let swinging = fastest_body(model, last_good);
        let (body, kind) = match kind {
            FailureKind::ForceSpike { joint, force, bound, .. } => {
                (joint, FailureKind::ForceSpike { joint, force, bound, swinging })
            }
            FailureKind::StepAboveLimit { limit, .. } => (limit.body, kind),
            FailureKind::TensionChatter { joint, .. } => (joint, kind),
            other => (swinging, other),
        };
        Failure { t, body, kind, initial_residual: None, last_limit: None }
    }

    /// The refusal of an RK4 step `dt` above `limit`, before the run.
    pub fn step_above_limit(dt: f64, limit: StabilityLimit) -> Self {
        Failure {
            t: 0.0,
            body: limit.body,
            kind: FailureKind::StepAboveLimit { dt, limit },
            initial_residual: None,
            last_limit: None,
        }
    }
}

/// The body (1-based, 2 … N) whose relative angle β_k turns fastest in (q, u, W): where
/// the unstable mode lives.
pub fn fastest_body(model: &Model, y: &[f64]) -> usize {
    let n = model.body_count();
    let u = &y[n..2 * n];
    let (i, _) = u[..n - 1]
        .iter()
        .enumerate()
        .fold((0, -1.0), |best, (i, &v)| if v.abs() > best.1 { (i, v.abs()) } else { best });
    i + 2
}

//! What a run produces: output samples, why it stopped, the anchor's switches, peak
//! tensions, and how static the initial configuration is.

use std::time::Duration;

use super::Failure;
use crate::dynamics::Dynamics;
use crate::energy::Energy;
use crate::forces::Forces;
use crate::kernel::{AnchorDof, BodyAcceleration, BodyState, Kernel, RhsError};
use crate::model::Model;
use crate::stability::StabilityLimit;

/// The state of every body at one output time.
#[derive(Clone, Debug)]
pub struct Sample {
    /// s.
    pub t: f64,
    /// Every body's state, B_1 first.
    pub bodies: Vec<BodyState>,
    /// The energy balance's terms (Eq. 63).
    pub energy: Energy,
    /// |F^H_k| for the joints k = 2 … N (index k − 2), N.
    pub tensions: Vec<f64>,
    /// The anchor's state.
    pub anchor: AnchorDof,
}

/// Why a run ended.
#[derive(Clone, Debug, PartialEq)]
pub enum Stop {
    /// `solver.end_time` was reached.
    EndTime,
    /// The ship's surge speed reached zero.
    ShipStopped,
    /// A numerical failure (worded by `kanestop_workflow::diagnostic::describe`).
    Failed(Failure),
}

/// A located switch of the anchor.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct AnchorEvent {
    /// s.
    pub t: f64,
    /// The anchor's state from then on.
    pub now: AnchorDof,
}

/// The largest tension seen at one joint.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct PeakTension {
    /// N.
    pub tension: f64,
    /// s.
    pub t: f64,
}

/// Everything a run produced.
#[derive(Clone, Debug)]
pub struct RunResult {
    /// The output samples, t = 0 first.
    pub samples: Vec<Sample>,
    /// Why the run ended.
    pub stop: Stop,
    /// Simulated time reached (last good state), s.
    pub t_end: f64,
    /// First zero of the ship's surge speed, located to round-off, s: 0 for a ship at rest at
    /// the start.
    pub stopping_time: Option<f64>,
    /// The ship's surge displacement at that zero, m: the stopping distance, also of a run
    /// that goes on past it (`solver.stop_when_ship_stops = false`).
    pub stopping_distance: Option<f64>,
    /// The anchor's switches, in order.
    pub anchor_events: Vec<AnchorEvent>,
    /// Peak tension at every joint k = 2 … N (index k − 2), over every step.
    pub peak_tensions: Vec<PeakTension>,
    /// Intervals of `solver.dt` completed.
    pub steps: u64,
    /// Right-hand-side solves (the stability limit's excluded).
    pub rhs_evaluations: u64,
    /// Wall time of the run (zero for a run refused or failed before its first step).
    pub wall_time: Duration,
    /// CPU time of the run on its own thread, over the same span as `wall_time` (none where
    /// the platform does not say, see [`super::cpu::thread_cpu_time`]; none too for a run
    /// refused or failed before its first step).
    pub cpu_time: Option<Duration>,
    /// Energy balance at t = 0, J.
    pub energy0: f64,
    /// Largest relative drift |E − E_0|/K of the balance over the run, K the largest kinetic
    /// energy before each check ([`health::energy_drift`](super::health::energy_drift)).
    pub max_energy_drift: f64,
    /// K at the run's end: the largest kinetic energy of its states that passed the checks (E^K,
    /// the entrained water's included), J.
    pub energy_scale: f64,
    /// Kernel used.
    pub kernel: &'static str,
    /// The generated kernel's form: `unrolled` (built for this N) or `rolled` (any N); none
    /// for the reference.
    pub kernel_form: Option<&'static str>,
    /// The load signature whose generated load code computed the loads (`wet_seabed`); none
    /// when the force modules did (the reference kernel).
    pub load_code: Option<String>,
    /// What the loads included.
    pub physics: String,
    /// How static the initial catenary is under the model's own forces.
    pub initial_residual: Option<StaticResidual>,
    /// RK4's step limit on the linearised equations at t = 0 (RK4 runs only).
    pub stability: Option<StabilityLimit>,
}

/// How far the initial configuration is from static equilibrium: the largest centroid
/// acceleration of a chain link or cable element at (q_0, u = 0) with the anchor held.
/// The chord polygon is not exactly a catenary, the elements sit at their static embedment,
/// and the vertical rod cannot carry the catenary's horizontal top tension, so the top
/// elements are never quite static; a small residual elsewhere says the layout is right.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct StaticResidual {
    /// Largest |a| over the chain and the cable below its top stage, m/s², and its body.
    pub line: (f64, usize),
    /// Largest |a| over the cable's top stage (beside the rod), m/s², and its body.
    pub top: (f64, usize),
}

/// The [`StaticResidual`] of a model with the given kernel.
pub fn static_residual(model: &Model, kernel: Box<dyn Kernel>) -> Result<StaticResidual, RhsError> {
    let n = model.body_count();
    let mut dynamics = Dynamics::new(kernel, Forces::new(model), AnchorDof::Stuck);
    let (q, u) = (model.q0.clone(), vec![0.0; n]);
    let mut qdd = vec![0.0; n];
    dynamics.accelerations(&q, &u, &mut qdd)?;
    let mut acc = vec![BodyAcceleration::default(); n];
    dynamics.body_accelerations(&q, &u, &qdd, &mut acc);
    let last_stage = model.scene.cable.stages.len().saturating_sub(1);
    let (mut line, mut top) = ((0.0, 0), (0.0, 0));
    for (k, (b, a)) in model.chain.bodies.iter().zip(&acc).enumerate() {
        let slot = match b.kind {
            kanestop_chain::BodyKind::ChainLink => &mut line,
            kanestop_chain::BodyKind::Cable { stage } if stage < last_stage => &mut line,
            kanestop_chain::BodyKind::Cable { .. } => &mut top,
            _ => continue,
        };
        let m = a.ax.hypot(a.az);
        if m > slot.0 {
            *slot = (m, k + 1);
        }
    }
    Ok(StaticResidual { line, top })
}

/// Largest centroid position difference at the output times both runs share, m.
pub fn trajectory_difference(a: &RunResult, b: &RunResult) -> f64 {
    let mut worst: f64 = 0.0;
    let mut j = 0;
    for s in &a.samples {
        while j < b.samples.len() && b.samples[j].t < s.t - 1e-9 {
            j += 1;
        }
        if j < b.samples.len() && (b.samples[j].t - s.t).abs() <= 1e-9 {
            for (p, q) in s.bodies.iter().zip(&b.samples[j].bodies) {
                worst = worst.max((p.x - q.x).hypot(p.z - q.z));
            }
        }
    }
    worst
}

impl RunResult {
    /// Body `body`'s (0-based) surge displacement over the samples, m: the anchor's drag
    /// distance for 0, the ship's for N − 1; 0 without samples.
    pub fn displacement(&self, body: usize) -> f64 {
        match (self.samples.first(), self.samples.last()) {
            (Some(a), Some(b)) => b.bodies[body].x - a.bodies[body].x,
            _ => 0.0,
        }
    }

    /// When the anchor first started to slide, s.
    pub fn anchor_start(&self) -> Option<f64> {
        self.anchor_events.iter().find(|e| e.now == AnchorDof::Free).map(|e| e.t)
    }

    /// Keeps the largest tension at every joint, `tensions` seen at t (s).
    pub(crate) fn track_peaks(&mut self, t: f64, tensions: &[f64]) {
        for (peak, &tension) in self.peak_tensions.iter_mut().zip(tensions) {
            if tension > peak.tension {
                *peak = PeakTension { tension, t };
            }
        }
    }

    /// Whether the run got past its start, so that its peaks and drift mean something: it
    /// completed an interval, or its ship was at rest at the start and the run stopped there
    /// (its peaks are the starting state's). A run refused or failed at the start did not.
    pub fn ran(&self) -> bool {
        self.steps > 0 || self.stop == Stop::ShipStopped
    }

    /// Whether the run observed its starting state, so that E_0, the work and the energy
    /// drift exist (a run that failed in its first interval has them; one refused before its
    /// first step does not).
    pub fn observed(&self) -> bool {
        !self.samples.is_empty()
    }

    /// The largest peak tension of the run and its joint k (between B_{k−1} and B_k).
    pub fn peak_tension(&self) -> Option<(usize, PeakTension)> {
        self.peak_tensions
            .iter()
            .enumerate()
            .max_by(|a, b| a.1.tension.total_cmp(&b.1.tension))
            .map(|(i, p)| (i + 2, *p))
    }
}

impl RunResult {
    /// A result with nothing run yet, for `stepper`'s kernel and loads and `n` bodies.
    pub(crate) fn empty(stepper: &super::Stepper<'_>, n: usize) -> Self {
        RunResult {
            samples: Vec::new(),
            stop: Stop::EndTime,
            t_end: 0.0,
            stopping_time: None,
            stopping_distance: None,
            anchor_events: Vec::new(),
            peak_tensions: vec![PeakTension::default(); n - 1],
            steps: 0,
            rhs_evaluations: 0,
            wall_time: Duration::ZERO,
            cpu_time: None,
            energy0: 0.0,
            max_energy_drift: 0.0,
            energy_scale: 0.0,
            kernel: stepper.kernel(),
            kernel_form: stepper.kernel_form(),
            load_code: stepper.load_code().map(str::to_string),
            physics: stepper.physics().to_string(),
            initial_residual: None,
            stability: None,
        }
    }
}

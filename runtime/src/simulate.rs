//! One run: integrate a model from t = 0 until the ship stops, the end time, or a
//! numerical failure, checking every step.
//!
//! After every accepted step the state is *observed*: body states and accelerations, the
//! joint forces (Eq. 52), the seabed's normal and holding forces on the anchor (Eqs. 37, 50)
//! and the energy balance (Eq. 63). Two kinds of event are located to round-off by bisection
//! on re-integrated partial steps, not merely detected at the next step:
//!
//! - the anchor's stick–slip switch (discussion after Eq. 26 and Eq. 37): held until the
//!   holding force exceeds μN, then sliding with friction −μN (N implicit, from the same
//!   solve; the paper lags it by one step, see docs/model-choices.md) until its velocity
//!   returns to zero, where it is held again if the pull is below μN;
//! - the ship stopping: the first zero of its surge velocity.
//!
//! Every step is checked for non-finite values, energy runaway (relative drift of the
//! energy balance beyond `solver.max_energy_drift`) and constraint-force spikes (a joint
//! force above [`SPIKE_FACTOR`] times the line's largest break load: the model has no
//! breaking, so such a force is numerical, not physical); a failure stops the run with a
//! [`Failure`] naming the time, the body, the likely cause and a suggestion, and the
//! samples up to the last good step are kept.

use std::time::{Duration, Instant};

use crate::dynamics::{Dynamics, WORK_COUNT};
use crate::energy::Energy;
use crate::forces::Forces;
use crate::integrate::{Adaptive, Dp5, Integrator, RhsError, Rk4, Sdirk4, Tolerances};
use crate::kernel::{AnchorDof, AnchorReaction, BodyAcceleration, BodyState, Kernel};
use crate::model::Model;
use crate::scene::Method;
use crate::stability::{self, StabilityLimit};

/// A joint force above this multiple of the largest break load in the line (chain or
/// cable) is a numerical spike: the line would have parted many times over.
pub const SPIKE_FACTOR: f64 = 10.0;

/// The state of every body at one output time.
#[derive(Clone, Debug)]
pub struct Sample {
    /// s.
    pub t: f64,
    pub bodies: Vec<BodyState>,
    pub energy: Energy,
    /// |F^H_k| for the joints k = 2 … N (index k − 2), N.
    pub tensions: Vec<f64>,
    pub anchor: AnchorDof,
}

/// Why a run ended.
#[derive(Clone, Debug, PartialEq)]
pub enum Stop {
    /// `solver.end_time` was reached.
    EndTime,
    /// The ship's surge speed reached zero.
    ShipStopped,
    /// A numerical failure; see the diagnostic.
    Failed(Failure),
}

/// What went wrong, where and what to do about it.
#[derive(Clone, Debug, PartialEq)]
pub struct Failure {
    /// Time of the first bad step, s.
    pub t: f64,
    /// The body most involved (1-based, B_k).
    pub body: usize,
    /// Its description, e.g. "auxiliary rod (B_45, 13.9 kg)".
    pub body_name: String,
    /// What was detected.
    pub what: String,
    /// The likely cause.
    pub cause: String,
    /// What to try.
    pub suggestion: String,
}

impl std::fmt::Display for Failure {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(
            f,
            "numerical failure at t = {:.4} s: {}\n  body: {}\n  likely cause: {}\n  suggestion: {}",
            self.t, self.what, self.body_name, self.cause, self.suggestion
        )
    }
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
    pub samples: Vec<Sample>,
    pub stop: Stop,
    /// Simulated time reached (last good state), s.
    pub t_end: f64,
    /// First zero of the ship's surge speed, located to round-off, s.
    pub stopping_time: Option<f64>,
    /// The anchor's switches, in order.
    pub anchor_events: Vec<AnchorEvent>,
    /// Peak tension at every joint k = 2 … N (index k − 2), over every step.
    pub peak_tensions: Vec<PeakTension>,
    pub steps: u64,
    pub rhs_evaluations: u64,
    pub wall_time: Duration,
    /// Energy balance at t = 0, J.
    pub energy0: f64,
    /// Largest relative drift |E − E_0|/E_0 of the balance over the run.
    pub max_energy_drift: f64,
    /// Kernel used.
    pub kernel: &'static str,
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
    /// When the anchor first started to slide, s.
    pub fn anchor_start(&self) -> Option<f64> {
        self.anchor_events.iter().find(|e| e.now == AnchorDof::Free).map(|e| e.t)
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

/// The observed state after an accepted step.
struct Observation {
    bodies: Vec<BodyState>,
    /// |F^H_k| of the force on B_k from B_{k−1}, k = 2 … N (index k − 2), N (Eq. 52).
    tensions: Vec<f64>,
    /// The seabed's normal and holding forces on the anchor (Eqs. 37, 50).
    reaction: AnchorReaction,
    energy: Energy,
}

/// A stretch of one observation interval with one anchor state: its start and the ship's
/// surge speed there.
struct Segment {
    t: f64,
    y: Vec<f64>,
    anchor: AnchorDof,
    direction: f64,
    ship_vx: f64,
}

/// The machinery of one run.
struct Runner<'a> {
    model: &'a Model,
    dynamics: Dynamics,
    integrator: Box<dyn Integrator>,
    qdd: Vec<f64>,
    acc: Vec<BodyAcceleration>,
}

impl Runner<'_> {
    fn n(&self) -> usize {
        self.model.body_count()
    }

    fn observe(&mut self, y: &[f64]) -> Result<Observation, RhsError> {
        let n = self.n();
        let (q, rest) = y.split_at(n);
        let (u, w) = rest.split_at(n);
        let reaction = self.dynamics.accelerations(q, u, &mut self.qdd)?;
        let bodies = self.dynamics.assembly().bodies.clone();
        self.dynamics.body_accelerations(q, u, &self.qdd, &mut self.acc);
        // Eq. 52 in Newton's form: the joint force on B_k balances the outboard bodies'
        // inertia (with added mass) less their applied loads.
        let mut tensions = vec![0.0; n - 1];
        let mut sum = [0.0, 0.0];
        for k in (1..n).rev() {
            let (b, a, l, s) = (&self.model.chain.bodies[k], &self.acc[k], &self.dynamics.loads()[k], &bodies[k]);
            let (sin, cos) = s.theta.sin_cos();
            let a_n = a.ax * sin + a.az * cos;
            sum[0] += b.mass * a.ax + b.added_mass * a_n * sin - l.fx;
            sum[1] += b.mass * a.az + b.added_mass * a_n * cos - l.fz;
            tensions[k - 1] = sum[0].hypot(sum[1]);
        }
        let work: [f64; WORK_COUNT] = w.try_into().expect("work accumulators");
        let env = &self.model.scene.environment;
        let energy = Energy::of(&self.model.chain, &bodies, env.gravity, self.model.seabed_z, work);
        Ok(Observation { bodies, tensions, reaction, energy })
    }

    /// Integrates from (t, y0) over h: one RK4 step, or error-controlled sub-steps of an
    /// adaptive method. A method's cached derivatives are keyed by (t, y), so a bisection
    /// restarting from y0 reuses them; a change of the anchor's state resets the method
    /// ([`Runner::set_state`]).
    fn advance(&mut self, t: f64, y0: &[f64], h: f64) -> Result<Vec<f64>, RhsError> {
        let mut y = y0.to_vec();
        self.integrator.step(&mut self.dynamics, t, &mut y, h)?;
        Ok(y)
    }

    /// Bisects (0, h] for the first sub-step at which `g` changes sign from its value at 0.
    ///
    /// A method with a continuous extension (DP5, SDIRK4) integrates [t, t + h] once and is
    /// probed on its interpolants, to their accuracy (one evaluation per probe, for the
    /// observation); RK4 re-integrates from (t, y0) to each probe, so the event falls on
    /// a step of its own.
    fn locate(
        &mut self,
        t: f64,
        y0: &[f64],
        h: f64,
        g: impl Fn(&Observation) -> bool,
    ) -> Result<(f64, Vec<f64>, Observation), RhsError> {
        let y_end = self.advance(t, y0, h)?;
        let mut y = y_end.clone();
        let dense = self.integrator.dense_state(t + h, &mut y);
        let (mut lo, mut hi) = (0.0, h);
        let mut best = None;
        for _ in 0..60 {
            let mid = 0.5 * (lo + hi);
            if !(dense && self.integrator.dense_state(t + mid, &mut y)) {
                y = self.advance(t, y0, mid)?;
            }
            let obs = self.observe(&y)?;
            if g(&obs) {
                hi = mid;
                best = Some((mid, y.clone(), obs));
            } else {
                lo = mid;
            }
            if hi - lo <= 1e-12 * h.max(1e-300) {
                break;
            }
        }
        match best {
            Some(b) => Ok(b),
            None => {
                let obs = self.observe(&y_end)?;
                Ok((h, y_end, obs))
            }
        }
    }

    fn mu(&self) -> f64 {
        self.dynamics.forces().anchor.friction_coefficient
    }

    fn release(&self, obs: &Observation) -> bool {
        releases(obs, self.mu())
    }

    fn set_sliding(&mut self, direction: f64) {
        self.set_state(AnchorDof::Free, direction);
    }

    /// Sets the anchor's state (held, or sliding in `direction`). The right-hand side
    /// changes at the same (t, y), so the method forgets what it cached.
    fn set_state(&mut self, anchor: AnchorDof, direction: f64) {
        match anchor {
            AnchorDof::Stuck => self.dynamics.stick_anchor(),
            AnchorDof::Free => self.dynamics.slide_anchor(direction),
        }
        self.integrator.reset();
    }

    fn set_stuck(&mut self, y: &mut [f64]) {
        let n = self.n();
        y[2 * n - 1] = 0.0;
        self.set_state(AnchorDof::Stuck, 0.0);
    }
}

/// Integrates `model` with `kernel`; `residual_kernel`, when given, first evaluates the
/// initial configuration's [`StaticResidual`].
pub fn run_checked(model: &Model, kernel: Box<dyn Kernel>, residual_kernel: Box<dyn Kernel>) -> RunResult {
    let residual = static_residual(model, residual_kernel).ok();
    let mut result = run(model, kernel);
    result.initial_residual = residual;
    result
}

/// Integrates `model` with `kernel`.
pub fn run(model: &Model, kernel: Box<dyn Kernel>) -> RunResult {
    let solver = &model.scene.solver;
    let n = model.body_count();
    let kernel_name = kernel.name();
    let forces = Forces::new(model);
    let physics = forces.description();
    let dim = 2 * n + WORK_COUNT;
    let mut r = Runner {
        model,
        dynamics: Dynamics::new(kernel, forces, model.anchor),
        integrator: integrator(solver, dim),
        qdd: vec![0.0; n],
        acc: vec![BodyAcceleration::default(); n],
    };
    let dt = solver.dt;
    let spike_bound = SPIKE_FACTOR * model.scene.chain.break_load.max(model.scene.cable.break_load);
    let stride = ((solver.output_interval / dt).round() as u64).max(1);
    let max_steps = (solver.end_time / dt).round() as u64;
    let start = Instant::now();

    let mut y: Vec<f64> = model.q0.iter().chain(&model.u0).copied().chain([0.0; WORK_COUNT]).collect();
    let mut result = RunResult {
        samples: Vec::new(),
        stop: Stop::EndTime,
        t_end: 0.0,
        stopping_time: None,
        anchor_events: Vec::new(),
        peak_tensions: vec![PeakTension::default(); n - 1],
        steps: 0,
        rhs_evaluations: 0,
        wall_time: Duration::ZERO,
        energy0: 0.0,
        max_energy_drift: 0.0,
        kernel: kernel_name,
        physics,
        initial_residual: None,
        stability: None,
    };
    // A fixed step beyond the initial state's stability limit is refused before the run.
    if solver.integrator == Method::Rk4 {
        match stability::limit(&mut r.dynamics, &y) {
            Ok(limit) => {
                result.stability = Some(limit);
                if dt > limit.rk4_dt {
                    result.stop = Stop::Failed(step_beyond_limit(model, &limit));
                    return result;
                }
            }
            Err(e) => {
                result.stop = Stop::Failed(failure(model, 0.0, &y, &e.0));
                return result;
            }
        }
    }
    let evaluations_before = r.dynamics.evaluations();
    let mut obs = match r.observe(&y) {
        Ok(o) => o,
        Err(e) => {
            result.stop = Stop::Failed(failure(model, 0.0, &y, &e.0));
            return result;
        }
    };
    result.energy0 = obs.energy.balance();
    record(&mut result, 0.0, &obs, r.dynamics.anchor());
    let mut t = 0.0;
    let mut step = 0u64;

    'steps: while step < max_steps {
        let t_next = (step + 1) as f64 * dt;
        let prev_ship_vx = obs.bodies[n - 1].vx;
        // Integrate [t, t_next] in segments split at located anchor events.
        let (mut t_seg, mut y_seg) = (t, y.clone());
        let mut segments = vec![Segment {
            t,
            y: y.clone(),
            anchor: r.dynamics.anchor(),
            direction: r.dynamics.sliding_direction(),
            ship_vx: prev_ship_vx,
        }];
        let mut events = 0;
        let outcome: Result<(Vec<f64>, Observation), RhsError> = loop {
            let h = t_next - t_seg;
            let y_end = match r.advance(t_seg, &y_seg, h) {
                Ok(v) => v,
                Err(e) => break Err(e),
            };
            if y_end.iter().any(|v| !v.is_finite()) {
                break Err(RhsError("non-finite state".into()));
            }
            let end = match r.observe(&y_end) {
                Ok(o) => o,
                Err(e) => break Err(e),
            };
            events += 1;
            let anchor = r.dynamics.anchor();
            let switched = match anchor {
                AnchorDof::Stuck if r.mu() > 0.0 && r.release(&end) && events < 8 => {
                    let mu = r.mu();
                    let (hs, ys, os) = match r.locate(t_seg, &y_seg, h, |o| releases(o, mu)) {
                        Ok(v) => v,
                        Err(e) => break Err(e),
                    };
                    r.set_sliding(-os.reaction.holding.signum());
                    Some((hs, ys, AnchorDof::Free, os.bodies[n - 1].vx))
                }
                AnchorDof::Free
                    if r.dynamics.sliding_direction() != 0.0
                        && end.bodies[0].vx * r.dynamics.sliding_direction() <= 0.0
                        && events < 8 =>
                {
                    let dir = r.dynamics.sliding_direction();
                    let (hs, mut ys, _) = match r.locate(t_seg, &y_seg, h, |o| o.bodies[0].vx * dir <= 0.0) {
                        Ok(v) => v,
                        Err(e) => break Err(e),
                    };
                    // The anchor has come to rest: held if the pull is within μN.
                    r.set_stuck(&mut ys);
                    let held = match r.observe(&ys) {
                        Ok(o) => o,
                        Err(e) => break Err(e),
                    };
                    let ship_vx = held.bodies[n - 1].vx;
                    if r.release(&held) {
                        r.set_sliding(-held.reaction.holding.signum());
                        Some((hs, ys, AnchorDof::Free, ship_vx))
                    } else {
                        Some((hs, ys, AnchorDof::Stuck, ship_vx))
                    }
                }
                _ => None,
            };
            match switched {
                Some((hs, ys, now, ship_vx)) => {
                    result.anchor_events.push(AnchorEvent { t: t_seg + hs, now });
                    t_seg += hs;
                    y_seg = ys;
                    segments.push(Segment {
                        t: t_seg,
                        y: y_seg.clone(),
                        anchor: now,
                        direction: r.dynamics.sliding_direction(),
                        ship_vx,
                    });
                    if t_next - t_seg <= 1e-12 * dt {
                        let o = match r.observe(&y_seg) {
                            Ok(o) => o,
                            Err(e) => break Err(e),
                        };
                        break Ok((y_seg, o));
                    }
                }
                None => break Ok((y_end, end)),
            }
        };
        let (y_new, obs_new) = match outcome {
            Ok(v) => v,
            Err(e) => {
                result.stop = Stop::Failed(failure(model, t_next, &y, &e.0));
                break 'steps;
            }
        };
        let drift = (obs_new.energy.balance() - result.energy0).abs() / result.energy0.abs().max(f64::MIN_POSITIVE);
        if !drift.is_finite() || drift > solver.max_energy_drift {
            let what = format!(
                "energy runaway: |E − E_0|/E_0 = {drift:.3e} exceeds solver.max_energy_drift = {}",
                solver.max_energy_drift
            );
            result.stop = Stop::Failed(failure(model, t_next, &y, &what));
            break;
        }
        result.max_energy_drift = result.max_energy_drift.max(drift);
        if let Some((k, tension)) = spike(&obs_new, spike_bound) {
            let what = format!(
                "constraint-force spike: joint {k} (B_{} – B_{k}) carries {tension:.3e} N, above {SPIKE_FACTOR} × the \
                 line's largest break load ({spike_bound:.3e} N in all)",
                k - 1
            );
            let mut f = failure(model, t_next, &y, &what);
            // The joint's outer body, not the fastest-turning one, is where it shows.
            (f.body, f.body_name) = (k, body_name(model, k));
            result.stop = Stop::Failed(f);
            break;
        }

        let ship_vx = obs_new.bodies[n - 1].vx;
        if prev_ship_vx > 0.0 && ship_vx <= 0.0 && result.stopping_time.is_none() {
            // The first segment whose end has the ship at rest, bisected under that
            // segment's anchor state (an anchor event may have split the interval).
            let i = (0..segments.len())
                .find(|&i| segments.get(i + 1).map_or(ship_vx, |s| s.ship_vx) <= 0.0)
                .unwrap_or(segments.len() - 1);
            let seg = &segments[i];
            let length = segments.get(i + 1).map_or(t_next, |s| s.t) - seg.t;
            let now = (r.dynamics.anchor(), r.dynamics.sliding_direction());
            r.set_state(seg.anchor, seg.direction);
            let located = r.locate(seg.t, &seg.y, length, |o| o.bodies[n - 1].vx <= 0.0);
            r.set_state(now.0, now.1);
            match located {
                Ok((hs, ys, os)) => {
                    result.stopping_time = Some(seg.t + hs);
                    if solver.stop_when_ship_stops {
                        step += 1;
                        t = seg.t + hs;
                        drop(ys);
                        track_peaks(&mut result, t, &os);
                        record(&mut result, t, &os, r.dynamics.anchor());
                        result.stop = Stop::ShipStopped;
                        break;
                    }
                }
                Err(e) => {
                    result.stop = Stop::Failed(failure(model, t_next, &y, &e.0));
                    break;
                }
            }
        }
        step += 1;
        t = t_next;
        y = y_new;
        obs = obs_new;
        track_peaks(&mut result, t, &obs);
        if step % stride == 0 || step == max_steps {
            record(&mut result, t, &obs, r.dynamics.anchor());
        }
    }
    result.t_end = t;
    result.steps = step;
    result.rhs_evaluations = r.dynamics.evaluations() - evaluations_before;
    result.wall_time = start.elapsed();
    result
}

/// The method a scene names, sized for states of `dim` entries.
pub fn integrator(solver: &crate::scene::Solver, dim: usize) -> Box<dyn Integrator> {
    let tolerances = || Tolerances::new(solver.rtol, solver.atol).expect("tolerances checked with the scene");
    match solver.integrator {
        Method::Rk4 => Box::new(Rk4::new(dim)),
        Method::Dp5 => {
            let mut m = Dp5::with_tolerances(dim, tolerances());
            m.control.h_max = solver.dt;
            Box::new(Adaptive::new(m))
        }
        Method::Sdirk4 => {
            let mut m = Sdirk4::with_tolerances(dim, tolerances());
            m.control.h_max = solver.dt;
            Box::new(Adaptive::new(m))
        }
    }
}

/// The refusal of an RK4 step above the stability limit (`solver.dt` out of range).
fn step_beyond_limit(model: &Model, limit: &StabilityLimit) -> Failure {
    let dt = model.scene.solver.dt;
    let (re, im) = (limit.lambda.re, limit.lambda.im.abs());
    Failure {
        t: 0.0,
        body: limit.body,
        body_name: body_name(model, limit.body),
        what: format!(
            "solver.dt = {dt} s is above this scene's RK4 stability limit of {:.3e} s: valid range 0 < dt ≤ {:.3e} s",
            limit.rk4_dt, limit.rk4_dt
        ),
        cause: format!(
            "the fastest mode of the linearised equations at t = 0 (eigenvalue {re:.3e} ± {im:.3e}i 1/s, period \
             {:.3e} s) would grow without bound at this step",
            if im > 0.0 { 2.0 * std::f64::consts::PI / im } else { f64::INFINITY }
        ),
        suggestion: format!(
            "set solver.dt ≤ {:.1e} s, or integrator = \"dp5\" (adapts its step) or \"sdirk4\" (stiff)",
            0.9 * limit.rk4_dt
        ),
    }
}

/// "auxiliary rod (B_45, 13.9 kg, 1.00 m)" for body k (1-based).
fn body_name(model: &Model, k: usize) -> String {
    let body = &model.chain.bodies[k - 1];
    format!("{} (B_{k}, {:.1} kg, {:.2} m)", body.kind, body.mass, body.length())
}

/// The joint k (2 … N) and its force when the largest joint force exceeds `bound`, N.
fn spike(obs: &Observation, bound: f64) -> Option<(usize, f64)> {
    let (i, tension) =
        obs.tensions.iter().enumerate().fold((0, 0.0), |best, (i, &t)| if t > best.1 { (i, t) } else { best });
    (tension > bound).then_some((i + 2, tension))
}

/// Static friction is exceeded: |H| > μN (Eq. 37 and the discussion after Eq. 26).
fn releases(obs: &Observation, mu: f64) -> bool {
    obs.reaction.holding.abs() > mu * obs.reaction.normal.max(0.0)
}

fn track_peaks(result: &mut RunResult, t: f64, obs: &Observation) {
    for (peak, &tension) in result.peak_tensions.iter_mut().zip(&obs.tensions) {
        if tension > peak.tension {
            *peak = PeakTension { tension, t };
        }
    }
}

fn record(result: &mut RunResult, t: f64, obs: &Observation, anchor: AnchorDof) {
    result.samples.push(Sample {
        t,
        bodies: obs.bodies.clone(),
        energy: obs.energy,
        tensions: obs.tensions.clone(),
        anchor,
    });
}

/// Builds the diagnostic for a failure detected at `t`, from the last good state.
fn failure(model: &Model, t: f64, last_good: &[f64], what: &str) -> Failure {
    let n = model.body_count();
    let u = &last_good[n..2 * n];
    // The body turning fastest relative to its neighbour is where the unstable mode lives.
    let (i, _) = u[..n - 1]
        .iter()
        .enumerate()
        .fold((0, -1.0), |best, (i, &v)| if v.abs() > best.1 { (i, v.abs()) } else { best });
    let k = i + 2;
    let body = &model.chain.bodies[k - 1];
    let solver = &model.scene.solver;
    let dt = solver.dt;
    let ratio = model.chain.bodies.iter().map(|b| b.mass).fold(0.0, f64::max) / body.mass;
    let mode = format!(
        "the stiffest mode: a light element swinging between heavy neighbours under high tension (mass ratio \
         {ratio:.0}:1 with the heaviest body)"
    );
    let kept = format!("the first {:.3} s up to the failure are kept", (t - dt).max(0.0));
    let (cause, suggestion) = match solver.integrator {
        Method::Rk4 => (
            format!("the explicit step dt = {dt} s is beyond the stability limit of {mode}"),
            format!("reduce solver.dt (try {:.1e} s) or use integrator = \"dp5\"; {kept}", dt / 16.0),
        ),
        Method::Dp5 => (
            format!("the error-controlled steps could not follow {mode}"),
            format!("tighten solver.rtol (now {}) or use integrator = \"sdirk4\"; {kept}", solver.rtol),
        ),
        Method::Sdirk4 => (
            format!("the implicit method's Newton iterations or error control failed on {mode}"),
            format!("tighten solver.rtol (now {}) or reduce solver.dt (now {dt} s); {kept}", solver.rtol),
        ),
    };
    Failure { t, body: k, body_name: body_name(model, k), what: what.to_string(), cause, suggestion }
}

//! One run: integrate a model from t = 0 until the ship stops, the end time, or a
//! numerical failure, checking every step.
//!
//! Every step is checked for non-finite values and for energy runaway (relative drift of
//! the energy balance beyond `solver.max_energy_drift`). A failure stops the run with a
//! [`Failure`] that names the time, the body, the likely cause and a suggestion; the
//! samples up to the last good step are kept.

use std::time::{Duration, Instant};

use crate::dynamics::Dynamics;
use crate::energy::Energy;
use crate::forces::Forces;
use crate::integrate::{Integrator, Rk4};
use crate::kernel::{BodyState, Kernel};
use crate::model::Model;
use crate::scene::IntegratorKind;

/// The state of every body at one output time.
#[derive(Clone, Debug)]
pub struct Sample {
    /// s.
    pub t: f64,
    pub bodies: Vec<BodyState>,
    pub energy: Energy,
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

/// Everything a run produced.
#[derive(Clone, Debug)]
pub struct RunResult {
    pub samples: Vec<Sample>,
    pub stop: Stop,
    /// Simulated time reached (last good step), s.
    pub t_end: f64,
    /// First zero of the ship's surge speed, located by linear interpolation, s.
    pub stopping_time: Option<f64>,
    pub steps: u64,
    pub rhs_evaluations: u64,
    pub wall_time: Duration,
    /// Total energy at t = 0, J.
    pub energy0: f64,
    /// Largest relative drift |E − E_0|/E_0 seen over the run.
    pub max_energy_drift: f64,
    /// Kernel used.
    pub kernel: &'static str,
}

/// Integrates `model` with `kernel`.
pub fn run(model: &Model, kernel: Box<dyn Kernel>) -> RunResult {
    let solver = &model.scene.solver;
    let g = model.scene.environment.gravity;
    let n = model.body_count();
    let kernel_name = kernel.name();
    let mut dynamics = Dynamics::new(kernel, Forces::new(model), model.anchor);
    let mut integrator: Box<dyn Integrator> = match solver.integrator {
        IntegratorKind::Rk4 => Box::new(Rk4::new(2 * n)),
    };
    let dt = solver.dt;
    let stride = ((solver.output_interval / dt).round() as u64).max(1);
    let max_steps = (solver.end_time / dt).round() as u64;

    let start = Instant::now();
    let mut y: Vec<f64> = model.q0.iter().chain(&model.u0).copied().collect();
    let mut bodies = vec![BodyState::default(); n];
    let observe = |dynamics: &mut Dynamics, y: &[f64], bodies: &mut [BodyState]| {
        let (q, u) = y.split_at(n);
        dynamics.kernel_mut().kinematics(q, u, bodies);
        Energy::of(&model.chain, bodies, g, model.seabed_z)
    };
    let e0 = observe(&mut dynamics, &y, &mut bodies);
    let energy0 = e0.total();
    let mut samples = vec![Sample { t: 0.0, bodies: bodies.clone(), energy: e0 }];
    let mut prev_ship_vx = bodies[n - 1].vx;
    let mut stop = Stop::EndTime;
    let mut stopping_time = None;
    let mut max_drift: f64 = 0.0;
    let mut t = 0.0;
    let mut step = 0;
    let mut last_good = y.clone();

    while step < max_steps {
        let result = integrator.step(&mut dynamics, t, &mut y, dt);
        let t_new = (step + 1) as f64 * dt;
        if let Err(e) = result {
            stop = Stop::Failed(failure(model, t_new, &last_good, &e.0));
            break;
        }
        if let Some(i) = y.iter().position(|v| !v.is_finite()) {
            let what = format!("non-finite state (entry {i} of y = (q, u))");
            stop = Stop::Failed(failure(model, t_new, &last_good, &what));
            break;
        }
        let energy = observe(&mut dynamics, &y, &mut bodies);
        let drift = (energy.total() - energy0).abs() / energy0.abs().max(f64::MIN_POSITIVE);
        if !drift.is_finite() || drift > solver.max_energy_drift {
            let what = format!(
                "energy runaway: |E − E_0|/E_0 = {drift:.3e} exceeds solver.max_energy_drift = {}",
                solver.max_energy_drift
            );
            stop = Stop::Failed(failure(model, t_new, &last_good, &what));
            break;
        }
        max_drift = max_drift.max(drift);
        step += 1;
        t = t_new;
        last_good.copy_from_slice(&y);

        let ship_vx = bodies[n - 1].vx;
        let stopped = prev_ship_vx > 0.0 && ship_vx <= 0.0;
        if stopped && stopping_time.is_none() {
            stopping_time = Some(t - dt + dt * prev_ship_vx / (prev_ship_vx - ship_vx));
        }
        prev_ship_vx = ship_vx;
        let last = step == max_steps || (stopped && solver.stop_when_ship_stops);
        if step % stride == 0 || last {
            samples.push(Sample { t, bodies: bodies.clone(), energy });
        }
        if stopped && solver.stop_when_ship_stops {
            stop = Stop::ShipStopped;
            break;
        }
    }

    RunResult {
        samples,
        stop,
        t_end: t,
        stopping_time,
        steps: step,
        rhs_evaluations: dynamics.evaluations(),
        wall_time: start.elapsed(),
        energy0,
        max_energy_drift: max_drift,
        kernel: kernel_name,
    }
}

/// Builds the diagnostic for a failure detected at `t`, from the last good state.
fn failure(model: &Model, t: f64, last_good: &[f64], what: &str) -> Failure {
    let n = model.body_count();
    let u = &last_good[n..];
    // The body turning fastest relative to its neighbour is where the unstable mode lives.
    let (i, _) = u[..n - 1]
        .iter()
        .enumerate()
        .fold((0, -1.0), |best, (i, &v)| if v.abs() > best.1 { (i, v.abs()) } else { best });
    let k = i + 2;
    let body = &model.chain.bodies[k - 1];
    let dt = model.scene.solver.dt;
    Failure {
        t,
        body: k,
        body_name: format!("{} (B_{k}, {:.1} kg, {:.2} m)", body.kind, body.mass, body.length()),
        what: what.to_string(),
        cause: format!(
            "the explicit step dt = {dt} s is beyond the stability limit of the stiffest mode: a light element \
             swinging between heavy neighbours under high tension (mass ratio {:.0}:1 with the heaviest body)",
            model.chain.bodies.iter().map(|b| b.mass).fold(0.0, f64::max) / body.mass
        ),
        suggestion: format!(
            "reduce solver.dt (try {:.1e} s) and rerun; the first {:.3} s up to the failure are kept",
            dt / 16.0,
            t - dt
        ),
    }
}

//! One run: integrate a model from t = 0 until the ship stops, the end time, or a
//! numerical failure, checking every step.
//!
//! After every accepted step the state is *observed* (the private `observe` module): body
//! states and accelerations, the joint forces (Eq. 52), the seabed's normal and holding
//! forces on the anchor (Eqs. 37, 50) and the energy balance (Eq. 63). Two kinds of event
//! are located to round-off by bisection on the integrator's dense output or on
//! re-integrated partial steps, not merely detected at the next step ([`events`]):
//!
//! - the anchor's stick–slip switch (discussion after Eq. 26 and Eq. 37): held until the
//!   holding force exceeds μN, then sliding with friction −μN (N implicit, from the same
//!   solve; the paper lags it by one step, see docs/model-choices.md) until its velocity
//!   returns to zero, where it is held again if the pull is below μN;
//! - the ship stopping: the first zero of its surge velocity.
//!
//! Every step is checked ([`health`]) for non-finite values, energy runaway (relative drift
//! of the energy balance beyond `solver.max_energy_drift`) and constraint-force spikes (a
//! joint force above [`SPIKE_FACTOR`] times the line's largest break load: the model has no
//! breaking, so such a force is numerical, not physical); a failure stops the run with a
//! [`Failure`] naming the time, the body and what was detected (typed data: the words are
//! the workflow's), and the samples up to the last good step are kept.
//!
//! [`Stepper`] advances a run interval by interval and says why it stopped ([`Stopped`]);
//! [`run`] drives it and collects the [`RunResult`].

use std::sync::atomic::{AtomicBool, Ordering};
use std::time::Instant;

pub mod cpu;
pub mod events;
pub mod failure;
pub mod health;
mod observe;
pub mod result;
pub mod stepper;

pub use failure::{early_window, is_early, Failure, FailureKind, EARLY_FAILURE_TIME};
pub use health::SPIKE_FACTOR;
pub use result::{
    static_residual, trajectory_difference, AnchorEvent, PeakTension, RunResult, Sample, StaticResidual, Stop,
};
pub use stepper::{Stepper, Stopped};

use crate::integrate::{Adaptive, Dp5, Integrator, Rk4, Sdirk4, Tolerances};
use crate::kernel::Kernel;
use crate::model::Model;
use crate::scene::Method;
use crate::stability::StabilityError;

/// Integrates `model` with `kernel`; `residual_kernel`, when given, first evaluates the
/// initial configuration's [`StaticResidual`].
pub fn run_checked(model: &Model, kernel: Box<dyn Kernel>, residual_kernel: Box<dyn Kernel>) -> RunResult {
    run_checked_cancellable(model, kernel, residual_kernel, &AtomicBool::new(false)).expect("nothing cancels it")
}

/// [`run_checked`], stopped as [`run_cancellable`] is: the one way every front end (the
/// command line's `run` and `batch`, sweeps, Python) runs a scene, so a failure's diagnosis
/// is the same wherever it is read.
pub fn run_checked_cancellable(
    model: &Model,
    kernel: Box<dyn Kernel>,
    residual_kernel: Box<dyn Kernel>,
    cancel: &AtomicBool,
) -> Result<RunResult, Cancelled> {
    let residual = static_residual(model, residual_kernel).ok();
    let mut result = run_cancellable(model, kernel, cancel)?;
    result.initial_residual = residual;
    if let Stop::Failed(f) = &mut result.stop {
        if failure::is_early(f.t, model.scene.solver.dt) {
            f.initial_residual = residual.map(Box::new);
        }
    }
    Ok(result)
}

/// Integrates `model` with `kernel`.
///
/// Case 1 of the paper (the embedded default scene) for its first 0.1 s with the generated
/// kernel:
///
/// ```
/// use kanestop_runtime::generated::GeneratedKernel;
/// use kanestop_runtime::model::Model;
/// use kanestop_runtime::paper::DEFAULT_SCENE;
/// use kanestop_runtime::scene::Scene;
/// use kanestop_runtime::simulate::{self, Stop};
///
/// let mut scene = Scene::from_toml(DEFAULT_SCENE, "case01.toml").unwrap();
/// scene.solver.end_time = 0.1; // s; the full case runs until the ship stops
/// let model = Model::new(&scene).unwrap();
/// let kernel = GeneratedKernel::new(&model.chain).unwrap();
/// let result = simulate::run(&model, Box::new(kernel));
/// assert_eq!(result.stop, Stop::EndTime);
/// assert_eq!(result.steps, 50); // dt = 0.002 s
/// assert!(!result.samples.is_empty());
/// ```
pub fn run(model: &Model, kernel: Box<dyn Kernel>) -> RunResult {
    run_cancellable(model, kernel, &AtomicBool::new(false)).expect("nothing cancels it")
}

/// A run cancelled from another thread (Python's Ctrl-C): its partial result is dropped.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Cancelled {
    /// The simulated time reached, s.
    pub t: f64,
}

/// [`run`], which stops with [`Cancelled`] at the first step after `cancel` is set, or
/// during the start-up stability analysis (RK4's, about 0.5 s at N = 518 and 1.4 s at
/// N = 1018) before its next column of the Jacobian or product of Arnoldi's method.
pub fn run_cancellable(model: &Model, kernel: Box<dyn Kernel>, cancel: &AtomicBool) -> Result<RunResult, Cancelled> {
    let mut stepper = Stepper::new(model, kernel);
    let mut result = RunResult::empty(&stepper, model.body_count());
    let (start, cpu_start) = (Instant::now(), cpu::thread_cpu_time());
    let started = stepper.start_cancellable(cancel);
    if matches!(&started, Err(f) if f.kind == FailureKind::Stability(StabilityError::Cancelled)) {
        return Err(Cancelled { t: 0.0 });
    }
    result.stability = stepper.stability();
    if let Err(f) = started {
        result.stop = Stop::Failed(f);
        return Ok(result);
    }
    result.energy0 = stepper.energy0();
    result.samples.extend(stepper.sample());
    result.stop = loop {
        if cancel.load(Ordering::Relaxed) {
            return Err(Cancelled { t: stepper.t() });
        }
        match stepper.step() {
            Ok(Stopped::AnchorSwitched(event)) => result.anchor_events.push(event),
            Ok(stopped @ (Stopped::Step | Stopped::ShipStopped { .. })) => {
                for (t, tensions) in stepper.inner_tensions() {
                    result.track_peaks(t, tensions);
                }
                result.track_peaks(stepper.t(), stepper.tensions());
                // A ship stopped at the start took no interval: its sample is the first.
                if (stopped != Stopped::Step || stepper.at_output()) && stepper.steps() > 0 {
                    result.samples.extend(stepper.sample());
                }
                if stopped != Stopped::Step {
                    break Stop::ShipStopped;
                }
            }
            Ok(Stopped::EndTime) => break Stop::EndTime,
            Err(f) => break Stop::Failed(f),
        }
    };
    result.stopping_time = stepper.stopping_time();
    result.stopping_distance = stepper.stopping_distance();
    result.t_end = stepper.t();
    result.steps = stepper.steps();
    result.rhs_evaluations = stepper.rhs_evaluations();
    result.max_energy_drift = stepper.max_energy_drift();
    result.energy_scale = stepper.energy_scale();
    result.wall_time = start.elapsed();
    result.cpu_time = cpu::since(cpu_start);
    Ok(result)
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

#[cfg(test)]
mod tests {
    use super::*;
    use crate::generated::GeneratedKernel;
    use crate::paper::DEFAULT_SCENE;
    use crate::scene::Scene;

    #[test]
    fn a_cancelled_run_stops_at_its_next_step() {
        let mut scene = Scene::from_toml(DEFAULT_SCENE, "case01.toml").unwrap();
        scene.solver.dt = 1e-4; // 200 000 steps to the stop: seconds, not the 20 ms waited
        let model = Model::new(&scene).unwrap();
        let kernel = || Box::new(GeneratedKernel::new(&model.chain).unwrap());
        assert_eq!(run_cancellable(&model, kernel(), &AtomicBool::new(true)).unwrap_err(), Cancelled { t: 0.0 });
        // Set from another thread while it runs: it stops before the ship does (20 s).
        let cancel = AtomicBool::new(false);
        std::thread::scope(|s| {
            let run = s.spawn(|| run_cancellable(&model, kernel(), &cancel));
            std::thread::sleep(std::time::Duration::from_millis(20));
            cancel.store(true, Ordering::Relaxed);
            let stopped = run.join().unwrap();
            assert!(matches!(stopped, Err(Cancelled { t }) if t < 20.0), "{stopped:?}");
        });
    }
}

//! The run as a stepper: [`Stepper::step`] advances the model by one output interval of
//! `solver.dt` (or to the next event inside it) and says why it stopped.
//!
//! An interval [t, t + dt] is integrated in segments split at located anchor switches:
//! each segment is integrated to the interval's end, its end observed, and when the
//! anchor's switching function changed sign the switch is located by bisection
//! ([`super::events`]), applied, and the segment ends there ([`Stopped::AnchorSwitched`]).
//! A completed interval is checked ([`super::health`]); a first zero of the ship's surge
//! speed inside it is then located under the anchor state of the segment it fell in.

use std::sync::atomic::AtomicBool;

use super::events::{self, Located};
use super::failure::{Failure, FailureKind};
use super::health;
use super::observe::{Observation, Observer, Watched};
use super::{integrator, AnchorEvent, Sample};
use crate::dynamics::{Dynamics, WORK_COUNT};
use crate::forces::Forces;
use crate::integrate::Integrator;
use crate::kernel::{AnchorDof, Kernel};
use crate::model::Model;
use crate::scene::Method;
use crate::stability::{self, StabilityLimit};

/// An interval is split at located anchor switches into at most this many segments: a
/// switch is looked for at the end of each of the first `MAX_SEGMENTS − 1`, and the last
/// integrates to the interval's end whatever the anchor does. A real stick–slip cycle takes
/// many steps; more switches than this within one step is chatter on the switching surface
/// (held and sliding each trigger the other within round-off), which would otherwise
/// loop without advancing time.
pub const MAX_SEGMENTS: u32 = 8;

/// Why [`Stepper::step`] returned.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Stopped {
    /// An interval of `solver.dt` was completed and passed the checks: the stepper is at its
    /// end ([`Stepper::t`]).
    Step,
    /// The anchor switched inside the current interval, at the event's time; the next call
    /// continues the interval from there.
    AnchorSwitched(AnchorEvent),
    /// The ship's surge speed reached zero at `t` (s) and the scene stops the run there
    /// (`solver.stop_when_ship_stops`): the stepper is at the located stop. Without that
    /// setting the run goes on and [`Stepper::stopping_time`] keeps the time. A ship at rest
    /// at the start (`initial.ship_speed = 0`) has stopped at t = 0: the first call returns
    /// this with no interval taken.
    ShipStopped {
        /// s.
        t: f64,
    },
    /// `solver.end_time` is reached: nothing more to do.
    EndTime,
}

/// A segment of one interval with one anchor state: its start and the ship's surge speed
/// there.
struct Segment {
    t: f64,
    y: Vec<f64>,
    anchor: AnchorDof,
    direction: f64,
    ship_vx: f64,
}

/// The interval being integrated.
struct Interval {
    t_next: f64,
    /// Start of the current segment and the state there.
    t_seg: f64,
    y_seg: Vec<f64>,
    segments: Vec<Segment>,
    /// Segments integrated so far.
    count: u32,
    /// A switch landed on the interval's end: nothing is left to integrate.
    at_end: bool,
    prev_ship_vx: f64,
}

/// A located, applied anchor switch: its offset in the segment (s), the state there, the
/// anchor's state from then on and the ship's surge speed (m/s).
type Switch = (f64, Vec<f64>, AnchorDof, f64);

/// How a segment ended.
enum SegmentEnd {
    Switched(AnchorEvent),
    Interval(Vec<f64>, Observation),
}

/// The right-hand side, the method and the observation's scratch.
struct Machine {
    dynamics: Dynamics,
    integrator: Box<dyn Integrator>,
    observer: Observer,
}

impl Machine {
    fn observe(&mut self, model: &Model, y: &[f64]) -> Result<Observation, FailureKind> {
        Ok(self.observer.observe(model, &mut self.dynamics, y)?)
    }

    fn locate(
        &mut self,
        model: &Model,
        span: (f64, &[f64], f64),
        g: impl Fn(&Observation) -> bool,
    ) -> Result<Located<Observation>, FailureKind> {
        let Machine { dynamics, integrator, observer } = self;
        let observe = |d: &mut Dynamics, y: &[f64]| observer.observe(model, d, y).map_err(FailureKind::from);
        events::locate(integrator.as_mut(), dynamics, span, observe, g)
    }

    fn mu(&self) -> f64 {
        self.dynamics.forces().anchor.friction_coefficient
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
}

/// One run of a model, advanced interval by interval.
///
/// A few steps of case 1 (the embedded default scene) with the generated kernel:
///
/// ```
/// use kanestop_runtime::generated::GeneratedKernel;
/// use kanestop_runtime::model::Model;
/// use kanestop_runtime::paper::DEFAULT_SCENE;
/// use kanestop_runtime::scene::Scene;
/// use kanestop_runtime::simulate::{Stepper, Stopped};
///
/// let mut scene = Scene::from_toml(DEFAULT_SCENE, "case01.toml").unwrap();
/// scene.solver.end_time = 0.1; // s
/// let model = Model::new(&scene).unwrap();
/// let kernel = GeneratedKernel::new(&model.chain).unwrap();
/// let mut stepper = Stepper::new(&model, Box::new(kernel));
/// stepper.start().unwrap();
/// for _ in 0..3 {
///     assert_eq!(stepper.step().unwrap(), Stopped::Step);
/// }
/// assert_eq!(stepper.steps(), 3);
/// assert!((stepper.t() - 3.0 * scene.solver.dt).abs() < 1e-12);
/// assert_eq!(stepper.tensions().len(), model.body_count() - 1);
/// ```
pub struct Stepper<'a> {
    model: &'a Model,
    m: Machine,
    kernel: &'static str,
    kernel_form: Option<&'static str>,
    /// The signature of the generated load code in use, none on the force modules.
    load_code: Option<String>,
    physics: String,
    stability: Option<StabilityLimit>,
    /// The last good state: time (s), y = (q, u, W) and its observation.
    t: f64,
    y: Vec<f64>,
    obs: Option<Observation>,
    steps: u64,
    max_steps: u64,
    stride: u64,
    interval: Option<Interval>,
    evaluations0: u64,
    /// E_0, the drift's scale K and the largest drift.
    drift: health::DriftWatch,
    spike_bound: f64,
    /// RK4's watch over its tensions from step to step; none under the adaptive methods,
    /// whose observations are `solver.dt` apart, not their steps.
    chatter: Option<health::ChatterWatch>,
    stopping_time: Option<f64>,
    /// The ship's surge position at the start and at the stop (its x), m.
    ship_x: (f64, Option<f64>),
    /// The tensions at an adaptive method's sub-step ends inside the current interval
    /// (time, s; |F^H_k|, N), before any anchor switch or ship stop in it.
    inner: Vec<(f64, Vec<f64>)>,
}

impl<'a> Stepper<'a> {
    /// A stepper at t = 0 for `model` with `kernel`; call [`Stepper::start`] before stepping.
    pub fn new(model: &'a Model, kernel: Box<dyn Kernel>) -> Self {
        let solver = &model.scene.solver;
        let n = model.body_count();
        let kernel_name = kernel.name();
        let forces = Forces::new(model);
        let physics = forces.description();
        let m = Machine {
            dynamics: Dynamics::new(kernel, forces, model.anchor),
            integrator: integrator(solver, 2 * n + WORK_COUNT),
            observer: Observer::new(n),
        };
        // After fusing: weight alone moves an unrolled kernel to the rolled one.
        let kernel_form = m.dynamics.kernel_form();
        let load_code = m.dynamics.loads_fused().then(|| m.dynamics.forces().signature().name());
        Stepper {
            model,
            m,
            kernel: kernel_name,
            kernel_form,
            load_code,
            physics,
            stability: None,
            t: 0.0,
            y: model.q0.iter().chain(&model.u0).copied().chain([0.0; WORK_COUNT]).collect(),
            obs: None,
            steps: 0,
            max_steps: solver.steps(),
            stride: ((solver.output_interval / solver.dt).round() as u64).max(1),
            interval: None,
            evaluations0: 0,
            drift: health::DriftWatch::default(),
            spike_bound: health::spike_bound(model),
            chatter: (solver.integrator == Method::Rk4).then(|| health::ChatterWatch::for_model(model)),
            stopping_time: None,
            ship_x: (0.0, None),
            inner: Vec::new(),
        }
    }

    /// Checks and observes the initial state: under RK4 the step is refused above the
    /// initial state's stability limit ([`Stepper::stability`]); then the energy balance
    /// E_0 is taken. Right-hand-side evaluations are counted from after the limit.
    pub fn start(&mut self) -> Result<(), Failure> {
        self.start_cancellable(&AtomicBool::new(false))
    }

    /// [`Stepper::start`], whose stability analysis stops soon after `cancel` is set, with
    /// the failure [`FailureKind::Stability`] of [`stability::StabilityError::Cancelled`].
    pub fn start_cancellable(&mut self, cancel: &AtomicBool) -> Result<(), Failure> {
        if self.model.scene.solver.integrator == Method::Rk4 {
            let limit =
                stability::limit(&mut self.m.dynamics, &self.y, cancel).map_err(|e| self.failure(0.0, e.into()))?;
            self.stability = Some(limit);
            let dt = self.model.scene.solver.dt;
            // An estimate (a long line's unsettled Krylov space) refuses nothing: the run's
            // health checks watch for a blow-up as they do past t = 0.
            if limit.settled && dt > limit.rk4_dt {
                return Err(Failure::step_above_limit(dt, limit));
            }
        }
        self.evaluations0 = self.m.dynamics.evaluations();
        let obs = self.m.observe(self.model, &self.y).map_err(|e| self.failure(0.0, e))?;
        self.drift = health::DriftWatch::new(obs.energy.balance(), obs.energy.kinetic_total());
        // A ship at rest has stopped before it moved: its first zero is the start, not the
        // first sign change of the round-off around rest that the line's settling gives.
        self.ship_x.0 = obs.ship_x();
        if obs.ship_vx() <= 0.0 {
            self.stopping_time = Some(0.0);
            self.ship_x.1 = Some(self.ship_x.0);
        }
        self.obs = Some(obs);
        Ok(())
    }

    /// Advances to the end of the current interval or to the next event in it. After an
    /// `Err`, [`Stopped::ShipStopped`] or [`Stopped::EndTime`] the run is over: the stepper
    /// stays at its last good state.
    pub fn step(&mut self) -> Result<Stopped, Failure> {
        self.advance().map_err(|f| self.with_last_limit(f))
    }

    /// [`Stepper::step`] before a failure is given its [`Failure::last_limit`].
    fn advance(&mut self) -> Result<Stopped, Failure> {
        if self.steps >= self.max_steps || self.obs.is_none() {
            return Ok(Stopped::EndTime);
        }
        if self.steps == 0 && self.stopping_time == Some(0.0) && self.model.scene.solver.stop_when_ship_stops {
            return Ok(Stopped::ShipStopped { t: 0.0 });
        }
        let mut iv = match self.interval.take() {
            Some(iv) => iv,
            None => {
                self.inner.clear();
                self.open_interval()
            }
        };
        let t_next = iv.t_next;
        let (y_new, obs_new) = match self.segment(&mut iv).map_err(|k| self.failure(t_next, k))? {
            SegmentEnd::Switched(event) => {
                self.interval = Some(iv);
                return Ok(Stopped::AnchorSwitched(event));
            }
            SegmentEnd::Interval(y, o) => (y, o),
        };
        self.check(&obs_new).map_err(|k| self.failure(t_next, k))?;
        if let Some(stopped) = self.ship_stop(&iv, &obs_new).map_err(|k| self.failure(t_next, k))? {
            return Ok(stopped);
        }
        self.steps += 1;
        (self.t, self.y, self.obs) = (t_next, y_new, Some(obs_new));
        Ok(Stopped::Step)
    }

    /// Time of the last good state, s.
    pub fn t(&self) -> f64 {
        self.t
    }

    /// Intervals completed.
    pub fn steps(&self) -> u64 {
        self.steps
    }

    /// Whether the last completed interval ends on an output time (every
    /// `solver.output_interval`, and the end time).
    #[allow(clippy::manual_is_multiple_of)] // is_multiple_of needs Rust 1.87; the crate's MSRV is 1.80
    pub fn at_output(&self) -> bool {
        self.steps % self.stride == 0 || self.steps == self.max_steps
    }

    /// The last good state as an output sample (`None` before a successful start).
    pub fn sample(&self) -> Option<Sample> {
        self.obs.as_ref().map(|o| Sample {
            t: self.t,
            bodies: o.bodies.clone(),
            energy: o.energy,
            tensions: o.tensions.clone(),
            anchor: self.m.dynamics.anchor(),
        })
    }

    /// |F^H_k| at the last good state, k = 2 … N (index k − 2), N (Eq. 52).
    pub fn tensions(&self) -> &[f64] {
        self.obs.as_ref().map_or(&[], |o| &o.tensions)
    }

    /// The tensions |F^H_k| (N, k = 2 … N) at the states an adaptive method accepted inside
    /// the interval in progress or last completed (`OdeSystem::accepted`), with their times
    /// (s), before its ship stop if it has one: where a peak may fall between two
    /// observations. Those after an anchor switch are dropped (integrated under the anchor's
    /// old state; the ones before it come from the first integration of the segment, not the
    /// switch's location, which agree to the tolerance). Empty under RK4.
    pub fn inner_tensions(&self) -> impl Iterator<Item = (f64, &[f64])> {
        let until = self.t;
        self.inner.iter().filter(move |(t, _)| *t < until).map(|(t, v)| (*t, v.as_slice()))
    }

    /// The energy balance at t = 0, J (0 before a successful start).
    pub fn energy0(&self) -> f64 {
        self.drift.energy0
    }

    /// The energy drift's scale K: the largest kinetic energy of the states that passed the
    /// checks (E^K, the entrained water's included), J.
    pub fn energy_scale(&self) -> f64 {
        self.drift.kinetic_max
    }

    /// Largest relative drift |E − E_0|/K over the completed intervals, K as it stood before
    /// each ([`Stepper::energy_scale`]).
    pub fn max_energy_drift(&self) -> f64 {
        self.drift.max_drift
    }

    /// First zero of the ship's surge speed, located to round-off, s: 0 for a ship at rest
    /// at the start.
    pub fn stopping_time(&self) -> Option<f64> {
        self.stopping_time
    }

    /// The ship's surge displacement from the start to that zero, m.
    pub fn stopping_distance(&self) -> Option<f64> {
        self.ship_x.1.map(|x| x - self.ship_x.0)
    }

    /// RK4's step limit at t = 0 (RK4 runs, after [`Stepper::start`]).
    pub fn stability(&self) -> Option<StabilityLimit> {
        self.stability
    }

    /// Right-hand-side solves since the start (the stability limit's excluded).
    pub fn rhs_evaluations(&self) -> u64 {
        self.m.dynamics.evaluations() - self.evaluations0
    }

    /// The kernel's name.
    pub fn kernel(&self) -> &'static str {
        self.kernel
    }

    /// The generated kernel's form (`unrolled` or `rolled`), none for the reference.
    pub fn kernel_form(&self) -> Option<&'static str> {
        self.kernel_form
    }

    /// The load signature whose generated code computes the loads, none when the force
    /// modules do.
    pub fn load_code(&self) -> Option<&str> {
        self.load_code.as_deref()
    }

    /// What the loads include.
    pub fn physics(&self) -> &str {
        &self.physics
    }

    /// `f` with RK4's stability limit at the last good state, for the failures a step beyond
    /// it gives (energy runaway, a non-finite state, a force spike), where it is settled. Its
    /// right-hand sides are not counted: the run's are. About as long as the start's analysis
    /// (0.5 s at N = 518), and not cancellable: it runs once, after the failure.
    fn with_last_limit(&mut self, mut f: Failure) -> Failure {
        let blow_up = matches!(
            f.kind,
            FailureKind::EnergyRunaway { .. } | FailureKind::NonFiniteState | FailureKind::ForceSpike { .. }
        );
        if self.model.scene.solver.integrator != Method::Rk4 || !blow_up || !self.y.iter().all(|v| v.is_finite()) {
            return f;
        }
        // At the start, the limit the run began with.
        let limit = if self.steps == 0 {
            self.stability
        } else {
            let before = self.m.dynamics.evaluations();
            let limit = stability::limit(&mut self.m.dynamics, &self.y, &AtomicBool::new(false)).ok();
            self.evaluations0 += self.m.dynamics.evaluations() - before;
            limit
        };
        // An estimate (a long line's unsettled Krylov space) is no bound to advise a step by.
        f.last_limit = limit.filter(|l| l.settled).map(Box::new);
        f
    }

    fn failure(&self, t: f64, kind: FailureKind) -> Failure {
        Failure::at(self.model, t, &self.y, kind)
    }

    fn open_interval(&self) -> Interval {
        let prev_ship_vx = self.obs.as_ref().map_or(0.0, Observation::ship_vx);
        let first = Segment {
            t: self.t,
            y: self.y.clone(),
            anchor: self.m.dynamics.anchor(),
            direction: self.m.dynamics.sliding_direction(),
            ship_vx: prev_ship_vx,
        };
        Interval {
            t_next: (self.steps + 1) as f64 * self.model.scene.solver.dt,
            t_seg: self.t,
            y_seg: self.y.clone(),
            segments: vec![first],
            count: 0,
            at_end: false,
            prev_ship_vx,
        }
    }

    /// Integrates the current segment to the interval's end and looks for an anchor switch.
    fn segment(&mut self, iv: &mut Interval) -> Result<SegmentEnd, FailureKind> {
        if iv.at_end {
            let o = self.m.observe(self.model, &iv.y_seg)?;
            return Ok(SegmentEnd::Interval(std::mem::take(&mut iv.y_seg), o));
        }
        let h = iv.t_next - iv.t_seg;
        let inner_from = self.inner.len();
        let Machine { dynamics, integrator, observer } = &mut self.m;
        let mut watched = Watched { model: self.model, dynamics, observer, inner: &mut self.inner };
        let y_end = events::advance(integrator.as_mut(), &mut watched, iv.t_seg, &iv.y_seg, h)?;
        health::finite(&y_end)?;
        // The states inside pass the spike check as the interval's end does.
        for (_, tensions) in &self.inner[inner_from..] {
            health::no_spike(tensions, self.spike_bound)?;
        }
        let end = self.m.observe(self.model, &y_end)?;
        iv.count += 1;
        let switch = if iv.count < MAX_SEGMENTS { self.anchor_switch(iv, h, &end)? } else { None };
        let Some((hs, ys, now, ship_vx)) = switch else { return Ok(SegmentEnd::Interval(y_end, end)) };
        let event = AnchorEvent { t: iv.t_seg + hs, now };
        // The segment's states after the switch were integrated under the anchor's old state.
        let kept = inner_from + self.inner[inner_from..].iter().take_while(|(t, _)| *t < event.t).count();
        self.inner.truncate(kept);
        iv.t_seg += hs;
        iv.y_seg = ys;
        let direction = self.m.dynamics.sliding_direction();
        iv.segments.push(Segment { t: iv.t_seg, y: iv.y_seg.clone(), anchor: now, direction, ship_vx });
        iv.at_end = iv.t_next - iv.t_seg <= 1e-12 * self.model.scene.solver.dt;
        Ok(SegmentEnd::Switched(event))
    }

    /// A switch of the anchor inside the segment of length h ending in `end`, located and
    /// applied: (offset, state, the anchor's state from then on, the ship's surge speed).
    fn anchor_switch(&mut self, iv: &Interval, h: f64, end: &Observation) -> Result<Option<Switch>, FailureKind> {
        let mu = self.m.mu();
        let direction = self.m.dynamics.sliding_direction();
        let span = (iv.t_seg, iv.y_seg.as_slice(), h);
        match self.m.dynamics.anchor() {
            AnchorDof::Stuck if mu > 0.0 && events::releases(end, mu) => {
                let (hs, ys, os) = self.m.locate(self.model, span, |o| events::releases(o, mu))?;
                self.m.set_state(AnchorDof::Free, -os.reaction.holding.signum());
                Ok(Some((hs, ys, AnchorDof::Free, os.ship_vx())))
            }
            AnchorDof::Free if direction != 0.0 && events::reversed(end, direction) => {
                let (hs, mut ys, _) = self.m.locate(self.model, span, |o| events::reversed(o, direction))?;
                // The anchor has come to rest: held if the pull is within μN.
                ys[2 * self.model.body_count() - 1] = 0.0;
                self.m.set_state(AnchorDof::Stuck, 0.0);
                let held = self.m.observe(self.model, &ys)?;
                if events::releases(&held, mu) {
                    self.m.set_state(AnchorDof::Free, -held.reaction.holding.signum());
                    Ok(Some((hs, ys, AnchorDof::Free, held.ship_vx())))
                } else {
                    Ok(Some((hs, ys, AnchorDof::Stuck, held.ship_vx())))
                }
            }
            _ => Ok(None),
        }
    }

    /// The health checks of a completed interval ([`health::DriftWatch::check`]).
    fn check(&mut self, obs: &Observation) -> Result<(), FailureKind> {
        let limit = self.model.scene.solver.max_energy_drift;
        let bound = self.spike_bound;
        let chatter = &mut self.chatter;
        self.drift.check(obs.energy.balance(), obs.energy.kinetic_total(), limit, || {
            health::no_spike(&obs.tensions, bound)?;
            chatter.as_mut().map_or(Ok(()), |c| c.check(&obs.tensions))
        })
    }

    /// Locates the ship's first stop inside the completed interval, under the anchor state
    /// of the first segment whose end has the ship at rest (an anchor event may have split
    /// the interval). `Some` when the run ends there.
    fn ship_stop(&mut self, iv: &Interval, end: &Observation) -> Result<Option<Stopped>, FailureKind> {
        let ship_vx = end.ship_vx();
        if !(iv.prev_ship_vx > 0.0 && ship_vx <= 0.0 && self.stopping_time.is_none()) {
            return Ok(None);
        }
        let segments = &iv.segments;
        let i = (0..segments.len())
            .find(|&i| segments.get(i + 1).map_or(ship_vx, |s| s.ship_vx) <= 0.0)
            .unwrap_or(segments.len() - 1);
        let seg = &segments[i];
        let length = segments.get(i + 1).map_or(iv.t_next, |s| s.t) - seg.t;
        let now = (self.m.dynamics.anchor(), self.m.dynamics.sliding_direction());
        self.m.set_state(seg.anchor, seg.direction);
        let located = self.m.locate(self.model, (seg.t, &seg.y, length), events::ship_stopped);
        self.m.set_state(now.0, now.1);
        let (hs, _, os) = located?;
        let t = seg.t + hs;
        self.stopping_time = Some(t);
        self.ship_x.1 = Some(os.ship_x());
        if !self.model.scene.solver.stop_when_ship_stops {
            return Ok(None);
        }
        self.steps += 1;
        (self.t, self.obs) = (t, Some(os));
        Ok(Some(Stopped::ShipStopped { t }))
    }
}

//! What is observed after every accepted step: body states and accelerations, the joint
//! forces (Eq. 52), the seabed's normal and holding forces on the anchor (Eqs. 37, 50) and
//! the energy balance (Eq. 63).

use crate::dynamics::{Dynamics, WORK_COUNT};
use crate::energy::Energy;
use crate::integrate::OdeSystem;
use crate::joints;
use crate::kernel::{AnchorReaction, BodyAcceleration, BodyState, RhsError};
use crate::model::Model;

/// The observed state after an accepted step.
#[derive(Clone, Debug)]
pub(crate) struct Observation {
    pub bodies: Vec<BodyState>,
    /// |F^H_k| of the force on B_k from B_{k−1}, k = 2 … N (index k − 2), N (Eq. 52).
    pub tensions: Vec<f64>,
    /// The seabed's normal and holding forces on the anchor (Eqs. 37, 50).
    pub reaction: AnchorReaction,
    pub energy: Energy,
}

impl Observation {
    /// The ship's surge position (the last body's x), m.
    pub fn ship_x(&self) -> f64 {
        self.bodies[self.bodies.len() - 1].x
    }

    /// The ship's surge velocity (the last body's ẋ), m/s.
    pub fn ship_vx(&self) -> f64 {
        self.bodies[self.bodies.len() - 1].vx
    }

    /// The anchor's surge velocity (B_1's ẋ), m/s.
    pub fn anchor_vx(&self) -> f64 {
        self.bodies[0].vx
    }
}

/// Scratch of the observation: generalised and body accelerations, joint forces.
pub(crate) struct Observer {
    qdd: Vec<f64>,
    acc: Vec<BodyAcceleration>,
    joints: Vec<[f64; 2]>,
}

impl Observer {
    /// Scratch for `n` bodies.
    pub fn new(n: usize) -> Self {
        Observer { qdd: vec![0.0; n], acc: vec![BodyAcceleration::default(); n], joints: vec![[0.0; 2]; n - 1] }
    }

    /// Observes y = (q, u, W) under `dynamics`' current anchor state.
    pub fn observe(&mut self, model: &Model, dynamics: &mut Dynamics, y: &[f64]) -> Result<Observation, RhsError> {
        let n = model.body_count();
        let (q, rest) = y.split_at(n);
        let (u, w) = rest.split_at(n);
        let reaction = dynamics.accelerations(q, u, &mut self.qdd)?;
        let bodies = dynamics.body_states().to_vec();
        // Eq. 52: from the solve's own rows when the kernel kept them, else in Newton's form
        // from the body accelerations.
        if !dynamics.joint_forces(&mut self.joints) {
            dynamics.body_accelerations(q, u, &self.qdd, &mut self.acc);
            joints::from_accelerations(&model.chain, &bodies, &self.acc, dynamics.loads(), &mut self.joints);
        }
        let tensions = self.joints.iter().map(|&f| joints::magnitude(f)).collect();
        let mut work = [0.0; WORK_COUNT];
        work.copy_from_slice(w);
        let env = &model.scene.environment;
        let energy = Energy::of(&model.chain, &bodies, env.gravity, model.seabed_z, work);
        Ok(Observation { bodies, tensions, reaction, energy })
    }
}

/// The right-hand side for a segment's integration that also watches the states an adaptive
/// method accepts inside it: their joint tensions (time, s; |F^H_k|, N) go to `inner`, for
/// the run's peaks. DP5 has evaluated its last stage at such a state, so `Dynamics` answers
/// the observation's solve from memory.
pub(crate) struct Watched<'a> {
    pub model: &'a Model,
    pub dynamics: &'a mut Dynamics,
    pub observer: &'a mut Observer,
    pub inner: &'a mut Vec<(f64, Vec<f64>)>,
}

impl OdeSystem for Watched<'_> {
    fn dim(&self) -> usize {
        self.dynamics.dim()
    }

    fn quadrature_components(&self) -> usize {
        self.dynamics.quadrature_components()
    }

    fn rhs(&mut self, t: f64, y: &[f64], dy: &mut [f64]) -> Result<(), RhsError> {
        self.dynamics.rhs(t, y, dy)
    }

    fn accepted(&mut self, t: f64, y: &[f64]) -> Result<(), RhsError> {
        let o = self.observer.observe(self.model, self.dynamics, y)?;
        self.inner.push((t, o.tensions));
        Ok(())
    }
}

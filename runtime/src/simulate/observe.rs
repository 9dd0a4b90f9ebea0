//! What is observed after every accepted step: body states and accelerations, the joint
//! forces (Eq. 52), the seabed's normal and holding forces on the anchor (Eqs. 37, 50) and
//! the energy balance (Eq. 63).

use crate::dynamics::{Dynamics, WORK_COUNT};
use crate::energy::Energy;
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
    /// The ship's surge velocity (the last body's ẋ), m/s.
    pub fn ship_vx(&self) -> f64 {
        self.bodies[self.bodies.len() - 1].vx
    }

    /// The anchor's surge velocity (B_1's ẋ), m/s.
    pub fn anchor_vx(&self) -> f64 {
        self.bodies[0].vx
    }
}

/// Scratch of the observation: generalised and body accelerations.
pub(crate) struct Observer {
    qdd: Vec<f64>,
    acc: Vec<BodyAcceleration>,
}

impl Observer {
    /// Scratch for `n` bodies.
    pub fn new(n: usize) -> Self {
        Observer { qdd: vec![0.0; n], acc: vec![BodyAcceleration::default(); n] }
    }

    /// Observes y = (q, u, W) under `dynamics`' current anchor state.
    pub fn observe(&mut self, model: &Model, dynamics: &mut Dynamics, y: &[f64]) -> Result<Observation, RhsError> {
        let n = model.body_count();
        let (q, rest) = y.split_at(n);
        let (u, w) = rest.split_at(n);
        let reaction = dynamics.accelerations(q, u, &mut self.qdd)?;
        let bodies = dynamics.assembly().bodies.clone();
        dynamics.body_accelerations(q, u, &self.qdd, &mut self.acc);
        // Eq. 52 in Newton's form: the joint force on B_k balances the outboard bodies'
        // inertia (with added mass) less their applied loads.
        let mut tensions = vec![0.0; n - 1];
        let mut sum = [0.0, 0.0];
        for k in (1..n).rev() {
            let (b, a, l, s) = (&model.chain.bodies[k], &self.acc[k], &dynamics.loads()[k], &bodies[k]);
            let (sin, cos) = (s.sin, s.cos);
            let a_n = a.ax * sin + a.az * cos;
            sum[0] += b.mass * a.ax + b.added_mass * a_n * sin - l.fx;
            sum[1] += b.mass * a.az + b.added_mass * a_n * cos - l.fz;
            tensions[k - 1] = (sum[0] * sum[0] + sum[1] * sum[1]).sqrt(); // no overflow below 1e150 N
        }
        let mut work = [0.0; WORK_COUNT];
        work.copy_from_slice(w);
        let env = &model.scene.environment;
        let energy = Energy::of(&model.chain, &bodies, env.gravity, model.seabed_z, work);
        Ok(Observation { bodies, tensions, reaction, energy })
    }
}

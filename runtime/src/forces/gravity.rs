//! Weight: G_k = m_k g, downward through the centroid (Eqs. 40, 53).

use crate::chain::Chain;
use crate::kernel::{BodyState, Load};

/// The weights of every body (Eq. 40).
#[derive(Clone, Debug)]
pub struct Gravity {
    /// G_k, N.
    weights: Vec<f64>,
}

impl Gravity {
    /// Weights for the chain's masses under gravity `g` (m/s²).
    pub fn new(chain: &Chain, g: f64) -> Self {
        Gravity { weights: chain.bodies.iter().map(|b| b.mass * g).collect() }
    }

    /// Adds −G_k to the z force of each body's load, N.
    pub fn add(&self, _bodies: &[BodyState], loads: &mut [Load]) {
        for (load, w) in loads.iter_mut().zip(&self.weights) {
            load.fz -= w;
        }
    }
}

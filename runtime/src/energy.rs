//! The energy terms of Section 3.3 that exist so far: kinetic (Eq. 64) and gravitational
//! potential (Eq. 65) with the seabed as datum.

use serde::{Deserialize, Serialize};

use crate::chain::Chain;
use crate::kernel::BodyState;

/// Energy terms at one instant, J.
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct Energy {
    /// E^K (Eq. 64).
    pub kinetic: f64,
    /// E^G (Eq. 65), heights above the seabed.
    pub potential: f64,
}

impl Energy {
    /// E^K + E^G.
    pub fn total(&self) -> f64 {
        self.kinetic + self.potential
    }

    /// The terms for body states `bodies`, gravity `g` (m/s²) and seabed height `seabed_z` (m).
    pub fn of(chain: &Chain, bodies: &[BodyState], g: f64, seabed_z: f64) -> Energy {
        let mut e = Energy::default();
        for (body, s) in chain.bodies.iter().zip(bodies) {
            e.kinetic += 0.5 * (body.mass * (s.vx * s.vx + s.vz * s.vz) + body.inertia[1] * s.omega * s.omega);
            e.potential += body.mass * g * (s.z - seabed_z);
        }
        e
    }
}

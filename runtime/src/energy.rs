//! The energy balance of Section 3.3 (Eqs. 63–69).
//!
//! E_0 = E^K + E^G − Σ W_i, with E^K the kinetic energy of the bodies (Eq. 64) plus that of
//! the water they entrain (the added mass of Eq. 46), E^G the gravitational potential with
//! the seabed as datum (Eq. 65, buoyancy counted as work), and W_i the work done on the
//! system by each other force (Eqs. 66–69: hydrostatics, anchor friction, seabed, water). The
//! W_i are integrated with the state, so the balance holds to integration accuracy.

use serde::{Deserialize, Serialize};

use crate::chain::Chain;
use crate::forces::{self, Power, REPORTED_WORK, WORK_TERMS};
use crate::kernel::BodyState;

/// Energy terms at one instant, J.
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct Energy {
    /// E^K of the bodies (Eq. 64).
    pub kinetic: f64,
    /// Kinetic energy of the entrained water, ½ m_a v_n² + ½ J ω² (Eq. 46).
    pub added_kinetic: f64,
    /// E^G, weights only, heights above the seabed (Eq. 65).
    pub potential: f64,
    /// Work done on the system by each term of [`WORK_TERMS`] since t = 0.
    pub work: Power,
}

impl Energy {
    /// E^K + E^A, the kinetic energy of the bodies and of the water they entrain, J.
    pub fn kinetic_total(&self) -> f64 {
        self.kinetic + self.added_kinetic
    }

    /// E^K + E^A + E^G − Σ W_i: constant for exact integration (Eq. 63).
    pub fn balance(&self) -> f64 {
        self.kinetic + self.added_kinetic + self.potential - self.work.iter().sum::<f64>()
    }

    /// The terms for body states `bodies`, gravity `g` (m/s²), seabed height `seabed_z` (m)
    /// and accumulated work `work` (J).
    pub fn of(chain: &Chain, bodies: &[BodyState], g: f64, seabed_z: f64, work: Power) -> Energy {
        let mut e = Energy { work, ..Energy::default() };
        for (body, s) in chain.bodies.iter().zip(bodies) {
            e.kinetic += 0.5 * (body.mass * (s.vx * s.vx + s.vz * s.vz) + body.inertia[1] * s.omega * s.omega);
            let v_n = s.vx * s.sin + s.vz * s.cos;
            e.added_kinetic += 0.5 * (body.added_mass * v_n * v_n + body.added_inertia * s.omega * s.omega);
            e.potential += body.mass * g * (s.z - seabed_z);
        }
        e
    }

    /// Named work terms, for reports.
    pub fn work_terms(&self) -> impl Iterator<Item = (&'static str, f64)> + '_ {
        WORK_TERMS.iter().copied().zip(self.work.iter().copied())
    }

    /// The work by the names of [`REPORTED_WORK`] (J): the split terms and the sums
    /// `friction` and `drag` of before the split.
    pub fn reported_work(&self) -> [(&'static str, f64); REPORTED_WORK.len()] {
        forces::reported_work(&self.work)
    }
}

//! Applied loads on each body (Section 3.2), one small module per force.
//!
//! The kernel calls [`Forces::loads`] with the body states it computed and projects the
//! result with the partial velocities (Eq. 23). Implemented so far: gravity (Eqs. 40, 53).
//! Buoyancy, seabed reaction, anchor friction and drag, Morison drag and added mass, and
//! the ship's hydrostatics and resistance come with the full physics.

pub mod gravity;

use crate::chain::Chain;
use crate::kernel::{BodyState, Load, LoadModel};
use crate::model::Model;

/// Which physics the loads include, for reports.
pub const PHYSICS: &str = "gravity only: buoyancy, seabed, friction, drag and ship hydrodynamics are not modelled yet";

/// All loads of a model.
#[derive(Clone, Debug)]
pub struct Forces {
    gravity: gravity::Gravity,
}

impl Forces {
    /// The loads of a model, as its scene's switches select.
    pub fn new(model: &Model) -> Self {
        Forces::gravity_only(&model.chain, model.scene.environment.gravity)
    }

    /// Weight alone, gravity `g` in m/s²: a chain hanging in vacuum.
    pub fn gravity_only(chain: &Chain, g: f64) -> Self {
        Forces { gravity: gravity::Gravity::new(chain, g) }
    }
}

impl LoadModel for Forces {
    fn loads(&mut self, bodies: &[BodyState], loads: &mut [Load]) {
        loads.iter_mut().for_each(|l| *l = Load::default());
        self.gravity.add(bodies, loads);
    }
}

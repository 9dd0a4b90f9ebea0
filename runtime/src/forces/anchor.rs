//! Forces on the gravity anchor (Eqs. 36–39): buoyancy, current drag and Coulomb friction.
//!
//! The anchor only translates along the seabed; its vertical balance is a constraint, so
//! the normal force is the seabed's reaction N = m_1 g − ρ V_1 g − F_2z (Eq. 37, F_2z the
//! chain's upward pull). Stick and slip are decided by the run (see `simulate`): while the
//! anchor is held the friction is a constraint force; while it slides the friction is
//! −μ N in the direction of sliding, set here by [`AnchorForces::set_sliding_friction`].

/// The anchor's force data.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct AnchorForces {
    /// V_1, m³.
    pub volume: f64,
    /// w_1 h_1, frontal area, m².
    pub frontal_area: f64,
    /// C_1^D.
    pub drag_coefficient: f64,
    /// μ.
    pub friction_coefficient: f64,
    /// Friction force along +x while sliding, N (0 while held).
    pub sliding_friction: f64,
}

impl AnchorForces {
    /// Drag along +x, N (Eq. 39): C_D ρ w h U|U|/2 with U the current relative to the anchor.
    pub fn drag(&self, rho: f64, current: f64, vx: f64) -> f64 {
        let u = current - vx;
        0.5 * self.drag_coefficient * rho * self.frontal_area * u * u.abs()
    }

    /// Sets the sliding friction from the normal force `normal` (N) and the direction of
    /// sliding (+1 or −1): −μ N direction (Eq. 37). A non-positive normal force (the chain
    /// lifting the anchor) gives no friction.
    pub fn set_sliding_friction(&mut self, normal: f64, direction: f64) {
        self.sliding_friction = -self.friction_coefficient * normal.max(0.0) * direction;
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn drag_and_friction_of_the_paper_anchor() {
        let mut a = AnchorForces {
            volume: 16.8,
            frontal_area: 8.4,
            drag_coefficient: 1.05,
            friction_coefficient: 0.3,
            sliding_friction: 0.0,
        };
        // Sliding at 1 m/s in still water: 1.05 · 1025 · 8.4 / 2 = 4520.25 N against the motion.
        assert!((a.drag(1025.0, 0.0, 1.0) + 4520.25).abs() < 1e-9);
        // Normal force of the 40 t anchor with no chain pull: (40000 − 1025 · 16.8) g.
        let normal = (40000.0 - 1025.0 * 16.8) * 9.81;
        a.set_sliding_friction(normal, 1.0);
        assert!((a.sliding_friction + 0.3 * normal).abs() < 1e-9);
        a.set_sliding_friction(-5.0, 1.0);
        assert_eq!(a.sliding_friction, 0.0);
    }
}

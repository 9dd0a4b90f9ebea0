//! Forces on the gravity anchor (Eqs. 36–39): buoyancy, current drag and Coulomb friction.
//!
//! The anchor only translates along the seabed; its vertical balance is a constraint, so
//! the normal force is the seabed's reaction N = m_1 g − ρ V_1 g − F_2z (Eq. 37, F_2z the
//! chain's upward pull). Stick and slip are decided by the run (see `simulate`): while the
//! anchor is held the friction is a constraint force; while it slides the friction is
//! −μ N against the direction of sliding, with N the normal force of the same solve: N is
//! linear in the accelerations, so the kernel's solve takes the friction implicitly
//! ([`crate::kernel::Kernel::solve`]; the paper lags N by one step instead).

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
}

impl AnchorForces {
    /// Drag along +x, N (Eq. 39): C_D ρ w h U|U|/2 with U the current relative to the anchor.
    pub fn drag(&self, rho: f64, current: f64, vx: f64) -> f64 {
        let u = current - vx;
        0.5 * self.drag_coefficient * rho * self.frontal_area * u * u.abs()
    }

    /// The friction factor k of a sliding anchor: μ times the direction of sliding (+1
    /// toward the ship, −1 away), so that the friction force along +x is −k N.
    pub fn friction_factor(&self, direction: f64) -> f64 {
        self.friction_coefficient * direction
    }

    /// The sliding friction force along +x, N, for the normal force `normal` (N) and the
    /// factor `k` (Eq. 37): −k N, none when the chain lifts the anchor (N ≤ 0).
    pub fn sliding_friction(k: f64, normal: f64) -> f64 {
        -k * normal.max(0.0)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn drag_and_friction_of_the_paper_anchor() {
        let a = AnchorForces { volume: 16.8, frontal_area: 8.4, drag_coefficient: 1.05, friction_coefficient: 0.3 };
        // Sliding at 1 m/s in still water: 1.05 · 1025 · 8.4 / 2 = 4520.25 N against the motion.
        assert!((a.drag(1025.0, 0.0, 1.0) + 4520.25).abs() < 1e-9);
        // Normal force of the 40 t anchor with no chain pull: (40000 − 1025 · 16.8) g.
        let normal = (40000.0 - 1025.0 * 16.8) * 9.81;
        let k = a.friction_factor(1.0);
        assert!((AnchorForces::sliding_friction(k, normal) + 0.3 * normal).abs() < 1e-9);
        assert!((AnchorForces::sliding_friction(a.friction_factor(-1.0), normal) - 0.3 * normal).abs() < 1e-9);
        assert_eq!(AnchorForces::sliding_friction(k, -5.0), 0.0);
    }
}

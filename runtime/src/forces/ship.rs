//! The ship's hydrostatics (Eqs. 53–58) and frictional resistance (Eqs. 59–62).
//!
//! Eq. 62 is printed as R = (C_f + C_sf) ρ S_W v|v|; the ITTC-1957 line of Eq. 60 and the
//! allowance of Eq. 61 (from Molland et al. 2011, the paper's source) are coefficients of
//! ½ ρ S V², so the resistance here carries the ½.
//!
//! The ship is a box floating level with draught T = m/(ρ L w); its weight and buoyancy
//! balance at rest, and heave ζ and pitch θ are restored linearly (Eq. 58 with the C_33 and
//! C_55 of Eq. 56 and the G_y^M of Eq. 57).

/// Hydrostatic and resistance data of the ship, from its box and mass.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ShipHydro {
    /// ρ, kg/m³.
    pub rho: f64,
    /// g, m/s².
    pub g: f64,
    /// ∇, displaced volume at rest, m³.
    pub volume: f64,
    /// A_W, water-plane area, m².
    pub waterplane_area: f64,
    /// G_y^M, longitudinal metacentric height (Eq. 57), m.
    pub metacentric_height: f64,
    /// S_W, wetted surface, m².
    pub wetted_surface: f64,
    /// L_N, m.
    pub length: f64,
    /// ϑ, m²/s.
    pub viscosity: f64,
    /// C_sf (Eq. 61).
    pub roughness_allowance: f64,
}

impl ShipHydro {
    /// The box of length `length`, beam `beam` and mass `mass`, with hull roughness `k_s`.
    pub fn new(mass: f64, length: f64, beam: f64, k_s: f64, rho: f64, g: f64, viscosity: f64) -> Self {
        let draught = mass / (rho * length * beam);
        let volume = length * beam * draught;
        // Eq. 57: z_B = T/2 (box), z_G = T (CoG in the water plane, assumption 8),
        // L³ w / (12 ∇) = BM_L.
        let metacentric_height = draught / 2.0 + length.powi(3) * beam / (12.0 * volume) - draught;
        ShipHydro {
            rho,
            g,
            volume,
            waterplane_area: length * beam,
            metacentric_height,
            wetted_surface: length * beam + 2.0 * (length + beam) * draught,
            length,
            viscosity,
            roughness_allowance: roughness_allowance(k_s, length),
        }
    }

    /// Buoyancy at rest plus heave restoring, N (Eqs. 54, 58): ρ g (∇ − A_W ζ), ζ the
    /// centroid's height above still water.
    pub fn vertical_force(&self, heave: f64) -> f64 {
        self.rho * self.g * (self.volume - self.waterplane_area * heave)
    }

    /// Pitch restoring moment about y, N·m (Eq. 58): −ρ g ∇ G_y^M θ.
    pub fn pitch_moment(&self, pitch: f64) -> f64 {
        -self.rho * self.g * self.volume * self.metacentric_height * pitch
    }

    /// Frictional resistance along x, N (Eq. 62 with the ½ of the coefficients' definition,
    /// C = R / (½ ρ S V²)): −½ (C_f + C_sf) ρ S_W v|v| for the ship's velocity `v_rel`
    /// relative to the water. See docs/model-choices.md for why the printed form is not used.
    pub fn resistance(&self, v_rel: f64) -> f64 {
        let re = v_rel.abs() * self.length / self.viscosity;
        -0.5 * (ittc_friction(re) + self.roughness_allowance) * self.rho * self.wetted_surface * v_rel * v_rel.abs()
    }
}

/// Below this Reynolds number Eq. 60 is outside its range (log Re − 2 → 0 at Re = 100); the
/// coefficient is held at its value here. At 3 m/s the paper's ship has Re ≈ 1.4e8.
pub const MIN_REYNOLDS: f64 = 1e5;

/// ITTC-1957 friction line, Eq. 60: C_f = 0.075 / (log₁₀ Re − 2)².
pub fn ittc_friction(re: f64) -> f64 {
    let lg = re.max(MIN_REYNOLDS).log10();
    0.075 / ((lg - 2.0) * (lg - 2.0))
}

/// Roughness allowance, Eq. 61: C_sf = [105 (k_s/L)^(1/3) − 0.64] × 10⁻³.
pub fn roughness_allowance(k_s: f64, length: f64) -> f64 {
    (105.0 * (k_s / length).cbrt() - 0.64) * 1e-3
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn ittc_coefficient_at_known_reynolds_numbers() {
        // Re = 1e7: 0.075 / 5² = 0.003; Re = 1e9: 0.075 / 7².
        assert!((ittc_friction(1e7) - 0.003).abs() < 1e-15);
        assert!((ittc_friction(1e9) - 0.075 / 49.0).abs() < 1e-15);
        // The paper's ship at 3 m/s: Re = 3 · 50 / 1.05e-6 = 1.4286e8 → 0.075 / 6.15490² = 0.00197979.
        assert!((ittc_friction(3.0 * 50.0 / 1.05e-6) - 0.001_979_79).abs() < 1e-8);
    }

    #[test]
    fn paper_ship_hydrostatics() {
        let s = ShipHydro::new(500e3, 50.0, 10.0, 150e-6, 1025.0, 9.81, 1.05e-6);
        let t = 500e3 / (1025.0 * 500.0);
        assert!((s.volume - 500e3 / 1025.0).abs() < 1e-9);
        assert!((s.wetted_surface - (500.0 + 120.0 * t)).abs() < 1e-9);
        assert!((s.metacentric_height - (2500.0 / (12.0 * t) - t / 2.0)).abs() < 1e-9);
        // Buoyancy at rest balances the weight.
        assert!((s.vertical_force(0.0) - 500e3 * 9.81).abs() < 1e-6);
        // C_sf for k_s = 150 µm, L = 50 m: (105 · 0.0144225 − 0.64)e-3 = 0.874362e-3.
        assert!((s.roughness_allowance - 0.874_362e-3).abs() < 1e-9);
        // Resistance opposes motion and scales with v|v|: at 3 m/s,
        // ½ (0.00197979 + 0.000874362) · 1025 · S_W · 9 with S_W = 500 + 120 T.
        let expected = 0.5 * (0.001_979_79 + 0.000_874_362) * 1025.0 * (500.0 + 120.0 * t) * 9.0;
        assert!((s.resistance(3.0) + expected).abs() < 1e-3 * expected, "{}", s.resistance(3.0));
        assert!(s.resistance(-3.0) > 0.0);
    }
}

//! The tidal current profile, Eq. 38: U(h) = U_ST (h/d)^(1/7), h above the seabed.

/// The current of a scene.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Current {
    /// U_ST, speed at the free surface along +x, m/s.
    pub surface_speed: f64,
    /// The profile exponent (1/7 in Eq. 38).
    pub exponent: f64,
    /// d, water depth, m.
    pub depth: f64,
    /// Height of the seabed in the inertial frame, m.
    pub seabed_z: f64,
}

impl Current {
    /// Current speed along +x at height `z` (inertial frame), m/s; zero at and below the
    /// seabed, U_ST at and above the surface.
    pub fn at(&self, z: f64) -> f64 {
        if self.surface_speed == 0.0 {
            return 0.0;
        }
        let h = (z - self.seabed_z).clamp(0.0, self.depth);
        self.surface_speed * (h / self.depth).powf(self.exponent)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn one_seventh_power_law() {
        let c = Current { surface_speed: 2.0, exponent: 1.0 / 7.0, depth: 6.0, seabed_z: -6.0 };
        assert_eq!(c.at(0.0), 2.0);
        assert_eq!(c.at(-6.0), 0.0);
        // Half depth: 2 · 0.5^(1/7) = 1.81144…
        assert!((c.at(-3.0) - 1.811_447_328).abs() < 1e-8);
    }
}

//! Morison loads on a chain or cable element (Eqs. 43–47): tangential skin drag and normal
//! drag integrated along the rotating element. The added mass of Eq. 46 is inertia, not a
//! load: it is [`crate::chain::added_mass`], part of each body's a_lp.
//!
//! In body axes the water's velocity relative to the element is (v_t, U) at the centroid
//! (Eq. 43); rotation ω about y adds ω ξ to the normal component at axial position ξ from
//! the centroid, so U(ξ) = U + ω ξ. Integrating ρ D C_D U|U| / 2 over ξ ∈ [−L/2, L/2]
//! gives both cases of Eq. 47 in one closed form; the moment is about the centroid, about y.

use std::f64::consts::PI;

/// Normal drag force (along the body z axis, N) and moment (about y, N·m) on an element of
/// diameter `d`, length `len`, for the relative normal velocity `u` at the centroid and
/// angular velocity `omega` (Eq. 47), with density `rho` and coefficient `c_d`.
pub fn normal_drag(rho: f64, c_d: f64, d: f64, len: f64, u: f64, omega: f64) -> (f64, f64) {
    let k = 0.5 * rho * d * c_d;
    let half = 0.5 * len;
    if u.abs() >= omega.abs() * half {
        // Eq. 47, first case: U(ξ) keeps its sign along the element.
        let s = u.signum();
        (k * s * (u * u * len + omega * omega * len.powi(3) / 12.0), -k * s * u * omega * len.powi(3) / 6.0)
    } else {
        // Eq. 47, second case: U(ξ) changes sign; with w = u + ωξ,
        // ∫ w|w| dξ = [w²|w|/3]/ω and ∫ ξ w|w| dξ = [w³|w|/4 − u w²|w|/3]/ω².
        let (wa, wb) = (u - omega * half, u + omega * half);
        let f2 = |w: f64| w * w * w.abs() / 3.0;
        let f3 = |w: f64| w * w * w * w.abs() / 4.0;
        let force = (f2(wb) - f2(wa)) / omega;
        let first_moment = (f3(wb) - f3(wa) - u * (f2(wb) - f2(wa))) / (omega * omega);
        // A force along +z at ξ along x gives a moment −ξ F about y.
        (k * force, -k * first_moment)
    }
}

/// Tangential drag along the body x axis, N (Eq. 45): sign(v_t) π ρ D L C_F v_t² / 2.
pub fn tangential_drag(rho: f64, c_f: f64, d: f64, len: f64, v_t: f64) -> f64 {
    0.5 * PI * rho * d * len * c_f * v_t * v_t.abs()
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Direct numerical integration of ρ D C_D U|U|/2 along the element.
    fn quadrature(rho: f64, c_d: f64, d: f64, len: f64, u: f64, omega: f64) -> (f64, f64) {
        let n = 200_000;
        let (mut f, mut m) = (0.0, 0.0);
        for i in 0..n {
            let xi = -len / 2.0 + (i as f64 + 0.5) * len / n as f64;
            let w = u + omega * xi;
            let df = 0.5 * rho * d * c_d * w * w.abs() * len / n as f64;
            f += df;
            m -= xi * df;
        }
        (f, m)
    }

    #[test]
    fn eq_47_both_cases_match_quadrature() {
        for &(u, omega) in &[(0.8, 0.3), (-0.8, 0.3), (0.1, 2.0), (-0.1, -2.0), (0.0, 1.0), (0.5, 0.0)] {
            let (f, m) = normal_drag(1025.0, 1.21, 0.0474, 10.0, u, omega);
            let (fq, mq) = quadrature(1025.0, 1.21, 0.0474, 10.0, u, omega);
            assert!((f - fq).abs() < 1e-6 * fq.abs().max(1.0), "F at ({u}, {omega}): {f} vs {fq}");
            assert!((m - mq).abs() < 1e-6 * mq.abs().max(1.0), "T at ({u}, {omega}): {m} vs {mq}");
        }
    }

    #[test]
    fn drag_at_a_given_reynolds_number() {
        // Chain element D = 0.1526 m, L = 1 m at U = 1 m/s (Re = U D / ϑ ≈ 1.45e5):
        // F = ρ D C_D U² L / 2 = 1025 · 0.1526 · 1.21 / 2 = 94.631075 N.
        let (f, m) = normal_drag(1025.0, 1.21, 0.1526, 1.0, 1.0, 0.0);
        assert!((f - 94.631_075).abs() < 1e-9, "{f}");
        assert_eq!(m, 0.0);
        // Tangential: π ρ D L C_F U² / 2 = π · 1025 · 0.1526 · 0.062 / 2 = 15.233159 N.
        assert!((tangential_drag(1025.0, 0.062, 0.1526, 1.0, 1.0) - 15.233_159).abs() < 1e-6);
    }
}

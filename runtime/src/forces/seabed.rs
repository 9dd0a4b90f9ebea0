//! The seabed as an elastic foundation, Eq. 41: F^S = k_z V^S, upward, with V^S the volume
//! of a rod below the seabed plane.
//!
//! The embedded volume of a tilted rod is ∫ A(δ(s)) ds along its axis, with δ(s) the depth
//! of the lowest fibre below the seabed at axial position s and A(δ) the circular segment
//! of depth δ (the section taken vertical: exact for a level rod, first-order for a tilted
//! one; elements on the seabed lie nearly level). See docs/model-choices.md. A(δ) is
//! [`segment_area`], shared with the model's resting heights.

use crate::geometry::segment_area;

/// Slip speed over which the line's seabed friction builds up, m/s: Coulomb friction
/// regularised as −μ N tanh(v / V_SLIP), so the right-hand side stays smooth.
pub const V_SLIP: f64 = 0.01;

/// Friction along x on an element sliding at `slip` (m/s) with foundation reaction
/// `reaction` (N) and coefficient `mu`, N.
pub fn sliding_friction(mu: f64, reaction: f64, slip: f64) -> f64 {
    -mu * reaction * (slip / V_SLIP).tanh()
}

/// Gauss–Legendre nodes and weights on [−1, 1], 8 points.
const GAUSS_8: [(f64, f64); 8] = [
    (-0.960_289_856_497_536_3, 0.101_228_536_290_376_26),
    (-0.796_666_477_413_626_7, 0.222_381_034_453_374_47),
    (-0.525_532_409_916_329, 0.313_706_645_877_887_3),
    (-0.183_434_642_495_649_8, 0.362_683_783_378_361_96),
    (0.183_434_642_495_649_8, 0.362_683_783_378_361_96),
    (0.525_532_409_916_329, 0.313_706_645_877_887_3),
    (0.796_666_477_413_626_7, 0.222_381_034_453_374_47),
    (0.960_289_856_497_536_3, 0.101_228_536_290_376_26),
];

/// Embedded volume of a rod of radius `r` whose axis runs from height `h_a` to `h_b`
/// above the seabed over a length `len`: (V^S in m³, its centroid's axial position s̄ in m
/// from the `h_a` end). Zero volume when the rod is clear of the seabed.
pub fn embedded_volume(r: f64, len: f64, h_a: f64, h_b: f64) -> (f64, f64) {
    // δ(s) = r − h(s) is linear; integrate over the part where δ > 0.
    let (da, db) = (r - h_a, r - h_b);
    if da <= 0.0 && db <= 0.0 {
        return (0.0, 0.0);
    }
    let (s0, s1) = if da > 0.0 && db > 0.0 {
        (0.0, len)
    } else {
        let s_cross = len * da / (da - db);
        if da > 0.0 {
            (0.0, s_cross)
        } else {
            (s_cross, len)
        }
    };
    let (mid, half) = (0.5 * (s0 + s1), 0.5 * (s1 - s0));
    let (mut v, mut moment) = (0.0, 0.0);
    // One rule for every configuration: switching rules (say, fewer points for a rod
    // embedded along its whole length) would make V^S jump by the rules' difference when an
    // end crosses the seabed plane, a discontinuity of the right-hand side that spoils error
    // control and convergence. The segment A ∝ δ^{3/2} near a crossing is integrated
    // continuously in the state this way.
    for &(x, w) in &GAUSS_8 {
        let s = mid + half * x;
        let a = segment_area(r, da + (db - da) * s / len);
        v += w * half * a;
        moment += w * half * a * s;
    }
    if v > 0.0 {
        (v, moment / v)
    } else {
        (0.0, 0.0)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::f64::consts::PI;

    #[test]
    fn half_buried_level_rod() {
        // Axis on the seabed: half of the cylinder is embedded, centroid at mid-length.
        let (v, s) = embedded_volume(0.05, 2.0, 0.0, 0.0);
        assert!((v - PI * 0.05 * 0.05).abs() < 1e-12);
        assert!((s - 1.0).abs() < 1e-12);
        // Eq. 41 with k_z = 5e6 N/m³: 39.27 kN.
        assert!((5e6 * v - 39_269.908).abs() < 1e-2);
    }

    #[test]
    fn slightly_tilted_embedded_rod_matches_fine_quadrature() {
        // A rod resting on the seabed, 6 mm and 9 mm deep at its ends: the 3-point rule
        // against a 20 000-point midpoint sum.
        let (r, len, ha, hb) = (0.0763, 1.0, 0.0763 - 0.006, 0.0763 - 0.009);
        let (v, s) = embedded_volume(r, len, ha, hb);
        let n = 20_000;
        let (mut vq, mut mq) = (0.0, 0.0);
        for i in 0..n {
            let x = (i as f64 + 0.5) / n as f64 * len;
            let a = segment_area(r, r - (ha + (hb - ha) * x / len));
            vq += a * len / n as f64;
            mq += a * x * len / n as f64;
        }
        assert!((v - vq).abs() < 1e-7 * vq, "{v} vs {vq}"); // 1e-8 measured
        assert!((s - mq / vq).abs() < 1e-6, "{s} vs {}", mq / vq); // 5e-8 m measured
    }

    #[test]
    fn line_friction_opposes_sliding_and_saturates() {
        assert_eq!(sliding_friction(0.5, 1000.0, 0.0), 0.0);
        assert!((sliding_friction(0.5, 1000.0, 1.0) + 500.0).abs() < 1e-9);
        assert!((sliding_friction(0.5, 1000.0, -1.0) - 500.0).abs() < 1e-9);
        assert!(sliding_friction(0.5, 1000.0, 0.001).abs() < 0.11 * 500.0);
    }

    #[test]
    fn tilted_rod_touching_at_one_end() {
        let (v, s) = embedded_volume(0.05, 1.0, 0.04, 0.5);
        assert!(v > 0.0 && s < 0.1, "only the low end is embedded: v = {v}, s̄ = {s}");
        assert_eq!(embedded_volume(0.05, 1.0, 0.06, 0.5), (0.0, 0.0));
    }
}

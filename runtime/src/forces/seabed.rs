//! The seabed as an elastic foundation, Eq. 41: F^S = k_z V^S, upward, with V^S the volume
//! of a rod below the seabed plane.
//!
//! The embedded volume of a tilted rod is ∫ A(δ(s)) ds along its axis, with δ(s) the depth
//! of the lowest fibre below the seabed at axial position s and A(δ) the circular segment
//! of depth δ (the section taken vertical: exact for a level rod, first-order for a tilted
//! one; elements on the seabed lie nearly level). See docs/model-choices.md. A(δ) is
//! [`segment_area`], shared with the model's resting heights.
//!
//! The axis height h = r − δ runs linearly along the rod, so the integral has a closed form
//! ([`embedded_volume`]): with the antiderivatives F(h) of A and G(h) of h·A, V^S = L (F(h_b)
//! − F(h_a)) / (h_b − h_a), two `acos` and two `sqrt` per element. A nearly level rod takes
//! its Taylor series about the mid height instead (the closed form cancels there), and a
//! nearly level rod at the edge of the section the quadrature
//! ([`embedded_volume_by_quadrature`], the literal statement of the integral, 8 `acos` and 8
//! `sqrt`).

use std::f64::consts::PI;

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

/// ∫ A dh: F(h) = r²(h acos(h/r) − √(r² − h²)) + (r² − h²)^{3/2}/3 for |h| < r, 0 above the
/// rod's top (h ≥ r: nothing embedded), π r² h below (h ≤ −r: the whole section), m³/m.
fn area_integral(r: f64, h: f64) -> f64 {
    if h >= r {
        0.0
    } else if h <= -r {
        PI * r * r * h
    } else {
        let w = (r * r - h * h).sqrt();
        r * r * (h * (h / r).acos() - w) + w * w * w / 3.0
    }
}

/// ∫ h A dh: G(h) = acos(h/r)(r²h²/2 − r⁴/8) + π r⁴/16 − h (r² + 2h²) √(r² − h²)/8 for
/// |h| < r, π r⁴/16 above, π r² h²/2 − π r⁴/16 below (continuous), m⁴/m.
fn moment_integral(r: f64, h: f64) -> f64 {
    let r4 = r * r * r * r;
    if h >= r {
        PI * r4 / 16.0
    } else if h <= -r {
        PI * r * r * h * h / 2.0 - PI * r4 / 16.0
    } else {
        let w = (r * r - h * h).sqrt();
        (h / r).acos() * (r * r * h * h / 2.0 - r4 / 8.0) + PI * r4 / 16.0 - h * (r * r + 2.0 * h * h) * w / 8.0
    }
}

/// Below this tilt, |h_b − h_a| relative to the ends' distance from the section's edges
/// (h = ±r), a rod is nearly level: its Taylor series about the mid height is exact to
/// about 1e-12 there, while the closed form loses digits to cancellation.
const NEARLY_LEVEL: f64 = 1e-3;

/// Embedded volume of a rod of radius `r` whose axis runs from height `h_a` to `h_b`
/// above the seabed over a length `len`: (V^S in m³, its centroid's axial position s̄ in m
/// from the `h_a` end). Zero volume when the rod is clear of the seabed. The integral of
/// [`embedded_volume_by_quadrature`] in closed form (see the module documentation).
pub fn embedded_volume(r: f64, len: f64, h_a: f64, h_b: f64) -> (f64, f64) {
    let (lo, hi) = (h_a.min(h_b), h_a.max(h_b));
    if lo >= r {
        return (0.0, 0.0);
    }
    if hi <= -r {
        return (PI * r * r * len, 0.5 * len);
    }
    let dh = h_b - h_a;
    let inside = r - lo.abs().max(hi.abs()); // > 0: both ends cut the section
    if dh.abs() <= NEARLY_LEVEL * inside {
        // A(h_m + tΔ) about the mid height, t in [−½, ½], with A1 = −2√(r² − h²),
        // A2 = 2h/√(r² − h²) and A3 = 2r²/(r² − h²)^{3/2} its derivatives.
        let h = 0.5 * (h_a + h_b);
        let w = (r * r - h * h).sqrt();
        let a = r * r * (h / r).acos() - h * w;
        let (a1, a2, a3) = (-2.0 * w, 2.0 * h / w, 2.0 * r * r / (w * w * w));
        let v = a + a2 * dh * dh / 24.0;
        let m = 0.5 * v + a1 * dh / 12.0 + a3 * dh * dh * dh / 480.0;
        return (len * v, len * m / v);
    }
    if dh.abs() <= NEARLY_LEVEL * r {
        // Nearly level across an edge of the section: the closed form would cancel.
        return embedded_volume_by_quadrature(r, len, h_a, h_b);
    }
    let df = area_integral(r, h_b) - area_integral(r, h_a);
    let v = len * df / dh;
    if v <= 0.0 {
        return (0.0, 0.0);
    }
    // ∫ A s ds with s = L (h − h_a)/Δ.
    let dg = moment_integral(r, h_b) - moment_integral(r, h_a) - h_a * df;
    (v, len * len * dg / (dh * dh) / v)
}

/// The embedded volume and its centroid as in [`embedded_volume`], by 8-point Gauss–Legendre
/// quadrature of ∫ A(δ(s)) ds over the embedded part: the literal statement of the integral.
pub fn embedded_volume_by_quadrature(r: f64, len: f64, h_a: f64, h_b: f64) -> (f64, f64) {
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

    /// ∫ A(δ(s)) ds and its centroid by a fine midpoint sum: the oracle.
    fn midpoint(r: f64, len: f64, ha: f64, hb: f64, n: usize) -> (f64, f64) {
        let (mut v, mut m) = (0.0, 0.0);
        for i in 0..n {
            let x = (i as f64 + 0.5) / n as f64 * len;
            let a = segment_area(r, r - (ha + (hb - ha) * x / len));
            v += a * len / n as f64;
            m += a * x * len / n as f64;
        }
        (v, if v > 0.0 { m / v } else { 0.0 })
    }

    #[test]
    fn antiderivatives_differentiate_to_the_integrands() {
        let r = 0.0763;
        for i in 0..41 {
            let h = -1.2 * r + 2.4 * r * i as f64 / 40.0;
            let e = 1e-7 * r;
            let fd = (area_integral(r, h + e) - area_integral(r, h - e)) / (2.0 * e);
            let gd = (moment_integral(r, h + e) - moment_integral(r, h - e)) / (2.0 * e);
            let a = segment_area(r, r - h);
            assert!((fd - a).abs() < 1e-8 * r * r, "F'({h}) = {fd} against A = {a}");
            assert!((gd - h * a).abs() < 1e-8 * r * r * r, "G'({h}) = {gd} against h A = {}", h * a);
        }
    }

    #[test]
    fn closed_form_matches_the_integral_in_every_configuration() {
        // Level, nearly level, tilted, crossing the seabed plane at either end, fully buried,
        // clear: against a 200 000-point midpoint sum.
        let (r, len) = (0.0763, 1.0);
        let mut cases = vec![(0.0, 0.0), (0.07, 0.07), (-0.09, -0.09), (0.2, 0.3), (-0.2, -0.1)];
        for &(h, dh) in &[(0.07, 1e-6), (0.07, 1e-4), (0.0, 3e-3), (0.05, 0.04), (0.07, 0.02), (-0.07, -0.02)] {
            cases.extend([(h - dh / 2.0, h + dh / 2.0), (h + dh / 2.0, h - dh / 2.0)]);
        }
        cases.extend([(r - 1e-9, r + 1e-9), (-r - 1e-5, -r + 1e-5), (0.04, 0.5), (-0.5, 0.01)]);
        for (ha, hb) in cases {
            let (v, s) = embedded_volume(r, len, ha, hb);
            let (vq, sq) = midpoint(r, len, ha, hb, 200_000);
            let scale = PI * r * r * len;
            assert!((v - vq).abs() < 1e-9 * scale, "h = ({ha}, {hb}): V {v} against {vq}");
            if vq > 1e-6 * scale {
                assert!((s - sq).abs() < 1e-6 * len, "h = ({ha}, {hb}): s̄ {s} against {sq}");
            }
        }
    }

    #[test]
    fn closed_form_is_continuous_where_its_branches_meet() {
        // Across the nearly-level threshold and across an end crossing the top of the section.
        let (r, len) = (0.0763, 1.0);
        let h: f64 = 0.03;
        // The tilt Δ where |Δ| = NEARLY_LEVEL (r − |h| − |Δ|/2): Taylor series below, closed form above.
        let edge = NEARLY_LEVEL * (r - h.abs()) / (1.0 + NEARLY_LEVEL / 2.0);
        let below = embedded_volume(r, len, h - edge * (0.5 - 1e-12), h + edge * (0.5 - 1e-12));
        let above = embedded_volume(r, len, h - edge * (0.5 + 1e-12), h + edge * (0.5 + 1e-12));
        assert!(
            (below.0 - above.0).abs() < 1e-12 * below.0 && (below.1 - above.1).abs() < 1e-10,
            "{below:?} {above:?}"
        );
        let (b, a) = (embedded_volume(r, len, 0.0, r - 1e-12), embedded_volume(r, len, 0.0, r + 1e-12));
        // (Moving an end by 2e-12 m changes V by about 3e-11 of itself.)
        assert!((b.0 - a.0).abs() < 1e-10 * b.0 && (b.1 - a.1).abs() < 1e-10, "{b:?} {a:?}");
    }

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

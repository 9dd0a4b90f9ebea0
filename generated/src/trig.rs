//! The sine and cosine of the bodies' rotations θ_k (Eq. 9), computed together: the kernels
//! need both of every angle, and the standard library's `sin` and `cos` (the C library's,
//! two calls, accurate at any argument) spend about a hundred instructions an angle. Here
//! the angle is reduced to r in [−π/4, π/4] around the nearest multiple k π/2 of π/2
//! (Cody and Waite's reduction, π/2 held in three parts so that k·π/2 is exact to far below
//! a rounding of r) and sin r, cos r are their Taylor polynomials to r¹⁷ and r¹⁶, whose
//! remainders (8e-20 and 2e-18 at π/4) are below a rounding. The tests measure the results
//! against the standard library's: within one unit in the last place for |θ| ≤ 100 rad and
//! two beyond.
//!
//! Beyond |θ| = 1e5 rad (a blown-up state) and for a non-finite angle the standard
//! library's functions are used. The generator's own numeric evaluation of its expression
//! graph (constant folding, its tests) keeps the standard library's. This file is written
//! by hand.

use crate::lanes::F2;

/// π/2 in three parts: the first two of 33 significant bits, so that k·`PIO2_HI` and
/// k·`PIO2_MID` are exact for |k| < 2²⁰; the three sum to π/2 within 1.01e-37.
const PIO2_HI: f64 = 1.5707963267341256;
const PIO2_MID: f64 = 6.077100506303966e-11;
const PIO2_LO: f64 = 2.0222662487959506e-21;

/// The largest |θ| reduced here (|k| ≤ 6.4e4 < 2²⁰).
const REDUCED_UP_TO: f64 = 1e5;

/// 1.5 · 2⁵²: adding and subtracting it rounds a number below 2⁵¹ to the nearest integer.
const ROUND: f64 = 6_755_399_441_055_744.0;

/// sin r = r + r·z·Σ S_i zⁱ, z = r², the Taylor coefficients (−1)^(i+1)/(2i + 3)!.
const S: [f64; 8] = [
    -1.0 / 6.0,
    1.0 / 120.0,
    -1.0 / 5040.0,
    1.0 / 362_880.0,
    -1.0 / 39_916_800.0,
    1.0 / 6_227_020_800.0,
    -1.0 / 1_307_674_368_000.0,
    1.0 / 355_687_428_096_000.0,
];

/// cos r = 1 − z/2 + z²·Σ C_i zⁱ, the Taylor coefficients (−1)^i/(2i + 4)!.
const C: [f64; 7] = [
    1.0 / 24.0,
    -1.0 / 720.0,
    1.0 / 40_320.0,
    -1.0 / 3_628_800.0,
    1.0 / 479_001_600.0,
    -1.0 / 87_178_291_200.0,
    1.0 / 20_922_789_888_000.0,
];

/// (sin θ, cos θ), θ in rad.
#[inline(always)]
pub fn sin_cos(theta: f64) -> (f64, f64) {
    if theta.abs() > REDUCED_UP_TO || theta.is_nan() {
        return theta.sin_cos();
    }
    // k + 1.5·2⁵² holds k in its mantissa's low bits (one unit in its last place is 1, and
    // 2⁵¹ ≡ 0 mod 4): its last two bits are k mod 4, the quadrant, with no conversion.
    let shifted = theta * core::f64::consts::FRAC_2_PI + ROUND;
    let k = shifted - ROUND;
    let r = ((theta - k * PIO2_HI) - k * PIO2_MID) - k * PIO2_LO;
    // The polynomials in z by Estrin's scheme (pairs, then pairs of pairs in z², z⁴): a
    // chain of four dependent operations instead of Horner's seven multiply-adds, and the
    // kernels evaluate many angles at once.
    let (z, z2) = (r * r, r * r * (r * r));
    let z4 = z2 * z2;
    let ps = ((S[0] + S[1] * z) + z2 * (S[2] + S[3] * z)) + z4 * ((S[4] + S[5] * z) + z2 * (S[6] + S[7] * z));
    // The sign of r kept for r = −0 (|z·ps| < 0.1, so the sum has r's sign anyway).
    let sin = (r + r * z * ps).copysign(r);
    let pc = ((C[0] + C[1] * z) + z2 * (C[2] + C[3] * z)) + z4 * ((C[4] + C[5] * z) + z2 * C[6]);
    // 1 − z/2 with its rounding error carried into the small terms.
    let half = 0.5 * z;
    let w = 1.0 - half;
    let cos = w + (((1.0 - w) - half) + z * z * pc);
    match shifted.to_bits() & 3 {
        0 => (sin, cos),
        1 => (cos, -sin),
        2 => (-sin, -cos),
        _ => (-cos, sin),
    }
}

/// The rotation table of a chain (Eqs. 1, 4): `trig[j] = [cos θ_j, sin θ_j]` for θ_0 = β_0,
/// θ_j = θ_{j−1} + β_j, the angles summed in the kinematics' order (so equal to theirs bit
/// for bit), their sines and cosines two at a time ([`sin_cos_pair`]). `trig` holds at least
/// `beta.len()` rows.
#[inline(always)]
pub fn rotations(beta: &[f64], trig: &mut [[f64; 2]]) {
    let m = beta.len();
    let trig = &mut trig[..m];
    let mut theta = 0.0;
    let mut j = 0;
    while j + 1 < m {
        // θ_0 = β_0 itself, as the first link's step takes it (0 + β_0 would turn −0 into +0).
        let a = if j == 0 { beta[0] } else { theta + beta[j] };
        theta = a + beta[j + 1];
        [trig[j], trig[j + 1]] = sin_cos_pair(a, theta);
        j += 2;
    }
    if j < m {
        let a = if j == 0 { beta[0] } else { theta + beta[j] };
        let (sin, cos) = sin_cos(a);
        trig[j] = [cos, sin];
    }
}

/// `[[cos a, sin a], [cos b, sin b]]`, equal bit for bit to two calls of [`sin_cos`]: the same
/// operations on two lanes ([`F2`]: on x86-64, in about half the instructions). For an angle
/// [`sin_cos`] hands to the standard library, two calls.
#[inline(always)]
pub fn sin_cos_pair(a: f64, b: f64) -> [[f64; 2]; 2] {
    if a.abs() <= REDUCED_UP_TO && b.abs() <= REDUCED_UP_TO {
        return sin_cos_lanes(a, b);
    }
    let ((sa, ca), (sb, cb)) = (sin_cos(a), sin_cos(b));
    [[ca, sa], [cb, sb]]
}

/// `[[cos a, sin a], [cos b, sin b]]` for |a|, |b| ≤ [`REDUCED_UP_TO`]: [`sin_cos`]'s steps
/// on two lanes ([`F2`]; its `copysign` a bit select, its quadrant's swap a select and its
/// negations sign flips, by the low bits of `shifted`).
#[inline(always)]
fn sin_cos_lanes(a: f64, b: f64) -> [[f64; 2]; 2] {
    let theta = F2::new(a, b);
    let splat = F2::splat;
    let shifted = theta * splat(core::f64::consts::FRAC_2_PI) + splat(ROUND);
    let k = shifted - splat(ROUND);
    let r = ((theta - k * splat(PIO2_HI)) - k * splat(PIO2_MID)) - k * splat(PIO2_LO);
    let (z, z2) = (r * r, r * r * (r * r));
    let z4 = z2 * z2;
    let (s, c) = (|i: usize| splat(S[i]), |i: usize| splat(C[i]));
    let ps = ((s(0) + s(1) * z) + z2 * (s(2) + s(3) * z)) + z4 * ((s(4) + s(5) * z) + z2 * (s(6) + s(7) * z));
    let sin = (r + r * z * ps).copysign(r);
    let pc = ((c(0) + c(1) * z) + z2 * (c(2) + c(3) * z)) + z4 * ((c(4) + c(5) * z) + z2 * c(6));
    let half = splat(0.5) * z;
    let w = splat(1.0) - half;
    let cos = w + (((splat(1.0) - w) - half) + z * z * pc);
    // Quadrant q (the low bits of `shifted`): odd q swaps the two; bit 1 of q negates the
    // sine, bit 1 of q + 1 the cosine.
    let (sin_q, cos_q) = (sin.select_odd(shifted, cos), cos.select_odd(shifted, sin));
    F2::zip(cos_q.negate_if(shifted, 1, 1), sin_q.negate_if(shifted, 0, 1))
}

/// sin θ, θ in rad: [`sin_cos`]'s first (a kernel asking for both gets one reduction).
#[inline(always)]
pub fn sin(theta: f64) -> f64 {
    sin_cos(theta).0
}

/// cos θ, θ in rad: [`sin_cos`]'s second.
#[inline(always)]
pub fn cos(theta: f64) -> f64 {
    sin_cos(theta).1
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Distance in units of the last place between `a` and the correctly rounded `b`.
    fn ulps(a: f64, b: f64) -> f64 {
        if a == b {
            return 0.0;
        }
        let unit = f64::from_bits(b.abs().to_bits() + 1) - b.abs();
        ((a - b) / unit).abs()
    }

    #[test]
    fn agrees_with_the_standard_library_to_a_unit_in_the_last_place() {
        // Dense over the rotations a chain takes, sparse out to the reduction's limit, and
        // the quadrant boundaries, where r is largest.
        let mut angles: Vec<f64> = (0..400_001).map(|i| -20.0 + 40.0 * i as f64 / 400_000.0).collect();
        angles.extend((0..20_001).map(|i| -1e5 + 1e5 * i as f64 / 10_000.0));
        for k in -64..=64 {
            let b = k as f64 * std::f64::consts::FRAC_PI_4;
            angles.extend([b, b + 1e-9, b - 1e-9]);
            if b != 0.0 {
                // Its neighbouring doubles.
                angles.extend([f64::from_bits(b.to_bits() + 1), f64::from_bits(b.to_bits() - 1)]);
            }
        }
        angles.extend([0.0, -0.0, 1e-300, -1e-300, 1e-8, 3e-4]);
        for &t in &angles {
            let (s, c) = sin_cos(t);
            let (s_std, c_std) = t.sin_cos();
            let (es, ec) = (ulps(s, s_std), ulps(c, c_std));
            // One unit over any rotation a chain takes; two far out (1e4 rad and beyond).
            let bound = if t.abs() <= 100.0 { 1.0 } else { 2.0 };
            assert!(es <= bound && ec <= bound, "θ = {t:e}: sin {s:e} ({es} ulp), cos {c:e} ({ec} ulp)");
        }
    }

    #[test]
    fn pairs_and_the_rotation_table_equal_the_single_angle_bit_for_bit() {
        let bits = |row: [f64; 2]| row.map(f64::to_bits);
        let one = |t: f64| {
            let (s, c) = sin_cos(t);
            [c, s]
        };
        // Every quadrant, signed zeros, the library's angles beyond the reduction and
        // non-finite ones, in either lane.
        let mut angles: Vec<f64> = (0..20_001).map(|i| -40.0 + 80.0 * i as f64 / 20_000.0).collect();
        angles.extend([0.0, -0.0, 1e-300, -1e-300, 1e5, -1e5, 1e5 + 1.0, -3e7, f64::NAN, f64::INFINITY]);
        for (i, &a) in angles.iter().enumerate() {
            let b = angles[(i * 7919 + 13) % angles.len()];
            let [ra, rb] = sin_cos_pair(a, b);
            assert_eq!((bits(ra), bits(rb)), (bits(one(a)), bits(one(b))), "θ = ({a:e}, {b:e})");
        }
        // The table's angles are the running sums, formed as the kinematics form them.
        for m in [0, 1, 2, 3, 8, 45] {
            let beta: Vec<f64> = (0..m).map(|j| 0.37 * (j as f64 * 1.3).sin() - 0.05).collect();
            let mut trig = vec![[0.0; 2]; m + 1];
            rotations(&beta, &mut trig);
            let mut theta = 0.0;
            for j in 0..m {
                theta = if j == 0 { beta[0] } else { theta + beta[j] };
                assert_eq!(bits(trig[j]), bits(one(theta)), "m = {m}, j = {j}");
            }
            assert_eq!(trig[m], [0.0; 2], "a row beyond β is left alone");
        }
    }

    #[test]
    fn the_reduction_is_exact_at_multiples_of_a_half_pi_and_beyond_it_the_library_serves() {
        assert_eq!(sin_cos(0.0), (0.0, 1.0));
        assert!(sin_cos(-0.0).0.is_sign_negative() && sin_cos(-0.0).1 == 1.0);
        let (s, c) = sin_cos(std::f64::consts::FRAC_PI_2);
        assert_eq!(s, 1.0);
        assert!(c.abs() < 1e-16);
        for t in [1e5 + 1.0, -3e7, 1e300] {
            assert_eq!(sin_cos(t), t.sin_cos());
        }
        for t in [f64::NAN, f64::INFINITY, f64::NEG_INFINITY] {
            let (s, c) = sin_cos(t);
            assert!(s.is_nan() && c.is_nan());
        }
    }
}

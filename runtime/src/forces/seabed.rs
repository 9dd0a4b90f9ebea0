//! The seabed as an elastic foundation, Eq. 41: F^S = k_z V^S, upward, with V^S the volume
//! of a rod below the seabed plane.
//!
//! The embedded volume of a tilted rod is ∫ A(δ(s)) ds along its axis, with δ(s) the depth
//! of the lowest fibre below the seabed at axial position s and A(δ) the circular segment
//! of depth δ (the section taken vertical: exact for a level rod, first-order for a tilted
//! one; elements on the seabed lie nearly level). See docs/model-choices.md. A(δ) is
//! [`segment_area`], shared with the model's resting heights.
//!
//! The axis height h = r − δ runs linearly along the rod, so the integral has closed forms
//! ([`embedded_volume`]), chosen so that they join smoothly (a jump between two formulas,
//! even of 1e-6 of V, spoils the finite-difference Jacobian of the implicit method: see
//! docs/integrators.md, "The stiff scene"):
//!
//! - near an edge of the section (the deeper end at most r/4 below the seabed, as every
//!   element resting on it; or nearly buried), a series in the depth whose terms are
//!   divided differences of powers of δ, formed without cancellation at any tilt
//!   (`near_edge`): one `sqrt` per end and a few terms;
//! - between the edges, with the antiderivatives F(h) of A and G(h) of h·A, V^S = L (F(h_b)
//!   − F(h_a)) / (h_b − h_a), one `acos` and one `sqrt` per end; it cancels as the rod levels
//!   out, so a nearly level rod takes its Taylor series about the mid height (one `acos`).
//!
//! The branches agree to about 1e-13 of V and 2e-11 of the length in the centroid where
//! they meet (asserted by the tests below: 2e-13 and 5e-11). The 8-point quadrature
//! ([`embedded_volume_by_quadrature`]) is the literal statement of the integral, kept as a
//! check.

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

/// The antiderivatives at axis height h: (F, G) with F(h) = ∫ A dh = r²(h acos(h/r) −
/// √(r² − h²)) + (r² − h²)^{3/2}/3 and G(h) = ∫ h A dh = acos(h/r)(r²h²/2 − r⁴/8) + π r⁴/16 −
/// h (r² + 2h²) √(r² − h²)/8 for |h| < r; above the rod's top (h ≥ r, nothing embedded) F = 0
/// and G = π r⁴/16; below (h ≤ −r, the whole section) F = π r² h and G = π r² h²/2 − π r⁴/16
/// (both continuous). One `acos` and one `sqrt`. Units m³/m and m⁴/m.
fn antiderivatives(r: f64, h: f64) -> (f64, f64) {
    let r4 = r * r * r * r;
    if h >= r {
        (0.0, PI * r4 / 16.0)
    } else if h <= -r {
        (PI * r * r * h, PI * r * r * h * h / 2.0 - PI * r4 / 16.0)
    } else {
        let (w, acos) = ((r * r - h * h).sqrt(), (h / r).acos());
        let f = r * r * (h * acos - w) + w * w * w / 3.0;
        let g = acos * (r * r * h * h / 2.0 - r4 / 8.0) + PI * r4 / 16.0 - h * (r * r + 2.0 * h * h) * w / 8.0;
        (f, g)
    }
}

/// A rod lies near the top of its section (barely touching) when its deeper end is at most
/// `NEAR_EDGE` × r below the seabed plane, and near the bottom (nearly buried) when its
/// shallower end is at least (2 − `NEAR_EDGE`) r deep: there the volume and centroid are
/// sums of the depth series of `near_edge` (terms shrinking by δ/2r ≤ 1/8), exact to about
/// 1e-15 for any tilt. Elements resting on the seabed lie here (the paper's chain about
/// 0.08 r deep, at k_z × 1e4 about 2e-4 r).
pub(crate) const NEAR_EDGE: f64 = 0.25;

/// Between the edges a rod is nearly level when |h_b − h_a| ≤ `TAYLOR` × the ends' distance
/// from the section's edges (h = ±r, at least 0.22 r there): its Taylor series about the
/// mid height (to Δ⁴ in V, Δ⁵ in the moment) is then exact to about 1e-14; beyond it
/// (|Δ| ≥ 0.0066 r) the closed form's rounding is about 1e-13 of V and 2e-11 of the length
/// in s̄ (what the two differ by where they meet, measured by the tests below).
const TAYLOR: f64 = 3e-2;

/// Embedded volume of a rod of radius `r` whose axis runs from height `h_a` to `h_b`
/// above the seabed over a length `len`: (V^S in m³, its centroid's axial position s̄ in m
/// from the `h_a` end). Zero volume when the rod is clear of the seabed; NaN for a NaN height.
/// The integral of [`embedded_volume_by_quadrature`]: near an edge of the section by the
/// depth series of `near_edge`, between the edges in closed form or, nearly level, by its
/// Taylor series (see the module documentation). The branches meet to about 1e-13 of V and
/// 2e-11 of the length in s̄, so the right-hand side is smooth to that level where they join.
pub fn embedded_volume(r: f64, len: f64, h_a: f64, h_b: f64) -> (f64, f64) {
    if h_a.is_nan() || h_b.is_nan() {
        return (f64::NAN, f64::NAN);
    }
    let (lo, hi) = if h_a <= h_b { (h_a, h_b) } else { (h_b, h_a) };
    if lo >= r {
        return (0.0, 0.0);
    }
    if hi <= -r {
        return (PI * r * r * len, 0.5 * len);
    }
    // Depths of the lowest fibre below the seabed plane at the two ends.
    let (da, db) = (r - h_a, r - h_b);
    if da.max(db) <= NEAR_EDGE * r {
        return near_edge(r, len, da, db);
    }
    if da.min(db) >= (2.0 - NEAR_EDGE) * r {
        // Nearly buried: the whole section less the segment left above the seabed plane,
        // of depth 2r − δ from the top fibre (A(δ) = π r² − A(2r − δ)).
        let (vc, sc) = near_edge(r, len, 2.0 * r - da, 2.0 * r - db);
        let full = PI * r * r * len;
        let v = full - vc;
        return (v, (0.5 * full * len - vc * sc) / v);
    }
    let dh = h_b - h_a;
    let inside = r - lo.abs().max(hi.abs()); // > 0: both ends cut the section
    if dh.abs() <= TAYLOR * inside {
        return nearly_level(r, len, 0.5 * (h_a + h_b), dh);
    }
    let ((fa, ga), (fb, gb)) = (antiderivatives(r, h_a), antiderivatives(r, h_b));
    let df = fb - fa;
    let v = len * df / dh;
    if v <= 0.0 {
        return (0.0, 0.0);
    }
    // ∫ A s ds with s = L (h − h_a)/Δ, kept inside the embedded part of the axis (a
    // safeguard: the rods for which G's terms would cancel lie near the edge, above).
    let s_bar = len * len * (gb - ga - h_a * df) / (dh * dh) / v;
    let s_edge = (len * (r - h_a) / dh).clamp(0.0, len); // where the axis leaves the section's top
    let (s0, s1) = if h_a < h_b { (0.0, s_edge) } else { (s_edge, len) };
    (v, s_bar.clamp(s0, s1))
}

/// A nearly level rod between the section's edges: A(h_m + tΔ) about the mid height h_m,
/// t in [−½, ½], integrated term by term (V/L = Σ A⁽ⁿ⁾ Δⁿ ∫tⁿ/n!, even n; the moment about the
/// mid-length Σ A⁽ⁿ⁾ Δⁿ ∫tⁿ⁺¹/n!, odd n), with w = √(r² − h²) and the derivatives
/// A′ = −2w, A″ = 2h/w, A‴ = 2r²/w³, A⁗ = 6r²h/w⁵, A⁽⁵⁾ = 6r²(w² + 5h²)/w⁷.
fn nearly_level(r: f64, len: f64, h: f64, dh: f64) -> (f64, f64) {
    let w = (r * r - h * h).sqrt();
    let (w2, w3) = (w * w, w * w * w);
    let a = r * r * (h / r).acos() - h * w;
    let (a1, a2, a3) = (-2.0 * w, 2.0 * h / w, 2.0 * r * r / w3);
    let (a4, a5) = (6.0 * r * r * h / (w3 * w2), 6.0 * r * r * (w2 + 5.0 * h * h) / (w3 * w2 * w2));
    let d2 = dh * dh;
    let v = a + d2 * (a2 / 24.0 + d2 * a4 / 1920.0);
    let m = 0.5 * v + dh * (a1 / 12.0 + d2 * (a3 / 480.0 + d2 * a5 / 53_760.0));
    (len * v, len * m / v)
}

/// Terms of the depth series of `near_edge` at most (they shrink by δ/2r ≤ 1/8 there, where
/// 17 reach 1e-17 of the sums; [`SERIES_REACH`] says how many a depth needs).
const SERIES_TERMS: usize = 20;

/// The depth series' coefficients and how far a number of terms reaches, built at compile
/// time (see [`SERIES`] and [`SERIES_REACH`]; a constant's initialiser, where floating-point
/// arithmetic has long been allowed, not a `const fn`).
const DEPTH_SERIES: ([[f64; 2]; SERIES_TERMS], [f64; SERIES_TERMS]) = {
    // C(½, k) by C(½, k + 1) = C(½, k)(½ − k)/(k + 1), for k = 0 … SERIES_TERMS, and the
    // coefficients C(½, k)/(p(p + 1)), C(½, k)/(p(p + 1)(p + 2)), p = k + 3/2.
    let mut binomial = [0.0; SERIES_TERMS + 1];
    let mut coefficient = [[0.0; 2]; SERIES_TERMS + 1];
    binomial[0] = 1.0;
    let mut k = 0;
    while k <= SERIES_TERMS {
        if k < SERIES_TERMS {
            binomial[k + 1] = binomial[k] * (0.5 - k as f64) / (k as f64 + 1.0);
        }
        let p = k as f64 + 1.5;
        coefficient[k] = [binomial[k] / (p * (p + 1.0)), binomial[k] / (p * (p + 1.0) * (p + 2.0))];
        k += 1;
    }
    let mut series = [[0.0; 2]; SERIES_TERMS];
    let mut reach = [0.0; SERIES_TERMS];
    let lead = coefficient[0][0];
    let mut n = 0;
    while n < SERIES_TERMS {
        series[n] = coefficient[n];
        // n terms leave out the term of degree n, |c_n| y^n (the rest of the tail adds less
        // than half of it, y ≤ 1/8), and its first and second divided differences carry up
        // to n and n² times that: reach[n] is the y with |c_n| y^n (n + 1)² = 1e-17 |c_0|, by
        // bisection.
        let omitted = coefficient[n][0];
        let omitted = if omitted < 0.0 { -omitted } else { omitted };
        let target = 1e-17 * lead / (omitted * ((n + 1) * (n + 1)) as f64);
        let (mut lo, mut hi) = (0.0, 1.0);
        let mut step = 0;
        while n > 0 && step < 64 {
            let mid = 0.5 * (lo + hi);
            let mut power = 1.0;
            let mut i = 0;
            while i < n {
                power *= mid;
                i += 1;
            }
            if power <= target {
                lo = mid;
            } else {
                hi = mid;
            }
            step += 1;
        }
        reach[n] = lo;
        n += 1;
    }
    (series, reach)
};

/// Per term k of the depth series, p = k + 3/2: the coefficients of x^k (x = −δ/2r) in
/// F₁(δ)/(c₀ δ^(5/2)) and F₂(δ)/(c₀ δ^(7/2)), C(½, k)/(p(p + 1)) and C(½, k)/(p(p + 1)(p + 2)),
/// with F₁ = ∫A dδ, F₂ = ∫F₁ dδ (both 0 at δ = 0) and c₀ = 2√(2r).
pub(crate) static SERIES: [[f64; 2]; SERIES_TERMS] = DEPTH_SERIES.0;

/// `SERIES_REACH[n]`: the largest δ/2r at which the first n terms leave out less than 1e-17
/// of the leading one, in the sums and in their first and second divided differences
/// (increasing in n; `SERIES_REACH[0]` = 0).
const SERIES_REACH: [f64; SERIES_TERMS] = DEPTH_SERIES.1;

/// The terms `near_edge` takes at y = δ/2r, by the 12 bits of |y| below its sign (exponent
/// and the mantissa's first bit: y's half of a binade, [`terms_for`]): the count
/// [`SERIES_REACH`] gives at the top of that half, so never fewer than y needs and about half
/// a term more (one table load in place of a comparison per term). At least one; NaN and ∞
/// take them all.
static TERMS_BY_HALF_BINADE: [u8; 4096] = {
    let mut table = [SERIES_TERMS as u8; 4096];
    // The top of half-binade i of positive numbers, from the subnormals' up.
    let mut binade = f64::MIN_POSITIVE / 2.0; // 2^(e − 1023) for e = 0, as if normal
    let mut i = 0;
    while i < 2046 * 2 {
        let top = if i % 2 == 0 { binade * 1.5 } else { binade * 2.0 };
        let mut count = 0;
        let mut n = 0;
        while n < SERIES_TERMS {
            if SERIES_REACH[n] < top {
                count += 1;
            }
            n += 1;
        }
        table[i] = if count < 1 { 1 } else { count as u8 };
        if i % 2 == 1 {
            binade *= 2.0;
        }
        i += 1;
    }
    table
};

/// The number of terms of the depth series at y = δ/2r ([`TERMS_BY_HALF_BINADE`]; the sign
/// is ignored).
pub(crate) fn terms_for(y: f64) -> usize {
    usize::from(TERMS_BY_HALF_BINADE[((y.to_bits() >> 51) & 0xfff) as usize])
}

/// A rod near the top of its section, its ends `da` and `db` deep (either may be ≤ 0: that
/// end is clear of the seabed; the deeper one is > 0). With dA/dδ = 2√(2rδ − δ²) and the
/// binomial series of √(1 − δ/2r),
///
/// A(δ) = Σ_k a_k δ^(k + 3/2), a_k = c₀ C(½, k) (−1/2r)^k / (k + 3/2), c₀ = 2√(2r),
///
/// and δ linear along the axis (a, b the ends' depths, the deeper one b), V^S/L is the mean
/// of A over [a, b], the first divided difference F₁[a, b], and the moment about the `a` end
/// M/L² = ∫ A(δ)(δ − a) dδ / (b − a)² the second, F₂[a, b, b]. With F₁ = c₀ δ^(5/2) P₁(x),
/// F₂ = c₀ δ^(7/2) P₂(x), x = −δ/2r and P₁, P₂ polynomials ([`SERIES`]), Leibniz's rule
/// splits them: F₁[a, b] = c₀ (a^(5/2) P₁[a, b] + δ^(5/2)[a, b] P₁(b)), F₂[a, b, b] =
/// c₀ (a^(7/2) P₂[a, b, b] + δ^(7/2)[a, b] P₂′(b) + δ^(7/2)[a, b, b] P₂(b)). The powers'
/// divided differences are sums of positive terms, from δ^(1/2)[a, b] = 1/(√a + √b) and
/// δ^(3/2)[a, b, b] = (2√a + √b)/(2(√a + √b)²) by (δu)[a, b] = a^q + b u[a, b] and (δu)[a, b, b]
/// = u[a, b] + b u[a, b, b]; the polynomials' by Horner's scheme, which carries the divided
/// differences along (p = c + x q: p[a, b] = q(b) + a q[a, b], p′(b) = q(b) + b q′(b),
/// p[a, b, b] = q′(b) + a q[a, b, b]). No cancellation as b − a → 0, no branch on the tilt,
/// and as many terms as the depth needs ([`SERIES_REACH`]): about 12 for a chain resting on
/// the seabed, five multiply–adds each. With the shallow end clear (a ≤ 0) the integrals run
/// over [0, b]: V/L = F₁(b)/(b − a), M/L² = V/L − F₂(b)/(b − a)².
///
/// The `a > 0` branch is written again on two lanes in `crate::contact` (`resting_pair`, the
/// fused load path), operation for operation: a change here is a change there, and that
/// module's tests compare the two bit for bit.
fn near_edge(r: f64, len: f64, da: f64, db: f64) -> (f64, f64) {
    let (a, b) = (da.min(db), da.max(db));
    let x = -0.5 / r; // dx/dδ

    // Looked up without a branch (a search's branches would mispredict from element to element).
    let y = -x * b;
    let terms = terms_for(y);
    let (xa, xb) = (x * a, x * b);
    // Horner from the highest term: P₁(x_b), P₁[x_a, x_b]; P₂(x_b), P₂′(x_b), P₂[x_a, x_b, x_b].
    let [c1, c2] = SERIES[terms - 1];
    let (mut p1, mut p1_ab) = (c1, 0.0);
    let (mut p2, mut p2_bb, mut p2_abb) = (c2, 0.0, 0.0);
    for &[c1, c2] in SERIES[..terms - 1].iter().rev() {
        p1_ab = p1 + xa * p1_ab;
        p1 = c1 + xb * p1;
        p2_abb = p2_bb + xa * p2_abb;
        p2_bb = p2 + xb * p2_bb;
        p2 = c2 + xb * p2;
    }
    let sb = b.sqrt();
    let (v, m) = if a > 0.0 {
        let sa = a.sqrt();
        let s = sa + sb;
        let p32 = sa + b / s; // δ^(3/2)[a, b]
        let p52 = a * sa + b * p32;
        let p72 = a * a * sa + b * p52;
        let r32 = (2.0 * sa + sb) / (2.0 * s * s); // δ^(3/2)[a, b, b]
        let r72 = p52 + b * (p32 + b * r32);
        // The polynomials' divided differences in δ: one factor dx/dδ per order.
        let v = a * a * sa * (x * p1_ab) + p52 * p1;
        let m = a * a * a * sa * (x * x * p2_abb) + p72 * (x * p2_bb) + r72 * p2;
        (v, m)
    } else {
        let dd = b - a;
        let (f1, f2) = (b * b * sb * p1, b * b * b * sb * p2);
        (f1 / dd, f1 / dd - f2 / (dd * dd))
    };
    let c0 = 2.0 * (2.0 * r).sqrt();
    let (v, m) = (c0 * v, c0 * m);
    let s_bar = len * m / v; // from the `a` end
    (len * v, if da <= db { s_bar } else { len - s_bar })
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

    /// The depth series of `near_edge` summed term by term in increasing powers until the
    /// terms fall below 1e-17 of the sums (the form before Horner's scheme): the powers'
    /// divided differences P_q = δ^q[a, b], R_q = δ^q[a, b, b] formed by their recurrences.
    fn near_edge_by_terms(r: f64, len: f64, da: f64, db: f64) -> (f64, f64) {
        if da > db {
            // The series below wants the deeper end second; the centroid is then from the other end.
            let (v, s) = near_edge_by_terms(r, len, db, da);
            return (v, len - s);
        }
        let b = db;
        // [C(½, k)/p, 1/(p + 1), 1/(p + 2), 1/((p + 1)(p + 2))], p = k + 3/2, k < 64.
        let mut terms = [[0.0; 4]; 64];
        let mut binomial = 1.0;
        for (k, t) in terms.iter_mut().enumerate() {
            let p = k as f64 + 1.5;
            *t = [binomial / p, 1.0 / (p + 1.0), 1.0 / (p + 2.0), 1.0 / ((p + 1.0) * (p + 2.0))];
            binomial *= (0.5 - k as f64) / (k as f64 + 1.0);
        }
        let sb = b.sqrt();
        let c0 = 2.0 * (2.0 * r).sqrt();
        // g = (−1/2r)^k; the k-th term's coefficient is a_k = c0 g C(½, k) / p ([`SERIES`]).
        let x = -0.5 / r;
        let mut g = 1.0;
        let (mut v, mut m) = (0.0, 0.0);
        let small = |t: f64, sum: f64| t.abs() <= 1e-17 * sum.abs();
        if da > 0.0 {
            // Both ends embedded: P_q and R_q for q = p + 1 and p + 2, and δ_a^(p+1).
            let (a, sa) = (da, da.sqrt());
            let s = sa + sb;
            let p32 = sa + b / s;
            let mut pq = a * sa + b * p32; // P_(5/2)
            let mut rq = pq + b * (p32 + b * (2.0 * sa + sb) / (2.0 * s * s)); // R_(7/2)
            let mut apow = a * a * sa; // δ_a^(5/2)
            for &[cp, i1, _, i12] in &terms {
                let c = c0 * g * cp;
                let (tv, tm) = (c * pq * i1, c * rq * i12);
                v += tv;
                m += tm;
                if small(tv, v) && small(tm, m) {
                    break;
                }
                g *= x;
                pq = apow + b * pq;
                rq = pq + b * rq;
                apow *= a;
            }
        } else {
            // The shallow end clear of the seabed: integrals over [0, δ_b], divided at the end.
            let dd = b - da;
            let mut bpow = b * b * sb; // δ_b^(p+1)
            for &[cp, i1, i2, _] in &terms {
                let c = c0 * g * cp;
                let (tv, tm) = (c * bpow * i1, c * bpow * (b * i2 - da * i1));
                v += tv;
                m += tm;
                if small(tv, v) && small(tm, m) {
                    break;
                }
                g *= x;
                bpow *= b;
            }
            (v, m) = (v / dd, m / (dd * dd));
        }
        (len * v, len * m / v)
    }

    #[test]
    fn the_depth_series_by_horner_matches_it_summed_term_by_term() {
        // Level, tilted either way, one end clear, at every depth of the near-edge region
        // (and the terms Horner's scheme takes: from 1 at δ → 0 to the most at δ = r/4).
        let r = 0.0763;
        let depths = [1e-17, 1e-12, 1e-9, 1e-6, 1e-4, 1e-3, 0.01, 0.04, 0.08, 0.15, 0.2, 0.25];
        for &b in &depths {
            for &ratio in &[1.0, 1.0 - 1e-12, 1.0 - 1e-6, 0.99, 0.9, 0.5, 0.1, 1e-6, 0.0, -0.3, -5.0] {
                let (db, da) = (b * r, ratio * b * r);
                for (da, db) in [(da, db), (db, da)] {
                    let (v, s) = near_edge(r, 1.0, da, db);
                    let (vt, st) = near_edge_by_terms(r, 1.0, da, db);
                    assert!((v - vt).abs() <= 1e-15 * vt, "({da:e}, {db:e}): V {v:e} against {vt:e}");
                    assert!((s - st).abs() <= 2e-15, "({da:e}, {db:e}): s̄ {s} against {st}");
                }
            }
        }
        // The reach covers the near-edge region, and the count grows with the depth: 12
        // terms for the paper's chain at rest, 0.08 r deep (docs/model-choices.md).
        const { assert!(SERIES_REACH[SERIES_TERMS - 1] > NEAR_EDGE / 2.0) };
        assert!(SERIES_REACH.windows(2).all(|w| w[0] < w[1]));
        assert_eq!(SERIES_REACH.iter().filter(|&&reach| reach < 0.08 / 2.0).count(), 12);
        assert_eq!(SERIES_REACH.iter().filter(|&&reach| reach < 1e-17 / 2.0).count(), 1);
        // The table by half-binades: never fewer terms than the depth needs and at most two
        // more, over the depths near_edge sees below its limit (at y = 1/8 itself, the bottom
        // of the next binade, it takes all 20).
        for i in 0..200_000 {
            let y = NEAR_EDGE / 2.0 * i as f64 / 200_000.0;
            let needed = SERIES_REACH.iter().filter(|&&reach| reach < y).count().max(1);
            let taken = terms_for(y);
            assert!((needed..=needed + 2).contains(&taken), "y = {y}: {taken} terms, {needed} needed");
            assert_eq!(terms_for(-y), taken, "the sign is ignored");
        }
        for y in [f64::NAN, -f64::NAN, f64::INFINITY, f64::NEG_INFINITY] {
            assert_eq!(terms_for(y), SERIES_TERMS, "{y}");
        }
        assert_eq!((terms_for(0.0), terms_for(-0.0)), (1, 1));
    }

    #[test]
    fn antiderivatives_differentiate_to_the_integrands() {
        let r = 0.0763;
        for i in 0..41 {
            let h = -1.2 * r + 2.4 * r * i as f64 / 40.0;
            let e = 1e-7 * r;
            let (fp, gp) = antiderivatives(r, h + e);
            let (fm, gm) = antiderivatives(r, h - e);
            let (fd, gd) = ((fp - fm) / (2.0 * e), (gp - gm) / (2.0 * e));
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

    /// The jumps of V (relative to V) and of s̄ (m, on a 1 m rod) at a branch boundary: the
    /// ends' heights (h_a, h_b) scaled about `c` by 1 ± e and 1 ± 3e, the boundary between
    /// 1 − e and 1 + e; the difference across it less the mean of the differences on either
    /// side (the smooth change), so that only a step remains.
    fn jump(r: f64, ends: (f64, f64), c: f64, e: f64) -> (f64, f64, f64) {
        let at = |f: f64| embedded_volume(r, 1.0, c + (ends.0 - c) * f, c + (ends.1 - c) * f);
        let [m3, m1, p1, p3] = [at(1.0 - 3.0 * e), at(1.0 - e), at(1.0 + e), at(1.0 + 3.0 * e)];
        let step = |x: [f64; 4]| (x[2] - x[1]) - 0.5 * ((x[3] - x[2]) + (x[1] - x[0]));
        let (v, s) = (step([m3.0, m1.0, p1.0, p3.0]), step([m3.1, m1.1, p1.1, p3.1]));
        (m1.0, v.abs() / m1.0, s.abs())
    }

    /// Rods straddling each branch boundary, for the chain's and the cable's radius: the
    /// near-edge series against the closed form and Taylor series at the deeper end r/4 below
    /// the seabed (level, tilted, the other end clear), the same at the bottom edge, and the
    /// Taylor series against the closed form between the edges.
    fn straddling(r: f64) -> Vec<((f64, f64), f64, f64)> {
        let mut cases = Vec::new();
        let edge = r - NEAR_EDGE * r; // axis height with the lowest fibre r/4 deep
        for t in [0.0, 1e-7, 1e-5, 1e-3, 3e-2, 0.2, 0.5] {
            // The deeper end on the boundary, scaled about the seabed's reference r (depth 0).
            cases.push(((edge + t * r, edge), r, 1e-12));
            cases.push(((edge, edge + t * r), r, 1e-12));
            // The shallower end on the bottom boundary, scaled about the section's bottom.
            let bottom = -r + NEAR_EDGE * r;
            cases.push(((bottom, bottom - t * r), -r, 1e-12));
        }
        for h in [0.0, 0.3 * r, -0.4 * r, 0.74 * r, -0.74 * r] {
            let d = TAYLOR * (r - h.abs()) / (1.0 + TAYLOR / 2.0);
            cases.push(((h - d / 2.0, h + d / 2.0), h, 1e-9));
            cases.push(((h + d / 2.0, h - d / 2.0), h, 1e-9));
        }
        cases
    }

    #[test]
    fn volume_and_centroid_are_continuous_across_every_branch_boundary() {
        // A step of 4.8e-6 × V (the old 8-point branch against the closed form, for a chain
        // link resting on the k_z × 1e4 seabed) broke SDIRK4's difference Jacobian there
        // (docs/integrators.md, "The stiff scene"); the old bound here was 1e-5 × V.
        for r in [0.0763, 0.0237] {
            for (ends, c, e) in straddling(r) {
                let (v, dv, ds) = jump(r, ends, c, e);
                assert!(dv <= 2e-13, "r = {r}, ends {ends:?}: V = {v:e} jumps by {dv:e} of itself");
                assert!(ds <= 5e-11, "r = {r}, ends {ends:?}: s̄ jumps by {ds:e} m on a 1 m rod");
            }
        }
    }

    #[test]
    fn slopes_match_across_every_branch_boundary() {
        // One-sided differences of V in h_a with SDIRK4's relative increment (√ε) on either
        // side of each boundary: the slope the Jacobian sees is the same on both.
        for r in [0.0763, 0.0237] {
            for (ends, c, e) in straddling(r) {
                let slope = |f: f64| {
                    let (ha, hb) = (c + (ends.0 - c) * f, c + (ends.1 - c) * f);
                    let dh = 1.5e-8 * r;
                    (embedded_volume(r, 1.0, ha + dh, hb).0 - embedded_volume(r, 1.0, ha, hb).0) / dh
                };
                let (below, above) = (slope(1.0 - e), slope(1.0 + e));
                let scale = below.abs().max(PI * r * r * 1e-6);
                assert!(
                    (above - below).abs() <= 1e-5 * scale,
                    "r = {r}, ends {ends:?}: ∂V/∂h_a {below:e} against {above:e}"
                );
            }
        }
    }

    #[test]
    fn level_rods_at_the_edges_match_the_segment_by_its_half_angle_series() {
        // Barely touching and nearly buried, where A's closed form (and the 8-point rule on
        // it) lose digits: A = r²(θ − sin 2θ / 2), θ = 2 asin √(δ/2r), by the sine series.
        let (r, len) = (0.0763, 1.0);
        let segment = |d: f64| {
            let t = 2.0 * (d / (2.0 * r)).sqrt().asin();
            let (mut term, mut sum) = (2.0 * t, 0.0); // (2θ)^(2n+1)/(2n+1)! with its sign
            for n in 1..30 {
                term *= -(2.0 * t) * (2.0 * t) / ((2 * n) as f64 * (2 * n + 1) as f64);
                sum -= term / 2.0;
            }
            r * r * sum
        };
        for d in [1e-9, 1e-7, 1e-5, 1e-3, 0.01, 0.019] {
            let d = r - (r - d); // the depth the heights represent (exactly)
            let (v, s) = embedded_volume(r, len, r - d, r - d);
            assert!((v - segment(d)).abs() < 1e-13 * v, "δ = {d}: V {v} against {}", segment(d));
            let (vb, sb) = embedded_volume(r, len, -(r - d), -(r - d)); // the section less a segment d high
            let full = PI * r * r;
            assert!((vb - (full - segment(d))).abs() < 1e-15 * full, "2r − δ = {d}: V {vb}");
            assert!((s - 0.5).abs() < 1e-15 && (sb - 0.5).abs() < 1e-15, "δ = {d}: s̄ {s}, {sb}");
        }
        // An end crossing the top of the section.
        let (b, a) = (embedded_volume(r, len, 0.0, r - 1e-12), embedded_volume(r, len, 0.0, r + 1e-12));
        // (Moving an end by 2e-12 m changes V by about 3e-11 of itself.)
        assert!((b.0 - a.0).abs() < 1e-10 * b.0 && (b.1 - a.1).abs() < 1e-10, "{b:?} {a:?}");
    }

    #[test]
    fn barely_touching_rod_has_its_centroid_on_the_embedded_part_and_nan_propagates() {
        let (r, len) = (0.0763, 1.0);
        for (ha, hb) in [(r - 1e-6, r + 0.01), (r + 0.01, r - 1e-6), (r - 1e-9, r + 0.5)] {
            let (v, s) = embedded_volume(r, len, ha, hb);
            let edge = len * (r - ha) / (hb - ha);
            let (s0, s1) = if ha < hb { (0.0, edge) } else { (edge, len) };
            assert!(v >= 0.0 && s >= s0 && s <= s1, "({ha}, {hb}): V {v}, s̄ {s} outside [{s0}, {s1}]");
        }
        let (v, s) = embedded_volume(r, len, f64::NAN, r + 1.0);
        assert!(v.is_nan() && s.is_nan());
        let (v, _) = embedded_volume(r, len, 0.03, 0.03);
        assert!(v > 0.0 && v.is_finite());
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
        // A rod resting on the seabed, 6 mm and 9 mm deep at its ends: the closed form
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

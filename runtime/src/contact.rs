//! The seabed's embedded volumes of a chain's touching elements, for the generated contact
//! pass (`LoadParams::embedded_volumes`): taken two at a time, and where both elements of a
//! pair lie near the top of their section with both ends below the seabed plane (every
//! element resting on it), [`embedded_volume`]'s depth series runs on two lanes ([`F2`]);
//! anywhere else, two calls of it. One call per evaluation does them all, so the pairs'
//! chains of dependent operations overlap in the processor and the per-element constants
//! stay in registers.
//!
//! The lanes run `forces::seabed`'s `near_edge` operation for operation, each with its own
//! number of terms, so a lane equals the scalar call bit for bit: the loads stay the force
//! modules' exactly, whichever element a lane is paired with. `resting_pair` is that
//! function's `a > 0` branch written again on lanes: a change to one is a change to both.

use kanestop_generated::lanes::F2;
use kanestop_generated::Element;

use crate::forces::seabed::{embedded_volume, terms_for, NEAR_EDGE, SERIES};

/// The embedded volumes of the touching elements, in place: a row `contacts[k]` reading
/// `[h_a, h_b, 1]` (element k's end heights above the seabed, marked touching by the contact
/// pass) becomes `[V^S, s̄, 0]` as [`embedded_volume`] gives them (`elements[k]`'s radius and
/// length); the other rows are left as they are.
pub fn embedded_volumes(elements: &[Element], contacts: &mut [[f64; 3]]) {
    let n = contacts.len().min(elements.len());
    let mut held = None;
    for k in 0..n {
        if contacts[k][2] != 1.0 {
            continue;
        }
        let Some(j) = held.take() else {
            held = Some(k);
            continue;
        };
        let (a, b) = (&elements[j], &elements[k]);
        let (ca, cb) = (contacts[j], contacts[k]);
        let [(va, sa), (vb, sb)] =
            embedded_volume_pair([a.radius, b.radius], [a.length, b.length], [ca[0], cb[0]], [ca[1], cb[1]]);
        contacts[j] = [va, sa, 0.0];
        contacts[k] = [vb, sb, 0.0];
    }
    if let Some(j) = held {
        let (e, c) = (&elements[j], contacts[j]);
        let (v, s_bar) = embedded_volume(e.radius, e.length, c[0], c[1]);
        contacts[j] = [v, s_bar, 0.0];
    }
}

/// `[(V^S, s̄)]` of two rods, lane i of radius `r[i]`, length `len[i]`, its axis from height
/// `h_a[i]` to `h_b[i]` above the seabed: as two calls of [`embedded_volume`].
#[inline(always)]
fn embedded_volume_pair(r: [f64; 2], len: [f64; 2], h_a: [f64; 2], h_b: [f64; 2]) -> [(f64, f64); 2] {
    let (da, db) = ([r[0] - h_a[0], r[1] - h_a[1]], [r[0] - h_b[0], r[1] - h_b[1]]);
    if resting(r[0], da[0], db[0]) && resting(r[1], da[1], db[1]) {
        resting_pair(r, len, da, db)
    } else {
        [embedded_volume(r[0], len[0], h_a[0], h_b[0]), embedded_volume(r[1], len[1], h_a[1], h_b[1])]
    }
}

/// Whether a rod of radius `r` whose lowest fibre lies `da`, `db` below the seabed at its
/// ends rests on it: both ends embedded, the deeper at most `NEAR_EDGE` r, i.e.
/// `embedded_volume`'s near-edge branch with its shallow end below the plane (false for NaN).
fn resting(r: f64, da: f64, db: f64) -> bool {
    let edge = NEAR_EDGE * r;
    da > 0.0 && db > 0.0 && da <= edge && db <= edge
}

/// `near_edge` of two rods whose ends are both embedded (`da`, `db` > 0, the depths of the
/// lowest fibre at the two ends): its steps on two lanes.
#[inline(always)]
fn resting_pair(r: [f64; 2], len: [f64; 2], da: [f64; 2], db: [f64; 2]) -> [(f64, f64); 2] {
    let lanes = |f: fn(f64, f64) -> f64| F2::new(f(da[0], db[0]), f(da[1], db[1]));
    let (a, b) = (lanes(f64::min), lanes(f64::max));
    let (r2, two) = (F2::new(r[0], r[1]), F2::splat(2.0));
    let x = F2::splat(-0.5) / r2;
    let y = (F2::splat(0.0) - x) * b;
    let [y0, y1] = y.lanes();
    let (t0, t1) = (terms_for(y0), terms_for(y1));
    let (xa, xb) = (x * a, x * b);
    // Each lane its own number of terms: Horner's scheme from the longer series' top, the
    // other lane's coefficients +0 until its own top (`keep`). From a state of +0 a zero
    // coefficient leaves +0 (0 + x·0 = 0 + (−0) = +0: x < 0, the state ≥ 0), and at its own
    // top term the lane takes exactly the scalar loop's starting state (c, 0, c₂, 0, 0): equal
    // to it bit for bit.
    let zero = F2::splat(0.0);
    let (mut p1, mut p1_ab) = (zero, zero);
    let (mut p2, mut p2_bb, mut p2_abb) = (zero, zero, zero);
    let mut step = |c1: F2, c2: F2| {
        p1_ab = p1 + xa * p1_ab;
        p1 = c1 + xb * p1;
        p2_abb = p2_bb + xa * p2_abb;
        p2_bb = p2 + xb * p2_bb;
        p2 = c2 + xb * p2;
    };
    let (short, long) = (t0.min(t1), t0.max(t1));
    let longer = [t0 == long, t1 == long];
    for &[c1, c2] in SERIES[short..long].iter().rev() {
        step(F2::splat(c1).keep(longer), F2::splat(c2).keep(longer));
    }
    for &[c1, c2] in SERIES[..short].iter().rev() {
        step(F2::splat(c1), F2::splat(c2));
    }
    let (sa, sb) = (a.sqrt(), b.sqrt());
    let s = sa + sb;
    let p32 = sa + b / s;
    let p52 = a * sa + b * p32;
    let p72 = a * a * sa + b * p52;
    let r32 = (two * sa + sb) / (two * s * s);
    let r72 = p52 + b * (p32 + b * r32);
    let v = a * a * sa * (x * p1_ab) + p52 * p1;
    let m = a * a * a * sa * (x * x * p2_abb) + p72 * (x * p2_bb) + r72 * p2;
    let c0 = two * (two * r2).sqrt();
    let (v, m) = (c0 * v, c0 * m);
    let length = F2::new(len[0], len[1]);
    let (volume, s_bar) = ((length * v).lanes(), (length * m / v).lanes());
    let lane = |i: usize| (volume[i], if da[i] <= db[i] { s_bar[i] } else { len[i] - s_bar[i] });
    [lane(0), lane(1)]
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Heights of rods resting on the seabed and of rods in every other regime (clear,
    /// crossing the plane, deep, buried, NaN), radius r: pairs of each with each.
    fn cases(r: f64) -> Vec<(f64, f64)> {
        let mut h = Vec::new();
        for i in 0..40 {
            let d = r * (0.002 + 0.0062 * i as f64); // up to 0.25 r deep
            for tilt in [0.0, 1e-9, 1e-4, 0.01, 0.3] {
                h.push((r - d, r - d * (1.0 - tilt)));
                h.push((r - d * (1.0 - tilt), r - d));
            }
        }
        h.extend([(r + 0.1, r + 0.2), (0.9 * r, 1.1 * r), (0.2 * r, 0.3 * r), (-2.0 * r, -1.5 * r)]);
        h.extend([(-0.95 * r, -0.9 * r), (f64::NAN, 0.9 * r), (0.0, 0.0), (0.76 * r, 0.74 * r)]);
        h
    }

    #[test]
    fn a_pair_equals_two_calls_bit_for_bit() {
        let (r, len) = (0.038, 2.0);
        let h = cases(r);
        let (mut pairs, mut on_lanes, mut unequal_terms) = (0, 0, 0);
        for (i, &(a0, b0)) in h.iter().enumerate() {
            for &(a1, b1) in h.iter().skip(i % 7).step_by(7) {
                let (r1, len1) = (1.3 * r, 0.5 * len);
                let got = embedded_volume_pair([r, r1], [len, len1], [a0, a1], [b0, b1]);
                let want = [embedded_volume(r, len, a0, b0), embedded_volume(r1, len1, a1, b1)];
                let bits = |(v, s): (f64, f64)| (v.to_bits(), s.to_bits());
                assert_eq!(got.map(bits), want.map(bits), "at {a0}, {b0} / {a1}, {b1}");
                pairs += 1;
                let (d0, d1) = ((r - a0, r - b0), (r1 - a1, r1 - b1));
                if resting(r, d0.0, d0.1) && resting(r1, d1.0, d1.1) {
                    on_lanes += 1;
                    let y = |d: (f64, f64), r: f64| d.0.max(d.1) / (2.0 * r);
                    unequal_terms += usize::from(terms_for(y(d0, r)) != terms_for(y(d1, r1)));
                }
            }
        }
        // The lanes ran for thousands of the pairs, most of those with series of different
        // lengths.
        assert!(
            on_lanes > 1000 && unequal_terms * 2 > on_lanes,
            "{on_lanes} of {pairs} on lanes, {unequal_terms} unequal"
        );
    }

    #[test]
    fn the_lanes_serve_resting_rods_and_leave_the_rest_to_the_scalar_form() {
        let r = 0.05;
        // Two resting rods of the same depth: the lanes, equal to the scalar call exactly.
        let (ha, hb) = (r - 0.004, r - 0.0041);
        let [p, q] = embedded_volume_pair([r; 2], [1.0; 2], [ha; 2], [hb; 2]);
        assert_eq!(p, embedded_volume(r, 1.0, ha, hb));
        assert_eq!(p, q);
        // A NaN height reaches the scalar form, which returns NaN.
        let [n, ok] = embedded_volume_pair([r; 2], [1.0; 2], [f64::NAN, ha], [hb; 2]);
        assert!(n.0.is_nan() && n.1.is_nan());
        assert_eq!(ok, embedded_volume(r, 1.0, ha, hb));
    }

    #[test]
    fn the_marked_rows_become_volumes_and_the_rest_stay() {
        let r = 0.04;
        // Only the radius and the length are read.
        let element = |length: f64| Element {
            length,
            radius: r,
            line: true,
            volume: 0.0,
            normal_drag: 0.0,
            tangential_drag: 0.0,
            length_cubed: 0.0,
        };
        let elements: Vec<Element> = (0..9).map(|k| element(1.0 + 0.1 * k as f64)).collect();
        // Resting, crossing, resting, untouched, resting, NaN, resting, resting, untouched:
        // pairs of every mix and an odd one left over.
        let heights = [
            (r - 0.003, r - 0.0031),
            (0.5 * r, 2.0 * r),
            (r - 0.002, r - 0.002),
            (9.0, 9.0),
            (r - 0.004, r - 0.0035),
            (f64::NAN, r),
            (r - 0.001, r - 0.0012),
            (-0.3 * r, 0.2 * r),
            (1.0, 2.0),
        ];
        let marked = |k: usize| !matches!(k, 3 | 8);
        let mut rows: Vec<[f64; 3]> = heights
            .iter()
            .enumerate()
            .map(|(k, &(a, b))| if marked(k) { [a, b, 1.0] } else { [7.0, 8.0, 0.0] })
            .collect();
        embedded_volumes(&elements, &mut rows);
        for (k, (&(a, b), row)) in heights.iter().zip(&rows).enumerate() {
            if !marked(k) {
                assert_eq!(*row, [7.0, 8.0, 0.0], "row {k} is not touched");
                continue;
            }
            let (v, s) = embedded_volume(r, elements[k].length, a, b);
            assert_eq!(row[2], 0.0);
            assert_eq!((row[0].to_bits(), row[1].to_bits()), (v.to_bits(), s.to_bits()), "row {k}");
        }
    }
}

//! The initial shape of the cable: a catenary with a grounded part (Eqs. 30–35), and the
//! rigid elements laid on it.
//!
//! The shape depends only on the geometry (L_c, x_L, h_L): w_c cancels between Eqs. 30 and
//! 31. Elements are rigid chords, and a chord is shorter than the arc it spans, so laying
//! elements of total length L_c along the catenary of length L_c would overshoot its end.
//! [`lay_elements`] therefore uses the catenary through the same end points whose length
//! L' ≥ L_c makes the chord polygon end exactly at (x_L, h_L).

/// The catenary of Eqs. 30–34, lower end o at the origin on the seabed line.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Catenary {
    /// Curve length L_c (cable length along this curve), m.
    pub length: f64,
    /// x_L, horizontal projection of the whole curve, m.
    pub horizontal: f64,
    /// h_L, vertical projection, m.
    pub vertical: f64,
    /// b = x_s / a (Eq. 30), dimensionless.
    pub b: f64,
    /// a = T_h / w_c, m.
    pub a: f64,
}

/// Why no catenary exists for the given geometry.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum CatenaryError {
    /// The geometry leaves no grounded part: Eqs. 30–34 need 0 < L_c − x_L < h_L.
    #[error(
        "no catenary with a grounded part: need 0 < L_c − x_L < h_L, have L_c = {length} m, x_L = {horizontal} m, h_L = {vertical} m"
    )]
    NoGroundedPart {
        /// L_c, m.
        length: f64,
        /// x_L, m.
        horizontal: f64,
        /// h_L, m.
        vertical: f64,
    },
    /// Eq. 30 has no root in the range searched.
    #[error("Eq. 30 has no root below b = 700")]
    NoRoot,
    /// A rigid element is too long to be laid as a chord of the curve.
    #[error("element of {length} m cannot be laid on the catenary")]
    ElementTooLong {
        /// The element's length, m.
        length: f64,
    },
    /// The first element is shorter than the rise from the chain's height to its upper joint.
    #[error("the first cable element ({length} m) cannot span the {rise} m rise from the chain to its upper joint")]
    FirstElementTooShort {
        /// Its length, m.
        length: f64,
        /// The rise it must span, m.
        rise: f64,
    },
    /// No curve length makes the chord polygon end at (x_L, h_L).
    #[error("elements cannot be laid to end at (x_L, h_L)")]
    CannotEnd,
    /// The curve through o and (x_L, h_L) would not touch the seabed at o: its lowest point
    /// lies behind o (a negative grounded length), so the cable would leave o with a slope and
    /// lift the chain. Needs x_L ≤ [`max_horizontal`].
    #[error(
        "no touchdown: x_L = {horizontal} m exceeds the fully suspended span {max} m for L_c = {length} m, h_L = {vertical} m"
    )]
    NoTouchdown {
        /// L_c, m.
        length: f64,
        /// x_L, m.
        horizontal: f64,
        /// h_L, m.
        vertical: f64,
        /// The largest x_L with touchdown, m.
        max: f64,
    },
    /// No x_L lays the elements on a catenary of this a = T_h / w_c, m (see
    /// [`horizontal_for_parameter`]).
    #[error("no laid line has a = T_h / w_c = {a} m{}", match range {
        Some((lo, hi)) => format!(" (the laid lines have a in ({lo}, {hi}] m)"),
        None => String::new(),
    })]
    NoLineWithParameter {
        /// The a asked for, m.
        a: f64,
        /// The a of the laid range's ends, m, when there is a laid range.
        range: Option<(f64, f64)>,
    },
    /// The scene gives neither x_L nor T_h, or both (`scene::Initial::layout`).
    #[error("the line is laid by x_L or by T_h: give one of them")]
    NoLayout,
    /// The laid chord polygon ends farther than [`END_TOLERANCE`] from (x_L, h_L).
    #[error("the laid elements end {gap:.3e} m from (x_L, h_L)")]
    EndMissed {
        /// Distance between the polygon's end and (x_L, h_L), m.
        gap: f64,
    },
}

/// How close the laid elements must end to (x_L, h_L), m.
pub const END_TOLERANCE: f64 = 1e-9;

/// The largest x_L for which a cable of length L_c with vertical projection h_L < L_c still
/// touches the seabed at o: the whole cable suspended, tangent to the seabed at o. From
/// Eq. 34 with S_c = L_c and Eq. 33, S_c² = h_L² + 2 a h_L gives a = (L_c² − h_L²)/(2 h_L),
/// and then x_s = a asinh(L_c/a) (Eq. 34 inverted), m.
pub fn max_horizontal(length: f64, vertical: f64) -> f64 {
    let a = (length * length - vertical * vertical) / (2.0 * vertical);
    a * (length / a).asinh()
}

/// The x_L for which a continuous cable of length L_c lies as the paper lays it (Section 3.1):
/// grounded from o, then the catenary of Eqs. 30–34 up to (x_L, h_L). Open below (x_L →
/// L_c − h_L: no tension, the cable hangs vertically), closed above (x_L =
/// [`max_horizontal`]: nothing grounded); empty (`None`) when h_L ≥ L_c, m.
pub fn continuous_range(length: f64, vertical: f64) -> Option<(f64, f64)> {
    (vertical > 0.0 && vertical < length).then(|| ((length - vertical).max(0.0), max_horizontal(length, vertical)))
}

impl Catenary {
    /// Solves Eq. 30 for b by bisection, then a from Eq. 31 (a = T_h/w_c).
    /// Requires 0 < L_c − x_L < h_L.
    pub fn solve(length: f64, horizontal: f64, vertical: f64) -> Result<Catenary, CatenaryError> {
        let slack = length - horizontal;
        if !(slack > 0.0 && slack < vertical) {
            return Err(CatenaryError::NoGroundedPart { length, horizontal, vertical });
        }
        // Eq. 30: g(b) = (cosh b − 1)(L_c − x_L) − h_L (sinh b − b); g > 0 for small b and
        // g < 0 for large b when L_c − x_L < h_L.
        let g = |b: f64| (b.cosh() - 1.0) * slack - vertical * (b.sinh() - b);
        let mut lo = 1e-6;
        let mut hi = 1.0;
        while g(hi) > 0.0 {
            lo = hi;
            hi *= 2.0;
            if hi > 700.0 {
                return Err(CatenaryError::NoRoot);
            }
        }
        for _ in 0..200 {
            let mid = 0.5 * (lo + hi);
            if g(mid) > 0.0 {
                lo = mid;
            } else {
                hi = mid;
            }
            if hi - lo <= 1e-15 * hi {
                break;
            }
        }
        let b = 0.5 * (lo + hi);
        let a = slack / (b.sinh() - b); // Eq. 31 divided by w_c
        let cat = Catenary { length, horizontal, vertical, b, a };
        if cat.grounded_length() < -END_TOLERANCE {
            let max = max_horizontal(length, vertical);
            return Err(CatenaryError::NoTouchdown { length, horizontal, vertical, max });
        }
        Ok(cat)
    }

    /// x_s = a b, horizontal extent of the suspended part, m.
    pub fn suspended_horizontal(&self) -> f64 {
        self.a * self.b
    }

    /// S_c = a sinh b (Eq. 34), length of the suspended part, m.
    pub fn suspended_length(&self) -> f64 {
        self.a * self.b.sinh()
    }

    /// Length lying on the seabed, L_c − S_c = x_L − x_s, m.
    pub fn grounded_length(&self) -> f64 {
        self.horizontal - self.suspended_horizontal()
    }

    /// The point at arc length `s` from o (Eqs. 33, 34), continued analytically past the
    /// end, m.
    pub fn point(&self, s: f64) -> [f64; 2] {
        let grounded = self.grounded_length();
        if s <= grounded {
            [s, 0.0]
        } else {
            let xi = self.a * ((s - grounded) / self.a).asinh();
            [grounded + xi, self.a * ((xi / self.a).cosh() - 1.0)]
        }
    }
}

/// Joint points of rigid elements of the given lengths laid from o along a catenary
/// through (x_L, h_L): `lengths.len() + 1` points, the first (0, 0), the last within
/// [`END_TOLERANCE`] of (x_L, h_L), or an error. Returns the curve used (its `length` is
/// L' ≥ L_c) and the points.
pub fn lay_elements(
    lengths: &[f64],
    horizontal: f64,
    vertical: f64,
) -> Result<(Catenary, Vec<[f64; 2]>), CatenaryError> {
    let (cat, points) = lay_chords(lengths, horizontal, vertical)?;
    let end = points.last().copied().unwrap_or([0.0, 0.0]);
    let gap = (end[0] - horizontal).hypot(end[1] - vertical);
    if gap.is_nan() || gap > END_TOLERANCE {
        return Err(CatenaryError::EndMissed { gap });
    }
    Ok((cat, points))
}

/// The x_L range, m, in which [`lay_elements`] lays these elements for this h_L: the
/// continuous range of [`continuous_range`] for L_c = Σ lengths, its lower end raised by
/// the rigid chords (near x_L = L_c − h_L the curve has a sharp corner the chords cannot
/// follow). Found by bisection on the laying itself (to 1e-9 of L_c), so a point inside lays
/// and a point outside does not. `None` when no x_L lays (h_L ≥ L_c, a single element).
pub fn laid_range(lengths: &[f64], vertical: f64) -> Option<(f64, f64)> {
    let total: f64 = lengths.iter().sum();
    let (lo, hi) = continuous_range(total, vertical)?;
    let lays = |x: f64| lay_elements(lengths, x, vertical).is_ok();
    // A point that lays: from the fully suspended end down towards the corner.
    let inside =
        [0.0, 1e-6, 1e-4, 1e-3, 1e-2, 0.1, 0.3, 0.5, 0.7, 0.9].iter().map(|f| hi - f * (hi - lo)).find(|&x| lays(x))?;
    let edge = |mut good: f64, mut bad: f64| {
        while (good - bad).abs() > 1e-9 * total {
            let mid = 0.5 * (good + bad);
            if lays(mid) {
                good = mid;
            } else {
                bad = mid;
            }
        }
        good
    };
    let upper = if lays(hi) { hi } else { edge(inside, hi) };
    Some((edge(inside, lo), upper))
}

/// The h_L range, m, in which [`lay_elements`] lays these elements for this x_L: that of a
/// continuous cable of length L_c = Σ lengths, (L_c − x_L, h_max] with h_max where
/// [`max_horizontal`] falls to x_L, narrowed to where the rigid chords lay (two 76 m elements
/// lay at x_L = 148 m only from h_L = 24.33 m, where the continuous range starts at 4 m). Found
/// by bisection on the laying itself (to 1e-9 of L_c); `None` when no h_L lays.
pub fn laid_vertical_range(lengths: &[f64], horizontal: f64) -> Option<(f64, f64)> {
    let total: f64 = lengths.iter().sum();
    let x = horizontal;
    if !(x > 0.0 && x < total) {
        return None;
    }
    // max_horizontal falls as h_L rises: bisect for max_horizontal(L_c, h) = x.
    let (mut h_lo, mut h_hi) = (1e-9 * total, total * (1.0 - 1e-12));
    if max_horizontal(total, h_lo) < x {
        return None;
    }
    for _ in 0..200 {
        let mid = 0.5 * (h_lo + h_hi);
        if max_horizontal(total, mid) >= x {
            h_lo = mid;
        } else {
            h_hi = mid;
        }
    }
    let (lo, hi) = (total - x, h_lo);
    let lays = |h: f64| lay_elements(lengths, x, h).is_ok();
    // A point that lays, scanned across the continuous range.
    let inside = (1..64).map(|k| lo + (hi - lo) * f64::from(k) / 64.0).find(|&h| lays(h))?;
    let edge = |mut good: f64, mut bad: f64| {
        while (good - bad).abs() > 1e-9 * total {
            let mid = 0.5 * (good + bad);
            if lays(mid) {
                good = mid;
            } else {
                bad = mid;
            }
        }
        good
    };
    let upper = if lays(hi) { hi } else { edge(inside, hi) };
    Some((edge(inside, lo), upper))
}

/// The x_L, m, at which [`lay_elements`] lays these elements on a catenary of parameter
/// `a` = T_h / w_c (Eq. 31), for this h_L: the horizontal projection that gives the laid line
/// a chosen horizontal tension T_h. The laid curve's a grows with x_L (less slack, more
/// tension), so the crossing is bracketed from the continuous cable's x_L at this a (Eqs. 33,
/// 34: S_c² = h_L² + 2 a h_L, x_s = a asinh(S_c/a), x_L = L_c − S_c + x_s) and found to
/// 1e-15 of x_L. Fails with [`CatenaryError::NoLineWithParameter`] when no x_L in
/// [`laid_range`] gives this a (too slack to lay, or no cable left on the seabed).
pub fn horizontal_for_parameter(lengths: &[f64], vertical: f64, a: f64) -> Result<f64, CatenaryError> {
    let total: f64 = lengths.iter().sum();
    let out_of_range = || {
        let range = laid_range(lengths, vertical).and_then(|(lo, hi)| {
            let at = |x: f64| lay_elements(lengths, x, vertical).ok().map(|(c, _)| c.a);
            Some((at(lo)?, at(hi)?))
        });
        CatenaryError::NoLineWithParameter { a, range }
    };
    let Some((lo, hi)) = continuous_range(total, vertical) else { return Err(out_of_range()) };
    if !(a > 0.0 && a.is_finite()) {
        return Err(out_of_range());
    }
    // f(x) = a of the laid curve − a: increasing in x; None where the elements do not lay.
    let f = |x: f64| lay_elements(lengths, x, vertical).ok().map(|(c, _)| c.a - a);
    let suspended = (vertical * vertical + 2.0 * a * vertical).sqrt();
    let guess = (total - suspended + a * (suspended / a).asinh()).clamp(lo, hi);
    // Near the corner (x_L → L_c − h_L) the chords may not lay at the continuous guess:
    // start from the laid range's nearer end instead.
    let start = match f(guess) {
        Some(_) => guess,
        None => {
            let (laid_lo, laid_hi) = laid_range(lengths, vertical).ok_or_else(out_of_range)?;
            guess.clamp(laid_lo, laid_hi)
        }
    };
    bracket_from(f, start, lo, hi, total).ok_or_else(out_of_range)
}

/// The crossing of the increasing `f` near `start` in [lo, hi]: steps of 1e-6·`scale`,
/// doubling, toward the sign change (a side that stops laying first is out of range), then
/// [`crossing`]. `None` when `f` stops being defined
/// (or the range ends) before its sign changes.
fn bracket_from(f: impl Fn(f64) -> Option<f64>, start: f64, lo: f64, hi: f64, scale: f64) -> Option<f64> {
    let f0 = f(start)?;
    if f0 == 0.0 {
        return Some(start);
    }
    let direction = if f0 < 0.0 { 1.0 } else { -1.0 };
    let (mut near, mut f_near) = (start, f0);
    let mut step = 1e-6 * scale;
    loop {
        let x = (near + direction * step).clamp(lo, hi);
        if x == near {
            return None;
        }
        let fx = f(x)?;
        if fx == 0.0 {
            return Some(x);
        }
        if (fx > 0.0) != (f0 > 0.0) {
            let ((a, fa), (b, fb)) =
                if direction > 0.0 { ((near, f_near), (x, fx)) } else { ((x, fx), (near, f_near)) };
            let g = |t: f64| f(t).ok_or(());
            let (a, b) = crossing(g, (a, fa), (b, fb), 1e-15).ok()?;
            return Some(0.5 * (a + b));
        }
        (near, f_near) = (x, fx);
        step *= 2.0;
    }
}

/// [`lay_elements`] before the check of its end.
fn lay_chords(lengths: &[f64], horizontal: f64, vertical: f64) -> Result<(Catenary, Vec<[f64; 2]>), CatenaryError> {
    let total: f64 = lengths.iter().sum();
    // Arc length reached by the chord polygon on the curve of length `curve_length`.
    let polygon = |curve_length: f64| -> Result<(Catenary, Vec<[f64; 2]>, f64), CatenaryError> {
        let cat = Catenary::solve(curve_length, horizontal, vertical)?;
        let mut points = vec![[0.0, 0.0]];
        let mut s = 0.0;
        for &len in lengths {
            let from = *points.last().unwrap();
            let chord = |t: f64| {
                let p = cat.point(t);
                ((p[0] - from[0]).powi(2) + (p[1] - from[1]).powi(2)).sqrt()
            };
            // The chord to arc position t grows with t; it is ≤ len at t = s + len.
            let (lo, hi) = (s + len, s + 4.0 * len);
            let beyond = chord(hi) - len;
            if beyond < 0.0 {
                return Err(CatenaryError::ElementTooLong { length: len });
            }
            let (a, b) =
                crossing(|t| Ok::<_, CatenaryError>(chord(t) - len), (lo, chord(lo) - len), (hi, beyond), 1e-14)?;
            s = 0.5 * (a + b);
            points.push(cat.point(s));
        }
        Ok((cat, points, s))
    };
    // Find L' in [L_c, x_L + h_L) with polygon end arc = L': the curve's length minus the
    // arc the chords reach, increasing in L'.
    let shortfall = |l: f64| polygon(l).map(|(_, _, s)| l - s);
    let lo = total;
    let hi = (total + 0.05 * total).min(horizontal + vertical - 1e-9 * total);
    let at_lo = shortfall(lo)?;
    if at_lo >= 0.0 {
        let (cat, points, _) = polygon(lo)?;
        return Ok((cat, points));
    }
    let at_hi = shortfall(hi)?;
    if at_hi < 0.0 {
        return Err(CatenaryError::CannotEnd);
    }
    // The end of the bracket where the chords reach the curve's end.
    let (_, length) = crossing(shortfall, (lo, at_lo), (hi, at_hi), 1e-15)?;
    let (cat, points, _) = polygon(length)?;
    Ok((cat, points))
}

/// Where the increasing `f` crosses zero in the bracket from `lo` = (x, f(x) < 0) to `hi` =
/// (x, f(x) ≥ 0): the bracket narrowed to `tol` × its upper end, as bisection gives it, by
/// regula falsi with the Illinois rule (the retained end's value halved when the
/// same end moves twice), which converges superlinearly on these smooth functions where
/// bisection needs some 50 halvings; a point outside the bracket, or two steps that did not
/// halve it, fall back to bisection, so a flat or rounding-noisy `f` near its root still
/// ends in a bracket of signs.
fn crossing<E>(
    mut f: impl FnMut(f64) -> Result<f64, E>,
    (mut a, mut fa): (f64, f64),
    (mut b, mut fb): (f64, f64),
    tol: f64,
) -> Result<(f64, f64), E> {
    let mut last = 0i8;
    // Bisect when two steps in a row did not halve the bracket: never more than three times
    // bisection's evaluations, whatever the shape of f (a value that underflows near the root
    // stalls interpolation).
    let (mut half, mut stalls) = (0.5 * (b - a), 0);
    for _ in 0..600 {
        if b - a <= tol * b {
            break;
        }
        let mut c = b - fb * (b - a) / (fb - fa);
        if !(c > a && c < b) || stalls >= 2 {
            c = 0.5 * (a + b);
        }
        let fc = f(c)?;
        if fc < 0.0 {
            (a, fa) = (c, fc);
            if last == -1 {
                fb *= 0.5;
            }
            last = -1;
        } else {
            (b, fb) = (c, fc);
            if last == 1 {
                fa *= 0.5;
            }
            last = 1;
        }
        if b - a <= half {
            (half, stalls) = (0.5 * (b - a), 0);
        } else {
            stalls += 1;
        }
    }
    Ok((a, b))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_crossing_is_bracketed_as_bisection_brackets_it_in_fewer_evaluations() {
        let mut calls = 0;
        let f = |x: f64| {
            calls += 1;
            Ok::<_, ()>(x * x * x - 2.0)
        };
        let (a, b) = crossing(f, (0.0, -2.0), (2.0, 6.0), 1e-14).unwrap();
        let root = 2f64.cbrt();
        assert!(a <= root && root <= b && b - a <= 1e-14 * b, "[{a}, {b}]");
        // Bisection needs 48 halvings from a width of 2 to 1e-14 × 1.26.
        assert!(calls < 20, "{calls} evaluations");
        // A flat-then-steep function: the interpolated points crawl, Illinois keeps it going.
        let (a, b) =
            crossing(|x: f64| Ok::<_, ()>((x - 0.9).powi(9)), (0.0, -(0.9f64.powi(9))), (1.0, 0.1f64.powi(9)), 1e-12)
                .unwrap();
        assert!(a <= 0.9 + 1e-9 && b >= 0.9 - 1e-9 && b - a <= 1e-12, "[{a}, {b}]");
    }

    #[test]
    fn eq_30_to_34_are_satisfied() {
        let c = Catenary::solve(152.0, 148.0, 6.0).unwrap();
        let (slack, h) = (152.0 - 148.0, 6.0);
        assert!(((c.b.cosh() - 1.0) * slack - h * (c.b.sinh() - c.b)).abs() < 1e-9);
        // Eq. 33 and Eq. 34 and the horizontal closure.
        assert!((c.a * ((c.suspended_horizontal() / c.a).cosh() - 1.0) - h).abs() < 1e-9);
        assert!((152.0 - c.suspended_length() + c.suspended_horizontal() - 148.0).abs() < 1e-9);
        let end = c.point(152.0);
        assert!((end[0] - 148.0).abs() < 1e-9 && (end[1] - 6.0).abs() < 1e-9);
    }

    #[test]
    fn elements_end_at_the_top() {
        let mut lengths = vec![2.0; 3];
        lengths.extend(vec![10.0; 12]);
        lengths.extend(vec![2.0; 13]);
        let (cat, pts) = lay_elements(&lengths, 148.0, 6.0).unwrap();
        let end = pts.last().unwrap();
        assert!((end[0] - 148.0).abs() < 1e-6 && (end[1] - 6.0).abs() < 1e-6, "{end:?}");
        assert!(cat.length >= 152.0 && cat.length < 152.1);
        for (w, &len) in pts.windows(2).zip(&lengths) {
            let d = ((w[1][0] - w[0][0]).powi(2) + (w[1][1] - w[0][1]).powi(2)).sqrt();
            assert!((d - len).abs() < 1e-9);
        }
    }

    #[test]
    fn a_tension_lays_the_line_at_the_projection_that_has_it() {
        let mut lengths = vec![2.0; 3];
        lengths.extend(vec![10.0; 12]);
        lengths.extend(vec![2.0; 13]);
        for h in [6.0, 20.0] {
            let (lo, hi) = laid_range(&lengths, h).unwrap();
            // Across the laid range, the corner and the fully suspended end included: the
            // projection found from the laid curve's a is the one it was laid at.
            for f in [1e-6, 0.01, 0.3, 0.7, 0.99, 1.0] {
                let x = lo + f * (hi - lo);
                let a = lay_elements(&lengths, x, h).unwrap().0.a;
                let found = horizontal_for_parameter(&lengths, h, a).unwrap();
                assert!((found - x).abs() < 1e-9 * 152.0, "h_L = {h}, x_L = {x}: found {found}");
                // At the corner a is nearly 0 and steep in x_L (f = 1e-6, h_L = 6 m: a = 5e-7 m,
                // 6e-6 apart at x_L 1e-12 apart): a is held away from it.
                let again = lay_elements(&lengths, found, h).unwrap().0.a;
                let tolerance = if f < 0.01 { 1e-4 } else { 1e-9 };
                assert!((again - a).abs() <= tolerance * a, "h_L = {h}, x_L = {x} (f = {f}): a {a}, again {again}");
            }
            // Outside: more tension than the fully suspended line has, none, or not a number;
            // the error gives the laid lines' range of a.
            let top = lay_elements(&lengths, hi, h).unwrap().0.a;
            for a in [top * 1.001, 0.0, -1.0, f64::NAN, f64::INFINITY] {
                match horizontal_for_parameter(&lengths, h, a) {
                    Err(CatenaryError::NoLineWithParameter { range: Some((r_lo, r_hi)), .. }) => {
                        assert!(r_lo > 0.0 && r_lo < 1e-2 * r_hi && (r_hi - top).abs() <= 1e-12 * top, "{r_lo} {r_hi}");
                    }
                    other => panic!("h_L = {h}, a = {a}: {other:?}"),
                }
            }
        }
        // No laid line at all: h_L above the cable's length.
        assert!(matches!(
            horizontal_for_parameter(&lengths, 200.0, 10.0),
            Err(CatenaryError::NoLineWithParameter { range: None, .. })
        ));
    }

    #[test]
    fn impossible_geometry_is_an_error() {
        assert!(Catenary::solve(152.0, 152.0, 6.0).is_err());
        assert!(Catenary::solve(152.0, 140.0, 6.0).is_err());
    }
}

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
    /// No curve length makes the chord polygon end at (x_L, h_L).
    #[error("elements cannot be laid to end at (x_L, h_L)")]
    CannotEnd,
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
        Ok(Catenary { length, horizontal, vertical, b, a })
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
/// through (x_L, h_L): `lengths.len() + 1` points, the first (0, 0), the last (x_L, h_L)
/// to round-off. Returns the curve used (its `length` is L' ≥ L_c) and the points.
pub fn lay_elements(
    lengths: &[f64],
    horizontal: f64,
    vertical: f64,
) -> Result<(Catenary, Vec<[f64; 2]>), CatenaryError> {
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
            let (mut lo, mut hi) = (s + len, s + 4.0 * len);
            if chord(hi) < len {
                return Err(CatenaryError::ElementTooLong { length: len });
            }
            for _ in 0..200 {
                let mid = 0.5 * (lo + hi);
                if chord(mid) < len {
                    lo = mid;
                } else {
                    hi = mid;
                }
                if hi - lo <= 1e-14 * hi {
                    break;
                }
            }
            s = 0.5 * (lo + hi);
            points.push(cat.point(s));
        }
        Ok((cat, points, s))
    };
    // Find L' in [L_c, x_L + h_L) with polygon end arc = L'.
    let residual = |l: f64| polygon(l).map(|(_, _, s)| s - l);
    let mut lo = total;
    let mut hi = (total + 0.05 * total).min(horizontal + vertical - 1e-9 * total);
    if residual(lo)? <= 0.0 {
        let (cat, points, _) = polygon(lo)?;
        return Ok((cat, points));
    }
    if residual(hi)? > 0.0 {
        return Err(CatenaryError::CannotEnd);
    }
    for _ in 0..200 {
        let mid = 0.5 * (lo + hi);
        if residual(mid)? > 0.0 {
            lo = mid;
        } else {
            hi = mid;
        }
        if hi - lo <= 1e-15 * hi {
            break;
        }
    }
    let (cat, points, _) = polygon(hi)?;
    Ok((cat, points))
}

#[cfg(test)]
mod tests {
    use super::*;

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
    fn impossible_geometry_is_an_error() {
        assert!(Catenary::solve(152.0, 152.0, 6.0).is_err());
        assert!(Catenary::solve(152.0, 140.0, 6.0).is_err());
    }
}

//! Plane geometry of a rod's circular cross-section, shared by the seabed's elastic
//! foundation (Eq. 41) and the resting heights of the laid chain and cable (Eqs. 41, 42).
//! It depends on nothing else in the crate.

/// Area of the circular segment of depth `delta` (m) cut from a circle of radius `r` (m),
/// m²: A(δ) = r² acos((r − δ)/r) − (r − δ) √(2rδ − δ²), with δ clamped to [0, 2r].
pub fn segment_area(r: f64, delta: f64) -> f64 {
    let d = delta.clamp(0.0, 2.0 * r);
    let c = r - d;
    r * r * (c / r).clamp(-1.0, 1.0).acos() - c * (2.0 * r * d - d * d).max(0.0).sqrt()
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::f64::consts::PI;

    #[test]
    fn segment_area_limits() {
        let r = 0.1;
        assert_eq!(segment_area(r, 0.0), 0.0);
        assert!((segment_area(r, r) - PI * r * r / 2.0).abs() < 1e-15);
        assert!((segment_area(r, 2.0 * r) - PI * r * r).abs() < 1e-15);
        // Shallow segment: A ≈ (4/3) √(2rδ) δ.
        let d = 1e-6;
        assert!((segment_area(r, d) / ((4.0 / 3.0) * (2.0 * r * d).sqrt() * d) - 1.0).abs() < 1e-4);
    }
}

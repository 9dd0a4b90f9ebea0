//! The explicit stability limit of a scene: the largest fixed step RK4 can take on the
//! linearised equations at the initial state.
//!
//! The Jacobian ∂ẏ/∂y of the (q, u) part of the right-hand side ([`crate::dynamics`]) is
//! formed by central differences at t = 0 and its eigenvalues λ found by a real Schur
//! decomposition. RK4 is stable for a mode when |R(hλ)| ≤ 1 with
//! R(z) = 1 + z + z²/2 + z³/6 + z⁴/24; the limit is the smallest such h over all modes
//! (2.83/|λ| for an undamped oscillation, 2.79/|λ| for a purely damped mode). Modes with Re λ > 0 (physically
//! unstable, or round-off around an undamped one) are taken as undamped.
//!
//! The limit belongs to the initial configuration: seabed contacts, tension and the anchor's
//! state change during a run, which is why every step is still checked for energy runaway
//! ([`crate::simulate`]). It names the body whose hinge is stiffest, where the fastest mode
//! lives.

use nalgebra::{Complex, DMatrix};

use crate::dynamics::Dynamics;
use crate::integrate::{OdeSystem, RhsError};

/// Why the stability limit could not be computed.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum StabilityError {
    /// The right-hand side failed at a perturbed state.
    #[error(transparent)]
    Rhs(#[from] RhsError),
    /// A difference quotient of ∂ẏ/∂y is NaN or infinite.
    #[error("the Jacobian at the initial state is not finite")]
    NonFiniteJacobian,
    /// The real Schur decomposition did not converge.
    #[error("the eigenvalues of the Jacobian at the initial state did not converge")]
    NoEigenvalues,
}

/// The fastest mode of a scene at t = 0 and the step RK4 can take on it.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct StabilityLimit {
    /// Largest stable RK4 step, s.
    pub rk4_dt: f64,
    /// The limiting eigenvalue, 1/s.
    pub lambda: Complex<f64>,
    /// The body (1-based, B_k) whose hinge has the largest stiffness ∂β̈_k/∂β_k.
    pub body: usize,
}

/// |R(z)| of the classic RK4 stability function.
fn rk4_amplification(z: Complex<f64>) -> f64 {
    let one = Complex::new(1.0, 0.0);
    (one + z * (one + z * (one / 2.0 + z * (one / 6.0 + z / 24.0)))).norm()
}

/// The largest h with |R(hλ)| ≤ 1 along the ray of λ (Re λ clipped to ≤ 0): the first
/// crossing of the stability boundary, found on a grid of h|λ| and refined by bisection.
pub fn rk4_step_limit(lambda: Complex<f64>) -> f64 {
    let lambda = Complex::new(lambda.re.min(0.0), lambda.im);
    let size = lambda.norm();
    if size == 0.0 {
        return f64::INFINITY;
    }
    let dir = lambda / size;
    // The region reaches |z| ≈ 2.83 at most; scan s = h|λ| up to 3.
    let unstable = |s: f64| rk4_amplification(dir * s) > 1.0 + 1e-12;
    let (mut lo, mut hi) = (0.0, 3.0);
    let n = 300;
    for i in 1..=n {
        let s = 3.0 * i as f64 / n as f64;
        if unstable(s) {
            hi = s;
            break;
        }
        lo = s;
    }
    for _ in 0..50 {
        let mid = 0.5 * (lo + hi);
        if unstable(mid) {
            hi = mid;
        } else {
            lo = mid;
        }
    }
    lo / size
}

/// The [`StabilityLimit`] of `dynamics` at the state `y0` = (q, u, W).
pub fn limit(dynamics: &mut Dynamics, y0: &[f64]) -> Result<StabilityLimit, StabilityError> {
    let n = dynamics.body_count();
    let dim = 2 * n;
    let mut jac = DMatrix::zeros(dim, dim);
    let (mut fp, mut fm) = (vec![0.0; y0.len()], vec![0.0; y0.len()]);
    let mut y = y0.to_vec();
    for j in 0..dim {
        let h = 1e-6 * y0[j].abs().max(1e-2);
        y[j] = y0[j] + h;
        dynamics.rhs(0.0, &y, &mut fp)?;
        y[j] = y0[j] - h;
        dynamics.rhs(0.0, &y, &mut fm)?;
        y[j] = y0[j];
        for i in 0..dim {
            jac[(i, j)] = (fp[i] - fm[i]) / (2.0 * h);
        }
    }
    if jac.iter().any(|v| !v.is_finite()) {
        return Err(StabilityError::NonFiniteJacobian);
    }
    // The hinge whose own angle drives its acceleration hardest.
    let (body, _) =
        (0..n - 1).map(|i| (i + 2, -jac[(n + i, i)])).fold((2, f64::MIN), |b, c| if c.1 > b.1 { c } else { b });
    let schur = nalgebra::linalg::Schur::try_new(jac, 1e-12, 100_000).ok_or(StabilityError::NoEigenvalues)?;
    let mut best = StabilityLimit { rk4_dt: f64::INFINITY, lambda: Complex::new(0.0, 0.0), body };
    for lambda in schur.complex_eigenvalues().iter() {
        let h = rk4_step_limit(*lambda);
        if h < best.rk4_dt {
            best.rk4_dt = h;
            best.lambda = *lambda;
        }
    }
    Ok(best)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn rk4_limits_on_the_axes() {
        // Imaginary axis: 2√2; real axis: 2.785 (the real root of R(z) = −1... |R| = 1).
        assert!((rk4_step_limit(Complex::new(0.0, 1.0)) - 8f64.sqrt()).abs() < 1e-6);
        assert!((rk4_step_limit(Complex::new(-1.0, 0.0)) - 2.785_293_563).abs() < 1e-6);
        assert!((rk4_step_limit(Complex::new(-100.0, 0.0)) - 0.027_852_935_63).abs() < 1e-8);
        // A slightly growing oscillation counts as undamped.
        assert_eq!(rk4_step_limit(Complex::new(1e-9, 1.0)), rk4_step_limit(Complex::new(0.0, 1.0)));
        assert_eq!(rk4_step_limit(Complex::new(0.0, 0.0)), f64::INFINITY);
    }
}

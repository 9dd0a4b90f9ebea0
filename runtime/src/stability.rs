//! The explicit stability limit of a scene: the largest fixed step RK4 can take on the
//! linearised equations at the initial state.
//!
//! The Jacobian ∂ẏ/∂y of the (q, u) part of the right-hand side ([`crate::dynamics`]) is
//! formed by central differences at t = 0 (4N right-hand sides, O(N²)) and its eigenvalues λ
//! found: for a small system (2N ≤ [`DENSE_MAX`]) all of them, by a real Schur decomposition
//! of the whole matrix (O(N³)); for a larger one the outer ones, by Arnoldi's method
//! ([`arnoldi`]) on the Jacobian's products with vectors (O(N²) each, a few hundred of them).
//! RK4 is stable for a mode when |R(hλ)| ≤ 1 with R(z) = 1 + z + z²/2 + z³/6 + z⁴/24; the
//! limit is the smallest such h over all modes (2.83/|λ| for an undamped oscillation,
//! 2.79/|λ| for a purely damped mode, 2.62–2.95/|λ| in between). Modes with Re λ > 0
//! (physically unstable, or round-off around an undamped one) are taken as undamped.
//!
//! The limit is set by the outer eigenvalues, the ones Arnoldi's method finds first: the
//! Krylov space grows until the limit agrees to 1e-10 between two sizes and the limiting Ritz
//! value's residual is below 1e-10 of it, or until it is complete (then its eigenvalues are
//! all the Jacobian's). Both ways agree to 1e-7 on every paper and stress scene and on long
//! fine lines, or within the limiting eigenvalue's own conditioning where that is wider
//! (`tests/stability_limit.rs`).
//!
//! The limit belongs to the initial configuration: seabed contacts, tension and the anchor's
//! state change during a run, which is why every step is still checked for energy runaway
//! ([`crate::simulate`]). It names the body whose hinge is stiffest, where the fastest mode
//! lives.

use nalgebra::{Complex, DMatrix};

use crate::dynamics::Dynamics;
use crate::integrate::{OdeSystem, RhsError};

pub mod arnoldi;

/// The largest 2N for which the limit takes every eigenvalue of the whole Jacobian (a dense
/// real Schur decomposition, O(N³)); above it, Arnoldi's method ([`arnoldi`]).
pub const DENSE_MAX: usize = 400;

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

/// The [`StabilityLimit`] of `dynamics` at the state `y0` = (q, u, W): every eigenvalue of
/// the [`jacobian`] up to 2N = [`DENSE_MAX`], the outer ones by Arnoldi's method above it.
pub fn limit(dynamics: &mut Dynamics, y0: &[f64]) -> Result<StabilityLimit, StabilityError> {
    let jac = jacobian(dynamics, y0)?;
    if jac.nrows() <= DENSE_MAX {
        dense_limit(&jac)
    } else {
        krylov_limit(&jac)
    }
}

/// ∂ẏ/∂y of the (q, u) part at `y0` by central differences, column by column: coordinate j
/// moves by ±1e-6 · max(|y_j|, 1e-2). 4N right-hand sides.
pub fn jacobian(dynamics: &mut Dynamics, y0: &[f64]) -> Result<DMatrix<f64>, StabilityError> {
    let dim = 2 * dynamics.body_count();
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
    Ok(jac)
}

/// The hinge whose own angle drives its acceleration hardest: the body (B_k, k ≥ 2) with the
/// largest −∂β̈_k/∂β_k.
fn stiffest_hinge(jac: &DMatrix<f64>) -> usize {
    let n = jac.nrows() / 2;
    (0..n - 1).map(|i| (i + 2, -jac[(n + i, i)])).fold((2, f64::MIN), |b, c| if c.1 > b.1 { c } else { b }).0
}

/// The smallest RK4 step limit over `eigenvalues`, with its eigenvalue.
fn smallest_limit(eigenvalues: impl IntoIterator<Item = Complex<f64>>) -> (f64, Complex<f64>) {
    eigenvalues.into_iter().fold((f64::INFINITY, Complex::new(0.0, 0.0)), |best, lambda| {
        let h = rk4_step_limit(lambda);
        if h < best.0 {
            (h, lambda)
        } else {
            best
        }
    })
}

/// The limit from every eigenvalue of `jac`, a [`jacobian`] (a dense real Schur
/// decomposition, O(N³)): the oracle of [`krylov_limit`].
pub fn dense_limit(jac: &DMatrix<f64>) -> Result<StabilityLimit, StabilityError> {
    let body = stiffest_hinge(jac);
    let schur = nalgebra::linalg::Schur::try_new(jac.clone(), 1e-12, 100_000).ok_or(StabilityError::NoEigenvalues)?;
    let (rk4_dt, lambda) = smallest_limit(schur.complex_eigenvalues().iter().copied());
    Ok(StabilityLimit { rk4_dt, lambda, body })
}

/// The limit from the outer eigenvalues of `jac`, a [`jacobian`], by Arnoldi's method on its
/// products with vectors (O(N²) each). The Krylov space grows by half from 48 vectors until
/// the limit agrees to 1e-10 between two sizes and the limiting Ritz value's residual is
/// below 1e-10 of it, or until it is complete (then the Ritz values are all the eigenvalues).
pub fn krylov_limit(jac: &DMatrix<f64>) -> Result<StabilityLimit, StabilityError> {
    let body = stiffest_hinge(jac);
    let dim = jac.nrows();
    let mut product = |v: &[f64], out: &mut [f64]| -> Result<(), StabilityError> {
        out.fill(0.0);
        // Column by column (the matrix is stored so): out += x_j J_j.
        for (column, &x) in jac.as_slice().chunks_exact(dim).zip(v) {
            out.iter_mut().zip(column).for_each(|(o, a)| *o += a * x);
        }
        Ok(())
    };
    let mut krylov = arnoldi::Arnoldi::new(dim);
    let mut m = 48.min(dim);
    let mut previous = f64::NAN;
    loop {
        krylov.extend_to(m, &mut product)?;
        let ritz = krylov.ritz_values().ok_or(StabilityError::NoEigenvalues)?;
        let (rk4_dt, lambda) = smallest_limit(ritz);
        let settled = (rk4_dt - previous).abs() <= 1e-10 * rk4_dt && krylov.residual(lambda) <= 1e-10 * lambda.norm();
        if m == dim || settled {
            return Ok(StabilityLimit { rk4_dt, lambda, body });
        }
        previous = rk4_dt;
        m = (m + m / 2).min(dim);
    }
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

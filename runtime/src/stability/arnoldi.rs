//! Arnoldi's method: the outer eigenvalues of an operator known only through its products
//! with vectors (Saad, *Numerical Methods for Large Eigenvalue Problems*, 2nd ed., §6.2).
//!
//! `m` steps build an orthonormal basis V_m = [v_1 … v_m] of the Krylov space
//! span{v_1, A v_1, …, A^{m−1} v_1} and the upper Hessenberg H_m = V_mᵀ A V_m, so that
//! A V_m = V_m H_m + β v_{m+1} e_mᵀ. The eigenvalues θ of H_m (Ritz values) approximate A's
//! outermost eigenvalues first; a Ritz pair (θ, V_m s), ‖s‖ = 1, has the residual
//! ‖A V_m s − θ V_m s‖ = β |s_m|. At m = n the basis is complete and H_n is similar to A.
//!
//! Each new vector is orthogonalised by Gram–Schmidt run twice (enough for orthogonality to
//! working precision); where the Krylov space stops growing (an invariant
//! subspace, β = 0) the basis goes on from a fresh vector orthogonal to it, so H_m stays
//! block upper Hessenberg and its eigenvalues stay A's.

use nalgebra::{Complex, DMatrix, DVector};

/// A growing Arnoldi factorisation of an n × n operator.
pub struct Arnoldi {
    n: usize,
    /// v_1 … v_{m+1}, each of length n (the last is the next direction; absent once m = n).
    basis: Vec<Vec<f64>>,
    /// Column j of H: its entries 0 ..= j+1 (the last is h_{j+1,j}, 0 after a restart).
    columns: Vec<Vec<f64>>,
    /// State of the generator of start vectors (deterministic: the same operator gives the
    /// same factorisation).
    seed: u64,
}

impl Arnoldi {
    /// A factorisation of an operator of size `n` ≥ 1, started from a fixed pseudo-random
    /// unit vector.
    pub fn new(n: usize) -> Self {
        let mut a = Self { n, basis: Vec::new(), columns: Vec::new(), seed: 0x9e37_79b9_7f4a_7c15 };
        let v = a.fresh();
        a.basis.push(v);
        a
    }

    /// Steps taken so far (m).
    pub fn steps(&self) -> usize {
        self.columns.len()
    }

    /// Takes steps until there are `m` (at most n), each applying `apply` (out = A v) once.
    pub fn extend_to<E>(
        &mut self,
        m: usize,
        apply: &mut impl FnMut(&[f64], &mut [f64]) -> Result<(), E>,
    ) -> Result<(), E> {
        let m = m.min(self.n);
        let mut w = vec![0.0; self.n];
        while self.steps() < m {
            let j = self.steps();
            apply(&self.basis[j], &mut w)?;
            let size = norm(&w);
            let mut column = vec![0.0; j + 2];
            orthogonalise(&self.basis, &mut w, &mut column[..=j]);
            let beta = norm(&w);
            let next = if j + 1 == self.n {
                None
            } else if beta > 1e-12 * size && beta > 0.0 {
                column[j + 1] = beta;
                Some(w.iter().map(|x| x / beta).collect())
            } else {
                // An invariant subspace: go on from a fresh direction (h_{j+1,j} = 0).
                Some(self.fresh_orthogonal())
            };
            self.columns.push(column);
            if let Some(v) = next {
                self.basis.push(v);
            }
        }
        Ok(())
    }

    /// H_m, m × m.
    fn hessenberg(&self) -> DMatrix<f64> {
        let m = self.steps();
        DMatrix::from_fn(m, m, |i, j| self.columns[j].get(i).copied().unwrap_or(0.0))
    }

    /// β = h_{m+1,m}: how far A leaves the basis (0 once m = n).
    fn beta(&self) -> f64 {
        match self.columns.last() {
            Some(c) if self.steps() < self.n => c[self.steps()],
            _ => 0.0,
        }
    }

    /// The Ritz values: the eigenvalues of H_m (None if the QR iteration does not converge).
    pub fn ritz_values(&self) -> Option<Vec<Complex<f64>>> {
        let schur = nalgebra::linalg::Schur::try_new(self.hessenberg(), 1e-14, 100_000)?;
        Some(schur.complex_eigenvalues().iter().copied().collect())
    }

    /// The residual ‖A x − θ x‖ of the Ritz pair of `theta` (a Ritz value), x = V_m s with
    /// ‖s‖ = 1: β |s_m|, s found by two steps of inverse iteration on H_m − θ I.
    pub fn residual(&self, theta: Complex<f64>) -> f64 {
        let beta = self.beta();
        if beta == 0.0 {
            return 0.0;
        }
        let m = self.steps();
        // Shifted off θ by a relative 1e-10 so the factorisation is not exactly singular.
        let shift = theta + Complex::new(1e-10 * theta.norm().max(f64::MIN_POSITIVE), 0.0);
        let h = self.hessenberg().map(|x| Complex::new(x, 0.0)) - DMatrix::identity(m, m) * shift;
        let lu = h.lu();
        let mut s = DVector::from_element(m, Complex::new(1.0, 0.0));
        for _ in 0..2 {
            match lu.solve(&s) {
                Some(z) if z.iter().all(|c| c.re.is_finite() && c.im.is_finite()) => {
                    let size = z.norm();
                    if size == 0.0 {
                        return f64::INFINITY;
                    }
                    s = z / Complex::new(size, 0.0);
                }
                _ => return f64::INFINITY,
            }
        }
        beta * s[m - 1].norm()
    }

    /// A pseudo-random vector of unit length (xorshift64*, entries uniform in [−1, 1)).
    fn fresh(&mut self) -> Vec<f64> {
        let mut v: Vec<f64> = (0..self.n)
            .map(|_| {
                self.seed ^= self.seed >> 12;
                self.seed ^= self.seed << 25;
                self.seed ^= self.seed >> 27;
                let bits = self.seed.wrapping_mul(0x2545_f491_4f6c_dd1d) >> 11;
                bits as f64 / (1u64 << 52) as f64 - 1.0
            })
            .collect();
        let size = norm(&v);
        v.iter_mut().for_each(|x| *x /= size);
        v
    }

    /// A fresh unit vector orthogonal to the basis so far.
    fn fresh_orthogonal(&mut self) -> Vec<f64> {
        loop {
            let mut v = self.fresh();
            let mut coefficients = vec![0.0; self.basis.len()];
            orthogonalise(&self.basis, &mut v, &mut coefficients);
            let size = norm(&v);
            if size > 1e-3 {
                v.iter_mut().for_each(|x| *x /= size);
                return v;
            }
        }
    }
}

/// Removes from `w` its components along `basis` (modified Gram–Schmidt, run twice), adding
/// them to `coefficients` (one per basis vector).
fn orthogonalise(basis: &[Vec<f64>], w: &mut [f64], coefficients: &mut [f64]) {
    for _ in 0..2 {
        for (c, v) in coefficients.iter_mut().zip(basis) {
            let dot = dot(v, w);
            *c += dot;
            w.iter_mut().zip(v).for_each(|(x, a)| *x -= dot * a);
        }
    }
}

/// a · b, summed in four interleaved partial sums (a single running sum waits for each
/// addition: four times slower on long vectors).
fn dot(a: &[f64], b: &[f64]) -> f64 {
    let mut sums = [0.0; 4];
    let (a4, b4) = (a.chunks_exact(4), b.chunks_exact(4));
    let tail: f64 = a4.remainder().iter().zip(b4.remainder()).map(|(x, y)| x * y).sum();
    for (x, y) in a4.zip(b4) {
        for k in 0..4 {
            sums[k] += x[k] * y[k];
        }
    }
    (sums[0] + sums[1]) + (sums[2] + sums[3]) + tail
}

fn norm(v: &[f64]) -> f64 {
    dot(v, v).sqrt()
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A dense operator's product.
    fn product(a: &DMatrix<f64>) -> impl FnMut(&[f64], &mut [f64]) -> Result<(), ()> + '_ {
        move |v, out| {
            let y = a * DVector::from_column_slice(v);
            out.copy_from_slice(y.as_slice());
            Ok(())
        }
    }

    fn sorted(mut v: Vec<Complex<f64>>) -> Vec<Complex<f64>> {
        v.sort_by(|a, b| a.re.total_cmp(&b.re).then(a.im.total_cmp(&b.im)));
        v
    }

    #[test]
    fn the_complete_basis_gives_the_operators_eigenvalues() {
        // A non-normal matrix with complex and real eigenvalues.
        let a = DMatrix::from_row_slice(
            4,
            4,
            &[0.0, 1.0, 0.0, 0.0, -4.0, -0.1, 2.0, 0.0, 0.0, 0.0, -3.0, 5.0, 0.0, 0.0, 0.0, -7.0],
        );
        let mut k = Arnoldi::new(4);
        k.extend_to(10, &mut product(&a)).unwrap();
        assert_eq!(k.steps(), 4);
        let got = sorted(k.ritz_values().unwrap());
        let want = sorted(a.complex_eigenvalues().iter().copied().collect());
        for (g, w) in got.iter().zip(&want) {
            assert!((g - w).norm() < 1e-12, "{got:?} against {want:?}");
        }
        for g in &got {
            assert_eq!(k.residual(*g), 0.0);
        }
    }

    #[test]
    fn the_outer_eigenvalue_converges_long_before_the_basis_is_complete() {
        // Diagonal 1, 2, …, 199 and one outer eigenvalue 1000: found in 40 steps, with a
        // small residual; an interior Ritz value has a large one.
        let n = 200;
        let a = DMatrix::from_fn(n, n, |i, j| {
            if i != j {
                0.0
            } else if i == n - 1 {
                1000.0
            } else {
                1.0 + i as f64
            }
        });
        let mut k = Arnoldi::new(n);
        k.extend_to(40, &mut product(&a)).unwrap();
        let ritz = k.ritz_values().unwrap();
        let top = ritz.iter().copied().max_by(|a, b| a.norm().total_cmp(&b.norm())).unwrap();
        assert!((top.re - 1000.0).abs() < 1e-9 && top.im == 0.0, "{top}");
        assert!(k.residual(top) < 1e-6, "{}", k.residual(top));
        let inner = ritz.iter().copied().min_by(|a, b| (a.re - 100.0).abs().total_cmp(&(b.re - 100.0).abs())).unwrap();
        assert!(k.residual(inner) > 1e-3, "{}", k.residual(inner));
    }

    #[test]
    fn an_invariant_subspace_is_left_for_a_fresh_direction() {
        // A start vector cannot reach every eigenvector of a matrix with a repeated
        // eigenvalue: the basis must go on after the breakdown to be complete.
        let a = DMatrix::from_diagonal(&DVector::from_vec(vec![2.0, 2.0, 2.0, -1.0, 5.0]));
        let mut k = Arnoldi::new(5);
        k.extend_to(5, &mut product(&a)).unwrap();
        let got = sorted(k.ritz_values().unwrap());
        let want = [-1.0, 2.0, 2.0, 2.0, 5.0];
        for (g, w) in got.iter().zip(want) {
            assert!((g.re - w).abs() < 1e-12 && g.im.abs() < 1e-12, "{got:?}");
        }
    }
}

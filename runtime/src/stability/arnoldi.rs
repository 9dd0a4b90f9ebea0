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

use nalgebra::{Complex, DMatrix};

/// A Ritz value θ and the residual ‖A x − θ x‖ of its unit Ritz vector x.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct RitzPair {
    /// θ, an eigenvalue of H_m.
    pub value: Complex<f64>,
    /// ‖A x − θ x‖ (in the operator's units; infinite where the eigenvector overflowed).
    pub residual: f64,
}

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
            } else if beta > 1e-12 * size {
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

    /// The Ritz values: the eigenvalues of H_m (a real Schur decomposition; None if the QR
    /// iteration does not converge). What [`Arnoldi::ritz_pairs`] gives without the residuals.
    pub fn ritz_values(&self) -> Option<Vec<Complex<f64>>> {
        let schur = nalgebra::linalg::Schur::try_new(self.hessenberg(), 1e-14, 100_000)?;
        Some(schur.complex_eigenvalues().iter().copied().collect())
    }

    /// The Ritz pairs: each eigenvalue θ of H_m with the residual ‖A x − θ x‖ of its Ritz
    /// vector x = V_m s, ‖s‖ = 1, which is β |s_m| (0 once the basis is complete). From the
    /// real Schur form H_m = Q T Qᵀ (T quasi-triangular: 1 × 1 blocks for real eigenvalues,
    /// 2 × 2 for complex pairs): s = Q z with z the eigenvector of T, by block back
    /// substitution as LAPACK's `trevc` does (a divisor below ε‖T‖ taken as ε‖T‖), so
    /// s_m = (row m of Q) · z / ‖z‖. O(m³) in all; a conjugate's residual is its partner's.
    /// None if the QR iteration does not converge.
    pub fn ritz_pairs(&self) -> Option<Vec<RitzPair>> {
        let m = self.steps();
        let (q, t) = nalgebra::linalg::Schur::try_new(self.hessenberg(), 1e-14, 100_000)?.unpack();
        let beta = self.beta();
        let small = f64::EPSILON * t.norm().max(f64::MIN_POSITIVE);
        // The diagonal blocks: (first row, size).
        let mut blocks = Vec::new();
        let mut i = 0;
        while i < m {
            let size = if i + 1 < m && t[(i + 1, i)] != 0.0 { 2 } else { 1 };
            blocks.push((i, size));
            i += size;
        }
        let mut z = vec![Complex::new(0.0, 0.0); m];
        let mut pairs: Vec<RitzPair> = Vec::with_capacity(m);
        for (b, &(k, size)) in blocks.iter().enumerate() {
            let values = block_eigenvalues(&t, k, size);
            if beta == 0.0 {
                pairs.extend(values.iter().map(|&value| RitzPair { value, residual: 0.0 }));
                continue;
            }
            for (v, &value) in values.iter().enumerate() {
                let residual = match pairs.last() {
                    // The conjugate of a complex pair: the conjugate vector, the same residual.
                    Some(&RitzPair { value: partner, residual }) if v == 1 && partner == value.conj() => residual,
                    _ => self.block_residual(&t, &q, &blocks[..=b], value, small, &mut z),
                };
                pairs.push(RitzPair { value, residual: if residual.is_finite() { residual } else { f64::INFINITY } });
            }
        }
        Some(pairs)
    }

    /// β |s_m| for the eigenvalue `value` of the last of `blocks` (T's diagonal blocks from
    /// the top, as (first row, size)): its eigenvector z of T by back substitution into `z`.
    fn block_residual(
        &self,
        t: &DMatrix<f64>,
        q: &DMatrix<f64>,
        blocks: &[(usize, usize)],
        value: Complex<f64>,
        small: f64,
        z: &mut [Complex<f64>],
    ) -> f64 {
        let zero = Complex::new(0.0, 0.0);
        let real = |x: f64| Complex::new(x, 0.0);
        let ((k, size), above) = blocks.split_last().expect("at least the block itself");
        let (k, end) = (*k, k + size);
        // The block's own null vector: (t_01, θ − t_00) from its first row, or (θ − t_11, t_10)
        // from its second where that one is larger.
        if *size == 1 {
            z[k] = real(1.0);
        } else {
            let first = (real(t[(k, k + 1)]), value - t[(k, k)]);
            let second = (value - t[(k + 1, k + 1)], real(t[(k + 1, k)]));
            let (x, y) =
                if first.0.norm() + first.1.norm() >= second.0.norm() + second.1.norm() { first } else { second };
            z[k] = x;
            z[k + 1] = y;
        }
        // The blocks above, from the bottom up: (T_ii − θ) z_i = −Σ_j T_ij z_j over the rows
        // already found.
        for &(i, rows) in above.iter().rev() {
            let rhs = |r: usize, z: &[Complex<f64>]| -(i + rows..end).fold(zero, |acc, j| acc + z[j] * t[(r, j)]);
            if rows == 1 {
                let mut d = real(t[(i, i)]) - value;
                if d.norm() < small {
                    d = real(small);
                }
                z[i] = rhs(i, z) / d;
            } else {
                // Cramer's rule on the 2 × 2 system.
                let (r0, r1) = (rhs(i, z), rhs(i + 1, z));
                let (a, b) = (real(t[(i, i)]) - value, real(t[(i, i + 1)]));
                let (c, d) = (real(t[(i + 1, i)]), real(t[(i + 1, i + 1)]) - value);
                let mut det = a * d - b * c;
                if det.norm() < small * small {
                    det = real(small * small);
                }
                z[i] = (r0 * d - b * r1) / det;
                z[i + 1] = (a * r1 - c * r0) / det;
            }
        }
        let size_z = z[..end].iter().map(|c| c.norm_sqr()).sum::<f64>().sqrt();
        let last = (0..end).fold(zero, |acc, i| acc + z[i] * q[(self.steps() - 1, i)]);
        self.beta() * last.norm() / size_z
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
        debug_assert!(self.basis.len() < self.n, "no direction is left orthogonal to a complete basis");
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

/// The eigenvalues of the diagonal block of `t` at row `k` of size 1 or 2 (a 2 × 2 block of
/// a real Schur form has a complex pair, the one with Im ≥ 0 first).
fn block_eigenvalues(t: &DMatrix<f64>, k: usize, size: usize) -> Vec<Complex<f64>> {
    if size == 1 {
        return vec![Complex::new(t[(k, k)], 0.0)];
    }
    let (a, b, c, d) = (t[(k, k)], t[(k, k + 1)], t[(k + 1, k)], t[(k + 1, k + 1)]);
    let mean = 0.5 * (a + d);
    let disc = 0.25 * (a - d) * (a - d) + b * c; // < 0 for a complex pair
    let im = (-disc).max(0.0).sqrt();
    vec![Complex::new(mean, im), Complex::new(mean, -im)]
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

    use nalgebra::DVector;

    impl Arnoldi {
        /// The unit Ritz vector V_m s of the Ritz value `theta`, s by inverse iteration on
        /// H_m − θ I (for checking the residuals of `ritz_pairs` in full).
        fn ritz_vector(&self, theta: Complex<f64>) -> DVector<Complex<f64>> {
            let m = self.steps();
            let shift = theta + Complex::new(1e-13 * theta.norm(), 0.0);
            let h = self.hessenberg().map(|x| Complex::new(x, 0.0)) - DMatrix::identity(m, m) * shift;
            let mut s = DVector::from_element(m, Complex::new(1.0, 0.0));
            for _ in 0..3 {
                s = h.clone().lu().solve(&s).unwrap();
                s /= Complex::new(s.norm(), 0.0);
            }
            let v = DMatrix::from_fn(self.n, m, |i, j| Complex::new(self.basis[j][i], 0.0));
            v * s
        }
    }

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
        let pairs = k.ritz_pairs().unwrap();
        assert!(pairs.iter().all(|p| p.residual == 0.0), "{pairs:?}");
        let got = sorted(pairs.iter().map(|p| p.value).collect());
        let want = sorted(a.complex_eigenvalues().iter().copied().collect());
        for (g, w) in got.iter().zip(&want) {
            assert!((g - w).norm() < 1e-12, "{got:?} against {want:?}");
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
        let ritz = k.ritz_pairs().unwrap();
        let top = ritz.iter().copied().max_by(|a, b| a.value.norm().total_cmp(&b.value.norm())).unwrap();
        assert!((top.value.re - 1000.0).abs() < 1e-9 && top.value.im.abs() < 1e-9, "{top:?}");
        assert!(top.residual < 1e-6, "{top:?}");
        let inner = ritz
            .iter()
            .copied()
            .min_by(|a, b| (a.value.re - 100.0).abs().total_cmp(&(b.value.re - 100.0).abs()))
            .unwrap();
        assert!(inner.residual > 1e-3, "{inner:?}");
        // Each residual is what it says: ‖A x − θ x‖ of the Ritz vector, formed here in full.
        for pair in [top, inner] {
            let x = k.ritz_vector(pair.value);
            let ax = a.map(|v| Complex::new(v, 0.0)) * &x;
            let direct = (ax - &x * pair.value).norm();
            assert!((direct - pair.residual).abs() <= 1e-9 + 1e-6 * direct, "{direct} against {pair:?}");
        }
    }

    #[test]
    fn residuals_of_complex_pairs_are_those_of_their_ritz_vectors() {
        // Rotations ±i ω_k, damped by −ω_k/20, and a few real modes, mixed by an orthogonal
        // change of basis: the Schur form has 2 × 2 blocks. Every Ritz pair's residual at
        // m = 30 equals ‖A x − θ x‖ of its Ritz vector formed in full.
        let n = 60;
        let mut d = DMatrix::zeros(n, n);
        for k in 0..25 {
            let w = 1.0 + k as f64;
            let (i, j) = (2 * k, 2 * k + 1);
            d[(i, i)] = -w / 20.0;
            d[(j, j)] = -w / 20.0;
            d[(i, j)] = w;
            d[(j, i)] = -w;
        }
        for k in 50..n {
            d[(k, k)] = -3.0 * (k - 49) as f64;
        }
        let mixed = DMatrix::from_fn(n, n, |i, j| ((i * 31 + j * 17) % 23) as f64 - 11.0);
        let q = mixed.qr().q();
        let a = &q * d * q.transpose();
        let mut k = Arnoldi::new(n);
        k.extend_to(30, &mut product(&a)).unwrap();
        let pairs = k.ritz_pairs().unwrap();
        assert_eq!(pairs.len(), 30);
        assert!(pairs.iter().filter(|p| p.value.im != 0.0).count() >= 10, "{pairs:?}");
        let values = sorted(k.ritz_values().unwrap());
        let mine = sorted(pairs.iter().map(|p| p.value).collect());
        for (x, y) in values.iter().zip(&mine) {
            assert!((x - y).norm() <= 1e-12 * (1.0 + x.norm()), "{x} against {y}");
        }
        let complex = a.map(|v| Complex::new(v, 0.0));
        for pair in &pairs {
            let x = k.ritz_vector(pair.value);
            let direct = (&complex * &x - &x * pair.value).norm();
            assert!((direct - pair.residual).abs() <= 1e-7 * (1.0 + direct), "{direct} against {pair:?}");
        }
    }

    #[test]
    fn an_invariant_subspace_is_left_for_a_fresh_direction() {
        // A start vector cannot reach every eigenvector of a matrix with a repeated
        // eigenvalue: the basis must go on after the breakdown to be complete.
        let a = DMatrix::from_diagonal(&DVector::from_vec(vec![2.0, 2.0, 2.0, -1.0, 5.0]));
        let mut k = Arnoldi::new(5);
        k.extend_to(5, &mut product(&a)).unwrap();
        let got = sorted(k.ritz_pairs().unwrap().iter().map(|p| p.value).collect());
        let want = [-1.0, 2.0, 2.0, 2.0, 5.0];
        for (g, w) in got.iter().zip(want) {
            assert!((g.re - w).abs() < 1e-12 && g.im.abs() < 1e-12, "{got:?}");
        }
    }
}

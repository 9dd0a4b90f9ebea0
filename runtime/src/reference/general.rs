//! Huston's form of Kane's method for an open chain of N rigid bodies, each with six
//! generalised speeds, evaluated numerically and literally (paper, Eqs. 1–26).
//!
//! Indices follow the paper but are stored 0-based: body B_k lives at `k` in arrays that
//! include the inertial frame B_0 at index 0, and generalised speed ẋ_l (l = 1 … 6N, Eq. 8)
//! at `l - 1` in the speed vector. Nothing here knows the chain is planar: the planar
//! restraining system is one use of it ([`super::planar`]).
//!
//! This is the oracle the generated kernels are checked against. It is deliberately slow
//! and close to the equations; keep it that way.

use nalgebra::{DMatrix, DVector, Matrix3, Vector3};

/// The six non-zero permutation symbols e_irm (Eq. 7), as (i, r, m, e_irm), 0-based.
const PERMUTATIONS: [(usize, usize, usize, f64); 6] =
    [(0, 1, 2, 1.0), (1, 2, 0, 1.0), (2, 0, 1, 1.0), (0, 2, 1, -1.0), (2, 1, 0, -1.0), (1, 0, 2, -1.0)];

/// e_irm by Eq. 7, 0-based indices: (i − r)(r − m)(m − i)/2 with 1-based values.
pub fn permutation_symbol(i: usize, r: usize, m: usize) -> f64 {
    let (i, r, m) = (i as i64, r as i64, m as i64);
    ((i - r) * (r - m) * (m - i)) as f64 / 2.0
}

/// The vector with components e_irm a_i b_r (summed over i, r): the form in which the
/// cross product appears in Eqs. 6, 15, 16 and 22.
pub fn e_product(a: &Vector3<f64>, b: &Vector3<f64>) -> Vector3<f64> {
    let mut out = Vector3::zeros();
    for &(i, r, m, e) in &PERMUTATIONS {
        out[m] += e * a[i] * b[r];
    }
    out
}

/// S^(jk) from the Euler parameters ε_k1 … ε_k4 of B_k relative to B_j (Huston 1990; in
/// the planar case, with ε_k1 = ε_k3 = 0, this is Eq. 3). S maps B_k components to B_j
/// components: n_j = S^(jk) n_k.
pub fn transformation_from_euler(e: [f64; 4]) -> Matrix3<f64> {
    let [e1, e2, e3, e4] = e;
    Matrix3::new(
        e1 * e1 - e2 * e2 - e3 * e3 + e4 * e4,
        2.0 * (e1 * e2 - e3 * e4),
        2.0 * (e1 * e3 + e2 * e4),
        2.0 * (e1 * e2 + e3 * e4),
        -e1 * e1 + e2 * e2 - e3 * e3 + e4 * e4,
        2.0 * (e2 * e3 - e1 * e4),
        2.0 * (e1 * e3 - e2 * e4),
        2.0 * (e2 * e3 + e1 * e4),
        -e1 * e1 - e2 * e2 + e3 * e3 + e4 * e4,
    )
}

/// The constant description of the chain, B_1 … B_N (arrays of length N).
pub struct ChainData {
    /// m_k, kg.
    pub mass: Vec<f64>,
    /// I^C_k, central inertia dyadic in B_k axes (Eq. 18), kg·m².
    pub inertia: Vec<Matrix3<f64>>,
    /// r_k: centroid C_k from o_k in B_k axes, m.
    pub r: Vec<Vector3<f64>>,
    /// q_k: joint Q_k in B_{k-1} axes (q_1 in the inertial frame), m.
    pub q: Vec<Vector3<f64>>,
    /// Added translational inertia of B_k in B_k axes (Eq. 46), kg: the water's reaction
    /// −A a_k to the body's acceleration. Zero for bodies in air.
    pub added_mass: Vec<Matrix3<f64>>,
    /// Added rotational inertia about C_k in B_k axes (Eq. 46), kg·m².
    pub added_inertia: Vec<Matrix3<f64>>,
}

/// The configuration and speeds at one instant.
pub struct GeneralState<'a> {
    /// Euler parameters of B_k relative to B_{k-1} (Eq. 2), N entries.
    pub euler: &'a [[f64; 4]],
    /// s_k: translation of B_k relative to B_{k-1}, in B_{k-1} axes, m. N entries.
    pub s: &'a [Vector3<f64>],
    /// ẋ_l, l = 1 … 6N (Eq. 8): rad/s for l ≤ 3N, m/s above.
    pub x_dot: &'a [f64],
}

/// Per-body applied force F_k (N) and moment T_k (N·m), inertial components (Eq. 23).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Wrench {
    /// F_k at the centroid C_k, N.
    pub force: Vector3<f64>,
    /// T_k, N·m.
    pub moment: Vector3<f64>,
}

/// All kinematic arrays of Eqs. 4–16 for a chosen list of generalised speeds.
///
/// Speeds outside `speeds` are taken as zero (the "constant generalised speeds" of the
/// reduction to Eq. 27); a speed that is non-zero must therefore be listed.
pub struct Partials {
    n: usize,
    /// The speeds l (1-based) the arrays are built for.
    speeds: Vec<usize>,
    /// S^(0k), k = 0 … N (Eq. 4).
    pub s0: Vec<Matrix3<f64>>,
    /// Ṡ^(0k), k = 0 … N (Eq. 6).
    pub s0_dot: Vec<Matrix3<f64>>,
    /// ω^(0k), k = 0 … N (Eq. 9).
    pub omega: Vec<Vector3<f64>>,
    /// ω_klm and ω̇_klm (Eqs. 10, 12): `[k][i]` for speed `speeds[i]`, k = 0 … N.
    w: Vec<Vec<Vector3<f64>>>,
    w_dot: Vec<Vec<Vector3<f64>>>,
    /// v_klm and v̇_klm (Eqs. 15, 16): `[k][i]`, k = 0 … N (row 0 unused).
    v: Vec<Vec<Vector3<f64>>>,
    v_dot: Vec<Vec<Vector3<f64>>>,
    /// p_k (Eq. 13), k = 0 … N.
    pub position: Vec<Vector3<f64>>,
}

impl Partials {
    // Long by design: the oracle reads as Eqs. 2–16 in order, one block per equation.
    /// Builds the arrays for `speeds` (1-based l, each ≤ 6N), Eqs. 2–16.
    pub fn new(chain: &ChainData, state: &GeneralState<'_>, speeds: &[usize]) -> Self {
        let n = chain.mass.len();
        assert_eq!(state.x_dot.len(), 6 * n, "ẋ must hold 6N speeds");
        // Partial velocities of translational speeds reuse partial angular velocities
        // (Eq. 15, third case), so those rotational speeds are built too.
        let mut all: Vec<usize> = speeds.to_vec();
        for &l in speeds {
            assert!((1..=6 * n).contains(&l), "speed index {l} outside 1..=6N");
            if l > 3 * n && !all.contains(&(l - 3 * n)) {
                all.push(l - 3 * n);
            }
        }
        let ns = all.len();

        // Eqs. 2–4: S^(0k) = S^(01) S^(12) … S^(k-1,k).
        let mut s0 = vec![Matrix3::identity(); n + 1];
        for k in 1..=n {
            s0[k] = s0[k - 1] * transformation_from_euler(state.euler[k - 1]);
        }

        // Eq. 10: ω_klm, by the recursion over k.
        let zero = Vector3::zeros();
        let mut w = vec![vec![zero; ns]; n + 1];
        for k in 1..=n {
            for (i, &l) in all.iter().enumerate() {
                w[k][i] = if l <= 3 * (k - 1) {
                    w[k - 1][i]
                } else if l <= 3 * k {
                    let p = l - (3 * k - 3) - 1;
                    // k = 1: δ_ml, since S^(00) is the identity.
                    s0[k - 1].column(p).into_owned()
                } else {
                    zero
                };
            }
        }

        // Eq. 9: ω^(0k) = ω_klm ẋ_l n_0m.
        let mut omega = vec![zero; n + 1];
        for k in 1..=n {
            for (i, &l) in all.iter().enumerate() {
                omega[k] += w[k][i] * state.x_dot[l - 1];
            }
        }

        // Eq. 6: Ṡ_in = −e_irm ω_m S_rn.
        let mut s0_dot = vec![Matrix3::zeros(); n + 1];
        for k in 1..=n {
            for col in 0..3 {
                for &(i, r, m, e) in &PERMUTATIONS {
                    s0_dot[k][(i, col)] -= e * omega[k][m] * s0[k][(r, col)];
                }
            }
        }

        // Eq. 12: ω̇_klm.
        let mut w_dot = vec![vec![zero; ns]; n + 1];
        for k in 2..=n {
            for (i, &l) in all.iter().enumerate() {
                w_dot[k][i] = if l <= 3 * (k - 1) {
                    w_dot[k - 1][i]
                } else if l <= 3 * k {
                    s0_dot[k - 1].column(l - (3 * k - 3) - 1).into_owned()
                } else {
                    zero
                };
            }
        }

        // The joint-to-joint vectors of Eqs. 13, 15 and 16: S^(0w)(q_v + s_v), its time
        // derivative Ṡ^(0w)(q_v + s_v) + S^(0w) ṡ_v (v = w + 1), and S^(0k) r_k, Ṡ^(0k) r_k.
        // ṡ_v is read from the translational speeds: ṡ_vn = ẋ_{3(N+v-1)+n}.
        let s_dot: Vec<Vector3<f64>> = (1..=n)
            .map(|v| {
                let base = 3 * (n + v - 1);
                Vector3::new(state.x_dot[base], state.x_dot[base + 1], state.x_dot[base + 2])
            })
            .collect();
        let mut link = vec![zero; n + 1];
        let mut link_dot = vec![zero; n + 1];
        for wi in 0..n {
            let qs = chain.q[wi] + state.s[wi];
            link[wi] = s0[wi] * qs;
            link_dot[wi] = s0_dot[wi] * qs + s0[wi] * s_dot[wi];
        }
        let arm: Vec<Vector3<f64>> = (0..=n).map(|k| if k == 0 { zero } else { s0[k] * chain.r[k - 1] }).collect();
        let arm_dot: Vec<Vector3<f64>> =
            (0..=n).map(|k| if k == 0 { zero } else { s0_dot[k] * chain.r[k - 1] }).collect();

        // Eq. 13: p_k = S^(0k) r_k + Σ_{w=0}^{k-1} S^(0w)(q_v + s_v).
        let mut position = vec![zero; n + 1];
        for k in 1..=n {
            let mut p = arm[k];
            for link_w in link.iter().take(k) {
                p += link_w;
            }
            position[k] = p;
        }

        // Eqs. 15 and 16. The w = 0 terms vanish because ω_0lm = 0 (B_0 does not rotate).
        let index_of = |l: usize| all.iter().position(|&x| x == l).expect("rotational partner built above");
        let mut v = vec![vec![zero; ns]; n + 1];
        let mut v_dot = vec![vec![zero; ns]; n + 1];
        for k in 1..=n {
            for (i, &l) in all.iter().enumerate() {
                if l <= 3 * k {
                    let mut vk = e_product(&w[k][i], &arm[k]);
                    let mut vk_dot = e_product(&w_dot[k][i], &arm[k]) + e_product(&w[k][i], &arm_dot[k]);
                    for wi in 1..k {
                        vk += e_product(&w[wi][i], &link[wi]);
                        vk_dot += e_product(&w_dot[wi][i], &link[wi]) + e_product(&w[wi][i], &link_dot[wi]);
                    }
                    v[k][i] = vk;
                    v_dot[k][i] = vk_dot;
                } else if l > 3 * n {
                    let j = index_of(l - 3 * n);
                    v[k][i] = w[k][j];
                    v_dot[k][i] = w_dot[k][j];
                }
                // 3k < l ≤ 3N: zero (Eq. 15, second case).
            }
        }
        let mut out = Partials { n, speeds: all, s0, s0_dot, omega, w, w_dot, v, v_dot, position };
        out.speeds.truncate(speeds.len());
        out
    }

    /// v^(0k) = v_klm ẋ_l n_0m (Eq. 14), for the listed speeds.
    pub fn velocity(&self, k: usize, x_dot: &[f64]) -> Vector3<f64> {
        self.speeds.iter().enumerate().map(|(i, &l)| self.v[k][i] * x_dot[l - 1]).sum()
    }

    /// a_k and α_k by Eq. 17, given the speeds ẋ and their rates ẍ (both 6N long).
    pub fn acceleration(&self, k: usize, x_dot: &[f64], x_ddot: &[f64]) -> (Vector3<f64>, Vector3<f64>) {
        let mut a = Vector3::zeros();
        let mut alpha = Vector3::zeros();
        for (i, &l) in self.speeds.iter().enumerate() {
            a += self.v[k][i] * x_ddot[l - 1] + self.v_dot[k][i] * x_dot[l - 1];
            alpha += self.w[k][i] * x_ddot[l - 1] + self.w_dot[k][i] * x_dot[l - 1];
        }
        (a, alpha)
    }

    /// I_k = S^(0k) I^C_k S^(0k)ᵀ, the central inertia in inertial components (Eq. 19).
    ///
    /// The paper prints Sᵀ I^C S; with S^(0k) mapping B_k components to inertial ones
    /// (n_0 = S n_k), the similarity is S I^C Sᵀ. For rotation about y alone both give the
    /// same I_22, which is all the planar model uses.
    pub fn inertia(&self, chain: &ChainData, k: usize) -> Matrix3<f64> {
        self.s0[k] * chain.inertia[k - 1] * self.s0[k].transpose()
    }

    /// Translational inertia m_k 1 + A_k and rotational inertia I_k + J_k in inertial
    /// components, with the added inertias of Eq. 46 rotated like Eq. 19.
    fn effective_inertia(&self, chain: &ChainData, k: usize) -> (Matrix3<f64>, Matrix3<f64>) {
        let s = &self.s0[k];
        let translational = Matrix3::identity() * chain.mass[k - 1] + s * chain.added_mass[k - 1] * s.transpose();
        let rotational = s * (chain.inertia[k - 1] + chain.added_inertia[k - 1]) * s.transpose();
        (translational, rotational)
    }

    /// The reduced Kane equations a_lp ẍ_p = f_l (Eqs. 22–27) over the listed speeds, with
    /// the per-body applied wrenches projected by Eq. 23.
    ///
    /// The added-mass force and moment of Eq. 46 are −A_k a_k and −J_k α_k with a_k, α_k
    /// from Eq. 17; they are linear in ẍ, so they join the inertia terms: m_k becomes
    /// m_k 1 + A_k and I_k becomes I_k + J_k in Eqs. 22, 25 and 26.
    pub fn kane_equations(
        &self,
        chain: &ChainData,
        x_dot: &[f64],
        wrenches: &[Wrench],
    ) -> (DMatrix<f64>, DVector<f64>) {
        let ns = self.speeds.len();
        let mut a = DMatrix::zeros(ns, ns);
        let mut f = DVector::zeros(ns);
        for k in 1..=self.n {
            let (m, inertia) = self.effective_inertia(chain, k);
            // The velocity-product parts of F*_k and T*_k (Eq. 22): v̇_kpm ẋ_p, ω̇_kpm ẋ_p
            // and e_rsm ω_kpr ω_kqn I_ksn ẋ_p ẋ_q.
            let mut a_vel = Vector3::zeros();
            let mut alpha_vel = Vector3::zeros();
            for (i, &l) in self.speeds.iter().enumerate() {
                a_vel += self.v_dot[k][i] * x_dot[l - 1];
                alpha_vel += self.w_dot[k][i] * x_dot[l - 1];
            }
            let gyro = e_product(&self.omega[k], &(inertia * self.omega[k]));
            let wrench = &wrenches[k - 1];
            for i in 0..ns {
                let (vl, wl) = (&self.v[k][i], &self.w[k][i]);
                // Eq. 26: a_lp = m_k v_klm v_kpm + I_kmn ω_klm ω_kpn.
                for j in 0..ns {
                    a[(i, j)] += vl.dot(&(m * self.v[k][j])) + wl.dot(&(inertia * self.w[k][j]));
                }
                // Eq. 23 (F_l) and Eq. 25 (f_l).
                f[i] += vl.dot(&wrench.force) + wl.dot(&wrench.moment)
                    - (vl.dot(&(m * a_vel)) + wl.dot(&(inertia * alpha_vel)) + wl.dot(&gyro));
            }
        }
        (a, f)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn permutation_table_matches_eq_7() {
        let mut count = 0;
        for i in 0..3 {
            for r in 0..3 {
                for m in 0..3 {
                    let e = permutation_symbol(i + 1, r + 1, m + 1);
                    let table = PERMUTATIONS.iter().find(|p| (p.0, p.1, p.2) == (i, r, m)).map_or(0.0, |p| p.3);
                    assert_eq!(e, table, "e_{}{}{}", i + 1, r + 1, m + 1);
                    count += (e != 0.0) as usize;
                }
            }
        }
        assert_eq!(count, 6);
    }

    #[test]
    fn e_product_is_the_cross_product() {
        let a = Vector3::new(0.3, -1.2, 2.0);
        let b = Vector3::new(-0.7, 0.4, 1.1);
        assert!((e_product(&a, &b) - a.cross(&b)).norm() < 1e-15);
    }

    #[test]
    fn euler_matrix_is_eq_3_for_rotation_about_y() {
        let beta: f64 = 0.7;
        let s = transformation_from_euler([0.0, (beta / 2.0).sin(), 0.0, (beta / 2.0).cos()]);
        let expected = Matrix3::new(beta.cos(), 0.0, beta.sin(), 0.0, 1.0, 0.0, -beta.sin(), 0.0, beta.cos());
        assert!((s - expected).norm() < 1e-15);
    }
}

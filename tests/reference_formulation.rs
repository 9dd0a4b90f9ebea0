//! The reference formulation (Eqs. 1–27) against an independent planar Lagrangian
//! computation, and its structural properties.

mod common;

use common::*;
use kanestop_runtime::chain::Chain;
use kanestop_runtime::kernel::{Assembly, BodyState, Kernel, Load, LoadModel};
use kanestop_runtime::reference::ReferenceKernel;
use nalgebra::{DMatrix, DVector};
use rand::Rng;

/// Fixed loads per body.
struct FixedLoads(Vec<Load>);
impl LoadModel for FixedLoads {
    fn loads(&mut self, _bodies: &[BodyState], loads: &mut [Load]) {
        loads.copy_from_slice(&self.0);
    }

    fn fused(&mut self, _power: &[f64]) {
        unreachable!("these loads are never offered to a kernel for fusing");
    }
}

/// R(θ) v: body (x, z) components to inertial, for a rotation θ about y.
fn rot(theta: f64, v: [f64; 2]) -> [f64; 2] {
    let (s, c) = theta.sin_cos();
    [v[0] * c + v[1] * s, -v[0] * s + v[1] * c]
}

/// M and f by the Jacobian form of Lagrange's equations, written directly for the planar
/// chain with absolute angles θ_k = β_2 + … + β_k:
/// M = Σ m J_kᵀJ_k + I_k G_kᵀG_k, f = Σ J_kᵀ(F_k − m_k J̇_k u) + G_kᵀ T_k.
fn lagrangian(chain: &Chain, q: &[f64], u: &[f64], loads: &[Load]) -> (DMatrix<f64>, DVector<f64>) {
    let n = chain.len();
    let mut theta = vec![0.0; n];
    let mut rate = vec![0.0; n];
    for k in 1..n {
        theta[k] = theta[k - 1] + q[k - 1];
        rate[k] = rate[k - 1] + u[k - 1];
    }
    let mut m = DMatrix::zeros(n, n);
    let mut f = DVector::zeros(n);
    for k in 0..n {
        let body = &chain.bodies[k];
        // Jacobian of the centroid: columns 0..n-1 are β_2..β_N, column n-1 is s.
        let mut jac = DMatrix::<f64>::zeros(2, n);
        let mut convective = [0.0, 0.0];
        // Terms from the joint vectors q_{j+1} in bodies j = 0..k-1 and from r_k.
        let mut arms: Vec<(usize, [f64; 2])> = (0..k).map(|j| (j, chain.bodies[j + 1].joint)).collect();
        arms.push((k, body.centroid));
        for (j, v) in arms {
            let w = rot(theta[j], v);
            // d(R v)/dθ = (w_z, −w_x) in inertial components.
            let dw = [w[1], -w[0]];
            for i in 1..=j {
                jac[(0, i - 1)] += dw[0];
                jac[(1, i - 1)] += dw[1];
            }
            convective[0] -= rate[j] * rate[j] * w[0];
            convective[1] -= rate[j] * rate[j] * w[1];
        }
        jac[(0, n - 1)] = 1.0;
        let mut grot = DVector::<f64>::zeros(n);
        for i in 1..=k {
            grot[i - 1] = 1.0;
        }
        let i_yy = body.inertia[1] + body.added_inertia;
        // Translational inertia: m 1 + m_a n nᵀ, n = the body's z axis in inertial components.
        let normal = rot(theta[k], [0.0, 1.0]);
        let n_vec = nalgebra::Vector2::new(normal[0], normal[1]);
        let mass = nalgebra::Matrix2::identity() * body.mass + body.added_mass * n_vec * n_vec.transpose();
        m += jac.transpose() * mass * &jac + i_yy * &grot * grot.transpose();
        let l = loads[k];
        let inertial = mass * nalgebra::Vector2::new(convective[0], convective[1]);
        let force = DVector::from_vec(vec![l.fx - inertial[0], l.fz - inertial[1]]);
        f += jac.transpose() * force + &grot * l.my;
    }
    (m, f)
}

#[test]
fn reference_matches_independent_lagrangian_form() {
    let mut rng = rng(7);
    for n in 3..=8 {
        for trial in 0..20 {
            // Half the chains carry added mass (submerged rods, Eq. 46).
            let chain = if trial % 2 == 0 { random_chain(n, &mut rng) } else { random_wet_chain(n, &mut rng) };
            let (q, u) = random_state(n, &mut rng);
            let loads: Vec<Load> = (0..n)
                .map(|_| Load {
                    fx: rng.gen_range(-1e4..1e4),
                    fz: rng.gen_range(-1e5..1e4),
                    my: rng.gen_range(-1e3..1e3),
                })
                .collect();
            let mut kernel = ReferenceKernel::new(&chain);
            let mut asm = Assembly::new(n);
            kernel.assemble(&q, &u, &mut FixedLoads(loads.clone()), &mut asm);
            let (m, f) = lagrangian(&chain, &q, &u, &loads);
            let m_scale = m.amax();
            let f_scale = f.amax();
            for i in 0..n {
                for j in 0..n {
                    let d = (asm.mass[(i, j)] - m[(i, j)]).abs();
                    assert!(d <= 1e-12 * m_scale, "N={n} M[{i},{j}]: {} vs {}", asm.mass[(i, j)], m[(i, j)]);
                }
                let d = (asm.rhs[i] - f[i]).abs();
                assert!(d <= 1e-10 * f_scale, "N={n} f[{i}]: {} vs {} (scale {f_scale})", asm.rhs[i], f[i]);
            }
            // qdd from the reference, checked by the residual of the independent system.
            let qdd = asm.mass.clone().cholesky().unwrap().solve(&asm.rhs);
            let residual = (&m * &qdd - &f).norm() / f.norm();
            assert!(residual < 1e-10, "N={n}: residual {residual}");
        }
    }
}

#[test]
fn body_states_match_direct_kinematics() {
    let mut rng = rng(11);
    let n = 6;
    let chain = random_chain(n, &mut rng);
    let (q, u) = random_state(n, &mut rng);
    let mut kernel = ReferenceKernel::new(&chain);
    let mut bodies = vec![BodyState::default(); n];
    kernel.kinematics(&q, &u, &mut bodies);
    // Centroid positions by direct summation and velocities by central differences.
    let positions = |q: &[f64]| -> Vec<[f64; 2]> {
        let mut theta = 0.0;
        let mut joint = [chain.bodies[0].joint[0] + q[n - 1], chain.bodies[0].joint[1]];
        let mut out = Vec::new();
        for k in 0..n {
            if k > 0 {
                let prev_theta = theta;
                theta += q[k - 1];
                let d = rot(prev_theta, chain.bodies[k].joint);
                joint = [joint[0] + d[0], joint[1] + d[1]];
            }
            let c = rot(theta, chain.bodies[k].centroid);
            out.push([joint[0] + c[0], joint[1] + c[1]]);
        }
        out
    };
    let p = positions(&q);
    let h = 1e-6;
    let qp: Vec<f64> = q.iter().zip(&u).map(|(a, b)| a + h * b).collect();
    let qm: Vec<f64> = q.iter().zip(&u).map(|(a, b)| a - h * b).collect();
    let (pp, pm) = (positions(&qp), positions(&qm));
    let mut theta = 0.0;
    for k in 0..n {
        if k > 0 {
            theta += q[k - 1];
        }
        let b = bodies[k];
        assert!((b.x - p[k][0]).abs() < 1e-9 && (b.z - p[k][1]).abs() < 1e-9, "position of B_{}", k + 1);
        assert!((b.theta - theta).abs() < 1e-12);
        let v = [(pp[k][0] - pm[k][0]) / (2.0 * h), (pp[k][1] - pm[k][1]) / (2.0 * h)];
        assert!((b.vx - v[0]).abs() < 1e-6 && (b.vz - v[1]).abs() < 1e-6, "velocity of B_{}", k + 1);
    }
}

#[test]
fn mass_matrix_is_symmetric_positive_definite() {
    let mut rng = rng(3);
    for n in 3..=50 {
        let chain = random_chain(n, &mut rng);
        let (q, u) = random_state(n, &mut rng);
        let mut kernel = ReferenceKernel::new(&chain);
        let mut asm = Assembly::new(n);
        kernel.assemble(&q, &u, &mut FixedLoads(vec![Load::default(); n]), &mut asm);
        let m = &asm.mass;
        let asym = (m - m.transpose()).amax() / m.amax();
        assert!(asym < 1e-14, "N={n}: asymmetry {asym}");
        let eig = nalgebra::SymmetricEigen::new(m.clone()).eigenvalues;
        assert!(eig.min() > 0.0, "N={n}: smallest eigenvalue {}", eig.min());
        assert!(m.clone().cholesky().is_some(), "N={n}: Cholesky failed");
    }
}

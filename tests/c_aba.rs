//! The C comparator of `benches/kernels.rs` (a hand-written planar articulated-body
//! algorithm, `benches/c-aba`) solves the problem the generated right-hand side solves: under
//! weight alone, anchor free, its generalised accelerations are those of `Dynamics` on the
//! generated kernel (unrolled where built, and rolled), and their backward error in the
//! reference formulation's system (Eqs. 1–27) is at rounding level, on random states of
//! paper-like chains. Without this the benchmark's ratio would compare different work.

mod common;

use kanestop_c_aba::{Aba, Body};
use kanestop_chain::BodyKind;
use kanestop_runtime::chain::{box_inertia, Body as ChainBody, Chain, Shape};
use kanestop_runtime::dynamics::Dynamics;
use kanestop_runtime::forces::Forces;
use kanestop_runtime::generated::{Form, GeneratedKernel};
use kanestop_runtime::kernel::{AnchorDof, Assembly, Kernel};
use kanestop_runtime::reference::ReferenceKernel;
use rand::{Rng, SeedableRng};

use common::{backward_error, G};

/// The two O(N) recursions (the C articulated-body algorithm, the generated Kane form) round
/// differently; this is about 100 times what they differ by (at most 5e-10 of the largest q̈
/// on these chains, whose 500 t ship and 14 kg rods make the system ill-conditioned).
const BETWEEN_RECURSIONS: f64 = 5e-8;

/// The normwise backward error in the reference system (`common::backward_error`), as
/// `tests/fused_loads.rs` holds the generated right-hand side to.
const BACKWARD: f64 = 1e-12;

/// `benches/kernels.rs`'s chain: a 5 t anchor, 1–10 m rods of 14–140 kg, a 500 t ship.
fn chain(n: usize) -> Chain {
    let mut bodies = vec![ChainBody {
        kind: BodyKind::Anchor,
        mass: 5000.0,
        inertia: box_inertia(5000.0, 2.0, 4.0, 2.1, 0.0),
        centroid: [1.0, 1.05],
        joint: [-300.0, -30.0],
        shape: Shape::Box { length: 2.0, width: 4.0, height: 2.1 },
        added_mass: 0.0,
        added_inertia: 0.0,
    }];
    let mut joint = [2.0, 0.08];
    for i in 0..n - 2 {
        let length = [1.0, 2.0, 10.0][i % 3];
        bodies.push(ChainBody::rod(BodyKind::ChainLink, length, 0.07, 14.0 + 10.0 * (i % 5) as f64, joint));
        joint = [length, 0.0];
    }
    let mass = 5.0e5;
    bodies.push(ChainBody {
        kind: BodyKind::Ship,
        mass,
        inertia: box_inertia(mass, 50.0, 10.0, 5.0, 1.5),
        centroid: [-25.0, -1.0],
        joint,
        shape: Shape::Box { length: 50.0, width: 10.0, height: 5.0 },
        added_mass: 0.0,
        added_inertia: 0.0,
    });
    Chain { bodies }
}

/// The chain as the C algorithm reads it (I_yy about the centroid, Eq. 18).
fn c_bodies(chain: &Chain) -> Vec<Body> {
    chain
        .bodies
        .iter()
        .map(|b| Body { mass: b.mass, inertia: b.inertia[1], centroid: b.centroid, joint: b.joint })
        .collect()
}

/// Generalised accelerations through `Dynamics` (weight alone fused where the kernel can).
fn dynamics_qdd(kernel: Box<dyn Kernel>, chain: &Chain, q: &[f64], u: &[f64]) -> Vec<f64> {
    let mut dynamics = Dynamics::new(kernel, Forces::gravity_only(chain, G), AnchorDof::Free);
    let mut qdd = vec![0.0; chain.len()];
    dynamics.accelerations(q, u, &mut qdd).expect("a smooth state solves");
    qdd
}

/// Largest entrywise difference, relative to the larger vector's largest entry.
fn relative_difference(a: &[f64], b: &[f64]) -> f64 {
    let scale = a.iter().chain(b).fold(0.0f64, |m, x| m.max(x.abs()));
    a.iter().zip(b).fold(0.0f64, |m, (x, y)| m.max((x - y).abs())) / scale
}

#[test]
fn the_c_aba_solves_what_the_generated_kernels_solve() {
    let mut rng = rand::rngs::StdRng::seed_from_u64(14);
    for n in [3, 5, 12, 46, 75] {
        let chain = chain(n);
        let mut aba = Aba::new(c_bodies(&chain), G);
        let mut worst = 0.0f64;
        for sample in 0..40 {
            let q: Vec<f64> = (0..n).map(|_| rng.gen_range(-0.6..0.6)).collect();
            let u: Vec<f64> = (0..n).map(|_| rng.gen_range(-0.4..0.4)).collect();
            let mut c = vec![0.0; n];
            aba.accelerations(&q, &u, &mut c);
            assert!(c.iter().all(|x| x.is_finite()), "N = {n}: the C algorithm gave {c:?}");
            let mut kernels: Vec<(&str, Box<dyn Kernel>)> =
                vec![("rolled", Box::new(GeneratedKernel::with_form(&chain, Form::Rolled).unwrap()))];
            if let Ok(k) = GeneratedKernel::with_form(&chain, Form::Unrolled) {
                kernels.push(("unrolled", Box::new(k)));
            }
            for (name, kernel) in kernels {
                let d = relative_difference(&c, &dynamics_qdd(kernel, &chain, &q, &u));
                assert!(d < BETWEEN_RECURSIONS, "N = {n}, {name}: the C algorithm differs by {d:e} of the largest q̈");
                worst = worst.max(d);
            }
            if sample % 8 == 0 {
                let mut asm = Assembly::new(n);
                let mut forces = Forces::gravity_only(&chain, G);
                ReferenceKernel::new(&chain).assemble(&q, &u, &mut forces, &mut asm);
                let r = backward_error(&asm, n, 0.0, &c);
                assert!(r < BACKWARD, "N = {n}: backward error {r:e} of the C result in the reference system");
            }
        }
        // Not a tautology: the accelerations do depend on the state, and on the bodies.
        assert!(worst > 0.0 || n == 3, "N = {n}: bit-for-bit equal, suspicious for two formulations");
    }
}

#[test]
fn a_wrong_body_changes_the_c_result() {
    // The test above can fail: a chain off by one body's mass is caught at its tolerance.
    let chain = chain(12);
    let mut bodies = c_bodies(&chain);
    bodies[5].mass *= 1.001;
    let (q, u) = (vec![0.3; 12], vec![0.1; 12]);
    let mut c = vec![0.0; 12];
    Aba::new(bodies, G).accelerations(&q, &u, &mut c);
    let g = dynamics_qdd(Box::new(GeneratedKernel::with_form(&chain, Form::Rolled).unwrap()), &chain, &q, &u);
    assert!(relative_difference(&c, &g) > 1e-6);
}

//! Shared helpers for the integration tests: small chains built directly, without scenes.
#![allow(dead_code)]

use kanestop_chain::BodyKind;
use kanestop_runtime::chain::{box_inertia, Body, Chain, Shape};
use kanestop_runtime::dynamics::{Dynamics, WORK_COUNT};
use kanestop_runtime::forces::Forces;
use kanestop_runtime::generated::GeneratedKernel;
use kanestop_runtime::integrate::{Integrator, Rk4};
use kanestop_runtime::kernel::{
    AnchorDof, AnchorReaction, Assembly, BodyAcceleration, BodyState, Kernel, LoadModel, RhsError,
};
use kanestop_runtime::reference::ReferenceKernel;
use rand::rngs::StdRng;
use rand::{Rng, SeedableRng};

pub const G: f64 = 9.81;

/// An anchor box of mass `mass` with its origin at `origin` (inertial).
pub fn anchor(mass: f64, origin: [f64; 2]) -> Body {
    Body {
        kind: BodyKind::Anchor,
        mass,
        inertia: box_inertia(mass, 2.0, 4.0, 2.1, 0.0),
        centroid: [1.0, 1.05],
        joint: origin,
        shape: Shape::Box { length: 2.0, width: 4.0, height: 2.1 },
        added_mass: 0.0,
        added_inertia: 0.0,
    }
}

/// Anchor + `rods` (length, mass per metre), the first hinged on the anchor's face.
pub fn rod_chain(anchor_mass: f64, rods: &[(f64, f64)]) -> Chain {
    let mut bodies = vec![anchor(anchor_mass, [0.0, 0.0])];
    let mut joint = [2.0, 0.5];
    for &(len, mpl) in rods {
        bodies.push(Body::rod(BodyKind::ChainLink, len, 0.05, mpl, joint));
        joint = [len, 0.0];
    }
    Chain { bodies }
}

/// As [`random_chain`], with random added mass and added inertia on the rods (submerged).
pub fn random_wet_chain(n: usize, rng: &mut StdRng) -> Chain {
    let mut chain = random_chain(n, rng);
    for b in chain.bodies.iter_mut().filter(|b| b.kind.is_rod_like()) {
        b.added_mass = rng.gen_range(0.0..2.0) * b.mass;
        b.added_inertia = b.added_mass * b.length() * b.length() / 12.0;
    }
    chain
}

/// A random chain of `n` bodies: anchor, rods with random lengths and masses and a last
/// box body whose centroid is off its hinge axis (like the ship).
pub fn random_chain(n: usize, rng: &mut StdRng) -> Chain {
    assert!(n >= 3);
    let rods: Vec<(f64, f64)> = (0..n - 2).map(|_| (rng.gen_range(0.5..10.0), rng.gen_range(5.0..150.0))).collect();
    let mut chain = rod_chain(rng.gen_range(1e3..5e4), &rods);
    let last_len = rods.last().unwrap().0;
    let mass = rng.gen_range(1e3..5e5);
    chain.bodies.push(Body {
        kind: BodyKind::Ship,
        mass,
        inertia: box_inertia(mass, 50.0, 10.0, 5.0, 1.5),
        centroid: [rng.gen_range(-25.0..25.0), rng.gen_range(-2.0..2.0)],
        joint: [last_len, 0.0],
        shape: Shape::Box { length: 50.0, width: 10.0, height: 5.0 },
        added_mass: 0.0,
        added_inertia: 0.0,
    });
    chain
}

/// A random state: angles anywhere, speeds of order one.
pub fn random_state(n: usize, rng: &mut StdRng) -> (Vec<f64>, Vec<f64>) {
    let q = (0..n).map(|_| rng.gen_range(-3.0..3.0)).collect();
    let u = (0..n).map(|_| rng.gen_range(-2.0..2.0)).collect();
    (q, u)
}

pub fn rng(seed: u64) -> StdRng {
    StdRng::seed_from_u64(seed)
}

/// Integrates with RK4 from (q, u) for `steps` steps of `dt`, calling `observe` after each.
pub fn integrate(
    chain: &Chain,
    anchor: AnchorDof,
    q: &[f64],
    u: &[f64],
    dt: f64,
    steps: usize,
    mut observe: impl FnMut(f64, &[f64], &[BodyState]),
) -> Vec<f64> {
    let n = chain.len();
    let mut dynamics = Dynamics::new(Box::new(ReferenceKernel::new(chain)), Forces::gravity_only(chain, G), anchor);
    let mut rk = Rk4::new(2 * n + WORK_COUNT);
    let mut y: Vec<f64> = q.iter().chain(u).copied().chain([0.0; WORK_COUNT]).collect();
    let mut bodies = vec![BodyState::default(); n];
    let mut kin = ReferenceKernel::new(chain);
    for i in 0..steps {
        rk.step(&mut dynamics, i as f64 * dt, &mut y, dt).unwrap();
        kin.kinematics(&y[..n], &y[n..2 * n], &mut bodies);
        observe((i + 1) as f64 * dt, &y, &bodies);
    }
    y.truncate(2 * n);
    y
}

/// Kinetic plus gravitational energy, J.
pub fn energy(chain: &Chain, bodies: &[BodyState]) -> f64 {
    kanestop_runtime::energy::Energy::of(chain, bodies, G, 0.0, [0.0; WORK_COUNT]).balance()
}

/// The reference system over the active speeds, (M, f); with the anchor sliding under
/// friction −k N, N = a_w ẍ − f_w moves into the surge row.
fn reference_system(asm: &Assembly, active: usize, friction: f64) -> (nalgebra::DMatrix<f64>, nalgebra::DVector<f64>) {
    let mut m = asm.mass.view((0, 0), (active, active)).into_owned();
    let mut f = asm.rhs.rows(0, active).into_owned();
    if active == asm.rhs.len() {
        let s = active - 1;
        for p in 0..active {
            m[(s, p)] += friction * asm.heave[p];
        }
        f[s] += friction * asm.heave_rhs;
    }
    (m, f)
}

/// The relative residual of `qdd` in the reference system, ‖M ẍ − f‖ / ‖f‖ ([`reference_system`]).
pub fn residual(asm: &Assembly, active: usize, friction: f64, qdd: &[f64]) -> f64 {
    let (m, f) = reference_system(asm, active, friction);
    let x = nalgebra::DVector::from_column_slice(&qdd[..active]);
    (m * x - &f).norm() / f.norm()
}

/// The normwise backward error of `qdd` in the reference system, ‖M ẍ − f‖ / (‖M‖ ‖ẍ‖ + ‖f‖)
/// (Frobenius norm for M). A scene's a_lp spans ten orders of magnitude (a 13 kg/m cable and
/// a 500 t ship), so the residual relative to ‖f‖ alone measures the conditioning, not the
/// solve: the reference's own Cholesky solution reaches 1e-10 there.
pub fn backward_error(asm: &Assembly, active: usize, friction: f64, qdd: &[f64]) -> f64 {
    let (m, f) = reference_system(asm, active, friction);
    let x = nalgebra::DVector::from_column_slice(&qdd[..active]);
    (&m * &x - &f).norm() / (m.norm() * x.norm() + f.norm())
}

/// A kernel that is the generated one but cannot fuse (the trait's default), so that
/// `Dynamics` calls the force modules, and keeps no rows for the joint forces (the
/// observation takes Newton's form): the same right-hand side, entry for entry. A test may
/// give it a hook called before each solve ([`Unfused::with_hook`]).
pub struct Unfused<F: FnMut() = fn()>(pub GeneratedKernel, pub F);

impl Unfused {
    pub fn new(kernel: GeneratedKernel) -> Self {
        Unfused(kernel, || {})
    }
}

impl<F: FnMut()> Unfused<F> {
    /// `before_solve` runs before every solve (e.g. counts them, or sets a cancel flag).
    pub fn with_hook(kernel: GeneratedKernel, before_solve: F) -> Self {
        Unfused(kernel, before_solve)
    }
}

impl<F: FnMut()> Kernel for Unfused<F> {
    fn name(&self) -> &'static str {
        "unfused"
    }
    fn body_count(&self) -> usize {
        self.0.body_count()
    }
    fn form(&self) -> Option<&'static str> {
        Kernel::form(&self.0)
    }
    fn kinematics(&mut self, q: &[f64], u: &[f64], bodies: &mut [BodyState]) {
        self.0.kinematics(q, u, bodies)
    }
    fn assemble(&mut self, q: &[f64], u: &[f64], model: &mut dyn LoadModel, out: &mut Assembly) {
        self.0.assemble(q, u, model, out)
    }
    fn accelerations(&mut self, q: &[f64], u: &[f64], qdd: &[f64], out: &mut [BodyAcceleration]) {
        self.0.accelerations(q, u, qdd, out)
    }
    #[allow(clippy::too_many_arguments)]
    fn solve(
        &mut self,
        q: &[f64],
        u: &[f64],
        anchor: AnchorDof,
        friction: f64,
        model: &mut dyn LoadModel,
        scratch: &mut Assembly,
        qdd: &mut [f64],
    ) -> Result<AnchorReaction, RhsError> {
        (self.1)();
        self.0.solve(q, u, anchor, friction, model, scratch, qdd)
    }
}

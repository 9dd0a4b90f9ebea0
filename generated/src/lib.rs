//! # kanestop-generated
//!
//! Kane kernels emitted by `kanestop-codegen`. The unrolled ones, one module per variant (N
//! bodies, water off, i.e. no added mass, or on), hold flat, branch-free functions for the body states
//! (Eqs. 9, 13, 14), a_lp and f_l (Eqs. 25–27), the body accelerations (Eq. 17) and the O(N)
//! solve with the anchor free or stuck (Eqs. 27, 50); see `docs/codegen.md`.
//!
//! The kernels for the test sizes (N = 3, 5) and for every count the repository's scenes
//! need are checked in (`src/chain*.rs`, listed in `src/kernels.rs`); a test fails when they
//! are stale. The build script generates any other count a scene under `scenes/` needs, and
//! the counts in `KANESTOP_EXTRA_BODY_COUNTS` (e.g. `12,24,100,200` for the benchmarks), into
//! OUT_DIR. Besides these unrolled kernels, two rolled ones (`src/rolled_dry.rs`,
//! `src/rolled_wet.rs`, [`rolled`]) serve a chain of any N without a rebuild;
//! `src/loads.rs` holds the load code of every load signature ([`LoadParams`]) and
//! `src/rhs.rs` the fused right-hand sides ([`rhs`]): per signature, kinematics, loads and
//! the O(N) solve in one pass each way over the chain, on the rolled kernel's steps.
//! This file, [`trig`] (the kernels' sine and cosine) and [`lanes`] (two f64 lanes) are
//! written by hand.

#[rustfmt::skip]
mod kernels;

/// The rolled kernel of any N, water off.
#[rustfmt::skip]
#[allow(clippy::all, unused_variables, dead_code)]
mod rolled_dry;
/// The rolled kernel of any N, water on.
#[rustfmt::skip]
#[allow(clippy::all, unused_variables, dead_code)]
mod rolled_wet;

/// The loads of every load signature.
#[rustfmt::skip]
#[allow(clippy::all, unused_variables, unused_mut, dead_code)]
mod loads;

/// The fused right-hand side of every load signature.
#[rustfmt::skip]
#[allow(clippy::all, unused_variables, dead_code)]
mod rhs;

pub mod lanes;
pub mod trig;

#[cfg(test)]
mod load_pairs;

mod extra {
    include!(concat!(env!("OUT_DIR"), "/extra.rs"));
}

/// The checked-in folded kernels (`src/folded.rs`: the paper's case 1).
#[rustfmt::skip]
mod folded;

/// The folded kernels the build takes from `KANESTOP_FOLDED_KERNELS`.
mod folded_extra {
    include!(concat!(env!("OUT_DIR"), "/folded.rs"));
}

pub use kernels::*;

/// The numeric parameters of one body B_k, as the kernels read them. Structurally zero
/// entries (a rod's centroid height, the joint height of B_3 … B_N, the added mass of the
/// anchor and the ship or of every body in a dry variant) are never read: the runtime checks
/// them before using a kernel.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct BodyParams {
    /// m_k, kg.
    pub mass: f64,
    /// I_yy about the centroid plus the added inertia (Eqs. 18, 46), kg·m².
    pub inertia: f64,
    /// r_k, the centroid from o_k in body axes (x, z), m.
    pub centroid: [f64; 2],
    /// q_k, the joint in the inner body's axes (x, z), m; for B_1 the anchor origin at t = 0.
    pub joint: [f64; 2],
    /// Added mass across the body axis (Eq. 46), kg.
    pub added_mass: f64,
}

/// Body states and the rotation table: `(p, q, u, trig, bodies)`.
pub type KinematicsFn = fn(&[BodyParams], &[f64], &[f64], &mut [[f64; 2]], &mut [[f64; 6]]);
/// a_lp, f_l and the anchor's heave row: `(p, u, trig, loads, m, f, heave)`.
pub type AssembleFn = fn(&[BodyParams], &[f64], &[[f64; 2]], &[[f64; 3]], &mut [f64], &mut [f64], &mut [f64]);
/// Body accelerations: `(p, u, trig, qdd, acc)`.
pub type AccelerationsFn = fn(&[BodyParams], &[f64], &[[f64; 2]], &[f64], &mut [[f64; 3]]);
/// O(N) solve with the anchor free and sliding friction μ·direction: `(p, u, trig, loads,
/// friction, qdd)`, returning the normal force (Eq. 37) and the friction factor.
pub type SolveFreeFn = fn(&[BodyParams], &[f64], &[[f64; 2]], &[[f64; 3]], f64, &mut [f64]) -> [f64; 2];
/// O(N) solve with the anchor stuck, returning the holding and normal forces (Eqs. 50, 37).
pub type SolveStuckFn = fn(&[BodyParams], &[f64], &[[f64; 2]], &[[f64; 3]], &mut [f64]) -> [f64; 2];

/// One generated variant's entry points: a table of functions, which the runtime's
/// `GeneratedKernel` binds to a chain's numbers behind its `Kernel` trait.
#[derive(Clone, Copy, Debug)]
pub struct KernelTable {
    /// N.
    pub bodies: usize,
    /// Whether the added mass enters a_lp (water on).
    pub wet: bool,
    pub kinematics: KinematicsFn,
    pub assemble: AssembleFn,
    pub accelerations: AccelerationsFn,
    pub solve_free: SolveFreeFn,
    pub solve_stuck: SolveStuckFn,
}

/// Values per body in the scratch rows of the rolled kernels: the solve's row (the hinge,
/// its gains and force row, a_{o_k}) and θ̇_k last.
pub const ROLLED_SCRATCH: usize = 13;

/// Rolled a_lp, f_l and heave row: `(p, u, trig, loads, m, f, heave, scratch)`.
pub type RolledAssembleFn = fn(
    &[BodyParams],
    &[f64],
    &[[f64; 2]],
    &[[f64; 3]],
    &mut [f64],
    &mut [f64],
    &mut [f64],
    &mut [[f64; ROLLED_SCRATCH]],
);
/// Rolled O(N) solve, anchor free: `(p, u, trig, loads, friction, qdd, scratch)` → `[N, factor]`.
pub type RolledSolveFreeFn =
    fn(&[BodyParams], &[f64], &[[f64; 2]], &[[f64; 3]], f64, &mut [f64], &mut [[f64; ROLLED_SCRATCH]]) -> [f64; 2];
/// Rolled O(N) solve, anchor stuck: `(p, u, trig, loads, qdd, scratch)` → `[holding, N]`.
pub type RolledSolveStuckFn =
    fn(&[BodyParams], &[f64], &[[f64; 2]], &[[f64; 3]], &mut [f64], &mut [[f64; ROLLED_SCRATCH]]) -> [f64; 2];

/// A rolled kernel's entry points: the per-body steps generated once per body kind, driven
/// by loops, for a chain of any N ≥ 3. The arguments are those of [`KernelTable`] plus a
/// scratch of N rows, which the caller allocates once.
#[derive(Clone, Copy, Debug)]
pub struct RolledTable {
    /// Whether the added mass enters a_lp (water on).
    pub wet: bool,
    pub kinematics: KinematicsFn,
    pub assemble: RolledAssembleFn,
    pub accelerations: AccelerationsFn,
    pub solve_free: RolledSolveFreeFn,
    pub solve_stuck: RolledSolveStuckFn,
    /// The force through every hinge at the last solve, from its rows (`scratch`, out).
    pub joint_forces: JointForcesFn,
}

/// `(scratch, out)`: the force on B_k from B_{k−1} (Eq. 52), `out[k − 2]` = [F_x, F_z],
/// k = 2 … N, from the rows the last rolled solve left in `scratch`.
pub type JointForcesFn = fn(&[[f64; ROLLED_SCRATCH]], &mut [[f64; 2]]);

/// Work terms in the power array of the load functions (the runtime's `WORK_TERMS`).
pub const POWER_TERMS: usize = 9;

/// The numbers the generated load code reads for a scene, SI units (see the runtime's
/// force modules, whose values these are).
#[derive(Clone, Copy, Debug)]
pub struct LoadParams {
    /// g, m/s².
    pub g: f64,
    /// ρ, kg/m³.
    pub rho: f64,
    /// Height of the seabed plane in the inertial frame, m.
    pub seabed_z: f64,
    /// k_z, the foundation's stiffness, N/m³ (Eq. 41).
    pub seabed_stiffness: f64,
    /// μ of the grounded line.
    pub line_friction: f64,
    /// The slip speed of the regularised line friction, m/s.
    pub slip_speed: f64,
    /// C_D across the line (Eq. 47).
    pub normal_drag: f64,
    /// C_F along the line (Eq. 45).
    pub tangential_drag: f64,
    /// U_ST, m/s (Eq. 38).
    pub current_speed: f64,
    /// The current profile's exponent (1/7 in Eq. 38).
    pub current_exponent: f64,
    /// d, water depth, m.
    pub water_depth: f64,
    /// V_1, m³.
    pub anchor_volume: f64,
    /// w_1 h_1, m².
    pub anchor_area: f64,
    /// C_1^D.
    pub anchor_drag: f64,
    /// ∇, the ship's displaced volume at rest, m³.
    pub ship_volume: f64,
    /// A_W, m².
    pub ship_waterplane_area: f64,
    /// G_y^M, m (Eq. 57).
    pub ship_metacentric_height: f64,
    /// S_W, m².
    pub ship_wetted_surface: f64,
    /// L_N, m.
    pub ship_length: f64,
    /// ϑ, m²/s.
    pub viscosity: f64,
    /// C_sf (Eq. 61).
    pub roughness_allowance: f64,
    /// The Reynolds number below which Eq. 60's coefficient is held.
    pub min_reynolds: f64,
    /// The embedded volumes of the touching line elements (Eq. 41), in place, over the rows of
    /// B_2 … B_{N−1} (the contact pass sets each to zeros or marks it): each row `contacts[k]`
    /// reading `[h_a, h_b, 1]` (element k's end heights above the seabed) becomes
    /// `[V^S m³, s̄ m from the h_a end, 0]`, the others stay; the runtime's closed form, handed
    /// in so that it has one statement, and called once for the whole chain.
    pub embedded_volumes: fn(&[Element], &mut [[f64; 3]]),
}

/// What the load code reads of one body besides its [`BodyParams`]; made by [`Element::new`].
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Element {
    /// Length, m.
    pub length: f64,
    /// Radius, m.
    pub radius: f64,
    /// A chain link or cable element (buoyancy, drag, the seabed); false for the rod in
    /// air, the anchor and the ship.
    pub line: bool,
    /// π r² L, its volume, m³ (Eq. 42).
    pub volume: f64,
    /// ½ ρ d C_D with d = 2r: Eq. 47's drag across the line per unit length and U|U|, kg/m².
    pub normal_drag: f64,
    /// ½ π ρ d L C_F: Eq. 45's friction along the line per U|U|, kg/m.
    pub tangential_drag: f64,
    /// L³, m³ (Eq. 47 over a spinning element).
    pub length_cubed: f64,
}

impl Element {
    /// A body's element of `length` and `radius` under the loads' numbers `lp`: the products
    /// of parameters the load code would otherwise form at every evaluation, formed here
    /// once, in the order the force modules form them (so the loads stay equal to theirs).
    pub fn new(lp: &LoadParams, length: f64, radius: f64, line: bool) -> Self {
        let d = 2.0 * radius;
        Element {
            length,
            radius,
            line,
            volume: ::std::f64::consts::PI * radius * radius * length,
            normal_drag: 0.5 * lp.rho * d * lp.normal_drag,
            tangential_drag: 0.5 * ::std::f64::consts::PI * lp.rho * d * length * lp.tangential_drag,
            length_cubed: length.powi(3),
        }
    }
}

/// What a fused right-hand side leaves behind besides ẍ, for the caller to read, and the
/// rows its O(N) solve keeps per body: allocated once per chain ([`Workspace::new`]).
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Workspace {
    /// `[cos θ, sin θ]` of every body.
    pub trig: Vec<[f64; 2]>,
    /// `[x, z, θ, v_x, v_z, ω]` of every body's centroid C_k (m, rad, m/s, rad/s).
    pub bodies: Vec<[f64; 6]>,
    /// `[F_x, F_z, M_y]` of every body at its centroid (N, N·m).
    pub loads: Vec<[f64; 3]>,
    /// The power of each work term (W), indexed as the runtime's `WORK_TERMS`.
    pub power: [f64; POWER_TERMS],
    /// The solve's rows, [`ROLLED_SCRATCH`] values per body.
    pub scratch: Vec<[f64; ROLLED_SCRATCH]>,
}

impl Workspace {
    /// Room for a chain of `n` bodies.
    pub fn new(n: usize) -> Self {
        Workspace {
            trig: vec![[0.0; 2]; n],
            bodies: vec![[0.0; 6]; n],
            loads: vec![[0.0; 3]; n],
            power: [0.0; POWER_TERMS],
            scratch: vec![[0.0; ROLLED_SCRATCH]; n],
        }
    }

    /// The chain's length N, checked against the workspace and the arguments' lengths `lens`.
    fn check(&self, p: &[BodyParams], lens: &[usize]) -> usize {
        let n = p.len();
        assert!(n >= 3, "a chain has at least an anchor, one rod and a ship");
        let own = [self.trig.len(), self.bodies.len(), self.loads.len(), self.scratch.len()];
        assert!(own.iter().chain(lens).all(|&l| l >= n), "every argument must hold N = {n} entries");
        n
    }
}

/// A fused right-hand side with the anchor free: `(p, lp, elements, q, u, friction, ws,
/// qdd)` → `[N, 1 + friction·∂N/∂F_x]`, the states, loads and powers left in `ws`.
pub type RhsFreeFn =
    fn(&[BodyParams], &LoadParams, &[Element], &[f64], &[f64], f64, &mut Workspace, &mut [f64]) -> [f64; 2];
/// A fused right-hand side with the anchor held: `(p, lp, elements, q, u, ws, qdd)` →
/// `[holding, N]`.
pub type RhsStuckFn =
    fn(&[BodyParams], &LoadParams, &[Element], &[f64], &[f64], &mut Workspace, &mut [f64]) -> [f64; 2];

/// One load signature's fused right-hand sides.
#[derive(Clone, Copy, Debug)]
pub struct RhsTable {
    /// Whether they run the wet rolled steps (the added mass in a_lp): the signature's water.
    pub wet: bool,
    pub free: RhsFreeFn,
    pub stuck: RhsStuckFn,
}

/// The fused right-hand sides of a signature, by its name (`wet_seabed_friction`).
pub fn rhs(signature: &str) -> Option<RhsTable> {
    rhs::RHS.iter().find(|(n, _)| *n == signature).map(|(_, t)| *t)
}

/// An unrolled kernel with one scene's body parameters folded in as literals
/// (`kanestop codegen --scene SCENE --fold DIR`): it serves a chain with exactly these
/// numbers, and ignores the `p` its functions are handed.
#[derive(Clone, Copy, Debug)]
pub struct FoldedKernel {
    /// The module's name (`folded_case01`).
    pub name: &'static str,
    /// Its entry points, those of an unrolled kernel.
    pub kernel: KernelTable,
    /// The parameters folded in, B_1 first.
    pub params: &'static [BodyParams],
}

/// The folded kernel for a chain whose parameters are `p`, bit for bit, with the water
/// switch `wet`: checked in or built from `KANESTOP_FOLDED_KERNELS`.
pub fn find_folded(p: &[BodyParams], wet: bool) -> Option<FoldedKernel> {
    // Every field, so that a new one cannot be left out of the match.
    let bits = |&BodyParams { mass, inertia, centroid, joint, added_mass }: &BodyParams| {
        [mass, inertia, centroid[0], centroid[1], joint[0], joint[1], added_mass].map(f64::to_bits)
    };
    let same = |f: &FoldedKernel| {
        f.kernel.wet == wet && f.params.len() == p.len() && f.params.iter().zip(p).all(|(a, b)| bits(a) == bits(b))
    };
    folded::FOLDED.iter().chain(folded_extra::FOLDED).find(|f| same(f)).copied()
}

/// The names of every folded kernel in this build.
pub fn folded_kernels() -> Vec<&'static str> {
    folded::FOLDED.iter().chain(folded_extra::FOLDED).map(|f| f.name).collect()
}

/// The rolled kernel for the water switch: any N.
pub fn rolled(wet: bool) -> RolledTable {
    if wet {
        rolled_wet::KERNEL
    } else {
        rolled_dry::KERNEL
    }
}

/// The kernel for `bodies` bodies and the water switch, checked-in or built for a scene.
pub fn find(bodies: usize, wet: bool) -> Option<KernelTable> {
    kernels::lookup(bodies, wet).or_else(|| extra::lookup(bodies, wet))
}

/// Every (N, wet) available in this build.
pub fn available() -> Vec<(usize, bool)> {
    let mut all: Vec<(usize, bool)> = kernels::AVAILABLE.iter().chain(extra::AVAILABLE).copied().collect();
    all.sort_unstable();
    all
}

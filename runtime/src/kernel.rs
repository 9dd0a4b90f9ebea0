//! The one interface every Kane kernel implements, generated or reference.
//!
//! A kernel takes the generalised coordinates and speeds of the planar chain and returns
//! the reduced Kane equations a_lp ẍ_p = f_l (Eq. 27) plus the state of every body. The
//! applied loads come from a [`LoadModel`]: the kernel calls back into the force models
//! with the body states it computed and projects what they return (Eq. 23), unless it took
//! the loads into its own code ([`Kernel::fuse_loads`], the generated load code of the
//! scene's signature), in which case it tells the model the power it computed
//! ([`LoadModel::fused`]) and keeps the loads until asked ([`Kernel::last_loads`]).
//!
//! # Coordinates (used by every kernel, `eval` and the state files)
//!
//! For N bodies, `q` and `u` have N entries each:
//! - `q[i] = β_{i+2}` for i = 0 … N−2: the rotation of B_{i+2} relative to B_{i+1} about y,
//!   rad (Eq. 1); `u[i] = β̇_{i+2}` = ω_{k2} = ẋ_{3k−1} with k = i+2 (Eq. 8).
//! - `q[N−1] = s_11`: the anchor's surge from its initial position along x, m;
//!   `u[N−1] = ṡ_11 = ẋ_{3N+1}` (Eq. 29).
//!
//! Angles are positive by the right-hand rule about y = z × x (x toward the ship, z up,
//! y into the page), so a positive angle turns a body's x axis downward. A body's absolute
//! angle is θ_k = β_2 + … + β_k (θ_1 = 0): a rod rising toward the ship has θ < 0.

use nalgebra::{DMatrix, DVector};

use crate::fusion::FusedLoads;

/// Why a kernel could not produce the accelerations: the right-hand side of ẏ = F(t, y)
/// cannot be evaluated at this state.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum RhsError {
    /// The Cholesky factorisation of a_lp (Eq. 26) failed.
    #[error("the mass matrix a_lp is not positive definite (non-finite state or degenerate chain)")]
    MassNotPositiveDefinite,
    /// The solve (any kernel's) returned a non-finite ẍ or anchor reaction.
    #[error("the solve produced a non-finite acceleration (a state beyond the model's range, such as an angle of 1e300 rad, or a degenerate chain)")]
    NonFiniteAcceleration,
    /// 1 + μ ∂N/∂F ≤ 0: sliding friction is ill-posed (Painlevé's paradox, Eq. 37).
    #[error(
        "the anchor's sliding friction is ill-posed (1 + μ ∂N/∂F = {factor:.3e} ≤ 0, Painlevé's paradox): \
         the chain's pull on the anchor grows the normal force faster than friction resists; \
         lower environment.seabed_friction"
    )]
    IllPosedFriction {
        /// The factor 1 + μ ∂N/∂F (dimensionless).
        factor: f64,
    },
}

impl RhsError {
    /// Whether the failure belongs to the state rather than to the model: a non-finite or
    /// degenerate solve, which an adaptive method's trial stage far off the solution gives
    /// (a step too long for a stiff term); the method rejects that step and tries a shorter
    /// one. Ill-posed friction is the model's at any step.
    pub fn at_trial_state(&self) -> bool {
        matches!(self, RhsError::MassNotPositiveDefinite | RhsError::NonFiniteAcceleration)
    }
}

/// Whether the anchor's surge is a degree of freedom.
#[derive(Clone, Copy, Debug, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum AnchorDof {
    /// The anchor slides: N generalised speeds.
    Free,
    /// The anchor is held by static friction: ṡ_11 = 0, N−1 speeds (Eq. 27 without 3N+1).
    Stuck,
}

/// A body's centroid and rotation in the inertial frame.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct BodyState {
    /// Centroid C_k, m (x toward the ship from the ship's initial water-plane centre).
    pub x: f64,
    /// Centroid height above the still-water plane, m.
    pub z: f64,
    /// Absolute angle θ_k about y, rad.
    pub theta: f64,
    /// cos θ_k, from the kernel's rotation table (Eq. 4), so the force models need no
    /// transcendental function the kinematics already evaluated.
    pub cos: f64,
    /// sin θ_k.
    pub sin: f64,
    /// Centroid velocity along x, m/s.
    pub vx: f64,
    /// Centroid velocity along z (up), m/s.
    pub vz: f64,
    /// Angular velocity ω_2^(0k) about y, rad/s.
    pub omega: f64,
}

impl Default for BodyState {
    /// At rest at the origin, level: θ = 0 with cos θ = 1 and sin θ = 0 (consistent).
    fn default() -> Self {
        BodyState { x: 0.0, z: 0.0, theta: 0.0, cos: 1.0, sin: 0.0, vx: 0.0, vz: 0.0, omega: 0.0 }
    }
}

/// The resultant applied load on a body, at its centroid, inertial components.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Load {
    /// Force along x, N.
    pub fx: f64,
    /// Force along z (up), N.
    pub fz: f64,
    /// Moment about y, N·m.
    pub my: f64,
}

/// What one kernel evaluation produces.
#[derive(Clone, Debug)]
pub struct Assembly {
    /// a_lp over all N speeds (Eq. 26). With the anchor stuck the solver uses the leading
    /// (N−1)×(N−1) block; the last row gives the anchor's constraint force (Eq. 50).
    pub mass: DMatrix<f64>,
    /// f_l (Eq. 25), N entries.
    pub rhs: DVector<f64>,
    /// a_{w,p}: the row of the anchor's heave speed w = ẋ_{3N+3} over the N speeds. The
    /// heave is always constrained; its row gives the seabed's normal force on the anchor,
    /// N = a_{w,p} ẍ_p − f_w (Eq. 50 for the vertical, Eq. 37).
    pub heave: DVector<f64>,
    /// f_w, N.
    pub heave_rhs: f64,
    /// Every body's state, B_1 first.
    pub bodies: Vec<BodyState>,
}

impl Assembly {
    /// Storage for a chain of `n` bodies.
    pub fn new(n: usize) -> Self {
        Assembly {
            mass: DMatrix::zeros(n, n),
            rhs: DVector::zeros(n),
            heave: DVector::zeros(n),
            heave_rhs: 0.0,
            bodies: vec![BodyState::default(); n],
        }
    }
}

/// The seabed's reaction on the anchor after a solve.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct AnchorReaction {
    /// With the anchor stuck, the horizontal force (N, along +x) the seabed must supply to
    /// keep it in place, F^C_{3N+1} = a_{3N+1,p} ẍ_p − f_{3N+1} (Eq. 50); 0 while it slides
    /// (the sliding friction is an applied force then).
    pub holding: f64,
    /// The normal force N (N, along +z), a_{w,p} ẍ_p − f_w (Eq. 37). Negative when the
    /// chain would lift the anchor.
    pub normal: f64,
}

/// Accelerations of one body (Eq. 17), inertial components.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct BodyAcceleration {
    /// Centroid acceleration along x, m/s².
    pub ax: f64,
    /// Centroid acceleration along z (up), m/s².
    pub az: f64,
    /// Angular acceleration about y, rad/s².
    pub alpha: f64,
}

/// The force models, seen from a kernel: given every body's state, fill every body's load.
pub trait LoadModel {
    /// Writes the resultant applied load on every body (at its centroid, inertial
    /// components) for the body states `bodies` into `loads`, B_1 first.
    fn loads(&mut self, bodies: &[BodyState], loads: &mut [Load]);

    /// Told instead of [`LoadModel::loads`] by a kernel that computed the loads in its own
    /// code ([`Kernel::fuse_loads`]): the power of each work term (W, in the order of
    /// `forces::WORK_TERMS`), for the model to keep as if it had computed it. The loads
    /// themselves stay in the kernel until asked for ([`Kernel::last_loads`]): an
    /// integration reads them only when it reports them, not at every evaluation.
    fn fused(&mut self, power: &[f64]);
}

/// A Kane kernel for one chain.
pub trait Kernel {
    /// A short name for reports ("reference", "generated").
    fn name(&self) -> &'static str;

    /// N, the number of bodies.
    fn body_count(&self) -> usize;

    /// Which form of the kernel runs, for reports: `unrolled` or `rolled` for the generated
    /// kernel, none for the reference.
    fn form(&self) -> Option<&'static str> {
        None
    }

    /// Takes the scene's loads into the kernel's own code (the generated load code of their
    /// signature): afterwards [`Kernel::solve`] computes them itself, tells its `model` their
    /// power through [`LoadModel::fused`] instead of calling [`LoadModel::loads`], and keeps
    /// the loads for [`Kernel::last_loads`], which a kernel that fuses must therefore
    /// implement too. Returns whether it did; the default cannot.
    fn fuse_loads(&mut self, _loads: &FusedLoads) -> bool {
        false
    }

    /// Body states only (Eqs. 9, 13, 14): for energy, output and diagnostics.
    fn kinematics(&mut self, q: &[f64], u: &[f64], bodies: &mut [BodyState]);

    /// The Kane equations at (q, u) with the loads of `model` (Eqs. 22–27).
    fn assemble(&mut self, q: &[f64], u: &[f64], model: &mut dyn LoadModel, out: &mut Assembly);

    /// Body accelerations (Eq. 17) for generalised accelerations `qdd`.
    ///
    /// It must not change what a later [`Kernel::solve`] or [`Kernel::assemble`] returns
    /// (scratch overwritten before use is fine): `Dynamics` keeps its last solve valid across
    /// this call.
    fn accelerations(&mut self, q: &[f64], u: &[f64], qdd: &[f64], out: &mut [BodyAcceleration]);

    /// Generalised accelerations at (q, u) over the speeds `anchor` leaves active; a stuck
    /// anchor's entry of `qdd` is 0. A sliding anchor feels the friction force −`friction`·N
    /// along x, with `friction` = μ times the direction of sliding (0: none) and N the
    /// normal force of this very solve (implicit, Eq. 37; the paper lags it by one step).
    /// Returns the seabed's reaction.
    ///
    /// `scratch.bodies` holds the body states of (q, u) afterwards, or, for a kernel that
    /// keeps them in its own storage, [`Kernel::last_states`] writes them there when asked.
    /// The default assembles
    /// a_lp, f_l and the heave row and solves the active block by Cholesky; kernels with a
    /// recursive O(N) solve override it.
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
        self.assemble(q, u, model, scratch);
        solve_assembled(scratch, anchor, friction, qdd)
    }

    /// The body states of the last [`Kernel::solve`] into `bodies`, when that solve kept
    /// them in the kernel's own storage instead of `scratch.bodies` (the generated fused
    /// right-hand side: converted only when asked, as an observation does once a step, not
    /// at every evaluation). Valid until the kernel's next call. Returns whether it wrote
    /// them; the default has nothing to write, its solve filled `scratch.bodies`.
    fn last_states(&self, _bodies: &mut [BodyState]) -> bool {
        false
    }

    /// The applied loads of the last [`Kernel::solve`] into `loads`, B_1 first, when that
    /// solve computed them in its own code ([`Kernel::fuse_loads`]) and told the load model
    /// only their power ([`LoadModel::fused`]). Valid until the kernel's next call. Returns
    /// whether it wrote them; the default has nothing to write, its solve asked the load
    /// model for them.
    fn last_loads(&self, _loads: &mut [Load]) -> bool {
        false
    }

    /// The force on B_k from B_{k−1} through their hinge (Eq. 52) at the last
    /// [`Kernel::solve`], `out[k − 2]` = [F_x, F_z] (N) for k = 2 … N, when the solve kept
    /// what they need (a recursive solve has them in its rows). Returns whether it wrote
    /// them; the default cannot, and the observation computes them from the body
    /// accelerations instead.
    fn joint_forces(&self, _out: &mut [[f64; 2]]) -> bool {
        false
    }
}

/// Solves an assembled system over the active speeds (see [`Kernel::solve`]).
///
/// With the anchor sliding, the friction F = −k N enters f_s and N = N_0 + c F is itself
/// linear in F (c = a_w M⁻¹ e_s), so F follows from one scalar equation (Sherman–Morrison on
/// the Cholesky factor): N = N_0 / (1 + k c), ẍ = M⁻¹ f + F M⁻¹ e_s.
pub fn solve_assembled(
    asm: &Assembly,
    anchor: AnchorDof,
    friction: f64,
    qdd: &mut [f64],
) -> Result<AnchorReaction, RhsError> {
    let n = asm.rhs.len();
    let m = match anchor {
        AnchorDof::Free => n,
        AnchorDof::Stuck => n - 1,
    };
    let a: DMatrix<f64> = asm.mass.view((0, 0), (m, m)).into_owned();
    let chol = a.cholesky().ok_or(RhsError::MassNotPositiveDefinite)?;
    let mut x = chol.solve(&asm.rhs.rows(0, m).into_owned());
    let heave = asm.heave.rows(0, m);
    let mut normal = heave.dot(&x) - asm.heave_rhs;
    if anchor == AnchorDof::Free && friction != 0.0 {
        let mut e = DVector::zeros(m);
        e[m - 1] = 1.0;
        let g = chol.solve(&e);
        let factor = 1.0 + friction * heave.dot(&g);
        check_friction_factor(factor)?;
        normal /= factor;
        x += g * (-friction * normal);
    }
    qdd[..m].copy_from_slice(x.as_slice());
    qdd[m..].iter_mut().for_each(|v| *v = 0.0);
    let holding = match anchor {
        AnchorDof::Free => 0.0,
        AnchorDof::Stuck => asm.mass.row(n - 1).columns(0, m).dot(&x.transpose()) - asm.rhs[n - 1],
    };
    Ok(AnchorReaction { holding, normal })
}

/// Refuses a sliding problem that friction makes ill-posed: 1 + k ∂N/∂F ≤ 0 means the
/// friction's own effect on the normal force outgrows it (Painlevé's paradox).
pub fn check_friction_factor(factor: f64) -> Result<(), RhsError> {
    if factor > 0.0 || factor.is_nan() {
        Ok(()) // NaN is left to the caller's finiteness check
    } else {
        Err(RhsError::IllPosedFriction { factor })
    }
}

//! The equations of motion as a first-order system: y = (q, u, W), ẏ = (u, ü, P) with ü
//! from a_lp ü_p = f_l (Eq. 27), q̇ = u (Eqs. 28, 29 integrate to this for the angles) and
//! P the power of each work term of the energy balance (Eqs. 66–69).
//!
//! The anchor is held (its surge is no speed) or slides in a known direction with the
//! friction −μ N of Eq. 37, N the normal force of the same evaluation: the kernel's solve
//! takes it implicitly, so the right-hand side is a function of (q, u) alone.

use kanestop_chain::BodyKind;
use kanestop_generated::{Element, LoadParams, POWER_TERMS};

use crate::forces::anchor::AnchorForces;
use crate::forces::{seabed, ship, Forces, WORK_TERMS};
use crate::fusion::FusedLoads;
use crate::integrate::{OdeSystem, RhsError};
use crate::kernel::{AnchorDof, AnchorReaction, Assembly, BodyAcceleration, BodyState, Kernel, Load, LoadModel};

/// Number of work accumulators at the end of the state.
pub const WORK_COUNT: usize = WORK_TERMS.len();

/// Kernel + loads + the anchor's state: the right-hand side the integrators see.
pub struct Dynamics {
    kernel: Box<dyn Kernel>,
    forces: Forces,
    anchor: AnchorDof,
    /// Direction of sliding (+1 toward the ship, −1 away, 0 for no friction) while free.
    direction: f64,
    assembly: Assembly,
    /// Whether `assembly.bodies` holds the last solve's body states, or the kernel still
    /// keeps them ([`Kernel::last_states`]).
    states_settled: bool,
    /// Whether `loads` holds the last evaluation's loads with the anchor's friction added.
    /// Until then they are in the kernel ([`Kernel::last_loads`]) or, when the force
    /// modules computed them, in `loads` without the friction.
    loads_settled: bool,
    evaluations: u64,
    loads: Vec<Load>,
    /// The seabed's reaction and the sliding friction force (N, along +x) of the last
    /// evaluation.
    reaction: AnchorReaction,
    friction: f64,
    /// The last evaluation's (q, u) and ü: an evaluation at the same state under the same
    /// anchor state is answered from it (see [`Dynamics::accelerations`]).
    last: LastEvaluation,
    /// Whether the kernel computes the loads itself ([`Kernel::fuse_loads`]).
    fused: bool,
}

const _: () = assert!(POWER_TERMS == WORK_TERMS.len(), "the generated load code's power array is WORK_TERMS");

/// Inputs and result of the last evaluation; `valid` is cleared whenever anything but
/// (q, u) that the result depends on may have changed.
#[derive(Default)]
struct LastEvaluation {
    valid: bool,
    q: Vec<f64>,
    u: Vec<f64>,
    qdd: Vec<f64>,
}

impl LastEvaluation {
    fn matches(&self, q: &[f64], u: &[f64]) -> bool {
        self.valid && self.q == q && self.u == u
    }

    fn set(&mut self, q: &[f64], u: &[f64], qdd: &[f64]) {
        for (v, x) in [(&mut self.q, q), (&mut self.u, u), (&mut self.qdd, qdd)] {
            v.clear();
            v.extend_from_slice(x);
        }
        self.valid = true;
    }
}

/// The forces seen by the kernel, keeping a copy of the loads they returned (a fused
/// kernel keeps its own: [`Kernel::last_loads`]).
struct Recording<'a> {
    forces: &'a mut Forces,
    loads: &'a mut Vec<Load>,
}

impl LoadModel for Recording<'_> {
    fn loads(&mut self, bodies: &[BodyState], loads: &mut [Load]) {
        self.forces.loads(bodies, loads);
        self.loads.clear();
        self.loads.extend_from_slice(loads);
    }

    fn fused(&mut self, power: &[f64]) {
        self.forces.fused(power);
    }
}

/// The loads of `forces` as the generated load code takes them: their signature, their
/// numbers, and the seabed's closed form (`seabed::embedded_volume`, by way of
/// `contact::embedded_volumes`), handed in. None when
/// the load code cannot state them: a chain not in Huston's order (the anchor first, the
/// ship last, line elements and the rod between; the load code assumes it, the force
/// modules dispatch on each body's kind), or, with water, a ship whose hydrostatics were
/// built with another ρ or g than the other loads (the load code has one of each).
pub fn fused_loads(forces: &Forces) -> Option<FusedLoads> {
    let (c, a, s) = (&forces.current, &forces.anchor, &forces.ship);
    let kinds: Vec<BodyKind> = forces.elements.iter().map(|e| e.kind).collect();
    let n = kinds.len();
    let ordered = n >= 3
        && kinds[0] == BodyKind::Anchor
        && kinds[n - 1] == BodyKind::Ship
        && kinds[1..n - 1].iter().all(|k| !matches!(k, BodyKind::Anchor | BodyKind::Ship));
    if !ordered || (forces.water && (s.rho != forces.rho || s.g != forces.g)) {
        return None;
    }
    let params = LoadParams {
        g: forces.g,
        rho: forces.rho,
        seabed_z: forces.seabed_z,
        seabed_stiffness: forces.k_z,
        line_friction: forces.line_friction,
        slip_speed: seabed::V_SLIP,
        normal_drag: forces.c_d,
        tangential_drag: forces.c_f,
        current_speed: c.surface_speed,
        current_exponent: c.exponent,
        water_depth: c.depth,
        anchor_volume: a.volume,
        anchor_area: a.frontal_area,
        anchor_drag: a.drag_coefficient,
        ship_volume: s.volume,
        ship_waterplane_area: s.waterplane_area,
        ship_metacentric_height: s.metacentric_height,
        ship_wetted_surface: s.wetted_surface,
        ship_length: s.length,
        viscosity: s.viscosity,
        roughness_allowance: s.roughness_allowance,
        min_reynolds: ship::MIN_REYNOLDS,
        embedded_volumes: crate::contact::embedded_volumes,
    };
    let elements = forces
        .elements
        .iter()
        .map(|e| {
            Element::new(&params, e.length, e.radius, matches!(e.kind, BodyKind::ChainLink | BodyKind::Cable { .. }))
        })
        .collect();
    Some(FusedLoads { signature: forces.signature(), params, elements })
}

impl Dynamics {
    /// The right-hand side for `kernel` under the loads `forces`, the anchor starting in
    /// state `anchor` (without friction until [`Dynamics::slide_anchor`] sets a direction).
    ///
    /// When the kernel can take the loads into its own code ([`Kernel::fuse_loads`], the
    /// generated load code of their signature), it does: the force modules are then not
    /// called per evaluation, and [`Dynamics::loads`] holds what the kernel computed.
    pub fn new(mut kernel: Box<dyn Kernel>, forces: Forces, anchor: AnchorDof) -> Self {
        let n = kernel.body_count();
        let fused = fused_loads(&forces).is_some_and(|f| kernel.fuse_loads(&f));
        Dynamics {
            kernel,
            forces,
            anchor,
            direction: 0.0,
            assembly: Assembly::new(n),
            states_settled: true,
            loads_settled: true,
            evaluations: 0,
            loads: vec![Load::default(); n],
            reaction: AnchorReaction::default(),
            friction: 0.0,
            last: LastEvaluation::default(),
            fused,
        }
    }

    /// N.
    pub fn body_count(&self) -> usize {
        self.kernel.body_count()
    }

    /// Whether the kernel computes the loads itself ([`Kernel::fuse_loads`]).
    pub fn loads_fused(&self) -> bool {
        self.fused
    }

    /// The form of the kernel that runs ([`Kernel::form`]), as fusing left it.
    pub fn kernel_form(&self) -> Option<&'static str> {
        self.kernel.form()
    }

    /// The load models (read-only: changing one would change the right-hand side behind the
    /// last evaluation's back).
    pub fn forces(&self) -> &Forces {
        &self.forces
    }

    /// Body accelerations (Eq. 17) for generalised accelerations `qdd` at (q, u). Pure
    /// kinematics: it leaves the last evaluation valid, so the fixed-step driver's observation
    /// at the end of a step is also the next step's first stage.
    pub fn body_accelerations(&mut self, q: &[f64], u: &[f64], qdd: &[f64], out: &mut [BodyAcceleration]) {
        self.settle_states();
        self.kernel.accelerations(q, u, qdd, out);
    }

    /// The force on B_k from B_{k−1} (Eq. 52) at the last evaluation, `out[k − 2]` =
    /// [F_x, F_z], k = 2 … N, from the kernel's own solve when it kept them
    /// ([`Kernel::joint_forces`]). Returns whether it wrote them.
    pub fn joint_forces(&self, out: &mut [[f64; 2]]) -> bool {
        self.kernel.joint_forces(out)
    }

    /// Whether the anchor is held or sliding now.
    pub fn anchor(&self) -> AnchorDof {
        self.anchor
    }

    /// Holds the anchor (its surge is no speed; static friction holds it).
    pub fn stick_anchor(&mut self) {
        self.anchor = AnchorDof::Stuck;
        self.direction = 0.0;
        self.last.valid = false;
    }

    /// Frees the anchor to slide in `direction` (+1 toward the ship, −1 away) against the
    /// friction −μ N, or without friction for `direction` = 0.
    pub fn slide_anchor(&mut self, direction: f64) {
        self.anchor = AnchorDof::Free;
        self.direction = direction;
        self.last.valid = false;
    }

    /// The direction of sliding (0 while held or frictionless).
    pub fn sliding_direction(&self) -> f64 {
        self.direction
    }

    /// Right-hand-side evaluations so far.
    pub fn evaluations(&self) -> u64 {
        self.evaluations
    }

    /// The last evaluation's body states, B_1 first.
    pub fn body_states(&mut self) -> &[BodyState] {
        self.settle_states();
        &self.assembly.bodies
    }

    /// The last solve's body states into `assembly.bodies` where the kernel kept them
    /// itself: before any call that may overwrite them, and when they are asked for.
    fn settle_states(&mut self) {
        if !self.states_settled {
            self.kernel.last_states(&mut self.assembly.bodies);
            self.states_settled = true;
        }
    }

    /// The last evaluation's loads into `loads` where the kernel kept them itself, and the
    /// anchor's sliding friction added to them (once): before any call that may overwrite
    /// them in the kernel, and when they are asked for.
    fn settle_loads(&mut self) {
        if !self.loads_settled {
            let kept = self.kernel.last_loads(&mut self.loads);
            debug_assert!(kept || !self.fused, "a kernel that fuses its loads keeps them (Kernel::last_loads)");
            self.loads[0].fx += self.friction;
            self.loads_settled = true;
        }
    }

    /// The applied loads of the last evaluation, per body, the anchor's sliding friction
    /// included.
    pub fn loads(&mut self) -> &[Load] {
        self.settle_loads();
        &self.loads
    }

    /// The seabed's reaction on the anchor at the last evaluation.
    pub fn reaction(&self) -> AnchorReaction {
        self.reaction
    }

    /// Number of active speeds: N (anchor free) or N − 1 (stuck).
    pub fn active_speeds(&self) -> usize {
        match self.anchor {
            AnchorDof::Free => self.body_count(),
            AnchorDof::Stuck => self.body_count() - 1,
        }
    }

    /// Generalised accelerations at (q, u) by the kernel's solve; a stuck anchor's entry is
    /// zero. Returns the seabed's reaction on the anchor (see [`Kernel::solve`]).
    ///
    /// A sliding anchor's friction is −μ N with N from this solve. Should N come out
    /// negative (the chain lifting the anchor), friction would pull the anchor along:
    /// the solve is repeated without friction (the model has no lift-off).
    ///
    /// A call at the (q, u) of the previous one, with nothing changed in between, returns
    /// its result without solving again: the driver observes the end of each interval,
    /// where Dormand–Prince has just evaluated its last stage. Only solves are counted in
    /// [`Dynamics::evaluations`].
    pub fn accelerations(&mut self, q: &[f64], u: &[f64], qdd: &mut [f64]) -> Result<AnchorReaction, RhsError> {
        if self.last.matches(q, u) {
            qdd.copy_from_slice(&self.last.qdd);
            return Ok(self.reaction);
        }
        self.last.valid = false;
        self.evaluations += 1;
        let k = match self.anchor {
            AnchorDof::Free => self.forces.anchor.friction_factor(self.direction),
            AnchorDof::Stuck => 0.0,
        };
        self.states_settled = false;
        self.loads_settled = false;
        // Until the solve succeeds: the loads of a refused evaluation carry no friction.
        self.friction = 0.0;
        let mut model = Recording { forces: &mut self.forces, loads: &mut self.loads };
        let mut reaction = self.kernel.solve(q, u, self.anchor, k, &mut model, &mut self.assembly, qdd)?;
        if k != 0.0 && reaction.normal < 0.0 {
            let mut model = Recording { forces: &mut self.forces, loads: &mut self.loads };
            reaction = self.kernel.solve(q, u, self.anchor, 0.0, &mut model, &mut self.assembly, qdd)?;
        }
        // Whatever the kernel: a state beyond what the model can represent (q = 1e300) gives
        // no accelerations, not NaNs passed on.
        if !reaction.holding.is_finite() || !reaction.normal.is_finite() || qdd.iter().any(|x| !x.is_finite()) {
            return Err(RhsError::NonFiniteAcceleration);
        }
        self.friction = AnchorForces::sliding_friction(k, reaction.normal);
        self.reaction = reaction;
        self.last.set(q, u, qdd);
        Ok(reaction)
    }

    /// a_lp and f_l at (q, u) with this system's loads, whatever path `accelerations` takes
    /// (for reports such as `eval`).
    pub fn assemble(&mut self, q: &[f64], u: &[f64], out: &mut Assembly) {
        self.settle_states();
        self.settle_loads();
        self.last.valid = false;
        self.kernel.assemble(q, u, &mut self.forces, out);
    }
}

impl OdeSystem for Dynamics {
    fn dim(&self) -> usize {
        2 * self.body_count() + WORK_COUNT
    }

    /// The work accumulators W never feed back into the motion.
    fn quadrature_components(&self) -> usize {
        WORK_COUNT
    }

    fn rhs(&mut self, _t: f64, y: &[f64], dy: &mut [f64]) -> Result<(), RhsError> {
        let n = self.body_count();
        let (q, rest) = y.split_at(n);
        let u = &rest[..n];
        let (dq, rest) = dy.split_at_mut(n);
        let (du, dw) = rest.split_at_mut(n);
        dq.copy_from_slice(u);
        if self.anchor == AnchorDof::Stuck {
            dq[n - 1] = 0.0;
        }
        self.accelerations(q, u, du)?;
        dw.copy_from_slice(&self.forces.power());
        // The sliding friction's power (Eq. 68), known only after the solve.
        dw[crate::forces::term::ANCHOR_FRICTION] += self.friction * u[n - 1];
        Ok(())
    }
}

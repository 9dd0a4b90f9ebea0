//! The equations of motion as a first-order system: y = (q, u, W), ẏ = (u, ü, P) with ü
//! from a_lp ü_p = f_l (Eq. 27), q̇ = u (Eqs. 28, 29 integrate to this for the angles) and
//! P the power of each work term of the energy balance (Eqs. 66–69).

use crate::forces::{Forces, WORK_TERMS};
use crate::integrate::{OdeSystem, RhsError};
use crate::kernel::{AnchorDof, Assembly, BodyState, Kernel, Load, LoadModel};

/// Number of work accumulators at the end of the state.
pub const WORK_COUNT: usize = WORK_TERMS.len();

/// Kernel + loads + the anchor's state: the right-hand side the integrators see.
pub struct Dynamics {
    kernel: Box<dyn Kernel>,
    /// The loads; the run sets the anchor's sliding friction here.
    pub forces: Forces,
    anchor: AnchorDof,
    assembly: Assembly,
    evaluations: u64,
    loads: Vec<Load>,
}

/// The forces seen by the kernel, keeping a copy of the loads they returned.
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
}

impl Dynamics {
    pub fn new(kernel: Box<dyn Kernel>, forces: Forces, anchor: AnchorDof) -> Self {
        let n = kernel.body_count();
        Dynamics { kernel, forces, anchor, assembly: Assembly::new(n), evaluations: 0, loads: vec![Load::default(); n] }
    }

    /// N.
    pub fn body_count(&self) -> usize {
        self.kernel.body_count()
    }

    pub fn kernel_mut(&mut self) -> &mut dyn Kernel {
        self.kernel.as_mut()
    }

    pub fn anchor(&self) -> AnchorDof {
        self.anchor
    }

    /// Switches the anchor between held and sliding.
    pub fn set_anchor(&mut self, anchor: AnchorDof) {
        self.anchor = anchor;
    }

    /// Right-hand-side evaluations so far.
    pub fn evaluations(&self) -> u64 {
        self.evaluations
    }

    /// The last evaluation's body states (and M, f when the kernel assembled them).
    pub fn assembly(&self) -> &Assembly {
        &self.assembly
    }

    /// The applied loads of the last evaluation, per body.
    pub fn loads(&self) -> &[Load] {
        &self.loads
    }

    /// Number of active speeds: N (anchor free) or N − 1 (stuck).
    pub fn active_speeds(&self) -> usize {
        match self.anchor {
            AnchorDof::Free => self.body_count(),
            AnchorDof::Stuck => self.body_count() - 1,
        }
    }

    /// Generalised accelerations at (q, u) by the kernel's solve; a stuck anchor's entry is
    /// zero. Returns the anchor's holding force (see [`Kernel::solve`]).
    pub fn accelerations(&mut self, q: &[f64], u: &[f64], qdd: &mut [f64]) -> Result<f64, RhsError> {
        self.evaluations += 1;
        let mut model = Recording { forces: &mut self.forces, loads: &mut self.loads };
        self.kernel.solve(q, u, self.anchor, &mut model, &mut self.assembly, qdd)
    }

    /// a_lp and f_l at (q, u) with this system's loads, whatever path `accelerations` takes
    /// (for reports such as `eval`).
    pub fn assemble(&mut self, q: &[f64], u: &[f64], out: &mut Assembly) {
        self.kernel.assemble(q, u, &mut self.forces, out);
    }
}

impl OdeSystem for Dynamics {
    fn dim(&self) -> usize {
        2 * self.body_count() + WORK_COUNT
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
        Ok(())
    }
}

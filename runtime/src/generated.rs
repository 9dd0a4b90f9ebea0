//! The generated kernel: code emitted by `kanestop-codegen` (crate `kanestop-generated`),
//! behind the same [`Kernel`] interface as the reference.
//!
//! Three forms ([`Form`]): **unrolled**, flat code for one body count and water switch, built
//! for the scenes under `scenes/` and `KANESTOP_EXTRA_BODY_COUNTS`; **folded**, the same with
//! one chain's numbers as literals (`kanestop codegen --fold`, `KANESTOP_FOLDED_KERNELS`); and
//! **rolled**, the same per-body steps generated once per body kind and driven by loops, for
//! any N. [`GeneratedKernel::new`] takes a folded kernel when the build has one with exactly
//! the chain's numbers, else the unrolled kernel when it has one, else the rolled one, and [`GeneratedKernel::form`] says which; a kernel that takes the scene's
//! loads ([`Kernel::fuse_loads`]) runs the rolled steps its fused right-hand side drives. The reference is never a
//! fallback: it is the oracle and an explicit choice.
//!
//! One kernel serves every scene with the same shape: masses, lengths and inertias are
//! runtime parameters ([`BodyParams`]); only the structurally zero ones are folded into the
//! code (all of them in a folded kernel), and [`GeneratedKernel::new`] checks that the chain agrees before using it.
//!
//! [`Kernel::solve`] uses the generated O(N) articulated-body recursion by default
//! ([`SolvePath::Recursive`]); [`SolvePath::Assembled`] assembles the generated a_lp and f_l
//! and factors them like the reference (kept for comparison and benchmarks).

use kanestop_chain::{ParamField, StructuralZero, Variant, Water};
use kanestop_generated::BodyParams;

use crate::chain::Chain;
use crate::fusion::FusedLoads;
use crate::kernel::RhsError;
use crate::kernel::{
    check_friction_factor, solve_assembled, AnchorDof, AnchorReaction, Assembly, BodyAcceleration, BodyState, Kernel,
    Load, LoadModel,
};

/// How [`GeneratedKernel`] solves for the generalised accelerations.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum SolvePath {
    /// The generated O(N) recursion (default).
    Recursive,
    /// Generated a_lp and f_l, then Cholesky (O(N²) to build, O(N³) to factor).
    Assembled,
}

/// Why a chain has no generated kernel.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum GeneratedError {
    /// Fewer than an anchor, one rod and a ship.
    #[error("a chain of {bodies} bodies has no generated kernel (N ≥ 3)")]
    TooFewBodies {
        /// N.
        bodies: usize,
    },
    /// The unrolled form was asked for, and this build has none for this shape.
    #[error(
        "no unrolled kernel for N = {bodies} bodies ({}) in this build: they are built for the scenes \
         under scenes/ and KANESTOP_EXTRA_BODY_COUNTS (up to 400 bodies); the rolled kernel serves any N",
        if *wet { "water on" } else { "water off" }
    )]
    NotBuilt {
        /// N.
        bodies: usize,
        /// Whether the added-mass variant was wanted.
        wet: bool,
    },
    /// The folded form was asked for, and this build has no folded kernel with this chain's
    /// numbers.
    #[error(
        "no folded kernel for this chain of N = {bodies} bodies in this build: write one with `kanestop codegen \
         --scene SCENE --fold DIR` and build with KANESTOP_FOLDED_KERNELS=DIR"
    )]
    NotFolded {
        /// N.
        bodies: usize,
    },
    /// The chain has a non-zero value where the kernels fold a structural zero.
    #[error("B_{} ({kind}) has {field} = {value}, which the generated kernels fold to zero; use --kernel reference", body + 1)]
    FoldedParameter {
        /// 0-based body index.
        body: usize,
        /// Its kind.
        kind: kanestop_chain::BodyKind,
        /// The parameter.
        field: ParamField,
        /// Its value.
        value: f64,
    },
}

/// Every (N, water on) with an unrolled kernel in this build (the rolled one serves any N).
pub fn available() -> Vec<(usize, bool)> {
    kanestop_generated::available()
}

/// The name of every folded kernel in this build (`kanestop codegen --fold`).
pub fn folded_kernels() -> Vec<&'static str> {
    kanestop_generated::folded_kernels()
}

/// The folded kernel with exactly `chain`'s numbers, if this build has one.
pub fn folded_for(chain: &Chain) -> Option<&'static str> {
    let wet = chain.has_added_mass();
    kanestop_generated::find_folded(&body_params(chain), wet).map(|f| f.name)
}

/// The numbers a generated kernel reads for each body of `chain`: the inertia about y plus
/// the added inertia (Eqs. 18, 46), the centroid, the joint and the added mass.
pub fn body_params(chain: &Chain) -> Vec<BodyParams> {
    chain
        .bodies
        .iter()
        .map(|b| BodyParams {
            mass: b.mass,
            inertia: b.inertia[1] + b.added_inertia,
            centroid: b.centroid,
            joint: b.joint,
            added_mass: b.added_mass,
        })
        .collect()
}

/// Which generated code a [`GeneratedKernel`] runs.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Form {
    /// Flat code for this N, from the build.
    Unrolled,
    /// Flat code for this N with this chain's parameters folded in as literals
    /// (`kanestop codegen --scene SCENE --fold DIR`, docs/codegen.md).
    Folded,
    /// Per-body-kind steps in a loop: any N, no rebuild.
    Rolled,
}

impl Form {
    /// `unrolled` or `rolled`.
    pub fn name(self) -> &'static str {
        match self {
            Form::Unrolled => "unrolled",
            Form::Folded => "folded",
            Form::Rolled => "rolled",
        }
    }
}

/// The entry points in use.
enum Table {
    Unrolled(kanestop_generated::KernelTable),
    /// An unrolled kernel with this chain's numbers folded in.
    Folded(kanestop_generated::KernelTable),
    Rolled(kanestop_generated::RolledTable),
}

/// The scene's whole right-hand side in generated code ([`Kernel::fuse_loads`]).
struct Fusion {
    /// The fused right-hand sides of the scene's signature.
    rhs: kanestop_generated::RhsTable,
    params: kanestop_generated::LoadParams,
    elements: Vec<kanestop_generated::Element>,
}

/// A generated kernel bound to one chain's numbers.
pub struct GeneratedKernel {
    table: Table,
    fusion: Option<Fusion>,
    bodies: usize,
    wet: bool,
    solve_path: SolvePath,
    params: Vec<BodyParams>,
    /// The rotation table, body states, loads and powers of the last evaluation, and the
    /// rolled solve's rows.
    ws: kanestop_generated::Workspace,
    /// The q that `ws.trig` was computed at (empty before the first kinematics): body
    /// accelerations at the state just solved, as every observation asks for, reuse it.
    trig_q: Vec<f64>,
    /// Whether `ws.scratch` holds the rows of the last solve, which was a rolled one (an
    /// unrolled solve keeps no rows; `assemble` overwrites them).
    rows_of_last_solve: bool,
    /// Whether `ws.bodies` and `ws.trig` hold the states of the last solve, a fused one,
    /// which left `scratch.bodies` as it was ([`Kernel::last_states`]).
    states_of_last_solve: bool,
    /// Whether `ws.loads` holds the loads the last solve, a fused one, computed
    /// ([`Kernel::last_loads`]).
    loads_of_last_solve: bool,
    loads: Vec<Load>,
    acc: Vec<[f64; 3]>,
    /// a_{w,p} and f_w from `assemble`.
    heave: Vec<f64>,
}

impl GeneratedKernel {
    /// The generated kernel for `chain`, water on when any body has added mass: unrolled
    /// when this build has one for N (folded when it has one for exactly this chain's
    /// numbers), rolled otherwise.
    pub fn new(chain: &Chain) -> Result<Self, GeneratedError> {
        let wet = chain.has_added_mass();
        let form = if kanestop_generated::find_folded(&body_params(chain), wet).is_some() {
            Form::Folded
        } else if kanestop_generated::find(chain.len(), wet).is_some() {
            Form::Unrolled
        } else {
            Form::Rolled
        };
        Self::with_form(chain, form)
    }

    /// The generated kernel of the given form for `chain`.
    pub fn with_form(chain: &Chain, form: Form) -> Result<Self, GeneratedError> {
        let n = chain.len();
        if n < 3 {
            return Err(GeneratedError::TooFewBodies { bodies: n });
        }
        let wet = chain.has_added_mass();
        let variant = Variant::new(n, if wet { Water::On } else { Water::Off });
        let params = body_params(chain);
        let table = match form {
            Form::Unrolled => {
                Table::Unrolled(kanestop_generated::find(n, wet).ok_or(GeneratedError::NotBuilt { bodies: n, wet })?)
            }
            Form::Folded => Table::Folded(
                kanestop_generated::find_folded(&params, wet).ok_or(GeneratedError::NotFolded { bodies: n })?.kernel,
            ),
            Form::Rolled => Table::Rolled(kanestop_generated::rolled(wet)),
        };
        for StructuralZero { body: k, field } in variant.structural_zeros() {
            let b = &params[k];
            let value = match field {
                ParamField::CentroidZ => b.centroid[1],
                ParamField::JointZ => b.joint[1],
                ParamField::AddedMass => b.added_mass,
            };
            if value != 0.0 {
                return Err(GeneratedError::FoldedParameter { body: k, kind: chain.bodies[k].kind, field, value });
            }
        }
        Ok(GeneratedKernel {
            table,
            fusion: None,
            bodies: n,
            wet,
            solve_path: SolvePath::Recursive,
            params,
            ws: kanestop_generated::Workspace::new(n),
            trig_q: Vec::with_capacity(n),
            rows_of_last_solve: false,
            states_of_last_solve: false,
            loads_of_last_solve: false,
            loads: vec![Load::default(); n],
            acc: vec![[0.0; 3]; n],
            heave: vec![0.0; n + 1],
        })
    }

    /// The same kernel with another solve path. Fused loads are dropped when the path is
    /// not the recursive one (the assembled path reads its loads from the model).
    pub fn with_solve_path(mut self, path: SolvePath) -> Self {
        self.solve_path = path;
        if path != SolvePath::Recursive {
            self.fusion = None;
        }
        self
    }

    /// How the accelerations are solved for.
    pub fn solve_path(&self) -> SolvePath {
        self.solve_path
    }

    /// True when the added-mass variant is in use.
    pub fn is_wet(&self) -> bool {
        self.wet
    }

    /// Whether the scene's fused right-hand side runs ([`Kernel::fuse_loads`]).
    pub fn is_fused(&self) -> bool {
        self.fusion.is_some()
    }

    /// Unrolled, folded or rolled.
    pub fn form(&self) -> Form {
        match self.table {
            Table::Unrolled(_) => Form::Unrolled,
            Table::Folded(_) => Form::Folded,
            Table::Rolled(..) => Form::Rolled,
        }
    }

    fn states(&mut self, q: &[f64], u: &[f64], bodies: &mut [BodyState]) {
        self.states_of_last_solve = false;
        let kinematics = match &self.table {
            Table::Unrolled(t) | Table::Folded(t) => t.kinematics,
            Table::Rolled(t) => t.kinematics,
        };
        kinematics(&self.params, q, u, &mut self.ws.trig, &mut self.ws.bodies);
        self.computed_at(q, bodies);
    }

    /// Records that `ws` holds the kinematics at `q` and copies its states into `bodies`.
    fn computed_at(&mut self, q: &[f64], bodies: &mut [BodyState]) {
        self.kinematics_at(q);
        self.copy_states(bodies);
    }

    /// Records that `ws` holds the kinematics at `q`.
    fn kinematics_at(&mut self, q: &[f64]) {
        self.trig_q.clear();
        self.trig_q.extend_from_slice(q);
    }

    /// The states in `ws` as the runtime's body states.
    fn copy_states(&self, bodies: &mut [BodyState]) {
        for ((b, s), t) in bodies.iter_mut().zip(&self.ws.bodies).zip(&self.ws.trig) {
            *b = BodyState { x: s[0], z: s[1], theta: s[2], cos: t[0], sin: t[1], vx: s[3], vz: s[4], omega: s[5] };
        }
    }

    /// The recursive solve with the loads of `model` at `bodies` (the states just computed).
    fn solve_with_loads(
        &mut self,
        u: &[f64],
        anchor: AnchorDof,
        friction: f64,
        model: &mut dyn LoadModel,
        bodies: &[BodyState],
        qdd: &mut [f64],
    ) -> Result<AnchorReaction, RhsError> {
        self.loads(model, bodies);
        let (p, ws) = (&self.params, &mut self.ws);
        Ok(match (anchor, &self.table) {
            (AnchorDof::Free, table) => {
                let [normal, factor] = match table {
                    Table::Unrolled(t) | Table::Folded(t) => (t.solve_free)(p, u, &ws.trig, &ws.loads, friction, qdd),
                    Table::Rolled(t) => (t.solve_free)(p, u, &ws.trig, &ws.loads, friction, qdd, &mut ws.scratch),
                };
                check_friction_factor(factor)?;
                AnchorReaction { holding: 0.0, normal }
            }
            (AnchorDof::Stuck, table) => {
                let [holding, normal] = match table {
                    Table::Unrolled(t) | Table::Folded(t) => (t.solve_stuck)(p, u, &ws.trig, &ws.loads, qdd),
                    Table::Rolled(t) => (t.solve_stuck)(p, u, &ws.trig, &ws.loads, qdd, &mut ws.scratch),
                };
                AnchorReaction { holding, normal }
            }
        })
    }

    /// The scene's fused right-hand side at (q, u): states, loads and ẍ in one generated
    /// function; the powers are told to `model`, the states and loads kept in `ws` for
    /// [`Kernel::last_states`] and [`Kernel::last_loads`].
    fn solve_fused(
        &mut self,
        q: &[f64],
        u: &[f64],
        anchor: AnchorDof,
        friction: f64,
        model: &mut dyn LoadModel,
        qdd: &mut [f64],
    ) -> Result<AnchorReaction, RhsError> {
        let f = self.fusion.as_ref().expect("solve_fused runs with a fusion set");
        let (p, lp, e, ws) = (&self.params, &f.params, &f.elements, &mut self.ws);
        let (reaction, factor) = match anchor {
            AnchorDof::Free => {
                let [normal, factor] = (f.rhs.free)(p, lp, e, q, u, friction, ws, qdd);
                (AnchorReaction { holding: 0.0, normal }, factor)
            }
            AnchorDof::Stuck => {
                let [holding, normal] = (f.rhs.stuck)(p, lp, e, q, u, ws, qdd);
                (AnchorReaction { holding, normal }, 1.0)
            }
        };
        // The workspace holds the kinematics at q whether or not the solve is refused.
        self.kinematics_at(q);
        self.states_of_last_solve = true;
        self.loads_of_last_solve = true;
        check_friction_factor(factor)?;
        model.fused(&self.ws.power);
        Ok(reaction)
    }

    fn loads(&mut self, model: &mut dyn LoadModel, bodies: &[BodyState]) {
        self.loads_of_last_solve = false;
        model.loads(bodies, &mut self.loads);
        for (a, l) in self.ws.loads.iter_mut().zip(&self.loads) {
            *a = [l.fx, l.fz, l.my];
        }
    }
}

impl Kernel for GeneratedKernel {
    fn name(&self) -> &'static str {
        "generated"
    }

    fn body_count(&self) -> usize {
        self.bodies
    }

    fn form(&self) -> Option<&'static str> {
        Some(GeneratedKernel::form(self).name())
    }

    /// Any signature on the recursive path: the scene's fused right-hand side (kinematics,
    /// the signature's load code and the O(N) solve in one generated function, on the rolled
    /// steps) replaces kinematics, loads and solve. An unrolled kernel switches to the rolled
    /// one, whose steps the fused functions drive (measured faster than the unrolled kernel
    /// fed by the force modules: docs/codegen.md), and says so in [`GeneratedKernel::form`].
    /// Not on the assembled path, which reads loads, nor when the signature's water differs
    /// from the kernel's (added mass without water, or water without added mass).
    fn fuse_loads(&mut self, fused: &FusedLoads) -> bool {
        let Some(rhs) = kanestop_generated::rhs(&fused.signature.name()) else { return false };
        if self.solve_path != SolvePath::Recursive || fused.elements.len() != self.bodies || rhs.wet != self.wet {
            return false;
        }
        if let Table::Unrolled(_) | Table::Folded(_) = self.table {
            self.table = Table::Rolled(kanestop_generated::rolled(self.wet));
        }
        self.fusion = Some(Fusion { rhs, params: fused.params, elements: fused.elements.clone() });
        true
    }

    fn kinematics(&mut self, q: &[f64], u: &[f64], bodies: &mut [BodyState]) {
        self.states(q, u, bodies);
    }

    fn assemble(&mut self, q: &[f64], u: &[f64], model: &mut dyn LoadModel, out: &mut Assembly) {
        self.rows_of_last_solve = false;
        self.states(q, u, &mut out.bodies);
        self.loads(model, &out.bodies);
        let (m, f, heave) = (out.mass.as_mut_slice(), out.rhs.as_mut_slice(), &mut self.heave);
        let (p, ws) = (&self.params, &mut self.ws);
        match &self.table {
            Table::Unrolled(t) | Table::Folded(t) => (t.assemble)(p, u, &ws.trig, &ws.loads, m, f, heave),
            Table::Rolled(t) => (t.assemble)(p, u, &ws.trig, &ws.loads, m, f, heave, &mut ws.scratch),
        }
        let n = self.heave.len() - 1;
        out.heave.copy_from_slice(&self.heave[..n]);
        out.heave_rhs = self.heave[n];
    }

    fn accelerations(&mut self, q: &[f64], u: &[f64], qdd: &[f64], out: &mut [BodyAcceleration]) {
        let (kinematics, accelerations) = match &self.table {
            Table::Unrolled(t) | Table::Folded(t) => (t.kinematics, t.accelerations),
            Table::Rolled(t) => (t.kinematics, t.accelerations),
        };
        if self.trig_q != q {
            self.states_of_last_solve = false;
            kinematics(&self.params, q, u, &mut self.ws.trig, &mut self.ws.bodies);
            self.kinematics_at(q);
        }
        accelerations(&self.params, u, &self.ws.trig, qdd, &mut self.acc);
        for (o, a) in out.iter_mut().zip(&self.acc) {
            *o = BodyAcceleration { ax: a[0], az: a[1], alpha: a[2] };
        }
    }

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
        if self.solve_path == SolvePath::Assembled {
            self.assemble(q, u, model, scratch);
            return solve_assembled(scratch, anchor, friction, qdd);
        }
        self.rows_of_last_solve = false;
        let reaction = if self.fusion.is_some() {
            self.solve_fused(q, u, anchor, friction, model, qdd)?
        } else {
            self.states(q, u, &mut scratch.bodies);
            self.solve_with_loads(u, anchor, friction, model, &scratch.bodies, qdd)?
        };
        self.rows_of_last_solve = matches!(self.table, Table::Rolled(_));
        Ok(reaction)
    }

    fn last_states(&self, bodies: &mut [BodyState]) -> bool {
        if self.states_of_last_solve {
            self.copy_states(bodies);
        }
        self.states_of_last_solve
    }

    /// From `ws.loads`, where the last solve, a fused one, left them: converted only when
    /// asked (an observation on a path without the solve's rows, a report), not at every
    /// evaluation.
    fn last_loads(&self, loads: &mut [Load]) -> bool {
        if self.loads_of_last_solve {
            for (l, &[fx, fz, my]) in loads.iter_mut().zip(&self.ws.loads) {
                *l = Load { fx, fz, my };
            }
        }
        self.loads_of_last_solve
    }

    /// From the rows the last successful rolled solve left (`joint_forces` of the rolled
    /// table): the fused right-hand sides and the rolled solves keep them, the unrolled ones
    /// do not. False too when `out` does not hold N − 1 joints.
    fn joint_forces(&self, out: &mut [[f64; 2]]) -> bool {
        match &self.table {
            Table::Rolled(t) if self.rows_of_last_solve && out.len() + 1 == self.bodies => {
                (t.joint_forces)(&self.ws.scratch, out);
                true
            }
            _ => false,
        }
    }
}

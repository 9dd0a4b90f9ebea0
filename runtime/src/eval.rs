//! `eval`: one evaluation of the equations of motion, as JSON for outside checks.
//!
//! The output is a contract; its fields are documented in `docs/eval.md` and checked by
//! the schema test. Coordinates follow [`crate::kernel`]: q = (β_2 … β_N, s_11).

use nalgebra::{DMatrix, DVector, SymmetricEigen};
use serde::{Deserialize, Serialize};

use crate::dynamics::Dynamics;
use crate::forces::Forces;
use crate::kernel::{AnchorDof, Assembly, BodyAcceleration, Kernel};
use crate::model::Model;

/// A state to evaluate: `q` and `u` with N entries each; `anchor` defaults to the scene's
/// initial anchor state.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct StateFile {
    /// Generalised coordinates (β_2 … β_N in rad, s_1 in m), N entries.
    pub q: Vec<f64>,
    /// Generalised speeds (β̇_2 … β̇_N in rad/s, ṡ_1 in m/s), N entries.
    pub u: Vec<f64>,
    /// Whether the anchor is stuck or free; the scene's initial state when absent.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub anchor: Option<AnchorDof>,
}

/// One body in the eval output: centroid position, velocity and acceleration (m, m/s,
/// m/s²; x toward the ship, z up) and rotation about y (rad, rad/s, rad/s²; positive
/// turns the body's x axis downward).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct EvalBody {
    /// k of B_k (1 = anchor, N = ship).
    pub index: usize,
    /// What the body is (anchor, chain link, cable element, rod, ship).
    pub kind: String,
    /// Centroid x, m.
    pub x: f64,
    /// Centroid z, m.
    pub z: f64,
    /// Centroid velocity along x, m/s.
    pub vx: f64,
    /// Centroid velocity along z, m/s.
    pub vz: f64,
    /// Centroid acceleration along x, m/s² (Eq. 17).
    pub ax: f64,
    /// Centroid acceleration along z, m/s² (Eq. 17).
    pub az: f64,
    /// Rotation θ_k about y, rad.
    pub angle: f64,
    /// Angular velocity about y, rad/s (Eq. 9).
    pub omega: f64,
    /// Angular acceleration about y, rad/s² (Eq. 17).
    pub alpha: f64,
}

/// The eval output.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct EvalOutput {
    /// The scene's name (`meta.name`).
    pub scene: String,
    /// The kernel that evaluated the state (reference or generated).
    pub kernel: String,
    /// Physics included in f.
    pub physics: String,
    /// N.
    pub bodies_count: usize,
    /// Whether the anchor was stuck or free at the state.
    pub anchor: AnchorDof,
    /// Names of q's entries: "beta_2" … "beta_N", "s_1".
    pub coordinates: Vec<String>,
    /// Generalised coordinates, N entries (rad, last m).
    pub q: Vec<f64>,
    /// Generalised speeds, N entries (rad/s, last m/s).
    pub u: Vec<f64>,
    /// Number of active speeds n: N (anchor free) or N − 1 (stuck); M, f and qdd are over
    /// the first n coordinates.
    pub active: usize,
    /// a_lp (Eq. 26), n × n, row-major.
    #[serde(rename = "M")]
    pub mass_matrix: Vec<Vec<f64>>,
    /// f_l (Eq. 25), n entries.
    pub f: Vec<f64>,
    /// Generalised accelerations solving M qdd = f, n entries.
    pub qdd: Vec<f64>,
    /// ‖M qdd − f‖ / ‖f‖.
    pub residual: f64,
    /// 2-norm condition number of M (λ_max / λ_min).
    pub cond: f64,
    /// Every body B_1 … B_N.
    pub bodies: Vec<EvalBody>,
}

/// Why a state cannot be evaluated.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum EvalError {
    /// `state.q` or `state.u` does not have N entries.
    #[error("state.{name} has {len} entries: the scene has N = {bodies} bodies, so it needs {bodies} (β_2 … β_{bodies}, s_1)")]
    Length {
        /// `q` or `u`.
        name: &'static str,
        /// The number of entries given.
        len: usize,
        /// N.
        bodies: usize,
    },
    /// An entry of the state is infinite or NaN.
    #[error("state.{name}[{index}] = {value}: must be finite")]
    NotFinite {
        /// `q` or `u`.
        name: &'static str,
        /// 0-based position of the entry.
        index: usize,
        /// The value given.
        value: f64,
    },
    /// The right-hand side refused the state.
    #[error(transparent)]
    Dynamics(#[from] crate::kernel::RhsError),
    /// The right-hand side refused a given state: its largest entry is named, the likeliest
    /// to be out of the model's range.
    #[error("{error}; the state's largest entry is state.{name}[{index}] = {value:e}")]
    StateRefused {
        /// Why.
        error: crate::kernel::RhsError,
        /// `q` or `u`.
        name: &'static str,
        /// 0-based position of the entry.
        index: usize,
        /// Its value.
        value: f64,
    },
}

impl StateFile {
    /// Checks the state against the model: lengths N, finite values.
    pub fn check(&self, n: usize) -> Result<(), EvalError> {
        for (name, v) in [("q", &self.q), ("u", &self.u)] {
            if v.len() != n {
                return Err(EvalError::Length { name, len: v.len(), bodies: n });
            }
            if let Some(i) = v.iter().position(|x| !x.is_finite()) {
                return Err(EvalError::NotFinite { name, index: i, value: v[i] });
            }
        }
        Ok(())
    }
}

/// Names of the generalised coordinates.
pub fn coordinate_names(n: usize) -> Vec<String> {
    (2..=n).map(|k| format!("beta_{k}")).chain(std::iter::once("s_1".to_string())).collect()
}

/// Evaluates the model at `state` (or its initial state) with `kernel`.
pub fn evaluate(model: &Model, kernel: Box<dyn Kernel>, state: Option<&StateFile>) -> Result<EvalOutput, EvalError> {
    let n = model.body_count();
    let (q, mut u, anchor) = match state {
        Some(s) => {
            s.check(n)?;
            (s.q.clone(), s.u.clone(), s.anchor.unwrap_or(model.anchor))
        }
        None => (model.q0.clone(), model.u0.clone(), model.anchor),
    };
    if anchor == AnchorDof::Stuck {
        u[n - 1] = 0.0;
    }
    let kernel_name = kernel.name().to_string();
    let forces = Forces::new(model);
    let physics = forces.description();
    let mut dynamics = Dynamics::new(kernel, forces, anchor);
    let mut qdd = vec![0.0; n];
    if let Err(error) = dynamics.accelerations(&q, &u, &mut qdd) {
        let Some(_) = state else { return Err(error.into()) };
        let entries = [("q", &q), ("u", &u)]
            .into_iter()
            .flat_map(|(name, v)| v.iter().enumerate().map(move |(i, &x)| (name, i, x)));
        let (name, index, value) = entries.fold(("q", 0, 0.0_f64), |m, e| if e.2.abs() > m.2.abs() { e } else { m });
        return Err(EvalError::StateRefused { error, name, index, value });
    }
    let active = dynamics.active_speeds();
    // M and f for the report come from an assembly, whatever the kernel's solve path.
    let mut asm = Assembly::new(n);
    dynamics.assemble(&q, &u, &mut asm);
    let m: DMatrix<f64> = asm.mass.view((0, 0), (active, active)).into_owned();
    let f: DVector<f64> = asm.rhs.rows(0, active).into_owned();
    let x = DVector::from_column_slice(&qdd[..active]);
    let residual = (&m * &x - &f).norm() / f.norm().max(f64::MIN_POSITIVE);
    let eig = SymmetricEigen::new(m.clone()).eigenvalues;
    let cond = eig.max() / eig.min();
    let mut acc = vec![BodyAcceleration::default(); n];
    dynamics.body_accelerations(&q, &u, &qdd, &mut acc);
    let bodies = asm
        .bodies
        .iter()
        .zip(&acc)
        .zip(&model.chain.bodies)
        .enumerate()
        .map(|(i, ((s, a), b))| EvalBody {
            index: i + 1,
            kind: b.kind.to_string(),
            x: s.x,
            z: s.z,
            vx: s.vx,
            vz: s.vz,
            ax: a.ax,
            az: a.az,
            angle: s.theta,
            omega: s.omega,
            alpha: a.alpha,
        })
        .collect();
    Ok(EvalOutput {
        scene: model.scene.meta.name.clone(),
        kernel: kernel_name,
        physics,
        bodies_count: n,
        anchor,
        coordinates: coordinate_names(n),
        q,
        u,
        active,
        mass_matrix: (0..active).map(|i| m.row(i).iter().copied().collect()).collect(),
        f: f.iter().copied().collect(),
        qdd: qdd[..active].to_vec(),
        residual,
        cond,
        bodies,
    })
}

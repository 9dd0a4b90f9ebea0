//! The restraining system through the general formulation: speeds ẋ_l with
//! l = 5, 8, …, 3N−1 (rotations about y) and l = 3N+1 (anchor surge), Eq. 27. The anchor's
//! heave ẋ_{3N+3} is added as a constrained speed (always zero) whose Kane equation gives
//! the seabed's normal force on the anchor, as Eq. 50 does for the holding force.

use nalgebra::{Matrix3, Vector3};

use super::general::{ChainData, GeneralState, Partials, Wrench};
use crate::chain::Chain;
use crate::kernel::{Assembly, BodyAcceleration, BodyState, Kernel, Load, LoadModel};

/// The reference kernel: slow, general, literal.
pub struct ReferenceKernel {
    data: ChainData,
    /// The active speeds l (1-based): 5, 8, …, 3N−1, 3N+1.
    speeds: Vec<usize>,
    /// The same followed by the constrained anchor heave 3N+3.
    with_heave: Vec<usize>,
    loads: Vec<Load>,
    wrenches: Vec<Wrench>,
}

impl ReferenceKernel {
    /// The reference kernel of a chain: its bodies as six-speed rigid bodies (Eqs. 1–26),
    /// the planar restraining system picked out by the active speeds.
    pub fn new(chain: &Chain) -> Self {
        let n = chain.len();
        let planar = |v: [f64; 2]| Vector3::new(v[0], 0.0, v[1]);
        let data = ChainData {
            mass: chain.bodies.iter().map(|b| b.mass).collect(),
            inertia: chain.bodies.iter().map(|b| Matrix3::from_diagonal(&Vector3::from(b.inertia))).collect(),
            r: chain.bodies.iter().map(|b| planar(b.centroid)).collect(),
            q: chain.bodies.iter().map(|b| planar(b.joint)).collect(),
            // A cylinder's added mass acts across its axis (body y and z), Eq. 46.
            added_mass: chain
                .bodies
                .iter()
                .map(|b| Matrix3::from_diagonal(&Vector3::new(0.0, b.added_mass, b.added_mass)))
                .collect(),
            added_inertia: chain
                .bodies
                .iter()
                .map(|b| Matrix3::from_diagonal(&Vector3::new(0.0, b.added_inertia, b.added_inertia)))
                .collect(),
        };
        let mut speeds: Vec<usize> = (2..=n).map(|k| 3 * (k - 1) + 2).collect();
        speeds.push(3 * n + 1);
        let with_heave = speeds.iter().copied().chain([3 * n + 3]).collect();
        ReferenceKernel {
            data,
            speeds,
            with_heave,
            loads: vec![Load::default(); n],
            wrenches: vec![Wrench::default(); n],
        }
    }

    fn n(&self) -> usize {
        self.data.mass.len()
    }

    /// Euler parameters (Eq. 2), translations and the 6N-long ẋ for the planar state.
    fn general_state(&self, q: &[f64], u: &[f64]) -> (Vec<[f64; 4]>, Vec<Vector3<f64>>, Vec<f64>) {
        let n = self.n();
        assert_eq!(q.len(), n, "q must have N entries");
        assert_eq!(u.len(), n, "u must have N entries");
        let mut euler = vec![[0.0, 0.0, 0.0, 1.0]; n];
        for k in 2..=n {
            let beta = q[k - 2];
            euler[k - 1] = [0.0, (beta / 2.0).sin(), 0.0, (beta / 2.0).cos()];
        }
        let mut s = vec![Vector3::zeros(); n];
        s[0] = Vector3::new(q[n - 1], 0.0, 0.0);
        let mut x_dot = vec![0.0; 6 * n];
        for (i, &l) in self.speeds.iter().enumerate() {
            x_dot[l - 1] = u[i];
        }
        (euler, s, x_dot)
    }

    /// The arrays for the active speeds, or with the heave speed appended.
    fn partials(&self, q: &[f64], u: &[f64], heave: bool) -> (Partials, Vec<f64>) {
        let (euler, s, x_dot) = self.general_state(q, u);
        let speeds = if heave { &self.with_heave } else { &self.speeds };
        let partials = Partials::new(&self.data, &GeneralState { euler: &euler, s: &s, x_dot: &x_dot }, speeds);
        (partials, x_dot)
    }

    fn body_states(&self, q: &[f64], partials: &Partials, x_dot: &[f64], bodies: &mut [BodyState]) {
        let mut theta = 0.0;
        for (k, body) in bodies.iter_mut().enumerate().map(|(i, b)| (i + 1, b)) {
            if k >= 2 {
                theta += q[k - 2];
            }
            let p = partials.position[k];
            let v = partials.velocity(k, x_dot);
            let (sin, cos) = theta.sin_cos();
            *body = BodyState { x: p.x, z: p.z, theta, cos, sin, vx: v.x, vz: v.z, omega: partials.omega[k].y };
        }
    }
}

impl Kernel for ReferenceKernel {
    fn name(&self) -> &'static str {
        "reference"
    }

    fn body_count(&self) -> usize {
        self.n()
    }

    fn kinematics(&mut self, q: &[f64], u: &[f64], bodies: &mut [BodyState]) {
        let (partials, x_dot) = self.partials(q, u, false);
        self.body_states(q, &partials, &x_dot, bodies);
    }

    fn assemble(&mut self, q: &[f64], u: &[f64], model: &mut dyn LoadModel, out: &mut Assembly) {
        let (partials, x_dot) = self.partials(q, u, true);
        self.body_states(q, &partials, &x_dot, &mut out.bodies);
        model.loads(&out.bodies, &mut self.loads);
        for (w, l) in self.wrenches.iter_mut().zip(&self.loads) {
            *w = Wrench { force: Vector3::new(l.fx, 0.0, l.fz), moment: Vector3::new(0.0, l.my, 0.0) };
        }
        let (a, f) = partials.kane_equations(&self.data, &x_dot, &self.wrenches);
        let n = self.n();
        out.mass.copy_from(&a.view((0, 0), (n, n)));
        out.rhs.copy_from(&f.rows(0, n));
        out.heave.copy_from(&a.view((n, 0), (1, n)).transpose());
        out.heave_rhs = f[n];
    }

    fn accelerations(&mut self, q: &[f64], u: &[f64], qdd: &[f64], out: &mut [BodyAcceleration]) {
        let (partials, x_dot) = self.partials(q, u, false);
        let n = self.n();
        let mut x_ddot = vec![0.0; 6 * n];
        for (i, &l) in self.speeds.iter().enumerate() {
            x_ddot[l - 1] = qdd[i];
        }
        for (k, acc) in out.iter_mut().enumerate().map(|(i, a)| (i + 1, a)) {
            let (a, alpha) = partials.acceleration(k, &x_dot, &x_ddot);
            *acc = BodyAcceleration { ax: a.x, az: a.z, alpha: alpha.y };
        }
    }
}

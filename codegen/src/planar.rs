//! The expansion of the planar Kane quantities of a restraining chain into the DAG.
//!
//! For the chain every generalised speed is a rotation about y (β̇_k, k = 2 … N) or the
//! anchor's surge ṡ_1, so the general arrays of Eqs. 9–16 collapse to planar vectors:
//!
//! - the partial angular velocity of B_k for β̇_j is ω_kj = 1 for j ≤ k (Eq. 10: the y
//!   column of S^(0,j−1)), 0 otherwise, and its time derivative is zero (Eq. 12);
//! - the partial velocity of C_k for β̇_j is v_kj = J(p_k − o_j), j ≤ k, where J(x, z) =
//!   (z, −x) is the rotation through +90° about y (Eq. 15); for ṡ_1 it is (1, 0);
//! - the velocity products of Eq. 16 are the centripetal terms −θ̇_w² (S^(0w) q_v) and
//!   −θ̇_k² S^(0k) r_k, and the gyroscopic term of Eq. 22 vanishes (ω ∥ I ω).
//!
//! Hence, with the translational inertia A_k = m_k 1 + m_a,k n_k n_kᵀ (n_k the body's z
//! axis, Eq. 46) and B_k = J ᵀ A_k J = m_k 1 + m_a,k t_k t_kᵀ (t_k its x axis):
//!
//! - a_{β_j β_l} = J_l + (o_l − o_j) · S_l for j ≤ l (Eq. 26), with the outboard sums
//!   S_l = Σ_{k≥l} B_k (p_k − o_l) and J_l = Σ_{k≥l} (p_k − o_l)ᵀ B_k (p_k − o_l) + I_k
//!   built once, from the ship inward;
//! - a_{β_j s} = (S_j)_z and a_{s s} = Σ_k (A_k)_xx;
//! - f_{β_j} = Σ_{k≥j} (p_k − o_j) × F̃_k + T_k and f_s = Σ_k F̃_kx (Eqs. 23, 25), with
//!   F̃_k = F_k − A_k ȧ_k, ȧ_k the velocity-product acceleration of C_k (Eq. 16).
//!
//! Everything but the a_lp entries is O(N); the entries are O(N²), four flops each, and
//! the dense block of them is filled by a fixed loop nest over O(N) arrays.
//!
//! The O(N) solve is an articulated-body recursion on the same quantities, written at each
//! body's origin o_k with (angular, x, z) components: articulated inertias and bias forces
//! from the ship inward, then accelerations outward (see [`solve`]).
//!
//! Indices: bodies are 0-based here (`k` = B_{k+1}) and 1-based in emitted names; the
//! a_lp names use the 0-based coordinate indices of `q` (`a_i_j` is `M[i][j]`).

use kanestop_chain::{ParamField, Variant};

use crate::body::{
    acceleration_step, add2, anchor_solve, angle_step, articulated_body, centripetal_step, centroid_kinematics,
    effective_force, eliminate_hinge, force_sums, hinge_kinematics, name2, outboard_step, outward_step, rot,
    Articulated, BodySyms, Outboard, V2,
};
use crate::expr::{Dag, Id};

/// The numeric parameters of every body, as DAG inputs with the structural zeros folded.
struct Params {
    mass: Vec<Id>,
    inertia: Vec<Id>,
    /// r_k in body axes.
    centroid: Vec<V2>,
    /// q_k in the inner body's axes (k = 0: the anchor origin, inertial).
    joint: Vec<V2>,
    added_mass: Vec<Id>,
}

/// One body's parameter values, for a kernel with a scene's numbers folded in.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct BodyValues {
    /// m_k, kg.
    pub mass: f64,
    /// I_yy plus the added inertia, kg·m².
    pub inertia: f64,
    /// r_k in body axes, m.
    pub centroid: [f64; 2],
    /// q_k in the inner body's axes, m.
    pub joint: [f64; 2],
    /// m_a,k, kg.
    pub added_mass: f64,
}

/// Where a kernel's body parameters come from.
#[derive(Clone, Copy, Debug)]
pub enum ParamSource<'a> {
    /// Runtime inputs `p[k].…`: one kernel serves every scene of the variant (the default).
    Inputs,
    /// One scene's values as literals, which the DAG folds (`kanestop codegen --scene` reports
    /// the effect on the operation counts).
    Folded(&'a [BodyValues]),
}

/// Which parameters a kernel of `variant` reads; the rest are structurally zero and the
/// runtime checks that the chain agrees ([`Variant::structural_zeros`]).
fn params(dag: &mut Dag, variant: Variant, source: ParamSource) -> Params {
    let n = variant.bodies;
    let zero = dag.zero();
    let mut p = Params { mass: vec![], inertia: vec![], centroid: vec![], joint: vec![], added_mass: vec![] };
    let value = |dag: &mut Dag, k: usize, name: &str, get: fn(&BodyValues) -> f64| match source {
        ParamSource::Inputs => dag.input(format!("p[{k}].{name}")),
        ParamSource::Folded(values) => dag.constant(get(&values[k])),
    };
    for k in 0..n {
        p.mass.push(value(dag, k, "mass", |b| b.mass));
        p.inertia.push(if k == 0 { zero } else { value(dag, k, "inertia", |b| b.inertia) });
        let cx = value(dag, k, "centroid[0]", |b| b.centroid[0]);
        let cz = if variant.folds(k, ParamField::CentroidZ) {
            zero
        } else {
            value(dag, k, "centroid[1]", |b| b.centroid[1])
        };
        p.centroid.push([cx, cz]);
        let jx = value(dag, k, "joint[0]", |b| b.joint[0]);
        let jz = if variant.folds(k, ParamField::JointZ) { zero } else { value(dag, k, "joint[1]", |b| b.joint[1]) };
        p.joint.push([jx, jz]);
        let folded = variant.folds(k, ParamField::AddedMass);
        p.added_mass.push(if folded { zero } else { value(dag, k, "added_mass", |b| b.added_mass) });
    }
    p
}

/// The kinematic quantities every phase needs, from (cos θ_k, sin θ_k) and u.
struct Kin {
    n: usize,
    p: Params,
    /// (cos θ_k, sin θ_k).
    cs: Vec<V2>,
    /// θ̇_k.
    omega: Vec<Id>,
    /// d_k = S^(0,k−1) q_k: o_{k−1} → o_k, inertial (k ≥ 1; d_0 unused).
    d: Vec<V2>,
    /// e_k = S^(0k) r_k: o_k → C_k, inertial.
    e: Vec<V2>,
}

impl Kin {
    fn new(dag: &mut Dag, variant: Variant, source: ParamSource, cs: Vec<V2>) -> Kin {
        let n = variant.bodies;
        let p = params(dag, variant, source);
        let zero = dag.zero();
        let mut omega = vec![zero; n];
        for k in 1..n {
            let u = dag.input(format!("u[{}]", k - 1));
            omega[k] = dag.add(omega[k - 1], u);
            dag.name(omega[k], format!("w_{}", k + 1));
        }
        let mut d = vec![[zero, zero]; n];
        let mut e = vec![[zero, zero]; n];
        for k in 0..n {
            if k > 0 {
                let v = rot(dag, cs[k - 1], p.joint[k]);
                d[k] = name2(dag, v, &format!("d_{}", k + 1));
            }
            let v = rot(dag, cs[k], p.centroid[k]);
            e[k] = name2(dag, v, &format!("e_{}", k + 1));
        }
        Kin { n, p, cs, omega, d, e }
    }

    /// Trigonometric values read from the `trig` argument (B_1 does not rotate).
    fn trig_inputs(dag: &mut Dag, n: usize) -> Vec<V2> {
        let mut cs = vec![[dag.one(), dag.zero()]];
        for k in 1..n {
            cs.push([dag.input(format!("trig[{k}][0]")), dag.input(format!("trig[{k}][1]"))]);
        }
        cs
    }

    /// The symbols of B_{k+1}.
    fn body(&self, k: usize) -> BodySyms {
        BodySyms {
            mass: self.p.mass[k],
            inertia: self.p.inertia[k],
            centroid: self.p.centroid[k],
            added_mass: self.p.added_mass[k],
            cs: self.cs[k],
            omega: self.omega[k],
            e: self.e[k],
        }
    }

    /// The velocity-product (centripetal) accelerations of every C_k (Eq. 16 times ẋ):
    /// ȧ_k = −Σ_{w<k} θ̇_w² d_{w+1} − θ̇_k² e_k.
    fn centripetal(&self, dag: &mut Dag) -> Vec<V2> {
        let zero = dag.zero();
        let mut origin = [zero, zero];
        let mut out = Vec::with_capacity(self.n);
        for k in 0..self.n {
            let hinge = (k > 0).then(|| (self.d[k], self.omega[k - 1]));
            let [o, a] = centripetal_step(dag, &self.body(k), origin, hinge, &format!("_{}", k + 1));
            origin = o;
            out.push(a);
        }
        out
    }

    /// F̃_k = F_k − A_k ȧ_k and T_k, from the `loads` argument.
    fn effective_loads(&self, dag: &mut Dag) -> Vec<(V2, Id)> {
        let acc = self.centripetal(dag);
        (0..self.n)
            .map(|k| {
                let f = [dag.input(format!("loads[{k}][0]")), dag.input(format!("loads[{k}][1]"))];
                let t = dag.input(format!("loads[{k}][2]"));
                (effective_force(dag, &self.body(k), acc[k], f, &format!("_{}", k + 1)), t)
            })
            .collect()
    }
}

/// An output place of a kernel: `array[index]`, or `array[index][component]` for an array
/// of small arrays. Kept typed here; [`crate::emit`] renders it as Rust.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct Slot {
    /// The argument or local array written (`m`, `qdd`, `bodies`, …).
    pub array: &'static str,
    /// The outer index.
    pub index: usize,
    /// The inner index, for arrays of small arrays (`bodies[k][j]`).
    pub component: Option<usize>,
}

impl Slot {
    /// `array[index]`.
    pub fn at(array: &'static str, index: usize) -> Slot {
        Slot { array, index, component: None }
    }

    /// `array[index][component]`.
    pub fn at2(array: &'static str, index: usize, component: usize) -> Slot {
        Slot { array, index, component: Some(component) }
    }
}

/// One output: `slot = value;`.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Store {
    /// Where the value goes.
    pub slot: Slot,
    /// What is stored.
    pub value: Id,
}

/// A function body: where each output goes.
pub struct Function {
    pub dag: Dag,
    /// The stores, emitted in order.
    pub stores: Vec<Store>,
    /// The returned values: none, one (`-> f64`) or several (`-> [f64; n]`).
    pub ret: Vec<Id>,
    /// `Some(N)` when, with N ≥ 4, the dense block of a_lp over the coordinates
    /// 1 ≤ j < l ≤ N − 2 is filled after the stores by a fixed loop nest,
    /// a_jl = K_l − ō_j · S_l, from the local arrays `k_col`, `s_col` and `o_rel` that the
    /// stores fill (see [`assemble`]).
    pub dense_fill: Option<usize>,
}

impl Function {
    pub(crate) fn new(dag: Dag) -> Self {
        Function { dag, stores: Vec::new(), ret: Vec::new(), dense_fill: None }
    }

    /// Appends the store `slot = value;`.
    pub(crate) fn store(&mut self, slot: Slot, value: Id) {
        self.stores.push(Store { slot, value });
    }

    /// Every value the function computes.
    pub fn roots(&self) -> Vec<Id> {
        self.stores.iter().map(|s| s.value).chain(self.ret.iter().copied()).collect()
    }
}

/// Body states and the rotation table: θ_k, (cos θ_k, sin θ_k), centroid positions
/// (Eq. 13) and velocities (Eq. 14), ω_k (Eq. 9).
pub fn kinematics(variant: Variant) -> Function {
    kinematics_with(variant, ParamSource::Inputs)
}

/// [`kinematics`] with the parameters from `source`.
pub fn kinematics_with(variant: Variant, source: ParamSource) -> Function {
    let n = variant.bodies;
    let mut dag = Dag::new();
    let zero = dag.zero();
    let mut theta = vec![zero; n];
    let mut cs = vec![[dag.one(), zero]];
    for k in 1..n {
        let q = dag.input(format!("q[{}]", k - 1));
        let (t, c) = angle_step(&mut dag, theta[k - 1], q, &format!("_{}", k + 1));
        theta[k] = t;
        cs.push(c);
    }
    let kin = Kin::new(&mut dag, variant, source, cs);
    let mut f = Function::new(Dag::new());
    // o_1 = q_1 + (s_1, 0); o_k = o_{k−1} + d_k; velocities by the same recursion.
    let s1 = dag.input(format!("q[{}]", n - 1));
    let s1_dot = dag.input(format!("u[{}]", n - 1));
    let mut origin = [dag.add(kin.p.joint[0][0], s1), kin.p.joint[0][1]];
    let mut origin_v = [s1_dot, zero];
    for (k, &theta_k) in theta.iter().enumerate() {
        if k > 0 {
            [origin, origin_v] =
                hinge_kinematics(&mut dag, [origin, origin_v], kin.d[k], kin.omega[k - 1], &format!("_{}", k + 1));
        }
        let [pos, vel] = centroid_kinematics(&mut dag, &kin.body(k), [origin, origin_v], &format!("_{}", k + 1));
        for (j, v) in [pos[0], pos[1], theta_k, vel[0], vel[1], kin.omega[k]].into_iter().enumerate() {
            f.store(Slot::at2("bodies", k, j), v);
        }
    }
    for k in 0..n {
        f.store(Slot::at2("trig", k, 0), kin.cs[k][0]);
        f.store(Slot::at2("trig", k, 1), kin.cs[k][1]);
    }
    f.dag = dag;
    f
}

/// a_lp (Eq. 26) over all N speeds, both triangles, and f_l (Eq. 25) with the loads
/// projected by Eq. 23; plus the row of the anchor's heave speed w = ẋ_{3N+3}, which is
/// always constrained: `heave[p]` = a_{w,p} for the N active speeds and `heave[N]` = f_w,
/// so that the seabed's normal force on the anchor is N = a_{w,p} ẍ_p − f_w (Eq. 50 for
/// the vertical; Eq. 37).
///
/// The heave speed moves every centroid by (0, 1), so a_{w,β_l} = Σ_{k≥l} e_zᵀ A_k J(p_k −
/// o_l) = −(S_l)_x (J(−1, 0) = e_z), a_{w,s} = Σ_k (A_k)_xz = Σ m_a,k sin θ_k cos θ_k and
/// f_w = Σ_k F̃_kz.
pub fn assemble(variant: Variant) -> Function {
    assemble_with(variant, ParamSource::Inputs)
}

// Long by design: the phases must create DAG nodes in this order (the emitted text is checked in).
/// [`assemble`] with the parameters from `source`.
pub fn assemble_with(variant: Variant, source: ParamSource) -> Function {
    let n = variant.bodies;
    let mut dag = Dag::new();
    let cs = Kin::trig_inputs(&mut dag, n);
    let kin = Kin::new(&mut dag, variant, source, cs);
    let zero = dag.zero();
    let mut f = Function::new(Dag::new());

    // Outboard sums from the ship inward: Btot_l = Σ B_k, S_l, J_l (about o_l).
    let mut s_l = vec![[zero, zero]; n];
    let mut j_l = vec![zero; n];
    let mut next: Option<Outboard> = None;
    for l in (1..n).rev() {
        let child = next.map(|c| (c, kin.d[l + 1], kin.p.joint[l + 1]));
        let sums = outboard_step(&mut dag, &kin.body(l), child, &format!("_{}", l + 1));
        s_l[l] = sums.s;
        j_l[l] = sums.j;
        next = Some(sums);
    }

    // a_{β_j β_l} = J_l + (o_l − o_j) · S_l = K_l − ō_j · S_l for j < l, with the hinge
    // positions ō_j = o_j − o_2 relative to the first hinge and K_l = J_l + ō_l · S_l: four
    // flops per entry. (Relative to o_2 the cancellation is bounded by the chain's length.)
    let mut rel = vec![[zero, zero]; n];
    for j in 2..n {
        let o = add2(&mut dag, rel[j - 1], kin.d[j]);
        rel[j] = name2(&mut dag, o, &format!("o_{}", j + 1));
    }
    //
    // Row 0 (j = B_2, ō = 0) is K_l. The rest of the dense block, 1 ≤ j < l ≤ N − 2 in
    // coordinates, is O(N²) with the same four flops everywhere: it is left to a fixed loop
    // nest over the arrays stored here (`k_col`, `s_col` by l, `o_rel` by j), which keeps the
    // build time of large kernels linear in N (see docs/codegen.md).
    let mut entries: Vec<(usize, usize, Id)> = Vec::new();
    for l in 1..n {
        let os = dag.dot2(rel[l], s_l[l]);
        let k_l = dag.add(j_l[l], os);
        let k_l = dag.name(k_l, format!("k_{}", l + 1));
        if l >= 2 {
            entries.push((0, l - 1, k_l));
        }
        let c = l - 1; // coordinate of β_{l+1}
        if (2..=n - 2).contains(&c) {
            f.store(Slot::at("k_col", c), k_l);
            f.store(Slot::at2("s_col", c, 0), s_l[l][0]);
            f.store(Slot::at2("s_col", c, 1), s_l[l][1]);
        }
        if (1..=n - 3).contains(&c) {
            f.store(Slot::at2("o_rel", c, 0), rel[l][0]);
            f.store(Slot::at2("o_rel", c, 1), rel[l][1]);
        }
        entries.push((l - 1, l - 1, j_l[l]));
        // a_{β_l s} = (S_l)_z.
        entries.push((l - 1, n - 1, s_l[l][1]));
        // a_{w β_l} = −(S_l)_x.
        let a_w = dag.neg(s_l[l][0]);
        let a_w = dag.name(a_w, format!("a_w_{}", l - 1));
        f.store(Slot::at("heave", l - 1), a_w);
    }
    f.dense_fill = (n >= 4).then_some(n);
    // a_{ss} = Σ m_k + m_a,k sin²θ_k and a_{ws} = Σ m_a,k sin θ_k cos θ_k.
    let mut ass = zero;
    let mut aws = zero;
    for k in 0..n {
        let [c, s] = kin.cs[k];
        let s2 = dag.mul(s, s);
        let a = dag.mul(kin.p.added_mass[k], s2);
        let t = dag.add(kin.p.mass[k], a);
        ass = dag.add(ass, t);
        let sc = dag.mul(s, c);
        let a = dag.mul(kin.p.added_mass[k], sc);
        aws = dag.add(aws, a);
    }
    entries.push((n - 1, n - 1, ass));
    let aws = dag.name(aws, format!("a_w_{}", n - 1));
    f.store(Slot::at("heave", n - 1), aws);
    entries.sort_by_key(|&(i, j, _)| (i, j));
    for &(i, j, a) in &entries {
        dag.name(a, format!("a_{i}_{j}"));
        f.store(Slot::at("m", i * n + j), a);
        if i != j {
            f.store(Slot::at("m", j * n + i), a);
        }
    }

    // f: G_l = Σ_{k≥l} F̃_k, H_l = Σ_{k≥l} (p_k − o_l) × F̃_k + T_k.
    let loads = kin.effective_loads(&mut dag);
    let mut g = [zero, zero];
    let mut h = zero;
    let mut rhs = vec![zero; n];
    for k in (0..n).rev() {
        let (fe, t) = loads[k];
        let e = (k > 0).then_some(kin.e[k]);
        let d_child = (k > 0 && k + 1 < n).then(|| kin.d[k + 1]);
        let (g_k, h_k) = force_sums(&mut dag, e, fe, t, (g, h), d_child, &format!("_{}", k + 1));
        if let Some(h_k) = h_k {
            h = h_k;
            rhs[k - 1] = dag.name(h, format!("f_{}", k - 1));
        }
        g = g_k;
    }
    rhs[n - 1] = dag.name(g[0], format!("f_{}", n - 1));
    for (i, &v) in rhs.iter().enumerate() {
        f.store(Slot::at("f", i), v);
    }
    let f_w = dag.name(g[1], "f_w");
    f.store(Slot::at("heave", n), f_w);
    f.dag = dag;
    f
}

/// Body accelerations for generalised accelerations `qdd` (Eq. 17): a_k = v_kl ẍ_l +
/// v̇_kl ẋ_l, α_k = ω_kl ẍ_l.
pub fn accelerations(variant: Variant) -> Function {
    accelerations_with(variant, ParamSource::Inputs)
}

/// [`accelerations`] with the parameters from `source`.
pub fn accelerations_with(variant: Variant, source: ParamSource) -> Function {
    let n = variant.bodies;
    let mut dag = Dag::new();
    let cs = Kin::trig_inputs(&mut dag, n);
    let kin = Kin::new(&mut dag, variant, source, cs);
    let zero = dag.zero();
    let mut f = Function::new(Dag::new());
    let s_dd = dag.input(format!("qdd[{}]", n - 1));
    let mut alpha = zero;
    let mut origin_a = [s_dd, zero];
    for k in 0..n {
        let hinge = (k > 0).then(|| (kin.d[k], kin.omega[k - 1], dag.input(format!("qdd[{}]", k - 1))));
        let (al, ao, a) = acceleration_step(&mut dag, &kin.body(k), (alpha, origin_a), hinge, &format!("_{}", k + 1));
        (alpha, origin_a) = (al, ao);
        f.store(Slot::at2("acc", k, 0), a[0]);
        f.store(Slot::at2("acc", k, 1), a[1]);
        f.store(Slot::at2("acc", k, 2), alpha);
    }
    f.dag = dag;
    f
}

/// The O(N) solve of a_lp ẍ_p = f_l by articulated-body recursion.
///
/// At each body origin o_k, with (angular, x, z) components and point accelerations
/// (α_k, a_{o_k}): the rigid inertia of B_k is [[I + eᵀBe, (J(Be))ᵀ], [J(Be), A]] (the
/// partial velocities of Eq. 15 at o_k), its bias the centripetal force −θ̇_k² A e (and
/// its moment), minus the applied load. Inward, the articulated inertia IA_k and bias pA_k
/// of the outboard subchain absorb each hinge (smooth: no joint moment): the hinge's row is
/// eliminated and the rest is carried across d_k to o_{k−1}. Outward, each hinge's
/// acceleration follows from its row. With the anchor free ẍ_s = −pA_1x / IA_1xx, or with
/// the sliding friction −k N taken implicitly, ẍ_s = −(pA_1x + k pA_1z) / (IA_1xx + k IA_1xz);
/// with it stuck ẍ_s = 0 and pA_1x is the holding force of Eq. 50. Both return the seabed's
/// normal force N = IA_1xz ẍ_s + pA_1z (Eq. 37).
pub fn solve(variant: Variant, stuck: bool) -> Function {
    solve_with(variant, stuck, ParamSource::Inputs)
}

// Long by design: the recursion reads as one inward and one outward pass, in node order.
/// [`solve`] with the parameters from `source`.
pub fn solve_with(variant: Variant, stuck: bool, source: ParamSource) -> Function {
    let n = variant.bodies;
    let mut dag = Dag::new();
    let cs = Kin::trig_inputs(&mut dag, n);
    let kin = Kin::new(&mut dag, variant, source, cs);
    let zero = dag.zero();
    dag.one();
    let loads = raw_loads(&mut dag, n);
    let mut f = Function::new(Dag::new());

    // Inward pass. ia[k] = IA_k as [00, 01, 02, 11, 12, 22]; pa[k] = pA_k.
    let mut ia: Vec<[Id; 6]> = vec![[zero; 6]; n];
    let mut pa: Vec<[Id; 3]> = vec![[zero; 3]; n];
    let mut gains = vec![[zero; 3]; n];
    // Carried from the child: (Xᵀ Ia X) as [00, 01, 02, 11, 12, 22] and Xᵀ(Ia c + pa).
    let mut carry: Option<Articulated> = None;
    for k in (0..n).rev() {
        let tag = format!("_{}", k + 1);
        let (i, p) = articulated_body(&mut dag, &kin.body(k), loads[k], carry, &tag);
        ia[k] = i;
        pa[k] = p;
        if k == 0 {
            break;
        }
        let (g, c, _) = eliminate_hinge(&mut dag, (i, p), kin.d[k], kin.omega[k - 1], &tag);
        gains[k] = g;
        carry = Some(c);
    }
    let (s_dd, ret) = anchor_solve(&mut dag, (ia[0], pa[0]), stuck);
    f.ret = ret;
    f.store(Slot::at("qdd", n - 1), s_dd);

    // Outward pass: (α, a_o) of each body; α_k = −(IA_01 â_x + IA_02 â_z + pA_0) / D, with
    // the divisions by D done in the inward pass (the hinge's gains).
    let mut alpha = zero;
    let mut acc = [s_dd, zero];
    for (k, &g) in gains.iter().enumerate().skip(1) {
        let tags = (format!("_{}", k + 1), format!("_{}", k - 1));
        let (new_alpha, a, beta_dd) =
            outward_step(&mut dag, kin.d[k], kin.omega[k - 1], alpha, acc, g, &tags.0, &tags.1);
        f.store(Slot::at("qdd", k - 1), beta_dd);
        alpha = new_alpha;
        acc = a;
    }
    f.stores.sort_by_key(|s| s.slot.index);
    f.dag = dag;
    f
}

fn raw_loads(dag: &mut Dag, n: usize) -> Vec<(V2, Id)> {
    (0..n)
        .map(|k| {
            let f = [dag.input(format!("loads[{k}][0]")), dag.input(format!("loads[{k}][1]"))];
            (f, dag.input(format!("loads[{k}][2]")))
        })
        .collect()
}

#[cfg(test)]
// Matrix rows and columns read best by index.
#[allow(clippy::needless_range_loop)]
mod tests {
    use std::collections::HashMap;

    use kanestop_chain::{ParamField, Variant, Water};

    use super::{accelerations, assemble, kinematics, solve, Function, Slot};

    /// Parameters of one body, with the variant's structural zeros applied.
    #[derive(Clone, Copy)]
    struct P {
        mass: f64,
        inertia: f64,
        centroid: [f64; 2],
        joint: [f64; 2],
        added_mass: f64,
    }

    /// A small chain with every parameter distinct (the folded ones zeroed).
    fn chain(v: Variant) -> Vec<P> {
        (0..v.bodies)
            .map(|k| {
                let kf = k as f64;
                let mut p = P {
                    mass: 3.0 + 1.5 * kf,
                    inertia: if k == 0 { 0.0 } else { 0.4 + 0.3 * kf },
                    centroid: [0.6 + 0.1 * kf, 0.25 - 0.05 * kf],
                    joint: [1.1 + 0.2 * kf, 0.3 + 0.1 * kf],
                    added_mass: 0.7 + 0.2 * kf,
                };
                if v.folds(k, ParamField::CentroidZ) {
                    p.centroid[1] = 0.0;
                }
                if v.folds(k, ParamField::JointZ) {
                    p.joint[1] = 0.0;
                }
                if v.folds(k, ParamField::AddedMass) {
                    p.added_mass = 0.0;
                }
                p
            })
            .collect()
    }

    /// The kernels' inputs by name, for [`crate::expr::Dag::eval`].
    #[derive(Default)]
    struct Inputs(HashMap<String, f64>);

    impl Inputs {
        fn new(ps: &[P]) -> Self {
            let mut i = Inputs::default();
            for (k, p) in ps.iter().enumerate() {
                i.set(format!("p[{k}].mass"), p.mass);
                i.set(format!("p[{k}].inertia"), p.inertia);
                i.set(format!("p[{k}].centroid[0]"), p.centroid[0]);
                i.set(format!("p[{k}].centroid[1]"), p.centroid[1]);
                i.set(format!("p[{k}].joint[0]"), p.joint[0]);
                i.set(format!("p[{k}].joint[1]"), p.joint[1]);
                i.set(format!("p[{k}].added_mass"), p.added_mass);
            }
            i
        }

        fn set(&mut self, name: String, v: f64) {
            self.0.insert(name, v);
        }

        fn array(&mut self, name: &str, values: &[f64]) {
            for (i, &v) in values.iter().enumerate() {
                self.set(format!("{name}[{i}]"), v);
            }
        }

        /// θ_k and the rotation table of the coordinates q.
        fn trig(&mut self, q: &[f64]) {
            for (k, t) in absolute_angles(q).into_iter().enumerate() {
                self.set(format!("trig[{k}][0]"), t.cos());
                self.set(format!("trig[{k}][1]"), t.sin());
            }
        }

        fn loads(&mut self, loads: &[[f64; 3]]) {
            for (k, l) in loads.iter().enumerate() {
                for (j, &v) in l.iter().enumerate() {
                    self.set(format!("loads[{k}][{j}]"), v);
                }
            }
        }

        /// Every store and returned value of `f`.
        fn run(&self, f: &Function) -> (HashMap<Slot, f64>, Vec<f64>) {
            let roots = f.roots();
            let values = f.dag.eval(&roots, &mut |name| {
                *self.0.get(name).unwrap_or_else(|| panic!("the kernel reads an unknown input `{name}`"))
            });
            let stores = f.stores.iter().zip(&values).map(|(s, &v)| (s.slot, v)).collect();
            (stores, values[f.stores.len()..].to_vec())
        }
    }

    /// θ_1 = 0, θ_k = β_2 + … + β_k.
    fn absolute_angles(q: &[f64]) -> Vec<f64> {
        let n = q.len();
        let mut theta = vec![0.0; n];
        for k in 1..n {
            theta[k] = theta[k - 1] + q[k - 1];
        }
        theta
    }

    /// R(θ) v with the paper's rotation about y.
    fn rot(theta: f64, v: [f64; 2]) -> [f64; 2] {
        let (s, c) = theta.sin_cos();
        [v[0] * c + v[1] * s, -v[0] * s + v[1] * c]
    }

    /// Centroid positions by direct forward kinematics (Eq. 13).
    fn centroids(ps: &[P], q: &[f64]) -> Vec<[f64; 2]> {
        let n = ps.len();
        let theta = absolute_angles(q);
        let mut o = [ps[0].joint[0] + q[n - 1], ps[0].joint[1]];
        let mut out = Vec::new();
        for k in 0..n {
            if k > 0 {
                let d = rot(theta[k - 1], ps[k].joint);
                o = [o[0] + d[0], o[1] + d[1]];
            }
            let e = rot(theta[k], ps[k].centroid);
            out.push([o[0] + e[0], o[1] + e[1]]);
        }
        out
    }

    fn axpy(q: &[f64], h: f64, u: &[f64]) -> Vec<f64> {
        q.iter().zip(u).map(|(a, b)| a + h * b).collect()
    }

    fn state(n: usize) -> (Vec<f64>, Vec<f64>) {
        let q: Vec<f64> = (0..n).map(|k| 0.3 - 0.17 * k as f64).collect();
        let u: Vec<f64> = (0..n).map(|k| 0.5 + 0.11 * k as f64 * if k % 2 == 0 { 1.0 } else { -1.0 }).collect();
        (q, u)
    }

    #[test]
    fn kinematics_of_a_three_body_chain_by_hand() {
        let v = Variant::new(3, Water::Off);
        let mut ps = chain(v);
        ps[0].joint = [0.0, 0.0];
        ps[0].centroid = [0.5, 0.25];
        ps[1].joint = [1.0, 0.5];
        ps[1].centroid = [0.5, 0.0];
        ps[2].joint = [1.0, 0.0];
        ps[2].centroid = [-0.2, 0.3];
        let q = [std::f64::consts::FRAC_PI_2, -std::f64::consts::FRAC_PI_2, 2.0];
        let mut i = Inputs::new(&ps);
        i.array("q", &q);
        i.array("u", &[0.0; 3]);
        let (s, _) = i.run(&kinematics(v));
        // o_1 = (2, 0); B_2 hangs straight down from o_2 = (3, 0.5); B_3 is level again at
        // o_3 = (3, −0.5).
        let expected = [[2.5, 0.25], [3.0, 0.0], [2.8, -0.2]];
        for (k, e) in expected.iter().enumerate() {
            for (j, &x) in e.iter().enumerate() {
                let got = s[&Slot::at2("bodies", k, j)];
                assert!((got - x).abs() < 1e-12, "body {k} coordinate {j}: {got} vs {x}");
            }
        }
        assert!((s[&Slot::at2("bodies", 1, 2)] - std::f64::consts::FRAC_PI_2).abs() < 1e-15);
        assert!(s[&Slot::at2("bodies", 2, 2)].abs() < 1e-15);
        assert!((s[&Slot::at2("trig", 1, 1)] - 1.0).abs() < 1e-15);
    }

    #[test]
    fn kinematics_match_forward_kinematics_and_its_time_derivative() {
        for water in [Water::Off, Water::On] {
            let v = Variant::new(5, water);
            let ps = chain(v);
            let (q, u) = state(5);
            let mut i = Inputs::new(&ps);
            i.array("q", &q);
            i.array("u", &u);
            let (s, _) = i.run(&kinematics(v));
            let h = 1e-6;
            let (p, pp, pm) = (centroids(&ps, &q), centroids(&ps, &axpy(&q, h, &u)), centroids(&ps, &axpy(&q, -h, &u)));
            for k in 0..5 {
                for j in 0..2 {
                    assert!((s[&Slot::at2("bodies", k, j)] - p[k][j]).abs() < 1e-12);
                    let fd = (pp[k][j] - pm[k][j]) / (2.0 * h);
                    let got = s[&Slot::at2("bodies", k, 3 + j)];
                    assert!((got - fd).abs() < 1e-7, "v of body {k}, {j}: {got} vs {fd}");
                }
            }
        }
    }

    /// a_lp from the stores, the dense block filled as the emitted loop nest does.
    fn mass_matrix(s: &HashMap<Slot, f64>, n: usize, dense: Option<usize>) -> Vec<f64> {
        let mut m = vec![f64::NAN; n * n];
        for (slot, &v) in s {
            if slot.array == "m" {
                m[slot.index] = v;
            }
        }
        if dense.is_some() {
            for l in 2..n - 1 {
                for j in 1..l {
                    let o = [s[&Slot::at2("o_rel", j, 0)], s[&Slot::at2("o_rel", j, 1)]];
                    let a = s[&Slot::at("k_col", l)]
                        - (o[0] * s[&Slot::at2("s_col", l, 0)] + o[1] * s[&Slot::at2("s_col", l, 1)]);
                    m[j * n + l] = a;
                    m[l * n + j] = a;
                }
            }
        }
        m
    }

    /// a_lp = Σ_k v_klᵀ A_k v_kp + I_k ω_kl ω_kp (Eq. 26) with the partial velocities v_kl of
    /// Eq. 15 taken by finite differences of the forward kinematics.
    fn mass_matrix_by_partials(ps: &[P], q: &[f64]) -> Vec<f64> {
        let n = ps.len();
        let h = 1e-6;
        let partial = |l: usize| {
            let mut dq = vec![0.0; n];
            dq[l] = 1.0;
            let (a, b) = (centroids(ps, &axpy(q, h, &dq)), centroids(ps, &axpy(q, -h, &dq)));
            (0..n).map(|k| [(a[k][0] - b[k][0]) / (2.0 * h), (a[k][1] - b[k][1]) / (2.0 * h)]).collect::<Vec<_>>()
        };
        let v: Vec<Vec<[f64; 2]>> = (0..n).map(partial).collect();
        let theta = absolute_angles(q);
        let omega = |k: usize, l: usize| if l < k && l + 1 < n { 1.0 } else { 0.0 };
        let mut m = vec![0.0; n * n];
        for l in 0..n {
            for p in 0..n {
                for (k, b) in ps.iter().enumerate() {
                    let nrm = [theta[k].sin(), theta[k].cos()];
                    let (a, c) = (v[l][k], v[p][k]);
                    let an = nrm[0] * c[0] + nrm[1] * c[1];
                    let av = [b.mass * c[0] + b.added_mass * an * nrm[0], b.mass * c[1] + b.added_mass * an * nrm[1]];
                    m[l * n + p] += a[0] * av[0] + a[1] * av[1] + b.inertia * omega(k, l) * omega(k, p);
                }
            }
        }
        m
    }

    #[test]
    fn a_lp_is_symmetric_and_matches_the_partial_velocities() {
        for n in [3, 4, 6] {
            for water in [Water::Off, Water::On] {
                let v = Variant::new(n, water);
                let ps = chain(v);
                let (q, u) = state(n);
                let mut i = Inputs::new(&ps);
                i.array("u", &u);
                i.trig(&q);
                i.loads(&vec![[0.0; 3]; n]);
                let f = assemble(v);
                assert_eq!(f.dense_fill, (n >= 4).then_some(n));
                let (s, _) = i.run(&f);
                let m = mass_matrix(&s, n, f.dense_fill);
                let reference = mass_matrix_by_partials(&ps, &q);
                for r in 0..n {
                    for c in 0..n {
                        assert_eq!(m[r * n + c], m[c * n + r], "N = {n}: a_{r}{c} ≠ a_{c}{r}");
                        let (got, want) = (m[r * n + c], reference[r * n + c]);
                        assert!(
                            (got - want).abs() < 1e-6 * want.abs().max(1.0),
                            "N = {n} {water:?}: a_{r}{c} = {got}, expected {want}"
                        );
                    }
                }
            }
        }
    }

    /// a_lp, f_l and the heave row from `assemble`, and the solve's qdd and returned values.
    struct Solved {
        m: Vec<f64>,
        f: Vec<f64>,
        heave: Vec<f64>,
        qdd: Vec<f64>,
        ret: Vec<f64>,
    }

    /// Assembles and solves at one state.
    fn solve_case(v: Variant, stuck: bool, friction: f64) -> Solved {
        let n = v.bodies;
        let ps = chain(v);
        let (q, u) = state(n);
        let loads: Vec<[f64; 3]> = (0..n).map(|k| [10.0 - 3.0 * k as f64, -20.0 + k as f64, 0.5 * k as f64]).collect();
        let mut i = Inputs::new(&ps);
        i.array("u", &u);
        i.trig(&q);
        i.loads(&loads);
        i.set("friction".to_string(), friction);
        let a = assemble(v);
        let (s, _) = i.run(&a);
        let m = mass_matrix(&s, n, a.dense_fill);
        let rhs: Vec<f64> = (0..n).map(|k| s[&Slot::at("f", k)]).collect();
        let heave: Vec<f64> = (0..=n).map(|k| s[&Slot::at("heave", k)]).collect();
        let sol = solve(v, stuck);
        let (st, ret) = i.run(&sol);
        let mut qdd = vec![0.0; n];
        for (slot, &x) in &st {
            assert_eq!(slot.array, "qdd");
            qdd[slot.index] = x;
        }
        assert!(sol.stores.windows(2).all(|w| w[0].slot.index < w[1].slot.index), "stores sorted by index");
        Solved { m, f: rhs, heave, qdd, ret }
    }

    fn row(m: &[f64], r: usize, x: &[f64]) -> f64 {
        let n = x.len();
        (0..n).map(|c| m[r * n + c] * x[c]).sum()
    }

    #[test]
    fn free_solve_satisfies_a_lp_qdd_equals_f_l() {
        for n in [3, 5] {
            for water in [Water::Off, Water::On] {
                let v = Variant::new(n, water);
                let Solved { m, f, heave, qdd, ret } = solve_case(v, false, 0.0);
                for r in 0..n {
                    let res = row(&m, r, &qdd) - f[r];
                    assert!(res.abs() < 1e-9 * f[r].abs().max(1.0), "N = {n}, row {r}: residual {res}");
                }
                // The returned normal force is the heave row's constraint force (Eq. 37).
                let normal: f64 = (0..n).map(|p| heave[p] * qdd[p]).sum::<f64>() - heave[n];
                assert!((ret[0] - normal).abs() < 1e-9 * normal.abs().max(1.0), "{} vs {normal}", ret[0]);
                assert!((ret[1] - 1.0).abs() < 1e-15, "no friction: factor 1");
            }
        }
    }

    #[test]
    fn sliding_friction_enters_the_anchor_row_only() {
        let v = Variant::new(5, Water::On);
        let k = 0.4;
        let Solved { m, f, heave, qdd, ret } = solve_case(v, false, k);
        let n = 5;
        let normal: f64 = (0..n).map(|p| heave[p] * qdd[p]).sum::<f64>() - heave[n];
        assert!((ret[0] - normal).abs() < 1e-9 * normal.abs().max(1.0));
        for r in 0..n - 1 {
            assert!((row(&m, r, &qdd) - f[r]).abs() < 1e-9 * f[r].abs().max(1.0));
        }
        // Surge: a_sp ẍ_p = f_s − k N.
        let res = row(&m, n - 1, &qdd) - (f[n - 1] - k * normal);
        assert!(res.abs() < 1e-9 * f[n - 1].abs().max(1.0), "surge residual {res}");
    }

    #[test]
    fn stuck_solve_returns_the_holding_force() {
        let n = 5;
        let Solved { m, f, heave, qdd, ret } = solve_case(Variant::new(n, Water::On), true, 0.0);
        assert_eq!(qdd[n - 1], 0.0);
        for r in 0..n - 1 {
            assert!((row(&m, r, &qdd) - f[r]).abs() < 1e-9 * f[r].abs().max(1.0));
        }
        // Eq. 50: F^C = a_sp ẍ_p − f_s; the normal force as in Eq. 37.
        let holding = row(&m, n - 1, &qdd) - f[n - 1];
        assert!((ret[0] - holding).abs() < 1e-9 * holding.abs().max(1.0), "{} vs {holding}", ret[0]);
        let normal: f64 = (0..n).map(|p| heave[p] * qdd[p]).sum::<f64>() - heave[n];
        assert!((ret[1] - normal).abs() < 1e-9 * normal.abs().max(1.0));
    }

    /// A scene's numbers folded in as literals change no value and save operations.
    #[test]
    fn folded_parameters_give_the_same_values_with_fewer_operations() {
        use super::{solve_with, BodyValues, ParamSource};
        let v = Variant::new(5, Water::On);
        let ps = chain(v);
        let values: Vec<BodyValues> = ps
            .iter()
            .map(|p| BodyValues {
                mass: p.mass,
                inertia: p.inertia,
                centroid: p.centroid,
                joint: p.joint,
                added_mass: p.added_mass,
            })
            .collect();
        let (q, u) = state(5);
        let mut i = Inputs::new(&ps);
        i.array("u", &u);
        i.trig(&q);
        i.loads(&(0..5).map(|k| [1.0 + k as f64, -2.0, 0.3 * k as f64]).collect::<Vec<_>>());
        i.set("friction".to_string(), 0.3);
        let (kept, folded) = (solve(v, false), solve_with(v, false, ParamSource::Folded(&values)));
        let ((a, ra), (b, rb)) = (i.run(&kept), i.run(&folded));
        for (slot, x) in &a {
            assert!((x - b[slot]).abs() <= 1e-12 * x.abs().max(1.0), "{slot:?}: {x} against {}", b[slot]);
        }
        assert!(ra.iter().zip(&rb).all(|(x, y)| (x - y).abs() <= 1e-12 * x.abs().max(1.0)));
        let count = |f: &Function| f.dag.count(&f.roots()).total();
        assert!(count(&folded) < count(&kept), "{} against {}", count(&folded), count(&kept));
    }

    #[test]
    fn accelerations_are_the_second_time_derivative() {
        let v = Variant::new(4, Water::On);
        let ps = chain(v);
        let (q, u) = state(4);
        let qdd = [0.7, -1.3, 0.4, 2.1];
        let mut i = Inputs::new(&ps);
        i.array("u", &u);
        i.array("qdd", &qdd);
        i.trig(&q);
        let (s, _) = i.run(&accelerations(v));
        // q(t) = q + u t + qdd t²/2 through the forward kinematics.
        let h = 1e-4;
        let at = |t: f64| {
            let qt: Vec<f64> = (0..4).map(|j| q[j] + u[j] * t + 0.5 * qdd[j] * t * t).collect();
            centroids(&ps, &qt)
        };
        let (a, b, c) = (at(h), at(0.0), at(-h));
        for k in 0..4 {
            for j in 0..2 {
                let fd = (a[k][j] - 2.0 * b[k][j] + c[k][j]) / (h * h);
                let got = s[&Slot::at2("acc", k, j)];
                assert!((got - fd).abs() < 1e-5 * fd.abs().max(1.0), "a of body {k}, {j}: {got} vs {fd}");
            }
        }
        let alpha: f64 = qdd[..2].iter().sum();
        assert!((s[&Slot::at2("acc", 2, 2)] - alpha).abs() < 1e-12);
    }
}

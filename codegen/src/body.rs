//! One body's share of the planar Kane quantities: the per-body steps of every recursion
//! (kinematics, velocity products, outboard sums, the articulated-body passes), written
//! once and driven two ways — over every body of a fixed N ([`crate::planar`], unrolled)
//! or once per body kind inside a loop ([`crate::rolled`]).
//!
//! Each step takes the symbols of one body ([`BodySyms`]) and what the recursion carries
//! in, and creates DAG nodes in a fixed order (the emitted text of the unrolled kernels is
//! checked in, so the order is part of the output). `tag` is appended to the names of the
//! nodes a step names (`_5` for B_5 in an unrolled kernel, `_k` in a rolled step).
//!
//! Notation as in [`crate::planar`]: (x, z) inertial components, J(x, z) = (z, −x) the
//! rotation through +90° about y (Eq. 15), A_k = m_k 1 + m_a,k n_k n_kᵀ (Eq. 46).

use crate::expr::{Dag, Id};

/// A planar vector (x, z).
pub(crate) type V2 = [Id; 2];

/// R(θ) v: body (x, z) components to inertial ones for a rotation θ about y.
pub(crate) fn rot(dag: &mut Dag, cs: V2, v: V2) -> V2 {
    let [c, s] = cs;
    let a = dag.mul(v[0], c);
    let b = dag.mul(v[1], s);
    let x = dag.add(a, b);
    let a = dag.mul(v[0], s);
    let b = dag.mul(v[1], c);
    let z = dag.sub(b, a);
    [x, z]
}

/// J(v) = (v_z, −v_x): d(R(θ)v)/dθ.
pub(crate) fn perp(dag: &mut Dag, v: V2) -> V2 {
    [v[1], dag.neg(v[0])]
}

pub(crate) fn add2(dag: &mut Dag, a: V2, b: V2) -> V2 {
    [dag.add(a[0], b[0]), dag.add(a[1], b[1])]
}

pub(crate) fn sub2(dag: &mut Dag, a: V2, b: V2) -> V2 {
    [dag.sub(a[0], b[0]), dag.sub(a[1], b[1])]
}

pub(crate) fn scale2(dag: &mut Dag, s: Id, v: V2) -> V2 {
    [dag.mul(s, v[0]), dag.mul(s, v[1])]
}

/// The y component of x × F for planar x, F: x_z F_x − x_x F_z.
pub(crate) fn cross(dag: &mut Dag, x: V2, f: V2) -> Id {
    let a = dag.mul(x[1], f[0]);
    let b = dag.mul(x[0], f[1]);
    dag.sub(a, b)
}

pub(crate) fn name2(dag: &mut Dag, v: V2, base: &str) -> V2 {
    [dag.name(v[0], format!("{base}_x")), dag.name(v[1], format!("{base}_z"))]
}

/// The symbols of one body B_k: parameters (structural zeros folded), rotation, angular
/// velocity and the centroid offset e_k = S^(0k) r_k.
#[derive(Clone, Copy)]
pub(crate) struct BodySyms {
    /// m_k, kg.
    pub mass: Id,
    /// I_yy + added inertia, kg·m².
    pub inertia: Id,
    /// r_k in body axes, m.
    pub centroid: V2,
    /// m_a,k, kg.
    pub added_mass: Id,
    /// (cos θ_k, sin θ_k).
    pub cs: V2,
    /// θ̇_k, rad/s.
    pub omega: Id,
    /// e_k = R(θ_k) r_k: o_k → C_k, inertial, m.
    pub e: V2,
}

impl BodySyms {
    /// t_k = R(θ_k)(1, 0), the body's x axis.
    pub fn t(&self, dag: &mut Dag) -> V2 {
        let [c, s] = self.cs;
        [c, dag.neg(s)]
    }

    /// n_k = R(θ_k)(0, 1), the body's z axis.
    pub fn normal(&self) -> V2 {
        let [c, s] = self.cs;
        [s, c]
    }

    /// A_k v = m v + m_a n (n · v).
    pub fn a_times(&self, dag: &mut Dag, v: V2) -> V2 {
        let mv = scale2(dag, self.mass, v);
        let n = self.normal();
        let nv = dag.dot2(n, v);
        let coef = dag.mul(self.added_mass, nv);
        let an = scale2(dag, coef, n);
        add2(dag, mv, an)
    }

    /// B_k = Jᵀ A_k J = m 1 + m_a t tᵀ as (xx, xz, zz).
    pub fn b_matrix(&self, dag: &mut Dag) -> [Id; 3] {
        let t = self.t(dag);
        let a = self.added_mass;
        let m = self.mass;
        let txx = dag.mul(t[0], t[0]);
        let txz = dag.mul(t[0], t[1]);
        let tzz = dag.mul(t[1], t[1]);
        let axx = dag.mul(a, txx);
        let xz = dag.mul(a, txz);
        let azz = dag.mul(a, tzz);
        [dag.add(m, axx), xz, dag.add(m, azz)]
    }

    /// B_k e_k = m e + m_a r_x t (t · e_k = r_x in body axes).
    pub fn b_e(&self, dag: &mut Dag) -> V2 {
        let me = scale2(dag, self.mass, self.e);
        let t = self.t(dag);
        let coef = dag.mul(self.added_mass, self.centroid[0]);
        let at = scale2(dag, coef, t);
        add2(dag, me, at)
    }

    /// e_kᵀ B_k e_k + I_k = m |r|² + m_a r_x² + I, from body-axis components.
    pub fn e_b_e_plus_i(&self, dag: &mut Dag) -> Id {
        let r = self.centroid;
        let r2 = dag.dot2(r, r);
        let mr2 = dag.mul(self.mass, r2);
        let rx2 = dag.mul(r[0], r[0]);
        let arx2 = dag.mul(self.added_mass, rx2);
        let s = dag.add(mr2, arx2);
        dag.add(s, self.inertia)
    }
}

/// dᵀ B d for the link vector d = R(θ_{k−1}) q_k and a symmetric B = (xx, xz, zz); for
/// B = m 1 this is m |q_k|² (rotations keep lengths: cos² + sin² = 1 where it arises).
pub(crate) fn quad(dag: &mut Dag, joint: V2, d: V2, b: [Id; 3]) -> Id {
    if dag.is_zero(b[1]) && b[0] == b[2] {
        let q2 = dag.dot2(joint, joint);
        return dag.mul(b[0], q2);
    }
    let bd = [dag.dot2([b[0], b[1]], d), dag.dot2([b[1], b[2]], d)];
    dag.dot2(d, bd)
}

/// The absolute angle θ_k = θ_{k−1} + β_k and (cos θ_k, sin θ_k) (Eqs. 1, 4).
pub(crate) fn angle_step(dag: &mut Dag, theta_prev: Id, beta: Id, tag: &str) -> (Id, V2) {
    let theta = dag.add(theta_prev, beta);
    dag.name(theta, format!("theta{tag}"));
    let c = dag.cos(theta);
    let s = dag.sin(theta);
    (theta, [dag.name(c, format!("c{tag}")), dag.name(s, format!("s{tag}"))])
}

/// Kinematics across hinge k (k ≥ 1): o_k = o_{k−1} + d_k, v_{o_k} = v_{o_{k−1}} +
/// θ̇_{k−1} J(d_k) (Eqs. 13, 14). Returns (o_k, v_{o_k}).
pub(crate) fn hinge_kinematics(dag: &mut Dag, origin: [V2; 2], d: V2, omega_prev: Id, tag: &str) -> [V2; 2] {
    let o = add2(dag, origin[0], d);
    let o = name2(dag, o, &format!("o{tag}"));
    let jd = perp(dag, d);
    let t = scale2(dag, omega_prev, jd);
    let v = add2(dag, origin[1], t);
    let v = name2(dag, v, &format!("vo{tag}"));
    [o, v]
}

/// The centroid's position and velocity from its origin's: p_k = o_k + e_k, v_k = v_{o_k} +
/// θ̇_k J(e_k) (Eqs. 13, 14).
pub(crate) fn centroid_kinematics(dag: &mut Dag, b: &BodySyms, origin: [V2; 2], tag: &str) -> [V2; 2] {
    let pos = add2(dag, origin[0], b.e);
    let pos = name2(dag, pos, &format!("p{tag}"));
    let je = perp(dag, b.e);
    let t = scale2(dag, b.omega, je);
    let vel = add2(dag, origin[1], t);
    let vel = name2(dag, vel, &format!("v{tag}"));
    [pos, vel]
}

/// The velocity-product (centripetal) acceleration of C_k (Eq. 16 times ẋ), carried along
/// the chain: the origin's ā_{o_k} = ā_{o_{k−1}} − θ̇_{k−1}² d_k (k ≥ 1, `hinge` =
/// (d_k, θ̇_{k−1})), then ȧ_k = ā_{o_k} − θ̇_k² e_k. Returns (ā_{o_k}, ȧ_k).
pub(crate) fn centripetal_step(dag: &mut Dag, b: &BodySyms, origin: V2, hinge: Option<(V2, Id)>, tag: &str) -> [V2; 2] {
    let mut origin = origin;
    if let Some((d, omega_prev)) = hinge {
        let w2 = dag.mul(omega_prev, omega_prev);
        let t = scale2(dag, w2, d);
        origin = sub2(dag, origin, t);
    }
    let w2 = dag.mul(b.omega, b.omega);
    let t = scale2(dag, w2, b.e);
    let a = sub2(dag, origin, t);
    [origin, name2(dag, a, &format!("ac{tag}"))]
}

/// F̃_k = F_k − A_k ȧ_k: the applied force less the velocity-product inertia force (Eqs. 22, 23).
pub(crate) fn effective_force(dag: &mut Dag, b: &BodySyms, acc: V2, force: V2, tag: &str) -> V2 {
    let inertial = b.a_times(dag, acc);
    let fe = sub2(dag, force, inertial);
    name2(dag, fe, &format!("fe{tag}"))
}

/// The outboard sums about o_l carried from the child (Eq. 26): Btot_{l+1}, S_{l+1},
/// J_{l+1}, the child's link d_{l+1} and joint q_{l+1} (body axes).
#[derive(Clone, Copy)]
pub(crate) struct Outboard {
    pub bt: [Id; 3],
    pub s: V2,
    pub j: Id,
}

/// Outboard sums at B_l (Eq. 26): Btot_l = B_l + Btot_{l+1}, S_l = B_l e_l + S_{l+1} +
/// Btot_{l+1} d_{l+1} and J_l = e_lᵀB_l e_l + I_l + J_{l+1} + 2 d_{l+1}·S_{l+1} +
/// d_{l+1}ᵀ Btot_{l+1} d_{l+1}; `child` = (its sums, d_{l+1}, q_{l+1}).
pub(crate) fn outboard_step(dag: &mut Dag, b: &BodySyms, child: Option<(Outboard, V2, V2)>, tag: &str) -> Outboard {
    let bm = b.b_matrix(dag);
    let be = b.b_e(dag);
    let ebe = b.e_b_e_plus_i(dag);
    let (bt, s, j) = match child {
        None => (bm, be, ebe),
        Some((c, d, joint)) => {
            let bt1 = c.bt;
            let bd = [dag.dot2([bt1[0], bt1[1]], d), dag.dot2([bt1[1], bt1[2]], d)];
            let s = add2(dag, be, c.s);
            let s = add2(dag, s, bd);
            let ds = dag.dot2(d, c.s);
            let two_ds = dag.add(ds, ds);
            let dbd = quad(dag, joint, d, bt1);
            let j = dag.sum(&[ebe, c.j, two_ds, dbd]);
            let bt = [dag.add(bm[0], bt1[0]), dag.add(bm[1], bt1[1]), dag.add(bm[2], bt1[2])];
            (bt, s, j)
        }
    };
    let bt = [
        dag.name(bt[0], format!("bt{tag}_xx")),
        dag.name(bt[1], format!("bt{tag}_xz")),
        dag.name(bt[2], format!("bt{tag}_zz")),
    ];
    let s = name2(dag, s, &format!("sm{tag}"));
    let j = dag.name(j, format!("j{tag}"));
    Outboard { bt, s, j }
}

/// The generalised forces carried inward (Eq. 25): G_k = G_{k+1} + F̃_k and, for k ≥ 1,
/// H_k = H_{k+1} + d_{k+1} × G_{k+1} + e_k × F̃_k + T_k (`d_child` = d_{k+1}, absent at
/// the ship). Returns (G_k, H_k), H_k = f_{β_k} (None at the anchor).
pub(crate) fn force_sums(
    dag: &mut Dag,
    e: Option<V2>,
    fe: V2,
    torque: Id,
    carried: (V2, Id),
    d_child: Option<V2>,
    tag: &str,
) -> (V2, Option<Id>) {
    let (g, h) = carried;
    let h = e.map(|e| {
        let zero = dag.zero();
        let arm = cross(dag, e, fe);
        let carry = match d_child {
            Some(d) => cross(dag, d, g),
            None => zero,
        };
        dag.sum(&[h, carry, arm, torque])
    });
    let g = add2(dag, g, fe);
    (name2(dag, g, &format!("g{tag}")), h)
}

/// The articulated inertia IA_k as [00, 01, 02, 11, 12, 22] and bias pA_k at o_k, with
/// (angular, x, z) components.
pub(crate) type Articulated = ([Id; 6], [Id; 3]);

/// One body's articulated inertia and bias at o_k (the inward pass of [`crate::planar::solve`]):
/// its rigid inertia [[I + eᵀBe, (J(Be))ᵀ], [J(Be), A]], its bias −θ̇_k² A e (and the
/// moment θ̇² m_a r_x r_z) minus the applied load (`force`, `torque`), plus what the child's
/// subchain carries across the hinge.
pub(crate) fn articulated_body(
    dag: &mut Dag,
    b: &BodySyms,
    load: (V2, Id),
    carry: Option<Articulated>,
    tag: &str,
) -> Articulated {
    let (m, am, r, e) = (b.mass, b.added_mass, b.centroid, b.e);
    let i00 = b.e_b_e_plus_i(dag);
    let be = b.b_e(dag);
    let g = perp(dag, be);
    let [s, c] = b.normal();
    let ss = dag.mul(s, s);
    let sc = dag.mul(s, c);
    let cc = dag.mul(c, c);
    let a_ss = dag.mul(am, ss);
    let a11 = dag.add(m, a_ss);
    let a12 = dag.mul(am, sc);
    let a_cc = dag.mul(am, cc);
    let a22 = dag.add(m, a_cc);
    let mut i = [i00, g[0], g[1], a11, a12, a22];
    let w2 = dag.mul(b.omega, b.omega);
    let ae = b.a_times(dag, e);
    let bias_f = scale2(dag, w2, ae);
    let bias_f = [dag.neg(bias_f[0]), dag.neg(bias_f[1])];
    let rxz = dag.mul(r[0], r[1]);
    let arxz = dag.mul(am, rxz);
    let bias_m = dag.mul(w2, arxz);
    let (fl, tl) = load;
    let moment = cross(dag, e, fl);
    let ext_m = dag.add(tl, moment);
    let mut p = [dag.sub(bias_m, ext_m), dag.sub(bias_f[0], fl[0]), dag.sub(bias_f[1], fl[1])];
    if let Some((ci, cp)) = carry {
        for (x, y) in i.iter_mut().zip(ci) {
            *x = dag.add(*x, y);
        }
        for (x, y) in p.iter_mut().zip(cp) {
            *x = dag.add(*x, y);
        }
    }
    for (x, nm) in i.iter_mut().zip(["00", "01", "02", "11", "12", "22"]) {
        *x = dag.name(*x, format!("ia{tag}_{nm}"));
    }
    for (x, nm) in p.iter_mut().zip(["m", "x", "z"]) {
        *x = dag.name(*x, format!("pa{tag}_{nm}"));
    }
    (i, p)
}

/// Eliminates hinge k from IA_k, pA_k and carries the rest across d_k to o_{k−1}:
/// Ia = IA − U Uᵀ / D, pa = pA − U pA_0 / D (U = IA e_0; the angular row and column vanish
/// exactly), then X = [[1, 0, 0], [j_x, 1, 0], [j_z, 0, 1]] with (j_x, j_z) = J(d_k) and the
/// joint's velocity product c = (0, −θ̇_{k−1}² d_k). Returns the hinge's gains for the
/// outward pass, (IA_01/D, IA_02/D, pA_0/D), the carry (Xᵀ Ia X, Xᵀ(Ia c + pa)), and the
/// hinge's force row: Ia's translational block and pa's forces, (Ia_11, Ia_12, Ia_22, pa_1,
/// pa_2), from which [`hinge_force`] gives the force through the hinge.
pub(crate) fn eliminate_hinge(
    dag: &mut Dag,
    ab: Articulated,
    d: V2,
    omega_prev: Id,
    tag: &str,
) -> ([Id; 3], Articulated, [Id; 5]) {
    let (i, p) = ab;
    let one = dag.one();
    let inv = dag.div(one, i[0]);
    let inv = dag.name(inv, format!("inv{tag}"));
    let u1 = dag.mul(i[1], inv);
    let u2 = dag.mul(i[2], inv);
    let t11 = dag.mul(u1, i[1]);
    let t12 = dag.mul(u1, i[2]);
    let t22 = dag.mul(u2, i[2]);
    let r11 = dag.sub(i[3], t11);
    let r12 = dag.sub(i[4], t12);
    let r22 = dag.sub(i[5], t22);
    let q1 = dag.mul(u1, p[0]);
    let q2 = dag.mul(u2, p[0]);
    let pm = dag.mul(p[0], inv);
    let pa1 = dag.sub(p[1], q1);
    let pa2 = dag.sub(p[2], q2);
    let jd = perp(dag, d);
    let w2p = dag.mul(omega_prev, omega_prev);
    let cv = scale2(dag, w2p, d);
    let cv = [dag.neg(cv[0]), dag.neg(cv[1])];
    let z1 = dag.dot2([r11, r12], cv);
    let z1 = dag.add(z1, pa1);
    let z2 = dag.dot2([r12, r22], cv);
    let z2 = dag.add(z2, pa2);
    let y1 = dag.dot2([r11, r12], jd);
    let y2 = dag.dot2([r12, r22], jd);
    let x00 = dag.dot2(jd, [y1, y2]);
    let xp0 = dag.dot2(jd, [z1, z2]);
    ([u1, u2, pm], ([x00, y1, y2, r11, r12, r22], [xp0, z1, z2]), [r11, r12, r22, pa1, pa2])
}

/// The anchor's row once every hinge is eliminated. The seabed supplies the wrench IA_1 (0,
/// ẍ_s, 0) + pA_1 at o_1: its x part is the holding force (Eq. 50), its z part the normal
/// force N (Eq. 37). Stuck: ẍ_s = 0, returns [holding, N]. Free, with sliding friction −k N
/// along x (input `friction` = k = μ·direction of sliding) implicit in ẍ_s: (IA_xx + k IA_xz)
/// ẍ_s = −(pA_x + k pA_z); returns [N, 1 + k ∂N/∂F_x]. Returns (ẍ_s, the returned values).
pub(crate) fn anchor_solve(dag: &mut Dag, anchor: Articulated, stuck: bool) -> (Id, Vec<Id>) {
    let (ia, pa) = anchor;
    if stuck {
        let holding = dag.name(pa[1], "holding_force");
        let normal = dag.name(pa[2], "normal_force");
        return (dag.zero(), vec![holding, normal]);
    }
    let k = dag.input("friction");
    let kz = dag.mul(k, ia[4]);
    let den = dag.add(ia[3], kz);
    let kp = dag.mul(k, pa[2]);
    let num = dag.add(pa[1], kp);
    let v = dag.div(num, den);
    let v = dag.neg(v);
    let s_dd = dag.name(v, "s_dd");
    let nz = dag.mul(ia[4], s_dd);
    let normal = dag.add(nz, pa[2]);
    let normal = dag.name(normal, "normal_force");
    // den / IA_xx = 1 + k ∂N/∂F_x: positive unless friction locks the anchor's surge
    // (Painlevé's paradox); the runtime refuses a non-positive value.
    let factor = dag.div(den, ia[3]);
    let factor = dag.name(factor, "friction_factor");
    (s_dd, vec![normal, factor])
}

/// The outward pass across hinge k: the origin's acceleration a_{o_k} = (a_{o_{k−1}} −
/// θ̇_{k−1}² d_k) + α_{k−1} J(d_k), then α_k = −(IA_01/D a_x + IA_02/D a_z + pA_0/D) and
/// β̈_k = α_k − α_{k−1}. `gains` = (IA_01/D, IA_02/D, pA_0/D) from [`eliminate_hinge`].
/// The pass is a chain from body to body through α; the operations are ordered so that
/// α_{k−1} enters last and the division was done in the inward pass: six dependent
/// operations a body (a product and a sum into a_{o_k}, two products summed and the
/// constant added into α_k), where dividing here took eight. Returns (α_k, a_{o_k}, β̈_k).
#[allow(clippy::too_many_arguments)]
pub(crate) fn outward_step(
    dag: &mut Dag,
    d: V2,
    omega_prev: Id,
    alpha: Id,
    acc: V2,
    gains: [Id; 3],
    tag: &str,
    coordinate: &str,
) -> (Id, V2, Id) {
    let jd = perp(dag, d);
    let w2p = dag.mul(omega_prev, omega_prev);
    let cv = scale2(dag, w2p, d);
    let t = scale2(dag, alpha, jd);
    let a = sub2(dag, acc, cv);
    let a = add2(dag, a, t);
    let a = name2(dag, a, &format!("ao{tag}"));
    let num = dag.dot2([gains[0], gains[1]], a);
    let q = dag.add(num, gains[2]);
    let new_alpha = dag.neg(q);
    let new_alpha = dag.name(new_alpha, format!("alpha{tag}"));
    let beta_dd = dag.sub(new_alpha, alpha);
    let beta_dd = dag.name(beta_dd, format!("qdd{coordinate}"));
    (new_alpha, a, beta_dd)
}

/// The force on the bodies outboard of hinge k from B_{k−1}, through the hinge at o_k
/// (Eq. 52): with the hinge's freedom eliminated, F = Ia a_{o_k} + pa in its translational
/// rows (`row` = (Ia_11, Ia_12, Ia_22, pa_1, pa_2) from [`eliminate_hinge`], `acc` = a_{o_k}
/// from [`outward_step`]); the hinge transmits no moment about y.
pub(crate) fn hinge_force(dag: &mut Dag, row: [Id; 5], acc: V2) -> V2 {
    let fx = dag.dot2([row[0], row[1]], acc);
    let fz = dag.dot2([row[1], row[2]], acc);
    [dag.add(fx, row[3]), dag.add(fz, row[4])]
}

/// Body accelerations (Eq. 17) across hinge k (`hinge` = (d_k, θ̇_{k−1}, β̈_k), absent at
/// the anchor): a_{o_k} = a_{o_{k−1}} + α_{k−1} J(d_k) − θ̇_{k−1}² d_k, α_k = α_{k−1} + β̈_k,
/// then a_k = a_{o_k} + α_k J(e_k) − θ̇_k² e_k. Returns (α_k, a_{o_k}, a_k).
pub(crate) fn acceleration_step(
    dag: &mut Dag,
    b: &BodySyms,
    carried: (Id, V2),
    hinge: Option<(V2, Id, Id)>,
    tag: &str,
) -> (Id, V2, V2) {
    let (mut alpha, mut origin_a) = carried;
    if let Some((d, omega_prev, beta_dd)) = hinge {
        let jd = perp(dag, d);
        let t = scale2(dag, alpha, jd);
        let w2 = dag.mul(omega_prev, omega_prev);
        let c = scale2(dag, w2, d);
        origin_a = add2(dag, origin_a, t);
        origin_a = sub2(dag, origin_a, c);
        origin_a = name2(dag, origin_a, &format!("ao{tag}"));
        alpha = dag.add(alpha, beta_dd);
        alpha = dag.name(alpha, format!("alpha{tag}"));
    }
    let je = perp(dag, b.e);
    let t = scale2(dag, alpha, je);
    let w2 = dag.mul(b.omega, b.omega);
    let c = scale2(dag, w2, b.e);
    let a = add2(dag, origin_a, t);
    let a = sub2(dag, a, c);
    let a = name2(dag, a, &format!("a{tag}"));
    (alpha, origin_a, a)
}

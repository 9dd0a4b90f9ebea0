//! The rolled kernels: the per-body recursion steps of `body.rs`, expanded once per
//! body kind and driven by loops over the chain, so that one kernel serves every N.
//!
//! A chain is always [anchor, first link, rod-like bodies …, ship]: B_1 does not rotate,
//! B_2 hangs from the anchor (its joint height is kept), B_3 … B_{N−1} are rods (centroid
//! and joint on the body axis) and B_N is the ship (no added mass). Each kind folds the same
//! structural zeros as the unrolled kernels ([`Variant::folds`]), so a rolled kernel reads
//! exactly the parameters an unrolled one reads.
//!
//! `first` and `rod` share the outboard-sum, surge and force steps (`outboard_rod`,
//! `surge_rod`, `forces_rod` run on B_2 too), and the child's parameters `pc` are read with
//! the `rod` folds even when the child is the ship: correct because those steps read only
//! the body's mass, added mass and centroid and the child's joint x, never a joint height or
//! the ship's centroid height. A step that needs them must get its own kind.
//!
//! Each step is a [`Step`]: a DAG [`Function`] with its Rust signature. Its inputs are the
//! body's parameters `p` (and its child's, `pc`), the rotation tables `t` (this body) and
//! `tp` (the parent's), angular velocities `w`, `wp`, loads `f`, and the recursion's carry
//! `c`; its outputs are stores into `body`, `trig`, `acc` or the scratch row `s`, and the
//! carry it returns. [`crate::drivers`] emits the loops that call them.

use kanestop_chain::{ParamField, Variant, Water};

use crate::body::{
    acceleration_step, anchor_solve, articulated_body, centripetal_step, centroid_kinematics, effective_force,
    eliminate_hinge, force_sums, hinge_force, hinge_kinematics, outboard_step, outward_step, rot, BodySyms, Outboard,
    V2,
};
use crate::expr::{Dag, Id};
use crate::planar::{Function, Slot};

/// The body kinds a rolled kernel distinguishes.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Kind {
    /// B_1, the gravity anchor: translates only.
    Anchor,
    /// B_2: the first rod, hinged to the anchor (joint height kept).
    First,
    /// B_3 … B_{N−1}: rods.
    Rod,
    /// B_N: the ship.
    Ship,
}

impl Kind {
    /// A body of this kind in a chain of five, for [`Variant::folds`].
    fn representative(self) -> usize {
        match self {
            Kind::Anchor => 0,
            Kind::First => 1,
            Kind::Rod => 2,
            Kind::Ship => 4,
        }
    }

    /// `anchor`, `first`, `rod` or `ship`, as in the step names.
    pub fn name(self) -> &'static str {
        match self {
            Kind::Anchor => "anchor",
            Kind::First => "first",
            Kind::Rod => "rod",
            Kind::Ship => "ship",
        }
    }

    /// Whether the parent body rotates (its rotation and angular velocity are inputs).
    fn parent_rotates(self) -> bool {
        matches!(self, Kind::Rod | Kind::Ship)
    }
}

/// One generated step: its name, documentation, Rust parameter list and return type, and body.
pub struct Step {
    /// The function's name, e.g. `inward_rod`.
    pub name: String,
    /// The body kind it serves, if any.
    pub kind: Option<Kind>,
    /// The doc comment.
    pub doc: String,
    /// The parameter list, Rust text (`p: &crate::BodyParams, c: &[f64; 9]`).
    pub params: String,
    /// The number of returned values (`-> [f64; n]`), 0 for none.
    pub returns: usize,
    /// What it computes.
    pub function: Function,
}

/// Appended to the names a step gives its values (`ia_k_00`, `alpha_k`), which keeps them
/// apart from the step's parameters (`c`, `s`, `t`, …).
const TAG: &str = "_k";

const PARAMS: &str = "p: &crate::BodyParams";
const CHILD: &str = "pc: &crate::BodyParams";

/// The parameter inputs of one body of `kind` (`place` = `p` or `pc`), structural zeros folded.
struct ParamSyms {
    mass: Id,
    inertia: Id,
    centroid: V2,
    joint: V2,
    added_mass: Id,
}

fn param_syms(dag: &mut Dag, kind: Kind, water: Water, place: &str) -> ParamSyms {
    let v = Variant::new(5, water);
    let k = kind.representative();
    let zero = dag.zero();
    let input = |dag: &mut Dag, field: Option<ParamField>, name: &str| match field {
        Some(f) if v.folds(k, f) => zero,
        _ => dag.input(format!("{place}.{name}")),
    };
    let mass = input(dag, None, "mass");
    let inertia = if kind == Kind::Anchor { zero } else { input(dag, None, "inertia") };
    let cx = input(dag, None, "centroid[0]");
    let cz = input(dag, Some(ParamField::CentroidZ), "centroid[1]");
    let jx = input(dag, None, "joint[0]");
    let jz = input(dag, Some(ParamField::JointZ), "joint[1]");
    let added_mass = input(dag, Some(ParamField::AddedMass), "added_mass");
    ParamSyms { mass, inertia, centroid: [cx, cz], joint: [jx, jz], added_mass }
}

/// `name[0]`, `name[1]`.
fn pair(dag: &mut Dag, name: &str) -> V2 {
    [dag.input(format!("{name}[0]")), dag.input(format!("{name}[1]"))]
}

/// `c[0]` … `c[len − 1]`.
fn carry_in(dag: &mut Dag, len: usize) -> Vec<Id> {
    (0..len).map(|i| dag.input(format!("c[{i}]"))).collect()
}

/// The articulated carry `c[0..9]` from the child: (Xᵀ Ia X, Xᵀ(Ia c + pa)).
fn articulated_carry(dag: &mut Dag) -> crate::body::Articulated {
    let c = carry_in(dag, 9);
    ([c[0], c[1], c[2], c[3], c[4], c[5]], [c[6], c[7], c[8]])
}

/// The rotation of this body (`t`) and of its parent (`tp`), (1, 0) where it does not rotate.
fn rotations(dag: &mut Dag, kind: Kind) -> (V2, V2) {
    let level = [dag.one(), dag.zero()];
    let cs = if kind == Kind::Anchor { level } else { pair(dag, "t") };
    let parent = if kind.parent_rotates() { pair(dag, "tp") } else { level };
    (cs, parent)
}

/// ω_k (`w`) and ω_{k−1} (`wp`), zero where the body or its parent does not rotate.
fn angular_velocities(dag: &mut Dag, kind: Kind) -> (Id, Id) {
    let zero = dag.zero();
    let w = if kind == Kind::Anchor { zero } else { dag.input("w") };
    let wp = if kind.parent_rotates() { dag.input("wp") } else { zero };
    (w, wp)
}

fn body_syms(dag: &mut Dag, p: &ParamSyms, cs: V2, omega: Id) -> BodySyms {
    let e = rot(dag, cs, p.centroid);
    BodySyms { mass: p.mass, inertia: p.inertia, centroid: p.centroid, added_mass: p.added_mass, cs, omega, e }
}

/// The signature text of a step of `kind` reading the rotations and angular velocities.
fn motion_params(kind: Kind) -> String {
    let mut s = String::new();
    if kind != Kind::Anchor {
        s += ", t: &[f64; 2], w: f64";
    }
    if kind.parent_rotates() {
        s += ", tp: &[f64; 2], wp: f64";
    }
    s
}

fn step(name: String, kind: Option<Kind>, doc: &str, params: String, function: Function) -> Step {
    let returns = function.ret.len();
    Step { name, kind, doc: doc.to_string(), params, returns, function }
}

/// `kin_<kind>`: θ_k, the centroid's position and velocity (Eqs. 9, 13, 14), with
/// (cos θ_k, sin θ_k) read from the rotation table `t` ([`crate::drivers`] fills it first;
/// the anchor's is (1, 0), stored here); the carry is [θ, cos θ, sin θ, ω, o_x, o_z, v_{o,x},
/// v_{o,z}] of the body.
pub fn kinematics(kind: Kind, water: Water) -> Step {
    let mut dag = Dag::new();
    let mut f = Function::new(Dag::new());
    let p = param_syms(&mut dag, kind, water, "p");
    let zero = dag.zero();
    let (theta, cs, omega, origin) = if kind == Kind::Anchor {
        let s1 = dag.input("q");
        let s1_dot = dag.input("u");
        let origin = [dag.add(p.joint[0], s1), p.joint[1]];
        ([zero, dag.one(), zero, zero], [dag.one(), zero], zero, [origin, [s1_dot, zero]])
    } else {
        let c = carry_in(&mut dag, 8);
        let first = kind == Kind::First;
        let (theta_prev, parent, omega_prev) =
            if first { (zero, [dag.one(), zero], zero) } else { (c[0], [c[1], c[2]], c[3]) };
        let q = dag.input("q");
        // θ_k is summed here as in `kanestop_generated::trig::rotations`'s table (the same additions in the same
        // order), whose (cos θ_k, sin θ_k) the step reads: the driver fills the table first,
        // two angles at a time.
        let theta = dag.add(theta_prev, q);
        let theta = dag.name(theta, format!("theta{TAG}"));
        let cs = pair(&mut dag, "t");
        let u = dag.input("u");
        let omega = dag.add(omega_prev, u);
        let omega = dag.name(omega, "w_k");
        let d = rot(&mut dag, parent, p.joint);
        let origin = hinge_kinematics(&mut dag, [[c[4], c[5]], [c[6], c[7]]], d, omega_prev, TAG);
        ([theta, cs[0], cs[1], omega], cs, omega, origin)
    };
    let b = body_syms(&mut dag, &p, cs, omega);
    let [pos, vel] = centroid_kinematics(&mut dag, &b, origin, TAG);
    for (j, v) in [pos[0], pos[1], theta[0], vel[0], vel[1], omega].into_iter().enumerate() {
        f.store(Slot::at("body", j), v);
    }
    if kind == Kind::Anchor {
        f.store(Slot::at("trig", 0), cs[0]);
        f.store(Slot::at("trig", 1), cs[1]);
    }
    f.ret = vec![theta[0], theta[1], theta[2], theta[3], origin[0][0], origin[0][1], origin[1][0], origin[1][1]];
    f.dag = dag;
    let params = if kind == Kind::Anchor {
        format!("{PARAMS}, q: f64, u: f64, body: &mut [f64; 6], trig: &mut [f64; 2]")
    } else {
        format!("{PARAMS}, q: f64, u: f64, c: &[f64; 8], t: &[f64; 2], body: &mut [f64; 6]")
    };
    step(
        format!("kin_{}", kind.name()),
        Some(kind),
        "Body state of one body from the parent's carry and its row of the rotation table (Eqs. 9, 13, 14).",
        params,
        f,
    )
}

/// `acc_<kind>`: the body's accelerations (Eq. 17); the carry is [α, a_{o,x}, a_{o,z}].
pub fn accelerations(kind: Kind, water: Water) -> Step {
    let mut dag = Dag::new();
    let mut f = Function::new(Dag::new());
    let p = param_syms(&mut dag, kind, water, "p");
    let zero = dag.zero();
    let (cs, parent) = rotations(&mut dag, kind);
    let (w, wp) = angular_velocities(&mut dag, kind);
    let b = body_syms(&mut dag, &p, cs, w);
    let (alpha, origin_a, a) = if kind == Kind::Anchor {
        let s_dd = dag.input("qdd");
        acceleration_step(&mut dag, &b, (zero, [s_dd, zero]), None, TAG)
    } else {
        let c = carry_in(&mut dag, 3);
        let d = rot(&mut dag, parent, p.joint);
        let beta_dd = dag.input("qdd");
        acceleration_step(&mut dag, &b, (c[0], [c[1], c[2]]), Some((d, wp, beta_dd)), TAG)
    };
    f.store(Slot::at("acc", 0), a[0]);
    f.store(Slot::at("acc", 1), a[1]);
    f.store(Slot::at("acc", 2), alpha);
    f.ret = vec![alpha, origin_a[0], origin_a[1]];
    f.dag = dag;
    let carry = if kind == Kind::Anchor { "" } else { ", c: &[f64; 3]" };
    step(
        format!("acc_{}", kind.name()),
        Some(kind),
        "Accelerations of one body (Eq. 17) for its β̈ (`qdd`; the anchor: s̈), from the parent's carry.",
        format!("{PARAMS}{}, qdd: f64{carry}, acc: &mut [f64; 3]", motion_params(kind)),
        f,
    )
}

/// Where a solve step's applied load on its body comes from.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Loads {
    /// The resultant at the centroid, `f` = [F_x, F_z, M_y], an input: any physics the
    /// runtime's force modules compute.
    Inputs,
    /// Weight alone, −m g through the centroid (Eq. 40), with `g` an input: the step reads
    /// no load, and the terms of F_x and M_y fold away. A dry scene without seabed (a chain
    /// hanging in vacuum) needs nothing else.
    Gravity,
}

impl Loads {
    /// `""` or `"_gravity"`, appended to the names of the steps and entry points.
    pub fn suffix(self) -> &'static str {
        match self {
            Loads::Inputs => "",
            Loads::Gravity => "_gravity",
        }
    }

    /// The Rust parameter the steps take for it.
    fn param(self) -> &'static str {
        match self {
            Loads::Inputs => "f: &[f64; 3]",
            Loads::Gravity => "g: f64",
        }
    }
}

/// The applied load (force at the centroid, moment about y) on a body of mass `mass`.
fn load_syms(dag: &mut Dag, loads: Loads, mass: Id) -> (V2, Id) {
    match loads {
        Loads::Inputs => (pair(dag, "f"), dag.input("f[2]")),
        Loads::Gravity => {
            let g = dag.input("g");
            let weight = dag.mul(mass, g);
            let zero = dag.zero();
            ([zero, dag.neg(weight)], zero)
        }
    }
}

/// `inward_<kind>` (not the anchor): the body's articulated inertia, its hinge eliminated
/// and carried to the parent (the inward pass of the O(N) solve). Stores the row the
/// outward pass needs, `s` = [d_x, d_z, IA_01/D, IA_02/D, pA_0/D], and the hinge's force
/// row (`s[5..10]` = Ia_11, Ia_12, Ia_22, pa_1, pa_2, for [`hinge`]); returns the carry
/// [Xᵀ Ia X (6), Xᵀ(Ia c + pa) (3)]. With [`Loads::Gravity`], `inward_<kind>_gravity`.
pub fn inward(kind: Kind, water: Water, loads: Loads) -> Step {
    assert_ne!(kind, Kind::Anchor, "the anchor closes the inward pass (anchor_free, anchor_stuck)");
    let mut dag = Dag::new();
    let mut f = Function::new(Dag::new());
    let p = param_syms(&mut dag, kind, water, "p");
    let (cs, parent) = rotations(&mut dag, kind);
    let (w, wp) = angular_velocities(&mut dag, kind);
    let b = body_syms(&mut dag, &p, cs, w);
    let load = load_syms(&mut dag, loads, p.mass);
    let carry = (kind != Kind::Ship).then(|| articulated_carry(&mut dag));
    let ab = articulated_body(&mut dag, &b, load, carry, TAG);
    let d = rot(&mut dag, parent, p.joint);
    let (gains, (ci, cp), force_row) = eliminate_hinge(&mut dag, ab, d, wp, TAG);
    for (j, v) in [d[0], d[1], gains[0], gains[1], gains[2]].into_iter().chain(force_row).enumerate() {
        f.store(Slot::at("s", j), v);
    }
    f.ret = ci.into_iter().chain(cp).collect();
    f.dag = dag;
    let carry = if kind == Kind::Ship { "" } else { ", c: &[f64; 9]" };
    let doc = match loads {
        Loads::Inputs => "The inward pass at one body: its articulated inertia and bias, the hinge eliminated and carried to the parent.",
        Loads::Gravity => "The inward pass at one body under its weight alone (−m g through the centroid, Eq. 40): its articulated inertia and bias, the hinge eliminated and carried to the parent.",
    };
    step(
        format!("inward_{}{}", kind.name(), loads.suffix()),
        Some(kind),
        doc,
        format!("{PARAMS}{}, {}{carry}, s: &mut [f64; crate::ROLLED_SCRATCH]", motion_params(kind), loads.param()),
        f,
    )
}

/// `anchor_free` / `anchor_stuck`: the anchor closes the inward pass (`body.rs`); with
/// [`Loads::Gravity`], `anchor_free_gravity` / `anchor_stuck_gravity`.
pub fn anchor(water: Water, stuck: bool, loads: Loads) -> Step {
    let mut dag = Dag::new();
    let mut f = Function::new(Dag::new());
    let p = param_syms(&mut dag, Kind::Anchor, water, "p");
    let (cs, _) = rotations(&mut dag, Kind::Anchor);
    let zero = dag.zero();
    let b = body_syms(&mut dag, &p, cs, zero);
    let load = load_syms(&mut dag, loads, p.mass);
    let carry = articulated_carry(&mut dag);
    let ab = articulated_body(&mut dag, &b, load, Some(carry), "_1");
    let (s_dd, ret) = anchor_solve(&mut dag, ab, stuck);
    f.ret = std::iter::once(s_dd).chain(ret).collect();
    f.dag = dag;
    let (name, doc, friction) = if stuck {
        ("anchor_stuck", "The anchor held: returns [0, holding force (Eq. 50), normal force (Eq. 37)].", "")
    } else {
        (
            "anchor_free",
            "The anchor sliding with friction −`friction`·N: returns [s̈, normal force (Eq. 37), 1 + friction·∂N/∂F_x].",
            ", friction: f64",
        )
    };
    step(
        format!("{name}{}", loads.suffix()),
        Some(Kind::Anchor),
        doc,
        format!("{PARAMS}, {}, c: &[f64; 9]{friction}", loads.param()),
        f,
    )
}

/// Where the scratch row keeps a_{o_k} after the outward pass, for [`hinge`].
pub const HINGE_ACCELERATION: usize = 10;

/// `hinge`: the force on the bodies outboard of the hinge from the inner body (Eq. 52),
/// [F_x, F_z], from the row `s` the solve left: the force row of the inward pass and a_{o_k}
/// of the outward pass (`s[10..12]`).
pub fn hinge() -> Step {
    let mut dag = Dag::new();
    let mut f = Function::new(Dag::new());
    let s: Vec<Id> = (0..HINGE_ACCELERATION + 2).map(|i| dag.input(format!("s[{i}]"))).collect();
    let row = [s[5], s[6], s[7], s[8], s[9]];
    let force = hinge_force(&mut dag, row, [s[HINGE_ACCELERATION], s[HINGE_ACCELERATION + 1]]);
    f.ret = force.to_vec();
    f.dag = dag;
    step(
        "hinge".to_string(),
        None,
        "The force on the bodies outboard of one hinge from the inner body (Eq. 52), [F_x, F_z], from the solve's row.",
        "s: &[f64; crate::ROLLED_SCRATCH]".to_string(),
        f,
    )
}

/// `outward`: the outward pass across one hinge from the row `s` the inward pass stored;
/// the carry is [α, a_{o,x}, a_{o,z}]; returns it and β̈.
pub fn outward() -> Step {
    let mut dag = Dag::new();
    let mut f = Function::new(Dag::new());
    let s: Vec<Id> = (0..5).map(|i| dag.input(format!("s[{i}]"))).collect();
    let wp = dag.input("wp");
    let c = carry_in(&mut dag, 3);
    let gains = [s[2], s[3], s[4]];
    let (alpha, a, beta_dd) = outward_step(&mut dag, [s[0], s[1]], wp, c[0], [c[1], c[2]], gains, TAG, TAG);
    f.ret = vec![alpha, a[0], a[1], beta_dd];
    f.dag = dag;
    step(
        "outward".to_string(),
        None,
        "The outward pass across one hinge: [α, a_{o,x}, a_{o,z}] of the body and its β̈.",
        "s: &[f64; crate::ROLLED_SCRATCH], wp: f64, c: &[f64; 3]".to_string(),
        f,
    )
}

/// `outboard_<kind>` (rod or ship): the outboard sums Btot, S, J about the body's origin
/// (Eq. 26); stores `s[0..3]` = [S_x, S_z, J]; the carry is [Btot (xx, xz, zz), S (2), J].
pub fn outboard(kind: Kind, water: Water) -> Step {
    assert!(matches!(kind, Kind::Rod | Kind::Ship), "outboard sums are per rod or ship");
    let mut dag = Dag::new();
    let mut f = Function::new(Dag::new());
    let p = param_syms(&mut dag, kind, water, "p");
    let cs = pair(&mut dag, "t");
    let zero = dag.zero();
    let b = body_syms(&mut dag, &p, cs, zero);
    let child = (kind == Kind::Rod).then(|| {
        let pc = param_syms(&mut dag, Kind::Rod, water, "pc");
        let c = carry_in(&mut dag, 6);
        // Dry, every B_k = m_k 1: the sum is isotropic, which the DAG then uses.
        let bt = if water == Water::Off { [c[0], zero, c[0]] } else { [c[0], c[1], c[2]] };
        let d = rot(&mut dag, cs, pc.joint);
        (Outboard { bt, s: [c[3], c[4]], j: c[5] }, d, pc.joint)
    });
    let o = outboard_step(&mut dag, &b, child, TAG);
    f.store(Slot::at("s", 0), o.s[0]);
    f.store(Slot::at("s", 1), o.s[1]);
    f.store(Slot::at("s", 2), o.j);
    f.ret = vec![o.bt[0], o.bt[1], o.bt[2], o.s[0], o.s[1], o.j];
    f.dag = dag;
    let extra = if kind == Kind::Rod { format!(", {CHILD}, c: &[f64; 6]") } else { String::new() };
    step(
        format!("outboard_{}", kind.name()),
        Some(kind),
        "Outboard sums about the body's origin (Eq. 26), from the child's (`pc`, `c`).",
        format!("{PARAMS}, t: &[f64; 2]{extra}, s: &mut [f64; crate::ROLLED_SCRATCH]"),
        f,
    )
}

/// `link`: d_k = R(θ_{k−1}) q_k for a rod or the ship (joint on the parent's axis).
pub fn link() -> Step {
    let mut dag = Dag::new();
    let mut f = Function::new(Dag::new());
    let zero = dag.zero();
    let tp = pair(&mut dag, "tp");
    let jx = dag.input("jx");
    let d = rot(&mut dag, tp, [jx, zero]);
    f.ret = d.to_vec();
    f.dag = dag;
    step(
        "link".to_string(),
        None,
        "d_k = R(θ_{k−1}) (q_x, 0): the hinge-to-hinge vector of a rod or the ship.",
        "tp: &[f64; 2], jx: f64".to_string(),
        f,
    )
}

/// `surge_<kind>`: the body's terms of a_ss = Σ m + m_a sin²θ and a_ws = Σ m_a sin θ cos θ.
pub fn surge(kind: Kind, water: Water) -> Step {
    let mut dag = Dag::new();
    let mut f = Function::new(Dag::new());
    let p = param_syms(&mut dag, kind, water, "p");
    let [c, s] = if kind == Kind::Anchor { [dag.one(), dag.zero()] } else { pair(&mut dag, "t") };
    let s2 = dag.mul(s, s);
    let a = dag.mul(p.added_mass, s2);
    let t = dag.add(p.mass, a);
    let sc = dag.mul(s, c);
    let a = dag.mul(p.added_mass, sc);
    f.ret = vec![t, a];
    f.dag = dag;
    let t = if kind == Kind::Anchor { "" } else { ", t: &[f64; 2]" };
    step(
        format!("surge_{}", kind.name()),
        Some(kind),
        "The body's share of a_ss and a_ws (the anchor's surge row of Eq. 26 and its heave row).",
        format!("{PARAMS}{t}"),
        f,
    )
}

/// `effective_<kind>`: the velocity-product acceleration carried along the chain and the
/// effective force F̃_k = F_k − A_k ȧ_k (Eqs. 16, 22); the carry is ā_o (2); returns it and F̃.
pub fn effective(kind: Kind, water: Water) -> Step {
    let mut dag = Dag::new();
    let mut f = Function::new(Dag::new());
    let p = param_syms(&mut dag, kind, water, "p");
    let (cs, parent) = rotations(&mut dag, kind);
    let (w, wp) = angular_velocities(&mut dag, kind);
    let b = body_syms(&mut dag, &p, cs, w);
    let force = pair(&mut dag, "f");
    let zero = dag.zero();
    let (origin, hinge) = if kind == Kind::Anchor {
        ([zero, zero], None)
    } else {
        let c = carry_in(&mut dag, 2);
        let d = rot(&mut dag, parent, p.joint);
        ([c[0], c[1]], Some((d, wp)))
    };
    let [o, a] = centripetal_step(&mut dag, &b, origin, hinge, TAG);
    let fe = effective_force(&mut dag, &b, a, force, TAG);
    f.ret = vec![o[0], o[1], fe[0], fe[1]];
    f.dag = dag;
    let carry = if kind == Kind::Anchor { "" } else { ", c: &[f64; 2]" };
    step(
        format!("effective_{}", kind.name()),
        Some(kind),
        "The effective force on one body (Eqs. 16, 22), the velocity-product acceleration carried from the parent.",
        format!("{PARAMS}{}, f: &[f64; 3]{carry}", motion_params(kind)),
        f,
    )
}

/// `forces_<kind>`: the generalised forces carried inward (Eq. 25), [G (2), H]; the anchor
/// returns G only.
pub fn forces(kind: Kind, water: Water) -> Step {
    let mut dag = Dag::new();
    let mut f = Function::new(Dag::new());
    let zero = dag.zero();
    let fe = pair(&mut dag, "fe");
    let (params, ret) = match kind {
        Kind::Anchor => {
            let c = carry_in(&mut dag, 3);
            let (g, _) = force_sums(&mut dag, None, fe, zero, ([c[0], c[1]], c[2]), None, TAG);
            ("fe: &[f64; 2], c: &[f64; 3]".to_string(), g.to_vec())
        }
        _ => {
            let p = param_syms(&mut dag, kind, water, "p");
            let cs = pair(&mut dag, "t");
            let torque = dag.input("torque");
            let b = body_syms(&mut dag, &p, cs, zero);
            let (carried, d_child, extra) = if kind == Kind::Ship {
                (([zero, zero], zero), None, String::new())
            } else {
                let pc = param_syms(&mut dag, Kind::Rod, water, "pc");
                let c = carry_in(&mut dag, 3);
                let d = rot(&mut dag, cs, pc.joint);
                (([c[0], c[1]], c[2]), Some(d), format!(", {CHILD}, c: &[f64; 3]"))
            };
            let (g, h) = force_sums(&mut dag, Some(b.e), fe, torque, carried, d_child, TAG);
            let h = h.expect("a rotating body has a hinge");
            (format!("{PARAMS}, t: &[f64; 2], fe: &[f64; 2], torque: f64{extra}"), vec![g[0], g[1], h])
        }
    };
    f.ret = ret;
    f.dag = dag;
    step(
        format!("forces_{}", kind.name()),
        Some(kind),
        "The generalised forces carried inward (Eqs. 23, 25): [G_x, G_z, H_k = f_{β_k}] from the child's.",
        params,
        f,
    )
}

/// Every step of the rolled kernel of `water`, in the order they are emitted: the dry
/// kernel also has the solve steps under weight alone ([`Loads::Gravity`]).
pub fn steps(water: Water) -> Vec<Step> {
    use Kind::{Anchor, First, Rod, Ship};
    let mut out = Vec::new();
    for kind in [Anchor, First, Rod, Ship] {
        out.push(kinematics(kind, water));
    }
    for kind in [Anchor, First, Rod, Ship] {
        out.push(accelerations(kind, water));
    }
    let fused: &[Loads] = match water {
        Water::Off => &[Loads::Inputs, Loads::Gravity],
        Water::On => &[Loads::Inputs],
    };
    for &loads in fused {
        for kind in [Ship, Rod, First] {
            out.push(inward(kind, water, loads));
        }
        out.push(anchor(water, false, loads));
        out.push(anchor(water, true, loads));
    }
    out.push(outward());
    out.push(hinge());
    out.push(outboard(Ship, water));
    out.push(outboard(Rod, water));
    out.push(link());
    for kind in [Anchor, Rod, Ship] {
        out.push(surge(kind, water));
    }
    for kind in [Anchor, First, Rod, Ship] {
        out.push(effective(kind, water));
    }
    for kind in [Ship, Rod, Anchor] {
        out.push(forces(kind, water));
    }
    out
}

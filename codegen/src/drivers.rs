//! Emission of the rolled kernels: the steps of [`crate::rolled`] as `#[inline(always)]`
//! functions and the loops over the chain that drive them, one file per water switch
//! (`generated/src/rolled_dry.rs`, `rolled_wet.rs`).
//!
//! The loops are the same text for both files: what differs between the variants and the
//! body kinds lives in the steps. They mirror the unrolled kernels phase by phase (same
//! operations in the same order wherever the recursion allows), with the per-body
//! quantities a later phase reads kept in `scratch`, one row of
//! `kanestop_generated::ROLLED_SCRATCH` values per body.

use kanestop_chain::Water;
use proc_macro2::TokenStream;
use quote::{format_ident, quote};

use crate::emit::{body, header, FunctionReport};
use crate::rolled::{steps, Step};

/// One emitted rolled kernel file.
#[derive(Clone, Debug)]
pub struct RolledFile {
    /// Dry or wet.
    pub water: Water,
    /// File name under `generated/src/`: `rolled_dry.rs` or `rolled_wet.rs`.
    pub file_name: String,
    /// The source text.
    pub source: String,
    /// Each step's operations (per call, i.e. per body of its kind).
    pub steps: Vec<FunctionReport>,
}

/// The module name of the rolled kernel of `water`.
pub fn module(water: Water) -> String {
    format!("rolled_{}", water.suffix())
}

fn step_item(step: &Step) -> (TokenStream, FunctionReport) {
    let ops = step.function.dag.count(&step.function.roots());
    let (stmts, statements) = body(&step.function);
    let name = format_ident!("{}", step.name);
    let params: TokenStream = step.params.parse().expect("step parameters are Rust");
    let ret = match step.returns {
        0 => quote!(),
        n => {
            let n = proc_macro2::Literal::usize_unsuffixed(n);
            quote!(-> [f64; #n])
        }
    };
    let doc = format!(" {}", step.doc);
    let item = quote! {
        #[doc = #doc]
        #[inline(always)]
        pub(crate) fn #name(#params) #ret { #stmts }
    };
    (item, FunctionReport { name: step.name.clone(), ops, statements })
}

/// Generates the rolled kernel file of `water`.
pub fn generate_rolled(water: Water) -> RolledFile {
    let mut items = TokenStream::new();
    let mut reports = Vec::new();
    for step in steps(water) {
        let (item, report) = step_item(&step);
        items.extend(item);
        reports.push(report);
    }
    let wet = water == Water::On;
    let drivers = drivers();
    let solves = solve_drivers();
    let tokens = quote! {
        /// This variant, for [`crate::rolled`].
        pub const KERNEL: crate::RolledTable = crate::RolledTable {
            wet: #wet,
            kinematics,
            assemble,
            accelerations,
            solve_free,
            solve_stuck,
            joint_forces,
        };
        #drivers
        #solves
        #items
    };
    let file: syn::File = syn::parse2(tokens).expect("generated rolled code parses");
    let what = match water {
        Water::Off => "the planar chain of any N, rolled, water off (no added mass)",
        Water::On => "the planar chain of any N, rolled, water on (added mass on the rods, Eq. 46)",
    };
    let source = header(what) + "\n" + &prettyplease::unparse(&file);
    RolledFile { water, file_name: format!("{}.rs", module(water)), source, steps: reports }
}

/// The O(N) solve's entry points on loads computed elsewhere (the force modules): the
/// inward pass from the ship to B_2, then `solve_free` and `solve_stuck`, every body's load
/// read from `loads`. The scene's own loads run inside the fused right-hand sides
/// ([`crate::rhs`]), which drive the same steps.
fn solve_drivers() -> TokenStream {
    let what = "with the loads `loads` ([F_x, F_z, M_y] of every body at its centroid)";
    let pass_doc =
        format!(" The inward pass of the O(N) solve, from the ship to B_2, {what}; returns what reaches the anchor.");
    let free_doc = format!(
        " ẍ of Eq. 27 with the anchor free, by the O(N) articulated-body recursion, {what}; sliding friction \
         −`friction`·N along x. Returns `[N, 1 + friction·∂N/∂F_x]`."
    );
    let stuck_doc = format!(
        " ẍ of Eq. 27 with the anchor stuck, {what}; returns the holding force (Eq. 50) and the normal force (Eq. 37)."
    );
    quote! {
        #[doc = #pass_doc]
        fn inward_pass(
            p: &[crate::BodyParams],
            trig: &[[f64; 2]],
            loads: &[[f64; 3]],
            scratch: &mut [[f64; crate::ROLLED_SCRATCH]],
        ) -> [f64; 9] {
            const W: usize = crate::ROLLED_SCRATCH - 1;
            let n = p.len();
            let (w, wp) = (scratch[n - 1][W], scratch[n - 2][W]);
            let mut c = inward_ship(&p[n - 1], &trig[n - 1], w, &trig[n - 2], wp, &loads[n - 1], &mut scratch[n - 1]);
            for k in (2..n - 1).rev() {
                let (w, wp) = (scratch[k][W], scratch[k - 1][W]);
                c = inward_rod(&p[k], &trig[k], w, &trig[k - 1], wp, &loads[k], &c, &mut scratch[k]);
            }
            let w = scratch[1][W];
            inward_first(&p[1], &trig[1], w, &loads[1], &c, &mut scratch[1])
        }

        #[doc = #free_doc]
        pub fn solve_free(
            p: &[crate::BodyParams],
            u: &[f64],
            trig: &[[f64; 2]],
            loads: &[[f64; 3]],
            friction: f64,
            qdd: &mut [f64],
            scratch: &mut [[f64; crate::ROLLED_SCRATCH]],
        ) -> [f64; 2] {
            let n = self::bodies(p, &[u.len(), trig.len(), loads.len(), qdd.len(), scratch.len()]);
            let scratch = &mut scratch[..n];
            angular_velocities(u, scratch);
            let c = inward_pass(p, trig, loads, scratch);
            let [s_dd, normal, factor] = anchor_free(&p[0], &loads[0], &c, friction);
            outward_pass(s_dd, scratch, qdd);
            [normal, factor]
        }

        #[doc = #stuck_doc]
        pub fn solve_stuck(
            p: &[crate::BodyParams],
            u: &[f64],
            trig: &[[f64; 2]],
            loads: &[[f64; 3]],
            qdd: &mut [f64],
            scratch: &mut [[f64; crate::ROLLED_SCRATCH]],
        ) -> [f64; 2] {
            let n = self::bodies(p, &[u.len(), trig.len(), loads.len(), qdd.len(), scratch.len()]);
            let scratch = &mut scratch[..n];
            angular_velocities(u, scratch);
            let c = inward_pass(p, trig, loads, scratch);
            let [s_dd, holding, normal] = anchor_stuck(&p[0], &loads[0], &c);
            outward_pass(s_dd, scratch, qdd);
            [holding, normal]
        }
    }
}

// Long by design: the entry points and their shared passes, as they appear in the file.
/// The loops over the chain: the public entry points but the solves ([`solve_drivers`]; the
/// signatures of the unrolled kernels plus `scratch`) and the passes they share.
fn drivers() -> TokenStream {
    let hinge_acceleration = proc_macro2::Literal::usize_unsuffixed(crate::rolled::HINGE_ACCELERATION);
    quote! {
        /// The chain's length, checked against every argument.
        fn bodies(p: &[crate::BodyParams], lens: &[usize]) -> usize {
            let n = p.len();
            assert!(n >= 3, "a chain has at least an anchor, one rod and a ship");
            assert!(lens.iter().all(|&l| l >= n), "every argument must hold N = {n} entries");
            n
        }

        /// Body states (Eqs. 9, 13, 14) and the rotation table of a chain of any N:
        /// `trig[k] = [cos θ, sin θ]`, `bodies[k] = [x, z, θ, v_x, v_z, ω]` of C_k, B_1 first.
        pub fn kinematics(p: &[crate::BodyParams], q: &[f64], u: &[f64], trig: &mut [[f64; 2]], bodies: &mut [[f64; 6]]) {
            let n = self::bodies(p, &[q.len(), u.len(), trig.len(), bodies.len()]);
            // Cut to N: the loop's indices need no bounds checks.
            let (q, u, trig, bodies) = (&q[..n], &u[..n], &mut trig[..n], &mut bodies[..n]);
            // The rotating bodies' rotations first, two angles at a time: θ_k = Σ β_j (Eq. 1).
            crate::trig::rotations(&q[..n - 1], &mut trig[1..]);
            let mut c = kin_anchor(&p[0], q[n - 1], u[n - 1], &mut bodies[0], &mut trig[0]);
            c = kin_first(&p[1], q[0], u[0], &c, &trig[1], &mut bodies[1]);
            for k in 2..n - 1 {
                c = kin_rod(&p[k], q[k - 1], u[k - 1], &c, &trig[k], &mut bodies[k]);
            }
            kin_ship(&p[n - 1], q[n - 2], u[n - 2], &c, &trig[n - 1], &mut bodies[n - 1]);
        }

        /// Body accelerations (Eq. 17): `acc[k] = [a_x, a_z, α]` of C_k for generalised
        /// accelerations `qdd`.
        pub fn accelerations(p: &[crate::BodyParams], u: &[f64], trig: &[[f64; 2]], qdd: &[f64], acc: &mut [[f64; 3]]) {
            let n = self::bodies(p, &[u.len(), trig.len(), qdd.len(), acc.len()]);
            let (u, trig, qdd, acc) = (&u[..n], &trig[..n], &qdd[..n], &mut acc[..n]);
            let mut c = acc_anchor(&p[0], qdd[n - 1], &mut acc[0]);
            let mut w = u[0];
            c = acc_first(&p[1], &trig[1], w, qdd[0], &c, &mut acc[1]);
            for k in 2..n - 1 {
                let wp = w;
                w = wp + u[k - 1];
                c = acc_rod(&p[k], &trig[k], w, &trig[k - 1], wp, qdd[k - 1], &c, &mut acc[k]);
            }
            let wp = w;
            w = wp + u[n - 2];
            acc_ship(&p[n - 1], &trig[n - 1], w, &trig[n - 2], wp, qdd[n - 2], &c, &mut acc[n - 1]);
        }

        /// θ̇_k into the last column of every scratch row (θ̇_1 = 0).
        pub(crate) fn angular_velocities(u: &[f64], scratch: &mut [[f64; crate::ROLLED_SCRATCH]]) {
            let mut w = 0.0;
            let u = &u[..scratch.len() - 1];
            scratch[0][crate::ROLLED_SCRATCH - 1] = w;
            for k in 1..scratch.len() {
                w += u[k - 1];
                scratch[k][crate::ROLLED_SCRATCH - 1] = w;
            }
        }

        /// The outward pass of the O(N) solve from the anchor's s̈; keeps each hinge's a_{o_k}
        /// in its row, for [`joint_forces`].
        pub(crate) fn outward_pass(s_dd: f64, scratch: &mut [[f64; crate::ROLLED_SCRATCH]], qdd: &mut [f64]) {
            const A: usize = #hinge_acceleration;
            let n = scratch.len();
            qdd[n - 1] = s_dd;
            let mut c = [0.0, s_dd, 0.0];
            for k in 1..n {
                let [alpha, ax, az, beta_dd] = outward(&scratch[k], scratch[k - 1][crate::ROLLED_SCRATCH - 1], &c);
                (scratch[k][A], scratch[k][A + 1]) = (ax, az);
                qdd[k - 1] = beta_dd;
                c = [alpha, ax, az];
            }
        }

        /// The force on B_k from B_{k−1} through their hinge (Eq. 52), `out[k − 2]` = [F_x, F_z]
        /// for k = 2 … N, from the rows the last solve left in `scratch` (`solve_free`,
        /// `solve_stuck` or a fused right-hand side): no second pass over the chain's dynamics.
        pub fn joint_forces(scratch: &[[f64; crate::ROLLED_SCRATCH]], out: &mut [[f64; 2]]) {
            assert!(scratch.len() > out.len(), "the scratch must hold the N rows of the solve");
            for (k, f) in out.iter_mut().enumerate() {
                *f = hinge(&scratch[k + 1]);
            }
        }

        /// a_lp (Eq. 26), f_l (Eq. 25) and the anchor's heave row, as the unrolled `assemble`.
        /// Scratch rows: [S_x, S_z, J then K, ō_x, ō_z, F̃_x, F̃_z, θ̇].
        #[allow(clippy::too_many_arguments)]
        pub fn assemble(
            p: &[crate::BodyParams],
            u: &[f64],
            trig: &[[f64; 2]],
            loads: &[[f64; 3]],
            m: &mut [f64],
            f: &mut [f64],
            heave: &mut [f64],
            scratch: &mut [[f64; crate::ROLLED_SCRATCH]],
        ) {
            let n = self::bodies(p, &[u.len(), trig.len(), loads.len(), f.len(), heave.len() - 1, scratch.len()]);
            assert!(m.len() >= n * n, "m must hold N² entries");
            let scratch = &mut scratch[..n];
            angular_velocities(u, scratch);
            // Outboard sums, from the ship inward.
            let mut c = outboard_ship(&p[n - 1], &trig[n - 1], &mut scratch[n - 1]);
            for l in (1..n - 1).rev() {
                c = outboard_rod(&p[l], &trig[l], &p[l + 1], &c, &mut scratch[l]);
            }
            // Hinge positions ō_l relative to o_2.
            scratch[1][3] = 0.0;
            scratch[1][4] = 0.0;
            for l in 2..n {
                let d = link(&trig[l - 1], p[l].joint[0]);
                scratch[l][3] = scratch[l - 1][3] + d[0];
                scratch[l][4] = scratch[l - 1][4] + d[1];
            }
            // The diagonal, the surge column, the heave row and row 0; J_l becomes K_l = J_l + ō_l · S_l.
            for l in 1..n {
                let row = &mut scratch[l];
                let (sx, sz, j, c) = (row[0], row[1], row[2], l - 1);
                m[c * n + c] = j;
                m[c * n + n - 1] = sz;
                m[(n - 1) * n + c] = sz;
                heave[c] = -sx;
                let k = j + (row[3] * sx + row[4] * sz);
                row[2] = k;
                if l >= 2 {
                    m[c] = k;
                    m[c * n] = k;
                }
            }
            // The dense block: a_jl = K_l − ō_j · S_l, 1 ≤ j < l ≤ N − 2 in coordinates.
            for l in 2..n - 1 {
                let (k, sx, sz) = (scratch[l + 1][2], scratch[l + 1][0], scratch[l + 1][1]);
                for j in 1..l {
                    let a = k - (scratch[j + 1][3] * sx + scratch[j + 1][4] * sz);
                    m[j * n + l] = a;
                    m[l * n + j] = a;
                }
            }
            // a_ss and a_ws.
            let [mut ass, mut aws] = surge_anchor(&p[0]);
            for k in 1..n - 1 {
                let [a, b] = surge_rod(&p[k], &trig[k]);
                ass += a;
                aws += b;
            }
            let [a, b] = surge_ship(&p[n - 1], &trig[n - 1]);
            m[n * n - 1] = ass + a;
            heave[n - 1] = aws + b;
            // Effective forces, from the anchor outward.
            const W: usize = crate::ROLLED_SCRATCH - 1;
            let r = effective_anchor(&p[0], &loads[0]);
            (scratch[0][5], scratch[0][6]) = (r[2], r[3]);
            let r = effective_first(&p[1], &trig[1], scratch[1][W], &loads[1], &[r[0], r[1]]);
            (scratch[1][5], scratch[1][6]) = (r[2], r[3]);
            let mut o = [r[0], r[1]];
            for k in 2..n {
                let (w, wp) = (scratch[k][W], scratch[k - 1][W]);
                let r = if k + 1 < n {
                    effective_rod(&p[k], &trig[k], w, &trig[k - 1], wp, &loads[k], &o)
                } else {
                    effective_ship(&p[k], &trig[k], w, &trig[k - 1], wp, &loads[k], &o)
                };
                (scratch[k][5], scratch[k][6]) = (r[2], r[3]);
                o = [r[0], r[1]];
            }
            // Generalised forces, from the ship inward.
            let fe = |k: usize| [scratch[k][5], scratch[k][6]];
            let mut c = forces_ship(&p[n - 1], &trig[n - 1], &fe(n - 1), loads[n - 1][2]);
            f[n - 2] = c[2];
            for k in (1..n - 1).rev() {
                c = forces_rod(&p[k], &trig[k], &fe(k), loads[k][2], &p[k + 1], &c);
                f[k - 1] = c[2];
            }
            let g = forces_anchor(&fe(0), &c);
            f[n - 1] = g[0];
            heave[n] = g[1];
        }
    }
}

#[cfg(test)]
mod tests {
    use kanestop_chain::Water;

    use super::generate_rolled;

    #[test]
    fn rolled_emission_is_deterministic_and_parses() {
        for water in [Water::Off, Water::On] {
            let (a, b) = (generate_rolled(water), generate_rolled(water));
            assert_eq!(a.source, b.source);
            syn::parse_file(&a.source).expect("the rolled source parses");
            assert!(a.steps.iter().all(|s| s.statements > 0 || s.ops.total() == 0));
        }
    }

    #[test]
    fn dry_rolled_kernel_reads_no_added_mass() {
        assert!(!generate_rolled(Water::Off).source.contains("added_mass"));
        assert!(generate_rolled(Water::On).source.contains("p.added_mass"));
        // A child's added mass never enters a step (the child is read for its joint only).
        let wet = generate_rolled(Water::On).source;
        assert!(!wet.contains("pc.added_mass"));
    }
}

//! The fused right-hand sides: per [`LoadSignature`], one function per anchor state that
//! runs a scene's whole evaluation in one pass each way over the chain
//! (`generated/src/rhs.rs`):
//!
//! 1. the kinematics, from B_1 outward (Eqs. 9, 13, 14): body states and rotations;
//! 2. with a seabed, every element's contact (its embedded volume, [`crate::loads`]);
//! 3. from the ship inward, the loads of two elements at a time (on the two lanes of an
//!    `F2`, [`crate::loads`]'s pair functions) where the inward pass of the O(N) solve reaches
//!    them, then the pass's steps at those two bodies: the elements' loads and the
//!    articulated-body steps are independent, so the processor overlaps the loads'
//!    arithmetic with the pass's chain of dependent operations (one division per body);
//!    an odd element out, B_1, runs alone;
//! 4. the anchor (free with friction, or held), then the outward pass: ẍ.
//!
//! The steps are the rolled kernel's ([`crate::drivers`]) of the signature's water switch and
//! the load functions of the signature ([`crate::loads`]); nothing is computed twice, and
//! what a signature lacks is in neither. Weight alone (signature `dry`) runs the steps that
//! compute −m g themselves ([`crate::rolled::Loads::Gravity`]), so no load is read.
//!
//! The loads and the work terms' powers are left in the caller's `Workspace` for the
//! observation. The powers are summed from the ship inward, the order of the pass, the
//! paired elements' in a sum per lane added at the end: the force modules sum from the anchor
//! outward, so the two agree to round-off, not to the bit.

use kanestop_chain::{LoadSignature, Water};
use proc_macro2::TokenStream;
use quote::{format_ident, quote};

use crate::drivers::module;
use crate::emit::header;
use crate::loads::term_list;
use crate::rolled::Loads;

/// The emitted `generated/src/rhs.rs`.
pub struct RhsFile {
    /// The source text.
    pub source: String,
}

/// Whether `sig` runs the steps under weight alone.
fn weight_alone(sig: &LoadSignature) -> bool {
    *sig == LoadSignature::weight_only()
}

/// The water switch of the rolled steps a signature runs on.
pub fn water(sig: &LoadSignature) -> Water {
    if sig.water {
        Water::On
    } else {
        Water::Off
    }
}

/// The fused pass of one signature and its two entry points.
fn signature_rhs(sig: &LoadSignature) -> TokenStream {
    let n = sig.name();
    let r = format_ident!("{}", module(water(sig)));
    let (la, le, ls) =
        (format_ident!("load_anchor_{n}"), format_ident!("load_element_{n}"), format_ident!("load_ship_{n}"));
    let gravity = weight_alone(sig);
    let sfx = if gravity { Loads::Gravity } else { Loads::Inputs }.suffix();
    let id = |name: &str| format_ident!("{name}{sfx}");
    let (ship, rod, first) = (id("inward_ship"), id("inward_rod"), id("inward_first"));
    let (anchor_free, anchor_stuck) = (id("anchor_free"), id("anchor_stuck"));
    // What a step reads for its body's load: the load just computed, or g.
    let arg = |k: TokenStream| if gravity { quote!(lp.g) } else { quote!(&loads[#k]) };
    let (f_ship, f_first) = (arg(quote!(n - 1)), arg(quote!(1)));
    let f_anchor = if gravity { quote!(lp.g) } else { quote!(&ws.loads[0]) };
    let contacts = if sig.seabed {
        let lc = format_ident!("contacts_{n}");
        quote!(crate::loads::#lc(lp, e, bodies, trig, loads);)
    } else {
        TokenStream::new()
    };
    // B_1's contact, where it runs alone.
    let contact_first = if sig.seabed { quote!(loads[1]) } else { quote!([0.0; 3]) };
    // The inward step at element `k` (its inboard neighbour `j` = k − 1).
    let step = |k: TokenStream, j: TokenStream| {
        let f = arg(k.clone());
        quote! {
            let (w, wp) = (scratch[#k][W], scratch[#j][W]);
            c = crate::#r::#rod(&p[#k], &trig[#k], w, &trig[#j], wp, #f, &c, &mut scratch[#k]);
        }
    };
    let one = |k: TokenStream, contact: TokenStream| quote!(loads[#k] = crate::loads::#le(&p[#k], lp, &e[#k], &bodies[#k], &trig[#k], #contact, power););
    let elements = if gravity {
        // Weight alone (no seabed, so no contact): the steps compute −m g; the loads are kept
        // for the observation.
        let no_contact = quote!([0.0; 3]);
        let (load_k, step_k, load_1) =
            (one(quote!(k), no_contact.clone()), step(quote!(k), quote!(k - 1)), one(quote!(1), no_contact));
        quote! {
            for k in (2..n - 1).rev() {
                #load_k
                #step_k
            }
            #load_1
        }
    } else {
        // The elements' loads two at a time (B_k on lane 0, B_{k−1} on lane 1, their powers
        // summed per lane in `pair_power`), then the two steps; an odd element out, B_1, alone.
        let pair = format_ident!("load_element_pair_{n}");
        let load_pair = |k: TokenStream, j: TokenStream| {
            let contact = if sig.seabed { quote!([loads[#k], loads[#j]]) } else { quote!([[0.0; 3]; 2]) };
            quote! {
                [loads[#k], loads[#j]] = crate::loads::#pair(
                    [&p[#k], &p[#j]], lp, [&e[#k], &e[#j]], [&bodies[#k], &bodies[#j]],
                    [&trig[#k], &trig[#j]], #contact, &mut pair_power,
                );
            }
        };
        let (pair_k, pair_2) = (load_pair(quote!(k), quote!(k - 1)), load_pair(quote!(2), quote!(1)));
        let (step_k, step_j, step_2) =
            (step(quote!(k), quote!(k - 1)), step(quote!(k - 1), quote!(k - 2)), step(quote!(2), quote!(1)));
        let load_1 = one(quote!(1), contact_first);
        quote! {
            let mut pair_power = [crate::lanes::F2::splat(0.0); crate::POWER_TERMS];
            let mut k = n - 2;
            while k >= 3 {
                #pair_k
                #step_k
                #step_j
                k -= 2;
            }
            if k == 2 {
                #pair_2
                #step_2
            } else {
                #load_1
            }
            for (sum, lane) in power.iter_mut().zip(pair_power) {
                let [a, b] = lane.lanes();
                *sum += a + b;
            }
        }
    };
    let pass = format_ident!("pass_{n}");
    let (free, stuck) = (format_ident!("rhs_free_{n}"), format_ident!("rhs_stuck_{n}"));
    let terms = term_list(sig);
    let pass_doc = format!(
        " Kinematics, then the loads of signature `{n}` ({terms}) with the inward pass of the O(N) solve, \
         the loads where the pass reaches each body (the line elements' two at a time, except under weight \
         alone); returns what reaches the anchor."
    );
    let free_doc = format!(
        " The right-hand side of signature `{n}` with the anchor free: ẍ of Eq. 27 at (q, u), sliding friction \
         −`friction`·N along x. Returns `[N, 1 + friction·∂N/∂F_x]`; the states, loads and powers are left in `ws`."
    );
    let stuck_doc = format!(
        " The right-hand side of signature `{n}` with the anchor held: ẍ of Eq. 27 at (q, u). Returns the holding \
         force (Eq. 50) and the normal force (Eq. 37); the states, loads and powers are left in `ws`."
    );
    quote! {
        #[doc = #pass_doc]
        #[inline(always)]
        fn #pass(
            p: &[crate::BodyParams],
            lp: &crate::LoadParams,
            e: &[crate::Element],
            q: &[f64],
            u: &[f64],
            ws: &mut crate::Workspace,
        ) -> [f64; 9] {
            const W: usize = crate::ROLLED_SCRATCH - 1;
            let n = p.len();
            let crate::Workspace { trig, bodies, loads, power: powers, scratch } = ws;
            crate::#r::kinematics(p, q, u, trig, bodies);
            // Every array cut to N: the indices below need no bounds checks.
            let (e, trig, bodies) = (&e[..n], &trig[..n], &bodies[..n]);
            let (loads, scratch) = (&mut loads[..n], &mut scratch[..n]);
            crate::#r::angular_velocities(u, scratch);
            #contacts
            // Summed in a local, which stays in registers (the stores into `ws`'s heap arrays
            // would otherwise make LLVM reload `ws.power`, whose disjointness it is not told),
            // and stored once.
            let mut sums = [0.0; crate::POWER_TERMS];
            let power = &mut sums;
            loads[n - 1] = crate::loads::#ls(&p[n - 1], lp, &bodies[n - 1], power);
            let (w, wp) = (scratch[n - 1][W], scratch[n - 2][W]);
            let mut c = crate::#r::#ship(&p[n - 1], &trig[n - 1], w, &trig[n - 2], wp, #f_ship, &mut scratch[n - 1]);
            #elements
            let c = crate::#r::#first(&p[1], &trig[1], scratch[1][W], #f_first, &c, &mut scratch[1]);
            loads[0] = crate::loads::#la(&p[0], lp, &bodies[0], power);
            *powers = sums;
            c
        }

        #[doc = #free_doc]
        #[allow(clippy::too_many_arguments)]
        pub fn #free(
            p: &[crate::BodyParams],
            lp: &crate::LoadParams,
            e: &[crate::Element],
            q: &[f64],
            u: &[f64],
            friction: f64,
            ws: &mut crate::Workspace,
            qdd: &mut [f64],
        ) -> [f64; 2] {
            let n = ws.check(p, &[e.len(), q.len(), u.len(), qdd.len()]);
            let c = #pass(p, lp, e, q, u, ws);
            let [s_dd, normal, factor] = crate::#r::#anchor_free(&p[0], #f_anchor, &c, friction);
            crate::#r::outward_pass(s_dd, &mut ws.scratch[..n], qdd);
            [normal, factor]
        }

        #[doc = #stuck_doc]
        pub fn #stuck(
            p: &[crate::BodyParams],
            lp: &crate::LoadParams,
            e: &[crate::Element],
            q: &[f64],
            u: &[f64],
            ws: &mut crate::Workspace,
            qdd: &mut [f64],
        ) -> [f64; 2] {
            let n = ws.check(p, &[e.len(), q.len(), u.len(), qdd.len()]);
            let c = #pass(p, lp, e, q, u, ws);
            let [s_dd, holding, normal] = crate::#r::#anchor_stuck(&p[0], #f_anchor, &c);
            crate::#r::outward_pass(s_dd, &mut ws.scratch[..n], qdd);
            [holding, normal]
        }
    }
}

/// Generates the fused right-hand side of every signature and their registry.
pub fn generate_rhs() -> RhsFile {
    let mut items = TokenStream::new();
    let mut entries = Vec::new();
    for sig in LoadSignature::all() {
        items.extend(signature_rhs(&sig));
        let n = sig.name();
        let wet = sig.water;
        let (free, stuck) = (format_ident!("rhs_free_{n}"), format_ident!("rhs_stuck_{n}"));
        entries.push(quote!((#n, crate::RhsTable { wet: #wet, free: #free, stuck: #stuck })));
    }
    let count = proc_macro2::Literal::usize_unsuffixed(entries.len());
    let tokens = quote! {
        /// Every signature's right-hand side, by [`kanestop_chain::LoadSignature::name`].
        pub const RHS: [(&str, crate::RhsTable); #count] = [#(#entries),*];
        #items
    };
    let file: syn::File = syn::parse2(tokens).expect("generated right-hand sides parse");
    let source = header("the rolled steps and the load code, one fused right-hand side per load signature")
        + "\n"
        + &prettyplease::unparse(&file);
    RhsFile { source }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn rhs_code_is_deterministic_and_parses() {
        let (a, b) = (generate_rhs(), generate_rhs());
        assert_eq!(a.source, b.source);
        syn::parse_file(&a.source).expect("parses");
        for sig in LoadSignature::all() {
            let n = sig.name();
            for entry in ["rhs_free", "rhs_stuck"] {
                assert_eq!(a.source.matches(&format!("pub fn {entry}_{n}(")).count(), 1, "{entry}_{n}");
            }
        }
    }

    #[test]
    fn only_weight_alone_runs_the_gravity_steps() {
        let source = generate_rhs().source;
        for sig in LoadSignature::all() {
            let start = source.find(&format!("fn pass_{}(", sig.name())).unwrap();
            let end = start + source[start..].find("\n}\n").unwrap();
            let pass = &source[start..end];
            assert_eq!(pass.contains("inward_rod_gravity"), weight_alone(&sig), "{}", sig.name());
            assert_eq!(pass.contains("contacts_"), sig.seabed, "{}", sig.name());
            assert!(pass.contains(&format!("crate::{}::kinematics", module(water(&sig)))), "{}", sig.name());
        }
    }
}

//! The generated loads: per [`LoadSignature`], one function per body kind (anchor, line
//! element, ship) and, with a seabed, the elements' contact, each term of Section 3.2 emitted
//! only where the signature has it (`generated/src/loads.rs`). The signature's fused
//! right-hand side ([`crate::rhs`]) calls them where its pass over the chain reaches each body.
//!
//! The runtime's force modules (`runtime/src/forces/`) are the readable statement of the
//! physics and the oracle of this code: the terms below are the same formulas, specialised
//! (a term the signature lacks is not emitted; zero components of a force are not
//! multiplied out) and written with the same operations in the same order, so that a
//! generated load equals the force modules' to the last bit wherever IEEE arithmetic
//! allows (`tests/fused_loads.rs` checks them on random states: equal as numbers).
//!
//! The loads are piecewise (the wetted fraction, U|U|, the two cases of Eq. 47), which the
//! expression DAG of [`crate::expr`] does not model; they are emitted as Rust fragments, and
//! their operations are counted on the emitted syntax ([`count`]). The seabed's embedded
//! volume is the one call: the runtime hands its closed form in (`LoadParams::embedded_volumes`),
//! so the generated crate depends on nothing and the volume has one statement. It runs in a
//! pass of its own over the elements before their loads (`contacts_<signature>`), which marks
//! the touching elements and makes one call for all of them.
//!
//! Per body the generated function reads the state `s = [x, z, θ, v_x, v_z, ω]` and the
//! rotation `t = [cos θ, sin θ]` the kinematics computed (no transcendental function of θ
//! again), and adds each term's power (the work terms of the energy balance, Eq. 63) into
//! `power`, indexed as the runtime's `WORK_TERMS`.
//!
//! The line elements' loads come in two forms: one element (`load_element_<signature>`) and
//! two at once on the lanes of the generated crate's `F2` (`load_element_pair_<signature>`,
//! which the fused pass runs), the same statements with each branch a select, so each lane
//! equals the single element's function bit for bit. The operation counts ([`LoadReport`])
//! are the single element's.

use std::collections::BTreeMap;

use kanestop_chain::{LoadSignature, LoadTerm};
use proc_macro2::{Literal, TokenStream};
use quote::{format_ident, quote};
use syn::visit::Visit;

use crate::emit::header;

/// Index of each work term in the power array (the runtime's `WORK_TERMS` order:
/// buoyancy, seabed, anchor friction, line friction, anchor drag, line drag, hull
/// resistance, hydrostatic, added mass). `tests/fused_loads.rs` checks the names against the
/// runtime's `WORK_TERMS`.
pub const POWER_INDEX: [(&str, usize); 9] = [
    ("buoyancy", 0),
    ("seabed", 1),
    ("anchor_friction", 2),
    ("line_friction", 3),
    ("anchor_drag", 4),
    ("line_drag", 5),
    ("hull_resistance", 6),
    ("hydrostatic", 7),
    ("added_mass", 8),
];

fn power(name: &str) -> TokenStream {
    let i = POWER_INDEX.iter().find(|(n, _)| *n == name).expect("a work term").1;
    let i = proc_macro2::Literal::usize_unsuffixed(i);
    quote!(power[#i])
}

/// Operations of emitted code, counted on its syntax.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct LoadOps {
    /// Additions and subtractions (compound assignments included).
    pub add: usize,
    /// Multiplications.
    pub mul: usize,
    /// Divisions.
    pub div: usize,
    /// Negations.
    pub neg: usize,
    /// Comparisons (the branches of the piecewise terms).
    pub cmp: usize,
    /// Function calls: `sqrt`, `tanh`, `powf`, `log10`, `abs`, `signum`, `min`, `max`,
    /// `clamp`, `powi`, and the embedded volume.
    pub func: usize,
}

impl LoadOps {
    /// Every operation.
    pub fn total(&self) -> usize {
        self.add + self.mul + self.div + self.neg + self.cmp + self.func
    }
}

impl std::ops::AddAssign for LoadOps {
    fn add_assign(&mut self, o: LoadOps) {
        self.add += o.add;
        self.mul += o.mul;
        self.div += o.div;
        self.neg += o.neg;
        self.cmp += o.cmp;
        self.func += o.func;
    }
}

impl<'a> Visit<'a> for LoadOps {
    fn visit_expr_binary(&mut self, e: &'a syn::ExprBinary) {
        use syn::BinOp::*;
        match e.op {
            Add(_) | Sub(_) | AddAssign(_) | SubAssign(_) => self.add += 1,
            Mul(_) | MulAssign(_) => self.mul += 1,
            Div(_) | DivAssign(_) => self.div += 1,
            Lt(_) | Le(_) | Gt(_) | Ge(_) | Eq(_) | Ne(_) => self.cmp += 1,
            _ => {}
        }
        syn::visit::visit_expr_binary(self, e);
    }

    fn visit_expr_unary(&mut self, e: &'a syn::ExprUnary) {
        if matches!(e.op, syn::UnOp::Neg(_)) {
            self.neg += 1;
        }
        syn::visit::visit_expr_unary(self, e);
    }

    fn visit_expr_method_call(&mut self, e: &'a syn::ExprMethodCall) {
        self.func += 1;
        syn::visit::visit_expr_method_call(self, e);
    }

    fn visit_expr_call(&mut self, e: &'a syn::ExprCall) {
        self.func += 1;
        syn::visit::visit_expr_call(self, e);
    }
}

/// The operations of a fragment of statements.
pub fn count(fragment: &TokenStream) -> LoadOps {
    let block: syn::Block = syn::parse2(quote!({ #fragment })).expect("a load fragment is Rust");
    let mut ops = LoadOps::default();
    ops.visit_block(&block);
    ops
}

/// Where a body's load code runs.
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord)]
pub enum LoadBody {
    /// B_1.
    Anchor,
    /// A chain link or cable element (B_2 … B_{N−1}; the rod in air carries its weight only).
    Element,
    /// B_N.
    Ship,
}

impl LoadBody {
    /// `anchor`, `element`, `ship`.
    pub fn name(self) -> &'static str {
        match self {
            LoadBody::Anchor => "anchor",
            LoadBody::Element => "element",
            LoadBody::Ship => "ship",
        }
    }
}

/// What the load code of one signature costs: operations per call of each body's
/// function, by term.
#[derive(Clone, Debug)]
pub struct LoadReport {
    /// The signature.
    pub signature: LoadSignature,
    /// (body, term) → operations per call.
    pub ops: BTreeMap<(LoadBody, LoadTerm), LoadOps>,
    /// body → operations per call that several terms share (a line element's rotation and
    /// end heights), in no term's count.
    pub shared: BTreeMap<LoadBody, LoadOps>,
}

impl LoadReport {
    /// Operations per call of `body`'s function, all terms.
    pub fn body_total(&self, body: LoadBody) -> usize {
        let shared = self.shared.get(&body).map_or(0, LoadOps::total);
        shared + self.ops.iter().filter(|((b, _), _)| *b == body).map(|(_, o)| o.total()).sum::<usize>()
    }

    /// Operations per call of `body`'s function that several terms share.
    pub fn shared_total(&self, body: LoadBody) -> usize {
        self.shared.get(&body).map_or(0, LoadOps::total)
    }

    /// Operations of `term` over a chain of `lines` line elements and `rods` rods in air
    /// (the anchor and the ship once): a line element runs the whole element function, a
    /// rod in air only its weight.
    pub fn term_total(&self, term: LoadTerm, lines: usize, rods: usize) -> usize {
        let calls = |b: LoadBody| match b {
            LoadBody::Element if term == LoadTerm::Weight => lines + rods,
            LoadBody::Element => lines,
            LoadBody::Anchor | LoadBody::Ship => 1,
        };
        self.ops.iter().filter(|((_, t), _)| *t == term).map(|((b, _), o)| o.total() * calls(*b)).sum()
    }
}

/// The pieces of one body's function: each term's statements, in order, with the
/// operations counted for the term (a term whose statements hold another's, as the seabed's
/// hold the line friction's, is counted without them).
struct Pieces {
    /// (term, or None for statements the terms share; code; its operations).
    terms: Vec<(Option<LoadTerm>, TokenStream, LoadOps)>,
}

impl Pieces {
    fn new() -> Self {
        Pieces { terms: Vec::new() }
    }

    fn push(&mut self, term: LoadTerm, code: TokenStream) {
        let ops = count(&code);
        self.terms.push((Some(term), code, ops));
    }

    /// Statements several terms use, counted apart.
    fn push_shared(&mut self, code: TokenStream) {
        let ops = count(&code);
        self.terms.push((None, code, ops));
    }

    /// `code`, counted as `counted` for `term` (the rest is counted by [`Pieces::count`]).
    fn push_counted(&mut self, term: LoadTerm, code: TokenStream, counted: &TokenStream) {
        self.terms.push((Some(term), code, count(counted)));
    }

    /// Operations of `term` emitted inside another term's statements.
    fn count(&mut self, term: LoadTerm, code: &TokenStream) {
        self.terms.push((Some(term), TokenStream::new(), count(code)));
    }

    fn record(&self, body: LoadBody, report: &mut LoadReport) {
        for (term, _, ops) in &self.terms {
            match term {
                Some(t) => *report.ops.entry((body, *t)).or_default() += *ops,
                None => *report.shared.entry(body).or_default() += *ops,
            }
        }
    }

    fn code(&self) -> TokenStream {
        self.terms.iter().map(|(_, c, _)| c.clone()).collect()
    }
}

/// The current at height `z` (tokens of an f64 expression), Eq. 38: U_ST (h/d)^(1/7) with h
/// the height above the seabed clamped to [0, d], as `Current::at`.
fn current_at(sig: &LoadSignature, z: TokenStream) -> (TokenStream, TokenStream) {
    if sig.current {
        let code = quote! {
            let current = lp.current_speed * ((#z - lp.seabed_z).clamp(0.0, lp.water_depth) / lp.water_depth).powf(lp.current_exponent);
        };
        (code, quote!(current))
    } else {
        (quote!(), quote!(0.0))
    }
}

/// B_1: weight, buoyancy (Eq. 36) and the current drag (Eq. 39). Its friction is the
/// solve's (Eq. 37).
fn anchor(sig: &LoadSignature, report: &mut LoadReport) -> TokenStream {
    let mut p = Pieces::new();
    p.push(LoadTerm::Weight, quote! { let mut fx = 0.0; let mut fz = -p.mass * lp.g; });
    if sig.water {
        let pb = power("buoyancy");
        p.push(
            LoadTerm::Buoyancy,
            quote! {
                let buoyancy = lp.rho * lp.anchor_volume * lp.g;
                fz += buoyancy;
                #pb += buoyancy * s[4];
            },
        );
        let (current, u_c) = current_at(sig, quote!(s[1]));
        p.push(LoadTerm::Current, current);
        let pd = power("anchor_drag");
        p.push(
            LoadTerm::AnchorDrag,
            quote! {
                let u = #u_c - s[3];
                let drag = 0.5 * lp.anchor_drag * lp.rho * lp.anchor_area * u * u.abs();
                fx += drag;
                #pd += drag * s[3];
            },
        );
    }
    p.record(LoadBody::Anchor, report);
    let body = p.code();
    let name = format_ident!("load_anchor_{}", sig.name());
    quote! {
        /// B_1's load at its state `s`.
        #[inline(always)]
        pub(crate) fn #name(p: &crate::BodyParams, lp: &crate::LoadParams, s: &[f64; 6], power: &mut [f64; crate::POWER_TERMS]) -> [f64; 3] {
            #body
            [fx, fz, 0.0]
        }
    }
}

/// A chain link or cable element: weight, the seabed (Eq. 41) with the line's friction,
/// buoyancy less the embedded volume (Eq. 42), Morison drag (Eqs. 43–47) on the wetted
/// fraction, and the added mass's power. The rod in air (`e.line` false) carries its weight.
fn element(sig: &LoadSignature, report: &mut LoadReport) -> TokenStream {
    let mut p = Pieces::new();
    p.push(
        LoadTerm::Weight,
        quote! {
            let mut fx = 0.0;
            let mut fz = -p.mass * lp.g;
            let mut my = 0.0;
        },
    );
    let line = sig.seabed || sig.water;
    if line {
        // The rod in air stops at its weight.
        p.push(
            LoadTerm::Weight,
            quote! {
                if !e.line {
                    return [fx, fz, my];
                }
            },
        );
        // The rotation and the element's ends (`end_heights`).
        let ends = end_heights();
        p.push_shared(quote! {
            let (cos, sin) = (t[0], t[1]);
            #ends
        });
    }
    if sig.seabed {
        let ps = power("seabed");
        let embedded = if sig.water { quote!(embedded = v;) } else { quote!() };
        let declare = if sig.water { quote!(let mut embedded = 0.0;) } else { quote!() };
        let friction = if sig.line_friction {
            let pf = power("line_friction");
            quote! {
                let slip = s[3] - xi * s[5] * sin;
                let friction = -lp.line_friction * reaction * (slip / lp.slip_speed).tanh();
                let m = -(xi * sin) * friction;
                fx += friction;
                my += m;
                #pf += friction * s[3] + m * s[5];
            }
        } else {
            quote!()
        };
        let seabed = |friction: &TokenStream| {
            quote! {
                #declare
                let [v, s_bar, _] = contact;
                if v > 0.0 {
                    #embedded
                    let xi = s_bar - half;
                    let reaction = lp.seabed_stiffness * v;
                    let m = -(xi * cos * reaction);
                    fz += reaction;
                    my += m;
                    #ps += reaction * s[4] + m * s[5];
                    #friction
                }
            }
        };
        p.push_counted(LoadTerm::Seabed, seabed(&friction), &seabed(&TokenStream::new()));
        if sig.line_friction {
            p.count(LoadTerm::LineFriction, &friction);
        }
    }
    if sig.water {
        let pb = power("buoyancy");
        let embedded = if sig.seabed { quote!(embedded) } else { quote!(0.0) };
        p.push(
            LoadTerm::Buoyancy,
            quote! {
                let (lo, hi) = (za.min(zb), za.max(zb));
                let fraction = if hi <= 0.0 { 1.0 } else if lo >= 0.0 { 0.0 } else { -lo / (hi - lo) };
                if fraction == 0.0 {
                    return [fx, fz, my];
                }
                let wet_centre = if fraction == 1.0 {
                    0.0
                } else {
                    let low_end = if za < zb { -half } else { half };
                    low_end - low_end.signum() * fraction * half
                };
                let volume = e.volume * fraction;
                let buoyancy = lp.rho * lp.g * (volume - #embedded).max(0.0);
                let m = -(wet_centre * cos * buoyancy);
                fz += buoyancy;
                my += m;
                #pb += buoyancy * s[4] + m * s[5];
            },
        );
        let (current, u_c) = current_at(sig, quote!(s[1]));
        p.push(LoadTerm::Current, current);
        let pd = power("line_drag");
        let pa = power("added_mass");
        p.push(
            LoadTerm::LineDrag,
            quote! {
                let (rel_x, rel_z) = (#u_c - s[3], -s[4]);
                let v_t = rel_x * cos - rel_z * sin;
                let u_n = rel_x * sin + rel_z * cos;
                let (w, len) = (s[5], e.length);
                let k = e.normal_drag;
                let (f_n, m_n) = if u_n.abs() >= w.abs() * half {
                    let sign = u_n.signum();
                    (k * sign * (u_n * u_n * len + w * w * e.length_cubed / 12.0), -k * sign * u_n * w * e.length_cubed / 6.0)
                } else {
                    let (wa, wb) = (u_n - w * half, u_n + w * half);
                    let (f2a, f2b) = (wa * wa * wa.abs() / 3.0, wb * wb * wb.abs() / 3.0);
                    let (f3a, f3b) = (wa * wa * wa * wa.abs() / 4.0, wb * wb * wb * wb.abs() / 4.0);
                    let force = (f2b - f2a) / w;
                    let first_moment = (f3b - f3a - u_n * (f2b - f2a)) / (w * w);
                    (k * force, -k * first_moment)
                };
                let f_t = e.tangential_drag * v_t * v_t.abs();
                let (f_n, m_n, f_t) = (f_n * fraction, m_n * fraction, f_t * fraction);
                let (dx, dz) = (f_n * sin + f_t * cos, f_n * cos - f_t * sin);
                fx += dx;
                fz += dz;
                my += m_n;
                #pd += dx * s[3] + dz * s[4] + m_n * w;
                let (bt, bn) = (s[3] * cos - s[4] * sin, s[3] * sin + s[4] * cos);
                #pa += p.added_mass * w * bt * bn;
            },
        );
    }
    p.record(LoadBody::Element, report);
    let body = p.code();
    let name = format_ident!("load_element_{}", sig.name());
    let unused = match (line, sig.seabed) {
        (false, _) => quote!(let _ = (e, s, t, contact);),
        (true, false) => quote!(let _ = contact;),
        (true, true) => quote!(),
    };
    quote! {
        /// The load of a line element (or of the rod in air) at its state `s` and rotation `t`,
        /// with its seabed contact (embedded volume and centroid, zeros without a seabed).
        #[inline(always)]
        pub(crate) fn #name(
            p: &crate::BodyParams,
            lp: &crate::LoadParams,
            e: &crate::Element,
            s: &[f64; 6],
            t: &[f64; 2],
            contact: [f64; 3],
            power: &mut [f64; crate::POWER_TERMS],
        ) -> [f64; 3] {
            #unused
            #body
            [fx, fz, my]
        }
    }
}

/// Two line elements' loads at once, element `[0]` on lane 0 and `[1]` on lane 1 of the
/// generated crate's `lanes::F2`: the statements of [`element`], each
/// lane doing the scalar code's operations in its order, so each lane's load equals the scalar
/// function's bit for bit. A branch of the scalar code becomes a select: both sides computed,
/// the lane's taken (the contact's `v > 0`, the wetted fraction's cases, Eq. 47's two cases);
/// a term the scalar code skips adds nothing to the lane (its update selected away, its power
/// masked to +0). A function with no lane form (`tanh`, `powf`) runs once per lane. The
/// powers accumulate per lane, in `power`, for the pass to add up at its end.
fn element_pair(sig: &LoadSignature) -> TokenStream {
    debug_assert!(sig.seabed || sig.water, "weight alone has no element term to pair");
    // `let name = F2::new(field(0), field(1));`: a number of each element in its lane.
    let gather = |name: &str, field: &dyn Fn(Literal) -> TokenStream| {
        let name = format_ident!("{name}");
        let (a, b) = (field(Literal::usize_unsuffixed(0)), field(Literal::usize_unsuffixed(1)));
        quote!(let #name = F2::new(#a, #b);)
    };
    let mut body = TokenStream::new();
    body.extend(gather("weight", &|i| quote!(-p[#i].mass * lp.g)));
    body.extend(quote! {
        let zero = F2::splat(0.0);
        let (mut fx, mut fz, mut my) = (zero, weight, zero);
        // The rod in air keeps its weight: every other term is masked by `line`.
        let line = F2::mask([e[0].line, e[1].line]);
    });
    body.extend(gather("cos", &|i| quote!(t[#i][0])));
    if sig.water || sig.line_friction {
        body.extend(gather("sin", &|i| quote!(t[#i][1])));
        body.extend(gather("vx", &|i| quote!(s[#i][3])));
    }
    body.extend(quote!(let half = F2::splat(0.5) * F2::new(e[0].length, e[1].length);));
    if sig.water {
        // The ends' heights (`end_heights`), for the wetted fraction.
        body.extend(gather("z", &|i| quote!(s[#i][1])));
        body.extend(quote!(let (za, zb) = (z + half * sin, z - half * sin);));
    }
    body.extend(gather("vz", &|i| quote!(s[#i][4])));
    body.extend(gather("w", &|i| quote!(s[#i][5])));
    if sig.seabed {
        let ps = power("seabed");
        body.extend(gather("v", &|i| quote!(contact[#i][0])));
        body.extend(gather("s_bar", &|i| quote!(contact[#i][1])));
        body.extend(quote! {
            let touching = v.gt(zero).keep_mask(line);
            let xi = s_bar - half;
            let reaction = F2::splat(lp.seabed_stiffness) * v;
            let m = -(xi * cos * reaction);
            fz = fz.select(touching, fz + reaction);
            my = my.select(touching, my + m);
            #ps = #ps + (reaction * vz + m * w).keep_mask(touching);
        });
        if sig.line_friction {
            let pf = power("line_friction");
            body.extend(quote! {
                let slip = vx - xi * w * sin;
                let friction = F2::splat(-lp.line_friction) * reaction * (slip / F2::splat(lp.slip_speed)).map(f64::tanh);
                let m = -(xi * sin) * friction;
                fx = fx.select(touching, fx + friction);
                my = my.select(touching, my + m);
                #pf = #pf + (friction * vx + m * w).keep_mask(touching);
            });
        }
        if sig.water {
            body.extend(quote!(let embedded = zero.select(touching, v);));
        }
    }
    if sig.water {
        let (pb, pd, pa) = (power("buoyancy"), power("line_drag"), power("added_mass"));
        let embedded = if sig.seabed { quote!(embedded) } else { quote!(zero) };
        body.extend(gather("volume", &|i| quote!(e[#i].volume)));
        body.extend(quote! {
            let lower = za.lt(zb);
            let (lo, hi) = (zb.select(lower, za), za.select(lower, zb));
            let fraction = (-lo / (hi - lo)).select(lo.ge(zero), zero).select(hi.le(zero), F2::splat(1.0));
            let wet = fraction.ne(zero).keep_mask(line);
            let low_end = half.select(lower, -half);
            let wet_centre = (low_end - F2::splat(1.0).copysign(low_end) * fraction * half).select(fraction.eq(F2::splat(1.0)), zero);
            let volume = volume * fraction;
            let above = volume - #embedded;
            let buoyancy = F2::splat(lp.rho * lp.g) * zero.select(above.gt(zero), above);
            let m = -(wet_centre * cos * buoyancy);
            let (mut fx_wet, mut fz_wet, mut my_wet) = (fx, fz + buoyancy, my + m);
            #pb = #pb + (buoyancy * vz + m * w).keep_mask(wet);
        });
        let u_c = if sig.current {
            body.extend(quote! {
                let depth = F2::splat(lp.water_depth);
                let current = F2::splat(lp.current_speed)
                    * ((z - F2::splat(lp.seabed_z)).clamp(zero, depth) / depth).map(|h| h.powf(lp.current_exponent));
            });
            quote!(current)
        } else {
            quote!(zero)
        };
        body.extend(gather("len", &|i| quote!(e[#i].length)));
        body.extend(gather("cubed", &|i| quote!(e[#i].length_cubed)));
        body.extend(gather("k", &|i| quote!(e[#i].normal_drag)));
        body.extend(gather("tangential", &|i| quote!(e[#i].tangential_drag)));
        body.extend(gather("added_mass", &|i| quote!(p[#i].added_mass)));
        body.extend(quote! {
            let (rel_x, rel_z) = (#u_c - vx, -vz);
            let v_t = rel_x * cos - rel_z * sin;
            let u_n = rel_x * sin + rel_z * cos;
            // Eq. 47's two cases, the lane's selected.
            let clear = u_n.abs().ge(w.abs() * half);
            let sign = F2::splat(1.0).copysign(u_n);
            let f_clear = k * sign * (u_n * u_n * len + w * w * cubed / F2::splat(12.0));
            let m_clear = -k * sign * u_n * w * cubed / F2::splat(6.0);
            let (wa, wb) = (u_n - w * half, u_n + w * half);
            let (f2a, f2b) = (wa * wa * wa.abs() / F2::splat(3.0), wb * wb * wb.abs() / F2::splat(3.0));
            let (f3a, f3b) = (wa * wa * wa * wa.abs() / F2::splat(4.0), wb * wb * wb * wb.abs() / F2::splat(4.0));
            let force = (f2b - f2a) / w;
            let first_moment = (f3b - f3a - u_n * (f2b - f2a)) / (w * w);
            let f_n = (k * force).select(clear, f_clear);
            let m_n = (-k * first_moment).select(clear, m_clear);
            let f_t = tangential * v_t * v_t.abs();
            let (f_n, m_n, f_t) = (f_n * fraction, m_n * fraction, f_t * fraction);
            let (dx, dz) = (f_n * sin + f_t * cos, f_n * cos - f_t * sin);
            fx_wet = fx_wet + dx;
            fz_wet = fz_wet + dz;
            my_wet = my_wet + m_n;
            #pd = #pd + (dx * vx + dz * vz + m_n * w).keep_mask(wet);
            let (bt, bn) = (vx * cos - vz * sin, vx * sin + vz * cos);
            #pa = #pa + (added_mass * w * bt * bn).keep_mask(wet);
            fx = fx.select(wet, fx_wet);
            fz = fz.select(wet, fz_wet);
            my = my.select(wet, my_wet);
        });
    }
    let name = format_ident!("load_element_pair_{}", sig.name());
    let scalar =
        format!(" The loads of two elements, as [`load_element_{}`] gives each, on the lanes of an `F2`.", sig.name());
    quote! {
        #[doc = #scalar]
        #[inline(always)]
        pub(crate) fn #name(
            p: [&crate::BodyParams; 2],
            lp: &crate::LoadParams,
            e: [&crate::Element; 2],
            s: [&[f64; 6]; 2],
            t: [&[f64; 2]; 2],
            contact: [[f64; 3]; 2],
            power: &mut [crate::lanes::F2; crate::POWER_TERMS],
        ) -> [[f64; 3]; 2] {
            use crate::lanes::F2;
            #body
            let [fx, fz, my] = [fx.lanes(), fz.lanes(), my.lanes()];
            [[fx[0], fz[0], my[0]], [fx[1], fz[1], my[1]]]
        }
    }
}

/// The seabed's contact of every line element: `loads[k] = [V^S, s̄, 0]` (Eq. 41's embedded
/// volume and its centroid from the `za` end), zeros for the rod in air and for an element
/// clear of the seabed (as `embedded_volume` gives there; a NaN height still reaches it). Run
/// over the elements before their loads, in a pass of its own: it marks each touching
/// element's row with its end heights, `[h_a, h_b, 1]`, and one call of the runtime's
/// `LoadParams::embedded_volumes` turns those into volumes, two elements at a time; the
/// element loads then run without a call.
fn contact(sig: &LoadSignature, report: &mut LoadReport) -> TokenStream {
    let ends = end_heights();
    let marks = quote! {
        if !e.line {
            continue;
        }
        #ends
        let (ha, hb) = (za - lp.seabed_z, zb - lp.seabed_z);
        if ha >= e.radius && hb >= e.radius {
            continue;
        }
        loads[k] = [ha, hb, 1.0];
    };
    let volumes = quote! { (lp.embedded_volumes)(&elements[1..n - 1], &mut loads[1..n - 1]); };
    let mut p = Pieces::new();
    p.push(LoadTerm::Seabed, marks.clone());
    p.count(LoadTerm::Seabed, &volumes);
    p.record(LoadBody::Element, report);
    let name = format_ident!("contacts_{}", sig.name());
    quote! {
        /// The seabed contact `[V^S, s̄, 0]` of every line element B_2 … B_{N−1} into `loads`,
        /// from the states `bodies` and rotations `trig`; zeros where an element does not touch.
        #[inline(always)]
        pub(crate) fn #name(lp: &crate::LoadParams, elements: &[crate::Element], bodies: &[[f64; 6]], trig: &[[f64; 2]], loads: &mut [[f64; 3]]) {
            let n = elements.len();
            for k in 1..n - 1 {
                loads[k] = [0.0; 3];
                let (e, s, t) = (&elements[k], &bodies[k], &trig[k]);
                #marks
            }
            #volumes
        }
    }
}

/// A line element's half length and the heights of its ends `za`, `zb` (ex = (cos, −sin), as
/// `Forces::element_loads`), from its state `s` and rotation `t`: the element's loads and its
/// seabed contact state them alike.
fn end_heights() -> TokenStream {
    quote! {
        let half = 0.5 * e.length;
        let (za, zb) = (s[1] + half * t[1], s[1] - half * t[1]);
    }
}

/// B_N: weight, the hydrostatics (Eqs. 54, 58) and the hull resistance (Eqs. 59–62).
fn ship(sig: &LoadSignature, report: &mut LoadReport) -> TokenStream {
    let mut p = Pieces::new();
    p.push(LoadTerm::Weight, quote! { let mut fx = 0.0; let mut fz = -p.mass * lp.g; let mut my = 0.0; });
    if sig.water {
        let ph = power("hydrostatic");
        p.push(
            LoadTerm::Hydrostatics,
            quote! {
                let vertical = lp.rho * lp.g * (lp.ship_volume - lp.ship_waterplane_area * s[1]);
                fz += vertical;
                #ph += vertical * s[4];
                let pitch = -lp.rho * lp.g * lp.ship_volume * lp.ship_metacentric_height * s[2];
                my += pitch;
                #ph += pitch * s[5];
            },
        );
        let (current, u_c) = current_at(sig, quote!(0.0));
        p.push(LoadTerm::Current, current);
        let pr = power("hull_resistance");
        p.push(LoadTerm::HullResistance, quote! {
            let v_rel = s[3] - #u_c;
            let re = v_rel.abs() * lp.ship_length / lp.viscosity;
            let lg = re.max(lp.min_reynolds).log10();
            let c_f = 0.075 / ((lg - 2.0) * (lg - 2.0));
            let resistance = -0.5 * (c_f + lp.roughness_allowance) * lp.rho * lp.ship_wetted_surface * v_rel * v_rel.abs();
            fx += resistance;
            #pr += resistance * s[3];
        });
    }
    p.record(LoadBody::Ship, report);
    let body = p.code();
    let name = format_ident!("load_ship_{}", sig.name());
    let unused = if sig.water { quote!() } else { quote!(let _ = s;) };
    quote! {
        /// B_N's load at its state `s`.
        #[inline(always)]
        pub(crate) fn #name(p: &crate::BodyParams, lp: &crate::LoadParams, s: &[f64; 6], power: &mut [f64; crate::POWER_TERMS]) -> [f64; 3] {
            #unused
            #body
            [fx, fz, my]
        }
    }
}

/// The tokens and the report of one signature's load functions.
pub fn signature_code(sig: &LoadSignature) -> (TokenStream, LoadReport) {
    let mut report = LoadReport { signature: *sig, ops: BTreeMap::new(), shared: BTreeMap::new() };
    let (a, e, s) = (anchor(sig, &mut report), element(sig, &mut report), ship(sig, &mut report));
    let c = if sig.seabed { contact(sig, &mut report) } else { TokenStream::new() };
    let pair = if sig.seabed || sig.water { element_pair(sig) } else { TokenStream::new() };
    let tokens = quote! {
        #a
        #c
        #e
        #pair
        #s
    };
    (tokens, report)
}

/// The terms of `sig`, comma-separated.
pub(crate) fn term_list(sig: &LoadSignature) -> String {
    sig.terms().iter().map(|t| t.name()).collect::<Vec<_>>().join(", ")
}

/// The emitted `generated/src/loads.rs`: every signature's functions.
pub struct LoadsFile {
    /// The source text.
    pub source: String,
    /// Each signature's operation counts.
    pub reports: Vec<LoadReport>,
}

/// Generates the load code of every signature.
pub fn generate_loads() -> LoadsFile {
    let mut items = TokenStream::new();
    let mut reports = Vec::new();
    for sig in LoadSignature::all() {
        let (tokens, report) = signature_code(&sig);
        items.extend(tokens);
        reports.push(report);
    }
    let file: syn::File = syn::parse2(items).expect("generated load code parses");
    let source = header("the load terms of Section 3.2, the functions of each load signature")
        + "\n"
        + &prettyplease::unparse(&file);
    LoadsFile { source, reports }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn load_code_is_deterministic_and_parses() {
        let (a, b) = (generate_loads(), generate_loads());
        assert_eq!(a.source, b.source);
        syn::parse_file(&a.source).expect("parses");
        assert_eq!(a.reports.len(), LoadSignature::all().len());
    }

    #[test]
    fn power_indices_are_distinct_and_in_order() {
        for (i, (_, k)) in POWER_INDEX.iter().enumerate() {
            assert_eq!(i, *k);
        }
    }
}

//! The generated kernels against the reference formulation (the oracle), for every variant
//! (water off and on; anchor free and stuck) and N ∈ {3, 5, 46, 48, 50}, at 100 random
//! states each (the rolled kernel at N ∈ {3, 4, 5, 11, 46, 51}, the last four of which no build
//! has unrolled): body states and their rotation table, a_lp, f_l and the anchor's heave row
//! entrywise to 1e-12 of their scale; body accelerations, and both solve paths by the residual of the reference
//! system, with the anchor stuck, free, or sliding with implicit friction; the normal force
//! of the heave row against Newton's sum over the bodies (Eq. 52).

mod common;

use std::path::Path;

use common::*;
use kanestop_runtime::chain::Chain;
use kanestop_runtime::generated::{Form, GeneratedError, GeneratedKernel, SolvePath};
use kanestop_runtime::kernel::{
    solve_assembled, AnchorDof, Assembly, BodyAcceleration, BodyState, Kernel, Load, LoadModel, RhsError,
};
use kanestop_runtime::model::Model;
use kanestop_runtime::reference::ReferenceKernel;
use kanestop_runtime::scene::Scene;
use nalgebra::DVector;
use rand::rngs::StdRng;
use rand::Rng;

const STATES: usize = 100;

/// Loads that depend on the body states (so a kernel must hand the right states to the
/// force models), plus fixed random parts: weight, linear drag on velocity and spin, a
/// position-dependent spring.
struct StateLoads {
    fixed: Vec<Load>,
    masses: Vec<f64>,
}

impl LoadModel for StateLoads {
    fn loads(&mut self, bodies: &[BodyState], loads: &mut [Load]) {
        for (k, (l, b)) in loads.iter_mut().zip(bodies).enumerate() {
            let m = self.masses[k];
            *l = Load {
                fx: self.fixed[k].fx - 0.3 * m * b.vx - 0.01 * m * b.x,
                fz: self.fixed[k].fz - G * m - 0.3 * m * b.vz - 0.01 * m * b.z,
                my: self.fixed[k].my - 0.2 * m * b.omega + 0.1 * m * b.sin,
            };
        }
    }

    fn fused(&mut self, _power: &[f64]) {
        unreachable!("these loads are never offered to a kernel for fusing");
    }
}

fn random_loads(chain: &Chain, rng: &mut StdRng) -> StateLoads {
    let fixed = chain
        .bodies
        .iter()
        .map(|b| Load {
            fx: rng.gen_range(-1.0..1.0) * b.mass * G,
            fz: rng.gen_range(-1.0..1.0) * b.mass * G,
            my: rng.gen_range(-1.0..1.0) * b.mass * G,
        })
        .collect();
    StateLoads { fixed, masses: chain.bodies.iter().map(|b| b.mass).collect() }
}

fn paper_chain(case: &str, wet: bool, rng: &mut StdRng) -> Chain {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let scene = Scene::load(&root.join("scenes/paper").join(case)).unwrap();
    let mut chain = Model::new(&scene).unwrap().chain;
    let has_added_mass = chain.bodies.iter().any(|b| b.added_mass != 0.0);
    for b in chain.bodies.iter_mut().filter(|b| b.kind.is_rod_like()) {
        if !wet {
            b.added_mass = 0.0;
            b.added_inertia = 0.0;
        } else if !has_added_mass {
            // Added mass of the order Eq. 46 gives submerged rods (C_M ρ π D² L / 4).
            b.added_mass = rng.gen_range(0.2..1.2) * b.mass;
            b.added_inertia = b.added_mass * b.length() * b.length() / 12.0;
        }
    }
    chain
}

/// The chains a size is checked on: random chains and, for the paper's sizes, the paper's.
fn chains(n: usize, wet: bool, rng: &mut StdRng) -> Vec<Chain> {
    let random = if wet { random_wet_chain(n, rng) } else { random_chain(n, rng) };
    let mut out = vec![random];
    let case = match n {
        46 => Some("case01.toml"),
        48 | 50 => std::fs::read_dir(Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes/paper"))
            .unwrap()
            .flatten()
            .map(|e| e.path())
            .find(|p| {
                let scene = Scene::load(p).unwrap();
                Model::new(&scene).unwrap().body_count() == n
            })
            .map(|p| p.file_name().unwrap().to_str().unwrap().to_string())
            .map(|s| Box::leak(s.into_boxed_str()) as &str),
        _ => None,
    };
    if let Some(case) = case {
        out.push(paper_chain(case, wet, rng));
    }
    out
}

/// The seabed's normal force on the anchor by Newton's sum over all bodies (Eq. 52 at the
/// anchor): N = Σ_k (m_k a_kz + m_a,k a_kn cos θ_k − F_kz).
fn newton_normal(chain: &Chain, bodies: &[BodyState], acc: &[BodyAcceleration], loads: &[Load]) -> f64 {
    let mut sum = 0.0;
    for (((b, s), a), l) in chain.bodies.iter().zip(bodies).zip(acc).zip(loads) {
        let (sin, cos) = s.theta.sin_cos();
        let a_n = a.ax * sin + a.az * cos;
        sum += b.mass * a.az + b.added_mass * a_n * cos - l.fz;
    }
    sum
}

fn check_size(n: usize, wet: bool) {
    check_form(n, wet, Form::Unrolled);
}

fn check_form(n: usize, wet: bool, form: Form) {
    let mut rng = rng(1000 + n as u64 + wet as u64);
    let chains = chains(n, wet, &mut rng);
    check_chains(&chains, n, wet, form, &mut rng);
}

fn check_chains(chains: &[Chain], n: usize, wet: bool, form: Form, rng: &mut StdRng) {
    let per_chain = STATES.div_ceil(chains.len());
    let mut worst = [0.0f64; 5];
    let mut sliding = 0;
    for chain in chains {
        let mut reference = ReferenceKernel::new(chain);
        let mut generated = GeneratedKernel::with_form(chain, form).unwrap();
        assert_eq!((generated.is_wet(), generated.form()), (wet, form));
        let mut assembled = GeneratedKernel::with_form(chain, form).unwrap().with_solve_path(SolvePath::Assembled);
        for trial in 0..per_chain {
            let (q, mut u) = random_state(n, rng);
            let mut loads = random_loads(chain, rng);
            // Free without friction, stuck, sliding either way (k = ±μ).
            let (anchor, friction) = match trial % 4 {
                0 => (AnchorDof::Free, 0.0),
                1 | 3 => (AnchorDof::Stuck, 0.0),
                _ => (AnchorDof::Free, rng.gen_range(-0.6..0.6)),
            };
            if anchor == AnchorDof::Stuck {
                u[n - 1] = 0.0;
            }
            let mut a_ref = Assembly::new(n);
            let mut a_gen = Assembly::new(n);
            reference.assemble(&q, &u, &mut loads, &mut a_ref);
            generated.assemble(&q, &u, &mut loads, &mut a_gen);

            // Body states.
            for (k, (r, g)) in a_ref.bodies.iter().zip(&a_gen.bodies).enumerate() {
                let scale = 1.0 + r.x.abs().max(r.z.abs());
                let vscale = 1.0 + r.vx.abs().max(r.vz.abs());
                assert!((r.x - g.x).abs() <= 1e-12 * scale && (r.z - g.z).abs() <= 1e-12 * scale, "N={n} B_{k}");
                assert!((r.vx - g.vx).abs() <= 1e-12 * vscale && (r.vz - g.vz).abs() <= 1e-12 * vscale);
                assert!((r.theta - g.theta).abs() <= 1e-14 * (1.0 + r.theta.abs()), "N={n} θ of B_{k}");
                assert!((r.omega - g.omega).abs() <= 1e-14 * (1.0 + r.omega.abs()), "N={n} ω of B_{k}");
                // The rotation table the force models read (cos θ, sin θ of the same θ).
                assert!((r.cos - g.cos).abs() <= 1e-14 && (r.sin - g.sin).abs() <= 1e-14, "N={n} trig of B_{k}");
                assert!((g.cos - g.theta.cos()).abs() <= 1e-15 && (g.sin - g.theta.sin()).abs() <= 1e-15);
            }

            // a_lp entrywise, scaled by the diagonal (|a_ij| ≤ √(a_ii a_jj)); f by its norm.
            let (m_ref, m_gen) = (&a_ref.mass, &a_gen.mass);
            for i in 0..n {
                for j in 0..n {
                    let scale = (m_ref[(i, i)] * m_ref[(j, j)]).sqrt();
                    let d = (m_ref[(i, j)] - m_gen[(i, j)]).abs() / scale;
                    worst[0] = worst[0].max(d);
                    assert!(d <= 1e-12, "N={n} wet={wet} M[{i},{j}]: {} vs {} ({d:e})", m_ref[(i, j)], m_gen[(i, j)]);
                }
            }
            let f_scale = a_ref.rhs.norm();
            for i in 0..n {
                let d = (a_ref.rhs[i] - a_gen.rhs[i]).abs() / f_scale;
                worst[1] = worst[1].max(d);
                assert!(d <= 1e-12, "N={n} wet={wet} f[{i}]: {} vs {} ({d:e})", a_ref.rhs[i], a_gen.rhs[i]);
            }

            // The heave row, on the scale of a_ss and of f.
            let h_scale = m_ref[(n - 1, n - 1)];
            for p in 0..n {
                let d = (a_ref.heave[p] - a_gen.heave[p]).abs() / (h_scale * m_ref[(p, p)]).sqrt();
                worst[0] = worst[0].max(d);
                assert!(d <= 1e-12, "N={n} wet={wet} a_w[{p}]: {} vs {} ({d:e})", a_ref.heave[p], a_gen.heave[p]);
            }
            let d = (a_ref.heave_rhs - a_gen.heave_rhs).abs() / f_scale.max(a_ref.heave_rhs.abs());
            worst[1] = worst[1].max(d);
            assert!(d <= 1e-12, "N={n} wet={wet} f_w: {} vs {} ({d:e})", a_ref.heave_rhs, a_gen.heave_rhs);

            // Both solve paths, judged by the reference system.
            let active = if anchor == AnchorDof::Free { n } else { n - 1 };
            let mut qdd_ref = vec![0.0; n];
            let reference_solve = solve_assembled(&a_ref, anchor, friction, &mut qdd_ref);
            let mut scratch = Assembly::new(n);
            for (kernel, slot) in [(&mut generated, 2), (&mut assembled, 3)] {
                let mut qdd = vec![0.0; n];
                let solved = kernel.solve(&q, &u, anchor, friction, &mut loads, &mut scratch, &mut qdd);
                let (reaction, reaction_ref) = match (solved, &reference_solve) {
                    (Ok(a), Ok(b)) => (a, *b),
                    (Err(a), Err(_)) => {
                        // Friction made the sliding problem ill-posed for both.
                        assert!(
                            matches!(a, RhsError::IllPosedFriction { .. }) && a.to_string().contains("Painlevé"),
                            "{a}"
                        );
                        continue;
                    }
                    (a, b) => panic!("N={n} {anchor:?} k={friction}: {a:?} vs reference {b:?}"),
                };
                sliding += usize::from(friction != 0.0);
                let r = residual(&a_ref, active, friction, &qdd);
                worst[slot] = worst[slot].max(r);
                assert!(r <= 1e-12, "N={n} wet={wet} {anchor:?} {:?}: residual {r:e}", kernel.solve_path());
                // N = a_w ẍ − f_w, on the scale of its terms.
                let row: f64 =
                    (0..active).map(|p| (a_ref.heave[p] * qdd[p]).abs()).sum::<f64>() + a_ref.heave_rhs.abs();
                let normal =
                    a_ref.heave.rows(0, active).dot(&DVector::from_column_slice(&qdd[..active])) - a_ref.heave_rhs;
                for value in [reaction.normal, reaction_ref.normal] {
                    let d = (value - normal).abs() / row;
                    assert!(d <= 1e-10, "N={n} {anchor:?} normal force {value} vs {normal} ({d:e})");
                }
                if anchor == AnchorDof::Stuck {
                    assert_eq!(qdd[n - 1], 0.0);
                    // F = a_{N,p} ẍ_p − f_N: compare on the scale of its terms.
                    let row: f64 = (0..active).map(|p| (a_ref.mass[(n - 1, p)] * qdd[p]).abs()).sum::<f64>()
                        + a_ref.rhs[n - 1].abs();
                    let d = (reaction.holding - reaction_ref.holding).abs() / row;
                    assert!(d <= 1e-10, "N={n} holding force {} vs {} ({d:e})", reaction.holding, reaction_ref.holding);
                } else {
                    assert_eq!(reaction.holding, 0.0);
                }
            }
            let Ok(reaction_ref) = reference_solve else { continue };

            // The heave row's normal force is Newton's: N by Eq. 52 from the accelerations.
            let mut acc = vec![BodyAcceleration::default(); n];
            reference.accelerations(&q, &u, &qdd_ref, &mut acc);
            let mut applied = vec![Load::default(); n];
            loads.loads(&a_ref.bodies, &mut applied);
            let newton = newton_normal(chain, &a_ref.bodies, &acc, &applied);
            let scale: f64 = applied.iter().map(|l| l.fz.abs()).sum();
            let d = (newton - reaction_ref.normal).abs() / scale;
            assert!(
                d <= 1e-10,
                "N={n} wet={wet} normal force: Kane {} vs Newton {newton} ({d:e})",
                reaction_ref.normal
            );

            // Body accelerations (Eq. 17) for the same ẍ.
            let mut acc_ref = vec![BodyAcceleration::default(); n];
            let mut acc_gen = vec![BodyAcceleration::default(); n];
            reference.accelerations(&q, &u, &qdd_ref, &mut acc_ref);
            generated.accelerations(&q, &u, &qdd_ref, &mut acc_gen);
            let a_scale = acc_ref.iter().map(|a| a.ax.abs().max(a.az.abs()).max(a.alpha.abs())).fold(1.0, f64::max);
            for (r, g) in acc_ref.iter().zip(&acc_gen) {
                let d = (r.ax - g.ax).abs().max((r.az - g.az).abs()).max((r.alpha - g.alpha).abs()) / a_scale;
                worst[4] = worst[4].max(d);
                assert!(d <= 1e-12, "N={n} accelerations: {r:?} vs {g:?}");
            }
        }
    }
    // Both solve paths of most sliding trials were checked (not skipped as ill-posed).
    assert!(sliding >= STATES / 4, "N={n}: only {sliding} sliding solves checked");
    eprintln!(
        "N={n} wet={wet} {}: worst M {:.1e}, f {:.1e}, residual recursive {:.1e}, assembled {:.1e}, acc {:.1e}, \
         {sliding} sliding solves",
        form.name(),
        worst[0],
        worst[1],
        worst[2],
        worst[3],
        worst[4]
    );
}

/// The checked-in folded kernel (case 1's numbers as literals) is taken for case 1's chain
/// and agrees with the oracle as the kept kernels do; a chain one number off gets the kept
/// kernel, and asking it for the folded form is a clear error.
#[test]
fn folded_kernel_matches_reference_on_its_chain() {
    let mut rng = rng(2046);
    let chain = paper_chain("case01.toml", true, &mut rng);
    assert_eq!(GeneratedKernel::new(&chain).unwrap().form(), Form::Folded, "the build folds case 1");
    check_chains(std::slice::from_ref(&chain), 46, true, Form::Folded, &mut rng);
    let mut other = chain.clone();
    other.bodies[45].mass += 1.0;
    assert_eq!(GeneratedKernel::new(&other).unwrap().form(), Form::Unrolled);
    let err = GeneratedKernel::with_form(&other, Form::Folded).err().expect("no folded kernel for it");
    assert_eq!(err, GeneratedError::NotFolded { bodies: 46 });
    assert!(err.to_string().contains("kanestop codegen --scene SCENE --fold DIR"), "{err}");
}

/// The rolled kernel (any N) at the unrolled sizes and at sizes no build has.
#[test]
fn rolled_matches_reference_at_any_n() {
    for n in [3, 4, 5, 11, 46, 51] {
        check_form(n, false, Form::Rolled);
        check_form(n, true, Form::Rolled);
    }
}

#[test]
fn generated_matches_reference_n3() {
    check_size(3, false);
    check_size(3, true);
}

#[test]
fn generated_matches_reference_n5() {
    check_size(5, false);
    check_size(5, true);
}

#[test]
fn generated_matches_reference_n46() {
    check_size(46, false);
    check_size(46, true);
}

#[test]
fn generated_matches_reference_n48() {
    check_size(48, false);
    check_size(48, true);
}

#[test]
fn generated_matches_reference_n50() {
    check_size(50, false);
    check_size(50, true);
}

#[test]
fn chain_that_breaks_a_structural_zero_is_refused() {
    let mut rng = rng(5);
    let mut chain = random_chain(5, &mut rng);
    chain.bodies[2].centroid[1] = 0.1;
    let err = GeneratedKernel::new(&chain).err().expect("refused");
    let text = err.to_string();
    assert!(text.contains("B_3") && text.contains("centroid[1]"), "{err}");
    assert!(matches!(err, GeneratedError::FoldedParameter { body: 2, value: 0.1, .. }), "{err:?}");
    let mut chain = random_chain(5, &mut rng);
    chain.bodies[4].added_mass = 1.0;
    assert!(GeneratedKernel::new(&chain).is_err());
}

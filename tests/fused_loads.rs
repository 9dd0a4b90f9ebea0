//! The fused right-hand sides (issue 14): per load signature, kinematics, the generated load
//! code (`generated/src/loads.rs`) and the O(N) solve in one generated function
//! (`generated/src/rhs.rs`) replace the kernel's kinematics, the force modules and its solve;
//! weight alone goes further, into the rolled kernel's own steps (`rhs_free_dry`).
//!
//! Checked against the oracles at 100 random states per scene, for every paper scene, every
//! stress scene, case 1 under each of the nine load signatures and random scenes, from the
//! kernel `GeneratedKernel::new` picks (unrolled where the build has one: fusing moves it to
//! the rolled steps the fused functions drive):
//! - the loads against the force modules (`Forces`, the oracle of the physics): equal, as
//!   floating-point numbers (within 1e-12 of their scale is allowed per entry, and equality
//!   asserted over each set); the work terms' power within 1e-14 of its scale (the fused
//!   pass sums from the ship inward, two elements at a time, the force modules from the
//!   anchor outward);
//! - ẍ from the fused solve against the same kernel fed by the force modules, and through
//!   its normwise backward error in the reference system (the oracle of the dynamics), to
//!   1e-12 (the residual relative to ‖f‖ alone is reported beside the reference's own
//!   solve's: a scene's a_lp spans ten orders of magnitude, see `common::backward_error`);
//!
//! and in the code: a term a signature leaves out is not in its generated code.

mod common;

use std::path::Path;

use common::*;
use kanestop_chain::{LoadSignature, LoadTerm, Water};
use kanestop_codegen::loads::{generate_loads, signature_code, LoadBody};
use kanestop_codegen::rolled::{anchor, inward, Kind, Loads};
use kanestop_runtime::chain::Chain;
use kanestop_runtime::dynamics::{fused_loads, Dynamics};
use kanestop_runtime::forces::anchor::AnchorForces;
use kanestop_runtime::forces::{Forces, WORK_TERMS};
use kanestop_runtime::generated::{Form, GeneratedKernel, SolvePath};
use kanestop_runtime::kernel::{AnchorDof, Assembly, BodyState, Kernel, Load, LoadModel};
use kanestop_runtime::model::Model;
use kanestop_runtime::reference::ReferenceKernel;
use kanestop_runtime::scene::Scene;
use rand::rngs::StdRng;
use rand::Rng;

const STATES: usize = 100;
const TOL: f64 = 1e-12;

/// A load model that records what a fused kernel tells it, and fails if it is asked to
/// compute.
#[derive(Default)]
struct Told {
    power: Vec<f64>,
}

impl LoadModel for Told {
    fn loads(&mut self, _bodies: &[BodyState], _loads: &mut [Load]) {
        panic!("a fused kernel computes its loads itself");
    }

    fn fused(&mut self, power: &[f64]) {
        self.power = power.to_vec();
    }
}

/// The loads a fused solve kept ([`Kernel::last_loads`]), failing if it kept none.
fn kept_loads(kernel: &impl Kernel, n: usize) -> Vec<Load> {
    let mut loads = vec![Load { fx: f64::NAN, fz: f64::NAN, my: f64::NAN }; n];
    assert!(kernel.last_loads(&mut loads), "a fused solve keeps its loads");
    loads
}

/// The relative difference of two vectors, on the scale of the larger.
fn rel(a: &[f64], b: &[f64]) -> f64 {
    let scale = a.iter().chain(b).fold(1.0f64, |m, x| m.max(x.abs()));
    a.iter().zip(b).map(|(x, y)| (x - y).abs()).fold(0.0, f64::max) / scale
}

fn load_scene(path: &Path) -> Model {
    Model::new(&Scene::load(path).unwrap()).unwrap_or_else(|e| panic!("{}: {e}", path.display()))
}

fn scenes(dir: &str) -> Vec<(String, Model)> {
    let mut files: Vec<_> = std::fs::read_dir(Path::new(env!("CARGO_MANIFEST_DIR")).join(dir))
        .unwrap()
        .map(|e| e.unwrap().path())
        .filter(|p| p.extension().is_some_and(|x| x == "toml"))
        .collect();
    files.sort();
    files.iter().map(|p| (p.file_stem().unwrap().to_string_lossy().into_owned(), load_scene(p))).collect()
}

/// A state near the scene's start: the angles moved by up to `spread` rad, the anchor by up
/// to a metre, speeds of order one (so the line lifts off and presses into the seabed,
/// crosses the surface at either end and drags both ways).
fn near_start(model: &Model, rng: &mut StdRng, spread: f64) -> (Vec<f64>, Vec<f64>) {
    let n = model.body_count();
    let mut q = model.q0.clone();
    let mut u = model.u0.clone();
    for (k, (qk, uk)) in q.iter_mut().zip(&mut u).enumerate() {
        *qk += if k == n - 1 { rng.gen_range(-1.0..1.0) } else { rng.gen_range(-spread..spread) };
        *uk += rng.gen_range(-1.0..1.0);
    }
    (q, u)
}

/// Scale of body k's load entries: its weight, and its weight times its length for the moment.
fn load_scales(chain: &Chain, g: f64) -> Vec<[f64; 3]> {
    chain
        .bodies
        .iter()
        .map(|b| {
            let w = b.mass * g;
            [w, w, w * b.length().max(1.0)]
        })
        .collect()
}

/// What the checks of one scene found: the worst relative differences.
#[derive(Default, Debug, Clone, Copy)]
struct Worst {
    loads: f64,
    power: f64,
    qdd: f64,
    /// How often the piecewise branches were met (at the oracle's states): an element
    /// partly wet with its a end lowest, with its b end lowest; Morison drag's second case
    /// (the normal flow changing sign along the element); an element on the seabed; the
    /// line's friction working.
    partly_wet: [usize; 2],
    flow_reversing: usize,
    grounded: usize,
    sliding: usize,
    /// The fused solve's backward error in the reference system.
    residual: f64,
    /// ‖M ẍ − f‖/‖f‖ of the fused solve and of the reference's own Cholesky solve.
    fused_residual: f64,
    reference_residual: f64,
}

/// The checks of one model: `states` random states.
fn check_model(name: &str, model: &Model, seed: u64, states: usize) -> Worst {
    let n = model.body_count();
    let chain = &model.chain;
    let mut rng = rng(seed);
    let mut forces = Forces::new(model);
    let mut fused = GeneratedKernel::new(chain).unwrap();
    assert!(fused.fuse_loads(&fused_loads(&forces).unwrap()), "{name}: the generated kernel fuses the loads");
    let form = fused.form();
    assert_eq!(form, Form::Rolled, "{name}: the fused right-hand side runs on the rolled steps");
    let mut fed = GeneratedKernel::with_form(chain, form).unwrap();
    let mut reference = ReferenceKernel::new(chain);
    let scales = load_scales(chain, model.scene.environment.gravity);
    let mu = model.scene.environment.seabed_friction;
    let mut worst = Worst::default();
    for trial in 0..states {
        let (q, mut u) = near_start(model, &mut rng, if trial % 2 == 0 { 0.02 } else { 0.3 });
        let (anchor, friction) = match trial % 3 {
            0 => (AnchorDof::Free, 0.0),
            1 => (AnchorDof::Stuck, 0.0),
            _ => (AnchorDof::Free, if rng.gen_bool(0.5) { mu } else { -mu }),
        };
        if anchor == AnchorDof::Stuck {
            u[n - 1] = 0.0;
        }
        let (mut scratch, mut told) = (Assembly::new(n), Told::default());
        let (mut a, mut b) = (vec![0.0; n], vec![0.0; n]);
        let ra = fused.solve(&q, &u, anchor, friction, &mut told, &mut scratch, &mut a).unwrap();
        assert!(fused.last_states(&mut scratch.bodies), "{name}: the fused solve keeps its states");
        assert_eq!(told.power.len(), WORK_TERMS.len(), "{name}: the kernel told its power");
        let kept = kept_loads(&fused, n);
        // The oracle's loads at the same body states.
        let mut oracle = vec![Load::default(); n];
        forces.loads(&scratch.bodies, &mut oracle);
        let power = forces.power();
        count_branches(model, &scratch.bodies, &power, &mut worst);
        for (k, ((x, y), s)) in kept.iter().zip(&oracle).zip(&scales).enumerate() {
            for (i, (p, r)) in [(x.fx, y.fx), (x.fz, y.fz), (x.my, y.my)].into_iter().enumerate() {
                let d = (p - r).abs() / s[i];
                assert!(d <= TOL, "{name} {form:?} state {trial}: B_{} load {i} {p} against {r} ({d:e})", k + 1);
                worst.loads = worst.loads.max(d);
            }
        }
        let power_scale = scratch
            .bodies
            .iter()
            .zip(&oracle)
            .map(|(s, l)| (l.fx * s.vx).abs() + (l.fz * s.vz).abs() + (l.my * s.omega).abs())
            .sum::<f64>()
            .max(1.0);
        for (i, (p, r)) in told.power.iter().zip(&power).enumerate() {
            let d = (p - r).abs() / power_scale;
            assert!(d <= TOL, "{name} {form:?} state {trial}: {} power {p} against {r} ({d:e})", WORK_TERMS[i]);
            worst.power = worst.power.max(d);
        }
        // The same kernel fed by the force modules.
        let rb = fed.solve(&q, &u, anchor, friction, &mut forces, &mut scratch, &mut b).unwrap();
        let d = rel(&a, &b).max(rel(&[ra.normal, ra.holding], &[rb.normal, rb.holding]));
        assert!(d <= TOL, "{name} {form:?} state {trial}: fused and fed solves differ by {d:e}");
        worst.qdd = worst.qdd.max(d);
        // The reference system's residual, every fifth state (the reference assembles in O(N³)).
        if trial % 5 == 0 {
            let mut asm = Assembly::new(n);
            reference.assemble(&q, &u, &mut forces, &mut asm);
            let active = if anchor == AnchorDof::Stuck { n - 1 } else { n };
            let r = backward_error(&asm, active, friction, &a);
            assert!(r <= TOL, "{name} {form:?} state {trial}: backward error {r:e} in the reference system");
            worst.residual = worst.residual.max(r);
            // For scale: the reference's own solve, by the residual relative to ‖f‖.
            let mut own = vec![0.0; n];
            kanestop_runtime::kernel::solve_assembled(&asm, anchor, friction, &mut own).unwrap();
            worst.reference_residual = worst.reference_residual.max(residual(&asm, active, friction, &own));
            worst.fused_residual = worst.fused_residual.max(residual(&asm, active, friction, &a));
        }
    }
    worst
}

/// Counts the piecewise branches the force modules take at `bodies` (see [`Worst`]).
fn count_branches(model: &Model, bodies: &[BodyState], power: &[f64], worst: &mut Worst) {
    use kanestop_chain::BodyKind;
    use kanestop_runtime::chain::Shape;
    use kanestop_runtime::forces::current::Current;
    let e = &model.scene.environment;
    let current = Current {
        surface_speed: if e.water { e.current_surface_speed } else { 0.0 },
        exponent: e.current_exponent,
        depth: model.water_depth(),
        seabed_z: model.seabed_z,
    };
    for (b, s) in model.chain.bodies.iter().zip(bodies) {
        let (BodyKind::ChainLink | BodyKind::Cable { .. }, Shape::Rod { length, radius }) = (b.kind, b.shape) else {
            continue;
        };
        let half = 0.5 * length;
        let (za, zb) = (s.z + half * s.sin, s.z - half * s.sin);
        if e.water && za.min(zb) < 0.0 && za.max(zb) > 0.0 {
            worst.partly_wet[usize::from(za > zb)] += 1;
        }
        let u_n = (current.at(s.z) - s.vx) * s.sin - s.vz * s.cos;
        if e.water && u_n.abs() < s.omega.abs() * half {
            worst.flow_reversing += 1;
        }
        let sb = model.seabed_z;
        if e.seabed && kanestop_runtime::forces::seabed::embedded_volume(radius, length, za - sb, zb - sb).0 > 0.0 {
            worst.grounded += 1;
        }
    }
    if power[kanestop_runtime::forces::term::LINE_FRICTION] != 0.0 {
        worst.sliding += 1;
    }
}

fn check_all(models: &[(String, Model)], seed: u64) -> Worst {
    let mut worst = Worst::default();
    for (i, (name, model)) in models.iter().enumerate() {
        {
            let w = check_model(name, model, seed + i as u64, STATES);
            worst.loads = worst.loads.max(w.loads);
            worst.power = worst.power.max(w.power);
            worst.qdd = worst.qdd.max(w.qdd);
            worst.residual = worst.residual.max(w.residual);
            worst.fused_residual = worst.fused_residual.max(w.fused_residual);
            worst.reference_residual = worst.reference_residual.max(w.reference_residual);
            worst.partly_wet = [worst.partly_wet[0] + w.partly_wet[0], worst.partly_wet[1] + w.partly_wet[1]];
            worst.flow_reversing += w.flow_reversing;
            worst.grounded += w.grounded;
            worst.sliding += w.sliding;
        }
    }
    worst
}

/// What docs/codegen.md says the checks measure: the loads and ẍ equal (as floating-point
/// numbers), the power within 1e-14 of its scale (summed in another order), the backward
/// error below 1e-16, and (for `conditioned`, the scenes of the paper's chain) the
/// reference's own residual relative to ‖f‖ above 1e-12.
fn as_documented(what: &str, worst: Worst, conditioned: bool) {
    eprintln!("{what}, fused against the oracles: {worst:?}");
    assert_eq!((worst.loads, worst.qdd), (0.0, 0.0), "{what}: not equal");
    assert!(worst.power < 1e-14, "{what}: power off by {:e} of its scale", worst.power);
    assert!(worst.residual < 1e-16, "{what}: backward error {:e}", worst.residual);
    if conditioned {
        assert!(worst.reference_residual > TOL, "{what}: the reference's own residual {:e}", worst.reference_residual);
    }
    // The states reach every branch of the piecewise terms.
    let met = [worst.partly_wet[0], worst.partly_wet[1], worst.flow_reversing, worst.grounded];
    assert!(met.iter().all(|&c| c > 0), "{what}: a branch never met: {worst:?}");
}

#[test]
fn fused_loads_are_the_force_modules_loads_in_every_paper_scene() {
    as_documented("paper scenes", check_all(&scenes("scenes/paper"), 1000), true);
}

#[test]
fn fused_loads_are_the_force_modules_loads_in_every_stress_scene() {
    as_documented("stress scenes", check_all(&scenes("scenes/stress"), 2000), true);
}

/// Case 1 under every load signature: water, seabed, current and line friction switched;
/// each as the paper has it (44 line elements and the rod: even) and with one chain link more
/// (odd: the fused pass pairs the elements, and B_1 runs alone).
fn case1_signatures() -> Vec<(String, Model)> {
    let base = Scene::load(&Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes/paper/case01.toml")).unwrap();
    let mut models = Vec::new();
    for sig in LoadSignature::all() {
        for more in [0, 1] {
            let mut scene = base.clone();
            scene.chain.elements += more;
            let e = &mut scene.environment;
            e.water = sig.water;
            e.seabed = sig.seabed;
            e.current_surface_speed = if sig.current { 1.2 } else { 0.0 };
            e.line_friction = if sig.line_friction { 0.5 } else { 0.0 };
            let model = Model::new(&scene).unwrap_or_else(|e| panic!("{}: {e}", sig.name()));
            assert_eq!(Forces::new(&model).signature(), sig);
            models.push((format!("{} (N = {})", sig.name(), model.body_count()), model));
        }
    }
    models
}

#[test]
fn every_load_signature_fuses_and_matches_the_force_modules() {
    let models = case1_signatures();
    assert_eq!(models.len(), 18);
    let odd = models.iter().filter(|(_, m)| m.body_count() % 2 == 1).count();
    assert_eq!(odd, 9, "one scene of each parity per signature");
    let worst = check_all(&models, 3000);
    assert!(worst.sliding > 0, "the line's friction never worked: {worst:?}");
    as_documented("case 1 under the nine signatures", worst, true);
}

#[test]
fn random_scenes_fuse_and_match_the_force_modules() {
    let base = Scene::load(&Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes/paper/case01.toml")).unwrap();
    let mut rng = rng(4000);
    let mut models = Vec::new();
    let mut refused = Vec::new();
    while models.len() < 6 {
        assert!(refused.len() < 50, "random scenes refused: {refused:?}");
        let mut s = base.clone();
        s.chain.elements = rng.gen_range(2..25);
        s.chain.element_length = rng.gen_range(0.5..3.0);
        s.chain.radius *= rng.gen_range(0.5..1.5);
        for stage in &mut s.cable.stages {
            // The stage keeps its length (the catenary needs the cable to reach the ship).
            let length = stage.elements as f64 * stage.element_length;
            stage.elements = rng.gen_range(1..15);
            stage.element_length = length / stage.elements as f64;
        }
        s.anchor.mass *= rng.gen_range(0.5..2.0);
        s.ship.mass *= rng.gen_range(0.2..3.0);
        s.environment.seabed_stiffness *= 10f64.powf(rng.gen_range(-1.0..2.0));
        s.environment.current_surface_speed = if rng.gen_bool(0.5) { rng.gen_range(-2.0..2.0) } else { 0.0 };
        s.environment.line_friction = if rng.gen_bool(0.5) { rng.gen_range(0.1..1.0) } else { 0.0 };
        s.initial.horizontal_projection = s.initial.horizontal_projection.map(|x| x * rng.gen_range(0.97..1.0));
        match Model::new(&s) {
            Ok(model) => models.push((format!("random scene {} (N = {})", models.len(), model.body_count()), model)),
            Err(e) => refused.push(e.to_string()),
        }
    }
    // Both parities of the element count N − 2: the fused pass pairs the elements, and an
    // odd one out (B_1) runs alone.
    let odd = models.iter().filter(|(_, m)| m.body_count() % 2 == 1).count();
    assert!(
        odd > 0 && odd < models.len(),
        "element counts of one parity only: {:?}",
        models.iter().map(|m| &m.0).collect::<Vec<_>>()
    );
    as_documented("random scenes", check_all(&models, 5000), false);
}

#[test]
fn every_scene_runs_fused_on_the_generated_kernel_and_not_on_the_reference() {
    for (name, model) in scenes("scenes/paper").into_iter().chain(scenes("scenes/stress")) {
        let kernel = GeneratedKernel::new(&model.chain).unwrap();
        let d = Dynamics::new(Box::new(kernel), Forces::new(&model), model.anchor);
        assert!(d.loads_fused(), "{name}");
        let r = Dynamics::new(Box::new(ReferenceKernel::new(&model.chain)), Forces::new(&model), model.anchor);
        assert!(!r.loads_fused(), "{name}");
    }
}

/// What marks each term in the emitted code: the parameters only it reads, and its functions.
fn markers(term: LoadTerm) -> &'static [&'static str] {
    match term {
        LoadTerm::Weight => &["lp.g"],
        LoadTerm::Seabed => &["embedded_volumes", "seabed_stiffness", "power[1]"],
        LoadTerm::LineFriction => &["tanh", "line_friction", "slip_speed", "power[3]"],
        LoadTerm::Buoyancy => &["fraction", "anchor_volume", "power[0]"],
        LoadTerm::Current => &["powf", "current_speed", "current_exponent"],
        LoadTerm::LineDrag => &["normal_drag", "tangential_drag", "power[5]", "power[8]"],
        LoadTerm::AnchorDrag => &["anchor_drag", "anchor_area", "power[4]"],
        LoadTerm::Hydrostatics => &["ship_volume", "ship_metacentric_height", "power[7]"],
        LoadTerm::HullResistance => &["log10", "ship_wetted_surface", "roughness_allowance", "power[6]"],
    }
}

/// A marker as it appears in a token stream's text (`lp . g`, `power [1]`).
fn spaced(marker: &str) -> String {
    marker.replace('.', " . ").replace('[', " [")
}

#[test]
fn a_term_switched_off_is_not_in_the_generated_code() {
    let full = LoadSignature::new(true, true, true, true);
    let (full_code, full_report) = signature_code(&full);
    let full_code = full_code.to_string();
    let ops = |r: &kanestop_codegen::loads::LoadReport| -> usize {
        [LoadBody::Anchor, LoadBody::Element, LoadBody::Ship].iter().map(|&b| r.body_total(b)).sum()
    };
    for term in LoadTerm::ALL.into_iter().filter(|&t| t != LoadTerm::Weight) {
        for m in markers(term) {
            assert!(full_code.contains(&spaced(m)), "{}: {m} in the full code", term.name());
        }
        let off = match term {
            LoadTerm::Seabed => LoadSignature::new(true, false, true, false),
            LoadTerm::LineFriction => LoadSignature::new(true, true, true, false),
            LoadTerm::Current => LoadSignature::new(true, true, false, true),
            _ => LoadSignature::new(false, true, false, true),
        };
        assert!(!off.has(term));
        let (code, report) = signature_code(&off);
        let code = code.to_string();
        for m in markers(term) {
            assert!(!code.contains(&spaced(m)), "{}: {m} left in the code of {}", term.name(), off.name());
        }
        assert_eq!(report.term_total(term, 40, 1), 0, "{}", term.name());
        assert!(full_report.term_total(term, 40, 1) > 0, "{}", term.name());
        assert!(
            ops(&report) < ops(&full_report),
            "{}: {} ops without, {} with",
            term.name(),
            ops(&report),
            ops(&full_report)
        );
    }
    // Weight alone is three numbers per body.
    let (code, report) = signature_code(&LoadSignature::weight_only());
    assert!(!code.to_string().contains("power ["), "weight does no work in the balance's terms");
    assert_eq!(ops(&report), 6, "−m g, a negation and a product per body kind: {:?}", report.ops);
    // The file holds every signature once.
    let source = generate_loads().source;
    for sig in LoadSignature::all() {
        let n = sig.name();
        for f in ["load_anchor", "load_element", "load_ship"] {
            assert_eq!(source.matches(&format!("pub(crate) fn {f}_{n}(")).count(), 1, "{f}_{n}");
        }
        assert_eq!(source.matches(&format!("pub(crate) fn contacts_{n}(")).count(), usize::from(sig.seabed), "{n}");
    }
}

#[test]
fn the_load_code_s_power_array_is_the_runtime_s_work_terms() {
    assert_eq!(kanestop_codegen::loads::POWER_INDEX.map(|(name, _)| name), WORK_TERMS);
    assert!(kanestop_codegen::loads::POWER_INDEX.iter().enumerate().all(|(i, (_, k))| i == *k));
}

/// A chain out of Huston's order (the ship not last) is not offered to the load code, which
/// assumes it: the force modules, which dispatch on each body's kind, compute its loads.
#[test]
fn a_chain_out_of_order_keeps_the_force_modules() {
    let model = &scenes("scenes/paper")[0].1;
    let mut chain = model.chain.clone();
    let n = chain.len();
    chain.bodies.swap(n - 2, n - 1);
    let forces = Forces::gravity_only(&chain, G);
    assert!(fused_loads(&forces).is_none());
    assert!(fused_loads(&Forces::gravity_only(&model.chain, G)).is_some());
}

/// `Dynamics` with the loads fused against `Dynamics` on the force modules (the same rolled
/// steps): the whole right-hand side (q̇ and ü equal, the work terms' power, the anchor's
/// friction included, to round-off), the loads it reports and the seabed's reaction, equal,
/// with the anchor held and sliding both ways (the retry without friction when the chain
/// lifts the anchor included); and the loads each reports equal to the force modules' at its
/// body states with the anchor's friction added once, asked before and after the body
/// accelerations.
#[test]
fn dynamics_with_fused_loads_is_dynamics_on_the_force_modules() {
    use kanestop_runtime::integrate::OdeSystem;
    let (mut retried, mut with_friction) = (0, 0);
    for (name, model) in case1_signatures().into_iter().chain(scenes("scenes/stress")) {
        let n = model.body_count();
        let mut oracle = Forces::new(&model);
        let kernel = GeneratedKernel::new(&model.chain).unwrap();
        let mut fused = Dynamics::new(Box::new(kernel), Forces::new(&model), model.anchor);
        let rolled = GeneratedKernel::with_form(&model.chain, Form::Rolled).unwrap();
        let mut fed = Dynamics::new(Box::new(Unfused::new(rolled)), Forces::new(&model), model.anchor);
        assert!(fused.loads_fused() && !fed.loads_fused(), "{name}");
        let mut rng = rng(6000);
        for trial in 0..30 {
            match trial % 3 {
                0 => [&mut fused, &mut fed].map(|d| d.stick_anchor()),
                1 => [&mut fused, &mut fed].map(|d| d.slide_anchor(1.0)),
                _ => [&mut fused, &mut fed].map(|d| d.slide_anchor(-1.0)),
            };
            let (q, u) = near_start(&model, &mut rng, 0.3);
            let y: Vec<f64> = q.iter().chain(&u).copied().chain([0.0; WORK_TERMS.len()]).collect();
            let (mut a, mut b) = (vec![0.0; y.len()], vec![0.0; y.len()]);
            let ra = fused.rhs(0.0, &y, &mut a);
            let rb = fed.rhs(0.0, &y, &mut b);
            assert_eq!(ra.is_ok(), rb.is_ok(), "{name} state {trial}");
            if ra.is_err() {
                continue;
            }
            assert_eq!(a[..2 * n], b[..2 * n], "{name} state {trial}: the right-hand sides differ");
            let scale = a[2 * n..].iter().chain(&b[2 * n..]).fold(1.0f64, |m, x| m.max(x.abs()));
            let d = a[2 * n..].iter().zip(&b[2 * n..]).fold(0.0f64, |m, (x, y)| m.max((x - y).abs()));
            assert!(d <= 1e-12 * scale, "{name} state {trial}: the powers differ by {d:e} of {scale:e}");
            assert_eq!(fused.loads(), fed.loads(), "{name} state {trial}: the loads reported differ");
            assert_eq!(fused.reaction(), fed.reaction(), "{name} state {trial}");
            if fused.sliding_direction() != 0.0 && fused.reaction().normal < 0.0 {
                retried += 1;
            }
            // Against the force modules at the reported states, the anchor's sliding friction
            // (Eq. 37) added once, on B_1; asked again after the body accelerations (which
            // recompute the kinematics), the same.
            for (which, d) in [("fused", &mut fused), ("fed", &mut fed)] {
                let bodies = d.body_states().to_vec();
                let mut expected = vec![Load::default(); n];
                oracle.loads(&bodies, &mut expected);
                let k = match d.anchor() {
                    AnchorDof::Free => oracle.anchor.friction_factor(d.sliding_direction()),
                    AnchorDof::Stuck => 0.0,
                };
                let friction = AnchorForces::sliding_friction(k, d.reaction().normal);
                expected[0].fx += friction;
                with_friction += usize::from(friction != 0.0);
                let loads_scale =
                    expected.iter().fold(1.0f64, |m, l| m.max(l.fx.abs()).max(l.fz.abs()).max(l.my.abs()));
                for ask in 0..2 {
                    if ask == 1 {
                        let mut acc = vec![Default::default(); n];
                        d.body_accelerations(&q, &u, &b[n..2 * n], &mut acc);
                    }
                    let got = d.loads();
                    assert_eq!(got.len(), n);
                    let diff = got.iter().zip(&expected).fold(0.0f64, |m, (x, y)| {
                        m.max((x.fx - y.fx).abs()).max((x.fz - y.fz).abs()).max((x.my - y.my).abs())
                    });
                    assert!(
                        diff <= 1e-12 * loads_scale,
                        "{name} state {trial}, {which}, ask {ask}: the loads differ from the force modules' by {diff:e}"
                    );
                }
            }
        }
    }
    assert!(with_friction > 0, "some states slide against friction");
    eprintln!(
        "right-hand sides compared; {retried} solved again without friction, {with_friction} loads with friction"
    );
}

/// A dry scene without seabed runs on the fused right-hand side of `dry`, case 1 on that of
/// `wet_seabed`, both on the rolled steps though the build has the unrolled kernel of N = 46,
/// the reference on the force modules; the run result and its summary say which.
#[test]
fn a_run_reports_the_kernel_form_fusing_chose() {
    let base = Scene::load(&Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes/paper/case01.toml")).unwrap();
    let mut scene = base.clone();
    scene.environment.water = false;
    scene.environment.seabed = false;
    scene.solver.end_time = 0.01;
    let model = Model::new(&scene).unwrap();
    let kernel = GeneratedKernel::new(&model.chain).unwrap();
    assert_eq!(kernel.form(), Form::Unrolled);
    let result = kanestop_runtime::simulate::run(&model, Box::new(kernel));
    assert_eq!(result.kernel_form, Some("rolled"), "the fused right-hand sides are rolled");
    assert_eq!(result.load_code.as_deref(), Some("dry"));
    let mut short = base;
    short.solver.end_time = 0.01;
    let model = Model::new(&short).unwrap();
    let result = kanestop_runtime::simulate::run(&model, Box::new(GeneratedKernel::new(&model.chain).unwrap()));
    assert_eq!((result.kernel_form, result.load_code.as_deref()), (Some("rolled"), Some("wet_seabed")));
    // The summary says so.
    let text = kanestop_workflow::summary::summary(&model, &result);
    assert!(text.contains("kernel generated (rolled), loads generated (wet_seabed)"), "{text}");
    // Without fusion (the assembled path) the unrolled kernel runs, on the force modules: the
    // folded one, since the build has case 1's numbers folded in (generated/src/folded_case01.rs).
    let kernel = GeneratedKernel::new(&model.chain).unwrap().with_solve_path(SolvePath::Assembled);
    let result = kanestop_runtime::simulate::run(&model, Box::new(kernel));
    assert_eq!((result.kernel_form, result.load_code.as_deref()), (Some("folded"), None));
    let result = kanestop_runtime::simulate::run(&model, Box::new(ReferenceKernel::new(&model.chain)));
    assert_eq!((result.kernel_form, result.load_code.as_deref()), (None, None));
    let text = kanestop_workflow::summary::summary(&model, &result);
    assert!(text.contains("kernel reference, loads by the force modules"), "{text}");
}

// --- Weight alone, inside the rolled kernel's steps ----------------------------------------

fn check_gravity(chain: &Chain, seed: u64) -> f64 {
    let n = chain.len();
    let mut rng = rng(seed);
    let mut forces = Forces::gravity_only(chain, G);
    let mut fused = GeneratedKernel::with_form(chain, Form::Rolled).unwrap();
    assert!(fused.fuse_loads(&fused_loads(&forces).unwrap()), "the dry rolled kernel fuses weight");
    assert!(fused.is_fused());
    let mut fed = GeneratedKernel::with_form(chain, Form::Rolled).unwrap();
    let mut reference = ReferenceKernel::new(chain);
    let mut worst = 0.0f64;
    for trial in 0..STATES {
        let (q, mut u) = random_state(n, &mut rng);
        let (anchor, friction) = match trial % 3 {
            0 => (AnchorDof::Free, 0.0),
            1 => (AnchorDof::Stuck, 0.0),
            _ => (AnchorDof::Free, rng.gen_range(-0.6..0.6)),
        };
        if anchor == AnchorDof::Stuck {
            u[n - 1] = 0.0;
        }
        let mut scratch = Assembly::new(n);
        let (mut a, mut b) = (vec![0.0; n], vec![0.0; n]);
        let mut told = Told::default();
        let ra = fused.solve(&q, &u, anchor, friction, &mut told, &mut scratch, &mut a).unwrap();
        assert!(kept_loads(&fused, n)
            .iter()
            .zip(&chain.bodies)
            .all(|(l, b)| l.fz == -b.mass * G && l.fx == 0.0 && l.my == 0.0));
        let rb = fed.solve(&q, &u, anchor, friction, &mut forces, &mut scratch, &mut b).unwrap();
        let d = rel(&a, &b);
        let force_scale = chain.bodies.iter().map(|b| b.mass * G).sum::<f64>();
        let dr = [(ra.normal, rb.normal), (ra.holding, rb.holding)]
            .iter()
            .map(|(x, y)| (x - y).abs() / force_scale)
            .fold(0.0, f64::max);
        assert!(d <= TOL, "N={n} {anchor:?} k={friction}: qdd differ by {d:e}");
        assert!(dr <= TOL, "N={n} {anchor:?} k={friction}: reaction differs by {dr:e}");
        let mut asm = Assembly::new(n);
        reference.assemble(&q, &u, &mut forces, &mut asm);
        let active = if anchor == AnchorDof::Stuck { n - 1 } else { n };
        let r = residual(&asm, active, friction, &a);
        assert!(r <= TOL, "N={n} {anchor:?} k={friction}: residual {r:e} in the reference system");
        worst = worst.max(d).max(dr).max(r);
    }
    worst
}

#[test]
fn fused_weight_is_the_force_modules_weight_at_every_size() {
    let mut rng = rng(77);
    let mut worst = 0.0f64;
    for n in [3, 4, 5, 11, 46, 51] {
        worst = worst.max(check_gravity(&random_chain(n, &mut rng), 500 + n as u64));
    }
    eprintln!("fused weight against the fed loads and the reference: worst {worst:e}");
}

#[test]
fn a_chain_in_vacuum_runs_fused_and_added_mass_without_water_on_the_force_modules() {
    let mut rng = rng(78);
    let chain = random_chain(46, &mut rng);
    let kernel = GeneratedKernel::new(&chain).unwrap();
    assert_eq!(kernel.form(), Form::Unrolled, "N = 46 dry has an unrolled kernel");
    let mut d = Dynamics::new(Box::new(kernel), Forces::gravity_only(&chain, G), AnchorDof::Stuck);
    assert!(d.loads_fused());
    // The weights are known after a solve, for the joint forces the observation computes.
    let (q, u) = random_state(46, &mut rng);
    let mut qdd = vec![0.0; 46];
    d.accelerations(&q, &u, &mut qdd).unwrap();
    assert!(d.loads().iter().zip(&chain.bodies).all(|(l, b)| l.fz == -b.mass * G && l.fx == 0.0 && l.my == 0.0));
    // Added mass without water: the fused right-hand sides of a dry signature run the dry
    // steps, which have no added mass, so the kernel keeps the force modules.
    let wet = random_wet_chain(46, &mut rng);
    let mut k = GeneratedKernel::new(&wet).unwrap();
    assert!(!k.fuse_loads(&fused_loads(&Forces::gravity_only(&wet, G)).unwrap()));
    assert!(!k.is_fused() && k.form() == Form::Unrolled);
}

#[test]
fn the_gravity_steps_read_no_load_and_do_less() {
    for (kind, fed, fused) in [
        (
            Some(Kind::Ship),
            inward(Kind::Ship, Water::Off, Loads::Inputs),
            inward(Kind::Ship, Water::Off, Loads::Gravity),
        ),
        (Some(Kind::Rod), inward(Kind::Rod, Water::Off, Loads::Inputs), inward(Kind::Rod, Water::Off, Loads::Gravity)),
        (
            Some(Kind::First),
            inward(Kind::First, Water::Off, Loads::Inputs),
            inward(Kind::First, Water::Off, Loads::Gravity),
        ),
        (None, anchor(Water::Off, false, Loads::Inputs), anchor(Water::Off, false, Loads::Gravity)),
        (None, anchor(Water::Off, true, Loads::Inputs), anchor(Water::Off, true, Loads::Gravity)),
    ] {
        let ops = |s: &kanestop_codegen::rolled::Step| s.function.dag.count(&s.function.roots()).total();
        let (a, b) = (ops(&fed), ops(&fused));
        // The anchor translates only: its −m g costs the one operation that reading F_z
        // saved, so it only breaks even; a rotating body also drops F_x and M_y's terms.
        if kind.is_some() {
            assert!(b < a, "{kind:?} {}: {b} ops fused against {a} fed", fused.name);
        } else {
            assert!(b <= a, "{}: {b} ops fused against {a} fed", fused.name);
        }
        assert!(fed.params.contains("f: &[f64; 3]") && !fused.params.contains("f: &[f64; 3]"), "{}", fused.name);
        assert!(fused.params.contains("g: f64") && fused.name.ends_with("_gravity"));
    }
    let rhs = kanestop_codegen::rhs::generate_rhs().source;
    let pass = &rhs[rhs.find("fn pass_dry(").unwrap()..];
    let pass = &pass[..pass.find("\n}\n").unwrap()];
    assert!(!pass.contains("&loads["), "the steps read no load: {pass}");
    assert!(pass.contains("inward_rod_gravity"), "{pass}");
    assert!(!kanestop_codegen::drivers::generate_rolled(Water::On).source.contains("_gravity"));
}

// --- The joint forces from the solve's rows ------------------------------------------------

/// The force through every hinge from the rows the solve left (`Kernel::joint_forces`)
/// against Newton's form on the body accelerations of the same solve (`joints`, the oracle):
/// within 1e-10 of the size of what Newton's form sums (each body's inertia force and load,
/// plus the chain's weight), on the fused right-hand
/// side of every paper and stress scene and on the rolled kernel fed by the force modules;
/// the unrolled kernels and the reference keep no rows and say so.
#[test]
fn the_solve_s_joint_forces_are_newton_s() {
    // Newton's form sums inertia forces and loads that nearly cancel (a 500 t ship's weight
    // and buoyancy, the line's, a stiff seabed's reactions), and the two forms round
    // differently: per joint, measured 7.4e-10 of what its sum adds up (the seabed 1e4 times
    // stiffer than the paper's, with contact forces of 1e8 N), 9.3e-12 of the whole chain's.
    const JOINT_TOL: f64 = 2e-9;
    use kanestop_runtime::joints;
    let mut worst = 0.0f64;
    let mut models = scenes("scenes/paper");
    models.extend(scenes("scenes/stress"));
    for (name, model) in &models {
        let (chain, n) = (&model.chain, model.body_count());
        let mut forces = Forces::new(model);
        let mut fused = GeneratedKernel::new(chain).unwrap();
        assert!(fused.fuse_loads(&fused_loads(&forces).unwrap()), "{name}");
        let mut fed = GeneratedKernel::with_form(chain, Form::Rolled).unwrap();
        let g = model.scene.environment.gravity;
        let mut rng = rng(9000);
        for trial in 0..20 {
            let (q, mut u) = near_start(model, &mut rng, 0.3);
            let (anchor, friction) = if trial % 2 == 0 { (AnchorDof::Free, 0.3) } else { (AnchorDof::Stuck, 0.0) };
            if anchor == AnchorDof::Stuck {
                u[n - 1] = 0.0;
            }
            for (kernel, fuses) in [(&mut fused, true), (&mut fed, false)] {
                let (mut scratch, mut qdd, mut told) = (Assembly::new(n), vec![0.0; n], Told::default());
                let loads = if fuses {
                    kernel.solve(&q, &u, anchor, friction, &mut told, &mut scratch, &mut qdd).unwrap();
                    assert!(kernel.last_states(&mut scratch.bodies), "{name}: the fused solve keeps its states");
                    kept_loads(&*kernel, n)
                } else {
                    kernel.solve(&q, &u, anchor, friction, &mut forces, &mut scratch, &mut qdd).unwrap();
                    let mut l = vec![Load::default(); n];
                    forces.loads(&scratch.bodies, &mut l);
                    l
                };
                let mut own = vec![[0.0; 2]; n - 1];
                assert!(kernel.joint_forces(&mut own), "{name}: the rolled solve keeps its rows");
                let mut acc = vec![Default::default(); n];
                kernel.accelerations(&q, &u, &qdd, &mut acc);
                let mut newton = vec![[0.0; 2]; n - 1];
                joints::from_accelerations(chain, &scratch.bodies, &acc, &loads, &mut newton);
                // Per joint, the size of what Newton's form sums for it: the inertia force,
                // load and weight of each body outboard of it (joint k − 2 carries B_k … B_N).
                let mut scales = vec![0.0; n - 1];
                let mut outboard = 0.0;
                for k in (1..n).rev() {
                    let (b, a, l) = (&chain.bodies[k], &acc[k], &loads[k]);
                    outboard +=
                        (b.mass + b.added_mass) * (a.ax.abs() + a.az.abs()) + l.fx.abs() + l.fz.abs() + b.mass * g;
                    scales[k - 1] = outboard;
                }
                for (k, ((a, b), scale)) in own.iter().zip(&newton).zip(&scales).enumerate() {
                    let d = (a[0] - b[0]).abs().max((a[1] - b[1]).abs()) / scale;
                    assert!(d <= JOINT_TOL, "{name} state {trial}: joint {} {a:?} against {b:?} ({d:e})", k + 2);
                    worst = worst.max(d);
                }
            }
        }
    }
    eprintln!("joint forces from the solve's rows against Newton's form: worst {worst:e} of the scale");
    // The kernels that keep no rows.
    let chain = &models[0].1.chain;
    let mut unrolled = GeneratedKernel::with_form(chain, Form::Unrolled).unwrap();
    let n = chain.len();
    let (q, u) = (models[0].1.q0.clone(), models[0].1.u0.clone());
    let (mut scratch, mut qdd, mut out) = (Assembly::new(n), vec![0.0; n], vec![[0.0; 2]; n - 1]);
    let mut forces = Forces::new(&models[0].1);
    unrolled.solve(&q, &u, AnchorDof::Stuck, 0.0, &mut forces, &mut scratch, &mut qdd).unwrap();
    assert!(!unrolled.joint_forces(&mut out));
    let mut reference = ReferenceKernel::new(chain);
    reference.solve(&q, &u, AnchorDof::Stuck, 0.0, &mut forces, &mut scratch, &mut qdd).unwrap();
    assert!(!reference.joint_forces(&mut out));
    // After an assembly the rows are gone.
    let mut rolled = GeneratedKernel::with_form(chain, Form::Rolled).unwrap();
    rolled.solve(&q, &u, AnchorDof::Stuck, 0.0, &mut forces, &mut scratch, &mut qdd).unwrap();
    assert!(rolled.joint_forces(&mut out));
    rolled.assemble(&q, &u, &mut forces, &mut scratch);
    assert!(!rolled.joint_forces(&mut out));
}

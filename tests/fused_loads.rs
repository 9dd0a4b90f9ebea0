//! Loads fused into the generated code (issue 14), so far weight alone: a dry chain without
//! seabed (a chain hanging in vacuum) runs on solves whose steps compute −m g themselves
//! (`solve_free_gravity`, `solve_stuck_gravity` in `generated/src/rolled_dry.rs`). Checked
//! against the same kernel fed the loads of the force modules (`Forces::gravity_only`, the
//! oracle of the physics) and against the reference formulation (the oracle of the
//! dynamics), at 100 random states for every size; and in the code: the fused steps read no
//! load and do fewer operations.

mod common;

use common::*;
use kanestop_chain::Water;
use kanestop_codegen::rolled::{anchor, inward, Kind, Loads};
use kanestop_runtime::chain::Chain;
use kanestop_runtime::dynamics::Dynamics;
use kanestop_runtime::forces::Forces;
use kanestop_runtime::generated::{Form, GeneratedKernel};
use kanestop_runtime::kernel::{AnchorDof, Assembly, Kernel};
use kanestop_runtime::reference::ReferenceKernel;
use rand::Rng;

const STATES: usize = 100;

/// The relative difference of two accelerations, on the scale of the larger.
fn rel(a: &[f64], b: &[f64]) -> f64 {
    let scale = a.iter().chain(b).fold(1.0f64, |m, x| m.max(x.abs()));
    a.iter().zip(b).map(|(x, y)| (x - y).abs()).fold(0.0, f64::max) / scale
}

fn check(chain: &Chain, seed: u64) -> f64 {
    let n = chain.len();
    let mut rng = rng(seed);
    let mut fused = GeneratedKernel::with_form(chain, Form::Rolled).unwrap();
    assert!(fused.fuse_gravity(G), "the dry rolled kernel fuses weight");
    assert!(fused.is_gravity_fused());
    let mut fed = GeneratedKernel::with_form(chain, Form::Rolled).unwrap();
    let mut reference = ReferenceKernel::new(chain);
    let mut forces = Forces::gravity_only(chain, G);
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
        // The fused kernel never calls the load model: hand it one that would be wrong.
        let mut nothing = Forces::gravity_only(chain, 0.0);
        let ra = fused.solve(&q, &u, anchor, friction, &mut nothing, &mut scratch, &mut a).unwrap();
        let rb = fed.solve(&q, &u, anchor, friction, &mut forces, &mut scratch, &mut b).unwrap();
        // Against the same code fed the force modules' weights: the same numbers.
        let d = rel(&a, &b);
        let force_scale = chain.bodies.iter().map(|b| b.mass * G).sum::<f64>();
        let dr = [(ra.normal, rb.normal), (ra.holding, rb.holding)]
            .iter()
            .map(|(x, y)| (x - y).abs() / force_scale)
            .fold(0.0, f64::max);
        assert!(d <= 1e-12, "N={n} {anchor:?} k={friction}: qdd differ by {d:e}");
        assert!(dr <= 1e-12, "N={n} {anchor:?} k={friction}: reaction differs by {dr:e}");
        // Against the reference: its system's residual (Eqs. 22–27 with the same weights).
        let mut asm = Assembly::new(n);
        reference.assemble(&q, &u, &mut forces, &mut asm);
        let active = if anchor == AnchorDof::Stuck { n - 1 } else { n };
        let r = residual(&asm, active, friction, &a);
        assert!(r <= 1e-12, "N={n} {anchor:?} k={friction}: residual {r:e} in the reference system");
        worst = worst.max(d).max(dr).max(r);
    }
    worst
}

#[test]
fn fused_weight_is_the_force_modules_weight_at_every_size() {
    let mut rng = rng(77);
    let mut worst = 0.0f64;
    for n in [3, 4, 5, 11, 46, 51] {
        worst = worst.max(check(&random_chain(n, &mut rng), 500 + n as u64));
    }
    eprintln!("fused weight against the fed loads and the reference: worst {worst:e}");
}

#[test]
fn a_chain_in_vacuum_runs_fused_and_a_wet_one_does_not() {
    let mut rng = rng(78);
    let chain = random_chain(46, &mut rng);
    let kernel = GeneratedKernel::new(&chain).unwrap();
    assert_eq!(kernel.form(), Form::Unrolled, "N = 46 dry has an unrolled kernel");
    let d = Dynamics::new(Box::new(kernel), Forces::gravity_only(&chain, G), AnchorDof::Stuck);
    assert!(d.loads_fused());
    // The weights are still known, for the joint forces the observation computes.
    assert!(d.loads().iter().zip(&chain.bodies).all(|(l, b)| l.fz == -b.mass * G && l.fx == 0.0 && l.my == 0.0));
    // No fusing on the reference kernel, nor for a wet chain (its kernel has no weight-only
    // solve; in a scene, water brings buoyancy and drag besides).
    let r = Dynamics::new(Box::new(ReferenceKernel::new(&chain)), Forces::gravity_only(&chain, G), AnchorDof::Stuck);
    assert!(!r.loads_fused());
    let wet = random_wet_chain(46, &mut rng);
    let d =
        Dynamics::new(Box::new(GeneratedKernel::new(&wet).unwrap()), Forces::gravity_only(&wet, G), AnchorDof::Stuck);
    assert!(!d.loads_fused());
}

#[test]
fn the_fused_steps_read_no_load_and_do_less() {
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
    // In the emitted file: the fused solve reads no load array.
    let dry = kanestop_codegen::drivers::generate_rolled(Water::Off).source;
    let fused_solve = &dry[dry.find("pub fn solve_free_gravity").unwrap()..];
    let fused_solve = &fused_solve[..fused_solve.find("\n}\n").unwrap()];
    assert!(!fused_solve.contains("loads"), "{fused_solve}");
    assert!(!kanestop_codegen::drivers::generate_rolled(Water::On).source.contains("_gravity"));
}

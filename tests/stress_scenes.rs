//! A reduced set of the stress scenes (`scenes/stress/`), shortened so the whole file runs
//! in a few seconds: each run either completes with an energy drift below 0.5 % or stops
//! with the diagnostic (time, body, cause, suggestion). Never a NaN, a panic or a hang. The
//! full set: `cargo run --release -- batch scenes/stress` (docs/integrators.md).

use std::path::Path;

use kanestop_runtime::generated::GeneratedKernel;
use kanestop_runtime::model::Model;
use kanestop_runtime::scene::Scene;
use kanestop_runtime::simulate::{self, RunResult, Stop};

fn run(name: &str, end_time: f64) -> RunResult {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes/stress").join(format!("{name}.toml"));
    let mut scene = Scene::load(&path).unwrap_or_else(|e| panic!("{e}"));
    scene.solver.end_time = end_time;
    let model = Model::new(&scene).unwrap_or_else(|e| panic!("{name}: {e}"));
    simulate::run(&model, Box::new(GeneratedKernel::new(&model.chain).unwrap()))
}

/// Completed runs: drift below 0.5 % and finite states throughout. Failed runs: a
/// diagnostic with a time inside the run, a body and a suggestion.
fn check(name: &str, r: &RunResult) {
    for s in &r.samples {
        assert!(s.bodies.iter().all(|b| [b.x, b.z, b.theta, b.vx, b.vz, b.omega].iter().all(|v| v.is_finite())));
        assert!(s.energy.balance().is_finite(), "{name}: non-finite energy at t = {}", s.t);
    }
    match &r.stop {
        Stop::Failed(f) => {
            assert!(f.t > 0.0 && f.t.is_finite(), "{name}: {f}");
            assert!(f.body >= 2 && !f.body_name.is_empty(), "{name}: {f}");
            assert!(!f.suggestion.is_empty() && !f.cause.is_empty(), "{name}: {f}");
        }
        Stop::EndTime | Stop::ShipStopped => {
            assert!(r.max_energy_drift < 0.005, "{name}: drift {:e}", r.max_energy_drift);
        }
    }
}

#[test]
fn very_stiff_seabed_stops_with_the_diagnostic_under_rk4() {
    let r = run("seabed_kz_x1e4", 1.0);
    check("seabed_kz_x1e4", &r);
    // RK4 at dt = 0.002 s is beyond the contact mode's stability limit: a clean stop.
    let Stop::Failed(f) = &r.stop else { panic!("expected a failure, got {:?}", r.stop) };
    assert!(f.t < 1.0 && f.suggestion.contains("dt"), "{f}");
}

#[test]
fn step_beyond_the_stability_limit_stops_with_the_diagnostic() {
    let r = run("dt_too_large", 5.0);
    check("dt_too_large", &r);
    assert!(matches!(r.stop, Stop::Failed(_)), "{:?}", r.stop);
    assert!(!r.samples.is_empty(), "the samples before the failure are kept");
}

#[test]
fn high_friction_anchor_completes() {
    let r = run("friction_mu_1", 10.0);
    check("friction_mu_1", &r);
    assert_eq!(r.stop, Stop::ShipStopped);
}

#[test]
fn deep_water_and_nearly_taut_cable_run_cleanly() {
    for name in ["deep_water_50m", "taut_cable"] {
        let r = run(name, 3.0);
        check(name, &r);
        assert!(!matches!(r.stop, Stop::Failed(_)), "{name}: {:?}", r.stop);
    }
}

/// Every stress scene is valid under the scene checks and builds a model.
#[test]
fn every_stress_scene_loads() {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes/stress");
    let mut count = 0;
    for entry in std::fs::read_dir(&dir).unwrap().flatten() {
        let p = entry.path();
        if p.extension().is_some_and(|x| x == "toml") {
            let scene = Scene::load(&p).unwrap_or_else(|e| panic!("{e}"));
            Model::new(&scene).unwrap_or_else(|e| panic!("{}: {e}", p.display()));
            assert!(!scene.meta.description.is_empty());
            count += 1;
        }
    }
    assert!(count >= 10, "{count} stress scenes");
}

/// A cable of 1 m elements (N = 170, its kernel generated into OUT_DIR at build time)
/// stops the ship at case 1's time: the paper's discretisation is converged.
#[test]
fn fine_cable_converges_to_the_paper_discretisation() {
    let fine = run("fine_cable", 60.0);
    check("fine_cable", &fine);
    assert_eq!(fine.samples[0].bodies.len(), 170);
    let scene = kanestop_runtime::paper::CASES[0].scene();
    let model = Model::new(&scene).unwrap();
    let coarse = simulate::run(&model, Box::new(GeneratedKernel::new(&model.chain).unwrap()));
    let (a, b) = (fine.stopping_time.unwrap(), coarse.stopping_time.unwrap());
    assert!((a - b).abs() < 0.01 * b, "fine cable stops at {a:.4} s, case 1 at {b:.4} s");
}

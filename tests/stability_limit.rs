//! The RK4 stability limit by Arnoldi's method (`stability::krylov_limit`, what scenes with
//! 2N > `stability::DENSE_MAX` use) against every eigenvalue of the whole Jacobian
//! (`stability::dense_limit`, the oracle), on the same finite-difference Jacobian: the same
//! limit to 1e-7 (or within the limiting eigenvalue's conditioning where that is wider) on
//! every paper and stress scene and on long fine lines with current, line friction and a
//! stiff seabed, where the top of the spectrum is a dense band of the line's modes. The paper
//! and stress scenes (2N ≈ 100) are small for the method: it tries 48 vectors, then takes the
//! dense decomposition; the fine lines are where it stops early. The stopping rule itself is
//! tested on a constructed spectrum in `runtime/src/stability.rs`.

mod common;

use std::path::Path;
use std::sync::atomic::{AtomicBool, AtomicUsize, Ordering};
use std::sync::Arc;

use common::Unfused;
use kanestop_runtime::dynamics::{Dynamics, WORK_COUNT};
use kanestop_runtime::forces::Forces;
use kanestop_runtime::generated::GeneratedKernel;
use kanestop_runtime::model::Model;
use kanestop_runtime::scene::{CableStage, Scene};
use kanestop_runtime::simulate::{self, Cancelled};
use kanestop_runtime::stability;

fn load(path: &Path) -> Scene {
    Scene::load(path).unwrap_or_else(|e| panic!("{e}"))
}

fn scenes(folder: &str) -> Vec<Scene> {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes").join(folder);
    let mut paths: Vec<_> = std::fs::read_dir(dir).unwrap().map(|e| e.unwrap().path()).collect();
    paths.sort();
    paths.iter().map(|p| load(p)).collect()
}

/// Arnoldi's limit of `scene` agrees with the dense one to 1e-7, or within the limiting
/// eigenvalue's conditioning where that is wider: how far the dense limit of Jᵀ (the same
/// eigenvalues in exact arithmetic) lies from that of J. Returns that spread and the size of
/// the Krylov space taken (2N where it went to the dense decomposition).
fn assert_agree(scene: &Scene) -> (f64, usize) {
    let name = &scene.meta.name;
    let model = Model::new(scene).unwrap_or_else(|e| panic!("{name}: {e}"));
    let y0: Vec<f64> = model.q0.iter().chain(&model.u0).copied().chain([0.0; WORK_COUNT]).collect();
    let mut dynamics =
        Dynamics::new(Box::new(GeneratedKernel::new(&model.chain).unwrap()), Forces::new(&model), model.anchor);
    let jac = stability::jacobian(&mut dynamics, &y0, &AtomicBool::new(false)).unwrap();
    let dense = stability::dense_limit(&jac).unwrap();
    let (krylov, steps) = stability::krylov_limit_with_steps(&jac, &AtomicBool::new(false)).unwrap();
    let spread = (stability::dense_limit(&jac.transpose()).unwrap().rk4_dt - dense.rk4_dt).abs() / dense.rk4_dt;
    let rel = (krylov.rk4_dt - dense.rk4_dt).abs() / dense.rk4_dt;
    assert!(
        rel <= 1e-7f64.max(2.0 * spread),
        "{name}: Arnoldi {:e} s against dense {:e} s ({rel:e}; J against Jᵀ {spread:e})",
        krylov.rk4_dt,
        dense.rk4_dt
    );
    (spread, steps)
}

#[test]
fn arnoldi_finds_the_dense_limit_on_the_paper_scenes() {
    for scene in scenes("paper") {
        assert!(assert_agree(&scene).0 < 1e-7, "{}", scene.meta.name);
    }
}

#[test]
fn arnoldi_finds_the_dense_limit_on_the_stress_scenes() {
    // Only the seabed 1e4 times stiffer than the paper's has an ill-conditioned limiting
    // eigenvalue (J and Jᵀ differ by 5e-5): entries of ∂ẏ/∂y from 1e-3 to 2e8.
    for scene in scenes("stress") {
        let (spread, _) = assert_agree(&scene);
        let wide = scene.meta.name == "seabed_kz_x1e4";
        assert!(if wide { spread < 1e-4 } else { spread < 1e-7 }, "{}: {spread:e}", scene.meta.name);
    }
}

/// Case 1 with its cable in `elements` elements of 1 m (the line's modes a dense band at the
/// top of the spectrum), and `edit` applied.
fn fine_line(elements: usize, edit: impl FnOnce(&mut Scene)) -> Scene {
    let mut scene = load(&Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes/paper/case01.toml"));
    scene.meta.name = format!("case 1, {elements} × 1 m of cable");
    scene.cable.stages = vec![CableStage { elements, element_length: 1.0 }];
    scene.initial.horizontal_projection = Some(elements as f64 - 3.0);
    edit(&mut scene);
    scene
}

#[test]
fn arnoldi_finds_the_dense_limit_on_long_fine_lines() {
    for scene in [
        fine_line(200, |_| {}),
        fine_line(240, |s| {
            s.environment.current_surface_speed = 1.5;
            s.environment.line_friction = 0.5;
        }),
        fine_line(300, |s| s.environment.seabed_stiffness *= 100.0),
        fine_line(500, |_| {}),
    ] {
        let dim = 2 * Model::new(&scene).unwrap().body_count();
        assert!(dim > stability::DENSE_MAX, "{}", scene.meta.name);
        let (spread, steps) = assert_agree(&scene);
        assert!(spread < 1e-7, "{}", scene.meta.name);
        // Where Arnoldi's method is meant to pay, it stops early: the lines of 300 m and
        // more, and the line with current and friction, stop at m = 243, 243 and 72 (the
        // 200 m line goes on to the dense decomposition: its top is a cluster whose Ritz
        // vectors converge slowly, and 0.4·2N is only 174 there).
        if scene.cable.stages[0].elements >= 300 || scene.environment.line_friction > 0.0 {
            assert!(steps < dim, "{}: m = {steps}", scene.meta.name);
        }
    }
}

/// A run cancelled while RK4's start-up analysis forms the Jacobian of a 500 m line
/// (N = 518, about 2 100 right-hand sides and 0.5 s of Arnoldi's method in all) stops
/// within a column of the flag, before any step; Arnoldi's method on that line's Jacobian,
/// given a set flag, returns `Cancelled` (without the check in its products it runs to the
/// limit, m = 243).
#[test]
fn the_start_up_analysis_stops_when_cancelled() {
    let model = Model::new(&fine_line(500, |_| {})).unwrap();
    let at = 10;
    let (cancel, solves) = (Arc::new(AtomicBool::new(false)), Arc::new(AtomicUsize::new(0)));
    // The generated kernel (on the force modules) that sets the flag at its `at`-th solve: a
    // user's Ctrl-C arriving during the start-up analysis, on cue.
    let (flag, count) = (cancel.clone(), solves.clone());
    let kernel = Unfused::with_hook(GeneratedKernel::new(&model.chain).unwrap(), move || {
        if count.fetch_add(1, Ordering::Relaxed) + 1 == at {
            flag.store(true, Ordering::Relaxed);
        }
    });
    let run = simulate::run_cancellable(&model, Box::new(kernel), &cancel);
    assert_eq!(run.unwrap_err(), Cancelled { t: 0.0 });
    // A column takes two right-hand sides (each one solve, or two when friction is retried).
    let taken = solves.load(Ordering::Relaxed);
    assert!((at..=at + 4).contains(&taken), "{taken} solves after the flag was set at the {at}th");

    let y0: Vec<f64> = model.q0.iter().chain(&model.u0).copied().chain([0.0; WORK_COUNT]).collect();
    let mut dynamics =
        Dynamics::new(Box::new(GeneratedKernel::new(&model.chain).unwrap()), Forces::new(&model), model.anchor);
    let jac = stability::jacobian(&mut dynamics, &y0, &AtomicBool::new(false)).unwrap();
    assert!(jac.nrows() > stability::DENSE_MAX);
    assert_eq!(
        stability::krylov_limit_with_steps(&jac, &AtomicBool::new(true)).unwrap_err(),
        stability::StabilityError::Cancelled
    );
}

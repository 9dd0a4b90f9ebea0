//! Whole runs with the generated kernel and with the reference: the same trajectory.

mod common;

use common::Unfused;
use kanestop_runtime::generated::GeneratedKernel;
use kanestop_runtime::model::Model;
use kanestop_runtime::paper::DEFAULT_SCENE;
use kanestop_runtime::reference::ReferenceKernel;
use kanestop_runtime::scene::Scene;
use kanestop_runtime::simulate::{self, RunResult};

fn case1(end_time: Option<f64>) -> Model {
    let mut scene = Scene::from_toml(DEFAULT_SCENE, "case01.toml").unwrap();
    if let Some(t) = end_time {
        scene.solver.end_time = t;
    }
    Model::new(&scene).unwrap()
}

fn runs(model: &Model) -> (RunResult, RunResult) {
    let reference = simulate::run(model, Box::new(ReferenceKernel::new(&model.chain)));
    let generated = simulate::run(model, Box::new(GeneratedKernel::new(&model.chain).unwrap()));
    (reference, generated)
}

/// Case 1 for its first half second: every sampled body state agrees.
#[test]
fn case1_start_is_the_same_with_both_kernels() {
    let model = case1(Some(0.5));
    let (r, g) = runs(&model);
    assert_eq!(g.kernel, "generated");
    assert_eq!(r.stop, g.stop);
    assert_eq!(r.samples.len(), g.samples.len());
    let mut worst: f64 = 0.0;
    for (a, b) in r.samples.iter().zip(&g.samples) {
        assert_eq!(a.t, b.t);
        for (x, y) in a.bodies.iter().zip(&b.bodies) {
            let d = [(x.x - y.x).abs(), (x.z - y.z).abs(), (x.theta - y.theta).abs(), (x.vx - y.vx).abs()];
            worst = worst.max(d.into_iter().fold(0.0, f64::max));
        }
    }
    assert!(worst < 1e-8, "largest state difference {worst:e}");
}

/// The whole of case 1: the same stopping time to 1e-6 s (about a minute with the
/// reference kernel; the test profile is optimised).
#[test]
fn case1_stopping_time_is_the_same_with_both_kernels() {
    let model = case1(None);
    let (r, g) = runs(&model);
    eprintln!(
        "reference: {:?} {:?} in {:?}; generated: {:?} {:?} in {:?}",
        r.stop, r.stopping_time, r.wall_time, g.stop, g.stopping_time, g.wall_time
    );
    assert_eq!(r.stop, g.stop);
    match (r.stopping_time, g.stopping_time) {
        (Some(a), Some(b)) => {
            assert!((a - b).abs() < 1e-6, "stopping time {a} vs {b}");
            // docs/codegen.md quotes the difference.
            let doc = std::fs::read_to_string(std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("docs/codegen.md"))
                .unwrap()
                .split_whitespace()
                .collect::<Vec<_>>()
                .join(" ");
            // The difference is rounding (ulps of the two formulations' sums, amplified over
            // 40 000 steps): the doc quotes its bound, not its value, which any change of
            // rounding in the physics moves (8e-10, 1e-8, 2e-9 so far).
            assert!((a - b).abs() < 1e-8, "the kernels stop {:e} s apart", (a - b).abs());
            let quoted = "the two stop less than 1e-8 s apart";
            assert!(doc.contains(quoted), "docs/codegen.md should say: {quoted}");
        }
        (a, b) => panic!("case 1 stops with both kernels: reference {a:?}, generated {b:?}"),
    }
}

/// Case 1 on the rolled kernel (any N) and on the unrolled one built for N = 46, both fed
/// by the force modules (fusing would move the unrolled kernel to the rolled steps) and
/// both with Newton's joint forces: the same operations on every value the run depends on,
/// so the same run bit for bit: stopping time, every sample's body states and tensions.
#[test]
fn case1_is_the_same_on_the_rolled_kernel() {
    use kanestop_runtime::generated::Form;
    let model = case1(None);
    let kernel = |form| Box::new(Unfused::new(GeneratedKernel::with_form(&model.chain, form).unwrap()));
    let unrolled = simulate::run(&model, kernel(Form::Unrolled));
    let rolled = simulate::run(&model, kernel(Form::Rolled));
    assert_eq!((unrolled.kernel_form, rolled.kernel_form), (Some("unrolled"), Some("rolled")));
    assert_eq!(unrolled.stop, rolled.stop);
    let (a, b) = (unrolled.stopping_time.expect("case 1 stops"), rolled.stopping_time.expect("case 1 stops"));
    assert_eq!(a.to_bits(), b.to_bits(), "stopping time {a} vs {b}");
    assert_eq!(unrolled.samples.len(), rolled.samples.len());
    for (x, y) in unrolled.samples.iter().zip(&rolled.samples) {
        assert_eq!(x.t, y.t);
        assert_eq!(x.bodies, y.bodies, "body states at t = {}", x.t);
        assert_eq!(x.tensions, y.tensions, "tensions at t = {}", x.t);
    }
}

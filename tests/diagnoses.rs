//! True diagnoses (issue 15, item 4): a run failing early from a state far from static says
//! so instead of blaming the step, and the advice never goes below the smallest sensible step.

use kanestop_runtime::model::Model;
use kanestop_runtime::paper::DEFAULT_SCENE;
use kanestop_runtime::scene::{Scene, MAX_STEPS};
use kanestop_runtime::simulate::{is_early, Failure, FailureKind, StaticResidual};
use kanestop_runtime::stability::StabilityLimit;
use kanestop_workflow::diagnostic::describe;

fn case1() -> Model {
    Model::new(&Scene::from_toml(DEFAULT_SCENE, "case01.toml").unwrap()).unwrap()
}

fn runaway(t: f64, residual: Option<StaticResidual>) -> Failure {
    Failure {
        t,
        body: 19,
        kind: FailureKind::EnergyRunaway { drift: 0.056, limit: 0.05, scale: 2.25e6 },
        initial_residual: residual.map(Box::new),
        last_limit: None,
    }
}

#[test]
fn an_early_failure_from_a_state_far_from_static_blames_the_state() {
    let model = case1();
    // The residual of the h_L = 60 m scene the issue ran (now refused).
    let bad = StaticResidual { line: (7.96, 19), top: (115.0, 44) };
    assert!(is_early(0.25, 0.002));
    let text = describe(&model, &runaway(0.25, Some(bad)));
    assert!(text.contains("the initial state is not static"), "{text}");
    assert!(text.contains("1.15e2 m/s² beside the rod (B_44)"), "{text}");
    // The geometry first; the finer integration only if the geometry is as meant.
    let geometry = text.find("initial.horizontal_projection").expect("the geometry fields");
    let finer = text.find("if they are as meant, follow the start's transient more finely: reduce solver.dt (try 1.3e-4 s) or use integrator = \"dp5\"").expect(&text);
    assert!(geometry < finer && text.contains("the initial geometry is the likely cause"), "{text}");
    // Case 1's own residual is near static: the step is advised as before.
    let good = StaticResidual { line: (3.37, 17), top: (3.54, 44) };
    let text = describe(&model, &runaway(0.25, Some(good)));
    assert!(text.contains("reduce solver.dt (try 1.3e-4 s)") && !text.contains("not static"), "{text}");
    assert!(!is_early(5.0, 0.002));
    // Without water the ship's free fall is the residual (1 g beside the rod): the dry ship is
    // named, not the geometry.
    let mut dry = case1();
    dry.scene.environment.water = false;
    let fall = StaticResidual { line: (0.2, 17), top: (9.81, 44) };
    let text = describe(&dry, &runaway(0.25, Some(fall)));
    assert!(text.contains("nothing holds the ship up") && !text.contains("not static"), "{text}");
}

#[test]
fn the_advice_never_goes_below_the_smallest_sensible_step() {
    let mut model = case1();
    let floor = model.scene.solver.end_time / MAX_STEPS;
    model.scene.solver.dt = 4.0 * floor;
    let text = describe(&model, &runaway(1.0, None));
    assert!(text.contains(&format!("try {floor:.1e} s, the smallest")), "{text}");
    model.scene.solver.dt = floor;
    let text = describe(&model, &runaway(1.0, None));
    assert!(text.contains("a smaller step is not sensible") && text.contains("dp5"), "{text}");
}

#[test]
fn a_failure_at_a_heavy_body_is_not_blamed_on_a_light_element() {
    let model = case1();
    // B_19, a cable element 18 048 times lighter than the ship: the light element's mode.
    let text = describe(&model, &runaway(1.0, None));
    assert!(text.contains("a light element swinging between heavy neighbours") && text.contains("18048:1"), "{text}");
    // The ship (B_46), the heaviest body: a stiffness grown with the motion, no mass ratio.
    let ship = Failure { body: model.body_count(), ..runaway(1.0, None) };
    let text = describe(&model, &ship);
    assert!(text.contains("ship (B_46") && text.contains("a stiffness that grew with the motion"), "{text}");
    assert!(!text.contains("light element swinging") && !text.contains("mass ratio"), "{text}");
    // The anchor (B_1), 12.5 times lighter than the ship, is an end of the line, no element
    // between neighbours.
    let anchor = Failure { body: 1, ..runaway(1.0, None) };
    let text = describe(&model, &anchor);
    assert!(text.contains("anchor (B_1") && text.contains("at an end of the line"), "{text}");
    assert!(!text.contains("light element swinging") && !text.contains("mass ratio"), "{text}");
}

/// RK4's limit at the last good state decides the advice: below the step, a step within it
/// (and at most half the failed one); at or above it, the linearisation does not explain the
/// blow-up, and the much finer step of old is advised.
#[test]
fn the_limit_at_the_last_good_state_decides_the_advice() {
    let model = case1();
    let limit =
        |rk4_dt: f64| StabilityLimit { rk4_dt, lambda: nalgebra::Complex::new(-1.0, 400.0), body: 45, settled: true };
    let at = |l: f64| describe(&model, &Failure { last_limit: Some(Box::new(limit(l))), ..runaway(1.0, None) });
    // dt = 2 ms: a limit of 1 ms, so 0.9 of it.
    let text = at(1.0e-3);
    assert!(
        text.contains("stiffened during the run: RK4's limit at the last good state (t = 0.998 s) is 1.000e-3 s"),
        "{text}"
    );
    assert!(text.contains("reduce solver.dt to 9.0e-4 s (at most 0.9 of that limit and half the step"), "{text}");
    // A limit just under the step: half the step.
    let text = at(1.9e-3);
    assert!(text.contains("reduce solver.dt to 1.0e-3 s"), "{text}");
    // Above the step: not the limit's doing.
    let text = at(3.0e-3);
    assert!(
        text.contains("RK4's linearised limit at the last good state (t = 0.998 s) is 3.000e-3 s, above the step"),
        "{text}"
    );
    assert!(text.contains("reduce solver.dt (try 1.3e-4 s)") && !text.contains("stiffened"), "{text}");
}

/// A step-size collapse or stall of an adaptive method is not advised tighter tolerances (they
/// shrink the steps sooner): the stiff method, or looser tolerances. A blow-up still is.
#[test]
fn a_collapse_of_the_adaptive_steps_is_advised_looser_tolerances() {
    use kanestop_runtime::integrate::StepError;
    use kanestop_runtime::scene::Method;
    let collapse = FailureKind::Step(StepError::StepSizeCollapse {
        t: 0.0,
        h: 1e-20,
        h_min: 1e-18,
        error: 3.0,
        component: 100,
        reason: "error test".into(),
    });
    let mut model = case1();
    (model.scene.solver.rtol, model.scene.solver.atol) = (1e-14, 1e-16);
    for (method, advice) in [
        (
            Method::Dp5,
            "use integrator = \"sdirk4\" (stiff), or loosen the tolerances (solver.rtol = 1e-14, solver.atol = 1e-16)",
        ),
        (Method::Sdirk4, "loosen the tolerances (solver.rtol = 1e-14, solver.atol = 1e-16), or reduce solver.dt"),
    ] {
        model.scene.solver.integrator = method;
        let text = describe(&model, &Failure { kind: collapse.clone(), ..runaway(1.0, None) });
        assert!(text.contains(advice) && !text.contains("tighten"), "{text}");
        let text = describe(&model, &runaway(1.0, None));
        assert!(text.contains("tighten solver.rtol"), "{text}");
    }
}

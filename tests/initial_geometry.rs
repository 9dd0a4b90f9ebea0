//! Every accepted scene starts in a physical state (issue 15, items 1 and 6): the laid line
//! ends at (x_L, h_L) to 1e-9 m and the ship's water-plane centre is the origin, or the
//! scene is refused naming the field, its value and the feasible range. The reproductions
//! of the issue, and sweeps of x_L and h_L across the documented feasible range.

use std::path::Path;

use kanestop_runtime::catenary::{continuous_range, laid_range, max_horizontal};
use kanestop_runtime::generated::GeneratedKernel;
use kanestop_runtime::model::Model;
use kanestop_runtime::paper::DEFAULT_SCENE;
use kanestop_runtime::scene::{Problem, Scene, SceneError};
use kanestop_runtime::simulate::{self, Stop};

fn case1() -> Scene {
    Scene::from_toml(DEFAULT_SCENE, "case01.toml").unwrap()
}

/// Case 1 with a 1 m high anchor, so that h_L down to 2 m leaves it under water (the
/// cross-field rule of `anchor.height`), and only the geometry decides.
fn low_anchor() -> Scene {
    let mut s = case1();
    s.anchor.height = 1.0;
    s
}

/// The problems of a scene built in code (as `Scene::from_toml` would report them).
fn problems(scene: &Scene) -> Vec<Problem> {
    let text = scene.to_toml();
    match Scene::from_toml(&text, "edited.toml") {
        Ok(_) => Vec::new(),
        Err(SceneError::Invalid { problems, .. }) => problems,
        Err(e) => panic!("{e}"),
    }
}

/// The one problem of a refused scene, on `field`.
fn refused(scene: &Scene, field: &str) -> Problem {
    let p = problems(scene);
    assert_eq!(p.len(), 1, "{p:?}");
    assert_eq!(p[0].field, field, "{p:?}");
    p[0].clone()
}

/// The line ends at (x_L, h_L) to 1e-9 m and the ship's water-plane centre is the origin.
fn assert_physical(scene: &Scene) -> Model {
    let model = Model::new(scene).unwrap_or_else(|e| panic!("{e}"));
    assert!(model.cable_end_error() <= 1e-9, "cable ends {} m from (x_L, h_L)", model.cable_end_error());
    let joints = model.initial_joints();
    let n = model.body_count();
    let ship = &model.chain.bodies[n - 1];
    let centre = [joints[n - 1][0] + ship.centroid[0], joints[n - 1][1] + ship.centroid[1]];
    assert!(centre[0].hypot(centre[1]) <= 1e-9, "ship's water-plane centre at {centre:?}");
    assert!(model.catenary.grounded_length() >= -1e-9, "grounded {}", model.catenary.grounded_length());
    model
}

#[test]
fn paper_case_1_is_physical() {
    assert_physical(&case1());
}

#[test]
fn vertical_projection_60_is_refused_with_the_range() {
    let mut s = case1();
    s.initial.vertical_projection = 60.0;
    let p = refused(&s, "initial.horizontal_projection");
    assert_eq!(p.value, "148");
    let hi = max_horizontal(152.0, 60.0);
    assert!((hi - 135.68).abs() < 0.01, "{hi}");
    for part in ["for cable length L_c = 152 m and h_L = 60 m", "135.68", "initial.vertical_projection in (4, "] {
        assert!(p.expected.contains(part), "{:?} lacks {part:?}", p.expected);
    }
}

#[test]
fn the_old_taut_cable_is_refused_and_the_new_one_lays() {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes/stress/taut_cable.toml");
    let mut s = Scene::load(&path).unwrap_or_else(|e| panic!("{e}"));
    assert_physical(&s);
    let (_, hi) = laid_range(&s.cable_element_lengths(), 6.0).unwrap();
    assert!(s.initial.horizontal_projection > hi - 0.05, "nearly taut: within 5 cm of {hi}");
    // The scene as it was: √(x_L² + h_L²) = 152.018 m > L_c, and past the fully suspended span.
    s.initial.horizontal_projection = 151.9;
    refused(&s, "initial.horizontal_projection");
    // Just infeasible.
    s.initial.horizontal_projection = hi + 1e-6;
    refused(&s, "initial.horizontal_projection");
}

/// Case 1 with a single-stage cable of `elements` × `length` m and no chain.
fn short_line(elements: usize, length: f64, x: f64, h: f64) -> Scene {
    let mut s = low_anchor();
    s.chain.elements = 0;
    s.cable.stages.truncate(1);
    s.cable.stages[0].elements = elements;
    s.cable.stages[0].element_length = length;
    s.initial.horizontal_projection = x;
    s.initial.vertical_projection = h;
    s
}

#[test]
fn one_cable_element_is_refused_with_the_reason() {
    let straight = short_line(1, (148.0f64 * 148.0 + 36.0).sqrt(), 148.0, 6.0);
    let p = refused(&straight, "cable.stages");
    assert!(p.expected.contains("at least 2 cable elements"), "{p:?}");
    refused(&short_line(1, 150.0, 148.0, 6.0), "cable.stages");
    refused(&short_line(1, 8.0, 5.0, 6.0), "cable.stages");
}

#[test]
fn two_short_elements_lay_or_are_refused_with_the_range() {
    let mut accepted = 0;
    for (len, h) in [(5.0, 6.0), (4.0, 6.0), (10.0, 6.0), (3.5, 2.0)] {
        let lengths = [len, len];
        for f in [0.05, 0.3, 0.6, 0.9, 0.99, 1.0] {
            let Some((lo, hi)) = continuous_range(2.0 * len, h) else { continue };
            let x = lo + f * (hi - lo);
            let s = short_line(2, len, x, h);
            let inside = laid_range(&lengths, h).is_some_and(|(a, b)| x >= a && x <= b);
            if problems(&s).is_empty() {
                assert!(inside, "accepted outside the laid range: {len} m × 2, x_L = {x}, h_L = {h}");
                assert_physical(&s);
                accepted += 1;
            } else {
                assert!(!inside, "refused inside the laid range: {len} m × 2, x_L = {x}, h_L = {h}");
                refused(&s, "initial.horizontal_projection");
            }
        }
    }
    assert!(accepted > 0);
}

/// Accepted points lay physically and run; refused points are outside the laid range.
fn sweep(base: &Scene, points: &[(f64, f64)]) {
    for &(x, h) in points {
        let mut s = base.clone();
        s.initial.horizontal_projection = x;
        s.initial.vertical_projection = h;
        let range = laid_range(&s.cable_element_lengths(), h);
        let inside = range.is_some_and(|(lo, hi)| x >= lo && x <= hi);
        if problems(&s).is_empty() {
            assert!(inside, "accepted x_L = {x} outside {range:?} (h_L = {h})");
            let model = assert_physical(&s);
            // Whole elements lie on the seabed: fewer than the catenary's grounded part, by the
            // element the catenary touches down in and the one the laying lifts off the
            // seabed to meet (x_L, h_L) (measured: at most 1.2 of the longest element here).
            let longest = s.cable_element_lengths().into_iter().fold(0.0, f64::max);
            let (laid, catenary) = (model.grounded_cable_length(), model.catenary.grounded_length());
            assert!(
                laid <= catenary + 1e-9 && catenary - laid < 2.0 * longest,
                "x_L = {x}: laid {laid} m, catenary {catenary} m"
            );
            let mut short = model.scene.clone();
            short.solver.end_time = 0.01;
            let model = Model::new(&short).unwrap();
            let result = simulate::run(&model, Box::new(GeneratedKernel::new(&model.chain).unwrap()));
            assert!(!matches!(result.stop, Stop::Failed(_)), "x_L = {x}, h_L = {h}: {:?}", result.stop);
        } else {
            assert!(!inside, "refused x_L = {x} inside {range:?} (h_L = {h})");
        }
    }
}

/// x_L from just below the smallest to just above the largest feasible value.
fn x_points(base: &Scene, h: f64, count: usize) -> Vec<(f64, f64)> {
    let (lo, hi) = laid_range(&base.cable_element_lengths(), h).unwrap();
    let mut xs: Vec<f64> = (0..=count).map(|i| lo + (hi - lo) * i as f64 / count as f64).collect();
    xs.extend([lo - 1e-6, hi + 1e-6, lo - 1.0, hi + 0.5, base.cable_length() - h]);
    xs.into_iter().map(|x| (x, h)).collect()
}

#[test]
fn sweep_of_x_l_for_case_1() {
    let base = case1();
    let (lo, hi) = laid_range(&base.cable_element_lengths(), 6.0).unwrap();
    let (clo, chi) = continuous_range(152.0, 6.0).unwrap();
    assert!(lo > clo && lo < clo + 1.0 && (hi - chi).abs() < 1e-9, "[{lo}, {hi}] against ({clo}, {chi}]");
    sweep(&base, &x_points(&base, 6.0, 24));
}

#[test]
fn sweep_of_h_l_from_2_to_30_m() {
    let base = low_anchor();
    for h in [2.0, 4.0, 8.0, 12.0, 20.0, 30.0] {
        sweep(&base, &x_points(&base, h, 6));
    }
}

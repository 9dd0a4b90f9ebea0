//! Bad scenes get a clear error naming the file, the field, the value and the valid range.

mod scratch;
use scratch::Scratch;

use kanestop_runtime::model::Model;
use kanestop_runtime::paper::DEFAULT_SCENE;
use kanestop_runtime::scene::{Scene, SceneError};

/// Case 1 with `from` replaced by `to` (which must occur exactly once).
fn edited(from: &str, to: &str) -> String {
    assert_eq!(DEFAULT_SCENE.matches(from).count(), 1, "{from:?} must occur once");
    DEFAULT_SCENE.replace(from, to)
}

fn error(text: &str) -> String {
    match Scene::from_toml(text, "bad.toml") {
        Ok(_) => panic!("scene was accepted"),
        Err(e) => e.to_string(),
    }
}

fn assert_mentions(message: &str, parts: &[&str]) {
    for p in parts {
        assert!(message.contains(p), "{message:?} does not mention {p:?}");
    }
}

#[test]
fn default_scene_is_valid() {
    let scene = Scene::from_toml(DEFAULT_SCENE, "case01.toml").unwrap();
    assert!(Model::new(&scene).is_ok());
}

#[test]
fn negative_mass() {
    let e = error(&edited("[anchor]\nmass = 40000.0", "[anchor]\nmass = -40000.0"));
    assert_mentions(&e, &["bad.toml", "anchor.mass = -40000", "> 0 kg"]);
}

#[test]
fn zero_length() {
    let e = error(&edited("[rod]\nlength = 1.0", "[rod]\nlength = 0.0"));
    assert_mentions(&e, &["bad.toml", "rod.length = 0", "> 0 m"]);
}

#[test]
fn nan_and_infinity() {
    let e = error(&edited("seabed_friction = 0.3", "seabed_friction = nan"));
    assert_mentions(&e, &["environment.seabed_friction = nan", "[0, 2]"]);
    let e = error(&edited("[ship]\nmass = 500000.0", "[ship]\nmass = inf"));
    assert_mentions(&e, &["ship.mass = inf", "finite"]);
}

#[test]
fn extreme_values_are_written_with_an_exponent() {
    // The value as typed, and a bound computed from it, not hundreds of digits.
    let e = error(&edited("gravity = 9.81", "gravity = 1e300"));
    assert_mentions(&e, &["environment.gravity = 1e300", "(0, 100]"]);
    assert!(!e.contains("000000000"), "{e:?}");
    let e = error(&edited("seabed_stiffness = 5000000.0", "seabed_stiffness = 1e-300"));
    assert_mentions(&e, &["environment.seabed_stiffness = 1e-300"]);
    assert!(!e.contains("000000000"), "{e:?}");
    let e = error(&edited("width = 4.0", "width = 1e12"));
    assert_mentions(&e, &["= 4.305e15 kg (the anchor would float)"]);
    let e = error(&edited("radius = 0.0763", "radius = 1e6"));
    assert_mentions(&e, &["= 3.220e15 kg/m (the chain would float"]);
    // Ordinary values stay as written.
    let e = error(&edited("[anchor]\nmass = 40000.0", "[anchor]\nmass = -40000.0"));
    assert_mentions(&e, &["anchor.mass = -40000:"]);
}

#[test]
fn magnitudes_that_overflow_the_equations_are_refused() {
    // 1e300 passed every check and overflowed at t = 0 into a non-finite acceleration that
    // read as a step-size failure; 1e15 still runs (tests/stress.rs runs none so large).
    for (from, to, field) in [
        ("[anchor]\nmass = 40000.0", "[anchor]\nmass = 1e300", "anchor.mass = 1e300"),
        ("element_length = 1.0", "element_length = 1e200", "chain.element_length = 1e200"),
        ("radius = 0.0763", "radius = 1e300", "chain.radius = 1e300"),
        // Two ranges bounded below by other values had no cap (1e300 was taken).
        (
            "output_interval = 0.02",
            "output_interval = 1e300",
            "solver.output_interval = 1e300: must be in [0.002, 1e15]",
        ),
        (
            "paper_stopping_time = 20.01",
            "paper_stopping_time = 1e300",
            "meta.paper_stopping_time = 1e300: must be in (0, 1e15]",
        ),
    ] {
        let e = error(&edited(from, to));
        assert_mentions(&e, &[field]);
        assert!(e.contains("at most 1e15") || e.contains("1e15]"), "{e}");
    }
    let ok = edited("[anchor]\nmass = 40000.0", "[anchor]\nmass = 1e15");
    assert!(Scene::from_toml(&ok, "big.toml").is_ok());
}

#[test]
fn hydrodynamic_coefficients_beyond_any_published_value_are_refused() {
    // A drag coefficient of 1e6 used to run and fail on a stiffness the diagnostic blamed on a
    // small mass; a hundred, the cap, still makes a model (case 1 stops at C_D = 100).
    let e = error(&edited("normal_drag_coefficient = 1.21", "normal_drag_coefficient = 1e6"));
    assert_mentions(&e, &["hydrodynamics.normal_drag_coefficient = 1000000", "in [0, 100]", "below 3"]);
    let e = error(&edited("tangential_drag_coefficient = 0.062", "tangential_drag_coefficient = -0.1"));
    assert_mentions(&e, &["hydrodynamics.tangential_drag_coefficient = -0.1", "in [0, 100]"]);
    let at_cap = edited("anchor_drag_coefficient = 1.05", "anchor_drag_coefficient = 100.0");
    let scene = Scene::from_toml(&at_cap, "cap.toml").unwrap();
    assert!(Model::new(&scene).is_ok());
}

#[test]
fn element_counts_whose_sum_overflows_are_counted_exactly() {
    let max = "9223372036854775807"; // i64::MAX, the largest TOML integer
    let text = edited("[[cable.stages]]\nelements = 3\n", &format!("[[cable.stages]]\nelements = {max}\n"))
        .replace("[[cable.stages]]\nelements = 12\n", &format!("[[cable.stages]]\nelements = {max}\n"));
    let e = error(&text);
    // 2 × (2^63 − 1) + 13 cable elements, + 15 chain links + 3: not usize::MAX.
    assert_mentions(&e, &["cable.stages = 18446744073709551627 elements", "N = 18446744073709551645"]);
}

#[test]
fn a_count_that_is_not_whole_is_refused_in_words() {
    let e = error(&edited("[chain]\nelements = 15", "[chain]\nelements = 15.5"));
    assert_mentions(&e, &["bad.toml", "15.5", "expected a whole number ≥ 0"]);
    assert!(!e.contains("usize"), "{e}");
    // A huge number is quoted as written, not as its 301 digits.
    let e = error(&edited("[chain]\nelements = 15", "[chain]\nelements = 1e300"));
    assert_mentions(&e, &["floating point `1e300`", "expected a whole number ≥ 0"]);
    assert!(!e.contains("0000000000"), "{e}");
    // An ordinary number as the reader wrote it: `15.0`, not a whole-looking `15`.
    let e = error(&edited("[chain]\nelements = 15", "[chain]\nelements = 15.0"));
    assert_mentions(&e, &["floating point `15.0`", "expected a whole number ≥ 0"]);
}

#[test]
fn unknown_key() {
    let e = error(&edited("[anchor]\n", "[anchor]\ncolour = \"red\"\n"));
    assert_mentions(&e, &["bad.toml", "unknown field `colour`", "mass"]);
}

#[test]
fn missing_key() {
    let e = error(&edited("width = 4.0\n", ""));
    assert_mentions(&e, &["bad.toml", "missing field `width`"]);
}

#[test]
fn wrong_type() {
    let e = error(&edited("[chain]\nelements = 15", "[chain]\nelements = -1"));
    assert_mentions(&e, &["bad.toml", "elements"]);
}

#[test]
fn non_positive_dt() {
    let e = error(&edited("dt = 0.002", "dt = 0.0"));
    assert_mentions(&e, &["solver.dt = 0", "(0, 1] s"]);
    let e = error(&edited("dt = 0.002", "dt = -0.1"));
    assert_mentions(&e, &["solver.dt = -0.1"]);
}

#[test]
fn too_few_bodies() {
    // No cable stage: the chain would be anchor, links, rod and ship only.
    let start = DEFAULT_SCENE.find("[[cable.stages]]").unwrap();
    let end = DEFAULT_SCENE.find("[rod]").unwrap();
    let text = format!("{}{}", &DEFAULT_SCENE[..start], &DEFAULT_SCENE[end..]);
    let e = error(&text);
    assert_mentions(&e, &["cable.stages", "at least one"]);
    let e = error(&edited("elements = 3\n", "elements = 0\n"));
    assert_mentions(&e, &["cable.stages[0].elements = 0", "≥ 1"]);
}

#[test]
fn impossible_catenary() {
    let e = error(&edited("horizontal_projection = 148.0", "horizontal_projection = 160.0"));
    assert_mentions(&e, &["initial.horizontal_projection = 160", "[14", "151.84", "h_L = 6 m", "Eqs. 30–34"]);
}

#[test]
fn sinking_ship() {
    let e = error(&edited("[ship]\nmass = 500000.0", "[ship]\nmass = 5000000.0"));
    assert_mentions(&e, &["ship.mass = 5000000", "draught"]);
}

#[test]
fn every_problem_is_reported_at_once() {
    let text = edited("[anchor]\nmass = 40000.0", "[anchor]\nmass = 0.0").replace("dt = 0.002", "dt = -1.0");
    match Scene::from_toml(&text, "bad.toml") {
        Err(SceneError::Invalid { problems, .. }) => {
            let fields: Vec<&str> = problems.iter().map(|p| p.field.as_str()).collect();
            assert_eq!(fields, ["anchor.mass", "solver.dt"]);
        }
        other => panic!("expected two problems, got {other:?}"),
    }
}

#[test]
fn missing_file_names_the_path() {
    let e = Scene::load(std::path::Path::new("no/such/scene.toml")).unwrap_err().to_string();
    assert_mentions(&e, &["no/such/scene.toml"]);
}

#[test]
fn zero_or_negative_tolerance() {
    let e = error(&edited("rtol = 0.000001", "rtol = 0.0"));
    assert_mentions(&e, &["solver.rtol = 0", "[1e-14, 0.1]"]);
    let e = error(&edited("atol = 0.00000001", "atol = -1e-8"));
    assert_mentions(&e, &["solver.atol = -0.00000001", "[1e-16, 1]"]);
    // Regression: atol = 1e-300 passed, and the adaptive steps collapsed at t = 0 (a work
    // term at zero asked for an error below rounding); the advice was to tighten rtol.
    let e = error(&edited("atol = 0.00000001", "atol = 1e-300"));
    assert_mentions(&e, &["solver.atol = 1e-300", "[1e-16, 1]", "a work term at the start"]);
    // A drift limit below the integration's own drift stopped sound runs as instabilities.
    let e = error(&edited("max_energy_drift = 0.05", "max_energy_drift = 1e-9"));
    assert_mentions(&e, &["solver.max_energy_drift = 0.000000001", "[0.0001, 10]", "a blow-up's detector"]);
}

#[test]
fn unknown_integrator() {
    let e = error(&edited("integrator = \"rk4\"", "integrator = \"euler\""));
    assert_mentions(&e, &["bad.toml", "euler", "rk4", "dp5", "sdirk4"]);
}

#[test]
fn a_relative_tolerance_double_precision_cannot_meet_is_refused() {
    // Regression: rtol in (0, 1e-14) passed the scene's check and then panicked in the
    // integrator's own (exit 101), in `run`, `batch` and sweeps.
    let e = error(&edited("rtol = 0.000001", "rtol = 5e-15"));
    assert_mentions(&e, &["solver.rtol = 5e-15", "in [1e-14, 0.1]"]);
    let scene = Scene::from_toml(&edited("rtol = 0.000001", "rtol = 1e-14"), "edge.toml").unwrap();
    assert!(kanestop_runtime::integrate::Tolerances::new(scene.solver.rtol, scene.solver.atol).is_ok());
}

#[test]
fn a_name_on_more_than_one_line_is_refused() {
    // Regression: a line break in meta.name split the terminal tables and batch.csv's rows.
    let e = error(&edited("name = \"case01\"", "name = \"case01\\nnext\""));
    assert_mentions(&e, &["meta.name = \"case01\\nnext\"", "one line of text"]);
    // A comma is a name like any other (CSV quotes it).
    assert!(Scene::from_toml(&edited("name = \"case01\"", "name = \"case 1, heavy\""), "comma.toml").is_ok());
}

#[test]
fn a_paper_time_that_is_not_a_time_is_refused() {
    let e = error(&edited("paper_stopping_time = 20.01", "paper_stopping_time = nan"));
    assert_mentions(&e, &["meta.paper_stopping_time = nan", "(0, 1e15] s"]);
}

#[cfg(unix)]
#[test]
fn a_scene_path_that_is_no_file_is_refused_without_reading_it() {
    // Regression: `extends = "/dev/zero"` read without end.
    let dir = Scratch::new("devzero");
    let file = dir.join("z.toml");
    std::fs::write(&file, "extends = \"/dev/zero\"\n").unwrap();
    let e = Scene::load(&file).unwrap_err().to_string();
    assert_mentions(&e, &["/dev/zero", "not a regular file"]);
    let e = Scene::load(&dir).unwrap_err().to_string();
    assert_mentions(&e, &["not a regular file"]);
}

/// A hinge so high that no water is left under the ship is named as such (the anchor and
/// the ship were blamed, with advice to raise h_L); a ship too heavy for its hull says what
/// the limit is (it said the ship "would float").
#[test]
fn geometry_refusals_name_the_field_that_is_off() {
    let e = error(&edited("hinge_z = 1.0", "hinge_z = 1000.0"));
    assert_mentions(
        &e,
        &["ship.hinge_z = 1000: must be ≤ ", "so that the water depth d", "is positive (it is -992.97"],
    );
    assert!(!e.contains("anchor.height") && !e.contains("ship.mass"), "{e}");
    let e = error(&edited("[ship]\nmass = 500000.0", "[ship]\nmass = 5e6"));
    assert_mentions(
        &e,
        &["ship.mass = 5000000: must be < ρ·L·w·depth = 2562500 kg", "would need a draught of 9.756 m"],
    );
    assert!(!e.contains("would float with"), "{e}");
}

#[test]
fn a_table_of_the_wrong_type_is_called_a_table_not_a_rust_type() {
    // Cable stages that are numbers, not tables: the message says what the file needs.
    let scene = Scene::from_toml(DEFAULT_SCENE, "case01.toml").unwrap();
    let stages = toml::Value::Array(vec![toml::Value::Integer(5)]);
    let e = scene.with_overrides(&[("cable.stages", stages)]).unwrap_err().to_string();
    assert_mentions(&e, &["expected a table"]);
    assert!(!e.contains("struct"), "{e:?}");
}

#[test]
fn a_positive_size_too_small_for_the_equations_is_refused() {
    // Regression: 1e-100 m links and a 1e-300 m rod failed at t = 0 (exit 3), blaming the rod.
    for (from, to, field) in [
        ("element_length = 1.0", "element_length = 1e-100", "chain.element_length = 1e-100"),
        ("mass = 500000.0", "mass = 2.9e-106", "ship.mass = 2.9e-106"),
    ] {
        let e = error(&edited(from, to));
        assert_mentions(&e, &[field, "at least 1e-15", "underflow"]);
    }
}

#[test]
fn an_end_time_of_zero_is_refused_once_and_an_empty_extends_is_no_file() {
    // Regression: two refusals of one field; "cannot read scene <folder>" for extends = "".
    let e = error(&edited("end_time = 60.0", "end_time = 0.0"));
    assert_eq!(e.matches("solver.end_time").count(), 1, "{e}");
    // A step out of its range bounds no other field (it gave an interval in [1e300, 1e15]).
    let e = error(&edited("dt = 0.002", "dt = 1e300"));
    assert_mentions(&e, &["1 invalid value(s)", "solver.dt = 1e300: must be in (0, 1] s"]);
    let dir = Scratch::new("empty-extends");
    let file = dir.join("e.toml");
    std::fs::write(&file, "extends = \"\"\n").unwrap();
    let e = Scene::load(&file).unwrap_err().to_string();
    assert_mentions(&e, &["e.toml", "extends must be a file name"]);
}

#[test]
fn a_sweep_spec_given_as_a_scene_is_named_so() {
    let spec = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes/sweeps/mass_speed.toml");
    let e = Scene::load(&spec).unwrap_err().to_string();
    assert_mentions(&e, &["unknown field `base`", "a sweep spec, not a scene: run it with `kanestop sweep"]);
    // A scene with a misspelt table is no spec.
    let e = error(&edited("[anchor]", "[anchr]"));
    assert!(!e.contains("sweep spec"), "{e}");
}

//! Rules between fields (issue 15, item 2): each value may be valid alone and the scene
//! still impossible; each rule is refused naming the field and what it must be.

mod scratch;
use scratch::Scratch;

use kanestop_runtime::paper::DEFAULT_SCENE;
use kanestop_runtime::scene::{fmt_value, Scene, SceneError};

fn case1() -> Scene {
    Scene::from_toml(DEFAULT_SCENE, "case01.toml").unwrap()
}

/// The fields named by the refusal of `scene` (after a TOML round trip, as a file would be).
fn refused_fields(scene: &Scene) -> Vec<(String, String)> {
    match Scene::from_toml(&scene.to_toml(), "edited.toml") {
        Ok(_) => panic!("accepted"),
        Err(SceneError::Invalid { problems, .. }) => problems.into_iter().map(|p| (p.field, p.expected)).collect(),
        Err(e) => panic!("{e}"),
    }
}

fn assert_refused(scene: &Scene, field: &str, part: &str) {
    let p = refused_fields(scene);
    assert!(p.iter().any(|(f, e)| f == field && e.contains(part)), "{p:?} lacks {field} with {part:?}");
}

#[test]
fn proof_load_above_break_load() {
    let mut s = case1();
    s.chain.proof_load = 2.0 * s.chain.break_load;
    assert_refused(&s, "chain.proof_load", "≤ chain.break_load");
}

/// Values in the wrong unit (docs/model-choices.md, "Inputs in the wrong unit"): each is
/// refused naming the unit likely meant, and a value just inside its bound is taken.
#[test]
fn values_in_the_wrong_unit_are_refused() {
    use kanestop_runtime::scene::{MIN_BREAKING_LENGTH, MIN_DRAUGHT_FRACTION, STANDARD_GRAVITY, WATER_DENSITY};
    // Break loads in kN: case 1's chain would break under 2.7 m of its own weight.
    let mut s = case1();
    (s.chain.proof_load, s.chain.break_load, s.cable.break_load) = (2709.0, 3866.0, 2520.0);
    assert_refused(&s, "chain.break_load", "this one would break under 2.7 m of it): a break load in N, not kN");
    assert_refused(&s, "cable.break_load", "this one would break under 18.6 m of it)");
    let mut s = case1();
    s.cable.break_load = 1.001 * s.cable.mass_per_length * STANDARD_GRAVITY * MIN_BREAKING_LENGTH;
    s.chain.break_load = 1.001 * s.chain.mass_per_length * STANDARD_GRAVITY * MIN_BREAKING_LENGTH;
    s.chain.proof_load = s.chain.break_load / 2.0;
    assert!(s.problems().is_empty(), "{:?}", s.problems());
    // A ship's mass in tonnes: 500 floats case 1's hull on 1 mm.
    let mut s = case1();
    s.ship.mass = 500.0;
    assert_refused(&s, "ship.mass", "a mass in kg, not t");
    let least = MIN_DRAUGHT_FRACTION * s.ship.depth * s.environment.water_density * s.ship.length * s.ship.beam;
    s.ship.mass = 1.001 * least;
    assert!(s.problems().is_empty(), "{:?}", s.problems());
    // Without water the ship is no ship afloat (a test of the mechanics): any mass.
    let mut s = case1();
    (s.environment.water, s.ship.mass) = (false, 500.0);
    assert!(!s.problems().iter().any(|p| p.field == "ship.mass"), "{:?}", s.problems());
    // A water density in t/m³.
    let mut s = case1();
    s.environment.water_density = 1.025;
    assert_refused(&s, "environment.water_density", "in [900, 1300] kg/m³");
    for rho in [WATER_DENSITY.0, 1000.0, WATER_DENSITY.1] {
        s.environment.water_density = rho;
        assert!(s.problems().is_empty(), "{rho}: {:?}", s.problems());
    }
}

#[test]
fn rod_under_water() {
    let mut s = case1();
    s.rod.length = 3.0;
    assert_refused(&s, "rod.length", "≤ ship.hinge_z = 1 m");
}

#[test]
fn anchor_taller_than_the_water() {
    let mut s = case1();
    s.initial.vertical_projection = 2.0;
    s.initial.horizontal_projection = Some(151.0);
    assert_refused(&s, "anchor.height", "below the water depth");
}

#[test]
fn the_depth_check_counts_the_cable_s_resting_height() {
    // A soft seabed buries a thick, heavy cable by most of its radius: the water over the
    // laid line is then shallower than h_L + rod.length − hinge_z (0.05 m here) by 0.15 m,
    // so the exact depth is negative: no water under the ship, which the hinge's height is
    // named for (before 2026-12-07 the anchor, 0.01 m tall, was said to stand out of it).
    let mut s = case1();
    s.environment.current_surface_speed = 1.0;
    s.environment.seabed_stiffness = 11000.0;
    s.anchor.height = 0.01;
    s.chain.elements = 0;
    s.cable.radius = 0.2;
    s.cable.mass_per_length = 140.0;
    s.ship.mass = 1.0e4;
    // A draught of 0.02 m, above the hundredth of the depth a ship afloat has.
    s.ship.depth = 1.0;
    s.ship.hinge_z = 1.45;
    s.initial.vertical_projection = 0.5;
    s.initial.horizontal_projection = Some(151.95);
    let approximate = s.initial.vertical_projection + s.rod.length - s.ship.hinge_z;
    assert!(s.anchor.height < approximate && s.water_depth() < 0.0, "{approximate}, {}", s.water_depth());
    assert_refused(&s, "ship.hinge_z", "≤ 1.351 m (h_L + the cable's resting height + rod.length)");
}

#[test]
fn the_scene_s_water_depth_is_the_model_s() {
    for case in kanestop_runtime::paper::CASES {
        let scene = case.scene();
        let model = kanestop_runtime::model::Model::new(&scene).unwrap();
        let (d, m) = (scene.water_depth(), model.water_depth());
        assert!((d - m).abs() <= 1e-12 * m, "case {}: scene {d} m, model {m} m", case.number);
    }
}

#[test]
fn ship_aground() {
    let mut s = case1();
    s.initial.vertical_projection = 2.5;
    s.initial.horizontal_projection = Some(151.0);
    s.anchor.height = 1.0;
    s.ship.mass = 3.0e6; // draught 5.9 m, depth 10 m: floats, but in 2.5 m of water
    s.ship.depth = 10.0;
    assert_refused(&s, "ship.mass", "the ship's keel");
}

#[test]
fn floating_anchor_chain_and_cable() {
    let mut s = case1();
    s.anchor.mass = 1000.0;
    assert_refused(&s, "anchor.mass", "would float");
    let mut s = case1();
    s.cable.mass_per_length = 1.0;
    assert_refused(&s, "cable.mass_per_length", "would float");
    let mut s = case1();
    s.chain.mass_per_length = 1.0;
    assert_refused(&s, "chain.mass_per_length", "would float");
    // Without water, a light line is a valid (vacuum) scene.
    let mut s = case1();
    s.environment.water = false;
    s.cable.mass_per_length = 1.0;
    assert!(Scene::from_toml(&s.to_toml(), "dry.toml").is_ok());
}

#[test]
fn seabed_too_soft() {
    let mut s = case1();
    s.environment.seabed_stiffness = 1.0e4;
    assert_refused(&s, "environment.seabed_stiffness", "cannot carry");
}

#[test]
fn a_million_chain_links_are_refused_before_allocating() {
    let mut s = case1();
    s.chain.elements = 1_000_000;
    assert_refused(&s, "chain.elements", "bytes");
    let mut s = case1();
    s.cable.stages[1].elements = 100_000;
    assert_refused(&s, "cable.stages", "at most 4000 bodies");
}

#[test]
fn steps_beyond_the_limit_are_refused_with_the_estimate() {
    for dt in [1e-300, 1e-6] {
        let mut s = case1();
        s.solver.dt = dt;
        s.solver.output_interval = 0.01;
        assert_refused(&s, "solver.dt", "steps exceed the limit of 1e7");
    }
    // An end time no step up to 1 s can reach in 1e7 steps: the end time is the field to
    // change (it used to ask for a step of 1e293 s, out of solver.dt's own range).
    let mut s = case1();
    s.solver.end_time = 1e300;
    assert_refused(&s, "solver.end_time", "≤ solver.dt × 1e7 = 20000 s");
    assert!(!refused_fields(&s).iter().any(|(f, _)| f == "solver.dt"), "solver.dt is not to blame");
    // One a longer step can reach names the step, and offers the end time's bound too.
    s.solver.end_time = 1e5;
    assert_refused(&s, "solver.dt", "or solver.end_time ≤ 20000 s");
    // A bound below 0.1 s keeps its digits (it once read "≤ 0.0 s").
    s.solver.dt = 1e-9;
    s.solver.output_interval = 1e-9;
    assert_refused(&s, "solver.dt", "or solver.end_time ≤ 0.01 s");
    let mut s = case1();
    s.solver.dt = 1e-5; // 6e6 steps: allowed
    assert!(Scene::from_toml(&s.to_toml(), "fine.toml").is_ok());
}

/// An output interval below the step names the step it must reach and the two ways out.
#[test]
fn an_output_interval_below_the_step_names_the_step() {
    let mut s = case1();
    s.solver.dt = 0.5;
    assert_refused(&s, "solver.output_interval", "at least solver.dt = 0.5 s: raise it, or take a smaller step");
}

/// The two ranges bounded by other fields, which docs/scenes.md states in words: the hinge on
/// the hull, [−L_N/2, L_N/2], both ends allowed, and the output interval at least the step.
/// The refusal and the reference give the same bounds.
#[test]
fn the_ranges_bounded_by_other_fields_are_the_ones_the_reference_states() {
    let doc = std::fs::read_to_string(concat!(env!("CARGO_MANIFEST_DIR"), "/docs/scenes.md")).unwrap();
    let row = |leaf: &str| doc.lines().find(|l| l.starts_with(&format!("| `{leaf}`"))).unwrap().to_string();
    assert!(row("hinge_x").contains("on the hull: in [−L_N/2, L_N/2]"), "{}", row("hinge_x"));
    assert!(row("output_interval").contains("at least `dt`"), "{}", row("output_interval"));

    let half = case1().ship.length / 2.0;
    for at_the_end in [-half, half] {
        let mut s = case1();
        s.ship.hinge_x = at_the_end;
        assert!(!s.problems().iter().any(|p| p.field == "ship.hinge_x"), "hinge_x = {at_the_end}");
    }
    let range = format!("in [{}, {}] m (on the hull)", fmt_value(-half), fmt_value(half));
    for beyond in [-half * (1.0 + 1e-9), half * (1.0 + 1e-9)] {
        let mut s = case1();
        s.ship.hinge_x = beyond;
        assert_refused(&s, "ship.hinge_x", &range);
    }

    // The interval may equal the step; a hair below it is refused with the step named.
    let mut s = case1();
    s.solver.output_interval = s.solver.dt;
    assert!(!s.problems().iter().any(|p| p.field == "solver.output_interval"));
    s.solver.output_interval = s.solver.dt * (1.0 - 1e-9);
    assert_refused(&s, "solver.output_interval", &format!("at least solver.dt = {} s", fmt_value(s.solver.dt)));
}

#[test]
fn a_check_is_set_on_a_scene_without_checks() {
    // Regression: `checks.max_stopping_distance` on case 1 (no [checks]) was "no field
    // `checks` here"; a check can be added to one run as a sweep's [checks] adds it.
    let case1 = case1();
    assert!(case1.checks.is_none());
    let s = case1.with_overrides(&[("checks.max_stopping_distance", toml::Value::Float(20.0))]).unwrap();
    let checks = s.checks.expect("[checks] added");
    assert_eq!(checks.max_stopping_distance, Some(20.0));
    assert_eq!(checks.safety_factor, None, "only the field set");
    let e = case1.with_overrides(&[("checks.max_distance", toml::Value::Float(20.0))]).unwrap_err().to_string();
    // (named as the unknown field, with the checks there are: it was "no field `checks`").
    assert!(
        e.contains("no field `max_distance` here (valid: max_anchor_drag, max_proof_utilisation, "),
        "a field that is no check is still refused: {e}"
    );
    // CHECK_FIELDS are DesignChecks' own fields.
    let all = kanestop_runtime::design::DesignChecks {
        max_stopping_distance: Some(1.0),
        max_stopping_time: Some(1.0),
        max_anchor_drag: Some(1.0),
        safety_factor: Some(1.0),
        max_proof_utilisation: Some(1.0),
    };
    let keys: Vec<String> = toml::Value::try_from(all).unwrap().as_table().unwrap().keys().cloned().collect();
    let mut fields: Vec<&str> = kanestop_runtime::design::CHECK_FIELDS.to_vec();
    fields.sort();
    assert_eq!(keys, fields);
}

/// The command line refuses an impossible geometry with exit 2, naming the field.
#[test]
fn cli_refuses_the_h_l_60_scene_with_exit_2() {
    let dir = Scratch::new("rules");
    let path = dir.join("bad60.toml");
    std::fs::write(&path, DEFAULT_SCENE.replace("vertical_projection = 6.0", "vertical_projection = 60.0")).unwrap();
    let out = std::process::Command::new(env!("CARGO_BIN_EXE_kanestop")).arg("run").arg(&path).output().unwrap();
    let err = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(2), "{err}");
    assert!(err.contains("bad60.toml") && err.contains("initial.horizontal_projection = 148"), "{err}");
    assert!(err.contains("[95.") && err.contains("135.68"), "{err}");
}

/// Every field with a fixed range states it in docs/scenes.md as the refusal does: the range
/// a user reads is the one the checks apply.
#[test]
fn the_scene_reference_states_each_fixed_range_the_checks_apply() {
    let doc = std::fs::read_to_string(concat!(env!("CARGO_MANIFEST_DIR"), "/docs/scenes.md")).unwrap();
    // Every field the checks hold to a range (`c.range("…"` in the scene's checks), but those
    // whose bounds are other fields, which the reference states in words: ship.hinge_x on the
    // hull, [−L_N/2, L_N/2], and solver.output_interval, at least dt.
    let source = std::fs::read_to_string(concat!(env!("CARGO_MANIFEST_DIR"), "/runtime/src/scene.rs")).unwrap();
    let fields: Vec<&str> = source
        .split("c.range(\"")
        .skip(1)
        .filter_map(|rest| rest.split('"').next())
        .filter(|f| !["ship.hinge_x", "solver.output_interval"].contains(f))
        .collect();
    assert!(fields.len() >= 13, "{fields:?}");
    for field in fields {
        // Above the range, or below where it has no upper bound.
        let refusal = [1e30, -1e30].into_iter().find_map(|bad| {
            let mut s = case1();
            let problems = if field == "meta.paper_stopping_time" {
                s.meta.paper_stopping_time = Some(bad);
                s.problems()
            } else {
                match s.with_overrides(&[(field, toml::Value::Float(bad))]) {
                    Ok(s) => s.problems(),
                    Err(SceneError::Invalid { problems, .. }) => problems,
                    Err(e) => panic!("{field}: {e}"),
                }
            };
            // Its fixed range's refusal (a huge end time is also refused against the step).
            problems.into_iter().find(|p| p.field == field && p.expected.starts_with("in "))
        });
        let p = refusal.unwrap_or_else(|| panic!("{field}: no value refused"));
        // "in (0, 1] s" → "in (0, 1]": the bounds as the refusal gives them.
        let end = p.expected.find([']', ')']).unwrap_or_else(|| panic!("{field}: {}", p.expected));
        let range = &p.expected[..=end];
        assert!(range.starts_with("in "), "{field}: {}", p.expected);
        let leaf = field.rsplit('.').next().unwrap();
        let row = doc.lines().find(|l| l.starts_with(&format!("| `{leaf}`"))).unwrap_or_else(|| panic!("{leaf}"));
        let sentence = range.replacen("in ", "In ", 1);
        assert!(row.contains(range) || row.contains(&sentence), "docs/scenes.md's {leaf} lacks {range:?}: {row}");
    }
}

//! Figures the docs quote in prose that follow from the scenes and the code's constants, not
//! from a whole run: each is computed here and must appear in its doc as written (whitespace
//! aside). A stale figure fails, naming the phrase the code gives now; edit the doc to it.
//! Figures from runs are checked where the runs are made (`paper_claims.rs`,
//! `stress_scenes.rs`, `sweeps.rs`, `generated_run.rs`); docs/validation.md lists them all.

use std::path::Path;

use kanestop_runtime::forces::ship::ShipHydro;
use kanestop_runtime::generated::GeneratedKernel;
use kanestop_runtime::model::Model;
use kanestop_runtime::paper::CASES;
use kanestop_runtime::scene::{bytes_for_bodies, MAX_BODIES, MAX_STEPS, SECONDS_PER_BODY_EVALUATION};

fn read(name: &str) -> String {
    std::fs::read_to_string(Path::new(env!("CARGO_MANIFEST_DIR")).join(name)).unwrap_or_else(|e| panic!("{name}: {e}"))
}

/// A doc with its whitespace collapsed, so a quoted phrase matches across line breaks.
fn flat(name: &str) -> String {
    read(name).split_whitespace().collect::<Vec<_>>().join(" ")
}

/// The phrases a doc should contain and does not.
fn missing(doc: &str, phrases: &[String]) -> Vec<String> {
    let text = flat(doc);
    phrases.iter().filter(|p| !text.contains(p.as_str())).map(|p| format!("{doc} should say: {p}")).collect()
}

fn assert_quoted(doc: &str, phrases: &[String]) {
    let m = missing(doc, phrases);
    assert!(m.is_empty(), "stale figures (edit the doc to what the code gives):\n{}", m.join("\n"));
}

/// `x` to `decimals` places without trailing zeros (146.000000 → 146).
fn trimmed(x: f64, decimals: usize) -> String {
    let s = format!("{x:.decimals$}");
    if s.contains('.') {
        s.trim_end_matches('0').trim_end_matches('.').to_string()
    } else {
        s
    }
}

/// An integer with its thousands grouped by spaces, as the docs write them (1 000 000).
fn grouped(n: usize) -> String {
    let digits = n.to_string();
    let mut out = String::new();
    for (i, c) in digits.chars().enumerate() {
        if i > 0 && (digits.len() - i) % 3 == 0 {
            out.push(' ');
        }
        out.push(c);
    }
    out
}

/// The value of `const NAME: TYPE = VALUE;` in a source file (constants the tests cannot import).
fn source_const(file: &str, name: &str) -> String {
    let text = read(file);
    let line = text.lines().find(|l| l.contains(&format!("const {name}:"))).unwrap_or_else(|| panic!("{file}: {name}"));
    line.split('=').nth(1).unwrap().trim().trim_end_matches(';').to_string()
}

#[test]
fn model_choices_figures_are_what_the_code_computes() {
    let scene = CASES[0].scene();
    let model = Model::new(&scene).unwrap();
    let (lo, hi) =
        kanestop_runtime::catenary::laid_range(&scene.cable_element_lengths(), scene.initial.vertical_projection)
            .expect("case 1 has a feasible range");
    let env = &scene.environment;
    let embedment = |radius: f64, mpl: f64| 1e3 * (radius - env.resting_height(radius, mpl));
    let ship = ShipHydro::new(
        scene.ship.mass,
        scene.ship.length,
        scene.ship.beam,
        scene.ship.hull_roughness,
        env.water_density,
        env.gravity,
        env.kinematic_viscosity,
    );
    let residual =
        kanestop_runtime::simulate::static_residual(&model, Box::new(GeneratedKernel::new(&model.chain).unwrap()))
            .unwrap();
    // The curve the rigid chords are laid on, longer than the cable (L' ≥ L_c).
    let (laid, _) = kanestop_runtime::catenary::lay_elements(
        &scene.cable_element_lengths(),
        scene.initial.horizontal_projection.expect("case 1 gives x_L"),
        scene.initial.vertical_projection,
    )
    .unwrap();
    let excess = laid.length - scene.cable_length();
    let drifts: Vec<f64> = CASES.iter().map(|c| c.scene().solver.max_energy_drift).collect();
    assert!(drifts.iter().all(|&d| d == drifts[0]), "one energy-drift limit for the paper scenes: {drifts:?}");
    assert_quoted(
        "docs/model-choices.md",
        &[
            format!("for case 1 it is [{lo:.6}, {hi:.6}] m"),
            format!("L' − L_c is {:.0} mm, {:.2} % of L_c", 1e3 * excess, 100.0 * excess / scene.cable_length()),
            format!("the {:.0} mm the chords add", 1e3 * excess),
            format!("radius of curvature a = {:.2} m", laid.a),
            format!(
                "about {:.0} mm into the seabed for the {} m chain and {:.0} mm for the cable",
                embedment(scene.chain.radius, scene.chain.mass_per_length),
                scene.chain.radius,
                embedment(scene.cable.radius, scene.cable.mass_per_length)
            ),
            format!("({:.3} m for case 1)", model.water_depth()),
            format!("({:.0} m for the {:.0} t ship)", ship.metacentric_height, scene.ship.mass / 1e3),
            format!("(case 1: {:.2} g, from the first cable element", residual.line.0 / env.gravity),
            format!("Above {} g the diagnosis", kanestop_workflow::diagnostic::NOT_STATIC),
            format!("`solver.max_energy_drift` ({} in the paper scenes)", drifts[0]),
            format!("the cable's {:.0} kN break load", scene.cable.break_load / 1e3),
            format!("at most `MAX_BODIES` = {MAX_BODIES}"),
            format!("{:.1} GB at N = {MAX_BODIES}", bytes_for_bodies(MAX_BODIES) / 1e9),
            format!("at most `MAX_STEPS` = {MAX_STEPS:e} steps"),
            format!("({:.2} µs per body and right-hand side", SECONDS_PER_BODY_EVALUATION * 1e6),
            format!("kernels up to `MAX_UNROLLED_BODIES` = {} bodies", kanestop_codegen::MAX_UNROLLED_BODIES),
        ],
    );
    // `initial.horizontal_projection`'s doc comment (runtime/src/scene.rs, rendered into
    // docs/scenes.md): the continuous cable's x_L range for case 1, and how far the rigid
    // elements raise its lower end.
    let (c_lo, c_hi) =
        kanestop_runtime::catenary::continuous_range(scene.cable_length(), scene.initial.vertical_projection)
            .expect("case 1 has a continuous range");
    assert!((lo - c_lo).abs() < 1e-5 && (hi - c_hi).abs() < 1e-5, "laid [{lo}, {hi}] against ({c_lo}, {c_hi}]");
    assert_quoted(
        "docs/scenes.md",
        &[
            format!("for case 1, ({}, {c_hi:.6}] m)", trimmed(c_lo, 6)),
            "the rigid elements may raise the lower end (case 1: by less than 1e-5 m)".to_string(),
        ],
    );
}

#[test]
fn codegen_and_conventions_figures_are_what_the_code_computes() {
    // The body counts of the paper's scenes: the unrolled kernels checked in for them.
    let mut counts: Vec<usize> = CASES.iter().map(|c| Model::new(&c.scene()).unwrap().body_count()).collect();
    counts.sort();
    counts.dedup();
    let counts: Vec<String> = counts.iter().map(|n| n.to_string()).collect();
    assert_quoted(
        "docs/codegen.md",
        &[
            format!("every N the paper's scenes (`scenes/paper/`) need ({})", counts.join(", ")),
            format!("in a scratch of {} values per body", source_const("generated/src/lib.rs", "ROLLED_SCRATCH")),
        ],
    );
    // The mass matrix's condition over the paper's chains at their initial states, and the
    // masses that make it so.
    let (mut lo, mut hi) = (f64::MAX, 0.0f64);
    for c in CASES {
        let model = Model::new(&c.scene()).unwrap();
        let e = kanestop_runtime::eval::evaluate(&model, Box::new(GeneratedKernel::new(&model.chain).unwrap()), None)
            .unwrap();
        (lo, hi) = (lo.min(e.cond), hi.max(e.cond));
    }
    let scene = CASES[0].scene();
    let model = Model::new(&scene).unwrap();
    let lightest = model.chain.bodies.iter().filter(|b| b.kind.is_rod_like()).map(|b| b.mass).fold(f64::MAX, f64::min);
    assert_quoted(
        "docs/conventions.md",
        &[format!(
            "(cond ≈ {lo:.1e}–{hi:.1e} at the paper's initial states: a {:.0} t ship on elements of {:.0} kg and more)",
            scene.ship.mass / 1e3,
            lightest
        )],
    );
}

#[test]
fn integrators_figures_are_what_the_code_computes() {
    use kanestop_runtime::integrate::StepControl;
    let tests = read("tests/integrators.rs").lines().filter(|l| l.trim() == "#[test]").count();
    // `report accuracy`'s runs at the CLI's default repeats (`--repeats`, in src/main.rs).
    let main = read("src/main.rs");
    let lines: Vec<&str> = main.lines().collect();
    let at = lines.iter().position(|l| l.trim() == "repeats: usize,").expect("src/main.rs: --repeats");
    let repeats: usize = lines[at - 1]
        .split("default_value_t =")
        .nth(1)
        .expect("--repeats default")
        .trim()
        .trim_end_matches(")]")
        .parse()
        .unwrap();
    let runs = kanestop_workflow::accuracy::run_count(&kanestop_workflow::accuracy::default_plan(), repeats);
    let c = StepControl::default();
    // DP5's stability limit on the negative real axis: the |hλ| at which one fixed step on
    // ẏ = −y stops damping (|R(−hλ)| = 1), found by bisection.
    let boundary = {
        struct Decay;
        impl kanestop_runtime::integrate::OdeSystem for Decay {
            fn dim(&self) -> usize {
                1
            }
            fn rhs(&mut self, _t: f64, y: &[f64], dy: &mut [f64]) -> Result<(), kanestop_runtime::integrate::RhsError> {
                dy[0] = -y[0];
                Ok(())
            }
        }
        use kanestop_runtime::integrate::Integrator;
        let mut dp = kanestop_runtime::integrate::Dp5::new(1, 1e-6, 1e-9).unwrap();
        let mut grows = |h: f64| {
            let mut y = [1.0];
            dp.step(&mut Decay, 0.0, &mut y, h).unwrap();
            y[0].abs() > 1.0
        };
        let (mut stable, mut unstable) = (1.0, 5.0);
        assert!(!grows(stable) && grows(unstable));
        while unstable - stable > 1e-9 {
            let mid = 0.5 * (stable + unstable);
            if grows(mid) {
                unstable = mid;
            } else {
                stable = mid;
            }
        }
        stable
    };
    assert_quoted(
        "docs/integrators.md",
        &[
            format!("(stability limit {boundary:.1}/1e6)"),
            format!("`cargo test --test integrators` ({tests} tests"),
            format!("the median over {repeats} runs in the same invocation"),
            format!("a line every 10 % of the {runs} runs"),
            format!(
                "StepControl: safety {}, fac {}..{}, PI β = {}, h_min, h_max",
                c.safety, c.fac_min, c.fac_max, c.beta
            ),
            format!("`max_rejections` ({}) consecutive failures", c.max_rejections),
            format!("`SPIKE_FACTOR` = {} × the line's largest break load", kanestop_runtime::simulate::SPIKE_FACTOR),
        ],
    );
}

#[test]
fn sweeps_figures_are_what_the_code_computes() {
    use kanestop_workflow::sweep::{shard::MAX_SHARDS, slurm::default_shards};
    assert_quoted(
        "docs/sweeps.md",
        &[
            format!("1 ≤ N ≤ {})", grouped(MAX_SHARDS)),
            format!("`--shards` defaults to one shard per row up to {}", default_shards(usize::MAX)),
        ],
    );
}

#[test]
fn python_figures_are_what_the_code_computes() {
    // The channels a case-1 run hands to NumPy, to the nearest ten.
    let channels = kanestop_workflow::history::all_channels(Model::new(&CASES[0].scene()).unwrap().body_count()).len();
    assert_quoted(
        "docs/python.md",
        &[format!("handing ~{} channels to NumPy", (channels as f64 / 10.0).round() * 10.0)],
    );
}

#[test]
fn a_stale_figure_is_reported() {
    // The check itself: a phrase the doc does not hold is reported, one it holds is not.
    assert!(missing("docs/model-choices.md", &["at most `MAX_BODIES` = 3999".to_string()]).len() == 1);
    assert!(missing("docs/model-choices.md", &["# Model choices".to_string()]).is_empty());
}

//! The command-line contract: `run`, `eval` and their JSON and CSV outputs.

mod scratch;
use scratch::Scratch;

use std::process::Command;

use kanestop_runtime::eval::EvalOutput;

fn kanestop() -> Command {
    Command::new(env!("CARGO_BIN_EXE_kanestop"))
}

/// The test's scratch folder, removed when it passes (tests/scratch).
fn temp_dir(name: &str) -> Scratch {
    Scratch::new(&format!("test-{name}"))
}

/// A short, stable scene: case 1 with a smaller step, ended at 0.05 s.
fn short_scene(dir: &std::path::Path) -> std::path::PathBuf {
    let text = kanestop_runtime::paper::DEFAULT_SCENE
        .replace("dt = 0.002", "dt = 0.0005")
        .replace("end_time = 60.0", "end_time = 0.05")
        .replace("output_interval = 0.02", "output_interval = 0.01");
    let path = dir.join("short.toml");
    std::fs::write(&path, text).unwrap();
    path
}

#[test]
fn eval_json_round_trips_and_is_consistent() {
    let out = kanestop().args(["eval"]).output().unwrap();
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    let text = String::from_utf8(out.stdout).unwrap();
    let parsed: EvalOutput = serde_json::from_str(&text).expect("eval output matches the documented schema");
    let again: EvalOutput = serde_json::from_str(&serde_json::to_string(&parsed).unwrap()).unwrap();
    assert_eq!(parsed, again);
    // Documented keys, by name, as outside checks read them.
    let value: serde_json::Value = serde_json::from_str(&text).unwrap();
    for key in ["q", "u", "M", "f", "qdd", "cond", "residual", "bodies", "coordinates", "anchor", "active"] {
        assert!(value.get(key).is_some(), "missing key {key}");
    }
    for key in ["x", "z", "vx", "vz", "ax", "az", "angle", "omega", "alpha"] {
        assert!(value["bodies"][0].get(key).is_some(), "missing body key {key}");
    }
    let n = parsed.bodies_count;
    assert_eq!(n, 46);
    assert_eq!(parsed.q.len(), n);
    assert_eq!(parsed.active, n - 1, "case 1 starts with the anchor held");
    assert_eq!(parsed.mass_matrix.len(), parsed.active);
    assert_eq!(parsed.qdd.len(), parsed.active);
    assert!(parsed.residual < 1e-6, "residual {}", parsed.residual);
    assert!(parsed.cond > 1.0 && parsed.cond.is_finite());
    // The ship's centroid is the inertial origin at t = 0 and moves at 3 m/s.
    let ship = &parsed.bodies[n - 1];
    assert!(ship.x.abs() < 1e-9 && ship.z.abs() < 1e-9);
    assert!((ship.vx - 3.0).abs() < 1e-12 && ship.vz.abs() < 1e-12);
    assert!(ship.omega.abs() < 1e-12);
}

#[test]
fn eval_accepts_a_state_file_and_rejects_a_bad_one() {
    let dir = temp_dir("eval");
    let first: EvalOutput = serde_json::from_slice(&kanestop().arg("eval").output().unwrap().stdout).unwrap();
    let mut q = first.q.clone();
    q[10] += 0.1;
    let state = dir.join("state.json");
    std::fs::write(&state, serde_json::json!({"q": q, "u": first.u, "anchor": "free"}).to_string()).unwrap();
    let out = kanestop().args(["eval", "--state"]).arg(&state).output().unwrap();
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    let parsed: EvalOutput = serde_json::from_slice(&out.stdout).unwrap();
    assert_eq!(parsed.q, q);
    assert_eq!(parsed.active, 46);

    // A state no kernel can evaluate is refused alike by both, not reported as nulls.
    q[10] = 1e300;
    std::fs::write(&state, serde_json::json!({"q": q, "u": first.u, "anchor": "free"}).to_string()).unwrap();
    for kernel in ["generated", "reference"] {
        let out = kanestop().args(["eval", "--kernel", kernel, "--state"]).arg(&state).output().unwrap();
        let err = String::from_utf8_lossy(&out.stderr);
        assert_eq!(out.status.code(), Some(2), "{kernel}: {err}");
        assert!(out.stdout.is_empty() && err.contains("non-finite acceleration"), "{kernel}: {err}");
        assert!(err.contains("the state's largest entry is state.q[10] = 1e300"), "{kernel}: {err}");
    }

    std::fs::write(&state, r#"{"q": [0.0, 1.0], "u": [0.0, 0.0]}"#).unwrap();
    let out = kanestop().args(["eval", "--state"]).arg(&state).output().unwrap();
    assert_eq!(out.status.code(), Some(2));
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(err.contains("state.q has 2 entries") && err.contains("N = 46"), "{err}");
}

#[test]
fn run_prints_a_summary_and_writes_the_csv_whole() {
    let dir = temp_dir("run");
    let scene = short_scene(&dir);
    let csv = dir.join("history.csv");
    let out = kanestop().arg("run").arg(&scene).arg("--out").arg(&csv).output().unwrap();
    let stdout = String::from_utf8_lossy(&out.stdout);
    assert!(out.status.success(), "{stdout}\n{}", String::from_utf8_lossy(&out.stderr));
    // The short scene ends at its end time with the ship still moving: `ended`, not `stopped`.
    for label in ["scene", "ended     end time", "anchor", "tension", "checks    PASS", "energy", "run"] {
        assert!(stdout.contains(label), "summary lacks {label}: {stdout}");
    }
    assert!(!stdout.contains("\ncatenary "), "solver internals only with --verbose: {stdout}");
    let out = kanestop().arg("run").arg(&scene).arg("--verbose").output().unwrap();
    let verbose = String::from_utf8_lossy(&out.stdout);
    for label in ["physics", "bodies", "N = 46", "catenary", "stability", "final", "balance"] {
        assert!(verbose.contains(label), "--verbose lacks {label}: {verbose}");
    }
    let text = std::fs::read_to_string(&csv).unwrap();
    let mut lines = text.lines();
    let header: Vec<&str> = lines.next().unwrap().split(',').collect();
    assert_eq!(
        header.len(),
        1 + 7 + 4 + 3 + 15 + 6 * 46 + 45,
        "t, ship, anchor, tension, energy (3 energies, 11 works, balance); 6 per body; 45 joints"
    );
    assert_eq!(&header[..4], ["t", "ship_x", "ship_z", "ship_theta"]);
    for name in
        ["ship_displacement", "anchor_drag", "anchor_sliding", "tension_fairlead", "tension_anchor", "work_friction"]
    {
        assert!(header.contains(&name), "no channel {name}");
    }
    assert!(header.contains(&"body46_x") && header.contains(&"body1_vx"));
    assert_eq!(header[header.len() - 1], "tension_joint46");
    let rows: Vec<Vec<f64>> = lines.map(|l| l.split(',').map(|v| v.parse().unwrap()).collect()).collect();
    assert_eq!(rows.len(), 6, "samples at 0, 0.01, …, 0.05 s");
    assert!(rows.iter().all(|r| r.len() == header.len()));
    let col = |name: &str| header.iter().position(|h| *h == name).unwrap();
    // Derived channels: displacements from t = 0, the fairlead tension is joint N's.
    assert_eq!(rows[0][col("ship_displacement")], 0.0);
    let last = rows.last().unwrap();
    assert!((last[col("ship_displacement")] - (last[col("ship_x")] - rows[0][col("ship_x")])).abs() < 1e-9);
    assert_eq!(last[col("tension_fairlead")], last[col("tension_joint46")]);
    assert_eq!(last[col("tension_anchor")], last[col("tension_joint2")]);
    // The units sidecar lists every column in order.
    let units = std::fs::read_to_string(dir.join("history.units.csv")).unwrap();
    let listed: Vec<&str> = units.lines().skip(1).map(|l| l.split(',').next().unwrap()).collect();
    assert_eq!(listed, header);
    assert!(units.contains("tension_fairlead,N,") && units.contains("ship_x,m,") && units.contains("t,s,"));
    assert!((rows.last().unwrap()[0] - 0.05).abs() < 1e-12);
    // No temporary file is left behind.
    let leftovers: Vec<_> = std::fs::read_dir(&dir)
        .unwrap()
        .filter_map(|e| e.ok())
        .filter(|e| e.file_name().to_string_lossy().contains(".tmp"))
        .collect();
    assert!(leftovers.is_empty());
}

#[test]
fn unwritable_output_is_an_error_and_leaves_nothing() {
    let dir = temp_dir("unwritable");
    let scene = short_scene(&dir);
    // A folder that cannot be made: its would-be parent is a file.
    std::fs::write(dir.join("plain"), "x").unwrap();
    let out = kanestop().arg("run").arg(&scene).arg("--out").arg(dir.join("plain/new/history.csv")).output().unwrap();
    assert_eq!(out.status.code(), Some(2));
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(err.contains("cannot write") && err.contains("not a folder"), "{err}");
    // Checked before the run: no summary was printed.
    assert!(out.stdout.is_empty(), "{}", String::from_utf8_lossy(&out.stdout));
    assert_eq!(std::fs::read_to_string(dir.join("plain")).unwrap(), "x");
}

#[test]
fn run_out_creates_its_folder_as_plot_and_batch_do() {
    let dir = temp_dir("run-new-folder");
    let scene = short_scene(&dir);
    let csv = dir.join("results/case/history.csv");
    let out = kanestop().arg("run").arg(&scene).arg("--out").arg(&csv).output().unwrap();
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    assert!(csv.is_file() && dir.join("results/case/history.units.csv").is_file());
}

#[test]
fn eval_takes_its_scene_as_run_does_or_by_flag() {
    let dir = temp_dir("eval-positional");
    let scene = short_scene(&dir);
    let positional = kanestop().arg("eval").arg(&scene).output().unwrap();
    assert!(positional.status.success(), "{}", String::from_utf8_lossy(&positional.stderr));
    let flag = kanestop().args(["eval", "--scene"]).arg(&scene).output().unwrap();
    assert!(flag.status.success(), "{}", String::from_utf8_lossy(&flag.stderr));
    assert_eq!(positional.stdout, flag.stdout);
    let both = kanestop().arg("eval").arg(&scene).arg("--scene").arg(&scene).output().unwrap();
    assert_eq!(both.status.code(), Some(2), "one scene, not two");
}

#[test]
fn bad_scene_is_a_clear_error_not_a_panic() {
    let dir = temp_dir("bad");
    let path = dir.join("bad.toml");
    std::fs::write(&path, kanestop_runtime::paper::DEFAULT_SCENE.replace("dt = 0.002", "dt = -0.002")).unwrap();
    let out = kanestop().arg("run").arg(&path).output().unwrap();
    assert_eq!(out.status.code(), Some(2));
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(err.contains("bad.toml") && err.contains("solver.dt = -0.002") && !err.contains("panicked"), "{err}");
}

#[test]
fn stiff_gravity_only_chain_diverges_with_a_diagnostic() {
    // Case 1 without water and seabed: the unbuoyed 500 t ship drops onto a chain of
    // 14–143 kg elements and the explicit step of 0.002 s becomes unstable. The run must stop
    // with the diagnostic, not print garbage.
    let dir = temp_dir("stiff");
    let path = dir.join("gravity-only.toml");
    let text = kanestop_runtime::paper::DEFAULT_SCENE
        .replace("water = true", "water = false")
        .replace("seabed = true", "seabed = false")
        .replace("end_time = 60.0", "end_time = 10.0")
        .replace("stop_when_ship_stops = true", "stop_when_ship_stops = false");
    std::fs::write(&path, text).unwrap();
    let out = kanestop().arg("run").arg(&path).arg("--verbose").output().unwrap();
    let stdout = String::from_utf8_lossy(&out.stdout);
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(3), "{stdout}");
    assert!(stdout.contains("physics   gravity\n") && stdout.contains("FAILED"), "{stdout}");
    // The diagnostic goes to standard error.
    // It names the dry scene's unsupported ship, which a user may not have meant.
    for part in [
        "numerical failure at t =",
        "body:",
        "likely cause:",
        "likely cause: without water (environment.water = false) nothing holds the ship up",
        "suggestion: for a ship afloat, environment.water = true; as it is, reduce solver.dt",
    ] {
        assert!(stderr.contains(part), "missing {part:?} in {stderr}");
    }
}

#[test]
fn default_run_reports_the_stopping_time_against_the_paper() {
    let out = kanestop().output().unwrap();
    let stdout = String::from_utf8_lossy(&out.stdout);
    assert!(out.status.success(), "{stdout}");
    for part in [
        "scene     case01",
        "initial   x_L = 148 m, h_L = 6 m, T_h = 148.0 N, T_t = 856.8 N at the top, water depth 6.022 m",
        "against one's loads, as in the paper's scenes, a utilisation is twice one line's",
        "(ship surge speed reached zero)",
        "paper (Table 3): 20.010 s",
        "anchor    started to slide",
        "checks    PASS",
        "anchor friction",
    ] {
        assert!(stdout.contains(part), "missing {part:?} in {stdout}");
    }
    println!("{stdout}");
}

#[test]
fn batch_tabulates_a_folder_and_writes_csv_and_json() {
    let dir = temp_dir("batch");
    let scenes = dir.join("scenes");
    std::fs::create_dir_all(&scenes).unwrap();
    let short = short_scene(&dir);
    std::fs::copy(&short, scenes.join("a.toml")).unwrap();
    std::fs::write(scenes.join("b.toml"), "not a scene").unwrap();
    let out_dir = dir.join("out");
    let out = kanestop().arg("batch").arg(&scenes).arg("--out").arg(&out_dir).output().unwrap();
    let stdout = String::from_utf8_lossy(&out.stdout);
    // One invalid scene: the batch reports it and exits non-zero, the valid one still runs.
    assert_eq!(out.status.code(), Some(1), "{stdout}");
    assert!(stdout.contains("case01") && stdout.contains("end time") && stdout.contains("invalid"), "{stdout}");
    let json: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(out_dir.join("batch.json")).unwrap()).unwrap();
    let rows = json.as_array().unwrap();
    assert_eq!(rows.len(), 2);
    for key in [
        "case",
        "stopping_time",
        "paper_stopping_time",
        "relative_difference",
        "peak_tension",
        "peak_joint",
        "anchor_start",
        "energy_drift",
        "wall_time",
    ] {
        assert!(rows[0].get(key).is_some(), "batch.json lacks {key}");
    }
    let csv = std::fs::read_to_string(out_dir.join("batch.csv")).unwrap();
    assert_eq!(csv.lines().count(), 3);
    assert!(
        csv.starts_with("case,file,status,bodies,stopping_time,paper_stopping_time,relative_difference,peak_tension")
    );
    // The design outputs as `run --json` gives them (added 2026-12-07, at the CSV's end).
    assert!(csv.lines().next().unwrap().ends_with(",stopping_distance,anchor_drag_distance,peak_break_utilisation"));
    let out = kanestop().arg("run").arg(&short).arg("--json").output().unwrap();
    let run: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    let a = rows.iter().find(|r| r["status"] == "end time").unwrap();
    assert_eq!(a["anchor_drag_distance"], run["anchor_drag_distance"], "{a}");
    assert_eq!(a["peak_break_utilisation"], run["peak_tension"]["break_utilisation"], "{a}");
    assert!(a["stopping_distance"].is_null() && run["stopping_distance"].is_null(), "{a}");
    let invalid = rows.iter().find(|r| r["status"] == "invalid").unwrap();
    assert!(invalid["anchor_drag_distance"].is_null() && invalid["peak_break_utilisation"].is_null(), "{invalid}");
    // A run that stops the ship after the anchor slid: case 1, against `run --json`'s numbers.
    let case1 = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes/paper/case01.toml");
    let out = kanestop().arg("batch").arg(&case1).arg("--out").arg(dir.join("case1")).output().unwrap();
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    let text = std::fs::read_to_string(dir.join("case1/batch.json")).unwrap();
    let row = &serde_json::from_str::<serde_json::Value>(&text).unwrap()[0];
    let out = kanestop().arg("run").arg(&case1).arg("--json").output().unwrap();
    let run: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    assert!(row["stopping_distance"].as_f64().is_some_and(|d| d > 26.0), "{row}");
    assert!(row["anchor_drag_distance"].as_f64().is_some_and(|d| d > 22.0), "{row}");
    for (b, r) in
        [("stopping_distance", &run["stopping_distance"]), ("anchor_drag_distance", &run["anchor_drag_distance"])]
    {
        assert_eq!(&row[b], r, "{b}");
    }
    assert_eq!(row["peak_break_utilisation"], run["peak_tension"]["break_utilisation"]);
}

/// `--methods` runs every scene with each method, side by side; `--error-estimate` adds the
/// refined runs' differences.
#[test]
fn batch_compares_methods_with_error_estimates() {
    let dir = temp_dir("methods");
    let scenes = dir.join("scenes");
    std::fs::create_dir_all(&scenes).unwrap();
    std::fs::copy(short_scene(&dir), scenes.join("a.toml")).unwrap();
    let out_dir = dir.join("out");
    let out = kanestop()
        .args(["batch"])
        .arg(&scenes)
        .args(["--methods", "rk4,dp5@0.01", "--rtol", "1e-5", "--atol", "1e-7", "--error-estimate", "--out"])
        .arg(&out_dir)
        .output()
        .unwrap();
    let stdout = String::from_utf8_lossy(&out.stdout);
    assert!(out.status.success(), "{stdout}{}", String::from_utf8_lossy(&out.stderr));
    assert!(stdout.contains("±traj m"), "{stdout}");
    let json: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(out_dir.join("batch.json")).unwrap()).unwrap();
    let rows = json.as_array().unwrap();
    let methods: Vec<&str> = rows.iter().map(|r| r["method"].as_str().unwrap()).collect();
    assert_eq!(methods, ["rk4", "dp5"]);
    // Each row says the step and the tolerances it ran at (none for RK4's fixed step).
    let setting = |r: &serde_json::Value| (r["dt"].as_f64(), r["rtol"].as_f64(), r["atol"].as_f64());
    assert_eq!(setting(&rows[0]), (Some(0.0005), None, None));
    assert_eq!(setting(&rows[1]), (Some(0.01), Some(1e-5), Some(1e-7)));
    let csv = std::fs::read_to_string(out_dir.join("batch.csv")).unwrap();
    assert!(csv.lines().next().unwrap().contains(",peak_error_estimate,dt,rtol,atol,"), "{csv}");
    assert!(csv.lines().nth(2).unwrap().contains(",0.01,0.00001,1e-7,"), "{csv}");
    for r in rows {
        // The short scene runs to its end time: a trajectory estimate, no stopping time.
        let e = r["trajectory_error_estimate"].as_f64().expect("an estimate");
        assert!(e.is_finite() && e < 1e-2, "{r}");
        assert!(r["stop_error_estimate"].is_null());
    }
    for r in rows {
        let e = r["peak_error_estimate"].as_f64().expect("a peak estimate, N");
        assert!(e.is_finite() && e < 1e-2 * r["peak_tension"].as_f64().unwrap(), "{r}");
    }
    assert!(stdout.contains("±peak kN"), "{stdout}");
    // The nearly taut cable under DP5 observed every 0.02 s: its peak, looked at after each of
    // its own steps, has the snap loads above the break load as its refined run does (before
    // 2026-12-06, looked at every 0.02 s, it missed them: 2 482 kN, ±peak 570 kN).
    let taut = dir.join("taut");
    std::fs::create_dir_all(&taut).unwrap();
    std::fs::copy(
        std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes/stress/taut_cable.toml"),
        taut.join("t.toml"),
    )
    .unwrap();
    let out = kanestop()
        .args(["batch"])
        .arg(&taut)
        .args(["--methods", "dp5@0.02", "--rtol", "1e-5", "--atol", "1e-7", "--error-estimate", "--out"])
        .arg(dir.join("taut-out"))
        .output()
        .unwrap();
    let stdout = String::from_utf8_lossy(&out.stdout);
    assert!(stdout.contains("break load exceeded") && !stdout.contains("not resolved"), "{stdout}");
    let json: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(dir.join("taut-out/batch.json")).unwrap()).unwrap();
    let (e, peak) = (json[0]["peak_error_estimate"].as_f64().unwrap(), json[0]["peak_tension"].as_f64().unwrap());
    assert!(peak > 2.52e6 && e < 0.02 * peak, "peak {peak} N, ±peak {e} N");
    // --methods owns the integrator and its step; a bad method is a clear error.
    let out = kanestop().args(["batch"]).arg(&scenes).args(["--methods", "rk4", "--dt", "0.01"]).output().unwrap();
    assert_eq!(out.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&out.stderr).contains("drop --integrator and --dt"));
    let out = kanestop().args(["batch"]).arg(&scenes).args(["--methods", "euler"]).output().unwrap();
    assert_eq!(out.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&out.stderr).contains("unknown method"));
    // One method at two steps: the method column says each row's step, and one method
    // twice at one step is refused.
    let out = kanestop()
        .args(["batch"])
        .arg(&scenes)
        .args(["--methods", "rk4@0.001,rk4@0.0005", "--out"])
        .arg(dir.join("steps-out"))
        .output()
        .unwrap();
    let stdout = String::from_utf8_lossy(&out.stdout);
    assert!(out.status.success(), "{stdout}");
    let method_column: Vec<&str> =
        stdout.lines().skip(1).take(2).map(|l| l.split_whitespace().nth(2).unwrap_or_default()).collect();
    assert_eq!(method_column, ["rk4@0.001", "rk4@0.0005"], "{stdout}");
    let out = kanestop().args(["batch"]).arg(&scenes).args(["--methods", "rk4@0.001,dp5,rk4@0.001"]).output().unwrap();
    assert_eq!(out.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&out.stderr).contains("--methods rk4@0.001: given twice"));
    // A method given twice names each entry's step (rk4 alone is the scene's own, 0.0005 s).
    let out = kanestop().args(["batch"]).arg(&scenes).args(["--methods", "rk4,rk4@0.0005"]).output().unwrap();
    assert_eq!(out.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&out.stderr)
        .contains("--methods rk4: rk4 is given more than once, so give each its step"));
}

#[test]
fn plot_writes_the_four_svg_charts() {
    let dir = temp_dir("plot");
    let scene = short_scene(&dir);
    let out_dir = dir.join("plots");
    let out = kanestop().arg("plot").arg(&scene).arg(&scene).arg("--out").arg(&out_dir).output().unwrap();
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    for name in ["ship-speed.svg", "displacement.svg", "peak-tension.svg", "energy.svg"] {
        let svg = std::fs::read_to_string(out_dir.join(name)).unwrap();
        assert!(svg.starts_with("<svg") && svg.trim_end().ends_with("</svg>"), "{name} is not a whole SVG");
        assert!(svg.contains("<polyline") || svg.contains("<path"), "{name} has no curve");
    }
    // The energy chart of one run: one title, its panel named by the run (it said it twice).
    let one = dir.join("one");
    assert!(kanestop().arg("plot").arg(&scene).arg("--out").arg(&one).output().unwrap().status.success());
    let energy = std::fs::read_to_string(one.join("energy.svg")).unwrap();
    assert!(energy.contains("\nEnergy terms\n") && !energy.contains("Energy terms, "), "the energy chart's title");
    // The limits, above the axis, are named with their members and values (Table 1's loads
    // of case 1: the chain's break load 3866 kN, the cable's 2520 kN, the chain's proof load
    // 2709 kN).
    let svg = std::fs::read_to_string(out_dir.join("peak-tension.svg")).unwrap();
    assert!(
        svg.contains("chain proof load 2709 kN") && svg.contains("break load: chain 3866, cable 2520 kN"),
        "limits named"
    );
}

#[test]
fn plot_of_a_run_refused_before_its_first_step_names_it_and_leaves_it_out() {
    // Regression: a run refused at t = 0 has no samples; plotting it beside a good run
    // indexed its first sample (exit 101, a partial set of SVGs).
    let dir = temp_dir("plot-refused");
    let scene = short_scene(&dir);
    let refused = dir.join("refused.toml");
    std::fs::write(
        &refused,
        std::fs::read_to_string(&scene)
            .unwrap()
            .replace("dt = 0.0005", "dt = 0.05")
            .replace("output_interval = 0.01", "output_interval = 0.05")
            .replace("name = \"case01\"", "name = \"refused\""),
    )
    .unwrap();
    let out_dir = dir.join("plots");
    let out = kanestop().arg("plot").arg(&refused).arg(&scene).arg("--out").arg(&out_dir).output().unwrap();
    // Refused, as `run` refuses it (exit 2, the diagnostic on standard error), and left out
    // of the charts; the good run is drawn.
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(2), "{stderr}");
    assert!(
        stderr.contains("error: ") && stderr.contains("refused.toml") && stderr.contains("stability limit"),
        "{stderr}"
    );
    assert!(stderr.contains("the run never started: not drawn"), "{stderr}");
    let svg = std::fs::read_to_string(out_dir.join("displacement.svg")).unwrap();
    assert!(svg.contains("\ncase01"), "the good run is drawn");
    assert!(!svg.contains("\nrefused") && svg.trim_end().ends_with("</svg>"));
    // Alone, nothing is drawn.
    let alone = dir.join("alone");
    let out = kanestop().arg("plot").arg(&refused).arg("--out").arg(&alone).output().unwrap();
    assert_eq!(out.status.code(), Some(2), "{}", String::from_utf8_lossy(&out.stderr));
    assert!(!alone.exists(), "no charts of a run that never started");
}

#[test]
fn batch_and_run_take_solver_overrides() {
    let dir = temp_dir("overrides");
    let scenes = dir.join("scenes");
    std::fs::create_dir_all(&scenes).unwrap();
    std::fs::copy(short_scene(&dir), scenes.join("a.toml")).unwrap();
    let out = kanestop()
        .args(["batch"])
        .arg(&scenes)
        .args(["--integrator", "dp5", "--dt", "0.01", "--rtol", "1e-5", "--atol", "1e-7", "--out"])
        .arg(dir.join("out"))
        .output()
        .unwrap();
    let stdout = String::from_utf8_lossy(&out.stdout);
    assert!(out.status.success(), "{stdout}");
    assert!(stdout.contains("end time"), "{stdout}");
    // A bad override is refused before any run (it made every scene invalid, exit 1).
    let out =
        kanestop().args(["batch"]).arg(&scenes).args(["--rtol", "0", "--out"]).arg(dir.join("out2")).output().unwrap();
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(2), "{stderr}");
    assert!(stderr.contains("--rtol = 0: must be in [1e-14, 0.1]"), "{stderr}");
    // One a scene's own fields make bad (its step, 0.5 ms, too short for 1e5 s) is that scene's.
    let out = kanestop()
        .args(["batch"])
        .arg(&scenes)
        .args(["--end-time", "1e5", "--out"])
        .arg(dir.join("out3"))
        .output()
        .unwrap();
    let stdout = String::from_utf8_lossy(&out.stdout);
    assert_eq!(out.status.code(), Some(1), "{stdout}");
    assert!(stdout.contains("invalid") && stdout.contains("solver.dt = 0.0005"), "{stdout}");
    let out =
        kanestop().args(["run"]).arg(short_scene(&dir)).args(["--integrator", "sdirk4", "--atol=-1"]).output().unwrap();
    assert_eq!(out.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&out.stderr).contains("solver.atol = -1"));
    // A flag that makes the file's own value wrong: the refusal says which flag sets that.
    let out = kanestop().args(["run", "--end-time", "1e5"]).output().unwrap();
    assert_eq!(out.status.code(), Some(2));
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(err.contains("solver.dt is the file's: --dt sets it on the command line"), "{err}");
}

/// One rule for a step given without an output interval (`run --dt`, `batch --methods
/// rk4@dt`, Python's `dt=`): the file's shorter interval is raised to the step, and `run`
/// says so; with `--output-interval` beside it, the interval is the flag's and is checked.
#[test]
fn a_step_given_raises_a_shorter_output_interval() {
    let dir = temp_dir("raise");
    let scene = short_scene(&dir);
    let out = kanestop().args(["run"]).arg(&scene).args(["--dt", "0.025", "--json"]).output().unwrap();
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(out.status.success(), "{err}");
    assert!(err.contains("note: solver.output_interval raised from the file's 0.01 s to the step, 0.025 s"), "{err}");
    let json: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    assert_eq!(json["dt"], 0.025, "{json}");
    // Two samples: at 0 and at the one step in 0.05 s, 0.025 s apart.
    let out = kanestop()
        .args(["run"])
        .arg(&scene)
        .args(["--dt", "0.025", "--out"])
        .arg(dir.join("run.csv"))
        .output()
        .unwrap();
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    let csv = std::fs::read_to_string(dir.join("run.csv")).unwrap();
    let times: Vec<&str> = csv.lines().skip(1).map(|l| l.split(',').next().unwrap()).collect();
    assert_eq!(times, ["0", "0.025", "0.05"], "{csv}");
    // A step no longer than the file's interval changes nothing, and says nothing.
    let out = kanestop().args(["run"]).arg(&scene).args(["--dt", "0.01"]).output().unwrap();
    assert!(out.status.success() && !String::from_utf8_lossy(&out.stderr).contains("raised"));
    // Given beside the step, the interval is the flag's: too short, it is refused.
    let out =
        kanestop().args(["run"]).arg(&scene).args(["--dt", "0.025", "--output-interval", "0.01"]).output().unwrap();
    assert_eq!(out.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&out.stderr).contains("solver.output_interval = 0.01: must be in [0.025"));
    // batch --dt follows the same rule (it refused the scene as invalid).
    let scenes = dir.join("scenes");
    std::fs::create_dir_all(&scenes).unwrap();
    std::fs::copy(&scene, scenes.join("a.toml")).unwrap();
    let out = kanestop()
        .args(["batch"])
        .arg(&scenes)
        .args(["--dt", "0.025", "--out"])
        .arg(dir.join("batch"))
        .output()
        .unwrap();
    let stdout = String::from_utf8_lossy(&out.stdout);
    assert!(out.status.success() && stdout.contains("end time"), "{stdout}");
}

#[test]
fn a_closed_pipe_ends_the_output_quietly() {
    // Regression: `kanestop codegen | head` panicked in println! (exit 101).
    use std::io::{BufRead, BufReader};
    let mut child = kanestop()
        .arg("codegen")
        .stdout(std::process::Stdio::piped())
        .stderr(std::process::Stdio::piped())
        .spawn()
        .unwrap();
    let mut first = String::new();
    BufReader::new(child.stdout.take().unwrap()).read_line(&mut first).unwrap();
    assert!(first.starts_with("scene"), "{first}");
    // The reader is dropped: the pipe is closed while codegen still has lines to print.
    let out = child.wait_with_output().unwrap();
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(!stderr.contains("panicked"), "{stderr}");
    assert_ne!(out.status.code(), Some(101), "{stderr}");
}

#[test]
fn run_json_is_the_documented_summary() {
    let dir = temp_dir("run-json");
    let scene = short_scene(&dir);
    let csv = dir.join("h.csv");
    let out = kanestop().arg("run").arg(&scene).arg("--json").arg("--out").arg(&csv).output().unwrap();
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    let v: serde_json::Value = serde_json::from_slice(&out.stdout).expect("stdout is one JSON object");
    for key in [
        "scene",
        "bodies",
        "method",
        "dt",
        "kernel",
        "kernel_form",
        "status",
        "stopping_time",
        "paper_stopping_time",
        "stopping_distance",
        "ship_displacement",
        "anchor_drag_distance",
        "anchor_start",
        "peak_tension",
        "chain_peak",
        "cable_peak",
        "rod_peak",
        "initial_energy",
        "work",
        "energy_drift",
        "t_end",
        "steps",
        "rhs_evaluations",
        "wall_time",
        "failure",
    ] {
        assert!(v.get(key).is_some(), "missing key {key}");
    }
    assert_eq!(v["bodies"], 46);
    // The fused right-hand side of case 1's signature runs on the rolled steps.
    assert_eq!((&v["kernel"], &v["kernel_form"]), (&"generated".into(), &"rolled".into()));
    assert_eq!(v["method"], "rk4");
    assert_eq!(v["status"], "end time");
    assert!(v["failure"].is_null() && v["stopping_distance"].is_null());
    assert!(v["work"]["friction"].as_f64().is_some());
    assert!(v["ship_displacement"].as_f64().unwrap() > 0.1, "the ship moves at 3 m/s for 0.05 s");
    let rod = &v["rod_peak"];
    assert_eq!(rod["joint"], 46);
    assert!(rod["break_utilisation"].as_f64().unwrap() > 0.0 && rod["proof_utilisation"].is_null());
    // The note on the CSV goes to standard error, keeping standard output pure JSON.
    assert!(String::from_utf8_lossy(&out.stderr).contains("written"));
    assert!(csv.exists());

    // A numerical failure: status and the worded diagnostic.
    let refused = dir.join("refused.toml");
    let text = std::fs::read_to_string(&scene).unwrap().replace("dt = 0.0005", "dt = 0.05");
    std::fs::write(&refused, text.replace("output_interval = 0.01", "output_interval = 0.05")).unwrap();
    let out = kanestop().arg("run").arg(&refused).arg("--json").output().unwrap();
    assert_eq!(out.status.code(), Some(2), "a step refused before the run is bad input");
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(stderr.contains("error: refused before the run: solver.dt = 0.05 s") && stderr.contains("stability limit"));
    assert!(!stderr.contains("numerical failure"), "a refusal is not a failure of the integration: {stderr}");
    let text = kanestop().arg("run").arg(&refused).output().unwrap();
    assert!(String::from_utf8_lossy(&text.stdout).contains("REFUSED   refused before the run"), "the summary's label");
    let v: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    assert_eq!(v["status"], "failed");
    assert!(v["failure"]["message"].as_str().unwrap().contains("stability limit"), "{}", v["failure"]);
    assert!(v["peak_tension"].is_null(), "a refused run has no peak");
    // The run ends at the last whole step at or before the end time (it went past: 0.502 s).
    let out = kanestop().args(["run", "--end-time", "0.501", "--json"]).output().unwrap();
    let v: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    assert_eq!((v["t_end"].as_f64(), v["steps"].as_u64()), (Some(0.5), Some(250)), "{v}");
}

#[test]
fn run_selects_channels_and_overrides_end_time_and_output_interval() {
    let dir = temp_dir("channels");
    let scene = short_scene(&dir);
    let csv = dir.join("sel.csv");
    let out = kanestop()
        .arg("run")
        .arg(&scene)
        .args(["--channels", "tension_fairlead,ship", "--end-time", "0.02", "--output-interval", "0.005", "--out"])
        .arg(&csv)
        .output()
        .unwrap();
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    let text = std::fs::read_to_string(&csv).unwrap();
    let header = text.lines().next().unwrap();
    assert_eq!(header, "t,ship_x,ship_z,ship_theta,ship_vx,ship_vz,ship_omega,ship_displacement,tension_fairlead");
    assert_eq!(text.lines().count(), 1 + 5, "samples at 0, 0.005, …, 0.02 s");
    // An unknown channel is bad input, found before the run; nothing is written.
    let bad = dir.join("bad.csv");
    let out = kanestop().arg("run").arg(&scene).args(["--channels", "x_46", "--out"]).arg(&bad).output().unwrap();
    assert_eq!(out.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&out.stderr).contains("unknown channel \"x_46\""));
    assert!(out.stdout.is_empty() && !bad.exists());
    let out = kanestop().arg("run").arg(&scene).args(["--end-time=-1"]).output().unwrap();
    assert_eq!(out.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&out.stderr).contains("solver.end_time"));
}

#[test]
fn a_variant_of_a_paper_case_is_not_compared_with_the_paper() {
    let dir = temp_dir("variant");
    let heavier = dir.join("heavier.toml");
    std::fs::write(&heavier, kanestop_runtime::paper::DEFAULT_SCENE.replace("mass = 500000.0", "mass = 600000.0"))
        .unwrap();
    let out = kanestop().arg("run").arg(&heavier).output().unwrap();
    let stdout = String::from_utf8_lossy(&out.stdout);
    assert!(out.status.success(), "{stdout}");
    assert!(!stdout.contains("paper (Table 3)"), "a 600 t ship is not case 1: {stdout}");
    // Another solver on the same physics still is case 1.
    let out = kanestop().args(["run", "--dt", "0.001"]).output().unwrap();
    assert!(String::from_utf8_lossy(&out.stdout).contains("paper (Table 3): 20.010 s"));
}

/// A chain of 20 links (N = 51) and 500 m of cable in 1 m elements (N = 518): no build has
/// an unrolled kernel for either, and both run on generated code, the rolled kernel, with no
/// reference fallback.
#[test]
fn any_element_count_runs_on_the_rolled_kernel() {
    let dir = temp_dir("rolled");
    let base = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes/paper/case01.toml");
    let base = format!("{:?}", base.display().to_string());
    for (name, extra, bodies) in [
        ("chain20", "[chain]\nelements = 20\n", 51),
        (
            "line500",
            "[[cable.stages]]\nelements = 500\nelement_length = 1.0\n[initial]\nhorizontal_projection = 497.0\n",
            518,
        ),
    ] {
        let path = dir.join(format!("{name}.toml"));
        let text = format!(
            "extends = {base}\n[meta]\nname = \"{name}\"\ndescription = \"any N\"\n[solver]\nend_time = 0.2\n{extra}"
        );
        std::fs::write(&path, text).unwrap();
        let out = kanestop().arg("run").arg(&path).arg("--json").output().unwrap();
        let stderr = String::from_utf8_lossy(&out.stderr);
        assert!(out.status.success(), "{name}: {stderr}");
        assert!(!stderr.contains("reference"), "{name}: no fallback note: {stderr}");
        let v: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
        assert_eq!(v["bodies"], bodies);
        assert_eq!((&v["kernel"], &v["kernel_form"]), (&"generated".into(), &"rolled".into()), "{name}");
        assert_eq!(v["status"], "end time", "{name}");
        assert!(v["energy_drift"].as_f64().unwrap() < 1e-4, "{name}: {}", v["energy_drift"]);
    }
}

/// Where case 1's kinetic energy went, split by force: the parts sum to the lumped
/// `friction` and `drag` of before the split, the anchor's friction and drag, the line's
/// drag and the hull's resistance all dissipate, the smooth line no friction; the balance
/// still holds and the text summary names the parts.
#[test]
fn run_json_splits_the_work_by_force() {
    let out = kanestop().args(["run", "scenes/paper/case01.toml", "--json"]).output().unwrap();
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    let v: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    let w = |k: &str| v["work"][k].as_f64().unwrap_or_else(|| panic!("work.{k}"));
    let close = |a: f64, b: f64| (a - b).abs() <= 1e-9 * a.abs().max(b.abs()).max(1.0);
    assert!(close(w("friction"), w("anchor_friction") + w("line_friction")));
    assert!(close(w("drag"), w("anchor_drag") + w("line_drag") + w("hull_resistance")));
    for k in ["anchor_friction", "anchor_drag", "line_drag", "hull_resistance"] {
        assert!(w(k) < -1e4, "{k} = {} J: case 1 dissipates there", w(k));
    }
    assert_eq!(w("line_friction"), 0.0, "case 1's line slides without friction");
    // The drift is relative to the largest kinetic energy: the ship's at t = 0 in case 1,
    // not E_0 (32.2 MJ, mostly the ship's weight above the seabed).
    assert!(v["energy_drift"].as_f64().unwrap() < 1e-6);
    assert_eq!(v["energy_scale"], v["initial_kinetic_energy"]);
    assert!(v["initial_energy"].as_f64().unwrap() > 10.0 * v["energy_scale"].as_f64().unwrap());
    let cpu = v["cpu_time"].as_f64().expect("cpu_time, s");
    assert!(cpu > 0.0 && cpu <= v["wall_time"].as_f64().unwrap() * 1.05 + 0.01, "cpu {cpu} s");

    let text = kanestop().args(["run", "scenes/paper/case01.toml"]).output().unwrap();
    let text = String::from_utf8_lossy(&text.stdout);
    let energy = text.lines().find(|l| l.starts_with("energy")).expect("energy line");
    for part in [
        "anchor friction",
        "anchor water drag",
        "line drag",
        "hull resistance",
        "drift",
        "of the kinetic energy at t = 0",
    ] {
        assert!(energy.contains(part), "{energy}");
    }
    // Every share named, those that gave energy back with their sign: they add up to 100 %
    // (each rounded to 0.1 %, shares below 0.05 % left out), as in case 2, whose ship's
    // hydrostatics give back about 2 %.
    for case in ["scenes/paper/case01.toml", "scenes/paper/case02.toml"] {
        let text = kanestop().args(["run", case]).output().unwrap();
        let text = String::from_utf8_lossy(&text.stdout);
        let energy = text.lines().find(|l| l.starts_with("energy")).expect("energy line");
        let shares = energy.split(": ").nth(1).unwrap().split(';').next().unwrap();
        let sum: f64 = shares.split(", ").map(|p| p.split(" %").next().unwrap().parse::<f64>().unwrap()).sum();
        assert!((sum - 100.0).abs() <= 0.6, "{case}: {sum} % in {energy}");
    }
}

/// `codegen --scene`: the signature, the kernel chosen and the operation counts with the
/// parameters kept and folded; a chain no build has gets the rolled kernel.
#[test]
fn codegen_reports_the_scene_kernel_and_what_folding_saves() {
    let out = kanestop().args(["codegen", "--scene", "scenes/paper/case01.toml"]).output().unwrap();
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    let text = String::from_utf8(out.stdout).unwrap();
    assert!(text.contains("kernel     rhs_free_wet_seabed, rhs_stuck_wet_seabed: the fused right-hand side"), "{text}");
    let root = std::path::Path::new(env!("CARGO_MANIFEST_DIR"));
    let lines = std::fs::read_to_string(root.join("generated/src/chain46_wet.rs")).unwrap().lines().count();
    assert!(text.contains(&format!("chain46_wet.rs: {lines} lines (the unrolled expansion for this N)")), "{text}");
    assert!(text.contains("15 chain links, 28 cable elements in 3 stages"), "{text}");
    assert!(text.contains("signature  wet_seabed (weight, seabed, buoyancy, line_drag"), "{text}");
    assert!(text.contains("left out   line_friction, current"), "{text}");
    assert!(text.contains("folded: folded_case01"), "{text}");
    assert!(text.contains("folded_case01 has this scene's numbers folded in"), "{text}");
    let solve = text.lines().find(|l| l.trim_start().starts_with("solve_free")).expect("solve_free row");
    let cols: Vec<&str> = solve.split_whitespace().collect();
    let (kept, folded): (usize, usize) = (cols[1].parse().unwrap(), cols[2].parse().unwrap());
    assert!(folded < kept, "{solve}");
    let dir = temp_dir("codegen-rolled");
    let scene = dir.join("chain20.toml");
    let base = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes/paper/case01.toml");
    std::fs::write(&scene, format!("extends = {:?}\n[chain]\nelements = 20\n", base.display().to_string())).unwrap();
    let out = kanestop().arg("codegen").arg(&scene).output().unwrap();
    let text = String::from_utf8(out.stdout).unwrap();
    assert!(text.contains("the fused right-hand side on the steps of rolled_wet (any N)"), "{text}");
}

/// `codegen --fold DIR` writes the scene's folded kernel and says how to build it in; a folder that cannot be one is refused before any work, and nothing is written.
#[test]
fn codegen_fold_writes_the_scene_s_folded_kernel() {
    let dir = temp_dir("codegen-fold");
    let out = kanestop().args(["codegen", "--scene", "scenes/paper/case01.toml", "--fold"]).arg(&dir).output().unwrap();
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    let text = String::from_utf8(out.stdout).unwrap();
    let path = dir.join("folded_case01.rs");
    assert!(text.contains(&format!("written    {}", path.display())), "{text}");
    assert!(text.contains("KANESTOP_FOLDED_KERNELS="), "{text}");
    // Its text against the checked-in file: tests/generated_fresh.rs.
    let written = std::fs::read_to_string(&path).unwrap();
    assert!(!written.contains("p[") && written.contains("pub const PARAMS"), "parameters folded, listed once");

    // Folding it again is fine; another scene's kernel under the name is not overwritten.
    let again = kanestop().args(["codegen", "scenes/paper/case01.toml", "--fold"]).arg(&dir).output().unwrap();
    assert!(again.status.success(), "{}", String::from_utf8_lossy(&again.stderr));
    let other = dir.join("elsewhere");
    std::fs::create_dir_all(&other).unwrap();
    let scene = other.join("case01.toml");
    // Case 8's chain has N = 48: other numbers under the name folded_case01.
    let base = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes/paper/case08.toml");
    std::fs::write(&scene, format!("extends = {:?}\n", base.display().to_string())).unwrap();
    let out = kanestop().arg("codegen").arg(&scene).arg("--fold").arg(&dir).output().unwrap();
    assert_eq!(out.status.code(), Some(2), "{}", String::from_utf8_lossy(&out.stderr));
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(err.contains("holds another kernel"), "{err}");
    assert_eq!(std::fs::read_to_string(&path).unwrap(), written, "left as it was");

    let file = dir.join("a-file");
    std::fs::write(&file, "").unwrap();
    let out = kanestop().args(["codegen", "--fold"]).arg(&file).output().unwrap();
    assert_eq!(out.status.code(), Some(2), "bad input");
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(err.contains("--fold: cannot write into") && err.contains("a-file"), "{err}");
    assert!(!out.stdout.starts_with(b"scene"), "refused before any work");
    let mut names: Vec<String> =
        std::fs::read_dir(&dir).unwrap().flatten().map(|e| e.file_name().to_string_lossy().into_owned()).collect();
    names.sort();
    assert_eq!(names, ["a-file", "elsewhere", "folded_case01.rs"], "nothing else written");

    // --write outside a checkout: refused before the report (it used to print it all first).
    let out = kanestop().args(["codegen", "--write", "--root"]).arg(&dir).output().unwrap();
    assert_eq!(out.status.code(), Some(2), "bad input");
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(err.contains("generated/src is not a directory: pass --root <repository>"), "{err}");
    assert!(out.stdout.is_empty(), "refused before any work: {}", String::from_utf8_lossy(&out.stdout));
}

/// `codegen` says how a scene's loads run: a chain in vacuum (water and seabed off) with its
/// weights inside the generated solve, case 1 on the generated load code of its signature,
/// with each term's operations and nothing of the terms it leaves out.
#[test]
fn codegen_says_when_the_loads_are_fused() {
    let dir = temp_dir("codegen-fused");
    let path = dir.join("vacuum.toml");
    let text = kanestop_runtime::paper::DEFAULT_SCENE
        .replace("water = true", "water = false")
        .replace("seabed = true", "seabed = false");
    std::fs::write(&path, text).unwrap();
    let out = kanestop().arg("codegen").arg(&path).output().unwrap();
    let text = String::from_utf8(out.stdout).unwrap();
    assert!(text.contains("signature  dry (weight)"), "{text}");
    assert!(text.contains("loads      weight alone, in the generated solve's own steps"), "{text}");
    assert!(
        text.contains("kernel     rhs_free_dry, rhs_stuck_dry: the fused right-hand side on the steps of rolled_dry"),
        "{text}"
    );
    let out = kanestop().args(["codegen", "scenes/paper/case01.toml"]).output().unwrap();
    let text = String::from_utf8(out.stdout).unwrap();
    assert!(text.contains("loads      generated in the solve's inward pass, line elements two at a time"), "{text}");
    assert!(text.contains("kernel     rhs_free_wet_seabed, rhs_stuck_wet_seabed"), "{text}");
    let row = |term: &str| text.lines().find(|l| l.split_whitespace().next() == Some(term)).map(str::to_string);
    let share = |t: &str| {
        let r = row(t).unwrap_or_else(|| panic!("no {t} row: {text}"));
        r.split_whitespace().nth(2).unwrap().trim_end_matches('%').parse::<f64>().unwrap()
    };
    let terms = ["weight", "seabed", "buoyancy", "line_drag", "anchor_drag", "hydrostatics", "hull_resistance"];
    // The table accounts for every operation: the terms and what they share.
    let shares: f64 = terms.iter().chain(&["shared"]).map(|t| share(t)).sum();
    assert!((shares - 100.0).abs() < 0.5, "the shares sum to {shares}: {text}");
    // docs/codegen.md: Morison drag is the largest term of case 1's load code.
    assert!(terms.iter().all(|t| share(t) <= share("line_drag")), "{text}");
    assert!(row("line_friction").is_none() && row("current").is_none(), "{text}");
}

/// A ship at rest at the start: `run` says so, and `--json` gives a stop at 0 s after 0 m
/// with the starting state's peak tension.
#[test]
fn run_of_a_ship_at_rest_says_it_stopped_at_the_start() {
    let dir = temp_dir("at-rest");
    let path = dir.join("at_rest.toml");
    let text = kanestop_runtime::paper::DEFAULT_SCENE.replace("ship_speed = 3.0", "ship_speed = 0.0");
    assert_ne!(text, kanestop_runtime::paper::DEFAULT_SCENE);
    std::fs::write(&path, text).unwrap();
    let out = kanestop().arg("run").arg(&path).output().unwrap();
    let stdout = String::from_utf8_lossy(&out.stdout);
    assert!(out.status.success(), "{stdout}\n{}", String::from_utf8_lossy(&out.stderr));
    assert!(stdout.contains("stopped   t = 0 s: the ship was at rest at the start"), "{stdout}");
    assert!(stdout.contains("tension"), "the start's peak is shown: {stdout}");
    let out = kanestop().arg("run").arg(&path).arg("--json").output().unwrap();
    let json: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    assert_eq!(json["status"], "stopped");
    assert_eq!((json["stopping_time"].as_f64(), json["stopping_distance"].as_f64()), (Some(0.0), Some(0.0)));
    assert_eq!(json["peak_tension"]["t"].as_f64(), Some(0.0), "{json}");
}

/// A run refused before its first step has no E_0, drift or work: `run --json` gives them as
/// null, every work name present (it gave 0 and an empty `work`), and no `checks_pass`.
#[test]
fn run_json_of_a_refused_run_has_nulls_where_nothing_was_measured() {
    let scene = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes/stress/dt_too_large.toml");
    let out = kanestop().arg("run").arg(&scene).arg("--json").output().unwrap();
    assert_eq!(out.status.code(), Some(2), "{}", String::from_utf8_lossy(&out.stderr));
    let v: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    assert_eq!(v["status"], "failed");
    for field in ["initial_energy", "energy_drift", "energy_scale"] {
        assert!(v[field].is_null(), "{field}: {}", v[field]);
    }
    let work = v["work"].as_object().unwrap();
    assert_eq!(work.len(), 11, "{work:?}");
    assert!(work.values().all(serde_json::Value::is_null), "{work:?}");
    assert_eq!(v["initial_kinetic_energy"], 0.0, "documented as 0 for a run that never started");
    // No check was made: not even the break loads' (a run that took a step has that one).
    assert!(v.get("checks_pass").is_none(), "{v}");
}

/// A peak at the engagement (the first 0.5 s of a ship under way) is said to be one, with the
/// largest tension sampled after; case 1's peak, at 1.5 s, is not.
#[test]
fn a_peak_at_the_engagement_is_said_to_be_one() {
    let dir = temp_dir("early-peak");
    let case1 = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes/paper/case01.toml");
    let deep = dir.join("deep.toml");
    let text = format!(
        "extends = {:?}\n[ship]\nmass = 1.5e6\n[chain]\nelements = 30\n[initial]\nvertical_projection = 20.0\n\
         [solver]\nend_time = 1.0\n",
        case1.display().to_string()
    );
    std::fs::write(&deep, text).unwrap();
    let out = kanestop().arg("run").arg(&deep).output().unwrap();
    let stdout = String::from_utf8_lossy(&out.stdout);
    assert!(out.status.success(), "{stdout}");
    let at = stdout.find("peak 282.9 kN at joint 61 (auxiliary rod – ship) at t = 0.154 s").expect(&stdout);
    let note = stdout[at..].lines().nth(1).unwrap();
    assert!(note.trim_start().starts_with("at the engagement: the model starts the ship at 3 m/s"), "{stdout}");
    assert!(note.contains("after 0.5 s the largest sampled tension is 180.8 kN at joint 61 at t = 0.800 s"), "{note}");
    let json = |scene: &std::path::Path| -> serde_json::Value {
        let out = kanestop().arg("run").arg(scene).args(["--json", "--end-time", "2"]).output().unwrap();
        serde_json::from_slice(&out.stdout).unwrap()
    };
    assert_eq!(json(&deep)["early_peak"], true);
    assert_eq!(json(&case1)["early_peak"], false);
    let out = kanestop().arg("run").arg(&case1).output().unwrap();
    assert!(!String::from_utf8_lossy(&out.stdout).contains("engagement"));
}

/// `batch` takes scene files as well as folders; a missing path, an empty folder and a scene
/// given twice are refused naming it (exit 2), before any run.
#[test]
fn batch_takes_files_and_folders() {
    let dir = temp_dir("batch-files");
    let scenes = dir.join("scenes");
    std::fs::create_dir_all(&scenes).unwrap();
    let short = short_scene(&dir);
    std::fs::copy(&short, scenes.join("a.toml")).unwrap();
    let out = kanestop().arg("batch").arg(&short).arg(&scenes).arg("--out").arg(dir.join("out")).output().unwrap();
    let stdout = String::from_utf8_lossy(&out.stdout);
    assert!(out.status.success(), "{stdout}{}", String::from_utf8_lossy(&out.stderr));
    let csv = std::fs::read_to_string(dir.join("out/batch.csv")).unwrap();
    assert_eq!(csv.lines().count(), 3, "a file and a folder of one: two rows\n{csv}");
    let empty = dir.join("empty");
    std::fs::create_dir_all(&empty).unwrap();
    for (args, says) in [
        (vec![dir.join("nope.toml")], "no such file or folder"),
        (vec![empty.clone()], "a folder without a *.toml scene"),
        (vec![scenes.join("a.toml"), scenes.clone()], "given twice"),
    ] {
        let out = kanestop().arg("batch").args(&args).arg("--out").arg(dir.join("refused")).output().unwrap();
        let stderr = String::from_utf8_lossy(&out.stderr);
        assert_eq!(out.status.code(), Some(2), "{stderr}");
        assert!(stderr.contains("SCENES = ") && stderr.contains(says), "{stderr}");
        assert!(!dir.join("refused").exists(), "nothing written");
    }
}

//! `kanestop sweep` and `report sensitivity`: rows in spec order with their inputs, a row
//! equal to its scene run alone, Latin-hypercube strata, design checks and exit codes.

mod scratch;
use scratch::Scratch;

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

use kanestop_workflow::sweep::sampling::Distribution;
use serde_json::Value;

fn kanestop() -> Command {
    Command::new(env!("CARGO_BIN_EXE_kanestop"))
}

fn root() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
}

/// The test's scratch folder, removed when it passes (tests/scratch).
fn temp_dir(name: &str) -> Scratch {
    Scratch::new(&format!("sweep-{name}"))
}

/// A spec in `dir` over the paper's case 1.
fn spec(dir: &Path, body: &str) -> PathBuf {
    let base = root().join("scenes/paper/case01.toml");
    let path = dir.join("spec.toml");
    std::fs::write(&path, format!("base = {:?}\n{body}", base.display().to_string())).unwrap();
    path
}

fn sweep(spec: &Path, out: &Path) -> Output {
    kanestop().args(["sweep", spec.to_str().unwrap(), "--out", out.to_str().unwrap()]).output().unwrap()
}

fn rows(out: &Path) -> Vec<Value> {
    let text = std::fs::read_to_string(out.join("sweep.json")).unwrap();
    serde_json::from_str::<Value>(&text).unwrap().as_array().unwrap().clone()
}

#[test]
fn a_3x3_grid_runs_in_spec_order_with_inputs_as_columns_and_checks() {
    let dir = temp_dir("grid");
    let out = dir.join("out");
    let o = sweep(&root().join("scenes/sweeps/mass_speed.toml"), &out);
    let code = o.status.code();
    assert!(code == Some(0) || code == Some(4), "{code:?} {}", String::from_utf8_lossy(&o.stderr));
    let rows = rows(&out);
    assert_eq!(rows.len(), 9);
    let mut expected = Vec::new();
    for m in [5e5, 7.5e5, 1e6] {
        for v in [2.0, 3.0, 4.0] {
            expected.push((m, v));
        }
    }
    for (i, (r, (m, v))) in rows.iter().zip(&expected).enumerate() {
        assert_eq!(r["index"], i);
        assert_eq!(r["name"], format!("mass_speed-{i:03}"));
        assert_eq!(r["inputs"]["ship.mass"].as_f64(), Some(*m));
        assert_eq!(r["inputs"]["initial.ship_speed"].as_f64(), Some(*v));
        assert_eq!(r["status"], "stopped", "{r}");
        assert!(r["checks_pass"].is_boolean());
        let checks = r["summary"]["checks"].as_array().unwrap();
        let names: Vec<&str> = checks.iter().map(|c| c["name"].as_str().unwrap()).collect();
        assert_eq!(names, ["max_stopping_distance", "max_anchor_drag", "safety_factor"]);
        // The safety factor's record holds utilisation × factor against 1, and the factor
        // achieved, break load over peak tension, which passes when at least the factor set.
        let (sf, required) = (&checks[2], 1.5);
        let (value, achieved) = (sf["value"].as_f64().unwrap(), sf["achieved"].as_f64().unwrap());
        assert!((achieved * value - required).abs() < 1e-12 && (achieved >= required) == sf["pass"], "{sf}");
        assert!(checks[0].get("achieved").is_none(), "the other checks have none: {}", checks[0]);
        // Only the rows that are paper cases are compared with Table 3: the base (case 1), its
        // ship at 4 m/s (case 14), of 750 t (case 16) and of 1000 t (case 17).
        let paper = r["summary"]["paper_stopping_time"].as_f64();
        let table3 = [(1, 20.01), (2, 23.654), (4, 29.134), (7, 38.242)];
        assert_eq!(paper, table3.iter().find(|c| c.0 == i).map(|c| c.1), "row {i}");
    }
    // docs/sweeps.md quotes how many of the rows fail a check.
    let failing = rows.iter().filter(|r| r["checks_pass"] == false).count();
    let doc = std::fs::read_to_string(root().join("docs/sweeps.md"))
        .unwrap()
        .split_whitespace()
        .collect::<Vec<_>>()
        .join(" ");
    let quoted = format!("{failing} of the {} rows fail", rows.len());
    assert!(doc.contains(&quoted), "docs/sweeps.md should say of scenes/sweeps/mass_speed.toml: {quoted}");
    // A row that fails a check says which in its message, as `batch` does; one that passes is silent.
    for r in &rows {
        let message = r["message"].as_str().unwrap();
        if r["checks_pass"] == false {
            assert!(message.starts_with("check failed: ") && message.contains("(FAIL)"), "{r}");
        } else {
            assert_eq!(message, "", "{r}");
        }
    }
    // Heavier and faster ships take longer to stop.
    let t = |i: usize| rows[i]["summary"]["stopping_time"].as_f64().unwrap();
    assert!(t(0) < t(3) && t(3) < t(6), "mass");
    let csv = std::fs::read_to_string(out.join("sweep.csv")).unwrap();
    let head: Vec<&str> = csv.lines().next().unwrap().split(',').collect();
    assert_eq!(&head[..6], ["index", "name", "ship.mass", "initial.ship_speed", "status", "checks"]);
    for col in [
        "stopping_distance",
        "anchor_drag_distance",
        "chain_peak_break_utilisation",
        "check_safety_factor_achieved",
        "check_safety_factor_pass",
        "work_friction",
        "work_anchor_friction",
        "work_line_friction",
        "dissipated_anchor_drag",
        "dissipated_line_drag",
        "dissipated_hull_resistance",
        "cpu_time",
    ] {
        assert!(head.contains(&col), "{col} in {head:?}");
    }
    // Beside it, every column's unit and meaning, in the CSV's order (none left undescribed).
    let units = std::fs::read_to_string(out.join("sweep.units.csv")).unwrap();
    let lines: Vec<Vec<&str>> = units.lines().skip(1).map(|l| l.splitn(3, ',').collect()).collect();
    assert_eq!(lines.iter().map(|l| l[0]).collect::<Vec<_>>(), head);
    assert!(lines.iter().all(|l| l[2].len() > 2), "{units}");
    let unit = |c: &str| lines.iter().find(|l| l[0] == c).map(|l| l[1]);
    assert_eq!(
        ["ship.mass", "initial.ship_speed", "chain_peak_tension", "work_friction", "check_max_stopping_distance_value"]
            .map(unit),
        [Some("kg"), Some("m/s"), Some("N"), Some("J"), Some("m")]
    );
    // The energy split: the parts sum to the lumped terms in every row.
    for r in &rows {
        let split = &r["energy_split"];
        let f = |k: &str| split[k].as_f64().unwrap_or_else(|| panic!("energy_split.{k}"));
        assert!((f("friction") - f("anchor_friction") - f("line_friction")).abs() < 1e-12);
        assert!((f("drag") - f("anchor_drag") - f("line_drag") - f("hull_resistance")).abs() < 1e-12);
        assert!(f("anchor_friction") > 0.0 && f("hull_resistance") > 0.0 && f("line_friction") == 0.0, "{split}");
        // Shares of the initial kinetic energy, as run's energy line: most of it goes to friction.
        let k0 = r["summary"]["initial_kinetic_energy"].as_f64().unwrap();
        let work = r["summary"]["work"]["anchor_friction"].as_f64().unwrap();
        assert_eq!(f("anchor_friction"), -work / k0);
        assert!(f("friction") > 0.3 && f("friction") < 1.0, "{split}");
    }
    // Two numeric grid axes: the default heat maps beside the CSV.
    for name in ["stopping_distance", "stopping_time", "peak_utilisation"] {
        let svg = std::fs::read_to_string(out.join(format!("heatmap-{name}.svg"))).unwrap();
        assert!(svg.starts_with("<svg") && svg.contains("ship.mass"), "{name}");
    }
    #[cfg(feature = "parquet")]
    {
        // sweep.parquet: a Parquet file (magic at both ends) naming the CSV's columns.
        let bytes = std::fs::read(out.join("sweep.parquet")).unwrap();
        assert!(bytes.starts_with(b"PAR1") && bytes.ends_with(b"PAR1"));
        let text = String::from_utf8_lossy(&bytes);
        assert!(head.iter().all(|h| text.contains(h)), "every column in the footer");
    }
    assert_eq!(csv.lines().count(), 10);
    assert_eq!(o.status.code() == Some(4), rows.iter().any(|r| r["checks_pass"] == false));
}

#[test]
fn a_line_length_and_depth_sweep_lays_every_row_by_its_tension() {
    let dir = temp_dir("line-depth");
    let spec_path = root().join("scenes/sweeps/line_depth.toml");
    let o = sweep(&spec_path, &dir.join("tension"));
    assert_eq!(o.status.code(), Some(0), "{}", String::from_utf8_lossy(&o.stderr));
    let by_tension = rows(&dir.join("tension"));
    assert_eq!(by_tension.len(), 12);
    for r in &by_tension {
        assert_eq!(r["status"], "stopped", "{r}");
        // Each row's scene lays its line by T_h, x_L left out.
        let scene = std::fs::read_to_string(dir.join(format!("tension/scenes/{}.toml", r["name"].as_str().unwrap())))
            .unwrap()
            .parse::<toml::Table>()
            .unwrap();
        assert_eq!(scene["initial"].get("horizontal_tension"), Some(&toml::Value::Float(150.0)));
        assert_eq!(scene["initial"].get("horizontal_projection"), None);
        // The laid line in the row's summary: T_h as set, x_L and the depth as laid.
        let s = &r["summary"];
        let (lc, h) = (
            3.0 * 2.0 + 12.0 * r["inputs"]["cable.stages[1].element_length"].as_f64().unwrap() + 13.0 * 2.0,
            r["inputs"]["initial.vertical_projection"].as_f64().unwrap(),
        );
        let (x, t, d) = (
            s["initial_horizontal_projection"].as_f64().unwrap(),
            s["initial_horizontal_tension"].as_f64().unwrap(),
            s["water_depth"].as_f64().unwrap(),
        );
        assert!((t - 150.0).abs() < 1e-9 * 150.0, "T_h {t}");
        // T_t = T_h + w_c h_L, the cable's weight in water (docs/model-choices.md).
        let w = (13.852119244119578 - 1025.0 * std::f64::consts::PI * 0.0237f64.powi(2)) * 9.81;
        let top = s["initial_top_tension"].as_f64().unwrap();
        assert!((top - (t + w * h)).abs() < 1e-9 * top, "T_t {top} for T_h {t}, h_L {h}");
        assert!(x > lc - h && x < lc, "x_L {x} for L_c {lc}, h_L {h}");
        assert!(d > h && d < h + 0.05, "depth {d} for h_L {h}");
    }
    // The same study at case 1's x_L (the spec without its [set]): docs/sweeps.md quotes how
    // many rows are refused.
    let text = std::fs::read_to_string(&spec_path).unwrap();
    let without_set: String = text
        .replace(
            "\"../paper/case01.toml\"",
            &format!("{:?}", root().join("scenes/paper/case01.toml").display().to_string()),
        )
        .lines()
        .filter(|l| !l.starts_with("[set]") && !l.starts_with("\"initial.horizontal_tension\""))
        .map(|l| format!("{l}\n"))
        .collect();
    let fixed_spec = dir.join("fixed.toml");
    std::fs::write(&fixed_spec, without_set).unwrap();
    let o = sweep(&fixed_spec, &dir.join("fixed"));
    // Exit 3: rows were invalid (docs/sweeps.md, exit codes).
    assert_eq!(o.status.code(), Some(3), "{}", String::from_utf8_lossy(&o.stderr));
    let refused = rows(&dir.join("fixed")).iter().filter(|r| r["status"] == "invalid").count();
    assert!(refused > 0);
    // The summary names them, as it names the rows failing a check.
    let line = format!("runs      0 failed and {refused} invalid of 12 rows");
    assert!(String::from_utf8_lossy(&o.stdout).contains(&line), "{line:?}");
    let doc = std::fs::read_to_string(root().join("docs/sweeps.md"))
        .unwrap()
        .split_whitespace()
        .collect::<Vec<_>>()
        .join(" ");
    let quoted = format!("{refused} of the 12 are refused");
    assert!(doc.contains(&quoted), "docs/sweeps.md should say of scenes/sweeps/line_depth.toml: {quoted}");
}

#[test]
fn a_sweep_row_equals_its_scene_run_alone() {
    let dir = temp_dir("alone");
    let out = dir.join("out");
    let body = "[solver]\nend_time = 8.0\n[[axis]]\npath = \"anchor.mass\"\nvalues = [30000.0, 50000.0]\n\
                [checks]\nmax_anchor_drag = 100.0\n";
    let o = sweep(&spec(&dir, body), &out);
    assert!(o.status.code().is_some_and(|c| c == 0 || c == 4), "{}", String::from_utf8_lossy(&o.stderr));
    let rows = rows(&out);
    assert_eq!(rows.len(), 2);
    for r in &rows {
        let scene = out.join("scenes").join(format!("{}.toml", r["name"].as_str().unwrap()));
        let alone = kanestop().args(["run", scene.to_str().unwrap(), "--json"]).output().unwrap();
        let mut alone: Value = serde_json::from_slice(&alone.stdout).unwrap();
        let mut row = r["summary"].clone();
        for v in [&mut alone, &mut row] {
            v.as_object_mut().unwrap().remove("wall_time");
            v.as_object_mut().unwrap().remove("cpu_time");
        }
        assert_eq!(row, alone, "every number but the wall and CPU times, exactly");
        assert!(row["checks_pass"].is_boolean());
    }
}

#[test]
fn two_hundred_latin_hypercube_samples_fall_one_per_stratum() {
    let dir = temp_dir("lhs");
    let out = dir.join("out");
    // The machinery only: each run cut to 0.1 s (the full-length command: docs/sweeps.md).
    let text = std::fs::read_to_string(root().join("scenes/sweeps/uncertain_lhs.toml")).unwrap();
    let body = text.replace("base = \"../paper/case01.toml\"", "[solver]\nend_time = 0.1\n");
    let o = sweep(&spec(&dir, &body), &out);
    // The runs end before the ship stops: the stopping-distance check fails (exit 4).
    assert_eq!(o.status.code(), Some(4), "{}", String::from_utf8_lossy(&o.stderr));
    let rows = rows(&out);
    assert_eq!(rows.len(), 200);
    let dists = [
        ("environment.seabed_friction", Distribution::Lognormal { median: 0.3, sigma: 0.2 }),
        ("ship.mass", Distribution::Normal { mean: 5e5, sd: 2.5e4 }),
        ("anchor.mass", Distribution::Uniform { low: 36000.0, high: 44000.0 }),
        ("hydrodynamics.anchor_drag_coefficient", Distribution::Lognormal { median: 1.05, sigma: 0.15 }),
    ];
    for (path, d) in dists {
        let mut x: Vec<f64> = rows.iter().map(|r| r["inputs"][path].as_f64().unwrap()).collect();
        x.sort_by(f64::total_cmp);
        for (k, x) in x.iter().enumerate() {
            let (lo, hi) = (k as f64 / 200.0, (k + 1) as f64 / 200.0);
            let lo = if k == 0 { f64::NEG_INFINITY } else { d.quantile(lo) };
            let hi = if k == 199 { f64::INFINITY } else { d.quantile(hi) };
            assert!(lo <= *x && *x <= hi, "{path}: sample {k} = {x} outside its stratum [{lo}, {hi}]");
        }
    }
    assert!(rows.iter().all(|r| r["status"] == "end time" && r["checks_pass"] == false));
    let csv = std::fs::read_to_string(out.join("sweep.csv")).unwrap();
    let head = csv.lines().next().unwrap();
    assert!(head.starts_with("index,name,environment.seabed_friction,ship.mass,anchor.mass,hydrodynamics.anchor_drag_coefficient,status,checks,"), "{head}");
}

#[test]
fn a_failing_check_exits_4_and_a_bad_spec_exits_2_naming_the_field() {
    let dir = temp_dir("exit");
    let out = dir.join("out");
    let o = sweep(&spec(&dir, "[checks]\nmax_stopping_distance = 1.0\n"), &out);
    assert_eq!(o.status.code(), Some(4), "{}", String::from_utf8_lossy(&o.stderr));
    let rows = rows(&out);
    assert_eq!(rows.len(), 1);
    assert_eq!(rows[0]["checks_pass"], false);
    let stderr = |o: &Output| String::from_utf8_lossy(&o.stderr).into_owned();
    let bad = sweep(&spec(&dir, "[[axis]]\npath = \"ship.mass\"\nrange = { from = 1e5, to = 2e5, steps = 0 }\n"), &out);
    assert_eq!(bad.status.code(), Some(2));
    assert!(stderr(&bad).contains("axis[0].range.steps = 0: in [1, 100000]"), "{}", stderr(&bad));
    let bad = sweep(&spec(&dir, "[[axis]]\npath = \"ship.mas\"\nvalues = [1.0]\n"), &out);
    assert_eq!(bad.status.code(), Some(2));
    assert!(stderr(&bad).contains("axis[0].path = ship.mas"), "{}", stderr(&bad));
    let bad = sweep(&spec(&dir, "[checks]\nsafety_factor = 0.5\n"), &out);
    assert!(stderr(&bad).contains("checks.safety_factor = 0.5: finite and ≥ 1"), "{}", stderr(&bad));
    // x_L and T_h give one quantity: set together ([set] and an axis), refused, naming both;
    // an axis value of the wrong type names the field's type, not x_L's value as an example.
    let both = "[set]\n\"initial.horizontal_projection\" = 149.0\n[[axis]]\npath = \"initial.horizontal_tension\"\nvalues = [150.0]\n";
    let bad = sweep(&spec(&dir, both), &out);
    assert_eq!(bad.status.code(), Some(2));
    assert!(
        stderr(&bad).contains("axis[0].path = initial.horizontal_tension: not set with initial.horizontal_projection"),
        "{}",
        stderr(&bad)
    );
    let bad = sweep(&spec(&dir, "[[axis]]\npath = \"initial.horizontal_tension\"\nvalues = [\"high\"]\n"), &out);
    assert!(stderr(&bad).contains("values of the field's type (float)"), "{}", stderr(&bad));
    // --heatmap: a name that is no output, or a spec without two grid axes, is refused
    // before any run.
    let one_axis = spec(&dir, "[[axis]]\npath = \"ship.mass\"\nvalues = [4e5, 5e5]\n");
    let with = |value: &str| {
        let args = ["sweep", one_axis.to_str().unwrap(), "--out", out.to_str().unwrap(), "--heatmap", value];
        kanestop().args(args).output().unwrap()
    };
    let bad = with("speed");
    assert_eq!(bad.status.code(), Some(2));
    assert!(
        stderr(&bad).contains("--heatmap = speed") && stderr(&bad).contains("stopping_distance"),
        "{}",
        stderr(&bad)
    );
    let bad = with("stopping_time");
    assert_eq!(bad.status.code(), Some(2));
    assert!(stderr(&bad).contains("exactly two grid axes; the spec has 1"), "{}", stderr(&bad));
    let help = kanestop().arg("--help").output().unwrap();
    let help = String::from_utf8_lossy(&help.stdout).into_owned();
    assert!(help.contains("4  a design check"), "{help}");
}

#[test]
fn sensitivity_on_case_1_reproduces_the_measured_ranking() {
    let dir = temp_dir("sens");
    let o = kanestop()
        .args(["report", "sensitivity", root().join("scenes/paper/case01.toml").to_str().unwrap()])
        .args(["--out", dir.to_str().unwrap()])
        .output()
        .unwrap();
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let study: Value = serde_json::from_str(&std::fs::read_to_string(dir.join("sensitivity.json")).unwrap()).unwrap();
    let rows = study["rows"].as_array().unwrap();
    let effect = |p: &str| -> f64 {
        let r = rows.iter().find(|r| r["parameter"] == p).unwrap_or_else(|| panic!("{p}"));
        r["stopping_time"].as_f64().unwrap()
    };
    // (parameter, d(stopping time)/d(ln p) in s, tolerance in s): the measurement.
    for (p, expected, tol) in [
        ("environment.seabed_friction", -16.0, 1.0),
        ("ship.mass", 18.0, 1.0),
        ("anchor.height", 10.0, 1.0),
        ("anchor.width", 10.0, 1.0),
        ("environment.water_density", 9.0, 0.5),
        ("hydrodynamics.anchor_drag_coefficient", -1.7, 0.1),
        ("hydrodynamics.tangential_drag_coefficient", -0.34, 0.03),
    ] {
        assert!((effect(p) - expected).abs() < tol, "{p}: {} against {expected} ± {tol}", effect(p));
    }
    for p in [
        "hydrodynamics.normal_drag_coefficient",
        "hydrodynamics.added_mass_coefficient",
        "environment.seabed_stiffness",
    ] {
        assert!(effect(p).abs() < 0.1, "{p}: {}", effect(p));
    }
    // Ranked by |effect| on the stopping time.
    let ranked: Vec<f64> = rows.iter().filter_map(|r| r["stopping_time"].as_f64()).map(f64::abs).collect();
    assert!(ranked.windows(2).all(|w| w[0] >= w[1]));
    // Parameters at the edge of their valid range: a cut or one-sided step, an effect all the
    // same, and the reason in the row. The line's slack leads: the laid line's horizontal
    // projection shortens the stop (a tauter line drags the anchor sooner), a longer middle
    // stage lengthens it.
    let row = |p: &str| rows.iter().find(|r| r["parameter"] == p).unwrap_or_else(|| panic!("{p}"));
    for (p, difference) in [
        ("initial.horizontal_projection", "central"),
        ("cable.stages[1].element_length", "central"),
        ("ship.hinge_x", "backward"),
        ("ship.length", "forward"),
        ("rod.length", "backward"),
        ("ship.hinge_z", "forward"),
    ] {
        let r = row(p);
        assert_eq!((r["difference"].as_str(), r["step"].as_f64()), (Some(difference), Some(0.01)), "{p}");
        assert!(r["stopping_time"].as_f64().is_some() && r["message"].as_str().unwrap().contains("refused"), "{p}");
    }
    assert!(effect("initial.horizontal_projection") < -20.0 && effect("cable.stages[1].element_length") > 20.0);
    // The three stages' element lengths act through one quantity, the line's length L_c:
    // d(t)/d(ln ℓ_k) = (dt/dL_c) n_k ℓ_k, so each effect over its stage's length (3 × 2 m,
    // 12 × 10 m, 13 × 2 m) gives the same dt/dL_c, whether differenced at ±5 % or ±1 %.
    let per_metre: Vec<f64> = [(0, 6.0), (1, 120.0), (2, 26.0)]
        .map(|(k, length)| effect(&format!("cable.stages[{k}].element_length")) / length)
        .to_vec();
    let mean = per_metre.iter().sum::<f64>() / 3.0;
    assert!(per_metre.iter().all(|x| (x / mean - 1.0).abs() < 0.03), "dt/dL_c by stage: {per_metre:?} s/m");
    assert!(rows.iter().all(|r| r["stopping_time"].is_number()), "every parameter of case 1 has an effect");
    assert_eq!(study["runs"].as_u64().unwrap(), 1 + 2 * rows.len() as u64 - 4, "four one-sided rows");
    refresh_sensitivity_doc(&study);
}

const SENSITIVITY_BEGIN: &str = "<!-- sensitivity:begin";
const SENSITIVITY_END: &str = "<!-- sensitivity:end -->";
/// Effects on the stopping time below this (s) are summed up in a sentence, not ranked.
const SENSITIVITY_SHOWN: f64 = 0.3;

/// docs/sweeps.md's "Measured on case 1": the study's ranking, rendered from its
/// `sensitivity.json` rows. A stale block fails and is rewritten.
fn refresh_sensitivity_doc(study: &Value) {
    let rows = study["rows"].as_array().unwrap();
    let signed = |v: &Value, scale: f64, digits: usize| match v.as_f64() {
        Some(x) => format!("{:+.*}", digits, x * scale).replace('-', "−"),
        None => "—".to_string(),
    };
    let effect =
        |p: &str| rows.iter().find(|r| r["parameter"] == p).map(|r| signed(&r["stopping_time"], 1.0, 3)).unwrap();
    let mut o = format!(
        "{SENSITIVITY_BEGIN}: rendered by tests/sweeps.rs::sensitivity_on_case_1_reproduces_the_measured_ranking -->\n\n\
         {} runs (the base and one or two per parameter); d(output)/d(ln p), the top of the ranking \
         (step: ±h central, +h or −h one-sided):\n\n\
         | rank | parameter | step | stop (s) | distance (m) | peak (kN) |\n| --- | --- | --- | --- | --- | --- |\n",
        study["runs"]
    );
    for (i, r) in rows.iter().enumerate() {
        if r["stopping_time"].as_f64().is_some_and(|t| t.abs() >= SENSITIVITY_SHOWN) {
            o.push_str(&format!(
                "| {} | {} | {}{} | {} | {} | {} |\n",
                i + 1,
                r["parameter"].as_str().unwrap(),
                match r["difference"].as_str() {
                    Some("forward") => "+",
                    Some("backward") => "−",
                    _ => "±",
                },
                r["step"],
                signed(&r["stopping_time"], 1.0, 2),
                signed(&r["stopping_distance"], 1.0, 2),
                signed(&r["peak_tension"], 1e-3, 1)
            ));
        }
    }
    o.push_str(&format!(
        "\nThe rest is below {SENSITIVITY_SHOWN} s (normal drag {} s, added mass {} s, seabed stiffness {} s).\n\n{SENSITIVITY_END}",
        effect("hydrodynamics.normal_drag_coefficient"),
        effect("hydrodynamics.added_mass_coefficient"),
        effect("environment.seabed_stiffness")
    ));
    let path = root().join("docs/sweeps.md");
    let mut text = std::fs::read_to_string(&path).unwrap();
    let a = text.find(SENSITIVITY_BEGIN).expect("docs/sweeps.md: sensitivity begin marker");
    let b = text.find(SENSITIVITY_END).expect("docs/sweeps.md: sensitivity end marker") + SENSITIVITY_END.len();
    if text[a..b] != o {
        text.replace_range(a..b, &o);
        std::fs::write(&path, &text).unwrap();
        panic!("docs/sweeps.md's sensitivity table was stale and has been regenerated: review and commit it");
    }
}

/// The table's utilisation is the line's worst joint's, not the one at the peak tension's
/// joint: with a weak chain the chain governs though the rod's joint carries more.
#[test]
fn the_table_gives_the_worst_joints_utilisation() {
    let dir = temp_dir("worst-util");
    let out = dir.join("out");
    let body = "[set]\n\"chain.proof_load\" = 3.5e5\n\
                [[axis]]\npath = \"chain.break_load\"\nvalues = [5e5]\n";
    let o = sweep(&spec(&dir, body), &out);
    let stdout = String::from_utf8_lossy(&o.stdout);
    let row = &rows(&out)[0]["summary"];
    let at_peak = row["peak_tension"]["break_utilisation"].as_f64().unwrap();
    let chain = row["chain_peak"]["break_utilisation"].as_f64().unwrap();
    assert!(chain > 2.0 * at_peak, "the chain should govern: {chain} against {at_peak}");
    let line = stdout.lines().find(|l| l.starts_with("spec-000")).unwrap();
    assert!(line.contains(&format!(" {:.1}  chain.break_load=500000", 100.0 * chain)), "{line}");
}

/// Samples that did not stop the ship by the end time are counted, and the stopping
/// statistics over those that did are said to be biased low (they used to be printed as if
/// over every sample).
#[test]
fn sampling_says_how_many_samples_stopped_the_ship() {
    let dir = temp_dir("stopped-count");
    let out = dir.join("out");
    // Case 1 stops at 19.8 s: the heavier ships of the sample have not stopped at 20.5 s.
    let body = "[set]\n\"solver.end_time\" = 20.5\n\
                [sampling]\nmethod = \"latin-hypercube\"\nsamples = 6\nseed = 3\n\
                [[uncertain]]\npath = \"ship.mass\"\ndistribution = \"normal\"\nmean = 5e5\nsd = 5e4\n";
    let o = sweep(&spec(&dir, body), &out);
    let stdout = String::from_utf8_lossy(&o.stdout);
    let stopped = rows(&out).iter().filter(|r| r["status"] == "stopped").count();
    assert!((2..6).contains(&stopped), "the sample should stop some ships and not others: {stdout}");
    assert!(stdout.contains(&format!("samples   6, {stopped} stopped the ship\n")), "{stdout}");
    let caveat = format!("(over the {stopped} that stopped: biased low)");
    for name in ["stopping time (s)", "stopping distance (m)"] {
        let line = stdout.lines().find(|l| l.starts_with(name)).expect(name);
        assert!(line.ends_with(&caveat), "{line}");
    }
    let peak = stdout.lines().find(|l| l.starts_with("peak tension (kN)")).unwrap();
    assert!(!peak.contains("biased"), "every sample ran to its end: {peak}");
}

/// Sampling on top of a grid: the statistics are each grid point's, over its own samples,
/// labelled by the point; pooled over the grid, two ship masses would blur into one spread.
#[test]
fn sampling_on_a_grid_gives_each_point_its_own_statistics() {
    let dir = temp_dir("grid-stats");
    let out = dir.join("out");
    let body = "[[axis]]\npath = \"ship.mass\"\nvalues = [4e5, 6e5]\n\
                [sampling]\nmethod = \"latin-hypercube\"\nsamples = 4\nseed = 3\n\
                [[uncertain]]\npath = \"anchor.mass\"\ndistribution = \"uniform\"\nlow = 36000.0\nhigh = 44000.0\n";
    let spec = spec(&dir, body);
    let o = sweep(&spec, &out);
    let stdout = String::from_utf8_lossy(&o.stdout);
    assert_eq!(o.status.code(), Some(0), "{stdout}{}", String::from_utf8_lossy(&o.stderr));
    let rows = rows(&out);
    let mut heads = Vec::new();
    for mass in [400000.0, 600000.0] {
        let times: Vec<f64> = rows
            .iter()
            .filter(|r| r["inputs"]["ship.mass"].as_f64() == Some(mass))
            .map(|r| r["summary"]["stopping_time"].as_f64().unwrap())
            .collect();
        assert_eq!(times.len(), 4);
        let mean = times.iter().sum::<f64>() / 4.0;
        let head =
            format!("point     ship.mass={mass} (4 samples, 4 stopped)\nstopping time (s)      mean {mean:.3}  sd ");
        assert!(stdout.contains(&head), "{head:?} not in\n{stdout}");
        heads.push(head);
    }
    assert!(!stdout.contains("pooled"), "{stdout}");
    // Run in two shards and merged without the spec: the shard files say the grid.
    let sharded = dir.join("sharded");
    for k in ["0/2", "1/2"] {
        let o = kanestop()
            .args(["sweep", spec.to_str().unwrap(), "--out", sharded.to_str().unwrap(), "--shard", k])
            .output()
            .unwrap();
        assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    }
    let o = kanestop().args(["sweep", "merge", sharded.to_str().unwrap()]).output().unwrap();
    let merged = String::from_utf8_lossy(&o.stdout);
    assert!(heads.iter().all(|h| merged.contains(h.as_str())) && !merged.contains("pooled"), "{merged}");
}

/// A base run that does not stop has no stop to move: the study is ranked by the effect on
/// the peak tension and says so; a band over inputs that are no parameters of the study is
/// none, and an `--uncertain` spec without inputs is refused before any run.
#[test]
fn sensitivity_of_a_base_that_does_not_stop_ranks_by_the_peak_tension() {
    let dir = temp_dir("sens-short");
    let short = dir.join("short.toml");
    let text = std::fs::read_to_string(root().join("scenes/paper/case01.toml")).unwrap();
    std::fs::write(&short, text.replace("end_time = 60.0", "end_time = 1.0")).unwrap();
    // environment.line_friction is 0 in case 1: no parameter of the study.
    let zero = spec(
        &dir,
        "[sampling]\nmethod = \"random\"\nsamples = 3\nseed = 1\n[[uncertain]]\npath = \"environment.line_friction\"\n\
         distribution = \"uniform\"\nlow = 0.0\nhigh = 0.2\n",
    );
    let out = dir.join("out");
    let study = |uncertain: &Path| {
        kanestop()
            .args(["report", "sensitivity", short.to_str().unwrap(), "--uncertain", uncertain.to_str().unwrap()])
            .arg("--out")
            .arg(&out)
            .output()
            .unwrap()
    };
    let o = study(&zero);
    let stdout = String::from_utf8_lossy(&o.stdout);
    assert!(o.status.success(), "{stdout}{}", String::from_utf8_lossy(&o.stderr));
    assert!(stdout.contains("note: the base run has no stop to move (it did not stop by its end time"), "{stdout}");
    assert!(stdout.contains("no first-order band: none of the 1 uncertain inputs"), "{stdout}");
    assert!(stdout.contains("environment.line_friction is not a continuous parameter"), "{stdout}");
    let csv = std::fs::read_to_string(out.join("sensitivity.csv")).unwrap();
    // sensitivity.units.csv names its columns in order, each with its unit.
    let units = std::fs::read_to_string(out.join("sensitivity.units.csv")).unwrap();
    let listed: Vec<&str> = units.lines().skip(1).map(|l| l.split(',').next().unwrap()).collect();
    assert_eq!(listed, csv.lines().next().unwrap().split(',').collect::<Vec<_>>());
    assert!(units.contains("\nd_peak_tension,N,"), "{units}");
    let peaks: Vec<f64> = csv
        .lines()
        .skip(1)
        .filter_map(|l| l.split(',').nth(5).and_then(|v| v.parse::<f64>().ok()).map(f64::abs))
        .collect();
    assert!(peaks.len() > 10 && peaks.windows(2).all(|w| w[0] >= w[1]), "ranked by |peak effect|: {peaks:?}");
    // A spec with no [[uncertain]] input: refused before the 70-odd runs.
    let none = spec(&dir, "[[axis]]\npath = \"ship.mass\"\nvalues = [5e5]\n");
    std::fs::remove_dir_all(&out).unwrap();
    let o = study(&none);
    assert_eq!(o.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&o.stderr).contains("no [[uncertain]] input in it"), "{o:?}");
    assert!(!out.exists());
}

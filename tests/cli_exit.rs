//! Every exit code of `kanestop --help`, and where the words go (standard output for
//! summaries, standard error for errors and diagnostics), and which files a run writes.

mod scratch;
use scratch::Scratch;

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

fn kanestop() -> Command {
    Command::new(env!("CARGO_BIN_EXE_kanestop"))
}

/// The test's scratch folder, removed when it passes (tests/scratch).
fn temp_dir(name: &str) -> Scratch {
    Scratch::new(&format!("exit-{name}"))
}

/// Case 1 with a smaller step, ended at 0.05 s, with `edit` applied to its text.
fn scene(dir: &Path, name: &str, edit: impl Fn(String) -> String) -> PathBuf {
    let text = kanestop_runtime::paper::DEFAULT_SCENE
        .replace("dt = 0.002", "dt = 0.0005")
        .replace("end_time = 60.0", "end_time = 0.05")
        .replace("output_interval = 0.02", "output_interval = 0.01");
    let path = dir.join(format!("{name}.toml"));
    std::fs::write(&path, edit(text)).unwrap();
    path
}

/// Case 1's RK4 step raised to 0.05 s: above the stability limit, refused before the run.
fn refused(dir: &Path) -> PathBuf {
    scene(dir, "refused", |t| {
        t.replace("dt = 0.0005", "dt = 0.05").replace("output_interval = 0.01", "output_interval = 0.05")
    })
}

/// Case 1 without water or seabed, run on for 10 s past the ship's stop: a run that fails
/// numerically on the way (exit 3), not refused before it.
fn gravity_only(dir: &Path) -> PathBuf {
    scene(dir, "gravity-only", |t| {
        t.replace("water = true", "water = false")
            .replace("seabed = true", "seabed = false")
            .replace("end_time = 0.05", "end_time = 10.0")
            .replace("dt = 0.0005", "dt = 0.002")
            .replace("stop_when_ship_stops = true", "stop_when_ship_stops = false")
    })
}

fn text(out: &Output) -> (String, String) {
    (String::from_utf8_lossy(&out.stdout).into_owned(), String::from_utf8_lossy(&out.stderr).into_owned())
}

#[test]
fn help_lists_the_exit_codes() {
    let out = kanestop().arg("--help").output().unwrap();
    let (stdout, _) = text(&out);
    assert!(out.status.success());
    for line in ["0  done", "1  batch", "2  bad input", "3  numerical failure", "4  a design check failed"] {
        assert!(stdout.contains(line), "--help lacks {line:?}: {stdout}");
    }
}

#[test]
fn exit_0_done() {
    let dir = temp_dir("done");
    let out = kanestop().arg("run").arg(scene(&dir, "short", |t| t)).output().unwrap();
    let (stdout, stderr) = text(&out);
    assert_eq!(out.status.code(), Some(0), "{stdout}{stderr}");
    assert!(stderr.is_empty(), "{stderr}");
}

#[test]
fn exit_1_batch_missed() {
    let dir = temp_dir("batch");
    let scenes = dir.join("scenes");
    std::fs::create_dir_all(&scenes).unwrap();
    std::fs::write(scenes.join("bad.toml"), "not a scene").unwrap();
    let out = kanestop().arg("batch").arg(&scenes).arg("--out").arg(dir.join("out")).output().unwrap();
    assert_eq!(out.status.code(), Some(1));
}

#[test]
fn exit_2_bad_arguments_scene_and_paths() {
    let dir = temp_dir("bad");
    let short = scene(&dir, "short", |t| t);
    for args in [
        vec!["run", "--dt", "nope"],
        vec!["run", "--no-such-flag"],
        vec!["frobnicate"],
        vec!["run", "/no/such/scene.toml"],
        vec!["plot", "/no/such/scene.toml", "--out", "/tmp"],
    ] {
        let out = kanestop().args(&args).output().unwrap();
        let (stdout, stderr) = text(&out);
        assert_eq!(out.status.code(), Some(2), "{args:?}: {stdout}{stderr}");
        assert!(!stderr.is_empty() && !stderr.contains("panicked"), "{args:?}: {stderr}");
    }
    // An input file that is no regular file is refused before it is read (read whole,
    // /dev/zero filled the memory at 1.5 GB/s).
    let out_dir = dir.join("zero-out");
    let out_dir = out_dir.to_str().unwrap();
    for args in [
        vec!["eval", "--state", "/dev/zero"],
        vec!["sweep", "/dev/zero", "--out", out_dir],
        vec!["sweep", "merge", "/dev/zero", "--out", out_dir],
        vec!["report", "sensitivity", "--uncertain", "/dev/zero", "--out", out_dir],
    ] {
        let out = kanestop().args(&args).output().unwrap();
        let (stdout, stderr) = text(&out);
        assert_eq!(out.status.code(), Some(2), "{args:?}: {stdout}{stderr}");
        assert!(stderr.contains("/dev/zero: not a regular file"), "{args:?}: {stderr}");
    }
    // A negative number is a value of its flag, refused by the scene's range, not an argument
    // of its own.
    for (flag, field) in [("--dt", "solver.dt = -1: must be in (0, 1] s"), ("--end-time", "solver.end_time = -1")] {
        let out = kanestop().args(["run", short.to_str().unwrap(), flag, "-1"]).output().unwrap();
        let (stdout, stderr) = text(&out);
        assert_eq!(out.status.code(), Some(2), "{flag}: {stdout}{stderr}");
        assert!(stderr.contains(field) && !stderr.contains("unexpected argument"), "{flag}: {stderr}");
    }
    for args in [
        vec!["report", "sensitivity", "--step", "-0.1"],
        vec!["sweep", "scenes/sweeps/mass_speed.toml", "--checkpoint", "-1"],
        // An atol out of a scene's range for some rtol of the study (1e300 ran every adaptive
        // setting to a failure, exit 0); a study of ten years.
        vec!["report", "accuracy", "--atol-ratio", "1e300"],
        vec!["report", "accuracy", "--repeats", "1000000000"],
    ] {
        let out = kanestop().args(&args).output().unwrap();
        let (stdout, stderr) = text(&out);
        assert_eq!(out.status.code(), Some(2), "{args:?}: {stdout}{stderr}");
        assert!(stderr.contains(args[args.len() - 2]) && !stderr.contains("unexpected argument"), "{args:?}: {stderr}");
    }
    // Output targets are checked before the run: nothing printed, nothing written.
    let file = dir.join("a-file");
    std::fs::write(&file, "").unwrap();
    for (flag, target) in [("--out", file.join("sub/history.csv")), ("--plot", file.join("plots"))] {
        let out = kanestop().arg("run").arg(&short).arg(flag).arg(&target).output().unwrap();
        let (stdout, stderr) = text(&out);
        assert_eq!(out.status.code(), Some(2), "{flag}: {stdout}{stderr}");
        assert!(stdout.is_empty() && stderr.contains("cannot write"), "{flag}: {stdout}{stderr}");
    }
    let short_path = short.to_str().unwrap();
    for sub in
        [vec!["plot", short_path], vec!["report", "accuracy", short_path], vec!["report", "sensitivity", short_path]]
    {
        let out = kanestop().args(&sub).arg("--out").arg(file.join("x")).output().unwrap();
        let (stdout, stderr) = text(&out);
        assert_eq!(out.status.code(), Some(2), "{sub:?}: {stdout}{stderr}");
        assert!(stderr.contains("cannot write into"), "{sub:?}: {stderr}");
    }
}

/// The command line's solver flags are laid on the file before it is checked: a flag mends
/// a file whose own step is refused (the file alone: exit 2). `batch` refuses a flag's value
/// outside its field's range before any run, and writes nothing (it ran every scene as
/// invalid and exited 1).
#[test]
fn solver_flags_mend_a_scene_and_batch_refuses_bad_ones_up_front() {
    let dir = temp_dir("flags");
    let coarse = scene(&dir, "coarse", |t| t.replace("dt = 0.0005", "dt = 0.05"));
    let o = kanestop().arg("run").arg(&coarse).output().unwrap();
    assert_eq!(o.status.code(), Some(2), "{:?}", text(&o));
    assert!(text(&o).1.contains("solver.output_interval = 0.01"), "{}", text(&o).1);
    let o = kanestop().arg("run").arg(&coarse).args(["--dt", "0.0005"]).output().unwrap();
    assert!(o.status.success(), "{:?}", text(&o));
    let o = kanestop().arg("run").arg(&coarse).args(["--dt", "0.0005", "--rtol", "nan"]).output().unwrap();
    assert_eq!(o.status.code(), Some(2));
    assert!(text(&o).1.contains("coarse.toml (with command-line overrides)"), "{}", text(&o).1);

    let scenes = dir.join("scenes");
    std::fs::create_dir_all(&scenes).unwrap();
    std::fs::copy(&coarse, scenes.join("coarse.toml")).unwrap();
    let out = dir.join("batch-out");
    for (flags, message) in [
        (vec!["--dt", "0"], "--dt = 0: must be in (0, 1] s"),
        (vec!["--integrator", "dp5", "--rtol", "nan"], "--rtol = nan: must be in [1e-14, 0.1]"),
        (vec!["--methods", "rk4@0"], "--methods rk4@0: --dt = 0: must be in (0, 1] s"),
    ] {
        let o = kanestop().arg("batch").arg(&scenes).arg("--out").arg(&out).args(&flags).output().unwrap();
        let (stdout, stderr) = text(&o);
        assert_eq!(o.status.code(), Some(2), "{flags:?}: {stdout}{stderr}");
        assert!(stderr.contains(message) && stdout.is_empty(), "{flags:?}: {stderr}");
        assert!(!out.exists(), "{flags:?} wrote {}", out.display());
    }
    // A flag is held to its own field's fixed range only, not to the file's other values, and
    // laid on each file before it is checked, as `run` lays it: the file's own step (0.05 s,
    // above its output interval of 0.01 s) is mended, and a step, an output interval and an
    // end time the file's values would refuse together are taken and run.
    for flags in [
        vec!["--dt", "0.0005", "--end-time", "0.002"],
        vec!["--dt", "0.0005", "--output-interval", "0.001", "--end-time", "0.001"],
        vec!["--methods", "rk4@0.0005", "--end-time", "0.001"],
        // The file's output interval (0.01 s) raised to the method's observation interval.
        vec!["--methods", "dp5@0.05", "--end-time", "0.1"],
    ] {
        let o = kanestop().arg("batch").arg(&scenes).arg("--out").arg(&out).args(&flags).output().unwrap();
        let (stdout, stderr) = text(&o);
        assert_eq!(o.status.code(), Some(0), "{flags:?}: {stdout}{stderr}");
        let csv = std::fs::read_to_string(out.join("batch.csv")).unwrap();
        let row = csv.lines().nth(1).unwrap();
        assert!(row.contains("coarse.toml,end time,"), "{flags:?}: {row}");
    }
    // A method's step raises a shorter output interval, not one out of its own range: a file's
    // `output_interval = 0` stays refused.
    let zero = dir.join("zero");
    std::fs::create_dir_all(&zero).unwrap();
    std::fs::write(
        zero.join("zero.toml"),
        std::fs::read_to_string(&coarse).unwrap().replace("output_interval = 0.01", "output_interval = 0.0"),
    )
    .unwrap();
    let o = kanestop().arg("batch").arg(&zero).arg("--out").arg(&out).args(["--methods", "dp5@0.05"]).output().unwrap();
    let (stdout, stderr) = text(&o);
    assert_eq!(o.status.code(), Some(1), "{stdout}{stderr}");
    assert!(stdout.contains("invalid") && stdout.contains("solver.output_interval = 0"), "{stdout}");
}

#[test]
fn exit_2_sweep_arguments_refused_before_anything_is_written() {
    let dir = temp_dir("sweep-args");
    let short = scene(&dir, "short", |t| t);
    let spec = |name: &str, axes: &str| {
        let path = dir.join(format!("{name}.toml"));
        std::fs::write(&path, format!("base = {:?}\n{axes}", short.file_name().unwrap())).unwrap();
        path
    };
    let small = spec("small", "[[axis]]\npath = \"anchor.mass\"\nvalues = [40000.0]\n");
    let axis = |p: &str| format!("[[axis]]\npath = \"{p}\"\nrange = {{ from = 1.0, to = 2.0, steps = 100000 }}\n");
    let huge = spec("huge", &(axis("anchor.mass") + &axis("ship.mass")));
    let huge4 =
        spec("huge4", &[axis("anchor.mass"), axis("ship.mass"), axis("rod.length"), axis("ship.length")].concat());
    let two = spec(
        "two",
        "[[axis]]\npath = \"anchor.mass\"\nvalues = [4e4, 5e4]\n[[axis]]\npath = \"ship.mass\"\nvalues = [4e5, 5e5]\n",
    );
    let out = dir.join("out");
    let cases: [(Vec<&str>, &str); 7] = [
        (
            vec!["sweep", two.to_str().unwrap(), "--shard", "0/1", "--heatmap", "stopping_time"],
            "--heatmap stopping_time with a shard (--shard): a shard holds some of the rows and draws no heat map",
        ),
        (vec!["sweep", small.to_str().unwrap(), "--jobs", "0"], "--jobs = 0: in [1, 1024]"),
        (vec!["sweep", small.to_str().unwrap(), "--shard", "0/1", "--jobs", "0"], "--jobs = 0: in [1, 1024]"),
        (vec!["sweep", small.to_str().unwrap(), "--jobs", "100000"], "--jobs = 100000: in [1, 1024]"),
        (
            vec!["sweep", small.to_str().unwrap(), "--shard", "0/1", "--checkpoint", "1e300"],
            "--checkpoint = 1e300: a number of seconds from 0 to 1e6",
        ),
        (vec!["sweep", huge.to_str().unwrap()], "axis = 100000 × 100000 rows: at most 1000000 rows in all"),
        (vec!["sweep", huge4.to_str().unwrap()], "axis = 100000 × 100000 × 100000 × 100000 rows"),
    ];
    for (args, message) in cases {
        let o = kanestop().args(&args).arg("--out").arg(&out).output().unwrap();
        let (stdout, stderr) = text(&o);
        assert_eq!(o.status.code(), Some(2), "{args:?}: {stdout}{stderr}");
        assert!(stderr.contains(message) && !stderr.contains("panicked"), "{args:?}: {stderr}");
        assert!(!out.exists(), "{args:?} wrote {}", out.display());
    }
    let o = kanestop()
        .args(["report", "sensitivity", short.to_str().unwrap(), "--jobs", "0"])
        .arg("--out")
        .arg(&out)
        .output()
        .unwrap();
    assert!(o.status.code() == Some(2) && text(&o).1.contains("--jobs = 0: in [1, 1024]"), "{:?}", text(&o));
    assert!(!out.exists(), "report sensitivity --jobs 0 wrote {}", out.display());
    // A folder where a heat map or a row's scene file goes is found before the runs (it was
    // found after them, with the table and some files written).
    for (blocked, args) in [
        ("heatmap-stopping_time.svg", vec!["sweep", two.to_str().unwrap()]),
        ("scenes/small-000.toml", vec!["sweep", small.to_str().unwrap()]),
    ] {
        let out = dir.join(format!("out-{}", blocked.len()));
        std::fs::create_dir_all(out.join(blocked)).unwrap();
        let o = kanestop().args(&args).arg("--out").arg(&out).output().unwrap();
        let (stdout, stderr) = text(&o);
        assert_eq!(o.status.code(), Some(2), "{args:?}: {stdout}{stderr}");
        assert!(stderr.contains(&format!("{blocked} exists and is not a regular file")), "{stderr}");
        assert!(stdout.is_empty() && !out.join("sweep.csv").exists(), "{args:?}: {stdout}");
    }
}

#[test]
fn exit_2_a_step_refused_before_the_run_writes_nothing() {
    // Regression: exited 3 (numerical failure), printed the diagnostic on standard output
    // and wrote a header-only CSV.
    let dir = temp_dir("refused");
    let csv = dir.join("h.csv");
    let plots = dir.join("plots");
    let out =
        kanestop().arg("run").arg(refused(&dir)).arg("--out").arg(&csv).arg("--plot").arg(&plots).output().unwrap();
    let (stdout, stderr) = text(&out);
    assert_eq!(out.status.code(), Some(2), "{stdout}{stderr}");
    assert!(stderr.contains("stability limit") && stderr.contains("suggestion:"), "{stderr}");
    assert!(!stdout.contains("suggestion:"), "the diagnostic is on standard error: {stdout}");
    assert!(!stderr.contains("panicked"), "{stderr}");
    assert!(!csv.exists(), "no CSV for a run that never started");
    assert!(!plots.exists(), "no plots for a run that never started");
}

#[test]
fn a_sensitivity_study_whose_base_run_fails_says_so_and_runs_no_probe() {
    // Regression: every probe ran and the table was all dashes, exit 0, without a word why;
    // the progress line then read 73/73 runs.
    let dir = temp_dir("sensitivity-base");
    let out_dir = dir.join("sens");
    let out =
        kanestop().args(["report", "sensitivity"]).arg(refused(&dir)).arg("--out").arg(&out_dir).output().unwrap();
    let (stdout, stderr) = text(&out);
    assert_eq!(out.status.code(), Some(2), "{stdout}{stderr}");
    assert!(stderr.contains("the base run failed, so there is nothing to take differences from"), "{stderr}");
    assert!(
        stderr.contains("stability limit") && stderr.contains("progress  1/") && !stderr.contains("ETA"),
        "{stderr}"
    );
    assert!(!out_dir.exists(), "nothing written");
    // Failed on the way (not refused): exit 3, as `run` exits.
    let failing = gravity_only(&dir);
    let out = kanestop().args(["report", "sensitivity"]).arg(&failing).arg("--out").arg(&out_dir).output().unwrap();
    let (stdout, stderr) = text(&out);
    assert_eq!(out.status.code(), Some(3), "{stdout}{stderr}");
    assert!(stderr.contains("numerical failure at t ="), "{stderr}");
}

#[test]
fn run_plot_of_the_stress_scene_dt_too_large_does_not_panic() {
    // Regression: `run --plot` on scenes/stress/dt_too_large.toml panicked.
    let dir = temp_dir("stress-plot");
    let scene = Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes/stress/dt_too_large.toml");
    let out = kanestop().arg("run").arg(&scene).arg("--plot").arg(dir.join("plots")).output().unwrap();
    let (stdout, stderr) = text(&out);
    assert_eq!(out.status.code(), Some(2), "{stdout}{stderr}");
    assert!(!stderr.contains("panicked"), "{stderr}");
}

#[test]
fn exit_3_numerical_failure() {
    let dir = temp_dir("numerical");
    let path = gravity_only(&dir);
    let csv = dir.join("h.csv");
    let out = kanestop().arg("run").arg(&path).arg("--out").arg(&csv).output().unwrap();
    let (stdout, stderr) = text(&out);
    assert_eq!(out.status.code(), Some(3), "{stdout}{stderr}");
    assert!(stderr.contains("numerical failure at t ="), "{stderr}");
    assert!(csv.exists(), "the history up to the failure is kept");
}

/// A run that failed passed no check: with no break load exceeded before the failure it has
/// no verdict (`run` prints no checks line, `run --json` no `checks_pass`, batch an empty
/// cell), as its `[checks]` of the tensions would have none.
#[test]
fn exit_3_a_failed_run_passes_no_check() {
    let dir = temp_dir("failed-unchecked");
    // RK4 at 15 ms blows up at 1.47 s, the peak tension 1 213 kN below every break load.
    let scene_text = kanestop_runtime::paper::DEFAULT_SCENE
        .replace("dt = 0.002", "dt = 0.015")
        .replace("end_time = 60.0", "end_time = 2.0");
    let scenes = dir.join("scenes");
    std::fs::create_dir_all(&scenes).unwrap();
    let path = scenes.join("tight.toml");
    std::fs::write(&path, scene_text).unwrap();
    let out = kanestop().arg("run").arg(&path).output().unwrap();
    let (stdout, stderr) = text(&out);
    assert_eq!(out.status.code(), Some(3), "{stdout}{stderr}");
    assert!(stdout.contains("exceeds solver.max_energy_drift = 0.05 ("), "{stdout}");
    assert!(stdout.contains("\ntension   peak") && !stdout.contains("\nchecks"), "{stdout}");
    let out = kanestop().arg("run").arg(&path).arg("--json").output().unwrap();
    let v: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    assert_eq!((v["status"].as_str(), v.get("checks_pass")), (Some("failed"), None), "{v}");
    let out = kanestop().arg("batch").arg(&scenes).arg("--out").arg(dir.join("out")).output().unwrap();
    assert_eq!(out.status.code(), Some(1), "{:?}", text(&out));
    let json: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(dir.join("out/batch.json")).unwrap()).unwrap();
    assert_eq!(json[0]["checks_pass"], serde_json::Value::Null, "{json}");
}

#[test]
fn exit_4_a_design_check_failed() {
    let dir = temp_dir("check");
    // A weak cable (20 kN, a breaking length of 150 m: still a line) over case 1's first
    // 1.3 s, in which the tension near the ship reaches 118 kN.
    let path = scene(&dir, "weak-cable", |t| {
        t.replace("break_load = 2520000.0", "break_load = 20000.0").replace("end_time = 0.05", "end_time = 1.3")
    });
    let out = kanestop().arg("run").arg(&path).output().unwrap();
    let (stdout, stderr) = text(&out);
    assert_eq!(out.status.code(), Some(4), "{stdout}{stderr}");
    assert!(stdout.contains("break load exceeded"), "{stdout}");
    // The JSON summary exits alike.
    let out = kanestop().arg("run").arg(&path).arg("--json").output().unwrap();
    assert_eq!(out.status.code(), Some(4));
    // A batch names it in the row's message and marks the row's checks failed, `[checks]`
    // or not, with the same words as `run`.
    let scenes = dir.join("scenes");
    std::fs::create_dir_all(&scenes).unwrap();
    std::fs::copy(&path, scenes.join("weak-cable.toml")).unwrap();
    let out = kanestop().arg("batch").arg(&scenes).arg("--out").arg(dir.join("out")).output().unwrap();
    let (batch_out, stderr) = text(&out);
    assert_eq!(out.status.code(), Some(4), "{batch_out}{stderr}");
    let failure = stdout.lines().find_map(|l| l.split("FAIL: ").nth(1)).expect("run's checks line").to_string();
    assert!(batch_out.contains(&format!("check failed: {failure}")), "{failure:?} in {batch_out}");
    let row = batch_out.lines().nth(1).unwrap();
    assert!(row.contains(" end time    fail "), "{row}");
    // So do its files, and run --json.
    let json: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(dir.join("out/batch.json")).unwrap()).unwrap();
    assert_eq!(json[0]["checks_pass"], serde_json::json!(false), "{json}");
    let csv = std::fs::read_to_string(dir.join("out/batch.csv")).unwrap();
    // (From the end: the message before it is quoted and holds commas.)
    let head: Vec<&str> = csv.lines().next().unwrap().split(',').collect();
    let from_end = head.len() - 1 - head.iter().position(|h| *h == "checks").unwrap();
    assert_eq!(csv.lines().nth(1).unwrap().rsplit(',').nth(from_end), Some("fail"), "{csv}");
    let out = kanestop().arg("run").arg(&path).arg("--json").output().unwrap();
    let summary: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    assert_eq!(summary["checks_pass"], serde_json::json!(false));
}

#[test]
fn a_batch_tolerance_of_1_or_more_is_taken_as_a_fraction_with_a_warning() {
    let dir = temp_dir("tolerance");
    let scenes = dir.join("scenes");
    std::fs::create_dir_all(&scenes).unwrap();
    scene(&scenes, "a", |t| t);
    let out =
        kanestop().arg("batch").arg(&scenes).args(["--tolerance", "5", "--out"]).arg(dir.join("out")).output().unwrap();
    let (stdout, stderr) = text(&out);
    assert!(stderr.contains("warning: --tolerance 5 is a fraction: 500 % (for 5 %, give 0.05)"), "{stdout}{stderr}");
    let out = kanestop()
        .arg("batch")
        .arg(&scenes)
        .args(["--tolerance", "0.05", "--out"])
        .arg(dir.join("out"))
        .output()
        .unwrap();
    assert!(!text(&out).1.contains("warning"), "{:?}", text(&out));
}

/// A batch whose scenes all run but one fails its `[checks]`: the table, the CSV and the
/// JSON say pass or fail per row, the failed check is named, and the exit is 4 as `run`'s;
/// an invalid scene beside it takes precedence (exit 1).
#[test]
fn exit_4_a_batch_row_fails_its_checks() {
    let dir = temp_dir("batch-check");
    let scenes = dir.join("scenes");
    std::fs::create_dir_all(&scenes).unwrap();
    scene(&scenes, "a-pass", |t| format!("{t}\n[checks]\nmax_anchor_drag = 100.0\n"));
    scene(&scenes, "b-fail", |t| format!("{t}\n[checks]\nmax_anchor_drag = 100.0\nmax_stopping_time = 30.0\n"));
    scene(&scenes, "c-none", |t| t);
    let out_dir = dir.join("out");
    let out = kanestop().arg("batch").arg(&scenes).arg("--out").arg(&out_dir).output().unwrap();
    let (stdout, stderr) = text(&out);
    assert_eq!(out.status.code(), Some(4), "{stdout}{stderr}");
    assert!(stdout.contains("checks") && stdout.contains("check failed: max_stopping_time"), "{stdout}");
    let json: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(out_dir.join("batch.json")).unwrap()).unwrap();
    let pass: Vec<&serde_json::Value> = json.as_array().unwrap().iter().map(|r| &r["checks_pass"]).collect();
    // c-none has no [checks]: the break loads are its check (as `run` says "PASS: no break
    // load exceeded"), passed.
    assert_eq!(pass, [&serde_json::json!(true), &serde_json::json!(false), &serde_json::json!(true)]);
    for r in json.as_array().unwrap() {
        assert!(r["cpu_time"].as_f64().is_some() && r["rhs_evaluations"].as_u64().unwrap() > 0, "{r}");
    }
    let csv = std::fs::read_to_string(out_dir.join("batch.csv")).unwrap();
    let head: Vec<&str> = csv.lines().next().unwrap().split(',').collect();
    let col = head.iter().position(|h| *h == "checks").expect("checks column");
    let cells: Vec<&str> = csv.lines().skip(1).map(|l| l.split(',').nth(col).unwrap()).collect();
    assert_eq!(cells, ["pass", "fail", "pass"]);
    // Beside it, every column's unit and meaning, in the CSV's order.
    let units = std::fs::read_to_string(out_dir.join("batch.units.csv")).unwrap();
    let listed: Vec<&str> = units.lines().skip(1).map(|l| l.split(',').next().unwrap()).collect();
    assert_eq!(listed, head);
    assert!(units.starts_with("column,unit,description\n") && units.contains("\npeak_tension,N,"), "{units}");

    // `run` of the failing scene names each [checks] limit with its value in the summary,
    // beside the break-load line, and exits 4.
    let out = kanestop().arg("run").arg(scenes.join("b-fail.toml")).output().unwrap();
    let (stdout, stderr) = text(&out);
    assert_eq!(out.status.code(), Some(4), "{stdout}{stderr}");
    // One verdict over the break loads and the [checks] (a PASS line for the break loads
    // followed by a FAIL line for [checks] read as a contradiction).
    assert!(
        stdout.contains("checks    FAIL: 1 of 3 failed\n          break loads: no break load exceeded"),
        "{stdout}"
    );
    assert_eq!(stdout.matches("checks    ").count(), 1, "{stdout}");
    assert!(stdout.contains("\n          max_anchor_drag = 100 m: dragged 0.00 m (pass)\n"), "{stdout}");
    assert!(
        stdout.contains("\n          max_stopping_time = 30 s: no value as the run did not reach it (FAIL)\n"),
        "{stdout}"
    );
    let out = kanestop().arg("run").arg(scenes.join("a-pass.toml")).output().unwrap();
    let stdout = text(&out).0;
    assert!(stdout.contains("checks    PASS: 0 of 2 failed\n"), "{stdout}");
    assert!(stdout.contains("\n          max_anchor_drag = 100 m: dragged 0.00 m (pass)\n"), "{stdout}");

    std::fs::write(scenes.join("d-bad.toml"), "not a scene").unwrap();
    let out = kanestop().arg("batch").arg(&scenes).arg("--out").arg(&out_dir).output().unwrap();
    assert_eq!(out.status.code(), Some(1));
}

/// Every file a command writes is checked before the work: a folder where a file goes (or a
/// file where a folder goes), a pipe, `--out` and `--plot` on one path. Nothing is run and
/// nothing is written (exit 2).
#[test]
fn exit_2_an_output_that_cannot_be_written_is_found_before_the_work() {
    let dir = temp_dir("targets");
    let scene = scene(&dir, "s", |t| t);
    std::fs::create_dir_all(dir.join("a/h.units.csv")).unwrap();
    std::fs::create_dir_all(dir.join("b/batch.json")).unwrap();
    std::fs::create_dir_all(dir.join("c")).unwrap();
    std::fs::write(dir.join("c/scenes"), "a file where the sweep's folder goes").unwrap();
    std::fs::create_dir_all(dir.join("d/sweep.units.csv")).unwrap();
    let scenes = dir.join("scenes");
    std::fs::create_dir_all(&scenes).unwrap();
    std::fs::copy(&scene, scenes.join("s.toml")).unwrap();
    let spec = dir.join("spec.toml");
    std::fs::write(&spec, format!("base = {:?}\n[[axis]]\npath = \"ship.mass\"\nvalues = [5e5]\n", scene)).unwrap();
    let s = scene.to_str().unwrap();
    let p = |rel: &str| dir.join(rel).to_str().unwrap().to_string();
    let cases: [(Vec<String>, &str); 8] = [
        (vec!["run".into(), s.into(), "--out".into(), p("a/h.csv")], "a/h.units.csv"),
        (
            vec!["run".into(), s.into(), "--out".into(), p("c/h"), "--plot".into(), p("c/h")],
            "a file cannot hold a folder",
        ),
        // Under the file, in a folder the run would create: refused before the run too.
        (
            vec!["run".into(), s.into(), "--out".into(), p("new/h.csv"), "--plot".into(), p("new/h.csv/plots")],
            "is at or under",
        ),
        // The same reached through `..`, and a plot of the history's own name.
        (
            vec!["run".into(), s.into(), "--out".into(), p("new/h.csv"), "--plot".into(), p("new/../new/h.csv/p")],
            "is at or under",
        ),
        (
            vec!["run".into(), s.into(), "--out".into(), p("new/energy.svg"), "--plot".into(), p("new")],
            "a plot of the same name",
        ),
        (
            vec!["batch".into(), scenes.to_str().unwrap().into(), "--out".into(), p("b")],
            "batch.json exists and is not a regular file",
        ),
        (
            vec!["sweep".into(), spec.to_str().unwrap().into(), "--out".into(), p("c")],
            "scenes exists and is not a folder",
        ),
        (
            vec!["sweep".into(), spec.to_str().unwrap().into(), "--out".into(), p("d")],
            "sweep.units.csv exists and is not a regular file",
        ),
    ];
    for (args, message) in cases {
        let out = kanestop().args(&args).output().unwrap();
        let (stdout, stderr) = text(&out);
        assert_eq!(out.status.code(), Some(2), "{args:?}: {stdout}{stderr}");
        assert!(stderr.contains(message), "{args:?}: {stderr}");
    }
    assert!(!dir.join("a/h.csv").exists() && !dir.join("b/batch.csv").exists() && !dir.join("c/sweep.csv").exists());
    assert!(!dir.join("d/sweep.csv").exists());
    assert!(!dir.join("new").exists(), "refused before anything is written");
}

//! Sharded sweeps (docs/sweeps.md, "Sharded sweeps"): the merge of N shards is the local
//! run, file for file (every byte but the wall times), for N = 1, 3 and 7 over 11 rows (a
//! count neither 3 nor 7 divides); a merge refuses shards of another sweep, a missing shard
//! and a row held twice; a shard killed halfway and resumed gives the same result.

mod scratch;
use scratch::Scratch;

use std::path::{Path, PathBuf};
use std::process::{Command, Output, Stdio};
use std::sync::OnceLock;
use std::time::{Duration, Instant};

use serde_json::Value;

fn kanestop() -> Command {
    Command::new(env!("CARGO_BIN_EXE_kanestop"))
}

/// The test's scratch folder, removed when it passes (tests/scratch).
fn temp_dir(name: &str) -> Scratch {
    Scratch::new(&format!("shards-{name}"))
}

/// A spec of 11 short rows over case 1: ten anchor masses and one invalid (negative) one;
/// the drag check fails for the lighter anchors.
fn spec(dir: &Path, end_time: f64) -> PathBuf {
    let base = Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes/paper/case01.toml");
    let path = dir.join("spec.toml");
    let text = format!(
        "base = {:?}\nname = \"shards\"\n[solver]\nend_time = {end_time:?}\n[[axis]]\npath = \"anchor.mass\"\n\
         values = [30000.0, 32000.0, 34000.0, 36000.0, -1.0, 40000.0, 42000.0, 44000.0, 46000.0, 48000.0, 50000.0]\n\
         [checks]\nmax_anchor_drag = 3.6\n",
        base.display().to_string()
    );
    std::fs::write(&path, text).unwrap();
    path
}

fn run(args: &[&str], env: &[(&str, String)]) -> Output {
    let mut c = kanestop();
    c.args(args);
    for v in ["SLURM_ARRAY_TASK_ID", "SLURM_ARRAY_TASK_COUNT", "JOB_COMPLETION_INDEX", "PBS_ARRAY_INDEX"] {
        c.env_remove(v);
    }
    for (k, v) in env {
        c.env(k, v);
    }
    c.output().unwrap()
}

fn s(p: &Path) -> &str {
    p.to_str().unwrap()
}

fn stderr(o: &Output) -> String {
    String::from_utf8_lossy(&o.stderr).into_owned()
}

/// The table and check summary a command printed, without the line naming the files.
fn table(o: &Output) -> String {
    String::from_utf8_lossy(&o.stdout).lines().filter(|l| !l.starts_with("written")).collect::<Vec<_>>().join("\n")
}

/// The local run of the 11-row spec: (folder, its output), made once, in cargo's folder for
/// the tests' files (shared by the tests, it outlives each of them).
fn local() -> &'static (PathBuf, Output) {
    static LOCAL: OnceLock<(PathBuf, Output)> = OnceLock::new();
    LOCAL.get_or_init(|| {
        let dir = Path::new(env!("CARGO_TARGET_TMPDIR")).join(format!("shards-local-{}", std::process::id()));
        let _ = std::fs::remove_dir_all(&dir);
        std::fs::create_dir_all(&dir).unwrap();
        let out = dir.join("out");
        let o = run(&["sweep", s(&spec(&dir, 3.0)), "--out", s(&out)], &[]);
        assert_eq!(o.status.code(), Some(3), "an invalid row: exit 3; {}", stderr(&o));
        (out, o)
    })
}

/// `sweep.csv` with the `wall_time` and `cpu_time` columns emptied (quoted cells kept whole).
fn csv_without_wall_time(path: &Path) -> String {
    let text = std::fs::read_to_string(path).unwrap();
    let split = |line: &str| -> Vec<String> {
        let (mut cells, mut cell, mut quoted) = (Vec::new(), String::new(), false);
        for c in line.chars() {
            match c {
                '"' => {
                    quoted = !quoted;
                    cell.push(c);
                }
                ',' if !quoted => cells.push(std::mem::take(&mut cell)),
                _ => cell.push(c),
            }
        }
        cells.push(cell);
        cells
    };
    let mut lines = text.lines();
    let head = split(lines.next().unwrap());
    let col = head.iter().position(|h| h == "wall_time").expect("a wall_time column");
    let cpu = head.iter().position(|h| h == "cpu_time").expect("a cpu_time column");
    let mut out = vec![head.join(",")];
    for line in lines {
        let mut cells = split(line);
        cells[col].clear();
        cells[cpu].clear();
        out.push(cells.join(","));
    }
    out.join("\n")
}

/// `sweep.json` without the `wall_time` and `cpu_time` of each row's summary.
fn json_without_wall_time(path: &Path) -> Value {
    let mut rows: Value = serde_json::from_str(&std::fs::read_to_string(path).unwrap()).unwrap();
    for r in rows.as_array_mut().unwrap() {
        if let Some(summary) = r["summary"].as_object_mut() {
            assert!(summary.remove("wall_time").is_some());
            assert!(summary.remove("cpu_time").is_some());
        }
    }
    rows
}

fn files(dir: &Path) -> Vec<(String, Vec<u8>)> {
    let mut out: Vec<(String, Vec<u8>)> = std::fs::read_dir(dir)
        .unwrap()
        .map(|e| e.unwrap().path())
        .map(|p| (p.file_name().unwrap().to_string_lossy().into_owned(), std::fs::read(&p).unwrap()))
        .collect();
    out.sort();
    out
}

/// The merged folder `merged` (and the merge's output `o`) holds what the local run wrote.
fn assert_same_as_local(merged: &Path, o: &Output, local: &Path, local_output: &Output) {
    assert_eq!(o.status.code(), local_output.status.code(), "exit code; {}", stderr(o));
    assert_eq!(table(o), table(local_output), "the printed table and check summary");
    assert_eq!(csv_without_wall_time(&merged.join("sweep.csv")), csv_without_wall_time(&local.join("sweep.csv")));
    assert_eq!(json_without_wall_time(&merged.join("sweep.json")), json_without_wall_time(&local.join("sweep.json")));
    let scenes = files(&merged.join("scenes"));
    assert_eq!(scenes.len(), 10, "one scene per valid row");
    assert_eq!(scenes, files(&local.join("scenes")), "every scene file, byte for byte");
}

/// Runs every shard of `n` into `out`, shard k as `how(k)` says (flag or environment).
fn run_shards(spec: &Path, out: &Path, n: usize, how: impl Fn(usize) -> (Vec<String>, Vec<(&'static str, String)>)) {
    for k in 0..n {
        let (extra, env) = how(k);
        let mut args = vec!["sweep", s(spec), "--out", s(out)];
        args.extend(extra.iter().map(String::as_str));
        let o = run(&args, &env);
        assert!(matches!(o.status.code(), Some(0 | 3 | 4)), "shard {k}/{n}: {}", stderr(&o));
        let file: Value =
            serde_json::from_slice(&std::fs::read(out.join(format!("shards/shard-{k}-of-{n}.json"))).unwrap()).unwrap();
        let expected: Vec<usize> = (k..11).step_by(n).collect();
        assert_eq!(file["row_indices"], serde_json::json!(expected));
        assert_eq!(file["complete"], true);
        assert_eq!(file["rows_total"], 11);
    }
}

fn merge(dirs: &[&Path]) -> Output {
    let mut args = vec!["sweep", "merge"];
    args.extend(dirs.iter().map(|d| s(d)));
    run(&args, &[])
}

#[test]
fn one_shard_merged_is_the_local_run() {
    let (local_out, local_output) = local();
    let dir = temp_dir("n1");
    let out = dir.join("out");
    run_shards(&spec(&dir, 3.0), &out, 1, |k| (vec!["--shard".into(), format!("{k}/1")], vec![]));
    let o = merge(&[&out]);
    assert_same_as_local(&out, &o, local_out, local_output);
}

#[test]
fn three_shards_merged_are_the_local_run_whichever_index_variable_gives_the_shard() {
    let (local_out, local_output) = local();
    let dir = temp_dir("n3");
    let out = dir.join("out");
    run_shards(&spec(&dir, 3.0), &out, 3, |k| match k {
        0 => (vec!["--shard".into(), "0/3".into()], vec![]),
        1 => (vec!["--shards".into(), "3".into()], vec![("JOB_COMPLETION_INDEX", "1".into())]),
        _ => (vec!["--shards".into(), "3".into()], vec![("PBS_ARRAY_INDEX", "2".into())]),
    });
    let merged = dir.join("merged");
    let mut o = merge(&[&out]);
    assert!(o.status.code() != Some(2), "{}", stderr(&o));
    // Into another folder, from the shard files named one by one.
    let files: Vec<PathBuf> = (0..3).map(|k| out.join(format!("shards/shard-{k}-of-3.json"))).collect();
    let mut args = vec!["sweep", "merge", "--out", s(&merged)];
    args.extend(files.iter().rev().map(|f| s(f)));
    o = run(&args, &[]);
    assert_same_as_local(&merged, &o, local_out, local_output);
    assert_same_as_local(&out, &o, local_out, local_output);
}

#[test]
fn seven_shards_of_a_slurm_array_merged_are_the_local_run() {
    let (local_out, local_output) = local();
    let dir = temp_dir("n7");
    let out = dir.join("out");
    // An array submitted as --array=1-7: the index is relative to SLURM_ARRAY_TASK_MIN.
    run_shards(&spec(&dir, 3.0), &out, 7, |k| {
        let env = vec![
            ("SLURM_ARRAY_TASK_ID", (k + 1).to_string()),
            ("SLURM_ARRAY_TASK_MIN", "1".to_string()),
            ("SLURM_ARRAY_TASK_COUNT", "7".to_string()),
        ];
        (vec!["--jobs".into(), "1".into(), "--shards".into(), "7".into()], env)
    });
    let o = merge(&[&out]);
    assert_same_as_local(&out, &o, local_out, local_output);
}

/// A task of a Slurm array takes its shard only with --shards N: a sweep run whole in each
/// task of an array (one spec per task) ran only its shard's rows and wrote a shard file
/// where the sweep's files were expected. Refused without it, naming both ways; `--shard
/// none` runs the whole sweep there.
#[test]
fn a_slurm_task_takes_its_shard_only_with_shards() {
    let dir = temp_dir("array-task");
    let spec = spec(&dir, 2.0);
    let env = [("SLURM_ARRAY_TASK_ID", "1".to_string()), ("SLURM_ARRAY_TASK_COUNT", "5".to_string())];
    let out = dir.join("refused");
    let o = run(&["sweep", s(&spec), "--out", s(&out)], &env);
    assert_eq!(o.status.code(), Some(2), "{}", stderr(&o));
    assert!(stderr(&o).contains("SLURM_ARRAY_TASK_ID = 1: set: give --shards N"), "{}", stderr(&o));
    assert!(stderr(&o).contains("--shard none"), "{}", stderr(&o));
    assert!(!out.exists(), "nothing written");
    let whole = dir.join("whole");
    let o = run(&["sweep", s(&spec), "--out", s(&whole), "--shard", "none"], &env);
    // (This spec's rows include an invalid one, anchor.mass = -1: exit 3, a result, not a refusal.)
    assert!(matches!(o.status.code(), Some(0 | 3 | 4)), "{:?} {}", o.status, stderr(&o));
    assert!(whole.join("sweep.csv").is_file() && !whole.join("shards").exists(), "the whole sweep, unsharded");
}

#[test]
fn a_merge_refuses_another_sweep_a_missing_shard_and_a_row_twice() {
    let dir = temp_dir("refuse");
    let out = dir.join("out");
    let spec_a = spec(&dir, 3.0);
    run_shards(&spec_a, &out, 3, |k| (vec!["--shard".into(), format!("{k}/3")], vec![]));
    let other = temp_dir("refuse-other");
    let o = run(&["sweep", s(&spec(&other, 2.5)), "--out", s(&other), "--shard", "1/3"], &[]);
    assert!(o.status.code() != Some(2), "{}", stderr(&o));
    let (a1, b1) = (out.join("shards/shard-1-of-3.json"), other.join("shards/shard-1-of-3.json"));
    let hash = |p: &Path| -> String {
        let v: Value = serde_json::from_slice(&std::fs::read(p).unwrap()).unwrap();
        v["plan_hash"].as_str().unwrap().to_string()
    };
    assert!(hash(&a1).starts_with("sha256:") && hash(&a1).len() == 7 + 64);
    assert_ne!(hash(&a1), hash(&b1), "another end time, another plan");

    // Another sweep's shard.
    let o = run(
        &["sweep", "merge", s(&out.join("shards/shard-0-of-3.json")), s(&b1), s(&out.join("shards/shard-2-of-3.json"))],
        &[],
    );
    assert_eq!(o.status.code(), Some(2));
    let e = stderr(&o);
    assert!(e.contains("belong to different sweeps"), "{e}");
    for part in [hash(&a1), hash(&b1), s(&b1).to_string(), "shard-0-of-3.json".to_string()] {
        assert!(e.contains(&part), "{part} in {e}");
    }
    assert!(!out.join("sweep.csv").exists(), "a refused merge writes nothing");

    // A missing shard.
    let o = run(
        &["sweep", "merge", s(&out.join("shards/shard-0-of-3.json")), s(&out.join("shards/shard-2-of-3.json"))],
        &[],
    );
    assert_eq!(o.status.code(), Some(2));
    let e = stderr(&o);
    assert!(e.contains("4 of the sweep's 11 rows are missing (row 1, 4, 7, 10): no file shard-1-of-3.json"), "{e}");

    // A row twice: the whole sweep as one shard beside its three shards.
    let o = run(&["sweep", s(&spec_a), "--out", s(&out), "--shard", "0/1"], &[]);
    assert!(o.status.code() != Some(2), "{}", stderr(&o));
    let o = merge(&[&out]);
    assert_eq!(o.status.code(), Some(2));
    let e = stderr(&o);
    assert!(e.contains("row 0 (shards-000) is there twice: in "), "{e}");
    assert!(e.contains("shard-0-of-1.json") && e.contains("shard-0-of-3.json"), "{e}");

    // Not a shard file; no shard file at all.
    let o = run(&["sweep", "merge", s(&spec_a)], &[]);
    assert!(o.status.code() == Some(2) && stderr(&o).contains("not JSON"), "{}", stderr(&o));
    let o = merge(&[&temp_dir("refuse-empty")]);
    assert!(o.status.code() == Some(2) && stderr(&o).contains("no shard file in"), "{}", stderr(&o));
    // A heat map asked of a merge without the spec that gives its axes (it was ignored).
    let o = run(&["sweep", "merge", s(&out), "--heatmap", "stopping_time"], &[]);
    assert!(
        o.status.code() == Some(2) && stderr(&o).contains("--heatmap stopping_time without --spec"),
        "{}",
        stderr(&o)
    );
}

#[test]
fn a_merge_refuses_edited_shard_files_without_a_panic() {
    let dir = temp_dir("edited");
    let out = dir.join("out");
    let spec_path = spec(&dir, 3.0);
    run_shards(&spec_path, &out, 1, |k| (vec!["--shard".into(), format!("{k}/1")], vec![]));
    let good: Value = serde_json::from_slice(&std::fs::read(out.join("shards/shard-0-of-1.json")).unwrap()).unwrap();
    let edited = |name: &str, edit: &dyn Fn(&mut Value)| -> PathBuf {
        let mut v = good.clone();
        edit(&mut v);
        let path = dir.join(name);
        std::fs::write(&path, serde_json::to_vec(&v).unwrap()).unwrap();
        path
    };
    let refused = |files: &[&Path], part: &str| {
        let mut args = vec!["sweep", "merge"];
        args.extend(files.iter().map(|f| s(f)));
        let o = run(&args, &[]);
        assert_eq!(o.status.code(), Some(2), "{}", stderr(&o));
        assert!(stderr(&o).contains(part), "{part:?} in {}", stderr(&o));
    };
    refused(&[&edited("count0.json", &|v| v["shard"]["count"] = 0.into())], "N in [1, 1000000]");
    refused(&[&edited("index9.json", &|v| v["shard"]["index"] = 9.into())], "K in [0, 0]");
    refused(
        &[&edited("huge.json", &|v| v["rows_total"] = 1_000_000_000_000u64.into())],
        "rows_total = 1000000000000: at most 1000000",
    );
    // Two files of one plan hash that disagree on the sweep's size.
    let a = edited("a.json", &|v| {
        v["shard"] = serde_json::json!({"index": 0, "count": 2});
        v["rows_total"] = 4.into();
        v["row_indices"] = serde_json::json!([0, 2]);
        v["rows"] = serde_json::json!([]);
    });
    let b = edited("b.json", &|v| {
        v["shard"] = serde_json::json!({"index": 1, "count": 2});
        v["rows_total"] = 2.into();
        v["row_indices"] = serde_json::json!([1]);
        v["rows"] = serde_json::json!([]);
    });
    refused(&[&a, &b], "rows_total = 2, but");
    // Rows edited under the plan hash: the merge with the spec checks each against the plan.
    let with_spec =
        |file: &Path| run(&["sweep", "merge", s(file), "--spec", s(&spec_path), "--out", s(&dir.join("m"))], &[]);
    let scene = edited("scene.json", &|v| {
        let text = v["rows"][0]["scene"].as_str().unwrap().replace("mass = 30000.0", "mass = 31000.0");
        v["rows"][0]["scene"] = text.into();
    });
    let o = with_spec(&scene);
    assert_eq!(o.status.code(), Some(2), "{}", stderr(&o));
    assert!(stderr(&o).contains("row 0 (shards-000): its scene file, not the plan's"), "{}", stderr(&o));
    let message = edited("message.json", &|v| v["rows"][4]["row"]["message"] = "fine".into());
    let o = with_spec(&message);
    assert!(stderr(&o).contains("row 4 (shards-004): its message \"fine\", not the plan's"), "{}", stderr(&o));
    assert!(!dir.join("m/sweep.csv").exists(), "a refused merge writes nothing");
    let empty = edited("empty.json", &|v| {
        v["rows_total"] = 0.into();
        v["row_indices"] = serde_json::json!([]);
        v["rows"] = serde_json::json!([]);
    });
    let o = with_spec(&empty);
    assert_eq!(o.status.code(), Some(2), "{}", stderr(&o));
    assert!(stderr(&o).contains("0 rows in all, not the plan's"), "{}", stderr(&o));
    let inputs = edited("inputs.json", &|v| v["rows"][1]["row"]["label"] = "anchor.mass=1".into());
    assert!(stderr(&with_spec(&inputs)).contains("row 1 (shards-001): its inputs \"anchor.mass=1\""));
    // The file as written merges: the invalid row gives exit 3, as the local run.
    let o = with_spec(&out.join("shards/shard-0-of-1.json"));
    assert_eq!(o.status.code(), Some(3), "{}", stderr(&o));
    assert!(dir.join("m/sweep.csv").exists());
    // --resume checks the rows it keeps before running the rest.
    std::fs::copy(&scene, out.join("shards/shard-0-of-1.json")).unwrap();
    let o = run(&["sweep", s(&spec_path), "--out", s(&out), "--shard", "0/1", "--resume"], &[]);
    assert_eq!(o.status.code(), Some(2), "{}", stderr(&o));
    assert!(stderr(&o).contains("row 0 (shards-000): its scene file, not the plan's"), "{}", stderr(&o));
}

#[test]
fn a_shard_killed_halfway_resumes_to_the_same_result() {
    // Rows of about 0.3 s each, one at a time, saved after every row.
    let dir = temp_dir("kill");
    let spec = spec(&dir, 15.0);
    let local = dir.join("local");
    let local_output = run(&["sweep", s(&spec), "--out", s(&local)], &[]);
    let out = dir.join("out");
    let file = out.join("shards/shard-0-of-2.json");
    let mut child = kanestop()
        .args(["sweep", s(&spec), "--out", s(&out), "--shard", "0/2", "--jobs", "1", "--checkpoint", "0"])
        .stdout(Stdio::null())
        .stderr(Stdio::null())
        .spawn()
        .unwrap();
    let start = Instant::now();
    let done = |v: &Value| v["rows"].as_array().map_or(0, Vec::len);
    loop {
        let saved = std::fs::read(&file).ok().and_then(|b| serde_json::from_slice::<Value>(&b).ok());
        if saved.as_ref().is_some_and(|v| done(v) >= 2) {
            break;
        }
        assert!(start.elapsed() < Duration::from_secs(60), "no row saved within 60 s");
        std::thread::sleep(Duration::from_millis(5));
    }
    child.kill().unwrap();
    child.wait().unwrap();
    // Whatever the moment of the kill, the file is whole: valid, incomplete.
    let saved: Value = serde_json::from_slice(&std::fs::read(&file).unwrap()).unwrap();
    assert_eq!(saved["complete"], false, "killed before its last row");
    assert!((2..6).contains(&done(&saved)), "{} of 6 rows", done(&saved));
    // Rows 0, 2, 4, … of which row 4 is invalid: kept only when it ran and did not fail.
    let kept = saved["rows"].as_array().unwrap().iter().filter(|r| r["row"]["status"] != "invalid").count();
    let names: Vec<String> = std::fs::read_dir(out.join("shards"))
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .filter(|n| !n.starts_with('.'))
        .collect();
    assert_eq!(names, ["shard-0-of-2.json"], "the shard file alone (besides a hidden temporary file of the kill)");

    let o = merge(&[&out]);
    assert_eq!(o.status.code(), Some(2));
    assert!(stderr(&o).contains("shard-0-of-2.json is incomplete"), "{}", stderr(&o));

    // The shard resumed: only its missing rows run.
    let o = run(&["sweep", s(&spec), "--out", s(&out), "--shard", "0/2", "--resume"], &[]);
    assert!(stderr(&o).contains(&format!("resume    {kept} rows kept from ")), "{}", stderr(&o));
    assert!(stderr(&o).contains(&format!(", {} run", 6 - kept)), "{}", stderr(&o));
    // Without a shard: every shard of the folder completed (here the absent 1/2), merged.
    let o = run(&["sweep", s(&spec), "--out", s(&out), "--resume"], &[]);
    assert!(stderr(&o).contains("resume    shard 0/2: 5 rows kept, 1 run"), "the invalid row again; {}", stderr(&o));
    assert!(stderr(&o).contains("resume    shard 1/2: 0 rows kept, 5 run"), "{}", stderr(&o));
    assert_same_as_local(&out, &o, &local, &local_output);
}

#[test]
fn the_slurm_script_names_the_array_the_task_and_the_merge() {
    let dir = temp_dir("slurm");
    let o = run(&["sweep", s(&spec(&dir, 3.0)), "--slurm", "--shards", "4", "--out", s(&dir.join("out"))], &[]);
    assert!(o.status.success(), "{}", stderr(&o));
    let script = String::from_utf8_lossy(&o.stdout);
    assert!(script.starts_with("#!/usr/bin/env bash\n"));
    assert!(script.contains("#SBATCH --array=0-3\n"), "{script}");
    assert!(script.contains("--shards 4 --resume"), "{script}");
    assert!(script.contains("--dependency=afterany:\"$array\""), "{script}");
    assert!(script.contains(" sweep merge "), "{script}");
    assert!(!stderr(&o).contains("MaxArraySize"), "{}", stderr(&o));
    // Above Slurm's default MaxArraySize (1001) the script is written, with a note.
    let big = dir.join("big.toml");
    let base = Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes/paper/case01.toml");
    let text = format!(
        "base = {:?}\n[[axis]]\npath = \"ship.mass\"\nrange = {{ from = 4e5, to = 6e5, steps = 1002 }}\n",
        base.display().to_string()
    );
    std::fs::write(&big, text).unwrap();
    let o = run(&["sweep", s(&big), "--slurm", "--shards", "1002", "--out", s(&dir.join("big"))], &[]);
    assert!(o.status.success(), "{}", stderr(&o));
    assert!(String::from_utf8_lossy(&o.stdout).contains("#SBATCH --array=0-1001\n"));
    assert!(stderr(&o).contains("note: --shards = 1002: above Slurm's default MaxArraySize, 1001"), "{}", stderr(&o));
    let o = run(&["sweep", s(&spec(&dir, 3.0)), "--slurm", "--shards", "12"], &[]);
    assert_eq!(o.status.code(), Some(2));
    assert!(stderr(&o).contains("--shards = 12: in [1, 11]"), "{}", stderr(&o));
    let o = run(&["sweep", s(&spec(&dir, 3.0)), "--shard", "7/7"], &[]);
    assert_eq!(o.status.code(), Some(2));
    assert!(stderr(&o).contains("--shard = 7/7: K in [0, 6]"), "{}", stderr(&o));
}

/// What the array's tasks or its merge would refuse only after running is refused when the
/// script is written: an output folder that is a file, shard files there of another shard
/// count or of another sweep.
#[test]
fn the_slurm_script_is_refused_for_a_folder_its_jobs_could_not_finish_in() {
    let dir = temp_dir("slurm-out");
    let file = dir.join("afile");
    std::fs::write(&file, "").unwrap();
    let o = run(&["sweep", s(&spec(&dir, 3.0)), "--slurm", "--out", s(&file)], &[]);
    assert_eq!(o.status.code(), Some(2), "{}", stderr(&o));
    assert!(stderr(&o).contains("not a folder"), "{}", stderr(&o));
    // One shard of 2 already run into the folder: an array of 4 would not merge with it.
    let out = dir.join("out");
    let o = run(&["sweep", s(&spec(&dir, 0.02)), "--out", s(&out), "--shard", "0/2"], &[]);
    assert!(matches!(o.status.code(), Some(0 | 3 | 4)), "{}", stderr(&o));
    let o = run(&["sweep", s(&spec(&dir, 0.02)), "--slurm", "--shards", "4", "--out", s(&out)], &[]);
    assert_eq!(o.status.code(), Some(2), "{}", stderr(&o));
    assert!(
        stderr(&o).contains("shard-0-of-2.json: shard 0/2 of this sweep, and the array would write shards of 4"),
        "{}",
        stderr(&o)
    );
    assert!(stderr(&o).contains("give --shards 2"), "{}", stderr(&o));
    let o = run(&["sweep", s(&spec(&dir, 0.02)), "--slurm", "--shards", "2", "--out", s(&out)], &[]);
    assert!(o.status.success(), "the array resumes the shard: {}", stderr(&o));
    // Another sweep's shard (another end time) in the folder.
    let o = run(&["sweep", s(&spec(&dir, 0.04)), "--slurm", "--shards", "2", "--out", s(&out)], &[]);
    assert_eq!(o.status.code(), Some(2), "{}", stderr(&o));
    assert!(stderr(&o).contains("belong to different sweeps"), "{}", stderr(&o));
}

#[test]
fn the_plan_hash_depends_on_the_plan_and_kernel_not_on_where_or_how_it_runs() {
    let hash_of = |dir: &Path, extra: &[&str]| -> String {
        let (out, spec) = (dir.join("out"), dir.join("spec.toml"));
        let mut args = vec!["sweep", s(&spec), "--out", s(&out), "--shard", "0/11"];
        args.extend(extra);
        let o = run(&args, &[]);
        assert!(o.status.code() != Some(2), "{}", stderr(&o));
        let v: Value = serde_json::from_slice(&std::fs::read(out.join("shards/shard-0-of-11.json")).unwrap()).unwrap();
        v["plan_hash"].as_str().unwrap().to_string()
    };
    let (a, b_root, c) = (temp_dir("hash-a"), temp_dir("hash-b"), temp_dir("hash-c"));
    let b = b_root.join("deeper");
    std::fs::create_dir_all(&b).unwrap();
    spec(&a, 3.0);
    spec(&b, 3.0);
    spec(&c, 3.0);
    let h = hash_of(&a, &[]);
    assert_eq!(hash_of(&b, &["--jobs", "1"]), h, "another folder, another thread count: the same plan");
    assert_ne!(hash_of(&c, &["--kernel", "reference"]), h, "another kernel");
}

/// A two-axis sweep: merged with `--spec`, the shards give the local run's heat maps byte for
/// byte; a spec that is not the shards' is refused, naming it.
#[test]
fn merge_with_the_spec_draws_the_local_heat_maps() {
    let dir = temp_dir("heat");
    let base = Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes/paper/case01.toml");
    let spec_text = |masses: &str| {
        format!(
            "base = {:?}\nname = \"heat\"\n[solver]\nend_time = 1.0\n[[axis]]\npath = \"anchor.mass\"\nvalues = {masses}\n\
             [[axis]]\npath = \"initial.ship_speed\"\nvalues = [2.0, 3.0]\n[checks]\nmax_anchor_drag = 0.5\n",
            base.display().to_string()
        )
    };
    let (spec, other) = (dir.join("spec.toml"), dir.join("other.toml"));
    std::fs::write(&spec, spec_text("[30000.0, 40000.0]")).unwrap();
    std::fs::write(&other, spec_text("[30000.0, 41000.0]")).unwrap();
    let (local, sharded) = (dir.join("local"), dir.join("sharded"));
    let o = run(&["sweep", s(&spec), "--out", s(&local)], &[]);
    assert!(matches!(o.status.code(), Some(0 | 4)), "{}", stderr(&o));
    for k in 0..2 {
        let o = run(&["sweep", s(&spec), "--out", s(&sharded), "--shard", &format!("{k}/2")], &[]);
        assert!(matches!(o.status.code(), Some(0 | 4)), "{}", stderr(&o));
    }
    let o = run(&["sweep", "merge", s(&sharded), "--spec", s(&other)], &[]);
    assert_eq!(o.status.code(), Some(2), "another spec is refused");
    assert!(stderr(&o).contains("other.toml") && stderr(&o).contains("plan"), "{}", stderr(&o));
    let o = run(&["sweep", "merge", s(&sharded), "--spec", s(&spec)], &[]);
    assert!(matches!(o.status.code(), Some(0 | 4)), "{}", stderr(&o));
    let maps = |d: &Path| -> Vec<(String, Vec<u8>)> {
        let mut out: Vec<(String, Vec<u8>)> = std::fs::read_dir(d)
            .unwrap()
            .map(|e| e.unwrap().path())
            .filter(|p| p.file_name().unwrap().to_string_lossy().starts_with("heatmap-"))
            .map(|p| (p.file_name().unwrap().to_string_lossy().into_owned(), std::fs::read(&p).unwrap()))
            .collect();
        out.sort();
        out
    };
    let local_maps = maps(&local);
    assert_eq!(local_maps.len(), 3, "the three default heat maps");
    assert_eq!(maps(&sharded), local_maps, "the merge's heat maps, byte for byte");
}

/// `--resume` without a shard draws the heat maps a local run draws, byte for byte; a sweep
/// into a folder that held another removes that one's row scenes and heat maps, and says so.
#[test]
fn a_resumed_sweep_draws_its_heat_maps_and_a_folder_holds_one_sweep() {
    let dir = temp_dir("resume-maps");
    let base = Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes/paper/case01.toml");
    let write = |name: &str, axes: &str| {
        let path = dir.join(format!("{name}.toml"));
        let text =
            format!("base = {:?}\nname = \"{name}\"\n[solver]\nend_time = 1.0\n{axes}", base.display().to_string());
        std::fs::write(&path, text).unwrap();
        path
    };
    let axis = |p: &str, v: &str| format!("[[axis]]\npath = \"{p}\"\nvalues = [{v}]\n");
    let grid = write("grid", &(axis("anchor.mass", "30000.0, 40000.0") + &axis("ship.mass", "4e5, 5e5")));
    let (local, resumed) = (dir.join("local"), dir.join("resumed"));
    assert!(run(&["sweep", s(&grid), "--out", s(&local)], &[]).status.success());
    let o = run(&["sweep", s(&grid), "--out", s(&resumed), "--resume"], &[]);
    assert!(o.status.success(), "{}", stderr(&o));
    let maps = |d: &Path| -> Vec<String> {
        let mut names: Vec<String> = std::fs::read_dir(d)
            .unwrap()
            .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
            .filter(|n| n.starts_with("heatmap-"))
            .collect();
        names.sort();
        names
    };
    assert_eq!(maps(&resumed).len(), 3, "the default three");
    assert_eq!(maps(&resumed), maps(&local));
    for m in maps(&local) {
        assert_eq!(std::fs::read(resumed.join(&m)).unwrap(), std::fs::read(local.join(&m)).unwrap(), "{m}");
    }
    // Another sweep into the local run's folder: one axis, no heat map, two rows.
    let line = write("line", &axis("anchor.mass", "30000.0, 40000.0"));
    let o = run(&["sweep", s(&line), "--out", s(&local)], &[]);
    assert!(o.status.success(), "{}", stderr(&o));
    let stdout = String::from_utf8_lossy(&o.stdout);
    assert!(stdout.contains("removed   an earlier sweep's files this one did not write:"), "{stdout}");
    assert!(stdout.contains("(7 in all)"), "4 scenes and 3 maps: {stdout}");
    assert!(maps(&local).is_empty());
    assert_eq!(files(&local.join("scenes")).len(), 2, "line-000 and line-001 only");
}

/// A shard run into a folder whose shard file of that shard belongs to another sweep is
/// refused (exit 2), that file untouched; the same sweep's shard runs again over its own.
#[test]
fn a_shard_does_not_write_over_another_sweep_s() {
    let dir = temp_dir("other-shard");
    let out = dir.join("out");
    let a = spec(&dir, 1.0);
    assert_ne!(run(&["sweep", s(&a), "--out", s(&out), "--shard", "0/3"], &[]).status.code(), Some(2));
    let file = out.join("shards/shard-0-of-3.json");
    let before = std::fs::read(&file).unwrap();
    let other = temp_dir("other-shard-b");
    let b = spec(&other, 1.5);
    let o = run(&["sweep", s(&b), "--out", s(&out), "--shard", "0/3"], &[]);
    assert_eq!(o.status.code(), Some(2), "{}", stderr(&o));
    assert!(stderr(&o).contains("belong to different sweeps"), "{}", stderr(&o));
    assert_eq!(std::fs::read(&file).unwrap(), before, "the other sweep's file is untouched");
    assert_ne!(run(&["sweep", s(&a), "--out", s(&out), "--shard", "0/3"], &[]).status.code(), Some(2));
}

/// SIGTERM (a scheduler's time limit, `scancel`) stops a shard's runs at their next step,
/// saves the rows done in its file (not complete) and ends the process by the signal;
/// `--resume` then runs only the rest. Before, a task killed between checkpoints (every 10 s
/// by default; here every 1000 s) lost every row since the last.
#[test]
fn a_shard_stopped_by_sigterm_saves_its_rows() {
    use std::io::{BufRead, BufReader};
    use std::os::unix::process::ExitStatusExt;
    let dir = temp_dir("sigterm");
    let base = Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes/paper/case01.toml");
    let spec = dir.join("slow.toml");
    let masses = "4e5, 4.5e5, 5e5, 5.5e5, 6e5, 6.5e5, 7e5, 7.5e5";
    let text = format!(
        "base = {:?}\nname = \"slow\"\n[solver]\nend_time = 20.0\ndt = 0.0001\n[[axis]]\npath = \"ship.mass\"\nvalues = [{masses}]\n",
        base.display().to_string()
    );
    std::fs::write(&spec, text).unwrap();
    let out = dir.join("out");
    let mut child = kanestop()
        .args(["sweep", s(&spec), "--out", s(&out), "--shard", "0/1", "--jobs", "1", "--checkpoint", "1000"])
        .stderr(std::process::Stdio::piped())
        .stdout(std::process::Stdio::null())
        .spawn()
        .unwrap();
    // Once the first row is done (the progress line), the task is told to end.
    let mut pipe = BufReader::new(child.stderr.take().unwrap());
    let mut seen = String::new();
    let mut line = String::new();
    while pipe.read_line(&mut line).unwrap() > 0 {
        seen.push_str(&line);
        if line.starts_with("progress  1/8") {
            // SAFETY: a signal to the child this test spawned.
            unsafe { libc::kill(child.id() as libc::pid_t, libc::SIGTERM) };
            break;
        }
        line.clear();
    }
    let mut rest = String::new();
    std::io::Read::read_to_string(&mut pipe, &mut rest).unwrap();
    seen.push_str(&rest);
    let status = child.wait().unwrap();
    assert_eq!(status.signal(), Some(libc::SIGTERM), "{status:?}\n{seen}");
    assert!(seen.contains("stopped   by SIGTERM:") && seen.contains("--resume"), "{seen}");
    let file: Value = serde_json::from_slice(&std::fs::read(out.join("shards/shard-0-of-1.json")).unwrap()).unwrap();
    let kept = file["rows"].as_array().unwrap().len();
    assert!(file["complete"] == false && (1..8).contains(&kept), "{kept} rows saved: {seen}");
    let o = run(&["sweep", s(&spec), "--out", s(&out), "--shard", "0/1", "--resume"], &[]);
    assert!(stderr(&o).contains(&format!("resume    {kept} rows kept")), "{}", stderr(&o));
}

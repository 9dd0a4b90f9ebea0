//! Structure-aware fuzzing of scenes (issue 15, item 5). Valid scenes (the paper's case 1 and
//! the stress scenes) are mutated line by line and table by table: every field set to
//! extreme and random values (zero, negative, NaN, ±∞, 1e±300, random magnitudes, wrong
//! types), lines removed and duplicated, tables removed and duplicated, random cable stages
//! and element counts. Each outcome must be a clean refusal (a parse error or problems that
//! name the file and a field), or a model whose laid line ends at (x_L, h_L) to 1e-9 m with
//! the ship at the origin and a short run that ends with a status: never a panic, an abort
//! or a hang.
//!
//! Bounded to about `KANESTOP_FUZZ_SECONDS` (default 45 s) with fixed seeds
//! (`KANESTOP_FUZZ_SEED` to start elsewhere). A failing scene is written to
//! `target/fuzz-failures/`; keep it in `tests/fuzz-corpus/`, which is replayed first, every
//! run.

use std::path::{Path, PathBuf};
use std::sync::mpsc;
use std::time::{Duration, Instant};

use kanestop_runtime::generated::GeneratedKernel;
use kanestop_runtime::kernel::Kernel;
use kanestop_runtime::model::Model;
use kanestop_runtime::reference::ReferenceKernel;
use kanestop_runtime::scene::{Scene, SceneError};
use kanestop_runtime::simulate;
use rand::rngs::StdRng;
use rand::{Rng, SeedableRng};

/// One scene's outcome is judged within this time, or it counts as a hang.
const CASE_TIMEOUT: Duration = Duration::from_secs(60);

fn root() -> &'static Path {
    Path::new(env!("CARGO_MANIFEST_DIR"))
}

/// Checks one scene text; `Err` says what was wrong.
fn judge(text: &str) -> Result<&'static str, String> {
    let scene = match Scene::from_toml(text, "fuzz.toml") {
        Err(SceneError::Parse { file, .. }) if file == "fuzz.toml" => return Ok("parse error"),
        Err(SceneError::Invalid { file, problems }) => {
            if file != "fuzz.toml" || problems.is_empty() || problems.iter().any(|p| p.field.is_empty()) {
                return Err(format!("refusal without file or field: {problems:?}"));
            }
            return Ok("refused");
        }
        Err(e) => return Err(format!("unexpected error: {e}")),
        Ok(scene) => scene,
    };
    let model = Model::new(&scene).map_err(|e| format!("accepted scene has no model: {e}"))?;
    let gap = model.cable_end_error();
    if gap.is_nan() || gap > 1e-9 {
        return Err(format!("accepted scene's line ends {gap} m from (x_L, h_L)"));
    }
    let n = model.body_count();
    let joints = model.initial_joints();
    let ship = &model.chain.bodies[n - 1];
    let centre = [joints[n - 1][0] + ship.centroid[0], joints[n - 1][1] + ship.centroid[1]];
    if centre[0].is_nan() || centre[1].is_nan() || centre[0].hypot(centre[1]) > 1e-9 {
        return Err(format!("accepted scene's ship starts at {centre:?}"));
    }
    if n > 120 {
        return Ok("accepted (too large to run here)");
    }
    // A short run: three observation intervals.
    let mut short = scene.clone();
    short.solver.end_time = 3.0 * short.solver.dt;
    let model = Model::new(&short).map_err(|e| format!("shortened scene has no model: {e}"))?;
    let kernel: Box<dyn Kernel> = match GeneratedKernel::new(&model.chain) {
        Ok(k) => Box::new(k),
        Err(_) => Box::new(ReferenceKernel::new(&model.chain)),
    };
    let _ = simulate::run(&model, kernel).stop;
    Ok("ran")
}

/// [`judge`] on its own thread, with a panic or a timeout as a failure.
fn judge_guarded(text: &str) -> Result<&'static str, String> {
    let (tx, rx) = mpsc::channel();
    let owned = text.to_string();
    std::thread::spawn(move || {
        let outcome = std::panic::catch_unwind(|| judge(&owned)).unwrap_or_else(|p| {
            let msg = p.downcast_ref::<String>().cloned().or_else(|| p.downcast_ref::<&str>().map(|s| s.to_string()));
            Err(format!("panic: {}", msg.unwrap_or_default()))
        });
        let _ = tx.send(outcome);
    });
    rx.recv_timeout(CASE_TIMEOUT).unwrap_or_else(|_| Err(format!("no outcome within {CASE_TIMEOUT:?}: a hang")))
}

/// The values a field is set to.
fn random_value(rng: &mut StdRng, old: &str) -> String {
    const EXTREMES: [&str; 16] = [
        "0", "0.0", "-1.0", "1e-300", "1e300", "nan", "inf", "-inf", "1", "2", "-0.0", "true", "\"x\"", "1e6", "3",
        "5e-324",
    ];
    let number = old.trim().parse::<f64>().ok();
    match rng.gen_range(0..4) {
        0 => EXTREMES[rng.gen_range(0..EXTREMES.len())].to_string(),
        1 if number.is_some() => {
            let v = number.unwrap_or(1.0) * 10f64.powf(rng.gen_range(-3.0..3.0));
            if old.contains('.') || old.contains('e') {
                format!("{v:?}")
            } else {
                format!("{}", v.round().abs() as u64)
            }
        }
        2 if number.is_some() => format!("{:?}", number.unwrap_or(0.0) * rng.gen_range(0.9..1.1)),
        _ => format!("{}", rng.gen_range(0..300)),
    }
}

/// Random `[[cable.stages]]` tables replacing the scene's.
fn random_stages(rng: &mut StdRng, text: &str) -> String {
    let mut lines: Vec<&str> = Vec::new();
    let mut skipping = false;
    for line in text.lines() {
        if line.starts_with('[') {
            skipping = line == "[[cable.stages]]";
        }
        if !skipping {
            lines.push(line);
        }
    }
    let mut out = lines.join("\n");
    for _ in 0..rng.gen_range(0..4) {
        let elements = if rng.gen_bool(0.1) { rng.gen_range(0..5000) } else { rng.gen_range(1..40) };
        out.push_str(&format!(
            "\n\n[[cable.stages]]\nelements = {elements}\nelement_length = {:?}\n",
            rng.gen_range(0.1..20.0)
        ));
    }
    out
}

/// A table `[name]` and its lines, removed or duplicated.
fn mutate_table(rng: &mut StdRng, text: &str) -> String {
    let headers: Vec<usize> = text.match_indices("\n[").map(|(i, _)| i + 1).collect();
    if headers.is_empty() {
        return text.to_string();
    }
    let k = rng.gen_range(0..headers.len());
    let (start, end) = (headers[k], headers.get(k + 1).copied().unwrap_or(text.len()));
    let block = &text[start..end];
    if rng.gen_bool(0.5) {
        format!("{}{}", &text[..start], &text[end..])
    } else {
        format!("{}{block}{}", &text[..end], &text[end..])
    }
}

/// One mutation of a valid scene.
fn mutate(rng: &mut StdRng, text: &str) -> String {
    let mut text = text.to_string();
    for _ in 0..rng.gen_range(1..4) {
        text = match rng.gen_range(0..10) {
            0 => mutate_table(rng, &text),
            1 => random_stages(rng, &text),
            kind => {
                let lines: Vec<String> = text.lines().map(str::to_string).collect();
                let fields: Vec<usize> = (0..lines.len()).filter(|&i| lines[i].contains(" = ")).collect();
                let i = fields[rng.gen_range(0..fields.len())];
                let mut lines = lines;
                match kind {
                    2 => {
                        lines.remove(i);
                    }
                    3 => {
                        let copy = lines[i].clone();
                        lines.insert(i, copy);
                    }
                    _ => {
                        let (key, old) =
                            lines[i].split_once(" = ").map(|(k, v)| (k.to_string(), v.to_string())).unwrap();
                        lines[i] = format!("{key} = {}", random_value(rng, &old));
                    }
                }
                lines.join("\n")
            }
        };
    }
    text
}

/// The valid scenes mutations start from.
fn seeds() -> Vec<String> {
    let mut out = vec![kanestop_runtime::paper::DEFAULT_SCENE.to_string()];
    let mut files: Vec<PathBuf> = std::fs::read_dir(root().join("scenes/stress"))
        .map(|d| d.filter_map(|e| e.ok().map(|e| e.path())).collect())
        .unwrap_or_default();
    files.sort();
    out.extend(files.iter().filter_map(|f| std::fs::read_to_string(f).ok()));
    out
}

fn save_failure(text: &str, why: &str, index: usize) -> PathBuf {
    let dir = root().join("target/fuzz-failures");
    let _ = std::fs::create_dir_all(&dir);
    let path = dir.join(format!("failure-{index}.toml"));
    let _ = std::fs::write(&path, format!("# {}\n{text}", why.replace('\n', " ")));
    path
}

#[test]
fn the_corpus_of_past_failures_is_refused_or_runs_physically() {
    let mut files: Vec<PathBuf> = std::fs::read_dir(root().join("tests/fuzz-corpus"))
        .expect("tests/fuzz-corpus")
        .filter_map(|e| e.ok().map(|e| e.path()))
        .filter(|p| p.extension().is_some_and(|e| e == "toml"))
        .collect();
    files.sort();
    assert!(!files.is_empty());
    for f in files {
        let text = std::fs::read_to_string(&f).unwrap();
        if let Err(why) = judge_guarded(&text) {
            panic!("{}: {why}", f.display());
        }
    }
}

#[test]
fn mutated_scenes_are_refused_cleanly_or_run_physically() {
    let seconds: u64 = std::env::var("KANESTOP_FUZZ_SECONDS").ok().and_then(|s| s.parse().ok()).unwrap_or(45);
    let seed: u64 = std::env::var("KANESTOP_FUZZ_SEED").ok().and_then(|s| s.parse().ok()).unwrap_or(15);
    let mut rng = StdRng::seed_from_u64(seed);
    let seeds = seeds();
    let start = Instant::now();
    let mut counts = std::collections::BTreeMap::new();
    let mut failures = Vec::new();
    let mut i = 0;
    while start.elapsed() < Duration::from_secs(seconds) {
        let base = &seeds[rng.gen_range(0..seeds.len())];
        let text = mutate(&mut rng, base);
        match judge_guarded(&text) {
            Ok(kind) => *counts.entry(kind).or_insert(0) += 1,
            Err(why) => failures.push(format!("{why} (saved as {})", save_failure(&text, &why, i).display())),
        }
        i += 1;
    }
    eprintln!("scene fuzz: {i} mutated scenes in {:.1} s (seed {seed}): {counts:?}", start.elapsed().as_secs_f64());
    assert!(failures.is_empty(), "{} failure(s):\n{}", failures.len(), failures.join("\n"));
    assert!(counts.get("ran").copied().unwrap_or(0) > 0, "no mutated scene ran: {counts:?}");
}

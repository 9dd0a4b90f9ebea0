//! The commands, once their arguments are parsed: each calls the runtime or the workflow
//! layer and prints what it returns.

use std::path::{Path, PathBuf};

use anyhow::{Context, Result};
use kanestop_runtime::eval::{evaluate, StateFile};
use kanestop_runtime::model::Model;
use kanestop_runtime::scene::{Scene, MAX_SCENE_BYTES};
use kanestop_runtime::simulate::{self, FailureKind, RunResult, Stop};
use kanestop_workflow::kernels::KernelFactory;
use kanestop_workflow::record::RunSummary;
use kanestop_workflow::{accuracy, batch, diagnostic, history, output, parallel, plot, progress, summary, validation};

/// How a run ended, for the exit code.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum RunOutcome {
    /// The run completed and every design check passed.
    Done,
    /// The run was refused before its first step (a step above the stability limit).
    Refused,
    /// The run ended in a numerical failure.
    NumericalFailure,
    /// The run completed, but a design check failed (a break load exceeded, or a limit of the
    /// scene's `[checks]`).
    CheckFailed,
}

/// Where `run` writes, checked before the run starts.
pub struct RunFiles<'a> {
    /// The CSV time history.
    pub out: Option<&'a Path>,
    /// The folder of plots.
    pub plot: Option<&'a Path>,
    /// The channels of the CSV history (names and groups; empty: all).
    pub channels: &'a [String],
}

impl RunFiles<'_> {
    /// Checks that every target can be written, before any work.
    pub fn check(&self) -> Result<()> {
        if let Some(path) = self.out {
            output::check_file_target(path).with_context(|| format!("cannot write {}", path.display()))?;
            let units = history::units_path(path);
            output::check_file_target(&units).with_context(|| format!("cannot write {}", units.display()))?;
        }
        if let Some(dir) = self.plot {
            // The plots' folder at or under a file the run writes could not be made after it,
            // and a plot written over that file would replace it: both refused, the paths
            // compared as the file system resolves them.
            let files = self.out.into_iter().flat_map(|out| [out.to_path_buf(), history::units_path(out)]);
            let d = output::resolved(dir).with_context(|| format!("cannot resolve --plot {}", dir.display()))?;
            for file in files {
                let Ok(f) = output::resolved(&file) else { continue };
                if d.starts_with(&f) {
                    anyhow::bail!(
                        "--plot {} is at or under {}, a file --out writes: a file cannot hold a folder",
                        dir.display(),
                        file.display()
                    );
                }
                if plot::FILES.iter().any(|name| d.join(name) == f) {
                    anyhow::bail!(
                        "--out writes {}, where --plot {} writes a plot of the same name: choose another file or folder",
                        file.display(),
                        dir.display()
                    );
                }
            }
            output::check_dir_entries(dir, &plot::FILES)
                .with_context(|| format!("cannot write plots into {}", dir.display()))?;
        }
        Ok(())
    }
}

/// `run`: one scene, its summary (text, or JSON with `json`) on standard output, a failure's
/// diagnostic on standard error, optionally its CSV history and plots (none for a run that
/// never started). The targets are checked before the run.
pub fn run(model: &Model, kernel: KernelFactory, files: &RunFiles, json: bool, verbose: bool) -> Result<RunOutcome> {
    files.check()?;
    let channels =
        history::select(model.body_count(), files.channels).map_err(|e| anyhow::anyhow!("--channels: {e}"))?;
    // The initial static residual on the run's own kind of kernel: the generated one agrees
    // with the reference to 1e-12 (tests/generated_vs_reference.rs) at a fraction of its
    // cost, which matters from a few hundred bodies.
    let result = simulate::run_checked(model, kernel(model), kernel(model));
    if json {
        println!("{}", serde_json::to_string_pretty(&RunSummary::of(model, &result))?);
    } else {
        print!("{}", summary::summary_with(model, &result, verbose));
    }
    let outcome = match &result.stop {
        Stop::Failed(f) => {
            let refused = matches!(f.kind, FailureKind::StepAboveLimit { .. });
            eprintln!("{}: {}", if refused { "error" } else { "failed" }, diagnostic::describe(model, f));
            if refused {
                RunOutcome::Refused
            } else {
                RunOutcome::NumericalFailure
            }
        }
        Stop::ShipStopped | Stop::EndTime if RunSummary::of(model, &result).checks_pass == Some(false) => {
            RunOutcome::CheckFailed
        }
        Stop::ShipStopped | Stop::EndTime => RunOutcome::Done,
    };
    // With JSON on standard output, the notes go to standard error.
    let note = |text: String| if json { eprintln!("{text}") } else { println!("{text}") };
    if result.samples.is_empty() {
        for path in files.out.iter().chain(&files.plot) {
            eprintln!("{:<10}{} (the run never started)", "skipped", path.display());
        }
        return Ok(outcome);
    }
    if let Some(path) = files.out {
        let [csv, units] = history::write_channels(&result, &channels, path)
            .with_context(|| format!("cannot write {}", path.display()))?;
        note(format!(
            "{:<10}{} ({} samples, {} channels)",
            "written",
            csv.display(),
            result.samples.len(),
            channels.len()
        ));
        note(format!("{:<10}{} (units)", "written", units.display()));
    }
    if let Some(dir) = files.plot {
        let runs = [(model, &result)];
        for f in plot::write_plots(&runs, dir)? {
            note(format!("written   {}", f.display()));
        }
    }
    Ok(outcome)
}

/// `eval`: the equations of motion at the initial state or at the state in `state`, as JSON.
pub fn eval(model: &Model, kernel: KernelFactory, state: Option<&Path>) -> Result<()> {
    let state = match state {
        Some(path) => {
            let text = kanestop_runtime::scene::read_text_file(path, MAX_SCENE_BYTES, "a state file's")
                .with_context(|| format!("cannot read {}", path.display()))?;
            let s: StateFile =
                serde_json::from_str(&text).with_context(|| format!("state file {} is not valid", path.display()))?;
            Some(s)
        }
        None => None,
    };
    let out = evaluate(model, kernel(model), state.as_ref())?;
    println!("{}", serde_json::to_string_pretty(&out)?);
    Ok(())
}

/// `batch SCENES…`: runs every scene (a file, or each of a folder's) once per configuration (one per method compared), prints
/// the table, writes batch.csv, batch.json and batch.units.csv; with `error_estimate`, each run is repeated
/// refined; with a `tolerance`, validates against Table 3. Returns how it went for the exit
/// code.
pub fn batch(
    paths: &[PathBuf],
    out: &Path,
    configures: &[batch::Configure],
    kernel: KernelFactory,
    error_estimate: bool,
    tolerance: Option<f64>,
) -> Result<BatchOutcome> {
    let files = batch::scene_files_of(paths)?;
    check_dir(out, &batch::FILES)?;
    let bar = progress::bar(files.len() * configures.len(), "scenes");
    let mut rows = Vec::new();
    for configure in configures {
        rows.extend(batch::run_all(&files, *configure, kernel, error_estimate, &|row| {
            let method = row.method.map(|m| m.name()).unwrap_or_default();
            bar.set_message(format!("{} {method} {}", row.case, row.status));
            bar.inc(1);
        }));
    }
    // Scene by scene, the methods side by side.
    rows.sort_by(|a, b| a.file.cmp(&b.file));
    bar.finish_and_clear();
    print!("{}", batch::table(&rows));
    let [csv, json, units] = batch::write(&rows, out)?;
    println!("written   {}, {} and {} (the columns' units)", csv.display(), json.display(), units.display());
    let mut ok = !rows.iter().any(|r| r.status.is_problem());
    if let Some(tol) = tolerance {
        let v = validation::validate(&rows, tol);
        if let Some(tau) = v.kendall_tau {
            println!("order     Kendall's τ against Table 3 = {tau:.3} ({} discordant pairs)", v.discordant.len());
            for (a, b) in &v.discordant {
                println!("          {a} and {b} are in the other order");
            }
        }
        for p in &v.problems {
            println!("MISS      {p}");
        }
        ok &= v.problems.is_empty() && v.discordant.is_empty();
        println!("validate  {} (tolerance {:.1} %)", if ok { "PASS" } else { "FAIL" }, 100.0 * tol);
    }
    let check_failed = rows.iter().any(|r| r.checks_pass == Some(false));
    Ok(if !ok {
        BatchOutcome::Missed
    } else if check_failed {
        BatchOutcome::CheckFailed
    } else {
        BatchOutcome::Done
    })
}

/// How a batch went, for the exit code.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum BatchOutcome {
    /// Every scene ran, every check passed (and the validation, when asked).
    Done,
    /// A scene was invalid or failed, or the validation missed (takes precedence).
    Missed,
    /// Every scene ran, but in some row a design check failed (a break load exceeded, or a
    /// limit of the scene's `[checks]`).
    CheckFailed,
}

/// `plot SCENE…`: runs the scenes and writes overlaid plots into `out`. A run that failed is
/// named on standard error with its diagnostic, as `run` names it, and drawn up to its
/// failure; one that never started (refused before its first step) is left out of the
/// charts. The outcome is the worst of the runs': refused before any numerical failure.
pub fn plot(scenes: &[PathBuf], out: &Path, kernel: KernelFactory) -> Result<RunOutcome> {
    check_dir(out, &plot::FILES)?;
    let models: Vec<Model> =
        scenes.iter().map(|p| -> Result<Model> { Ok(Model::new(&Scene::load(p)?)?) }).collect::<Result<_>>()?;
    let bar = progress::bar(models.len(), "scenes");
    let results = parallel::run_models(&models, kernel, &|_| bar.inc(1));
    bar.finish_and_clear();
    let mut outcome = RunOutcome::Done;
    let mut drawn: Vec<(&Model, &RunResult)> = Vec::new();
    for ((path, model), result) in scenes.iter().zip(&models).zip(&results) {
        if let Stop::Failed(f) = &result.stop {
            let refused = matches!(f.kind, FailureKind::StepAboveLimit { .. });
            let word = if refused { "error" } else { "failed" };
            eprintln!("{word}: {}: {}", path.display(), diagnostic::describe(model, f));
            outcome = match (outcome, refused) {
                (_, true) | (RunOutcome::Refused, _) => RunOutcome::Refused,
                _ => RunOutcome::NumericalFailure,
            };
        }
        if result.samples.is_empty() {
            eprintln!("{:<10}{} (the run never started: not drawn)", "skipped", path.display());
        } else {
            drawn.push((model, result));
        }
    }
    if !drawn.is_empty() {
        for f in plot::write_plots(&drawn, out)? {
            println!("written   {}", f.display());
        }
    }
    Ok(outcome)
}

/// `report accuracy`: the work–precision study, printed and written into `out`.
pub fn accuracy(scene: &Scene, out: &Path, repeats: usize, atol_ratio: f64, kernel: KernelFactory) -> Result<()> {
    let plan = accuracy::default_plan();
    accuracy::check(&plan, atol_ratio, repeats)?;
    check_dir(out, &accuracy::FILES)?;
    let bar = progress::bar(accuracy::run_count(&plan, repeats), "runs");
    let study = accuracy::study(scene, &plan, atol_ratio, kernel, repeats, &|what| {
        bar.set_message(what.to_string());
        bar.inc(1);
    });
    bar.finish_and_clear();
    let study = study?;
    print!("{}", accuracy::table(&study));
    for f in accuracy::write(&study, out)? {
        println!("written   {}", f.display());
    }
    Ok(())
}

/// Checks, before any run, that files can be written into the folder `dir` (created later
/// where it does not exist yet).
pub(crate) fn check_dir(dir: &Path, entries: &[&str]) -> Result<()> {
    output::check_dir_entries(dir, entries).with_context(|| format!("cannot write into {}", dir.display()))
}

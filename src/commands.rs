//! The commands that run many scenes: `batch` (a folder, tabulated) and `plot` (overlaid
//! time histories). Both run scenes in parallel.

use std::path::{Path, PathBuf};

use anyhow::{Context, Result};
use indicatif::{ProgressBar, ProgressStyle};
use kanestop_runtime::batch;
use kanestop_runtime::kernel::Kernel;
use kanestop_runtime::model::Model;
use kanestop_runtime::plot;
use kanestop_runtime::scene::Scene;
use kanestop_runtime::simulate::{self, RunResult};
use rayon::prelude::*;

/// Builds the kernel of each run.
pub type KernelFactory<'a> = &'a (dyn Fn(&Model) -> Box<dyn Kernel> + Sync);

fn progress(len: usize) -> ProgressBar {
    let bar = ProgressBar::new(len as u64);
    bar.set_style(
        ProgressStyle::with_template("{bar:40} {pos}/{len} scenes  {elapsed_precise}  {msg}")
            .expect("a valid progress template"),
    );
    bar
}

/// `batch DIR`: runs every scene once per configuration (one per method compared), prints
/// the table, writes batch.csv and batch.json; with `error_estimate`, each run is repeated
/// refined; with a `tolerance`, validates against Table 3 and returns whether every check
/// passed.
pub fn batch(
    dir: &Path,
    out: &Path,
    configures: &[batch::Configure],
    kernel: KernelFactory,
    error_estimate: bool,
    tolerance: Option<f64>,
) -> Result<bool> {
    let files = batch::scene_files(dir).with_context(|| format!("cannot read scene folder {}", dir.display()))?;
    anyhow::ensure!(!files.is_empty(), "no *.toml scene in {}", dir.display());
    let bar = progress(files.len() * configures.len());
    let mut rows = Vec::new();
    for configure in configures {
        rows.extend(batch::run_all(&files, *configure, kernel, error_estimate, &|row| {
            bar.set_message(format!("{} {} {}", row.case, row.method, row.status));
            bar.inc(1);
        }));
    }
    // Scene by scene, the methods side by side.
    rows.sort_by(|a, b| a.file.cmp(&b.file));
    bar.finish_and_clear();
    print!("{}", batch::table(&rows));
    let (csv, json) = batch::write(&rows, out).with_context(|| format!("cannot write into {}", out.display()))?;
    println!("written   {} and {}", csv.display(), json.display());
    let mut ok = !rows.iter().any(|r| r.status == "failed" || r.status == "invalid");
    if let Some(tol) = tolerance {
        let v = batch::validate(&rows, tol);
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
    Ok(ok)
}

/// `plot SCENE…`: runs the scenes and writes overlaid plots into `out`.
pub fn plot(scenes: &[PathBuf], out: &Path, kernel: KernelFactory) -> Result<Vec<PathBuf>> {
    let models: Vec<Model> =
        scenes.iter().map(|p| -> Result<Model> { Ok(Model::new(&Scene::load(p)?)?) }).collect::<Result<_>>()?;
    let bar = progress(models.len());
    let results: Vec<RunResult> = models
        .par_iter()
        .map(|m| {
            let r = simulate::run(m, kernel(m));
            bar.inc(1);
            r
        })
        .collect();
    bar.finish_and_clear();
    write_plots(&models, &results, out)
}

/// Writes the plots of finished runs.
pub fn write_plots(models: &[Model], results: &[RunResult], out: &Path) -> Result<Vec<PathBuf>> {
    let runs: Vec<(&Model, &RunResult)> = models.iter().zip(results).collect();
    let files = plot::write_plots(&runs, out).map_err(anyhow::Error::msg)?;
    for f in &files {
        println!("written   {}", f.display());
    }
    Ok(files)
}

/// `report accuracy`: the work–precision study, printed and written into `out`.
pub fn accuracy(scene: &Scene, out: &Path, repeats: usize, atol_ratio: f64, kernel: KernelFactory) -> Result<()> {
    anyhow::ensure!(repeats >= 1, "--repeats {repeats}: must be at least 1");
    anyhow::ensure!(
        atol_ratio.is_finite() && atol_ratio > 0.0,
        "--atol-ratio {atol_ratio}: must be finite and > 0 (atol = ratio × rtol)"
    );
    let plan = kanestop_runtime::accuracy::default_plan();
    let study =
        kanestop_runtime::accuracy::study(scene, &plan, atol_ratio, kernel, repeats).map_err(anyhow::Error::msg)?;
    print!("{}", kanestop_runtime::accuracy::table(&study));
    for f in kanestop_runtime::accuracy::write(&study, out).map_err(anyhow::Error::msg)? {
        println!("written   {}", f.display());
    }
    Ok(())
}

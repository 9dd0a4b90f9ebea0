//! `sweep SPEC` and `report sensitivity SCENE`: the CLI side (arguments, progress, printing,
//! exit codes) of `kanestop_workflow::sweep` and `kanestop_workflow::sensitivity`.

use std::path::PathBuf;

use anyhow::{Context, Result};

use crate::Exit;
use kanestop_runtime::scene::Scene;
use kanestop_workflow::kernels::{self, KernelChoice};
use kanestop_workflow::output::write_atomically;
use kanestop_workflow::sweep::heatmap;
use kanestop_workflow::sweep::Progress;
use kanestop_workflow::{sensitivity, sweep};

/// `sweep SPEC`.
#[derive(clap::Args)]
pub struct SweepArgs {
    /// Sweep spec (TOML, docs/sweeps.md): base scene, axes, uncertain inputs, checks.
    spec: PathBuf,
    /// Folder for sweep.csv, sweep.json and scenes/ (each row's scene, to rerun it alone).
    #[arg(long, default_value = "out/sweep")]
    out: PathBuf,
    /// Runs at once (default: one per core).
    #[arg(long)]
    jobs: Option<usize>,
    /// Which Kane kernel evaluates the equations of motion (generated or reference).
    #[arg(long, default_value = "generated", value_parser = ["generated", "reference"])]
    kernel: String,
    /// Heat maps over the two grid axes (a spec with exactly two numeric axes), one
    /// heatmap-NAME.svg each: stopping_distance, stopping_time, peak_utilisation,
    /// peak_tension, anchor_drag_distance, ship_displacement, or none [default: the first
    /// three].
    #[arg(long, value_delimiter = ',')]
    heatmap: Vec<String>,
}

/// `report sensitivity SCENE`.
#[derive(clap::Args)]
pub struct SensitivityArgs {
    /// Scene TOML file; omitted: the embedded case 1.
    scene: Option<PathBuf>,
    /// Relative step h of the central differences, p·(1 ± h).
    #[arg(long, default_value_t = sensitivity::DEFAULT_STEP)]
    step: f64,
    /// A sweep spec whose `[[uncertain]]` inputs give the parameter uncertainties: prints the
    /// first-order output band (sample it with `kanestop sweep SPEC`).
    #[arg(long)]
    uncertain: Option<PathBuf>,
    /// Folder for sensitivity.csv and sensitivity.json.
    #[arg(long, default_value = "out/sensitivity")]
    out: PathBuf,
    /// Runs at once (default: one per core).
    #[arg(long)]
    jobs: Option<usize>,
}

fn choice(name: &str) -> KernelChoice {
    if name == "reference" {
        KernelChoice::Reference
    } else {
        KernelChoice::Generated
    }
}

/// Reads one output of a summary.
type Output<'a> = &'a dyn Fn(&kanestop_workflow::record::RunSummary) -> Option<f64>;

/// `sweep SPEC`: runs every row, prints the table, writes the files; the exit code.
pub fn sweep(args: &SweepArgs) -> Result<Exit> {
    let spec = sweep::Spec::load(&args.spec)?;
    let heat_maps = heatmap::parse_outputs(&args.heatmap)?;
    if !args.heatmap.is_empty() && !heat_maps.is_empty() {
        if let Some(why) = heatmap::unsupported(&spec) {
            anyhow::bail!("--heatmap {}: {why}", args.heatmap.join(","));
        }
    }
    sweep::check_writable(&args.out)?;
    let plan = spec.plan();
    let kernel = kernels::factory(choice(&args.kernel));
    let bar = Progress::new(plan.len(), "runs");
    let rows = sweep::run(&plan, &kernel, args.jobs, &|r| bar.inc(format!("{} {}", r.name, r.status)))?;
    bar.finish();
    print!("{}", sweep::table(&rows));
    if spec.sampling.is_some() {
        let stats: [(&str, Output, f64); 3] = [
            ("stopping time (s)", &|s| s.stopping_time, 1.0),
            ("stopping distance (m)", &|s| s.stopping_distance, 1.0),
            ("peak tension (kN)", &|s| s.peak_tension.map(|p| p.tension), 1e-3),
        ];
        for (name, f, scale) in stats {
            if let Some([mean, sd, p5, p95]) = sweep::statistics(&rows, f) {
                let [mean, sd, p5, p95] = [mean, sd, p5, p95].map(|v| v * scale);
                println!("{name:<22} mean {mean:.3}  sd {sd:.3}  5 % {p5:.3}  95 % {p95:.3}");
            }
        }
    }
    let (csv, json) = sweep::write(&rows, &plan, &args.out)?;
    println!(
        "written   {} and {} ({} rows; scenes in {})",
        csv.display(),
        json.display(),
        rows.len(),
        args.out.join("scenes").display()
    );
    for f in heatmap::write(&spec, &rows, &heat_maps, &args.out)? {
        println!("written   {}", f.display());
    }
    let (failed, check_failed) = sweep::outcome(&rows);
    if check_failed {
        let n = rows.iter().filter(|r| r.checks_pass == Some(false)).count();
        println!("checks    FAIL in {n} of {} rows", rows.len());
    }
    Ok(if failed {
        Exit::NumericalFailure
    } else if check_failed {
        Exit::CheckFailed
    } else {
        Exit::Done
    })
}

/// `report sensitivity [SCENE]`.
pub fn sensitivity(args: &SensitivityArgs) -> Result<Exit> {
    let scene = match &args.scene {
        Some(p) => Scene::load(p)?,
        None => Scene::from_toml(kanestop_runtime::paper::DEFAULT_SCENE, "embedded case01.toml")?,
    };
    let sigmas: Vec<(String, f64)> = match &args.uncertain {
        Some(p) => {
            sweep::Spec::load(p)?.uncertain.iter().map(|u| (u.path.clone(), u.distribution.sigma_ln())).collect()
        }
        None => Vec::new(),
    };
    std::fs::create_dir_all(&args.out).with_context(|| format!("cannot create {}", args.out.display()))?;
    let runs = 1 + 2 * sensitivity::parameters(&scene).len();
    let kernel = kernels::factory(KernelChoice::Generated);
    let bar = Progress::new(runs, "runs");
    let study = sensitivity::study(&scene, args.step, &kernel, args.jobs, &|| bar.inc(String::new()))?;
    bar.finish();
    print!("{}", sensitivity::table(&study));
    if !sigmas.is_empty() {
        let (band, missing) = sensitivity::band(&study, &sigmas);
        let o = |v: Option<f64>, s: f64| v.map(|v| format!("{:.3}", v * s)).unwrap_or("—".into());
        println!("first-order band (1 σ) from {} uncertain inputs:", sigmas.len());
        println!("  stopping time      {} ± {:.3} s", o(study.base[0], 1.0), band[0]);
        println!("  stopping distance  {} ± {:.3} m", o(study.base[1], 1.0), band[1]);
        println!("  peak tension       {} ± {:.1} kN", o(study.base[2], 1e-3), band[2] * 1e-3);
        for m in missing {
            println!("  note: {m} is not a continuous parameter of the scene; ignored");
        }
    }
    let (c, j) = (args.out.join("sensitivity.csv"), args.out.join("sensitivity.json"));
    write_atomically(&c, sensitivity::csv(&study).as_bytes())
        .with_context(|| format!("cannot write {}", c.display()))?;
    write_atomically(&j, serde_json::to_string_pretty(&study)?.as_bytes())
        .with_context(|| format!("cannot write {}", j.display()))?;
    println!("written   {} and {}", c.display(), j.display());
    Ok(Exit::Done)
}

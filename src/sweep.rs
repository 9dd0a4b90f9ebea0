//! `sweep SPEC`, `sweep merge DIR…` and `report sensitivity SCENE`: the CLI side (arguments, progress, printing,
//! exit codes) of `kanestop_workflow::sweep` and `kanestop_workflow::sensitivity`.

use std::path::{Path, PathBuf};
use std::time::Duration;

use anyhow::{Context, Result};

use crate::commands::check_dir;
use crate::{Exit, KernelArg};
use kanestop_runtime::scene::Scene;
use kanestop_workflow::batch::Status;
use kanestop_workflow::kernels::{self, KernelChoice};
use kanestop_workflow::sweep::heatmap;
use kanestop_workflow::sweep::shard::{self, Shard};
use kanestop_workflow::sweep::shard_file::{self, ShardFile, ShardRun, SweepId};
use kanestop_workflow::sweep::{merge, slurm, PlannedRow, SweepRow};
use kanestop_workflow::{progress, sensitivity, sweep};

/// `sweep SPEC` and `sweep merge DIR…`.
#[derive(clap::Args)]
#[command(args_conflicts_with_subcommands = true, subcommand_negates_reqs = true)]
pub struct SweepArgs {
    #[command(subcommand)]
    command: Option<SweepCommand>,
    /// Sweep spec (TOML, docs/sweeps.md): base scene, axes, uncertain inputs, checks.
    #[arg(required = true)]
    spec: Option<PathBuf>,
    /// Folder for sweep.csv, sweep.units.csv, sweep.json and scenes/ (each row's scene, to
    /// rerun it alone);
    /// a shard writes shards/shard-K-of-N.json there.
    #[arg(long, default_value = "out/sweep")]
    out: PathBuf,
    /// Runs at once (default: one per core).
    #[arg(long)]
    jobs: Option<usize>,
    /// Which Kane kernel evaluates the equations of motion.
    #[arg(long, value_enum, default_value = "generated")]
    kernel: KernelArg,
    /// Run only shard K of N (numbered from 0: the rows i with i mod N = K) and write
    /// OUT/shards/shard-K-of-N.json; merge the shards with `sweep merge OUT`. Without it, a
    /// task of a job array takes its shard from the scheduler with --shards N: K from
    /// SLURM_ARRAY_TASK_ID (N checked against SLURM_ARRAY_TASK_COUNT), JOB_COMPLETION_INDEX
    /// (Kubernetes) or PBS_ARRAY_INDEX. `none`: the whole sweep, in a job array's task too.
    #[arg(long, value_name = "K/N", conflicts_with_all = ["slurm", "shards"])]
    shard: Option<String>,
    /// Number of shards: the size of --slurm's job array (default: one per row, up to 10),
    /// or N beside a Kubernetes or PBS index (checked against SLURM_ARRAY_TASK_COUNT).
    #[arg(long, value_name = "N")]
    shards: Option<usize>,
    /// Rerun only the rows missing or failed in OUT's shard files; without a shard, complete
    /// every shard in OUT (one shard when there is none), then merge them.
    #[arg(long)]
    resume: bool,
    /// A running shard saves its file (the rows done so far, for --resume) every SECONDS
    /// (0 to 1e6).
    #[arg(long, value_name = "SECONDS", allow_negative_numbers = true, default_value_t = 10.0)]
    checkpoint: f64,
    /// Print a Slurm job script (bash) that submits the sweep as a job array of --shards
    /// shards and a merge job after it; run it with `bash`.
    #[arg(long, conflicts_with = "resume")]
    slurm: bool,
    /// Heat maps over the two grid axes (a spec with exactly two numeric axes; drawn by a
    /// local run and by --resume, refused with a shard: `sweep merge --spec` draws a sharded
    /// sweep's), one heatmap-NAME.svg each: stopping_distance, stopping_time,
    /// peak_utilisation, peak_tension, anchor_drag_distance, ship_displacement, or none
    /// [default: the first three].
    #[arg(long, value_delimiter = ',')]
    heatmap: Vec<String>,
}

/// `sweep merge`.
#[derive(clap::Subcommand)]
enum SweepCommand {
    /// Merge a sweep's shard files into sweep.csv, sweep.units.csv, sweep.json and scenes/, as a local run
    /// writes them; refused when shards are of different sweeps, a row is missing or twice.
    Merge(MergeArgs),
}

/// `sweep merge DIR…`.
#[derive(clap::Args)]
struct MergeArgs {
    /// Sweep folders (their shards/shard-K-of-N.json files) or shard files.
    #[arg(required = true, value_name = "DIR")]
    dirs: Vec<PathBuf>,
    /// Folder for sweep.csv, sweep.units.csv, sweep.json and scenes/ (default: the first
    /// folder given).
    #[arg(long)]
    out: Option<PathBuf>,
    /// The sweep's spec: checked against the shards' plan hash and every row against its
    /// plan (name, inputs, scene), it lets the merge draw the heat maps a local run draws
    /// (without it, the merge writes none).
    #[arg(long)]
    spec: Option<PathBuf>,
    /// Heat maps to draw with --spec, as for a local run [default: the first three].
    #[arg(long, value_delimiter = ',')]
    heatmap: Vec<String>,
}

/// `report sensitivity SCENE`.
#[derive(clap::Args)]
pub struct SensitivityArgs {
    /// Scene TOML file; omitted: the embedded case 1.
    scene: Option<PathBuf>,
    /// Relative step h of the central differences, p·(1 ± h).
    #[arg(long, allow_negative_numbers = true, default_value_t = sensitivity::DEFAULT_STEP)]
    step: f64,
    /// A sweep spec whose `[[uncertain]]` inputs give the parameter uncertainties: prints the
    /// first-order output band (sample it with `kanestop sweep SPEC`).
    #[arg(long)]
    uncertain: Option<PathBuf>,
    /// Folder for sensitivity.csv, sensitivity.json and sensitivity.units.csv.
    #[arg(long, default_value = "out/sensitivity")]
    out: PathBuf,
    /// Runs at once (default: one per core).
    #[arg(long)]
    jobs: Option<usize>,
}

/// The longest `--checkpoint`, s (11.6 days: longer than a scheduler's time limits).
const MAX_CHECKPOINT: f64 = 1e6;

/// Reads one output of a summary.
type Output<'a> = &'a dyn Fn(&kanestop_workflow::record::RunSummary) -> Option<f64>;

/// `sweep SPEC` (the whole sweep, one shard, every shard with `--resume`, or the Slurm
/// job script) and `sweep merge DIR…`; the exit code.
pub fn sweep(args: &SweepArgs) -> Result<Exit> {
    if let Some(SweepCommand::Merge(m)) = &args.command {
        return merge(m);
    }
    let file = args.spec.as_ref().context("a sweep spec (SPEC.toml) is needed")?;
    let spec = sweep::Spec::load(file)?;
    let heat_maps = heatmap::parse_outputs(&args.heatmap)?;
    if !args.heatmap.is_empty() && !heat_maps.is_empty() {
        if let Some(why) = heatmap::unsupported(&spec) {
            anyhow::bail!("--heatmap {}: {why}", args.heatmap.join(","));
        }
    }
    kanestop_workflow::parallel::check_jobs(args.jobs)?;
    let plan = spec.plan();
    anyhow::ensure!(
        (0.0..=MAX_CHECKPOINT).contains(&args.checkpoint),
        "--checkpoint = {}: a number of seconds from 0 to {MAX_CHECKPOINT:e}",
        kanestop_runtime::scene::fmt_value(args.checkpoint)
    );
    if args.slurm {
        return slurm(args, &spec, &plan);
    }
    let shard = match args.shard.as_deref() {
        // The whole sweep, whatever a scheduler's variables say (one sweep per array task).
        Some("none") => None,
        Some(text) => Some((Shard::parse(text)?, "--shard")),
        None => shard::from_env(|name| std::env::var(name).ok(), args.shards)?,
    };
    if shard.is_none() {
        if let Some(n) = args.shards {
            anyhow::bail!(
                "--shards = {n}: only with --slurm, or in a job array that gives the index ({}); one shard: --shard K/N",
                shard::INDEX_VARIABLES.join(", ")
            );
        }
    }
    if let (Some((_, from)), false) = (&shard, heat_maps.is_empty() || args.heatmap.is_empty()) {
        anyhow::bail!(
            "--heatmap {} with a shard ({from}): a shard holds some of the rows and draws no heat map; \
             `kanestop sweep merge OUT --spec SPEC` draws them from the merged rows",
            args.heatmap.join(",")
        );
    }
    let id = SweepId::of(&spec, &plan, args.kernel.0.name());
    match shard {
        Some((s, from)) => run_shard(args, &id, &plan, s, from),
        None if args.resume => resume_all(args, &spec, &heat_maps, &id, &plan),
        None => {
            check_outputs(&args.out, plan.iter().map(|r| r.name.as_str()), Some(&spec), &heat_maps)?;
            let kernel = args.kernel.factory();
            let bar = progress::bar(plan.len(), "runs");
            let rows = sweep::run(&plan, &kernel, args.jobs, &|r| {
                bar.set_message(format!("{} {}", r.name, r.status));
                bar.inc(1);
            })?;
            bar.finish_and_clear();
            let scenes = sweep::scene_files(&plan);
            let earlier = sweep::rows_in(&args.out);
            let code = report(&rows, id.sampling, id.samples_per_point, &scenes, &args.out)?;
            finish(Some(&spec), &rows, &heat_maps, (&earlier, &scenes), &args.out)?;
            Ok(code)
        }
    }
}

/// Prints the table (and, with sampling, the statistics of each grid point, its rows
/// `per_point` consecutive ones; 0: not known), writes the files, prints the check summary;
/// the exit code. The same for a local run and a merge.
fn report(
    rows: &[SweepRow],
    sampling: bool,
    per_point: usize,
    scenes: &[(String, String)],
    out: &Path,
) -> Result<Exit> {
    print!("{}", sweep::table(rows));
    if sampling {
        let stats: [(&str, Output, f64); 3] = [
            ("stopping time (s)", &|s| s.stopping_time, 1.0),
            ("stopping distance (m)", &|s| s.stopping_distance, 1.0),
            ("peak tension (kN)", &|s| s.peak_tension.map(|p| p.tension), 1e-3),
        ];
        if per_point == 0 {
            println!(
                "statistics over all {} rows (shard files of before 2026-12-06 do not say the grid: if the sweep \
                 has axes, their points are pooled)",
                rows.len()
            );
        }
        let points = sweep::by_grid_point(rows, per_point);
        for (point, group) in &points {
            // The rows that ran to their end (the statistics' samples), those of them that
            // stopped the ship (a run kept going after its stop, `stop_when_ship_stops =
            // false`, did too), and those cut short by the end time.
            let ran: Vec<&SweepRow> =
                group.iter().filter(|r| matches!(r.status, Status::Stopped | Status::EndTime)).collect();
            let stopped = ran.iter().filter(|r| r.summary.as_ref().is_some_and(|s| s.stopping_time.is_some())).count();
            let cut = ran.len() - stopped;
            let problems = group.len() - ran.len();
            let others = if problems > 0 { format!(", {problems} failed or invalid") } else { String::new() };
            if points.len() > 1 {
                println!("point     {point} ({} samples, {stopped} stopped{others})", group.len());
            } else {
                println!("samples   {}, {stopped} stopped the ship{others}", group.len());
            }
            for (name, f, scale) in stats {
                // Over the samples that gave the output: where some ran to the end time without
                // a stop, the stopping outputs are over those that stopped, the shortest: biased low.
                let gave = ran.iter().filter(|r| r.summary.as_ref().and_then(f).is_some()).count();
                let Some([mean, sd, p5, p95]) = sweep::statistics(group, f) else {
                    println!("{name:<22} none: {gave} sample(s) gave it, statistics need 2");
                    continue;
                };
                let caveat = if gave < ran.len() && cut > 0 {
                    format!(" (over the {gave} that stopped: biased low)")
                } else {
                    String::new()
                };
                let [mean, sd, p5, p95] = [mean, sd, p5, p95].map(|v| v * scale);
                println!("{name:<22} mean {mean:.3}  sd {sd:.3}  5 % {p5:.3}  95 % {p95:.3}{caveat}");
            }
        }
    }
    let (csv, json) = sweep::write(rows, scenes, out)?;
    println!(
        "written   {} and {} ({} rows; the columns' units in sweep.units.csv; scenes in {})",
        csv.display(),
        json.display(),
        rows.len(),
        out.join("scenes").display()
    );
    Ok(exit(rows))
}

/// Draws the heat maps (given the spec) and removes what an earlier sweep (its rows
/// `earlier`, read before this one's files replaced its) wrote into `out` and this one did
/// not ([`sweep::remove_stale`]), saying so. The same for a local run, a
/// resume and a merge.
fn finish(
    spec: Option<&sweep::Spec>,
    rows: &[SweepRow],
    heat_maps: &[heatmap::Output],
    (earlier, scenes): (&[String], &[(String, String)]),
    out: &Path,
) -> Result<()> {
    let charts = spec.map(|spec| heatmap::write(spec, rows, heat_maps, out)).transpose()?;
    for f in charts.iter().flatten() {
        println!("written   {}", f.display());
    }
    let removed = sweep::remove_stale(out, earlier, scenes, charts.as_deref())?;
    if let Some(first) = removed.first() {
        let more = if removed.len() > 1 { format!(", … ({} in all)", removed.len()) } else { String::new() };
        println!("removed   an earlier sweep's files this one did not write: {}{more}", first.display());
    }
    Ok(())
}

/// The exit code of finished rows (printing how many failed a check): 3 when a row failed
/// or was invalid, else 4 when a check failed, else 0.
fn exit(rows: &[SweepRow]) -> Exit {
    let (failed, check_failed) = sweep::outcome(rows);
    if check_failed {
        let n = rows.iter().filter(|r| r.checks_pass == Some(false)).count();
        // Which checks failed, in how many rows each: the break loads and the [checks].
        let mut counts: Vec<(String, usize)> = Vec::new();
        for s in rows.iter().filter(|r| r.checks_pass == Some(false)).filter_map(|r| r.summary.as_ref()) {
            let over = s.break_load_exceeded();
            let failed: Vec<String> = s.checks.iter().filter(|c| !c.pass).map(|c| c.name.clone()).collect();
            // A failing row none of whose [checks] failed failed on a break load.
            let names = (over || failed.is_empty()).then(|| "break load".to_string()).into_iter();
            for name in names.chain(failed) {
                match counts.iter_mut().find(|(n, _)| *n == name) {
                    Some((_, k)) => *k += 1,
                    None => counts.push((name, 1)),
                }
            }
        }
        let which: Vec<String> = counts.iter().map(|(name, k)| format!("{name} in {k}")).collect();
        let which = if which.is_empty() { String::new() } else { format!(": {}", which.join(", ")) };
        println!("checks    FAIL in {n} of {} rows{which}", rows.len());
    }
    // Exit 3's rows, named: the table shows them among the others.
    let count = |status: Status| rows.iter().filter(|r| r.status == status).count();
    let (bad, invalid) = (count(Status::Failed), count(Status::Invalid));
    if bad + invalid > 0 {
        println!("runs      {bad} failed and {invalid} invalid of {} rows (the table says why)", rows.len());
    }
    if failed {
        Exit::NumericalFailure
    } else if check_failed {
        Exit::CheckFailed
    } else {
        Exit::Done
    }
}

/// Checks, before any run, that every file a sweep of the rows `names` writes into `out` can
/// be written there ([`sweep::output_entries`]): the rows' scene files where `out/scenes`
/// exists already, and the heat maps `heat_maps` where `spec` draws them (it is given and
/// has two numeric grid axes).
fn check_outputs<'a>(
    out: &Path,
    names: impl Iterator<Item = &'a str>,
    spec: Option<&sweep::Spec>,
    heat_maps: &[heatmap::Output],
) -> Result<()> {
    let names: Vec<&str> = if out.join("scenes").is_dir() { names.collect() } else { Vec::new() };
    let drawn = spec.is_some_and(|s| heatmap::unsupported(s).is_none());
    let entries = sweep::output_entries(names, if drawn { heat_maps } else { &[] });
    check_dir(out, &entries.iter().map(String::as_str).collect::<Vec<_>>())
}

/// Runs the rows of `shard` still to do (all, or with `resume` those missing or failed in
/// its file), saving its file as it goes; the file at the end and how many rows were kept.
fn execute_shard(
    args: &SweepArgs,
    id: &SweepId,
    plan: &[PlannedRow],
    shard: Shard,
    resume: bool,
) -> Result<(ShardFile, usize, PathBuf)> {
    check_dir(&args.out.join("shards"), &[])?;
    let every = Duration::from_secs_f64(args.checkpoint);
    let (run, todo) = ShardRun::start(id, plan, shard, &args.out, resume, every)?;
    let kernel = args.kernel.factory();
    let bar = progress::bar(todo.rows.len(), "runs");
    let stop = stop_signal::catch();
    let done = sweep::run_cancellable(
        &todo.rows,
        &kernel,
        args.jobs,
        &|r| {
            run.add(r);
            bar.set_message(format!("{} {}", r.name, r.status));
            bar.inc(1);
        },
        stop.flag(),
    )?;
    bar.finish_and_clear();
    let path = run.path().to_path_buf();
    let file = run.finish()?;
    if let Some(name) = stop.caught() {
        eprintln!(
            "stopped   by {name}: {} of the shard's {} rows saved in {} ({} this time); run it again with --resume to finish it",
            file.rows.len(),
            file.row_indices.len(),
            path.display(),
            done.len()
        );
        stop.end_by_it();
    }
    Ok((file, todo.kept, path))
}

/// SIGTERM (a scheduler's time limit or `scancel`) and SIGINT (Ctrl-C) during a shard's runs:
/// the runs stop at their next step and the shard file is saved with the rows done, then
/// the process ends by the same signal. Without this a task killed at its time limit kept
/// only what its last checkpoint had saved.
mod stop_signal {
    use std::sync::atomic::{AtomicBool, AtomicI32, Ordering};

    static STOP: AtomicBool = AtomicBool::new(false);
    static SIGNAL: AtomicI32 = AtomicI32::new(0);

    #[cfg(unix)]
    extern "C" fn on_signal(signal: libc::c_int) {
        // Async-signal-safe: two lock-free stores.
        SIGNAL.store(signal, Ordering::Relaxed);
        STOP.store(true, Ordering::Relaxed);
    }

    /// The signals caught until [`Caught`] is dropped or ends the process.
    pub struct Caught;

    /// Catches SIGTERM and SIGINT from now on.
    pub fn catch() -> Caught {
        #[cfg(unix)]
        // SAFETY: the handler only stores to atomics; it is installed for two signals whose
        // default action it replaces until `Caught` restores it.
        unsafe {
            libc::signal(libc::SIGTERM, on_signal as extern "C" fn(libc::c_int) as libc::sighandler_t);
            libc::signal(libc::SIGINT, on_signal as extern "C" fn(libc::c_int) as libc::sighandler_t);
        }
        Caught
    }

    impl Caught {
        /// The flag the runs poll.
        pub fn flag(&self) -> &'static AtomicBool {
            &STOP
        }

        /// The signal's name, once one came.
        pub fn caught(&self) -> Option<&'static str> {
            match SIGNAL.load(Ordering::Relaxed) {
                0 => None,
                #[cfg(unix)]
                libc::SIGINT => Some("SIGINT"),
                _ => Some("SIGTERM"),
            }
        }

        /// Ends the process by the signal that came, its default action restored (a shell
        /// or scheduler sees it terminated by that signal, as without the handler).
        pub fn end_by_it(self) {
            let signal = SIGNAL.load(Ordering::Relaxed);
            drop(self);
            #[cfg(unix)]
            // SAFETY: raising a signal whose default action is restored ends the process.
            unsafe {
                libc::raise(signal);
            }
            std::process::exit(128 + signal);
        }
    }

    impl Drop for Caught {
        fn drop(&mut self) {
            #[cfg(unix)]
            // SAFETY: restores the default actions `catch` replaced.
            unsafe {
                libc::signal(libc::SIGTERM, libc::SIG_DFL);
                libc::signal(libc::SIGINT, libc::SIG_DFL);
            }
        }
    }
}

/// `sweep SPEC --shard K/N` (or K and N from a job array): one shard, its table and file.
fn run_shard(args: &SweepArgs, id: &SweepId, plan: &[PlannedRow], shard: Shard, from: &str) -> Result<Exit> {
    let n = shard.rows(plan.len()).len();
    eprintln!("shard     {shard} (from {from}): {n} of the {} rows of {}", plan.len(), id.name);
    let (file, kept, path) = execute_shard(args, id, plan, shard, args.resume)?;
    if args.resume {
        eprintln!("resume    {kept} rows kept from {}, {} run", path.display(), n - kept);
    }
    let rows: Vec<SweepRow> = file.rows.into_iter().map(|r| r.row).collect();
    print!("{}", sweep::table(&rows));
    println!("written   {} (shard {shard}: {} of {} rows)", path.display(), rows.len(), plan.len());
    Ok(exit(&rows))
}

/// `sweep SPEC --resume` without a shard: completes every shard of the folder (by the shard
/// count of its files; one shard when it has none), then merges them.
fn resume_all(
    args: &SweepArgs,
    spec: &sweep::Spec,
    heat_maps: &[heatmap::Output],
    id: &SweepId,
    plan: &[PlannedRow],
) -> Result<Exit> {
    check_outputs(&args.out, plan.iter().map(|r| r.name.as_str()), Some(spec), heat_maps)?;
    let folder = args.out.join("shards");
    let files = if folder.is_dir() { shard_file::files_in(&args.out)? } else { Vec::new() };
    let mut counts = std::collections::BTreeSet::new();
    for f in &files {
        counts.insert(ShardFile::read(f)?.shard.count);
    }
    anyhow::ensure!(
        counts.len() <= 1,
        "--resume: {} holds shard files of {} shard counts ({:?}); keep those of one run",
        folder.display(),
        counts.len(),
        counts
    );
    let count = counts.into_iter().next().unwrap_or(1);
    for k in 0..count {
        let shard = Shard { index: k, count };
        let (file, kept, _) = execute_shard(args, id, plan, shard, true)?;
        eprintln!("resume    shard {shard}: {kept} rows kept, {} run", file.rows.len() - kept);
    }
    // The rows kept were checked against the plan as each shard resumed (ShardRun::start).
    let merged = merge::merge(std::slice::from_ref(&args.out))?;
    let earlier = sweep::rows_in(&args.out);
    let code = report(&merged.rows, merged.sampling, merged.samples_per_point, &merged.scenes, &args.out)?;
    finish(Some(spec), &merged.rows, heat_maps, (&earlier, &merged.scenes), &args.out)?;
    Ok(code)
}

/// `sweep merge DIR…`.
fn merge(m: &MergeArgs) -> Result<Exit> {
    let first = &m.dirs[0];
    let out = m.out.clone().unwrap_or_else(|| {
        if first.is_dir() {
            return first.clone();
        }
        let parent = first.parent().map(Path::to_path_buf).unwrap_or_default();
        match parent.file_name() {
            Some(name) if name == "shards" => parent.parent().map(Path::to_path_buf).unwrap_or_default(),
            _ => parent,
        }
    });
    check_dir(&out, &sweep::FILES)?;
    let heat_maps = heatmap::parse_outputs(&m.heatmap)?;
    anyhow::ensure!(
        m.heatmap.is_empty() || heat_maps.is_empty() || m.spec.is_some(),
        "--heatmap {} without --spec: a heat map's axes come from the sweep spec; give --spec SPEC",
        m.heatmap.join(",")
    );
    let spec = m.spec.as_ref().map(|f| sweep::Spec::load(f)).transpose()?;
    let merged = merge::merge(&m.dirs)?;
    check_outputs(&out, merged.scenes.iter().map(|(name, _)| name.as_str()), spec.as_ref(), &heat_maps)?;
    if let (Some(spec), Some(file)) = (&spec, &m.spec) {
        let plan = spec.plan();
        let same = ["generated", "reference"].iter().any(|k| SweepId::of(spec, &plan, k).plan_hash == merged.plan_hash);
        anyhow::ensure!(
            same,
            "--spec {}: its plan is not the shards' ({}): the spec changed since the shards ran, or belongs to another sweep",
            file.display(),
            merged.plan_hash
        );
        merged.check_rows(&plan)?;
    }
    eprintln!(
        "merged    {} shard files of {} ({} rows, plan {})",
        merged.files.len(),
        merged.name,
        merged.rows.len(),
        merged.plan_hash
    );
    let earlier = sweep::rows_in(&out);
    let code = report(&merged.rows, merged.sampling, merged.samples_per_point, &merged.scenes, &out)?;
    finish(spec.as_ref(), &merged.rows, &heat_maps, (&earlier, &merged.scenes), &out)?;
    Ok(code)
}

/// `sweep SPEC --slurm`: prints the job script.
fn slurm(args: &SweepArgs, spec: &sweep::Spec, plan: &[PlannedRow]) -> Result<Exit> {
    let rows = plan.len();
    let shards = args.shards.unwrap_or(slurm::default_shards(rows));
    anyhow::ensure!((1..=rows).contains(&shards), "--shards = {shards}: in [1, {rows}] (the sweep's rows)");
    let cpus = args.jobs.unwrap_or(1);
    anyhow::ensure!(cpus >= 1, "--jobs = 0: at least 1 (each task's CPUs)");
    let exe = std::env::current_exe().context("cannot find the kanestop binary's path")?;
    let spec_file = spec.file.canonicalize().with_context(|| format!("cannot resolve {}", spec.file.display()))?;
    let out = std::path::absolute(&args.out).with_context(|| format!("cannot resolve {}", args.out.display()))?;
    // What the jobs would find only after the array ran: the folder and the merge's files in
    // it, and shard files there of another sweep or shard count.
    let heat_maps = heatmap::parse_outputs(&args.heatmap)?;
    check_outputs(&out, plan.iter().map(|r| r.name.as_str()), Some(spec), &heat_maps)?;
    check_dir(&out.join("shards"), &[])?;
    let id = SweepId::of(spec, plan, args.kernel.0.name());
    kanestop_workflow::sweep::shard_file::check_joinable(&out, &id, shards)?;
    if shards > slurm::DEFAULT_MAX_ARRAY_SIZE {
        eprintln!(
            "note: --shards = {shards}: above Slurm's default MaxArraySize, {} (task indices 0 to {}), sbatch refuses \
             the array unless the cluster raised it (scontrol show config | grep MaxArraySize); or give fewer shards",
            slurm::DEFAULT_MAX_ARRAY_SIZE,
            slurm::DEFAULT_MAX_ARRAY_SIZE - 1
        );
    }
    let script = slurm::JobScript {
        kanestop: &exe,
        spec: &spec_file,
        out: &out,
        name: &spec.name,
        rows,
        shards,
        cpus,
        kernel: args.kernel.0.name(),
        checkpoint: args.checkpoint,
        heatmap: &args.heatmap,
    };
    print!("{}", script.text());
    Ok(Exit::Done)
}

/// `report sensitivity [SCENE]`.
pub fn sensitivity(args: &SensitivityArgs) -> Result<Exit> {
    let scene = match &args.scene {
        Some(p) => Scene::load(p)?,
        None => Scene::from_toml(kanestop_runtime::paper::DEFAULT_SCENE, "embedded case01.toml")?,
    };
    let sigmas: Vec<(String, f64)> = match &args.uncertain {
        Some(p) => {
            let spec = sweep::Spec::load(p)?;
            anyhow::ensure!(
                !spec.uncertain.is_empty(),
                "--uncertain {}: no [[uncertain]] input in it; the band needs at least one (path, distribution)",
                p.display()
            );
            spec.uncertain.iter().map(|u| (u.path.clone(), u.distribution.sigma_ln())).collect()
        }
        None => Vec::new(),
    };
    kanestop_workflow::parallel::check_jobs(args.jobs)?;
    check_dir(&args.out, &sensitivity::FILES)?;
    sensitivity::check_step(args.step)?;
    let probes = sensitivity::probes(&scene, args.step);
    let kernel = kernels::factory(KernelChoice::Generated);
    let bar = progress::bar(sensitivity::run_count(&probes), "runs");
    let study = match sensitivity::study(&scene, args.step, &probes, &kernel, args.jobs, &|| bar.inc(1)) {
        Err(e @ kanestop_workflow::Error::BaseRun { refused, .. }) => {
            bar.finish_and_clear();
            eprintln!("error: {e}");
            return Ok(if refused { Exit::BadInput } else { Exit::NumericalFailure });
        }
        study => study?,
    };
    bar.finish_and_clear();
    print!("{}", sensitivity::table(&study));
    if !sigmas.is_empty() {
        let sensitivity::Band { sd: band, unknown, missing } = sensitivity::band(&study, &sigmas);
        let used = sigmas.len() - missing.len();
        if used == 0 {
            println!(
                "no first-order band: none of the {} uncertain inputs is a continuous parameter of the scene",
                sigmas.len()
            );
        } else {
            // An output the base run did not give has no band, nor one an input's effect on
            // is unknown (counting it as zero would narrow the band).
            let o = |k: usize, s: f64, digits: usize, unit: &str| match study.base[k] {
                Some(_) if !unknown[k].is_empty() => format!(
                    "— (the effect of {} is unknown: see the table's line under its row)",
                    unknown[k].join(", ")
                ),
                Some(v) => format!("{:.*} ± {:.*} {unit}", digits, v * s, digits, band[k] * s),
                None => "— (the base run gave none)".to_string(),
            };
            let inputs = if used == 1 { "input" } else { "inputs" };
            println!("first-order band (1 σ) from {used} uncertain {inputs}:");
            println!("  stopping time      {}", o(0, 1.0, 3, "s"));
            println!("  stopping distance  {}", o(1, 1.0, 3, "m"));
            println!("  peak tension       {}", o(2, 1e-3, 1, "kN"));
        }
        for m in missing {
            println!("  note: {m} is not a continuous parameter of the scene (a zero or non-real field); ignored");
        }
    }
    let [c, j, u] = sensitivity::write(&study, &args.out)?;
    println!("written   {}, {} and {} (the columns' units)", c.display(), j.display(), u.display());
    Ok(Exit::Done)
}

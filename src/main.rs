//! `kanestop`: simulate a ship-restraining system with Kane's method.
//!
//! `cargo run --release` runs the paper's case 1 (embedded); see `--help` for the rest.

mod commands;
mod sweep;

use commands::RunOutcome;

use std::path::{Path, PathBuf};
use std::process::ExitCode;

use anyhow::{Context, Result};
use clap::builder::PossibleValue;
use clap::{Parser, Subcommand, ValueEnum};
use kanestop_runtime::model::Model;
use kanestop_runtime::paper::DEFAULT_SCENE;
use kanestop_runtime::scene::{Method, Scene, SceneError};
use kanestop_workflow::kernels::{self, KernelChoice};
use kanestop_workflow::output::CsvNumber;

#[derive(Parser)]
#[command(
    name = "kanestop",
    version,
    about = "Kane-method simulator for ship-restraining systems (anchor, chain, cable, rod, ship)",
    after_help = EXIT_CODES_HELP
)]
struct Cli {
    #[command(subcommand)]
    command: Option<Command>,
}

#[derive(Subcommand)]
enum Command {
    /// Run one scene and print a summary (default: the paper's case 1).
    Run {
        /// Scene TOML file; omitted: the embedded case 1.
        scene: Option<PathBuf>,
        /// Write the time history as CSV to this file (written whole or not at all; a missing
        /// folder is created).
        #[arg(long)]
        out: Option<PathBuf>,
        /// Write plots (SVG) of the run into this folder.
        #[arg(long)]
        plot: Option<PathBuf>,
        /// Channels of the CSV history, by name or group, e.g. `ship_x,tension_fairlead` or
        /// `ship,anchor,tension` (groups: ship, anchor, tension, energy, bodies, joints);
        /// default: all. The units go beside it in `<name>.units.csv` (docs/conventions.md).
        #[arg(long, value_delimiter = ',', requires = "out")]
        channels: Vec<String>,
        /// Print the summary as one JSON object (docs/conventions.md) instead of text; notes
        /// on files written go to standard error.
        #[arg(long)]
        json: bool,
        /// Add the solver internals to the text summary: physics, bodies, catenary
        /// residuals, stability eigenvalues, final state (--json's object is the
        /// same with or without it).
        #[arg(long, short)]
        verbose: bool,
        /// Which Kane kernel evaluates the equations of motion.
        #[arg(long, value_enum, default_value = "generated")]
        kernel: KernelArg,
        #[command(flatten)]
        solver: SolverOverrides,
    },
    /// Evaluate the equations of motion once and print JSON (M, f, qdd, body states).
    Eval {
        /// Scene TOML file; omitted: the embedded case 1.
        scene: Option<PathBuf>,
        /// The scene, as a flag (the same as the positional argument).
        #[arg(long = "scene", value_name = "SCENE", conflicts_with = "scene")]
        scene_flag: Option<PathBuf>,
        /// State JSON {"q": [...], "u": [...], "anchor": "free"|"stuck"}; omitted: the
        /// scene's initial state.
        #[arg(long)]
        state: Option<PathBuf>,
        #[arg(long, value_enum, default_value = "generated")]
        kernel: KernelArg,
    },
    /// Reports that run a scene many times (e.g. `report accuracy`).
    Report {
        #[command(subcommand)]
        kind: ReportKind,
    },
    /// Run scenes in parallel (files, or every *.toml of a folder): a table of stopping times
    /// (against Table 3 where the scene is one of the paper's cases), peak tensions, anchor
    /// start and energy drift, also written as batch.csv and batch.json, with the columns'
    /// units in batch.units.csv.
    Batch {
        /// Scene TOML files or folders of them, e.g. scenes/paper, or
        /// scenes/paper/case01.toml scenes/paper/case15.toml.
        #[arg(required = true, value_name = "SCENES")]
        paths: Vec<PathBuf>,
        /// Folder for batch.csv, batch.json and batch.units.csv.
        #[arg(long, default_value = "out")]
        out: PathBuf,
        /// Validate against Table 3: every paper case's stopping time within this relative
        /// tolerance (e.g. 0.05), same order, energy drift < 0.5 %, no break load exceeded;
        /// exit code 1 otherwise.
        #[arg(long, allow_negative_numbers = true)]
        tolerance: Option<f64>,
        #[arg(long, value_enum, default_value = "generated")]
        kernel: KernelArg,
        #[command(flatten)]
        solver: SolverOverrides,
        /// Compare methods: run every scene with each, e.g. `rk4,dp5@0.02,sdirk4@0.02`
        /// (`@dt` sets that method's step or observation interval, s; a method given more than
        /// once needs it on each, `rk4@0.01,rk4@0.005`). Replaces --integrator.
        #[arg(long, value_delimiter = ',')]
        methods: Vec<MethodSpec>,
        /// Repeat every run refined (dt/2; adaptive methods also at rtol/10 and atol/10) and
        /// report the differences as error estimates (stopping time, trajectory, peak tension).
        #[arg(long)]
        error_estimate: bool,
    },
    /// Run one or more scenes and plot them overlaid (SVG): ship surge speed, ship and
    /// anchor displacement, peak joint tension and its utilisation along the line, energy
    /// terms.
    Plot {
        /// Scene TOML files.
        #[arg(required = true)]
        scenes: Vec<PathBuf>,
        /// Folder for the SVG files.
        #[arg(long, default_value = "out/plots")]
        out: PathBuf,
        #[arg(long, value_enum, default_value = "generated")]
        kernel: KernelArg,
    },
    /// Run one scene over grid axes and sampled uncertain inputs (docs/sweeps.md): one row
    /// per run with its inputs, outputs and design checks, as sweep.csv (its units in
    /// sweep.units.csv) and sweep.json; in
    /// shards over a job array (--shard, --slurm) merged by `sweep merge`.
    Sweep(sweep::SweepArgs),
    /// Show what the generator makes of a scene: its signature, the kernel chosen (unrolled or
    /// rolled) and what it leaves out, operation counts with the parameters kept as inputs and
    /// folded as the scene's literals; `--fold DIR` writes the scene's folded kernel, `--write`
    /// regenerates the checked-in kernels under generated/src/.
    Codegen {
        /// Scene TOML file; omitted: the embedded case 1.
        scene: Option<PathBuf>,
        /// The scene, as a flag (the same as the positional argument).
        #[arg(long = "scene", value_name = "SCENE", conflicts_with = "scene")]
        scene_flag: Option<PathBuf>,
        /// Rewrite every checked-in kernel (the test sizes and the counts of scenes/paper).
        #[arg(long)]
        write: bool,
        /// Write the scene's unrolled kernel with its parameters folded in as literals into
        /// this folder, as `folded_<scene file name>.rs`; `KANESTOP_FOLDED_KERNELS=DIR cargo
        /// build --release` builds it in, and a chain with exactly these numbers runs on it
        /// (docs/codegen.md, "Parameters: kept as inputs or folded").
        #[arg(long, value_name = "DIR")]
        fold: Option<PathBuf>,
        /// Repository root holding scenes/ and generated/ (for --write).
        #[arg(long, default_value = ".")]
        root: PathBuf,
    },
}

/// The reports.
#[derive(Subcommand)]
enum ReportKind {
    /// Error against run time: a work–precision study of RK4 (over dt), DP5 and SDIRK4
    /// (over tolerances) against a tight reference run; table, accuracy.csv/json (the CSV's
    /// units in accuracy.units.csv) and a log–log plot (accuracy.svg).
    Accuracy {
        /// Scene TOML file; omitted: the embedded case 1.
        scene: Option<PathBuf>,
        /// Folder for accuracy.csv, accuracy.json, accuracy.svg and accuracy.units.csv.
        #[arg(long, default_value = "out/accuracy")]
        out: PathBuf,
        /// Runs per setting, 1 to 100; the median CPU time (and the median wall time beside it)
        /// is reported.
        #[arg(long, default_value_t = 3)]
        repeats: usize,
        /// Absolute tolerance of the adaptive runs as a multiple of their rtol: 1e-8 to 1e3, so
        /// that every atol of the study is a scene's (in [1e-16, 1]).
        #[arg(long, allow_negative_numbers = true, default_value_t = kanestop_workflow::accuracy::DEFAULT_ATOL_RATIO)]
        atol_ratio: f64,
        #[arg(long, value_enum, default_value = "generated")]
        kernel: KernelArg,
    },
    /// d(output)/d(ln p) of stopping time, stopping distance and peak tension against every
    /// continuous physical parameter (central differences, runs in parallel), ranked.
    Sensitivity(sweep::SensitivityArgs),
}

/// `--kernel`: which Kane kernel evaluates the equations of motion.
#[derive(Clone, Copy)]
pub(crate) struct KernelArg(pub(crate) KernelChoice);

impl ValueEnum for KernelArg {
    fn value_variants<'a>() -> &'a [Self] {
        &[KernelArg(KernelChoice::Reference), KernelArg(KernelChoice::Generated)]
    }

    fn to_possible_value(&self) -> Option<PossibleValue> {
        let help = match self.0 {
            KernelChoice::Reference => "The generic formulation of the paper's Eqs. 1–27 (slow, the oracle)",
            KernelChoice::Generated => {
                "Flat code emitted by kanestop-codegen, with the O(N) recursive solve (default): the rolled steps, \
                 which serve any N, with the scene's loads fused in (every scene of the repository); unrolled where \
                 the loads are not fused and the build has the chain's N"
            }
        };
        Some(PossibleValue::new(self.0.name()).help(help))
    }
}

impl KernelArg {
    pub(crate) fn factory(self) -> impl Fn(&Model) -> Box<dyn kanestop_runtime::kernel::Kernel> + Sync {
        kernels::factory(self.0)
    }
}

/// `codegen`: what would be generated for a scene, and optionally write the checked-in files.
fn codegen(scene: Option<&PathBuf>, write: bool, fold: Option<&Path>, root: &Path) -> Result<()> {
    use kanestop_chain::Water;
    // The folded kernel's name, from the scene's file name, and its folder, checked first.
    let fold = fold
        .map(|dir| -> Result<(PathBuf, String)> {
            let stem = scene.and_then(|s| s.file_stem()).map_or("case01".into(), |s| s.to_string_lossy());
            let name = folded_name(&stem);
            kanestop_workflow::output::check_dir_target(dir)
                .with_context(|| format!("--fold: cannot write into {}", dir.display()))?;
            Ok((dir.join(format!("{name}.rs")), name))
        })
        .transpose()?;
    // --write's folder, checked before any work.
    let write_dir = write.then(|| root.join("generated/src"));
    if let Some(dir) = &write_dir {
        anyhow::ensure!(dir.is_dir(), "{} is not a directory: pass --root <repository>", dir.display());
    }
    let model = load_model(scene)?;
    let n = model.body_count();
    let variant = variant_of(&model);
    let (water, wet) = (variant.water, variant.water == Water::On);
    let t = &model.topology;
    println!("scene      {} (N = {n})", model.scene.meta.name);
    println!(
        "bodies     anchor, {} chain links, {} cable elements in {} stage{}, auxiliary rod, ship",
        t.chain_links,
        t.cable_elements(),
        t.cable_stages.len(),
        if t.cable_stages.len() == 1 { "" } else { "s" }
    );
    let forces = kanestop_runtime::forces::Forces::new(&model);
    let mut kernel = kanestop_runtime::generated::GeneratedKernel::new(&model.chain);
    // Whether a run fuses the loads into the kernel: as the run's own dynamics decide it.
    let fused = kernel.as_mut().is_ok_and(|k| {
        use kanestop_runtime::kernel::Kernel;
        kanestop_runtime::dynamics::fused_loads(&forces).is_some_and(|f| k.fuse_loads(&f))
    });
    load_report(&model, &forces, fused);
    let sig = forces.signature().name();
    let kernel = match kernel.map(|k| k.form()) {
        Ok(_) if fused => format!(
            "rhs_free_{sig}, rhs_stuck_{sig}: the fused right-hand side on the steps of rolled_{} (any N)",
            water.suffix()
        ),
        Ok(kanestop_runtime::generated::Form::Unrolled) => {
            format!("{} (unrolled, built for N = {n})", variant.module())
        }
        Ok(kanestop_runtime::generated::Form::Folded) => format!(
            "{} (unrolled, this scene's parameters folded in)",
            kanestop_runtime::generated::folded_for(&model.chain).unwrap_or_default()
        ),
        Ok(kanestop_runtime::generated::Form::Rolled) => {
            format!("rolled_{} (any N; no unrolled kernel for N = {n} in this build)", water.suffix())
        }
        Err(e) => format!("none: {e}"),
    };
    println!("kernel     {kernel}");
    let zeros = variant.structural_zeros().count();
    println!(
        "folded     {zeros} structurally zero parameters{}",
        if wet { "" } else { "; every added-mass term (water off)" }
    );
    // The unrolled expansion's DAG recurses with N (docs/codegen.md: the build script stops at
    // MAX_UNROLLED_BODIES for the same reason); above that only the rolled kernel exists.
    if n <= kanestop_codegen::MAX_UNROLLED_BODIES {
        unrolled_op_counts(&model, variant);
    } else {
        let max = kanestop_codegen::MAX_UNROLLED_BODIES;
        println!("unrolled   not expanded above N = {max} (the rolled kernel's steps: docs/codegen.md)");
    }
    let available = kanestop_runtime::generated::available();
    println!(
        "built in  {}; folded: {}",
        available
            .iter()
            .map(|(n, w)| format!("{n}{}", if *w { " wet" } else { " dry" }))
            .collect::<Vec<_>>()
            .join(", "),
        kanestop_runtime::generated::folded_kernels().join(", ")
    );
    if let Some(name) = kanestop_runtime::generated::folded_for(&model.chain) {
        println!("           {name} has this scene's numbers folded in (it runs where the loads are not fused)");
    }
    if let Some((path, name)) = fold {
        let max = kanestop_codegen::MAX_UNROLLED_BODIES;
        anyhow::ensure!(n <= max, "--fold: no unrolled kernel is expanded above N = {max} bodies (this scene has {n})");
        let values = folded_values(&model);
        // Another scene's kernel under the same name (a scene of the same file name
        // elsewhere) is not overwritten.
        if let Ok(old) = std::fs::read_to_string(&path) {
            let same = kanestop_codegen::emit::folded_values_of(&old).is_ok_and(|v| v == values);
            anyhow::ensure!(
                same,
                "--fold: {} holds another kernel (not this scene's numbers); remove it or fold into another folder",
                path.display()
            );
        }
        let file = kanestop_codegen::emit::generate_folded(variant, &values, &name);
        let dir = path.parent().unwrap_or(Path::new("."));
        std::fs::create_dir_all(dir).with_context(|| format!("cannot create {}", dir.display()))?;
        kanestop_workflow::output::write_atomically(&path, file.source.as_bytes())
            .with_context(|| format!("cannot write {}", path.display()))?;
        // The folder as the build script reads it: absolute, whatever the directory now.
        let dir = dir.canonicalize().unwrap_or_else(|_| dir.to_path_buf());
        println!(
            "written    {} ({} lines); build it in: KANESTOP_FOLDED_KERNELS={} cargo build --release",
            path.display(),
            file.lines(),
            dir.display()
        );
    }
    if let Some(dir) = write_dir {
        let mut files = kanestop_codegen::checked_in_files(&kanestop_runtime::paper::body_counts());
        files.push(checked_in_folded(&root.join("scenes/paper/case01.toml"))?);
        for (name, text) in files {
            let path = dir.join(&name);
            let old = std::fs::read_to_string(&path).unwrap_or_default();
            if old != text {
                kanestop_workflow::output::write_atomically(&path, text.as_bytes())
                    .with_context(|| format!("cannot write {}", path.display()))?;
                println!("written   {}", path.display());
            }
        }
    }
    Ok(())
}

/// The scene's load signature, what its generated load code has and leaves out, and each
/// term's operations over this chain.
fn load_report(model: &Model, forces: &kanestop_runtime::forces::Forces, fused: bool) {
    use kanestop_chain::LoadTerm;
    use kanestop_codegen::loads::{signature_code, LoadBody};
    let sig = forces.signature();
    let (_, report) = signature_code(&sig);
    let names = |terms: Vec<LoadTerm>| terms.iter().map(|t| t.name()).collect::<Vec<_>>().join(", ");
    let absent: Vec<LoadTerm> = LoadTerm::ALL.into_iter().filter(|&t| !sig.has(t)).collect();
    println!("signature  {} ({})", sig.name(), names(sig.terms()));
    println!("left out   {}", if absent.is_empty() { "no load term".to_string() } else { names(absent) });
    if !fused {
        println!("loads      {} (the runtime's force models)", forces.description());
        return;
    }
    if sig == kanestop_chain::LoadSignature::weight_only() {
        println!("loads      weight alone, in the generated solve's own steps (no load array read)");
    } else {
        println!(
            "loads      generated in the solve's inward pass, line elements two at a time (no force model per call)"
        );
    }
    let count = |f: fn(&kanestop_chain::BodyKind) -> bool| model.chain.bodies.iter().filter(|b| f(&b.kind)).count();
    let lines = count(|k| matches!(k, kanestop_chain::BodyKind::ChainLink | kanestop_chain::BodyKind::Cable { .. }));
    let rods = count(|k| matches!(k, kanestop_chain::BodyKind::Rod));
    let term = |t: LoadTerm| report.term_total(t, lines, rods);
    let ops = |b, t| report.ops.get(&(b, t)).map_or(0, |o: &kanestop_codegen::loads::LoadOps| o.total());
    let shared = lines * report.shared_total(LoadBody::Element);
    let total: usize = shared + sig.terms().iter().map(|&t| term(t)).sum::<usize>();
    let per = |b| report.body_total(b);
    println!(
        "  load code  {total} operations per evaluation: anchor {}, line element {} (× {lines}), rod in air {} (× {rods}), ship {}",
        per(LoadBody::Anchor),
        per(LoadBody::Element),
        ops(LoadBody::Element, LoadTerm::Weight),
        per(LoadBody::Ship)
    );
    println!("             (counted on the emitted code: both branches of a piecewise term, the embedded volume as one call)");
    for t in sig.terms() {
        let n = term(t);
        println!("  {:<14} {n:>8} {:>6.1}%", t.name(), 100.0 * n as f64 / total.max(1) as f64);
    }
    if shared > 0 {
        let share = 100.0 * shared as f64 / total.max(1) as f64;
        println!(
            "  {:<14} {shared:>8} {share:>6.1}%   (a line element's rotation and end heights, which the terms share)",
            "shared"
        );
    }
}

/// The unrolled kernel's operation counts for `model`, parameters kept and folded.
fn unrolled_op_counts(model: &Model, variant: kanestop_chain::Variant) {
    let kept = kanestop_codegen::generate(variant);
    let folded = kanestop_codegen::emit::folded_op_counts(variant, &folded_values(model));
    println!("{}: {} lines (the unrolled expansion for this N)", kept.file_name, kept.lines());
    println!(
        "  {:<14} {:>10} {:>12} {:>8}   (operations; sin/cos in kinematics)",
        "function", "kept", "folded", "saved"
    );
    for (k, f) in kept.functions.iter().zip(&folded) {
        let (a, b) = (k.ops.total(), f.ops.total());
        println!("  {:<14} {a:>10} {b:>12} {:>7.1}%", k.name, 100.0 * (a as f64 - b as f64) / a as f64);
    }
}

/// The checked-in folded kernel (`kanestop_codegen::CHECKED_IN_FOLDED`) of the scene `case1`:
/// its file name and text.
fn checked_in_folded(case1: &Path) -> Result<(String, String)> {
    let model = load_model(Some(&case1.to_path_buf()))?;
    let variant = variant_of(&model);
    let name = kanestop_codegen::CHECKED_IN_FOLDED;
    let file = kanestop_codegen::emit::generate_folded(variant, &folded_values(&model), name);
    Ok((file.file_name, file.source))
}

/// The unrolled kernel's variant for `model`'s chain: N, water on when any body has added mass.
fn variant_of(model: &Model) -> kanestop_chain::Variant {
    let water = if model.chain.has_added_mass() { kanestop_chain::Water::On } else { kanestop_chain::Water::Off };
    kanestop_chain::Variant::new(model.body_count(), water)
}

/// The very numbers the runtime hands the kernel, for the generator to fold in.
fn folded_values(model: &Model) -> Vec<kanestop_codegen::planar::BodyValues> {
    kanestop_runtime::generated::body_params(&model.chain)
        .into_iter()
        .map(|b| kanestop_codegen::planar::BodyValues {
            mass: b.mass,
            inertia: b.inertia,
            centroid: b.centroid,
            joint: b.joint,
            added_mass: b.added_mass,
        })
        .collect()
}

/// A folded kernel's module name from a scene's file name: `folded_` and the name in lower
/// case, anything but letters and digits as `_`.
fn folded_name(stem: &str) -> String {
    let tail: String =
        stem.chars().map(|c| if c.is_ascii_alphanumeric() { c.to_ascii_lowercase() } else { '_' }).collect();
    format!("folded_{tail}")
}

fn load_model(scene: Option<&PathBuf>) -> Result<Model> {
    load_model_with(scene, &SolverOverrides::default())
}

/// Command-line overrides of the scene's `[solver]` section.
#[derive(clap::Args, Clone, Default)]
struct SolverOverrides {
    /// Integration method (overrides solver.integrator).
    #[arg(long, value_enum)]
    integrator: Option<MethodArg>,
    /// Time step or, for adaptive methods, observation interval, s (overrides solver.dt).
    #[arg(long, allow_negative_numbers = true)]
    dt: Option<f64>,
    /// Relative tolerance of the adaptive methods (overrides solver.rtol).
    #[arg(long, allow_negative_numbers = true)]
    rtol: Option<f64>,
    /// Absolute tolerance of the adaptive methods (overrides solver.atol).
    #[arg(long, allow_negative_numbers = true)]
    atol: Option<f64>,
    /// Interval of the recorded samples, s (overrides solver.output_interval).
    #[arg(long, allow_negative_numbers = true)]
    output_interval: Option<f64>,
    /// Time at which the run ends if the ship has not stopped, s (overrides solver.end_time).
    #[arg(long, allow_negative_numbers = true)]
    end_time: Option<f64>,
}

/// `--integrator`: a [`Method`], with the help text of each.
#[derive(Clone, Copy)]
struct MethodArg(Method);

impl ValueEnum for MethodArg {
    fn value_variants<'a>() -> &'a [Self] {
        &[MethodArg(Method::Rk4), MethodArg(Method::Dp5), MethodArg(Method::Sdirk4)]
    }

    fn to_possible_value(&self) -> Option<PossibleValue> {
        let help = match self.0 {
            Method::Rk4 => "Classic RK4, fixed step (the paper's)",
            Method::Dp5 => "Dormand–Prince 5(4), adaptive",
            Method::Sdirk4 => "L-stable SDIRK4, adaptive, for stiff scenes",
        };
        Some(PossibleValue::new(self.0.name()).help(help))
    }
}

/// One method of `batch --methods`: `rk4`, `dp5@0.02`, …
#[derive(Clone, Copy, Debug)]
struct MethodSpec {
    method: Method,
    dt: Option<f64>,
}

impl std::str::FromStr for MethodSpec {
    type Err = String;

    fn from_str(text: &str) -> Result<Self, String> {
        let (name, dt) = match text.split_once('@') {
            Some((name, dt)) => {
                let dt: f64 =
                    dt.parse().map_err(|_| format!("{text}: the step after @ must be a number of seconds"))?;
                (name, Some(dt))
            }
            None => (text, None),
        };
        let method = name.parse::<Method>().map_err(|e| format!("{e}, each optionally @dt"))?;
        Ok(MethodSpec { method, dt })
    }
}

impl std::fmt::Display for MethodSpec {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self.dt {
            Some(dt) => f.write_str(&kanestop_workflow::batch::method_at(self.method, dt)),
            None => f.write_str(self.method.name()),
        }
    }
}

/// The scene with the command line's `[solver]` values laid on its file's before it is
/// checked (they may mend it), and its model.
fn load_model_with(scene: Option<&PathBuf>, o: &SolverOverrides) -> Result<Model> {
    let over = o.table();
    let given: Vec<String> =
        over.get("solver").and_then(|t| t.as_table()).map_or(Vec::new(), |t| t.keys().cloned().collect());
    let raised = std::cell::Cell::new(None);
    let edit = |value: &mut toml::Value| raised.set(o.lay_on(value));
    let scene = match scene {
        Some(path) => Scene::load_edited(path, &edit),
        None if over.is_empty() => Scene::from_toml(DEFAULT_SCENE, "embedded case01.toml"),
        None => {
            let mut value = toml::Value::Table(DEFAULT_SCENE.parse::<toml::Table>().expect("case 1 is TOML"));
            edit(&mut value);
            Scene::from_value(value, "embedded case01.toml (with command-line overrides)")
        }
    }
    .map_err(|e| with_flag_hints(e, &given))?;
    if let Some(interval) = raised.get() {
        eprintln!(
            "note: solver.output_interval raised from the file's {} s to the step, {} s (the output grid holds at least one step; --output-interval sets it)",
            CsvNumber(interval),
            CsvNumber(scene.solver.dt)
        );
    }
    if scene.solver.integrator == Method::Rk4 && (o.rtol.is_some() || o.atol.is_some()) {
        eprintln!(
            "note: --rtol and --atol are the adaptive methods' tolerances; rk4 takes a fixed step and ignores them"
        );
    }
    Ok(Model::new(&scene)?)
}

/// The command-line flag that sets `[solver]` field `key`: `output_interval` → `--output-interval`.
fn flag(key: &str) -> String {
    format!("--{}", key.replace('_', "-"))
}

/// A scene refused with command-line flags given (`given`: the `[solver]` keys they set),
/// with a hint for each `[solver]` field refused that no flag set: its value is the file's,
/// and which flag sets it (`run --dt 0.1` refuses the file's output_interval = 0.02).
fn with_flag_hints(e: SceneError, given: &[String]) -> anyhow::Error {
    let hints: Vec<String> = match (&e, given.is_empty()) {
        (SceneError::Invalid { problems, .. }, false) => problems
            .iter()
            .filter_map(|p| p.field.strip_prefix("solver."))
            .filter(|key| !given.iter().any(|g| g == key))
            .map(|key| format!("  solver.{key} is the file's: {} sets it on the command line", flag(key)))
            .collect(),
        _ => Vec::new(),
    };
    let e = anyhow::Error::from(e);
    if hints.is_empty() {
        e
    } else {
        anyhow::anyhow!("{e}\n{}", hints.join("\n"))
    }
}

impl SolverOverrides {
    /// Refuses a value outside its field's own range before anything runs (`batch --dt 0`
    /// ran every scene as invalid): [`kanestop_runtime::scene::Solver::own_problems`] of the
    /// flags laid on case 1's solver, the flags' fields only (a range bound by another field
    /// of a scene, `output_interval` ≥ `dt`, is each scene's to meet).
    fn check_alone(&self) -> Result<()> {
        let case = Scene::from_toml(DEFAULT_SCENE, "embedded case01.toml")?;
        let mut value = toml::Value::try_from(&case.solver).expect("a solver is a table");
        let Some(solver) = self.table().remove("solver") else { return Ok(()) };
        kanestop_runtime::overrides::merge(&mut value, solver.clone());
        let flags: kanestop_runtime::scene::Solver =
            kanestop_runtime::scene::from_value_at(value).map_err(|e| anyhow::anyhow!("{e}"))?;
        let given = |key: &str| solver.as_table().is_some_and(|t| t.contains_key(key));
        let bad: Vec<String> = flags
            .own_problems()
            .iter()
            .filter_map(|p| p.field.strip_prefix("solver.").filter(|key| given(key)).map(|key| (key, p)))
            .map(|(key, p)| format!("{} = {}: must be {}", flag(key), p.value, p.expected))
            .collect();
        anyhow::ensure!(bad.is_empty(), "{}", bad.join("\n"));
        Ok(())
    }

    /// Lays the overrides on a scene's tables, a step without `--output-interval` raising the
    /// scene's shorter interval to it ([`kanestop_runtime::overrides::raise_output_interval`],
    /// whose returned interval this returns).
    fn lay_on(&self, value: &mut toml::Value) -> Option<f64> {
        kanestop_runtime::overrides::merge(value, toml::Value::Table(self.table()));
        let dt = self.dt.filter(|_| self.output_interval.is_none())?;
        kanestop_runtime::overrides::raise_output_interval(value, dt)
    }

    /// The overrides as a scene's tables: `{solver = {dt = …, …}}`, empty when none is given.
    fn table(&self) -> toml::Table {
        let mut solver = toml::Table::new();
        if let Some(MethodArg(method)) = self.integrator {
            solver.insert("integrator".into(), toml::Value::String(method.name().into()));
        }
        let reals =
            [("dt", self.dt), ("rtol", self.rtol), ("atol", self.atol), ("output_interval", self.output_interval)];
        for (key, v) in reals.into_iter().chain([("end_time", self.end_time)]) {
            if let Some(v) = v {
                solver.insert(key.into(), toml::Value::Float(v));
            }
        }
        let mut top = toml::Table::new();
        if !solver.is_empty() {
            top.insert("solver".into(), toml::Value::Table(solver));
        }
        top
    }
}

/// A batch configuration that owns its captures.
type BoxedConfigure<'a> = Box<dyn Fn(&mut toml::Value) + Sync + 'a>;

/// How `batch` edits each scene file's tables before they are checked: once with the
/// overrides alone, or once per method of `--methods` (each with its `@dt`, the file's output
/// interval raised to it where shorter: the output grid must hold at least one step), the
/// flags laid on last.
fn configurations<'a>(solver: &'a SolverOverrides, methods: &[MethodSpec]) -> Vec<BoxedConfigure<'a>> {
    let edit = move |value: &mut toml::Value, method: Option<MethodSpec>| {
        if let (Some(m), Some(top)) = (method, value.as_table_mut()) {
            let table = top.entry("solver").or_insert_with(|| toml::Value::Table(toml::Table::new()));
            if let Some(table) = table.as_table_mut() {
                table.insert("integrator".into(), toml::Value::String(m.method.name().into()));
                if let Some(dt) = m.dt {
                    table.insert("dt".into(), toml::Value::Float(dt));
                }
            }
            if let Some(dt) = m.dt {
                kanestop_runtime::overrides::raise_output_interval(value, dt);
            }
        }
        solver.lay_on(value);
    };
    if methods.is_empty() {
        vec![Box::new(move |value: &mut toml::Value| edit(value, None))]
    } else {
        methods.iter().map(|&m| Box::new(move |value: &mut toml::Value| edit(value, Some(m))) as Box<_>).collect()
    }
}

/// Rust ignores SIGPIPE, so a closed pipe (`kanestop codegen | head`) makes `println!`
/// panic; like other command-line tools, end quietly instead.
fn restore_sigpipe() {
    #[cfg(unix)]
    // SAFETY: called first in main, before any thread exists; SIG_DFL is a valid handler.
    unsafe {
        libc::signal(libc::SIGPIPE, libc::SIG_DFL);
    }
}

/// The exit codes, as `--help` lists them.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Exit {
    /// Done.
    Done = 0,
    /// `batch`: a scene was invalid or failed, or `--tolerance` validation missed.
    BatchMissed = 1,
    /// Bad input: arguments, scene, state file, output path, or a step refused before the run.
    BadInput = 2,
    /// A run ended in a numerical failure.
    NumericalFailure = 3,
    /// A run completed but a design check failed (a break load exceeded, or a `[checks]` limit).
    CheckFailed = 4,
}

/// The exit codes in words, for `--help`.
const EXIT_CODES_HELP: &str = "Exit codes:
  0  done
  1  batch: a scene was invalid or failed, or --tolerance validation missed
  2  bad input: arguments, scene, state file, an output path that cannot be written, or a
     step refused before the run (the diagnostic is printed on standard error); sweep
     merge: shard files of different sweeps, a row missing or twice
  3  numerical failure during a run (the diagnostic is printed on standard error)
  4  a design check failed: a break load was exceeded, or a limit of the scene's or the sweep
     spec's [checks] (sweep, a shard or a merge, batch: in some row); 3 takes precedence
     over 4, and in a batch 1 does

Summaries and tables go to standard output; errors, diagnostics and progress to standard error.";

impl From<Exit> for ExitCode {
    fn from(e: Exit) -> ExitCode {
        ExitCode::from(e as u8)
    }
}

fn main() -> ExitCode {
    restore_sigpipe();
    match try_main() {
        Ok(code) => code.into(),
        Err(e) => {
            eprintln!("error: {e:#}");
            Exit::BadInput.into()
        }
    }
}

fn try_main() -> Result<Exit> {
    let cli = Cli::parse();
    let command = cli.command.unwrap_or(Command::Run {
        scene: None,
        out: None,
        plot: None,
        channels: Vec::new(),
        json: false,
        verbose: false,
        kernel: KernelArg(KernelChoice::Generated),
        solver: SolverOverrides::default(),
    });
    match command {
        Command::Run { scene, out, plot, channels, json, verbose, kernel: choice, solver } => {
            let model = load_model_with(scene.as_ref(), &solver)?;
            let files = commands::RunFiles { out: out.as_deref(), plot: plot.as_deref(), channels: &channels };
            Ok(match commands::run(&model, &choice.factory(), &files, json, verbose)? {
                RunOutcome::Done => Exit::Done,
                RunOutcome::Refused => Exit::BadInput,
                RunOutcome::NumericalFailure => Exit::NumericalFailure,
                RunOutcome::CheckFailed => Exit::CheckFailed,
            })
        }
        Command::Eval { scene, scene_flag, state, kernel: choice } => {
            let model = load_model(scene.as_ref().or(scene_flag.as_ref()))?;
            commands::eval(&model, &choice.factory(), state.as_deref())?;
            Ok(Exit::Done)
        }
        Command::Report { kind: ReportKind::Accuracy { scene, out, repeats, atol_ratio, kernel: choice } } => {
            let model = load_model(scene.as_ref())?;
            commands::accuracy(&model.scene, &out, repeats, atol_ratio, &choice.factory())?;
            Ok(Exit::Done)
        }
        Command::Sweep(args) => sweep::sweep(&args),
        Command::Report { kind: ReportKind::Sensitivity(args) } => sweep::sensitivity(&args),
        Command::Plot { scenes, out, kernel: choice } => Ok(match commands::plot(&scenes, &out, &choice.factory())? {
            RunOutcome::Refused => Exit::BadInput,
            RunOutcome::NumericalFailure => Exit::NumericalFailure,
            RunOutcome::Done | RunOutcome::CheckFailed => Exit::Done,
        }),
        Command::Batch { paths, out, tolerance, kernel: choice, solver, methods, error_estimate } => {
            if let Some(t) = tolerance {
                anyhow::ensure!(t.is_finite() && t > 0.0, "--tolerance {t}: must be a number > 0 (e.g. 0.05 for 5 %)");
                if t >= 1.0 {
                    eprintln!(
                        "warning: --tolerance {t} is a fraction: {} % (for {t} %, give {})",
                        100.0 * t,
                        t / 100.0
                    );
                }
            }
            anyhow::ensure!(
                methods.is_empty() || (solver.integrator.is_none() && solver.dt.is_none()),
                "--methods sets the integrator and its step (method@dt): drop --integrator and --dt"
            );
            solver.check_alone()?;
            for (i, m) in methods.iter().enumerate() {
                anyhow::ensure!(
                    !methods[..i].iter().any(|o| o.method == m.method && o.dt == m.dt),
                    "--methods {m}: given twice (each method once per step)"
                );
                // Without its step, an entry runs each scene at the scene's own, which another
                // entry's may equal: rows alike, and no step common to a label's rows.
                let again = methods.iter().filter(|o| o.method == m.method).count() > 1;
                anyhow::ensure!(
                    !again || m.dt.is_some(),
                    "--methods {m}: {} is given more than once, so give each its step ({}@DT)",
                    m.method.name(),
                    m.method.name()
                );
                SolverOverrides { integrator: Some(MethodArg(m.method)), dt: m.dt, ..solver.clone() }
                    .check_alone()
                    .with_context(|| format!("--methods {m}"))?;
            }
            let per_method = configurations(&solver, &methods);
            let configures: Vec<kanestop_workflow::batch::Configure> = per_method.iter().map(|c| c.as_ref()).collect();
            Ok(match commands::batch(&paths, &out, &configures, &choice.factory(), error_estimate, tolerance)? {
                commands::BatchOutcome::Done => Exit::Done,
                commands::BatchOutcome::Missed => Exit::BatchMissed,
                commands::BatchOutcome::CheckFailed => Exit::CheckFailed,
            })
        }
        Command::Codegen { scene, scene_flag, write, fold, root } => {
            codegen(scene.as_ref().or(scene_flag.as_ref()), write, fold.as_deref(), &root)?;
            Ok(Exit::Done)
        }
    }
}

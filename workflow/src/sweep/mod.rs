//! Sweeps: one base scene run over grid axes and sampled uncertain inputs ([`spec`],
//! [`sampling`]), one row per run in spec order with its inputs as columns, the run's
//! summary ([`crate::record::RunSummary`], the same numbers as `run --json` of the row's
//! scene) and its design checks; written as CSV and JSON (docs/sweeps.md). A sweep can run
//! in [`shard`]s, each saved as a [`shard_file`], and be put back together by [`merge`];
//! [`slurm`] writes the job script that does it on a Slurm cluster.

pub mod heatmap;
pub mod merge;
#[cfg(feature = "parquet")]
pub mod parquet;
pub mod sampling;
pub mod shard;
pub mod shard_file;
pub mod slurm;
pub mod spec;
pub mod units;

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};
use std::sync::atomic::AtomicBool;

use kanestop_runtime::model::Model;
use kanestop_runtime::simulate;
use serde::de::{MapAccess, Visitor};
use serde::ser::SerializeMap;
use serde::{Deserialize, Deserializer, Serialize, Serializer};
use toml::Value;

pub use spec::{PlannedRow, Spec};

use crate::batch::Status;
use crate::checks;
use crate::kernels::KernelFactory;
use crate::output::{self, csv_field, write_atomically, CsvNumber};
use crate::record::{Peak, RunSummary};
use crate::{parallel, Error, Result};

/// A row's inputs in spec order (a JSON object keyed by dotted path).
#[derive(Clone, Debug, PartialEq)]
pub struct Inputs(pub Vec<(String, Value)>);

impl Serialize for Inputs {
    fn serialize<S: Serializer>(&self, s: S) -> std::result::Result<S::Ok, S::Error> {
        let mut m = s.serialize_map(Some(self.0.len()))?;
        for (k, v) in &self.0 {
            m.serialize_entry(k, v)?;
        }
        m.end()
    }
}

impl<'de> Deserialize<'de> for Inputs {
    fn deserialize<D: Deserializer<'de>>(d: D) -> std::result::Result<Inputs, D::Error> {
        /// Reads the object's entries in file order (the spec's order of the inputs).
        struct InOrder;
        impl<'de> Visitor<'de> for InOrder {
            type Value = Inputs;
            fn expecting(&self, f: &mut std::fmt::Formatter) -> std::fmt::Result {
                f.write_str("an object of inputs by dotted path")
            }
            fn visit_map<A: MapAccess<'de>>(self, mut map: A) -> std::result::Result<Inputs, A::Error> {
                let mut out = Vec::new();
                while let Some(entry) = map.next_entry::<String, Value>()? {
                    out.push(entry);
                }
                Ok(Inputs(out))
            }
        }
        d.deserialize_map(InOrder)
    }
}

/// One run of a sweep.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct SweepRow {
    /// Its index, from 0, in spec order.
    pub index: usize,
    /// `name-000`: also the row scene's `meta.name`.
    pub name: String,
    /// The inputs, e.g. `ship.mass=750000 initial.ship_speed=3`.
    pub label: String,
    /// The swept inputs and their values.
    pub inputs: Inputs,
    /// How the run ended (`invalid`: the inputs give no valid scene or model).
    pub status: Status,
    /// Whether every design check passed (the break loads and `[checks]`, the run's
    /// `checks_pass`); none when no check was made: no `[checks]`, and an invalid row or a run
    /// refused or failed with no break load exceeded.
    pub checks_pass: Option<bool>,
    /// Energy taken by each term over the initial kinetic energy (−work / K_0), by name
    /// (negative where the term gave energy back).
    pub energy_split: BTreeMap<String, f64>,
    /// The run's summary, as `run --json` prints it for the row's scene (none when invalid).
    pub summary: Option<RunSummary>,
    /// Why the row is invalid, or the failure's diagnostic, on one line.
    pub message: String,
}

pub(crate) fn label(inputs: &[(String, Value)]) -> String {
    inputs.iter().map(|(k, v)| format!("{k}={}", fmt_value(v))).collect::<Vec<_>>().join(" ")
}

fn fmt_value(v: &Value) -> String {
    match v {
        Value::String(s) => s.clone(),
        // As every CSV writes a number: an exponent for the very small and large (1e300
        // wrote 301 digits).
        Value::Float(x) => CsvNumber(*x).to_string(),
        other => other.to_string(),
    }
}

/// Runs one planned row, stopped at the run's next step (or within its start-up stability analysis)
/// once `cancel` is set (Python's Ctrl-C): None.
pub fn run_row_cancellable(row: &PlannedRow, kernel: KernelFactory, cancel: &AtomicBool) -> Option<SweepRow> {
    let mut out = SweepRow {
        index: row.index,
        name: row.name.clone(),
        label: label(&row.inputs),
        inputs: Inputs(row.inputs.clone()),
        status: Status::Invalid,
        checks_pass: None,
        energy_split: BTreeMap::new(),
        summary: None,
        message: String::new(),
    };
    let model = match row.scene.clone().and_then(|s| Model::new(&s).map_err(|e| e.to_string())) {
        Ok(m) => m,
        Err(e) => {
            out.message = one_line(&e);
            return Some(out);
        }
    };
    let result = simulate::run_checked_cancellable(&model, kernel(&model), kernel(&model), cancel).ok()?;
    let summary = RunSummary::of(&model, &result);
    out.status = summary.status;
    out.checks_pass = summary.checks_pass;
    // Shares of the initial kinetic energy, as `run`'s energy line gives them.
    let k0 = summary.initial_kinetic_energy;
    if k0 > 0.0 {
        // + 0.0: no work is 0, not the -0.0 of its negation.
        out.energy_split = summary.work.iter().filter_map(|(k, w)| Some((k.clone(), -(*w)? / k0 + 0.0))).collect();
    }
    // A numerical failure's diagnostic, else the failed design checks (as `batch` words them).
    out.message = match &summary.failure {
        Some(f) => one_line(&f.message),
        None => {
            let failed = checks::failures(&model, &result);
            if failed.is_empty() {
                String::new()
            } else {
                format!("check failed: {}", failed.join("; "))
            }
        }
    };
    out.summary = Some(summary);
    Some(out)
}

/// Runs every row of `plan` (on `jobs` threads, or rayon's default), calling `done` as each
/// finishes; rows come back in spec order.
pub fn run(
    plan: &[PlannedRow],
    kernel: KernelFactory,
    jobs: Option<usize>,
    done: &(dyn Fn(&SweepRow) + Sync),
) -> Result<Vec<SweepRow>> {
    // Nothing cancels it: every row comes back.
    run_cancellable(plan, kernel, jobs, done, &AtomicBool::new(false))
}

/// [`run`], stopped once `cancel` is set (a shard's task told to end by its scheduler): the
/// rows not started are not run and those running stop at their next step; the rows that
/// finished come back in spec order, `done` called for each as it finishes.
pub fn run_cancellable(
    plan: &[PlannedRow],
    kernel: KernelFactory,
    jobs: Option<usize>,
    done: &(dyn Fn(&SweepRow) + Sync),
    cancel: &AtomicBool,
) -> Result<Vec<SweepRow>> {
    let rows = parallel::map_jobs(jobs, plan, |row| {
        if cancel.load(std::sync::atomic::Ordering::Relaxed) {
            return None;
        }
        let r = run_row_cancellable(row, kernel, cancel)?;
        done(&r);
        Some(r)
    })?;
    Ok(rows.into_iter().flatten().collect())
}

/// A message on one line.
pub(crate) fn one_line(text: &str) -> String {
    text.lines().map(str::trim).filter(|l| !l.is_empty()).collect::<Vec<_>>().join(" | ")
}

/// The outcome of a sweep for the exit code: (some row failed or was invalid, some check failed).
pub fn outcome(rows: &[SweepRow]) -> (bool, bool) {
    (rows.iter().any(|r| r.status.is_problem()), rows.iter().any(|r| r.checks_pass == Some(false)))
}

/// One cell of the sweep table ([`cells`]): what `sweep.csv` writes and the Python package
/// hands over as a typed value.
#[derive(Clone, Debug, PartialEq)]
pub enum Cell {
    /// No value (an output the row does not have): an empty CSV field, None in Python.
    Empty,
    /// A real number, written in full ([`CsvNumber`]: its shortest exact form).
    Number(f64),
    /// A count or an index.
    Count(u64),
    /// A word or a message.
    Text(String),
    /// An input as the spec (or the row) gave it.
    Input(Value),
}

impl Cell {
    fn csv(&self) -> String {
        match self {
            Cell::Empty => String::new(),
            Cell::Number(v) => CsvNumber(*v).to_string(),
            Cell::Count(n) => n.to_string(),
            Cell::Text(s) => csv_field(s),
            Cell::Input(v) => csv_field(&fmt_value(v)),
        }
    }
}

fn number(v: Option<f64>) -> Cell {
    v.map_or(Cell::Empty, Cell::Number)
}

fn pass(p: Option<bool>) -> Cell {
    match p {
        Some(true) => Cell::Text("pass".into()),
        Some(false) => Cell::Text("fail".into()),
        None => Cell::Empty,
    }
}

/// Reads one peak of a summary.
type PeakOf<'a> = &'a dyn Fn(&RunSummary) -> Option<Peak>;

/// The sweep table: its column names and one row of cells per sweep row. Columns: index,
/// name, the inputs (one column per path, in spec order; rows that set different paths get
/// the union, in order of appearance), status, checks, then the outputs (docs/sweeps.md).
pub fn cells(rows: &[SweepRow]) -> (Vec<String>, Vec<Vec<Cell>>) {
    let Layout { paths, works, checks, head } = layout(rows);
    let body =
        rows.iter()
            .map(|r| {
                let mut cells: Vec<Cell> = vec![Cell::Count(r.index as u64), Cell::Text(r.name.clone())];
                cells.extend(paths.iter().map(|p| {
                    r.inputs.0.iter().find(|(k, _)| k == p).map_or(Cell::Empty, |(_, v)| Cell::Input(v.clone()))
                }));
                cells.push(Cell::Text(r.status.name().into()));
                cells.push(pass(r.checks_pass));
                let s = r.summary.as_ref();
                let f = |g: &dyn Fn(&RunSummary) -> Option<f64>| number(s.and_then(g));
                cells.push(f(&|s| s.stopping_time));
                cells.push(f(&|s| s.paper_stopping_time));
                cells.push(f(&|s| s.stopping_distance));
                cells.push(f(&|s| Some(s.ship_displacement)));
                cells.push(f(&|s| Some(s.anchor_drag_distance)));
                cells.push(f(&|s| s.anchor_start));
                let peaks: [PeakOf; 4] = [&|s| s.peak_tension, &|s| s.chain_peak, &|s| s.cable_peak, &|s| s.rod_peak];
                for peak in peaks {
                    let p = s.and_then(peak);
                    cells.push(number(p.map(|p| p.tension)));
                    cells.push(p.map_or(Cell::Empty, |p| Cell::Count(p.joint as u64)));
                    cells.push(number(p.map(|p| p.t)));
                    cells.push(number(p.and_then(|p| p.proof_utilisation)));
                    cells.push(number(p.and_then(|p| p.break_utilisation)));
                }
                cells.push(f(&|s| s.initial_energy));
                cells.extend(works.iter().map(|w| number(s.and_then(|s| s.work.get(w).copied().flatten()))));
                cells.extend(works.iter().map(|w| number(r.energy_split.get(w).copied())));
                for c in &checks {
                    let outcome = s.and_then(|s| s.checks.iter().find(|x| &x.name == c));
                    cells.push(number(outcome.and_then(|x| x.value)));
                    cells.push(pass(outcome.map(|x| x.pass)));
                }
                cells.push(f(&|s| s.energy_drift));
                cells.push(f(&|s| Some(s.t_end)));
                cells.push(s.map_or(Cell::Empty, |s| Cell::Count(s.steps)));
                cells.push(s.map_or(Cell::Empty, |s| Cell::Count(s.rhs_evaluations)));
                cells.push(f(&|s| Some(s.wall_time)));
                cells.push(Cell::Text(r.message.clone()));
                cells.push(f(&|s| s.cpu_time));
                cells.push(f(&|s| Some(s.initial_kinetic_energy)));
                cells.push(f(&|s| Some(s.initial_horizontal_projection)));
                cells.push(f(&|s| Some(s.initial_horizontal_tension)));
                cells.push(f(&|s| Some(s.water_depth)));
                cells.push(f(&|s| Some(s.initial_top_tension)));
                cells.push(f(&|s| s.energy_scale));
                // Added 2026-12-07, at the end as every column since the first.
                if checks.iter().any(|c| c == "safety_factor") {
                    let outcome = s.and_then(|s| s.checks.iter().find(|x| x.name == "safety_factor"));
                    cells.push(number(outcome.and_then(|x| x.achieved)));
                }
                cells
            })
            .collect();
    (head, body)
}

/// The columns of [`cells`]: the input paths, the work terms and the checks the rows have,
/// and the header they give.
struct Layout<'a> {
    paths: Vec<&'a str>,
    works: Vec<String>,
    checks: Vec<String>,
    head: Vec<String>,
}

fn layout(rows: &[SweepRow]) -> Layout<'_> {
    let paths = input_paths(rows);
    // Every summary reports every term (`RunSummary::work`): the columns are there whether or
    // not a row ran (a sweep of invalid rows had none, and a DataFrame changed its shape).
    let works: Vec<String> = kanestop_runtime::energy::Energy::default()
        .reported_work()
        .iter()
        .map(|(name, _)| name.to_string())
        .collect::<std::collections::BTreeSet<_>>()
        .into_iter()
        .collect();
    let checks: Vec<String> = rows
        .iter()
        .find_map(|r| r.summary.as_ref().filter(|s| !s.checks.is_empty()))
        .map(|s| s.checks.iter().map(|c| c.name.clone()).collect())
        .unwrap_or_default();
    let mut head: Vec<String> = vec!["index".into(), "name".into()];
    head.extend(paths.iter().map(|p| p.to_string()));
    head.extend(["status", "checks"].map(String::from));
    head.extend(
        [
            "stopping_time",
            "paper_stopping_time",
            "stopping_distance",
            "ship_displacement",
            "anchor_drag_distance",
            "anchor_start",
        ]
        .map(String::from),
    );
    for seg in ["peak", "chain_peak", "cable_peak", "rod_peak"] {
        for f in ["tension", "joint", "t", "proof_utilisation", "break_utilisation"] {
            head.push(format!("{seg}_{f}"));
        }
    }
    head.push("initial_energy".into());
    head.extend(works.iter().map(|w| format!("work_{w}")));
    head.extend(works.iter().map(|w| format!("dissipated_{w}")));
    for c in &checks {
        head.push(format!("check_{c}_value"));
        head.push(format!("check_{c}_pass"));
    }
    head.extend(
        [
            "energy_drift",
            "t_end",
            "steps",
            "rhs_evaluations",
            "wall_time",
            "message",
            "cpu_time",
            "initial_kinetic_energy",
            "initial_horizontal_projection",
            "initial_horizontal_tension",
            "water_depth",
            "initial_top_tension",
            "energy_scale",
        ]
        .map(String::from),
    );
    if checks.iter().any(|c| c == "safety_factor") {
        head.push("check_safety_factor_achieved".into());
    }
    Layout { paths, works, checks, head }
}

/// The input columns of [`cells`]: one per path a row sets, in order of appearance.
fn input_paths(rows: &[SweepRow]) -> Vec<&str> {
    let mut paths: Vec<&str> = Vec::new();
    for (k, _) in rows.iter().flat_map(|r| r.inputs.0.iter()) {
        if !paths.contains(&k.as_str()) {
            paths.push(k);
        }
    }
    paths
}

/// Each column of [`cells`] with its unit and meaning ([`units::column`]), in order.
pub fn column_units(rows: &[SweepRow]) -> Vec<(String, &'static str, String)> {
    let Layout { paths, head, .. } = layout(rows);
    units::described(&head, &paths)
}

/// `sweep.units.csv`: the unit and meaning of each column of [`csv`] ([`column_units`]).
pub fn units_csv(rows: &[SweepRow]) -> String {
    let described = column_units(rows);
    crate::output::units_csv(described.iter().map(|(n, u, w)| (n.as_str(), *u, w.as_str())))
}

/// The rows as CSV: [`cells`], a header line and one line per row.
pub fn csv(rows: &[SweepRow]) -> String {
    let (head, body) = cells(rows);
    let mut out = head.iter().map(|h| csv_field(h)).collect::<Vec<_>>().join(",");
    out.push('\n');
    for row in body {
        out.push_str(&row.iter().map(Cell::csv).collect::<Vec<_>>().join(","));
        out.push('\n');
    }
    out
}

/// The table of [`cells`] as text, unquoted (empty for none): for writers of other formats.
pub fn columns(rows: &[SweepRow]) -> (Vec<String>, Vec<Vec<String>>) {
    let (head, body) = cells(rows);
    let text = |c: &Cell| match c {
        Cell::Empty => String::new(),
        Cell::Number(v) => CsvNumber(*v).to_string(),
        Cell::Count(n) => n.to_string(),
        Cell::Text(s) => s.clone(),
        Cell::Input(v) => fmt_value(v),
    };
    (head, body.iter().map(|row| row.iter().map(text).collect()).collect())
}

/// The rows as a terminal table (the first columns; the files hold every output).
pub fn table(rows: &[SweepRow]) -> String {
    let d = |v: Option<f64>, scale: f64, digits: usize| {
        v.map(|v| format!("{:.*}", digits, v * scale)).unwrap_or_else(|| "—".into())
    };
    // The row column as wide as the longest name, so the others stay under their headings.
    let w = rows.iter().map(|r| r.name.chars().count()).max().unwrap_or(0).max(3);
    let mut out = format!(
        "{:<w$} {:<9} {:>6} {:>9} {:>9} {:>9} {:>10} {:>6}  {}\n",
        "row", "status", "checks", "stop (s)", "dist (m)", "drag (m)", "peak (kN)", "util %", "inputs"
    );
    for r in rows {
        let s = r.summary.as_ref();
        out.push_str(&format!(
            "{:<w$} {:<9} {:>6} {:>9} {:>9} {:>9} {:>10} {:>6}  {}\n",
            r.name,
            r.status.name(),
            match r.checks_pass {
                Some(true) => "pass",
                Some(false) => "FAIL",
                None => "—",
            },
            d(s.and_then(|s| s.stopping_time), 1.0, 3),
            d(s.and_then(|s| s.stopping_distance), 1.0, 2),
            d(s.map(|s| s.anchor_drag_distance), 1.0, 2),
            d(s.and_then(|s| s.peak_tension).map(|p| p.tension), 1e-3, 1),
            // The worst joint's, as the heat map and the safety factor judge it.
            d(s.and_then(RunSummary::max_break_utilisation), 100.0, 1),
            short_label(&r.label)
        ));
        if !r.message.is_empty() {
            out.push_str(&format!("{:w$}  {}\n", "", r.message));
        }
    }
    out
}

/// A row's inputs for the terminal: each number to six significant digits (a sampled
/// `ship.mass=516549.9044855506` reads `ship.mass=516550`); the files keep them whole.
fn short_label(label: &str) -> String {
    let short = |word: &str| -> String {
        let Some((key, value)) = word.split_once('=') else { return word.to_string() };
        match value.parse::<f64>() {
            Ok(v) if v.is_finite() && value.contains(['.', 'e', 'E']) => {
                let rounded: f64 = format!("{v:.5e}").parse().unwrap_or(v);
                format!("{key}={rounded}")
            }
            _ => word.to_string(),
        }
    };
    label.split(' ').map(short).collect::<Vec<_>>().join(" ")
}

/// The rows of each grid point, in spec order: with sampling on top of a grid, the points'
/// rows are consecutive, `per_point` (the samples) each, and a point's statistics are over its
/// own samples. Each group is labelled by the inputs all its rows share, the point's axis
/// values (`ship.mass=500000`; every row lists its inputs in the same order, so they are
/// compared by position, O(rows)). `per_point` 0 (not known) or the row count: one group.
pub fn by_grid_point(rows: &[SweepRow], per_point: usize) -> Vec<(String, &[SweepRow])> {
    if per_point == 0 || per_point >= rows.len() {
        return vec![(String::new(), rows)];
    }
    rows.chunks(per_point)
        .map(|group| {
            let first = &group[0].inputs.0;
            let shared: Vec<(String, Value)> = (0..first.len())
                .filter(|&k| group.iter().all(|r| r.inputs.0.get(k) == Some(&first[k])))
                .map(|k| first[k].clone())
                .collect();
            (label(&shared), group)
        })
        .collect()
}

/// Mean, standard deviation, 5 % and 95 % quantiles of an output over the rows that have it
/// and ran to their end (stopped, or at the end time): a failed run's partial peak is no
/// sample of the output. The quantiles interpolate linearly between the sorted values at
/// p·(n − 1) (Hyndman and Fan's type 7: NumPy's, pandas' and spreadsheets' default).
pub fn statistics(rows: &[SweepRow], output: impl Fn(&RunSummary) -> Option<f64>) -> Option<[f64; 4]> {
    let ran = rows.iter().filter(|r| matches!(r.status, Status::Stopped | Status::EndTime));
    let mut v: Vec<f64> = ran.filter_map(|r| r.summary.as_ref().and_then(&output)).collect();
    if v.len() < 2 {
        return None;
    }
    v.sort_by(f64::total_cmp);
    let n = v.len() as f64;
    let mean = v.iter().sum::<f64>() / n;
    let sd = (v.iter().map(|x| (x - mean).powi(2)).sum::<f64>() / (n - 1.0)).sqrt();
    Some([mean, sd, quantile(&v, 0.05), quantile(&v, 0.95)])
}

/// The `p` quantile (0 ≤ p ≤ 1) of `sorted` (ascending, not empty): linear between the values
/// at p·(n − 1), Hyndman and Fan's type 7.
fn quantile(sorted: &[f64], p: f64) -> f64 {
    let at = p * (sorted.len() - 1) as f64;
    let (i, f) = (at.floor() as usize, at.fract());
    match sorted.get(i + 1) {
        Some(next) => sorted[i] + f * (next - sorted[i]),
        None => sorted[i],
    }
}

/// The file `scenes/NAME.toml` of a planned row: its scene, to rerun it alone (none when
/// its inputs give no valid scene).
pub fn scene_file(row: &PlannedRow) -> Option<String> {
    let scene = row.scene.as_ref().ok()?;
    Some(format!("# Row {} of a sweep: {}\n{}", row.index, label(&row.inputs), scene.to_toml()))
}

/// A row's name as a file name in one folder: a character that could lead elsewhere (`/`,
/// `\`, a control character) or a leading `.` becomes `_`. A spec's name is checked
/// ([`spec::check_name`]); this keeps a name from Python or an edited shard file from writing
/// outside `scenes/` too.
pub fn file_stem(name: &str) -> String {
    let stem: String =
        name.chars().map(|c| if c == '/' || c == '\\' || c.is_control() || c == ':' { '_' } else { c }).collect();
    match stem.strip_prefix('.') {
        Some(rest) => format!("_{rest}"),
        None if stem.is_empty() => "_".into(),
        None => stem,
    }
}

/// The files and folders (ending in `/`) [`write()`] writes into its folder; the heat maps'
/// `heatmap-NAME.svg` beside them.
pub const FILES: [&str; 5] = ["sweep.csv", "sweep.json", "sweep.units.csv", "sweep.parquet", "scenes/"];

/// Every entry of a sweep's folder that its rows `names` and heat maps `heat_maps` are
/// written to: [`FILES`], `scenes/NAME.toml` and `heatmap-NAME.svg`, for
/// [`output::check_dir_entries`] before any run (a folder where a file goes was found only
/// when the rows had run, and left some files written).
pub fn output_entries<'a>(names: impl IntoIterator<Item = &'a str>, heat_maps: &[heatmap::Output]) -> Vec<String> {
    let mut entries: Vec<String> = FILES.iter().map(|f| f.to_string()).collect();
    entries.extend(heat_maps.iter().map(|&o| heatmap::file_name(o)));
    entries.extend(names.into_iter().map(|n| format!("scenes/{}.toml", file_stem(n))));
    entries
}

/// Every row's scene file: (row name, text), for [`write()`].
pub fn scene_files(plan: &[PlannedRow]) -> Vec<(String, String)> {
    plan.iter().filter_map(|row| Some((row.name.clone(), scene_file(row)?))).collect()
}

/// Writes `sweep.csv`, `sweep.json`, `sweep.units.csv` (the columns' units) and each row's
/// scene (`scenes/NAME.toml` from `scenes`, (row name, text) as [`scene_files`] gives them, to
/// rerun one alone) into `dir`, each file whole or not at all. Returns the CSV and JSON paths.
pub fn write(rows: &[SweepRow], scenes: &[(String, String)], dir: &Path) -> Result<(PathBuf, PathBuf)> {
    let folder = dir.join("scenes");
    std::fs::create_dir_all(&folder).map_err(Error::io("create", &folder))?;
    for (name, text) in scenes {
        let path = folder.join(format!("{}.toml", file_stem(name)));
        write_atomically(&path, text.as_bytes()).map_err(Error::io("write", &path))?;
    }
    #[cfg(feature = "parquet")]
    {
        let (head, cells) = columns(rows);
        let bytes = parquet::encode(&head, &cells)
            .map_err(|message| Error::Encode { file: "sweep.parquet".into(), message })?;
        let p = dir.join("sweep.parquet");
        write_atomically(&p, &bytes).map_err(Error::io("write", &p))?;
    }
    let json = serde_json::to_string_pretty(rows).expect("rows serialise: plain numbers and strings");
    let [c, j, _] = output::write_into(dir, [FILES[0], FILES[1], FILES[2]], [csv(rows), json, units_csv(rows)])?;
    Ok((c, j))
}

/// The row names of the sweep whose `sweep.json` is in `dir` (none when there is none or it
/// cannot be read): what [`remove_stale`] may remove of it.
pub fn rows_in(dir: &Path) -> Vec<String> {
    let Ok(text) = std::fs::read_to_string(dir.join("sweep.json")) else { return Vec::new() };
    let Ok(serde_json::Value::Array(rows)) = serde_json::from_str::<serde_json::Value>(&text) else {
        return Vec::new();
    };
    rows.iter().filter_map(|r| r["name"].as_str().map(str::to_string)).collect()
}

/// Removes from `dir` what an earlier sweep wrote there and this one did not, so that the
/// folder holds one sweep: the scene files of the earlier sweep's rows (`earlier`, from its
/// `sweep.json`: [`rows_in`], read before this sweep's replaced it) that this sweep's
/// `scenes` do not name and that still begin as [`scene_file`] begins them, and, when the
/// heat maps were drawn (`charts`), the `heatmap-NAME.svg` of the other outputs. A file of
/// another name (a user's copy of a row's scene) is never touched. Returns what it removed.
pub fn remove_stale(
    dir: &Path,
    earlier: &[String],
    scenes: &[(String, String)],
    charts: Option<&[PathBuf]>,
) -> Result<Vec<PathBuf>> {
    let mut stale = Vec::new();
    let written: std::collections::HashSet<String> = scenes.iter().map(|(name, _)| file_stem(name)).collect();
    for name in earlier.iter().map(|n| file_stem(n)).filter(|n| !written.contains(n)) {
        let path = dir.join("scenes").join(format!("{name}.toml"));
        let text = std::fs::read_to_string(&path).unwrap_or_default();
        if text.lines().next().is_some_and(|l| l.starts_with("# Row ") && l.contains(" of a sweep: ")) {
            stale.push(path);
        }
    }
    if let Some(charts) = charts {
        for o in heatmap::Output::ALL {
            let path = dir.join(format!("heatmap-{}.svg", o.name()));
            if path.is_file() && !charts.contains(&path) {
                stale.push(path);
            }
        }
    }
    stale.sort();
    stale.dedup();
    for path in &stale {
        std::fs::remove_file(path).map_err(Error::io("remove", path))?;
    }
    Ok(stale)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn quantiles_interpolate_as_numpy_does() {
        // numpy.percentile([1, 2, 3, 4, 10], [5, 95]) = [1.2, 8.8]; of 1 … 30, 2.45 and 28.55.
        let v = [1.0, 2.0, 3.0, 4.0, 10.0];
        assert!((quantile(&v, 0.05) - 1.2).abs() < 1e-12 && (quantile(&v, 0.95) - 8.8).abs() < 1e-12);
        let thirty: Vec<f64> = (1..=30).map(f64::from).collect();
        assert!((quantile(&thirty, 0.05) - 2.45).abs() < 1e-12 && (quantile(&thirty, 0.95) - 28.55).abs() < 1e-12);
        assert_eq!((quantile(&v, 0.0), quantile(&v, 1.0), quantile(&[7.0], 0.95)), (1.0, 10.0, 7.0));
    }

    #[test]
    fn inputs_are_written_as_every_csv_writes_a_number() {
        let inputs = [("ship.mass".to_string(), Value::Float(5e5)), ("x".to_string(), Value::Float(1e300))];
        assert_eq!(label(&inputs), "ship.mass=500000 x=1e300");
    }

    #[test]
    fn an_earlier_sweep_s_files_are_removed_and_nothing_else() {
        let dir = std::env::temp_dir().join(format!("kanestop-stale-{}", std::process::id()));
        let scenes = dir.join("scenes");
        std::fs::create_dir_all(&scenes).unwrap();
        let ours = "# Row 1 of a sweep: ship.mass=4e5\n[meta]\n";
        // a-001-tweaked.toml: a user's copy of a row's scene, its header kept.
        for (name, text) in
            [("a-000.toml", ours), ("a-001.toml", ours), ("a-001-tweaked.toml", ours), ("mine.toml", "[meta]\n")]
        {
            std::fs::write(scenes.join(name), text).unwrap();
        }
        std::fs::write(dir.join("sweep.json"), r#"[{"name": "a-000"}, {"name": "a-001"}, {"name": "mine"}]"#).unwrap();
        for name in ["heatmap-stopping_time.svg", "heatmap-stopping_distance.svg", "heatmap-mine.svg"] {
            std::fs::write(dir.join(name), "<svg/>").unwrap();
        }
        let earlier = rows_in(&dir);
        assert_eq!(earlier, ["a-000", "a-001", "mine"]);
        let written = [("a-000".to_string(), ours.to_string())];
        // Without heat maps drawn (a merge without its spec), the maps stay; mine.toml is no
        // row's file (no header), so it stays though its name was a row's.
        let removed = remove_stale(&dir, &earlier, &written, None).unwrap();
        assert_eq!(removed, [scenes.join("a-001.toml")]);
        let charts = [dir.join("heatmap-stopping_distance.svg")];
        let removed = remove_stale(&dir, &earlier, &written, Some(&charts)).unwrap();
        assert_eq!(removed, [dir.join("heatmap-stopping_time.svg")]);
        for kept in
            [scenes.join("a-000.toml"), scenes.join("a-001-tweaked.toml"), scenes.join("mine.toml"), charts[0].clone()]
        {
            assert!(kept.is_file(), "{} kept", kept.display());
        }
        assert!(dir.join("heatmap-mine.svg").is_file(), "not an output's name: kept");
        assert!(rows_in(&dir.join("nowhere")).is_empty());
        std::fs::remove_dir_all(&dir).unwrap();
    }

    #[test]
    fn the_terminal_shows_six_significant_digits_of_an_input() {
        assert_eq!(
            short_label(
                "ship.mass=516549.9044855506 initial.ship_speed=3 anchor.mass=2.5e6 case=x=1.5 rod.length=1.25"
            ),
            "ship.mass=516550 initial.ship_speed=3 anchor.mass=2500000 case=x=1.5 rod.length=1.25"
        );
    }
}

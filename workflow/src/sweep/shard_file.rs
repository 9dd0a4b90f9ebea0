//! The shard file, `DIR/shards/shard-K-of-N.json`: what one shard of a sweep produced, with
//! the plan hash that says which sweep it belongs to, the shard's row indices and each done
//! row's full result and scene file, so that [`super::merge`] writes exactly what a local
//! run writes. A running shard saves it whole (never half-written) at its start, every
//! `--checkpoint` seconds and at its end; `complete` is true only at the end.
//! Format: docs/sweeps.md.

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};
use std::sync::Mutex;
use std::time::{Duration, Instant};

use serde::{Deserialize, Serialize};
use sha2::{Digest, Sha256};

use super::shard::{Shard, ShardError};
use super::spec::MAX_ROWS;
use super::{scene_file, PlannedRow, Spec, SweepRow};
use crate::output::write_atomically;
use crate::{Error, Result};

/// The largest shard file read, bytes: [`MAX_ROWS`] rows of up to 16 kB each. A larger file
/// (or `/dev/zero`) is no shard file.
const MAX_SHARD_BYTES: u64 = 16_384 * MAX_ROWS as u64;

/// The `format` field of a shard file.
pub const FORMAT: &str = "kanestop-sweep-shard/1";

/// What names one sweep across its shards: the same on every machine that plans it.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct SweepId {
    /// `sha256:` and the hex digest of the resolved plan and the kernel ([`plan_hash`]).
    pub plan_hash: String,
    /// The sweep's name (rows are `name-000`, …).
    pub name: String,
    /// Its number of rows.
    pub rows: usize,
    /// Whether it samples uncertain inputs (the summary then gives statistics).
    pub sampling: bool,
    /// Rows per grid point, consecutive in spec order: the samples (1 without sampling).
    pub samples_per_point: usize,
    /// The spec file it was planned from (for messages only: not part of the hash).
    pub spec: PathBuf,
}

impl SweepId {
    /// The id of `spec`'s `plan`, run with the kernel named `kernel`.
    pub fn of(spec: &Spec, plan: &[PlannedRow], kernel: &str) -> SweepId {
        SweepId {
            plan_hash: plan_hash(&spec.name, plan, kernel),
            name: spec.name.clone(),
            rows: plan.len(),
            sampling: spec.sampling.is_some(),
            samples_per_point: spec.sampling.map_or(1, |s| s.1),
            spec: spec.file.clone(),
        }
    }
}

/// SHA-256 of the resolved plan: the sweep's name, the kernel and, for every row, its
/// index, name, inputs and scene (the base scene with the row's overrides, as TOML) or why
/// it has none. Each field is length-prefixed, so no two plans give the same text; paths
/// and timings are not part of it, so the spec may sit anywhere.
pub fn plan_hash(name: &str, plan: &[PlannedRow], kernel: &str) -> String {
    let mut h = Sha256::new();
    let mut field = |text: &str| {
        h.update(format!("{}:", text.len()).as_bytes());
        h.update(text.as_bytes());
    };
    // The version of what a row's results mean: 2 since `dissipated_<term>` became a share
    // of the initial kinetic energy (shards of version 1 hold shares of E_0 and are not
    // merged with these); 3 since a row's summary has the laid line's x_L, T_h and water
    // depth and an adaptive method's peak tensions are looked at after each of its steps
    // (2026-12-06); 4 since it also has the laid line's top tension T_t, and the energy
    // drift is relative to the largest kinetic energy instead of E_0 (2026-12-06); 5 since a
    // ship at rest at the start has stopped at t = 0, and a row refused before its first step
    // has no E_0, drift or work (null, where it read 0) (2026-12-07); 6 since the break loads
    // are a design check of every run that took a step and did not fail, so a row without
    // `[checks]` has a verdict (`checks_pass`, where it had none) (2026-12-07); 7 since a run
    // ends at the last whole step at or before its end time (the nearest, past it, before),
    // an RK4 blow-up's message names the limit at its last good state, and the work columns
    // are every term's whether or not a row ran (2026-12-07); 8 since a row's summary says
    // whether its peak came at the engagement (`early_peak`) and its safety-factor check the
    // factor achieved (2026-12-07).
    field("kanestop sweep plan 8");
    field(name);
    field(kernel);
    field(&plan.len().to_string());
    for row in plan {
        field(&row.index.to_string());
        field(&row.name);
        field(&row.inputs.len().to_string());
        for (path, value) in &row.inputs {
            field(path);
            field(&value.to_string());
        }
        match &row.scene {
            Ok(scene) => field(&scene.to_toml()),
            Err(why) => field(&format!("invalid: {why}")),
        }
    }
    let digest = h.finalize();
    format!("sha256:{}", digest.iter().map(|b| format!("{b:02x}")).collect::<String>())
}

/// One done row of a shard.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct ShardRow {
    /// The row, as `sweep.json` holds it.
    pub row: SweepRow,
    /// Its `scenes/NAME.toml` (none when its inputs give no valid scene).
    pub scene: Option<String>,
}

/// The contents of a shard file.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct ShardFile {
    /// [`FORMAT`].
    pub format: String,
    /// The sweep's plan hash ([`plan_hash`]).
    pub plan_hash: String,
    /// The sweep's name.
    pub sweep: String,
    /// Which shard: K of N.
    pub shard: Shard,
    /// The sweep's number of rows.
    pub rows_total: usize,
    /// Whether the sweep samples uncertain inputs.
    pub sampling: bool,
    /// Rows per grid point, consecutive in spec order (the samples; 1 without sampling), so a
    /// merge gives each point's statistics without the spec; 0 in a file written before
    /// 2026-12-06 (its statistics are then over all rows).
    #[serde(default)]
    pub samples_per_point: usize,
    /// True once every row of the shard is done; false while it runs (or if it died).
    pub complete: bool,
    /// The indices of every row of the shard (done or not).
    pub row_indices: Vec<usize>,
    /// The rows done, in index order.
    pub rows: Vec<ShardRow>,
}

impl ShardFile {
    /// The file of `shard` in the sweep folder `dir`: `dir/shards/shard-K-of-N.json`.
    pub fn path(dir: &Path, shard: Shard) -> PathBuf {
        dir.join("shards").join(shard.file_name())
    }

    /// Reads and checks a shard file.
    pub fn read(path: &Path) -> Result<ShardFile> {
        let text = kanestop_runtime::scene::read_text_file(path, MAX_SHARD_BYTES, "a shard file's")
            .map_err(Error::io("read", path))?;
        let problem = |p: String| Error::Shard(ShardError::File { file: path.to_path_buf(), problem: p });
        let format = serde_json::from_str::<serde_json::Value>(&text)
            .map_err(|e| problem(format!("not JSON ({e})")))?
            .get("format")
            .and_then(|f| f.as_str().map(String::from));
        if format.as_deref() != Some(FORMAT) {
            return Err(problem(format!("format {format:?}, expected \"{FORMAT}\"")));
        }
        let file: ShardFile = serde_json::from_str(&text).map_err(|e| problem(e.to_string()))?;
        Shard::new(file.shard.index, file.shard.count, "shard").map_err(|e| problem(e.to_string()))?;
        if file.rows_total > MAX_ROWS {
            return Err(problem(format!("rows_total = {}: at most {MAX_ROWS}", file.rows_total)));
        }
        if file.row_indices != file.shard.rows(file.rows_total) {
            return Err(problem(format!("its row_indices are not those of shard {}", file.shard)));
        }
        if let Some(r) = file.rows.iter().find(|r| !file.shard.holds(r.row.index) || r.row.index >= file.rows_total) {
            return Err(problem(format!("row {} is not one of shard {}", r.row.index, file.shard)));
        }
        Ok(file)
    }

    /// Checks that this file, read from `path`, is of the sweep `id` (its plan hash).
    fn of_sweep(&self, path: &Path, id: &SweepId) -> Result<()> {
        if self.plan_hash == id.plan_hash {
            return Ok(());
        }
        Err(Error::Shard(ShardError::OtherSweep {
            first: path.to_path_buf(),
            first_hash: self.plan_hash.clone(),
            second: id.spec.clone(),
            second_hash: id.plan_hash.clone(),
        }))
    }

    /// Writes it whole or not at all.
    pub fn write(&self, path: &Path) -> Result<()> {
        let json = serde_json::to_string_pretty(self).expect("a shard file serialises: numbers and strings");
        write_atomically(path, json.as_bytes()).map_err(Error::io("write", path))
    }
}

/// A shard as it runs: its file, saved at the start, every `every` (or ten times as long as
/// the last save took, if longer) and at the end.
pub struct ShardRun {
    path: PathBuf,
    every: Duration,
    scenes: BTreeMap<usize, Option<String>>,
    state: Mutex<State>,
}

struct State {
    file: ShardFile,
    /// When the file was last saved, and how long that took.
    saved: Instant,
    cost: Duration,
    error: Option<Error>,
}

/// What a shard has to do: rows kept from an earlier try and rows to run.
pub struct Todo {
    /// Rows kept from the shard file (`--resume`).
    pub kept: usize,
    /// The planned rows still to run, in index order.
    pub rows: Vec<PlannedRow>,
}

impl ShardRun {
    /// Starts `shard` of the sweep `id` (planned as `plan`) in the sweep folder `dir`: with
    /// `resume`, keeps the rows of an existing shard file that neither failed nor were
    /// invalid; saves the file (incomplete) at once. An existing shard file of another sweep
    /// is refused, resumed or not (until 2026-12-07 a shard run without `--resume` wrote over
    /// it: a hand-written array script into a folder in use lost that sweep's rows).
    pub fn start(
        id: &SweepId,
        plan: &[PlannedRow],
        shard: Shard,
        dir: &Path,
        resume: bool,
        every: Duration,
    ) -> Result<(ShardRun, Todo)> {
        let path = ShardFile::path(dir, shard);
        let mut file = ShardFile {
            format: FORMAT.into(),
            plan_hash: id.plan_hash.clone(),
            sweep: id.name.clone(),
            shard,
            rows_total: id.rows,
            sampling: id.sampling,
            samples_per_point: id.samples_per_point,
            complete: false,
            row_indices: shard.rows(id.rows),
            rows: Vec::new(),
        };
        if !resume && path.exists() {
            // A file that does not read as a shard file is written over, as before.
            if let Ok(old) = ShardFile::read(&path) {
                old.of_sweep(&path, id)?;
            }
        }
        if resume && path.exists() {
            let old = ShardFile::read(&path)?;
            old.of_sweep(&path, id)?;
            // Kept rows are the plan's, checked now rather than at the merge after the rest ran.
            let differs = |r: &ShardRow| match plan.get(r.row.index) {
                Some(planned) => super::merge::differs(&r.row, r.scene.as_deref(), planned),
                None => Some(format!("row {} ({}): beyond the plan's {} rows", r.row.index, r.row.name, plan.len())),
            };
            if let Some(what) = old.rows.iter().find_map(differs) {
                return Err(super::merge::not_the_plans(&path, what));
            }
            file.rows = old.rows.into_iter().filter(|r| !r.row.status.is_problem()).collect();
        }
        let kept = file.rows.len();
        let done: std::collections::BTreeSet<usize> = file.rows.iter().map(|r| r.row.index).collect();
        let rows: Vec<PlannedRow> =
            file.row_indices.iter().filter(|i| !done.contains(i)).map(|&i| plan[i].clone()).collect();
        let scenes = rows.iter().map(|r| (r.index, scene_file(r))).collect();
        if let Some(parent) = path.parent() {
            std::fs::create_dir_all(parent).map_err(Error::io("create", parent))?;
        }
        file.complete = rows.is_empty();
        file.write(&path)?;
        let state = Mutex::new(State { file, saved: Instant::now(), cost: Duration::ZERO, error: None });
        Ok((ShardRun { path, every, scenes, state }, Todo { kept, rows }))
    }

    /// The shard file's path.
    pub fn path(&self) -> &Path {
        &self.path
    }

    /// Records a done row; saves the file when `every` has passed since the last save.
    pub fn add(&self, row: &SweepRow) {
        let mut s = self.state.lock().expect("shard file lock");
        let scene = self.scenes.get(&row.index).cloned().flatten();
        s.file.rows.push(ShardRow { row: row.clone(), scene });
        // At most a tenth of the time goes to saving, however large the file grows.
        if s.saved.elapsed() >= self.every.max(s.cost * 10) && s.error.is_none() {
            let start = Instant::now();
            s.file.rows.sort_by_key(|r| r.row.index);
            if let Err(e) = s.file.write(&self.path) {
                s.error = Some(e);
            }
            (s.saved, s.cost) = (Instant::now(), start.elapsed());
        }
    }

    /// Saves the file complete (every row done); the first error of a save, if any.
    pub fn finish(self) -> Result<ShardFile> {
        let mut s = self.state.into_inner().expect("shard file lock");
        if let Some(e) = s.error {
            return Err(e);
        }
        s.file.rows.sort_by_key(|r| r.row.index);
        s.file.complete = s.file.rows.len() == s.file.row_indices.len();
        s.file.write(&self.path)?;
        Ok(s.file)
    }
}

/// Checks, before a job array of `shards` shards of the sweep `id` is submitted into the
/// sweep folder `dir`, that the shard files already there can join it: each of the same
/// sweep (plan hash) and of the same shard count. Otherwise every task would run and the
/// resume or the merge refuse only at the end.
pub fn check_joinable(dir: &Path, id: &SweepId, shards: usize) -> Result<()> {
    if !dir.join("shards").is_dir() {
        return Ok(());
    }
    for path in files_in(dir)? {
        let file = ShardFile::read(&path)?;
        file.of_sweep(&path, id)?;
        if file.shard.count != shards {
            return Err(Error::Shard(ShardError::File {
                file: path,
                problem: format!(
                    "shard {} of this sweep, and the array would write shards of {shards}: a merge refuses the mix; \
                     give --shards {} to resume those, or another --out folder",
                    file.shard, file.shard.count
                ),
            }));
        }
    }
    Ok(())
}

/// The shard files in a sweep folder (`DIR/shards/shard-K-of-N.json`, or in `DIR` itself
/// when it has no `shards/`), ordered by N then K.
pub fn files_in(dir: &Path) -> Result<Vec<PathBuf>> {
    let folder = if dir.join("shards").is_dir() { dir.join("shards") } else { dir.to_path_buf() };
    let entries = std::fs::read_dir(&folder).map_err(Error::io("read", &folder))?;
    let mut found = Vec::new();
    for entry in entries {
        let path = entry.map_err(Error::io("read", &folder))?.path();
        let name = path.file_name().map(|n| n.to_string_lossy().into_owned()).unwrap_or_default();
        let parsed = name.strip_prefix("shard-").and_then(|n| n.strip_suffix(".json")).and_then(|n| {
            let (k, n) = n.split_once("-of-")?;
            Some((n.parse::<usize>().ok()?, k.parse::<usize>().ok()?))
        });
        if let Some(key) = parsed {
            found.push((key, path));
        }
    }
    found.sort();
    Ok(found.into_iter().map(|(_, p)| p).collect())
}

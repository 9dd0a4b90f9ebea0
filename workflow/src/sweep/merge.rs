//! Merging a sweep's shard files into the rows of the whole sweep, as a local run gives
//! them: every file of one sweep (the same plan hash), every row exactly once.

use std::path::{Path, PathBuf};

use super::shard::{Shard, ShardError};
use super::shard_file::{self, ShardFile, ShardRow};
use super::{PlannedRow, SweepRow};
use crate::{Error, Result};

/// A whole sweep put back together from its shards.
#[derive(Clone, Debug)]
pub struct Merged {
    /// The plan hash every shard file shares.
    pub plan_hash: String,
    /// The sweep's name.
    pub name: String,
    /// Whether it samples uncertain inputs.
    pub sampling: bool,
    /// Rows per grid point (0: not known, a shard file of before 2026-12-06).
    pub samples_per_point: usize,
    /// Every row, in spec order.
    pub rows: Vec<SweepRow>,
    /// Every row's scene file (row name, text), for [`super::write()`].
    pub scenes: Vec<(String, String)>,
    /// The shard files read.
    pub files: Vec<PathBuf>,
    /// The shard file each row came from (`rows[i]` from `sources[i]`).
    pub sources: Vec<PathBuf>,
}

impl Merged {
    /// Checks every row against `plan`, the sweep's plan (whose hash the files carry): its
    /// name, its scene file and, for a row whose inputs give no scene, why. The plan hash
    /// names the sweep but a file's rows are only as good as the file: this refuses rows
    /// edited, or copied from another sweep, naming the row and its file.
    pub fn check_rows(&self, plan: &[PlannedRow]) -> Result<()> {
        let problem = |file: &Path, what: String| Err(not_the_plans(file, what));
        if plan.len() != self.rows.len() {
            return problem(&self.files[0], format!("{} rows in all", self.rows.len()));
        }
        let scenes: std::collections::HashMap<&str, &str> =
            self.scenes.iter().map(|(name, text)| (name.as_str(), text.as_str())).collect();
        for (i, (row, planned)) in self.rows.iter().zip(plan).enumerate() {
            if let Some(what) = differs(row, scenes.get(row.name.as_str()).copied(), planned) {
                return problem(&self.sources[i], what);
            }
        }
        Ok(())
    }
}

/// The error for a shard file whose rows are not the plan's: `what` of them differs.
pub fn not_the_plans(file: &Path, what: String) -> Error {
    Error::Shard(ShardError::File {
        file: file.to_path_buf(),
        problem: format!("{what}, not the plan's: the file was edited or holds another sweep's rows"),
    })
}

/// What of a done row (its scene file `scene`, if it has one) is not `planned`'s, in words
/// (`row 3 (name-003): its scene file`), or None: its name, its inputs, its scene file and, for
/// a row whose inputs give no scene, its message.
pub fn differs(row: &SweepRow, scene: Option<&str>, planned: &PlannedRow) -> Option<String> {
    let what = if row.name != planned.name {
        format!("its name {:?}", row.name)
    } else if row.label != super::label(&planned.inputs) {
        format!("its inputs {:?}", row.label)
    } else if scene != super::scene_file(planned).as_deref() {
        "its scene file".into()
    } else {
        match &planned.scene {
            Err(why) if row.message != super::one_line(why) => format!("its message {:?}", row.message),
            _ => return None,
        }
    };
    Some(format!("row {} ({}): {what}", planned.index, planned.name))
}

/// The shard files named by `paths`: a folder gives its shard files
/// ([`shard_file::files_in`]), a file itself; each once.
pub fn collect(paths: &[PathBuf]) -> Result<Vec<PathBuf>> {
    let key = |p: &Path| p.canonicalize().unwrap_or_else(|_| p.to_path_buf());
    let mut files: Vec<PathBuf> = Vec::new();
    for p in paths {
        let found = if p.is_dir() { shard_file::files_in(p)? } else { vec![p.clone()] };
        for f in found {
            if !files.iter().any(|g| key(g) == key(&f)) {
                files.push(f);
            }
        }
    }
    if files.is_empty() {
        let names: Vec<String> = paths.iter().map(|p| p.display().to_string()).collect();
        return Err(Error::Shard(ShardError::NoShards(names.join(", "))));
    }
    Ok(files)
}

/// Reads the shard files named by `paths` and merges them. Refused, with a message naming
/// the files: shards of different sweeps (plan hashes), a row held twice, rows missing (an
/// absent or incomplete shard file).
pub fn merge(paths: &[PathBuf]) -> Result<Merged> {
    let files = collect(paths)?;
    let read = files.iter().map(|f| Ok((f.clone(), ShardFile::read(f)?))).collect::<Result<Vec<_>>>()?;
    let (first_path, first) = &read[0];
    if let Some((path, other)) = read.iter().find(|(_, f)| f.plan_hash != first.plan_hash) {
        return Err(Error::Shard(ShardError::OtherSweep {
            first: first_path.clone(),
            first_hash: first.plan_hash.clone(),
            second: path.clone(),
            second_hash: other.plan_hash.clone(),
        }));
    }
    if let Some((path, other)) = read.iter().find(|(_, f)| f.rows_total != first.rows_total) {
        return Err(Error::Shard(ShardError::File {
            file: path.clone(),
            problem: format!(
                "rows_total = {}, but {} says {} for the same plan hash",
                other.rows_total,
                first_path.display(),
                first.rows_total
            ),
        }));
    }
    let mut slots: Vec<Option<(&ShardRow, &Path)>> = vec![None; first.rows_total];
    for (path, file) in &read {
        for r in &file.rows {
            if let Some((_, earlier)) = slots[r.row.index] {
                return Err(Error::Shard(ShardError::Duplicate {
                    index: r.row.index,
                    name: r.row.name.clone(),
                    first: earlier.to_path_buf(),
                    second: path.clone(),
                }));
            }
            slots[r.row.index] = Some((r, path));
        }
    }
    let missing: Vec<usize> = (0..slots.len()).filter(|&i| slots[i].is_none()).collect();
    if !missing.is_empty() {
        return Err(Error::Shard(missing_rows(&read, &missing, first.rows_total)));
    }
    let (done, sources): (Vec<&ShardRow>, Vec<PathBuf>) =
        slots.into_iter().map(|s| s.expect("no row missing")).map(|(r, p)| (r, p.to_path_buf())).unzip();
    Ok(Merged {
        plan_hash: first.plan_hash.clone(),
        name: first.sweep.clone(),
        sampling: first.sampling,
        samples_per_point: first.samples_per_point,
        rows: done.iter().map(|r| r.row.clone()).collect(),
        scenes: done.iter().filter_map(|r| Some((r.row.name.clone(), r.scene.clone()?))).collect(),
        files,
        sources,
    })
}

/// The message for missing rows: which rows, which shard files are absent (by the shard
/// count of the files read) and which are incomplete.
fn missing_rows(read: &[(PathBuf, ShardFile)], missing: &[usize], total: usize) -> ShardError {
    let list = |items: Vec<String>| {
        let n = items.len();
        let mut shown: Vec<String> = items.into_iter().take(10).collect();
        if n > 10 {
            shown.push(format!("… {} more", n - 10));
        }
        shown.join(", ")
    };
    let mut detail = Vec::new();
    let count = read[0].1.shard.count;
    let absent: Vec<String> = (0..count)
        .map(|k| Shard { index: k, count })
        .filter(|s| !read.iter().any(|(_, f)| f.shard == *s) && missing.iter().any(|&i| s.holds(i)))
        .map(|s| s.file_name())
        .collect();
    if !absent.is_empty() {
        detail.push(format!("no file {}", list(absent)));
    }
    for (path, f) in read.iter().filter(|(_, f)| f.rows.len() < f.row_indices.len()) {
        detail.push(format!(
            "{} is incomplete, {} of its {} rows (the task stopped early, or is still running)",
            path.display(),
            f.rows.len(),
            f.row_indices.len()
        ));
    }
    ShardError::Missing {
        missing: missing.len(),
        total,
        rows: format!("row {}", list(missing.iter().map(|i| i.to_string()).collect())),
        detail: detail.join("; "),
    }
}

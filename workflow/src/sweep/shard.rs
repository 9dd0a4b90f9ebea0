//! Shards: a stable partition of a sweep's rows into N parts, so that N tasks of a job
//! array (Slurm, a Kubernetes indexed job, a PBS array) each run one part and a merge puts
//! the rows back together (docs/sweeps.md, "Sharded sweeps").
//!
//! Shard K of N (numbered from 0, like the schedulers' task indices) holds the rows whose
//! index i has i mod N = K: the partition depends on the row indices alone, never on timing
//! or thread counts, and neighbouring rows (often of similar cost) go to different shards.

use std::path::PathBuf;

use serde::{Deserialize, Serialize};

/// Why a sweep cannot be sharded, run as a shard or merged.
#[derive(Debug, thiserror::Error)]
pub enum ShardError {
    /// A flag or a scheduler's environment variable is out of range.
    #[error("{name} = {value}: {expected}")]
    Bad {
        /// The flag (`--shard`) or variable (`SLURM_ARRAY_TASK_ID`).
        name: String,
        /// Its value as given.
        value: String,
        /// The valid range.
        expected: String,
    },
    /// A shard file cannot be read, or is not a shard file.
    #[error("shard file {}: {problem}", file.display())]
    File {
        /// The file.
        file: PathBuf,
        /// What is wrong with it.
        problem: String,
    },
    /// Two shard files come from different sweeps (spec, base scene or kernel).
    #[error(
        "{} and {} belong to different sweeps: plan hash {first_hash} against {second_hash} \
         (the spec, its base scene or the kernel differ); merge or resume only the shards of one \
         sweep, and give another sweep another --out folder",
        first.display(),
        second.display()
    )]
    OtherSweep {
        /// The first file read.
        first: PathBuf,
        /// Its plan hash.
        first_hash: String,
        /// The file that differs.
        second: PathBuf,
        /// Its plan hash.
        second_hash: String,
    },
    /// A row is held by two shard files (or twice by one).
    #[error("row {index} ({name}) is there twice: in {} and in {}; keep one shard file per shard", first.display(), second.display())]
    Duplicate {
        /// The row's index.
        index: usize,
        /// The row's name.
        name: String,
        /// The file where it was first found.
        first: PathBuf,
        /// The file where it was found again.
        second: PathBuf,
    },
    /// Rows are missing: a shard's file is absent or incomplete.
    #[error(
        "{missing} of the sweep's {total} rows are missing ({rows}): {detail}; run the missing \
         shards (or `kanestop sweep SPEC --out DIR --resume`), then merge again"
    )]
    Missing {
        /// How many rows are missing.
        missing: usize,
        /// The sweep's rows.
        total: usize,
        /// The first missing row indices.
        rows: String,
        /// Which shards: absent files, incomplete files.
        detail: String,
    },
    /// No shard file was found.
    #[error("no shard file in {0} (shard runs write DIR/shards/shard-K-of-N.json)")]
    NoShards(String),
}

/// One part of a sweep: shard `index` of `count`, numbered from 0.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
pub struct Shard {
    /// K, from 0 to `count` − 1.
    pub index: usize,
    /// N ≥ 1.
    pub count: usize,
}

/// The largest shard count accepted.
pub const MAX_SHARDS: usize = 1_000_000;

impl Shard {
    /// The whole sweep as one shard.
    pub const WHOLE: Shard = Shard { index: 0, count: 1 };

    /// Shard `index` of `count`, checked; `name` is the flag or variable it came from.
    pub fn new(index: usize, count: usize, name: &str) -> Result<Shard, ShardError> {
        if !(1..=MAX_SHARDS).contains(&count) {
            return Err(bad(name, format!("{index}/{count}"), format!("N in [1, {MAX_SHARDS}]")));
        }
        if index >= count {
            return Err(bad(
                name,
                format!("{index}/{count}"),
                format!("K in [0, {}]: shards are numbered from 0 to N − 1", count - 1),
            ));
        }
        Ok(Shard { index, count })
    }

    /// Parses `K/N` (the `--shard` flag).
    pub fn parse(text: &str) -> Result<Shard, ShardError> {
        let expected = "K/N, shard K of N numbered from 0, e.g. 0/3, 1/3, 2/3";
        let (k, n) = text.split_once('/').ok_or_else(|| bad("--shard", text, expected))?;
        let (Ok(k), Ok(n)) = (k.trim().parse::<usize>(), n.trim().parse::<usize>()) else {
            return Err(bad("--shard", text, expected));
        };
        Shard::new(k, n, "--shard")
    }

    /// Whether row `index` belongs to this shard.
    pub fn holds(&self, index: usize) -> bool {
        index % self.count == self.index
    }

    /// The indices of this shard's rows among `total`, in order.
    pub fn rows(&self, total: usize) -> Vec<usize> {
        (self.index..total).step_by(self.count).collect()
    }

    /// Its file in a sweep's `shards/` folder: `shard-K-of-N.json`.
    pub fn file_name(&self) -> String {
        format!("shard-{}-of-{}.json", self.index, self.count)
    }
}

impl std::fmt::Display for Shard {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "{}/{}", self.index, self.count)
    }
}

fn bad(name: &str, value: impl std::fmt::Display, expected: impl Into<String>) -> ShardError {
    ShardError::Bad { name: name.to_string(), value: value.to_string(), expected: expected.into() }
}

/// The variables a task of a job array is told its index by, in the order they are read.
pub const INDEX_VARIABLES: [&str; 3] = ["SLURM_ARRAY_TASK_ID", "JOB_COMPLETION_INDEX", "PBS_ARRAY_INDEX"];

/// This task's shard from a scheduler's environment (`var` reads a variable), and the
/// variable it came from; none outside a job array. `shards` is `--shards`, which every
/// scheduler's task must give: the count where the scheduler gives none (Kubernetes, PBS),
/// checked against Slurm's. Until 2026-12-07 a Slurm task without it ran its shard of
/// `SLURM_ARRAY_TASK_COUNT`: a sweep run whole in each task of an array of other work ran a
/// fraction of its rows, and wrote a shard file where a sweep's files were expected.
///
/// - Slurm: K = (`SLURM_ARRAY_TASK_ID` − `SLURM_ARRAY_TASK_MIN`) / `SLURM_ARRAY_TASK_STEP`,
///   N = `--shards`, equal to `SLURM_ARRAY_TASK_COUNT` (min 0 and step 1 when unset);
/// - Kubernetes indexed job: K = `JOB_COMPLETION_INDEX`, N = `--shards` (the job's
///   `completions`);
/// - PBS array (`qsub -J 0-(N−1)`): K = `PBS_ARRAY_INDEX`, N = `--shards`.
pub fn from_env(
    var: impl Fn(&str) -> Option<String>,
    shards: Option<usize>,
) -> Result<Option<(Shard, &'static str)>, ShardError> {
    let number = |name: &str| -> Result<Option<usize>, ShardError> {
        match var(name) {
            None => Ok(None),
            Some(v) => v.trim().parse().map(Some).map_err(|_| bad(name, &v, "a whole number ≥ 0")),
        }
    };
    if let Some(id) = number("SLURM_ARRAY_TASK_ID")? {
        let (min, step) = (number("SLURM_ARRAY_TASK_MIN")?.unwrap_or(0), number("SLURM_ARRAY_TASK_STEP")?.unwrap_or(1));
        let Some(shards) = shards else {
            return Err(bad(
                "SLURM_ARRAY_TASK_ID",
                id,
                "set: give --shards N to run this task's shard of an N-task array, or --shard none to run the \
                 whole sweep in this task",
            ));
        };
        let count = number("SLURM_ARRAY_TASK_COUNT")?.unwrap_or(shards);
        if let Some(n) = Some(shards).filter(|&n| n != count) {
            return Err(bad("--shards", n, format!("the array's size, SLURM_ARRAY_TASK_COUNT = {count}")));
        }
        if id < min || step == 0 || (id - min) % step != 0 {
            return Err(bad(
                "SLURM_ARRAY_TASK_ID",
                id,
                format!("a task of an array min, min + step, … (min {min}, step {step}): submit --array=0-(N−1)"),
            ));
        }
        return Shard::new((id - min) / step, count, "SLURM_ARRAY_TASK_ID/SLURM_ARRAY_TASK_COUNT")
            .map(|s| Some((s, "SLURM_ARRAY_TASK_ID")));
    }
    for (name, what) in
        [("JOB_COMPLETION_INDEX", "the indexed job's completions"), ("PBS_ARRAY_INDEX", "the array's size")]
    {
        if let Some(k) = number(name)? {
            let n = shards.ok_or_else(|| {
                bad(
                    name,
                    k,
                    format!(
                        "set: give the number of shards with --shards N ({what}), or --shard none to run the \
                             whole sweep in this task"
                    ),
                )
            })?;
            return Shard::new(k, n, &format!("{name}/--shards")).map(|s| Some((s, name)));
        }
    }
    Ok(None)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn env<'a>(pairs: &'a [(&'a str, &'a str)]) -> impl Fn(&str) -> Option<String> + 'a {
        move |name| pairs.iter().find(|(k, _)| *k == name).map(|(_, v)| v.to_string())
    }

    #[test]
    fn the_shards_partition_the_rows_whatever_n() {
        for total in [0, 1, 10, 11, 23] {
            for count in [1, 3, 7, 30] {
                let mut seen = vec![0; total];
                for k in 0..count {
                    for i in Shard::new(k, count, "t").unwrap().rows(total) {
                        seen[i] += 1;
                    }
                }
                assert!(seen.iter().all(|&n| n == 1), "{total} rows, {count} shards");
            }
        }
        assert_eq!(Shard::parse("1/3").unwrap().rows(11), [1, 4, 7, 10]);
    }

    #[test]
    fn bad_shards_name_the_flag_the_value_and_the_range() {
        let e = |t: &str| Shard::parse(t).unwrap_err().to_string();
        assert_eq!(e("3/3"), "--shard = 3/3: K in [0, 2]: shards are numbered from 0 to N − 1");
        assert!(e("0/0").starts_with("--shard = 0/0: N in [1, "), "{}", e("0/0"));
        assert!(e("two").starts_with("--shard = two: K/N"), "{}", e("two"));
        assert!(e("-1/3").starts_with("--shard = -1/3: K/N"));
    }

    #[test]
    fn the_schedulers_index_variables_give_the_shard() {
        let slurm = [("SLURM_ARRAY_TASK_ID", "5"), ("SLURM_ARRAY_TASK_MIN", "1"), ("SLURM_ARRAY_TASK_COUNT", "7")];
        assert_eq!(
            from_env(env(&slurm), Some(7)).unwrap(),
            Some((Shard { index: 4, count: 7 }, "SLURM_ARRAY_TASK_ID"))
        );
        // Without --shards, a task of any array (a sweep run whole in each) is refused.
        let e = from_env(env(&slurm), None).unwrap_err().to_string();
        assert!(e.contains("SLURM_ARRAY_TASK_ID = 5: set: give --shards N") && e.contains("--shard none"), "{e}");
        let e = from_env(env(&slurm), Some(6)).unwrap_err().to_string();
        assert!(e.contains("--shards = 6: the array's size, SLURM_ARRAY_TASK_COUNT = 7"), "{e}");
        let k8s = [("JOB_COMPLETION_INDEX", "2")];
        assert_eq!(from_env(env(&k8s), Some(3)).unwrap(), Some((Shard { index: 2, count: 3 }, "JOB_COMPLETION_INDEX")));
        assert!(from_env(env(&k8s), None).unwrap_err().to_string().contains("--shards N"));
        let pbs = [("PBS_ARRAY_INDEX", "3")];
        assert!(from_env(env(&pbs), Some(3)).unwrap_err().to_string().contains("K in [0, 2]"));
        assert_eq!(from_env(env(&[]), Some(3)).unwrap(), None);
        let e = from_env(env(&[("SLURM_ARRAY_TASK_ID", "x")]), None).unwrap_err().to_string();
        assert_eq!(e, "SLURM_ARRAY_TASK_ID = x: a whole number ≥ 0");
    }
}

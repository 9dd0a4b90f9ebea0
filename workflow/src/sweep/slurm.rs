//! The Slurm job script of a sharded sweep (`kanestop sweep SPEC --slurm`): a short bash
//! driver that submits the sweep as a job array of N shards (task k runs shard k of N, read
//! from `SLURM_ARRAY_TASK_ID` and `SLURM_ARRAY_TASK_COUNT`) and a merge job that starts when
//! every task has ended. Submitting it again reruns only the rows still missing or failed.

use std::path::Path;

/// What the script runs.
#[derive(Clone, Debug)]
pub struct JobScript<'a> {
    /// The `kanestop` binary (an absolute path the compute nodes see).
    pub kanestop: &'a Path,
    /// The sweep spec (absolute).
    pub spec: &'a Path,
    /// The sweep folder (absolute): shard files, the merged result, the jobs' logs.
    pub out: &'a Path,
    /// The sweep's name (the jobs' names).
    pub name: &'a str,
    /// Its number of rows.
    pub rows: usize,
    /// N, the array's size.
    pub shards: usize,
    /// CPUs per task (its runs at once).
    pub cpus: usize,
    /// The kernel (`generated` or `reference`).
    pub kernel: &'a str,
    /// How often a task saves its shard file, s (`--checkpoint`).
    pub checkpoint: f64,
    /// The heat maps the merge draws (`--heatmap`; empty: its default).
    pub heatmap: &'a [String],
}

/// Slurm's default `MaxArraySize` (slurm.conf): an array's task indices run from 0 to one
/// less; `sbatch` refuses a larger array unless the cluster raised it.
pub const DEFAULT_MAX_ARRAY_SIZE: usize = 1001;

/// The shard count when `--shards` is not given: one shard per row up to 10.
pub fn default_shards(rows: usize) -> usize {
    rows.clamp(1, 10)
}

/// `text` quoted for a POSIX shell.
pub fn shell_quote(text: &str) -> String {
    format!("'{}'", text.replace('\'', r"'\''"))
}

impl JobScript<'_> {
    /// The driver script. Every path is shell-quoted and the name appears only as the job
    /// name (letters, digits, `-_.`, others as `_`), so no text of the spec or the command
    /// line runs as a command.
    pub fn text(&self) -> String {
        let q = |p: &Path| shell_quote(&p.display().to_string());
        let (exe, spec, out) = (q(self.kanestop), q(self.spec), q(self.out));
        let job: String =
            self.name.chars().map(|c| if c.is_ascii_alphanumeric() || "-_.".contains(c) { c } else { '_' }).collect();
        let (n, last) = (self.shards, self.shards - 1);
        let logs = |file: &str| shell_quote(&format!("{}/logs/{file}", self.out.display()));
        let (shard_log, merge_log) = (logs("shard-%a.log"), logs("merge.log"));
        let (cpus, kernel, rows, checkpoint) = (self.cpus, self.kernel, self.rows, self.checkpoint);
        let heatmap = if self.heatmap.is_empty() {
            String::new()
        } else {
            format!(" --heatmap {}", shell_quote(&self.heatmap.join(",")))
        };
        format!(
            r#"#!/usr/bin/env bash
# The sweep {job} ({rows} rows) as a Slurm job array of {n} shards, then a merge job once
# every shard has ended. Written by `kanestop sweep SPEC --slurm`; submit it with
#     bash THIS_FILE
# Partition, time limit, account: add #SBATCH lines to the two jobs below, or export
# SBATCH_PARTITION, SBATCH_TIMELIMIT, SBATCH_ACCOUNT before submitting.
# Submitting it again reruns only the rows still missing or failed (--resume); the logs
# are appended to, so an earlier attempt's stays. A task stopped by its time limit (SIGTERM)
# saves the rows it finished first.
set -euo pipefail
mkdir -p {out}/logs

# Task k of the array runs shard k of {n}: rows k, k + {n}, k + 2·{n}, …
array=$(sbatch --parsable --output={shard_log} --open-mode=append <<'JOB'
#!/bin/bash
#SBATCH --job-name={job}
#SBATCH --array=0-{last}
#SBATCH --cpus-per-task={cpus}
exec {exe} sweep {spec} --out {out} --shards {n} --resume --jobs "${{SLURM_CPUS_PER_TASK:-{cpus}}}" --kernel {kernel} --checkpoint {checkpoint}
JOB
)
array=${{array%%;*}}

# The merge: after every task, whatever its exit code (a shard whose rows fail a design
# check exits 4); it refuses, naming them, shards that are missing or incomplete.
merge=$(sbatch --parsable --dependency=afterany:"$array" --output={merge_log} --open-mode=append <<'JOB'
#!/bin/bash
#SBATCH --job-name={job}-merge
exec {exe} sweep merge {out} --spec {spec}{heatmap}
JOB
)
merge=${{merge%%;*}}

echo "submitted array job $array ({n} shards of {job}) and merge job $merge (after it)"
echo 'merged result: '{out}'/sweep.csv and sweep.json (log: '{out}'/logs/merge.log)'
"#,
        )
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_script_submits_an_array_of_n_and_a_merge_after_it() {
        let script = JobScript {
            kanestop: Path::new("/opt/bin/kanestop"),
            spec: Path::new("/home/a b/spec.toml"),
            out: Path::new("/scratch/it's"),
            name: "mass speed",
            rows: 23,
            shards: 7,
            cpus: 2,
            kernel: "generated",
            checkpoint: 10.0,
            heatmap: &[],
        }
        .text();
        assert!(script.contains("#SBATCH --array=0-6\n"), "{script}");
        assert!(script.contains("#SBATCH --job-name=mass_speed\n"));
        assert!(script.contains("exec '/opt/bin/kanestop' sweep '/home/a b/spec.toml' --out '/scratch/it'\\''s' --shards 7 --resume --jobs \"${SLURM_CPUS_PER_TASK:-2}\""), "{script}");
        assert!(script.contains("--dependency=afterany:\"$array\""));
        // A resubmission appends to the logs: the failed attempt's stays to be read.
        assert_eq!(script.matches("--open-mode=append").count(), 2, "{script}");
        assert!(
            script.contains("exec '/opt/bin/kanestop' sweep merge '/scratch/it'\\''s' --spec '/home/a b/spec.toml'\n")
        );
        assert_eq!(default_shards(3), 3);
        assert_eq!(default_shards(500), 10);
        // The heat maps asked for are the merge's (they were checked, then dropped).
        let maps = ["stopping_time".to_string(), "peak_tension".to_string()];
        let script = JobScript {
            kanestop: Path::new("/k"),
            spec: Path::new("/s.toml"),
            out: Path::new("/o"),
            name: "m",
            rows: 2,
            shards: 2,
            cpus: 1,
            kernel: "generated",
            checkpoint: 10.0,
            heatmap: &maps,
        }
        .text();
        assert!(
            script.contains("exec '/k' sweep merge '/o' --spec '/s.toml' --heatmap 'stopping_time,peak_tension'\n"),
            "{script}"
        );
    }

    /// No text of the spec or the command line runs as a command: the script submitted
    /// (`sbatch` a stub) with a name and an output folder full of shell syntax runs nothing
    /// else and prints the folder as it is.
    #[cfg(unix)]
    #[test]
    fn names_and_paths_never_run_as_commands() {
        use std::os::unix::fs::PermissionsExt as _;
        let dir = std::env::temp_dir().join(format!("kanestop-slurm-{}", std::process::id()));
        let _ = std::fs::remove_dir_all(&dir);
        let bin = dir.join("bin");
        std::fs::create_dir_all(&bin).unwrap();
        let sbatch = bin.join("sbatch");
        std::fs::write(&sbatch, "#!/bin/sh\ncat > /dev/null\necho 42\n").unwrap();
        std::fs::set_permissions(&sbatch, std::fs::Permissions::from_mode(0o755)).unwrap();
        let out = dir.join("o$(touch PWNED1)\"`touch PWNED2`'x");
        let script = JobScript {
            kanestop: Path::new("/opt/bin/kanestop"),
            spec: Path::new("/home/spec.toml"),
            out: &out,
            name: "g\ntouch PWNED3 #$(touch PWNED4)",
            rows: 2,
            shards: 2,
            cpus: 1,
            kernel: "generated",
            checkpoint: 10.0,
            heatmap: &[],
        }
        .text();
        let file = dir.join("sweep.sh");
        std::fs::write(&file, &script).unwrap();
        let path = format!("{}:{}", bin.display(), std::env::var("PATH").unwrap_or_default());
        let run = std::process::Command::new("bash").arg(&file).current_dir(&dir).env("PATH", path).output().unwrap();
        let stdout = String::from_utf8_lossy(&run.stdout);
        assert!(run.status.success(), "{script}\n{}", String::from_utf8_lossy(&run.stderr));
        let pwned: Vec<_> = std::fs::read_dir(&dir)
            .unwrap()
            .flatten()
            .filter(|e| e.file_name().to_string_lossy().starts_with("PWNED"))
            .map(|e| e.file_name())
            .collect();
        assert!(pwned.is_empty(), "the script ran {pwned:?}:\n{script}");
        assert!(stdout.contains(&format!("merged result: {}/sweep.csv", out.display())), "{stdout}");
        assert!(stdout.contains("2 shards of g_touch_PWNED3____touch_PWNED4_)"), "{stdout}");
        let _ = std::fs::remove_dir_all(&dir);
    }
}

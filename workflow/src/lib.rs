//! # kanestop-workflow
//!
//! Everything that orchestrates runs of the lean runtime (`kanestop-runtime`) and shows their
//! results, shared by the command line and the Python package:
//!
//! - [`kernels`]: which Kane kernel a run uses;
//! - [`parallel`]: many runs at once on a thread pool (feature `parallel`, on by default),
//!   with [`progress`] reporting;
//! - [`batch`]: a folder of scenes as one table ([`validation`] against the paper's Table 3);
//! - [`accuracy`]: the work–precision study (error against run time);
//! - [`sweep`]: one scene over grid axes and sampled uncertain inputs, with design checks;
//!   run in shards over a job array and merged ([`sweep::shard`], [`sweep::merge`],
//!   [`sweep::slurm`]); [`sensitivity`]: d(output)/d(ln p) for every continuous physical
//!   parameter;
//! - reports that only read results: [`summary`] (the one-screen text), [`record`] (the
//!   machine-readable summary of `run --json`), [`diagnostic`] (a
//!   failure in words, with advice), [`history`] (the CSV time history), [`checks`] (peaks
//!   against load limits) and [`plot`] (SVG charts);
//! - [`output`]: files written whole or not at all.
//!
//! This is the only layer with plotting, thread pools, progress bars and JSON; the runtime
//! below it has none of them (docs/architecture.md).

#![warn(missing_docs)]

pub mod accuracy;
pub mod batch;
pub mod checks;
pub mod diagnostic;
pub mod history;
pub mod kernels;
pub mod output;
pub mod parallel;
pub mod plot;
pub mod progress;
pub mod record;
pub mod sensitivity;
pub mod summary;
pub mod sweep;
pub mod validation;

use std::path::PathBuf;

/// Why a workflow could not be carried out. A numerical failure of a run is not an error:
/// it is a result ([`kanestop_runtime::simulate::Stop::Failed`]).
#[derive(Debug, thiserror::Error)]
pub enum Error {
    /// A scene could not be read or is not valid.
    #[error(transparent)]
    Scene(#[from] kanestop_runtime::scene::SceneError),
    /// The base scene a sweep spec names could not be read or is not valid: the scene's
    /// error, and where it was asked for.
    #[error("{error}\n  (the base scene of sweep spec {})", spec.display())]
    BaseScene {
        /// The spec file.
        spec: PathBuf,
        /// The scene's error (boxed: it is large, and rare).
        error: Box<kanestop_runtime::scene::SceneError>,
    },
    /// A scene admits no model (e.g. no initial configuration).
    #[error(transparent)]
    Model(#[from] kanestop_runtime::model::ModelError),
    /// A file or folder could not be read or written.
    #[error("cannot {action} {}: {cause}", path.display())]
    Io {
        /// What was attempted: "read", "write", "create".
        action: &'static str,
        /// The file or folder.
        path: PathBuf,
        /// What the system said (in the message, so not also a `source()` that a report of
        /// the error's chain would print twice).
        cause: std::io::Error,
    },
    /// An output file could not be encoded (e.g. sweep.parquet).
    #[error("cannot encode {file}: {message}")]
    Encode {
        /// The file's name.
        file: String,
        /// What the encoder said.
        message: String,
    },
    /// A chart could not be drawn.
    #[error("cannot draw {chart}: {message}")]
    Plot {
        /// The chart's file name.
        chart: String,
        /// What the plotting library said.
        message: String,
    },
    /// An argument of the workflow is out of range.
    #[error("{name} = {value}: {expected}")]
    Argument {
        /// The argument, e.g. `--repeats`.
        name: &'static str,
        /// Its value as given.
        value: String,
        /// The valid range.
        expected: String,
    },
    /// A sweep spec's field is missing, of the wrong type or out of range.
    #[error("sweep spec {}: {}", file.display(), spec_problem(field, value, expected))]
    Spec {
        /// The spec file.
        file: PathBuf,
        /// The field, e.g. `axis[1].range.steps`.
        field: String,
        /// Its value as given.
        value: String,
        /// The valid range, or what went wrong.
        expected: String,
    },
    /// A sweep's shard cannot be run or its shards cannot be merged.
    #[error(transparent)]
    Shard(#[from] sweep::shard::ShardError),
    /// The accuracy study's reference run did not stop the ship.
    #[error("the reference run did not stop the ship: {0}")]
    NoReference(String),
    /// The sensitivity study's base run failed (or was refused before its first step).
    #[error("the base run failed, so there is nothing to take differences from:\n{message}")]
    BaseRun {
        /// Its diagnostic.
        message: String,
        /// Refused before its first step (bad input) rather than failed on the way.
        refused: bool,
    },
}

/// A spec's problem in words: `field = value: expected`; without a value (the spec did not
/// parse, a path was refused), the field and what went wrong, the field named once.
fn spec_problem(field: &str, value: &str, expected: &str) -> String {
    match (value.is_empty(), field) {
        (false, _) => format!("{field} = {value}: {expected}"),
        (true, "(file)" | "(spec)") => expected.to_string(),
        (true, _) if expected.starts_with(field) => expected.to_string(),
        (true, _) => format!("{field}: {expected}"),
    }
}

/// The workflow layer's result.
pub type Result<T, E = Error> = std::result::Result<T, E>;

impl Error {
    /// An I/O error on `path`.
    pub fn io(action: &'static str, path: impl Into<PathBuf>) -> impl FnOnce(std::io::Error) -> Error {
        let path = path.into();
        move |cause| Error::Io { action, path, cause }
    }
}

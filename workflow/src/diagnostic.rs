//! A numerical failure in words: what was detected, where, the likely cause and what to try.

use kanestop_runtime::model::Model;
use kanestop_runtime::simulate::Failure;

/// The diagnostic of `failure` in `model`'s run, on several lines.
pub fn describe(_model: &Model, failure: &Failure) -> String {
    failure.to_string()
}

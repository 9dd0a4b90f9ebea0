//! What a run's results say against the line's load limits.

use kanestop_runtime::model::Model;
use kanestop_runtime::simulate::RunResult;

/// A joint whose peak tension exceeded its break load.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Exceedance {
    /// The joint k (between B_{k−1} and B_k).
    pub joint: usize,
    /// Its peak tension, N.
    pub peak: f64,
    /// Its break load, N.
    pub limit: f64,
}

/// Joints whose peak tension exceeded their break load.
pub fn break_exceedances(model: &Model, result: &RunResult) -> Vec<Exceedance> {
    result
        .peak_tensions
        .iter()
        .enumerate()
        .filter_map(|(i, p)| {
            let joint = i + 2;
            let limit = model.joint_limits(joint).breaking?;
            (p.tension > limit).then_some(Exceedance { joint, peak: p.tension, limit })
        })
        .collect()
}

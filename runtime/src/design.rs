//! Design checks: the limits a run's results are held to (`[checks]` of a scene or a sweep
//! spec). The runtime only carries and range-checks them; the workflow evaluates them
//! against a finished run (`kanestop_workflow::checks`).

use serde::{Deserialize, Serialize};

/// The fields of [`DesignChecks`], as a scene's `[checks]` names them.
pub const CHECK_FIELDS: [&str; 5] =
    ["max_stopping_distance", "max_stopping_time", "max_anchor_drag", "safety_factor", "max_proof_utilisation"];

/// `[checks]`: pass/fail limits on a run's results. Every field is optional; a check that
/// is absent is not made. SI units.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct DesignChecks {
    /// Largest allowed stopping distance (the ship's surge to its stop), m, > 0. A run that
    /// did not stop the ship fails it.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub max_stopping_distance: Option<f64>,
    /// Largest allowed stopping time, s, > 0. A run that did not stop the ship fails it.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub max_stopping_time: Option<f64>,
    /// Largest allowed anchor drag distance, m, ≥ 0.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub max_anchor_drag: Option<f64>,
    /// Required safety factor on the break load, dimensionless, ≥ 1: at every joint with a break load,
    /// peak tension × safety_factor ≤ break load (break utilisation ≤ 1 / safety_factor).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub safety_factor: Option<f64>,
    /// Largest allowed proof-load utilisation (peak tension over proof load) at every joint
    /// with a proof load, dimensionless, in (0, 10], e.g. 1.0: the peak stays below the proof load.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub max_proof_utilisation: Option<f64>,
}

impl DesignChecks {
    /// True when no check is set.
    pub fn is_empty(&self) -> bool {
        *self == DesignChecks::default()
    }

    /// Every out-of-range limit as (field under `prefix`, value, valid range).
    pub fn problems(&self, prefix: &str) -> Vec<(String, f64, &'static str)> {
        let mut out = Vec::new();
        let mut check = |name: &str, v: Option<f64>, ok: fn(f64) -> bool, expected: &'static str| {
            if let Some(v) = v.filter(|&v| !ok(v)) {
                out.push((format!("{prefix}.{name}"), v, expected));
            }
        };
        let positive = |v: f64| v.is_finite() && v > 0.0;
        check("max_stopping_distance", self.max_stopping_distance, positive, "finite and > 0 m");
        check("max_stopping_time", self.max_stopping_time, positive, "finite and > 0 s");
        check("max_anchor_drag", self.max_anchor_drag, |v| v.is_finite() && v >= 0.0, "finite and ≥ 0 m");
        check("safety_factor", self.safety_factor, |v| v.is_finite() && v >= 1.0, "finite and ≥ 1");
        check("max_proof_utilisation", self.max_proof_utilisation, |v| v > 0.0 && v <= 10.0, "in (0, 10]");
        out
    }
}

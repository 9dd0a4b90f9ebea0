//! The machine-readable summary of a run (`run --json`, the Python package's
//! `result.summary`, the rows of a sweep): one flat, documented record, computed from the
//! results only. Its field names and units are a contract (docs/conventions.md).

use std::collections::BTreeMap;

use kanestop_chain::BodyKind;
use kanestop_runtime::energy::Energy;
use kanestop_runtime::model::{LoadLimits, Model};
use kanestop_runtime::scene::Method;
use kanestop_runtime::simulate::{RunResult, Stop};
use serde::{Deserialize, Serialize};

use crate::batch::Status;
use crate::checks::{self, CheckOutcome};
use crate::diagnostic;

/// What one run produced, in SI units.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct RunSummary {
    /// The scene's `meta.name`.
    pub scene: String,
    /// N, the number of bodies.
    pub bodies: usize,
    /// The integrator.
    pub method: Method,
    /// `solver.dt`: RK4's step or the adaptive methods' observation interval, s.
    pub dt: f64,
    /// The kernel that evaluated the equations: `generated` or `reference`.
    pub kernel: String,
    /// The generated kernel's form: `rolled` (any N; the fused right-hand sides), `unrolled`
    /// (built for this N) or `folded` (built for this chain's numbers); none for the reference.
    pub kernel_form: Option<String>,
    /// How the run ended: `stopped`, `end time` or `failed`.
    pub status: Status,
    /// First zero of the ship's surge speed, s.
    pub stopping_time: Option<f64>,
    /// Table 3's stopping time when the scene is a paper case, s.
    pub paper_stopping_time: Option<f64>,
    /// The ship's surge displacement from t = 0 to its stop (when the run ended there), m.
    pub stopping_distance: Option<f64>,
    /// The ship's surge displacement at the end of the run, m.
    pub ship_displacement: f64,
    /// How far the anchor was dragged by the end of the run, m.
    pub anchor_drag_distance: f64,
    /// When the anchor first slid, s.
    pub anchor_start: Option<f64>,
    /// The largest joint tension of the run.
    pub peak_tension: Option<Peak>,
    /// The largest tension at a joint of the chain (a chain link on either side), its
    /// utilisations against the chain's own proof and break loads (at the chain–cable joint
    /// too, where `peak_tension` takes the weaker of the two members).
    pub chain_peak: Option<Peak>,
    /// The largest tension at a joint of the cable (cable elements, the rod's foot included),
    /// its utilisation against the cable's break load.
    pub cable_peak: Option<Peak>,
    /// The tension at the rod–ship joint (the fairlead): its peak, against the cable's break
    /// load (the rod's).
    pub rod_peak: Option<Peak>,
    /// Energy balance at t = 0 (Eq. 63), J; `None` for a run that never started (refused or
    /// failed before its first state was observed).
    pub initial_energy: Option<f64>,
    /// Kinetic energy at t = 0, the entrained water's included, J: the energy the system
    /// must absorb to stop the ship, the base of the energy split (0 for a run that never
    /// started).
    #[serde(default)]
    pub initial_kinetic_energy: f64,
    /// Work done on the system by each term of the energy balance by the end of the run
    /// (negative: dissipated), J, by name: buoyancy, seabed, friction, drag, hydrostatic,
    /// added_mass, and the parts of friction and drag: anchor_friction, line_friction
    /// (friction = their sum), anchor_drag, line_drag, hull_resistance (drag = their sum).
    /// Every name is present; each `None` for a run that never started.
    pub work: BTreeMap<String, Option<f64>>,
    /// Largest relative drift |E − E_0|/K of the energy balance, K the largest kinetic energy
    /// so far (`energy_scale` at the end); until 2026-12-06 it was relative to E_0. `None` for
    /// a run that never started.
    pub energy_drift: Option<f64>,
    /// K, the energy drift's scale: the run's largest kinetic energy, the entrained water's
    /// included, J (for a ship that only slows, `initial_kinetic_energy`); `None` for a run
    /// that never started.
    #[serde(default)]
    pub energy_scale: Option<f64>,
    /// Simulated time reached, s.
    pub t_end: f64,
    /// Intervals of `dt` completed.
    pub steps: u64,
    /// Right-hand-side evaluations.
    pub rhs_evaluations: u64,
    /// Wall time of the run, s.
    pub wall_time: f64,
    /// CPU time of the run on its own thread, s (none where the platform does not say, or
    /// for a run refused before its first step).
    #[serde(default)]
    pub cpu_time: Option<f64>,
    /// The numerical failure, when the run ended in one.
    pub failure: Option<FailureRecord>,
    /// The design checks of the scene's `[checks]`, each with its value, limit and pass
    /// (absent when the scene has none).
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub checks: Vec<CheckOutcome>,
    /// Whether every design check passed: false when a break load was exceeded or a limit of
    /// `[checks]` failed, true when nothing failed and a check was made (the break loads of a
    /// run that took a step and did not fail, or `[checks]`), absent when none was made
    /// ([`checks::verdict`]).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub checks_pass: Option<bool>,
    /// x_L of the laid line, m: `initial.horizontal_projection`, or the one that
    /// `initial.horizontal_tension` or `initial.top_tension` lays it at.
    #[serde(default)]
    pub initial_horizontal_projection: f64,
    /// T_h of the laid line, N: w_c a of the catenary its elements are laid on (Eq. 31), as
    /// given by `initial.horizontal_tension` or as the scene lays the line.
    #[serde(default)]
    pub initial_horizontal_tension: f64,
    /// T_t of the laid line, its top tension at rest, N: w_c (a + h_L), as given by
    /// `initial.top_tension` or as the scene lays the line.
    #[serde(default)]
    pub initial_top_tension: f64,
    /// The water depth d, m (`Scene::water_depth`).
    #[serde(default)]
    pub water_depth: f64,
    /// Whether the peak tension came at the engagement ([`early_peak`]): within 0.5 s (or 20
    /// steps) of the start of a ship under way, where the model takes the line up at once
    /// (`run` notes it, with the largest sampled tension after). Added 2026-12-07.
    #[serde(default)]
    pub early_peak: bool,
}

/// The largest sampled tension after the engagement, of a run whose peak came in it
/// ([`early_peak`]).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct LaterPeak {
    /// Tension, N.
    pub tension: f64,
    /// The joint k.
    pub joint: usize,
    /// When, s (an output time).
    pub t: f64,
}

/// A run whose peak tension came at the engagement: within
/// [`kanestop_runtime::simulate::EARLY_FAILURE_TIME`] (or 20 steps) of the start, the ship
/// under way. The model starts the ship at full speed on a line at rest (docs/model-choices.md,
/// "Initial speeds"), so the line near the ship is taken up at once: a snap that a net's
/// give would soften, and that the line's layout at rest does not explain (a review's deeper
/// scene: 283 kN at 0.154 s at 3 m/s, 112 kN at 1.75 s at 1.5 m/s, 19 kN at rest). Some
/// with the largest tension sampled after that window (none when the run ended in it). None
/// for a run that failed (its peak is the failure's) and for a peak at t = 0 (the laid line's
/// own tension).
pub fn early_peak(model: &Model, result: &RunResult) -> Option<Option<LaterPeak>> {
    let (_, peak) = result.peak_tension()?;
    let dt = model.scene.solver.dt;
    let early = |t: f64| kanestop_runtime::simulate::is_early(t, dt);
    let failed = matches!(result.stop, kanestop_runtime::simulate::Stop::Failed(_));
    if !result.ran() || failed || model.scene.initial.ship_speed == 0.0 || peak.t <= 0.0 || !early(peak.t) {
        return None;
    }
    let later = result
        .samples
        .iter()
        .filter(|s| !early(s.t))
        .flat_map(|s| {
            s.tensions.iter().enumerate().map(move |(i, &tension)| LaterPeak { tension, joint: i + 2, t: s.t })
        })
        .max_by(|a, b| a.tension.total_cmp(&b.tension));
    Some(later)
}

/// A peak joint tension.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct Peak {
    /// Tension, N.
    pub tension: f64,
    /// The joint k (between B_{k−1} and B_k).
    pub joint: usize,
    /// When, s.
    pub t: f64,
    /// Tension over the joint's proof load, when it has one.
    pub proof_utilisation: Option<f64>,
    /// Tension over the joint's break load, when it has one.
    pub break_utilisation: Option<f64>,
}

/// A numerical failure: its data and its words.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct FailureRecord {
    /// Time of the first bad step, s.
    pub t: f64,
    /// The body most involved (1-based, B_k).
    pub body: usize,
    /// The diagnostic as the summary prints it.
    pub message: String,
}

/// Which part of the line a joint belongs to, for the per-segment peaks.
#[derive(Clone, Copy, PartialEq, Eq)]
enum Segment {
    Chain,
    Cable,
    Rod,
}

fn segment(model: &Model, k: usize) -> Segment {
    let (inner, outer) = (model.chain.bodies[k - 2].kind, model.chain.bodies[k - 1].kind);
    match (inner, outer) {
        (_, BodyKind::Ship) => Segment::Rod,
        (BodyKind::ChainLink, _) | (_, BodyKind::ChainLink) => Segment::Chain,
        _ => Segment::Cable,
    }
}

impl RunSummary {
    /// Whether a break load was exceeded: some peak (over the whole line, or a member's
    /// over its joints) above its break load.
    pub fn break_load_exceeded(&self) -> bool {
        self.max_break_utilisation().is_some_and(|u| u > 1.0)
    }

    /// The line's largest break utilisation: peak tension over break load at the worst joint,
    /// which need not be the joint of the largest tension (a weaker chain). Each member has
    /// one break load, so it is the largest of the members' peaks' utilisations.
    pub fn max_break_utilisation(&self) -> Option<f64> {
        [&self.peak_tension, &self.chain_peak, &self.cable_peak, &self.rod_peak]
            .into_iter()
            .flatten()
            .filter_map(|p| p.break_utilisation)
            .reduce(f64::max)
    }

    /// The summary of `result`, a run of `model`.
    pub fn of(model: &Model, result: &RunResult) -> RunSummary {
        let n = model.body_count();
        let ran = result.ran();
        let (t_h, t_t) = model.initial_tensions();
        let displacement = |body: usize| result.displacement(body);
        // The peak over the joints `keep` takes, its utilisations against `limits` (the
        // joint's, or a segment's own member's).
        let peak_over = |keep: &dyn Fn(usize) -> bool, limits: &dyn Fn(usize) -> LoadLimits| -> Option<Peak> {
            let (i, p) = result
                .peak_tensions
                .iter()
                .enumerate()
                .filter(|(i, _)| keep(i + 2))
                .max_by(|a, b| a.1.tension.total_cmp(&b.1.tension))?;
            let k = i + 2;
            let limits = limits(k);
            Some(Peak {
                tension: p.tension,
                joint: k,
                t: p.t,
                proof_utilisation: limits.proof.map(|l| p.tension / l),
                break_utilisation: limits.breaking.map(|l| p.tension / l),
            })
        };
        let peak_in = |s: Segment| {
            let own = model.member_limits(match s {
                Segment::Chain => BodyKind::ChainLink,
                Segment::Cable | Segment::Rod => BodyKind::Rod,
            });
            if ran {
                peak_over(&|k| segment(model, k) == s, &|_| own)
            } else {
                None
            }
        };
        let last = result.samples.last();
        let started = result.observed();
        let outcomes = model.scene.checks.as_ref().map(|c| checks::evaluate(c, model, result)).unwrap_or_default();
        RunSummary {
            scene: model.scene.meta.name.clone(),
            bodies: n,
            method: model.scene.solver.integrator,
            dt: model.scene.solver.dt,
            kernel: result.kernel.to_string(),
            kernel_form: result.kernel_form.map(str::to_string),
            status: Status::of(&result.stop),
            stopping_time: result.stopping_time,
            paper_stopping_time: kanestop_runtime::paper::stopping_time(&model.scene),
            stopping_distance: result.stopping_distance,
            ship_displacement: displacement(n - 1),
            anchor_drag_distance: displacement(0),
            anchor_start: result.anchor_start(),
            peak_tension: if ran { peak_over(&|_| true, &|k| model.joint_limits(k)) } else { None },
            chain_peak: peak_in(Segment::Chain),
            cable_peak: peak_in(Segment::Cable),
            rod_peak: peak_in(Segment::Rod),
            initial_energy: started.then_some(result.energy0),
            initial_kinetic_energy: result.samples.first().map_or(0.0, |s| s.energy.kinetic + s.energy.added_kinetic),
            work: last
                .map(|s| s.energy.reported_work())
                .unwrap_or_else(|| Energy::default().reported_work())
                .iter()
                .map(|(name, work)| (name.to_string(), started.then_some(*work)))
                .collect(),
            energy_drift: started.then_some(result.max_energy_drift),
            energy_scale: started.then_some(result.energy_scale),
            t_end: result.t_end,
            steps: result.steps,
            rhs_evaluations: result.rhs_evaluations,
            wall_time: result.wall_time.as_secs_f64(),
            cpu_time: result.cpu_time.map(|d| d.as_secs_f64()),
            failure: match &result.stop {
                Stop::Failed(f) => {
                    Some(FailureRecord { t: f.t, body: f.body, message: diagnostic::describe(model, f) })
                }
                Stop::ShipStopped | Stop::EndTime => None,
            },
            checks_pass: checks::verdict(
                &outcomes,
                &checks::break_exceedances(model, result),
                checks::break_loads_held(model, result),
            ),
            checks: outcomes,
            initial_horizontal_projection: model.catenary.horizontal,
            initial_horizontal_tension: t_h,
            initial_top_tension: t_t,
            early_peak: early_peak(model, result).is_some(),
            water_depth: model.water_depth(),
        }
    }
}

#[cfg(test)]
mod tests {
    use std::path::Path;

    use kanestop_runtime::generated::GeneratedKernel;
    use kanestop_runtime::paper::DEFAULT_SCENE;
    use kanestop_runtime::scene::Scene;
    use kanestop_runtime::simulate;

    use super::*;
    use crate::batch;

    /// A run that observed its start but completed no interval (as one that fails in its
    /// first): no peak, but its drift, in `run --json` and in a batch row alike; refused
    /// before its first step, neither.
    #[test]
    fn a_batch_row_reports_peak_and_drift_as_the_run_summary_does() {
        let mut scene = Scene::from_toml(DEFAULT_SCENE, "case01.toml").unwrap();
        scene.solver.end_time = 0.01;
        let model = Model::new(&scene).unwrap();
        let full = simulate::run(&model, Box::new(GeneratedKernel::new(&model.chain).unwrap()));
        let mut start = full.clone();
        (start.steps, start.max_energy_drift) = (0, 0.0);
        start.samples.truncate(1);
        let mut refused = start.clone();
        refused.samples.clear();
        for (name, result, peak, drift) in [
            ("full", &full, true, Some(full.max_energy_drift)),
            ("start", &start, false, Some(0.0)),
            ("refused", &refused, false, None),
        ] {
            let (row, summary) = (batch::row(Path::new("case01.toml"), &model, result), RunSummary::of(&model, result));
            assert_eq!((row.peak_tension.is_some(), row.energy_drift), (peak, drift), "{name}");
            assert_eq!(summary.peak_tension.is_some(), peak, "{name}");
            assert_eq!(summary.energy_drift, drift, "{name}");
        }
    }
}

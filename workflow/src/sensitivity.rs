//! Sensitivity: d(output)/d(ln p) of the stopping time, stopping distance and peak tension
//! against every continuous physical parameter of a scene (every nonzero real field outside
//! `[meta]`, `[solver]` and `[checks]`), by central differences p·(1 ± h), the runs in
//! parallel; ranked by |effect on the stopping time|. With parameter uncertainties (σ of
//! ln p) a first-order output band: σ_out² = Σ (effect · σ_ln p)².

use kanestop_runtime::model::Model;
use kanestop_runtime::scene::Scene;
use kanestop_runtime::simulate;
use serde::Serialize;
use toml::Value;

use crate::kernels::KernelFactory;
use crate::record::RunSummary;
use crate::{parallel, Result};

/// The default relative step h: p·(1 ± 0.05).
pub const DEFAULT_STEP: f64 = 0.05;

/// The outputs differentiated.
pub const OUTPUTS: [&str; 3] = ["stopping_time", "stopping_distance", "peak_tension"];

/// One parameter's effects.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Sensitivity {
    /// The dotted path, e.g. `environment.seabed_friction`.
    pub parameter: String,
    /// Its value in the scene.
    pub value: f64,
    /// d(stopping time)/d(ln p), s; none when a perturbed run did not stop the ship.
    pub stopping_time: Option<f64>,
    /// d(stopping distance)/d(ln p), m.
    pub stopping_distance: Option<f64>,
    /// d(peak tension)/d(ln p), N.
    pub peak_tension: Option<f64>,
    /// Why a perturbed run gave nothing, if it did not.
    pub message: String,
}

/// A sensitivity study of one scene.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Study {
    /// The scene's name.
    pub scene: String,
    /// The relative step h.
    pub step: f64,
    /// The base run's stopping time, stopping distance and peak tension.
    pub base: [Option<f64>; 3],
    /// The parameters, ranked by |d(stopping time)/d(ln p)| (largest first).
    pub rows: Vec<Sensitivity>,
}

/// Every continuous physical parameter of `scene`: (dotted path, value), in file order.
pub fn parameters(scene: &Scene) -> Vec<(String, f64)> {
    fn walk(prefix: &str, v: &Value, out: &mut Vec<(String, f64)>) {
        match v {
            Value::Table(t) => {
                for (k, v) in t {
                    let p = if prefix.is_empty() { k.clone() } else { format!("{prefix}.{k}") };
                    walk(&p, v, out);
                }
            }
            Value::Array(a) => {
                for (i, v) in a.iter().enumerate() {
                    walk(&format!("{prefix}[{i}]"), v, out);
                }
            }
            Value::Float(x) if *x != 0.0 => out.push((prefix.to_string(), *x)),
            _ => {}
        }
    }
    let mut out = Vec::new();
    if let Value::Table(t) = scene.to_value() {
        for (k, v) in &t {
            if !["meta", "solver", "checks"].contains(&k.as_str()) {
                walk(k, v, &mut out);
            }
        }
    }
    out
}

fn outputs(s: &RunSummary) -> [Option<f64>; 3] {
    [s.stopping_time, s.stopping_distance, s.peak_tension.map(|p| p.tension)]
}

/// Runs the base scene and each parameter at p·(1 ± step), `jobs` at a time.
pub fn study(
    scene: &Scene,
    step: f64,
    kernel: KernelFactory,
    jobs: Option<usize>,
    done: &(dyn Fn() + Sync),
) -> Result<Study> {
    if !(step > 0.0 && step < 0.5) {
        return Err(crate::Error::Argument {
            name: "--step",
            value: step.to_string(),
            expected: "in (0, 0.5), e.g. 0.05".into(),
        });
    }
    let params = parameters(scene);
    let mut scenes: Vec<std::result::Result<Scene, String>> = vec![Ok(scene.clone())];
    for (path, v) in &params {
        for sign in [1.0, -1.0] {
            scenes.push(
                scene.with_overrides(&[(path, Value::Float(v * (1.0 + sign * step)))]).map_err(|e| e.to_string()),
            );
        }
    }
    let runs = parallel::map_jobs(jobs, &scenes, |s| {
        let r = s.clone().and_then(|s| {
            let model = Model::new(&s).map_err(|e| e.to_string())?;
            let result = simulate::run(&model, kernel(&model));
            Ok(outputs(&RunSummary::of(&model, &result)))
        });
        done();
        r
    })?;
    let base = runs[0].clone().map_err(crate::Error::NoReference)?;
    let denom = ((1.0 + step) / (1.0 - step)).ln();
    let mut rows: Vec<Sensitivity> = params
        .iter()
        .enumerate()
        .map(|(i, (path, value))| {
            let (up, down) = (&runs[1 + 2 * i], &runs[2 + 2 * i]);
            let mut row = Sensitivity {
                parameter: path.clone(),
                value: *value,
                stopping_time: None,
                stopping_distance: None,
                peak_tension: None,
                message: String::new(),
            };
            match (up, down) {
                (Ok(u), Ok(d)) => {
                    let e = |k: usize| u[k].zip(d[k]).map(|(a, b)| (a - b) / denom);
                    row.stopping_time = e(0);
                    row.stopping_distance = e(1);
                    row.peak_tension = e(2);
                }
                (Err(m), _) | (_, Err(m)) => row.message = m.lines().map(str::trim).collect::<Vec<_>>().join(" | "),
            }
            row
        })
        .collect();
    rows.sort_by(|a, b| {
        b.stopping_time.map(f64::abs).unwrap_or(-1.0).total_cmp(&a.stopping_time.map(f64::abs).unwrap_or(-1.0))
    });
    Ok(Study { scene: scene.meta.name.clone(), step, base, rows })
}

/// The first-order standard deviation of each output, from each parameter's σ of ln p
/// (`(path, sigma_ln)`; paths not in the study are ignored and returned).
pub fn band(study: &Study, sigmas: &[(String, f64)]) -> ([f64; 3], Vec<String>) {
    let mut var = [0.0; 3];
    let mut missing = Vec::new();
    for (path, s) in sigmas {
        match study.rows.iter().find(|r| &r.parameter == path) {
            Some(r) => {
                for (k, e) in [r.stopping_time, r.stopping_distance, r.peak_tension].iter().enumerate() {
                    var[k] += (e.unwrap_or(0.0) * s).powi(2);
                }
            }
            None => missing.push(path.clone()),
        }
    }
    (var.map(f64::sqrt), missing)
}

/// The study as a terminal table.
pub fn table(study: &Study) -> String {
    let d = |v: Option<f64>, scale: f64, digits: usize| {
        v.map(|v| format!("{:+.*}", digits, v * scale)).unwrap_or_else(|| "—".into())
    };
    let mut out = format!(
        "sensitivity of {} (central differences at p·(1 ± {})): d(output)/d(ln p)\n{:<4} {:<42} {:>14} {:>12} {:>12} {:>12}\n",
        study.scene, study.step, "rank", "parameter", "value", "stop (s)", "dist (m)", "peak (kN)"
    );
    for (i, r) in study.rows.iter().enumerate() {
        out.push_str(&format!(
            "{:<4} {:<42} {:>14} {:>12} {:>12} {:>12}\n",
            i + 1,
            r.parameter,
            format!("{:.6}", r.value).trim_end_matches('0').trim_end_matches('.').to_string(),
            d(r.stopping_time, 1.0, 3),
            d(r.stopping_distance, 1.0, 3),
            d(r.peak_tension, 1e-3, 1)
        ));
        if !r.message.is_empty() {
            out.push_str(&format!("     {}\n", r.message));
        }
    }
    out
}

/// The study as CSV, in rank order.
pub fn csv(study: &Study) -> String {
    let o = |v: Option<f64>| v.map(|v| format!("{v}")).unwrap_or_default();
    let mut out = String::from("rank,parameter,value,d_stopping_time,d_stopping_distance,d_peak_tension,message\n");
    for (i, r) in study.rows.iter().enumerate() {
        out.push_str(&format!(
            "{},{},{},{},{},{},\"{}\"\n",
            i + 1,
            r.parameter,
            r.value,
            o(r.stopping_time),
            o(r.stopping_distance),
            o(r.peak_tension),
            r.message.replace('"', "'")
        ));
    }
    out
}

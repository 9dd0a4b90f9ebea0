//! The sweep spec (TOML): a base scene, overrides for every row, grid axes and uncertain
//! inputs over dotted paths, and design checks. [`Spec::load`] checks a file whole
//! ([`Spec::from_toml`] text, [`Spec::from_table`] a table, as the Python package gives) and
//! [`Spec::plan`] turns it into one scene per row, in spec order. Format: docs/sweeps.md.

use std::path::{Path, PathBuf};

use kanestop_runtime::design::DesignChecks;
use kanestop_runtime::overrides;
use kanestop_runtime::scene::{Scene, SceneError, MAX_SCENE_BYTES};
use serde::Deserialize;
use toml::Value;

use super::sampling::{self, Distribution, Method};
use crate::{Error, Result};

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct SpecFile {
    base: Option<String>,
    name: Option<String>,
    solver: Option<toml::Table>,
    set: Option<toml::Table>,
    #[serde(default)]
    axis: Vec<AxisFile>,
    sampling: Option<SamplingFile>,
    #[serde(default)]
    uncertain: Vec<UncertainFile>,
    checks: Option<DesignChecks>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct AxisFile {
    path: String,
    values: Option<Vec<Value>>,
    range: Option<RangeFile>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct RangeFile {
    from: f64,
    to: f64,
    steps: usize,
    #[serde(default)]
    scale: Scale,
}

#[derive(Clone, Copy, Default, Deserialize, PartialEq)]
#[serde(rename_all = "lowercase")]
enum Scale {
    #[default]
    Linear,
    Log,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct SamplingFile {
    method: Method,
    samples: usize,
    seed: u64,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct UncertainFile {
    path: String,
    distribution: String,
    low: Option<f64>,
    high: Option<f64>,
    mean: Option<f64>,
    sd: Option<f64>,
    median: Option<f64>,
    sigma: Option<f64>,
}

/// The most rows a spec may plan (every row's scene is held in memory): a million runs,
/// about a CPU-day of paper cases; a larger study is several specs.
pub const MAX_ROWS: usize = 1_000_000;

/// One grid axis: a dotted path and its values, in order.
#[derive(Clone, Debug, PartialEq)]
pub struct Axis {
    /// The scene field, e.g. `ship.mass`.
    pub path: String,
    /// Its values.
    pub values: Vec<Value>,
}

/// One uncertain input.
#[derive(Clone, Debug, PartialEq)]
pub struct Uncertain {
    /// The scene field (a float).
    pub path: String,
    /// Its distribution.
    pub distribution: Distribution,
}

/// A checked sweep spec.
#[derive(Clone, Debug, PartialEq)]
pub struct Spec {
    /// The spec file.
    pub file: PathBuf,
    /// The sweep's name (`name`, or the spec file's stem): rows are `name-000`, ….
    pub name: String,
    /// The base scene, with the spec's `[checks]` (in place of the base's own), `[solver]`
    /// and `[set]` applied, in that order: a `[set]` path under `checks.` sets one check.
    pub base: Scene,
    /// Grid axes, combined as a Cartesian product (last fastest).
    pub axes: Vec<Axis>,
    /// Sampling of the uncertain inputs: method, samples, seed.
    pub sampling: Option<(Method, usize, u64)>,
    /// The uncertain inputs.
    pub uncertain: Vec<Uncertain>,
}

/// One row of a sweep before it runs.
#[derive(Clone, Debug)]
pub struct PlannedRow {
    /// Its index, from 0, in spec order.
    pub index: usize,
    /// `name-000`.
    pub name: String,
    /// The swept inputs (axes, then uncertain inputs) and their values.
    pub inputs: Vec<(String, Value)>,
    /// The row's scene, or why the inputs give none.
    pub scene: std::result::Result<Scene, String>,
}

fn bad(file: &Path, field: impl Into<String>, value: impl std::fmt::Display, expected: impl Into<String>) -> Error {
    Error::Spec { file: file.to_path_buf(), field: field.into(), value: value.to_string(), expected: expected.into() }
}

/// Checks a sweep's name, which names its rows' files (`NAME-000.toml`) and its Slurm jobs:
/// 1 to 100 letters, digits, spaces and `-_.+`, not starting with `.`; else the valid form.
pub fn check_name(name: &str) -> std::result::Result<(), String> {
    let fine = |c: char| c.is_alphanumeric() || " -_.+".contains(c);
    if (1..=100).contains(&name.chars().count()) && name.chars().all(fine) && !name.starts_with('.') {
        Ok(())
    } else {
        Err("1 to 100 letters, digits, spaces and - _ . + (not starting with .): it names the rows' files and the jobs"
            .into())
    }
}

impl Spec {
    /// Reads and checks a spec file; the base scene is relative to it.
    pub fn load(file: &Path) -> Result<Spec> {
        let text = kanestop_runtime::scene::read_text_file(file, MAX_SCENE_BYTES, "a sweep spec's")
            .map_err(Error::io("read", file))?;
        let dir = file.parent().unwrap_or(Path::new(""));
        Spec::from_toml(&text, file, dir, None)
    }

    /// Checks a spec given as TOML text. `file` names it in messages (its stem is the default
    /// `name`; `sweep` for a label such as `<string>`), `base` is relative to `dir`, and
    /// `scene`, when given, is the base scene instead (the spec then has no `base`).
    pub fn from_toml(text: &str, file: &Path, dir: &Path, scene: Option<Scene>) -> Result<Spec> {
        let raw: SpecFile = toml::from_str(text).map_err(|e| {
            // A scene given for a spec: say what a sweep needs, not the TOML error.
            let tables: Option<toml::Table> = toml::from_str(text).ok();
            if tables.is_some_and(|t| ["meta", "ship", "chain", "anchor"].iter().any(|k| t.contains_key(*k))) {
                return bad(
                    file,
                    "(file)",
                    "",
                    "a spec, not a scene: this is a scene file; a sweep over it is a spec file with \
                     base = \"<this file>\" and its [[axis]] or [sampling] (docs/sweeps.md); from \
                     Python, give the scene with rows=[…] instead",
                );
            }
            bad(file, "(file)", "", kanestop_runtime::scene::plain_types(&e.to_string()))
        })?;
        Spec::from_raw(raw, file, dir, scene)
    }

    /// [`Spec::from_toml`] of a spec given as a table of the same fields (a Python dict).
    pub fn from_table(table: toml::Table, file: &Path, dir: &Path, scene: Option<Scene>) -> Result<Spec> {
        let root = Value::Table(table);
        let raw: SpecFile = kanestop_runtime::scene::from_value_at(root.clone()).map_err(|e| {
            // The message ends "in `axis[1].range.steps`" when the error is at a key: its field,
            // whose value as given is said with it (none where the key is missing).
            let text = kanestop_runtime::scene::plain_types(&e);
            match text.trim_end().rsplit_once("\nin `") {
                Some((message, key)) => {
                    let key = key.trim_end_matches('`');
                    let value = overrides::get(&root, key).map(Value::to_string).unwrap_or_default();
                    bad(file, key, value, message.trim())
                }
                None => bad(file, "(spec)", "", text.trim()),
            }
        })?;
        Spec::from_raw(raw, file, dir, scene)
    }

    /// The spec of one scene with no axis and no sampling: one row, the scene, until rows
    /// are given to [`Spec::plan_inputs`]. Rows are `name-000`, ….
    pub fn of_scene(scene: Scene, name: &str) -> Spec {
        Spec {
            file: PathBuf::from(format!("<{name}>")),
            name: name.to_string(),
            base: scene,
            axes: Vec::new(),
            sampling: None,
            uncertain: Vec::new(),
        }
    }

    /// The same spec with `values` set on the base scene for every row, as if added to `[set]`;
    /// a path that is an input of the spec (an axis, an uncertain input) is refused, as in
    /// `[set]`: its values would override the one given in every row.
    pub fn with_set(mut self, values: &[(&str, Value)]) -> Result<Spec> {
        let inputs = self.axes.iter().map(|a| &a.path).chain(self.uncertain.iter().map(|u| &u.path));
        // As in a spec file: allowed where the base needs the value to be valid at all.
        let needed = |path: &str| {
            let others: Vec<(&str, Value)> = values.iter().filter(|(p, _)| *p != path).cloned().collect();
            self.base.with_overrides(&others).is_err()
        };
        if let Some((path, v)) = values.iter().find(|(p, _)| inputs.clone().any(|i| i == p) && !needed(p)) {
            return Err(bad(
                &self.file,
                *path,
                v,
                "a path not also an input of the spec (an axis or an uncertain input), whose values would override it",
            ));
        }
        if !values.is_empty() {
            self.base = self.base.with_overrides(values)?;
        }
        Ok(self)
    }

    fn from_raw(raw: SpecFile, file: &Path, dir: &Path, scene: Option<Scene>) -> Result<Spec> {
        let original = match (raw.base, scene) {
            (Some(base), None) => Scene::load(&dir.join(base))
                .map_err(|error| Error::BaseScene { spec: file.to_path_buf(), error: Box::new(error) })?,
            (None, Some(scene)) => scene,
            (Some(base), Some(_)) => return Err(bad(file, "base", base, "given twice: a file and a scene")),
            (None, None) => return Err(bad(file, "base", "(missing)", "the base scene, a file relative to the spec")),
        };
        let mut value = original.to_value();
        // The spec's checks replace the base's, before [set], whose `checks.*` paths then
        // set one of them (an axis's, in the row's scene, as well).
        if let Some(c) = &raw.checks {
            if let Some((field, v, expected)) = c.problems("checks").into_iter().next() {
                return Err(bad(file, field, v, expected));
            }
            if let Value::Table(t) = &mut value {
                t.insert("checks".into(), Value::try_from(c).expect("design checks are optional numbers"));
            }
        }
        let with_checks = value.clone();
        let mut set =
            |path: &str, v: Value| overrides::set(&mut value, path, v).map_err(|e| bad(file, path, "", e.to_string()));
        // The spec's field, path and value of everything fixed for all rows ([solver], [set]):
        // each path once, and none an axis or uncertain input too, whose values would silently
        // override it in every row (unless the base needs it to be valid at all).
        let mut fixed: Vec<(String, String, Value)> = Vec::new();
        for (k, v) in raw.solver.into_iter().flatten() {
            let path = format!("solver.{k}");
            set(&path, v.clone())?;
            fixed.push((path.clone(), path, v));
        }
        // Each input's field in the spec, its path and what the field holds (a [set] entry
        // holds its value, an axis's `path` the path).
        let mut inputs: Vec<(String, String, String)> = Vec::new();
        for (k, v) in raw.set.into_iter().flatten() {
            let field = format!("set.\"{k}\"");
            if k == ROW_NAME.0 {
                return Err(bad(file, field, v, ROW_NAME.1));
            }
            if let Some((other, ..)) = fixed.iter().find(|(_, p, _)| *p == k) {
                return Err(bad(file, field, v, format!("{k} is set in [solver] too ({other}): set it in one place")));
            }
            inputs.push((field.clone(), k.clone(), v.to_string()));
            fixed.push((field, k.clone(), v.clone()));
            set(&k, v)?;
        }
        // Whether the base is a valid scene without the fixed entry `skip` (its field).
        let valid_without = |skip: &str| {
            let mut v = with_checks.clone();
            fixed.iter().filter(|(f, ..)| f != skip).all(|(_, p, x)| overrides::set(&mut v, p, x.clone()).is_ok())
                && Scene::from_value(v, "").is_ok()
        };
        let named = format!("(the base of sweep spec {} with its [checks], [solver] and [set])", file.display());
        let base = Scene::from_value(value, &named)?;
        let base_value = base.to_value();
        let axes =
            raw.axis.into_iter().enumerate().map(|(i, a)| axis(file, &base_value, i, a)).collect::<Result<Vec<_>>>()?;
        let uncertain = raw
            .uncertain
            .into_iter()
            .enumerate()
            .map(|(i, u)| uncertain(file, &base_value, i, u))
            .collect::<Result<Vec<_>>>()?;
        // Each input path once: a second axis (or uncertain input) on a path would override
        // the first in the scene while the table recorded the first; one on a path [set] or
        // [solver] fixes would override that in every row.
        let paths = axes.iter().map(|a| a.path.as_str()).chain(uncertain.iter().map(|u| u.path.as_str()));
        for (i, path) in paths.clone().enumerate() {
            let field =
                if i < axes.len() { format!("axis[{i}].path") } else { format!("uncertain[{}].path", i - axes.len()) };
            if paths.clone().take(i).any(|p| p == path) {
                return Err(bad(
                    file,
                    field,
                    path,
                    "a path not already an input (each path once, as an axis or an uncertain input)",
                ));
            }
            // Allowed where the base needs the fixed value to be valid (an output interval no
            // shorter than a [solver] dt, with the interval an axis): the rows take the input's.
            if let Some((other, ..)) = fixed.iter().find(|(_, p, _)| p == path).filter(|(f, ..)| valid_without(f)) {
                return Err(bad(
                    file,
                    field,
                    path,
                    format!("a path not fixed for every row: {other} sets it too, and the input would override it"),
                ));
            }
        }
        // Two ways to give one quantity (two of x_L, T_h and T_t) in one spec: the row's scene
        // would keep the one set last.
        let path_of = |field: String, path: &String| (field, path.clone(), path.clone());
        inputs.extend(axes.iter().enumerate().map(|(i, a)| path_of(format!("axis[{i}].path"), &a.path)));
        inputs.extend(uncertain.iter().enumerate().map(|(i, u)| path_of(format!("uncertain[{i}].path"), &u.path)));
        let paths: Vec<&str> = inputs.iter().map(|(_, p, _)| p.as_str()).collect();
        if let Some((i, j)) = overrides::conflicting_alternatives(&paths) {
            let why = format!("not set with {} ({}): both give one quantity, set one of them", paths[i], inputs[i].0);
            return Err(bad(file, &inputs[j].0, &inputs[j].2, why));
        }
        let sampling = match (raw.sampling, uncertain.is_empty()) {
            (Some(s), false) if (1..=MAX_ROWS).contains(&s.samples) => Some((s.method, s.samples, s.seed)),
            (Some(s), false) => return Err(bad(file, "sampling.samples", s.samples, format!("in [1, {MAX_ROWS}]"))),
            (Some(_), true) => return Err(bad(file, "sampling", "set", "needs at least one [[uncertain]] input")),
            (None, false) => return Err(bad(file, "uncertain", "set", "needs [sampling] (method, samples, seed)")),
            (None, true) => None,
        };
        let sizes: Vec<usize> = axes.iter().map(|a| a.values.len()).chain(sampling.map(|s| s.1)).collect();
        if sizes.iter().try_fold(1usize, |all, &n| all.checked_mul(n).filter(|&t| t <= MAX_ROWS)).is_none() {
            let product = sizes.iter().map(usize::to_string).collect::<Vec<_>>().join(" × ");
            let what = if sampling.is_some() { "the axes' values times the samples" } else { "the axes' values" };
            return Err(bad(
                file,
                "axis",
                format!("{product} rows"),
                format!("at most {MAX_ROWS} rows in all ({what}); split the study into several specs"),
            ));
        }
        let stem = file
            .file_stem()
            .map(|s| s.to_string_lossy().into_owned())
            .filter(|s| !s.starts_with('<'))
            .unwrap_or_else(|| "sweep".into());
        let given = raw.name.is_some();
        let name = raw.name.unwrap_or(stem);
        check_name(&name).map_err(|expected| {
            // A name the spec did not give is its file's stem: say so, and how to give one.
            let (value, expected) = if given {
                (format!("{name:?}"), expected)
            } else {
                (
                    format!("{name:?} (the spec file's name: the spec has no `name`)"),
                    format!("{expected}; set name = \"…\""),
                )
            };
            bad(file, "name", value, expected)
        })?;
        Ok(Spec { file: file.to_path_buf(), name, base, axes, sampling, uncertain })
    }

    /// The spec's own fields as a spec file's table, without `base` (the scene, with
    /// `[checks]`, `[solver]` and `[set]` already applied, is [`Spec::base`]): `name`, every
    /// axis as its values, `sampling` and `uncertain`. `Spec::from_table` of it with the base
    /// gives the spec back (Python pickles a spec so).
    pub fn to_table(&self) -> toml::Table {
        let mut t = toml::Table::new();
        t.insert("name".into(), Value::String(self.name.clone()));
        let axes = self.axes.iter().map(|a| {
            let mut axis = toml::Table::new();
            axis.insert("path".into(), Value::String(a.path.clone()));
            axis.insert("values".into(), Value::Array(a.values.clone()));
            Value::Table(axis)
        });
        t.insert("axis".into(), Value::Array(axes.collect()));
        if let Some((method, samples, seed)) = self.sampling {
            let method = match method {
                Method::Random => "random",
                Method::LatinHypercube => "latin-hypercube",
            };
            let mut sampling = toml::Table::new();
            sampling.insert("method".into(), Value::String(method.into()));
            sampling.insert("samples".into(), Value::Integer(samples as i64));
            sampling.insert("seed".into(), Value::Integer(seed as i64));
            t.insert("sampling".into(), Value::Table(sampling));
        }
        let uncertain = self.uncertain.iter().map(|u| {
            let (name, params) = match u.distribution {
                Distribution::Uniform { low, high } => ("uniform", [("low", low), ("high", high)]),
                Distribution::Normal { mean, sd } => ("normal", [("mean", mean), ("sd", sd)]),
                Distribution::Lognormal { median, sigma } => ("lognormal", [("median", median), ("sigma", sigma)]),
            };
            let mut entry = toml::Table::new();
            entry.insert("path".into(), Value::String(u.path.clone()));
            entry.insert("distribution".into(), Value::String(name.into()));
            for (k, v) in params {
                entry.insert(k.into(), Value::Float(v));
            }
            Value::Table(entry)
        });
        t.insert("uncertain".into(), Value::Array(uncertain.collect()));
        t
    }

    /// Number of rows: the grid's size times the samples.
    pub fn rows(&self) -> usize {
        self.axes.iter().map(|a| a.values.len()).product::<usize>() * self.sampling.map_or(1, |s| s.1)
    }

    /// Every row's inputs and scene, in spec order: grid points (last axis fastest), and
    /// for each the samples in draw order (the same samples at every grid point).
    pub fn plan(&self) -> Vec<PlannedRow> {
        let grid: usize = self.axes.iter().map(|a| a.values.len()).product();
        let points = match self.sampling {
            Some((method, n, seed)) => sampling::unit_points(method, n, self.uncertain.len(), seed),
            None => vec![vec![]],
        };
        let mut inputs = Vec::with_capacity(self.rows());
        for g in 0..grid {
            let mut at = Vec::new();
            let mut rest = g;
            for a in self.axes.iter().rev() {
                at.push((a.path.clone(), a.values[rest % a.values.len()].clone()));
                rest /= a.values.len();
            }
            at.reverse();
            for p in &points {
                let mut row = at.clone();
                for (u, x) in self.uncertain.iter().zip(p) {
                    row.push((u.path.clone(), Value::Float(u.distribution.quantile(*x))));
                }
                inputs.push(row);
            }
        }
        self.plan_inputs(inputs)
    }

    /// One row per entry of `inputs`, in order, named and built as [`Spec::plan`]'s rows are
    /// (explicit rows, e.g. Python's `sweep(scene, rows)`; the rows may set different paths).
    pub fn plan_inputs(&self, inputs: impl IntoIterator<Item = Vec<(String, Value)>>) -> Vec<PlannedRow> {
        inputs
            .into_iter()
            .enumerate()
            .map(|(index, inputs)| {
                let name = format!("{}-{index:03}", self.name);
                let scene = self.scene(&name, &inputs);
                PlannedRow { index, name, inputs, scene }
            })
            .collect()
    }

    /// The scene of one row: the base with `inputs` set, named `name` and described by its
    /// inputs; its Table 3 time that of the paper case it is, if any
    /// (`paper::stopping_time`, the rule every report follows), so its scene file says so.
    pub fn scene(&self, name: &str, inputs: &[(String, Value)]) -> std::result::Result<Scene, String> {
        let values: Vec<(&str, Value)> = inputs.iter().map(|(p, v)| (p.as_str(), v.clone())).collect();
        let mut scene = self.base.with_overrides(&values).map_err(|e| e.to_string())?;
        scene.meta.paper_stopping_time = kanestop_runtime::paper::stopping_time(&scene);
        // The row's own description: the base's would describe a scene it no longer is.
        let set: Vec<String> = inputs.iter().map(|(p, v)| format!("{p} = {v}")).collect();
        scene.meta.description = if inputs.iter().any(|(p, _)| p == "meta.description") {
            scene.meta.description
        } else if set.is_empty() {
            format!("row of sweep {}: {}", self.name, self.base.meta.name)
        } else {
            format!("row of sweep {}: {} with {}", self.name, self.base.meta.name, set.join(", "))
        };
        scene.meta.name = name.to_string();
        Ok(scene)
    }
}

/// What a row's name replaces: `meta.name` is no input of a sweep.
const ROW_NAME: (&str, &str) =
    ("meta.name", "a field other than meta.name, which each row's name takes (NAME-000; the sweep's `name` sets NAME)");

fn axis(file: &Path, base: &Value, i: usize, a: AxisFile) -> Result<Axis> {
    // Long by design: an axis's path, its values (given or a range) and their types are
    // checked in the order a spec's reader meets them, each refusal naming its field.
    let field = |f: &str| format!("axis[{i}].{f}");
    if a.path == ROW_NAME.0 {
        return Err(bad(file, field("path"), &a.path, ROW_NAME.1));
    }
    let current = overrides::get_or_alternative(base, &a.path).ok_or_else(|| {
        // Why, where setting the path says (a part that names no field, with the valid ones;
        // an index past the array's end, with its length).
        let why = match overrides::set(&mut base.clone(), &a.path, Value::Integer(0)) {
            Err(e) => format!(": {e}"),
            Ok(()) => String::new(),
        };
        bad(
            file,
            field("path"),
            &a.path,
            format!("a field of the scene, e.g. ship.mass or cable.stages[1].elements{why}"),
        )
    })?;
    let integer = current.is_integer();
    // Where the values came from, for a refusal of one of them.
    let given = if a.range.is_some() { "range" } else { "values" };
    let values: Vec<Value> = match (a.values, a.range) {
        (Some(v), None) if !v.is_empty() => v,
        (Some(_), None) => return Err(bad(file, field("values"), "[]", "at least one value")),
        (None, Some(r)) => {
            if !(r.from.is_finite() && r.to.is_finite()) {
                return Err(bad(file, field("range"), format!("{}..{}", r.from, r.to), "finite from and to"));
            }
            if !(1..=100_000).contains(&r.steps) || (r.steps == 1 && r.from != r.to) {
                return Err(bad(file, field("range.steps"), r.steps, "in [1, 100000] (1 only when from = to)"));
            }
            if r.scale == Scale::Log && !(r.from > 0.0 && r.to > 0.0) {
                return Err(bad(
                    file,
                    field("range"),
                    format!("{}..{}", r.from, r.to),
                    "from and to > 0 for scale = \"log\"",
                ));
            }
            (0..r.steps)
                .map(|k| {
                    let s = if r.steps == 1 { 0.0 } else { k as f64 / (r.steps - 1) as f64 };
                    let x = match r.scale {
                        Scale::Linear => r.from + s * (r.to - r.from),
                        Scale::Log => (r.from.ln() + s * (r.to.ln() - r.from.ln())).exp(),
                    };
                    // To 12 digits of the range's larger end, its own ends exact: the
                    // arithmetic's last bits are noise that would print in tables, files and
                    // refusals (a log range from 1e4 to 8e4 computes 20000.00000000002, a
                    // linear one from -0.1 to 0.5 gives -1.4e-17 for 0).
                    let x = if k == 0 {
                        r.from
                    } else if k + 1 == r.steps {
                        r.to
                    } else {
                        let scale = r.from.abs().max(r.to.abs());
                        // In f64: a range at zero (scale 0) has log10 = -inf, 300 places.
                        let decimals = (11.0 - scale.log10().floor()).clamp(0.0, 300.0) as usize;
                        format!("{x:.decimals$}").parse::<f64>().map_or(x, |v| v + 0.0)
                    };
                    // For an integer field, a point whole up to the range's rounding is whole
                    // (a log range from 1 to 100 in 3 steps computes 10.000000000000002).
                    let whole = x.round();
                    let snapped = integer && (x - whole).abs() <= 1e-9 * whole.abs().max(1.0);
                    Value::Float(if snapped { whole } else { x })
                })
                .collect()
        }
        _ => {
            return Err(bad(file, field("values"), "", "exactly one of values = [...] or range = { from, to, steps }"))
        }
    };
    let typed = values
        .into_iter()
        .map(|v| match (&v, integer, current.is_float()) {
            (Value::Float(x), _, _) if !x.is_finite() => Err(bad(file, field(given), x, "finite numbers")),
            (Value::Float(x), true, _) if x.fract() == 0.0 && x.abs() < 9e15 => Ok(Value::Integer(*x as i64)),
            (Value::Float(x), true, _) if given == "range" => Err(bad(
                file,
                field(given),
                format!("a point {x}"),
                format!(
                    "whole points: {} is an integer field (from, to and steps with (to − from)/(steps − 1) whole)",
                    a.path
                ),
            )),
            (Value::Float(x), true, _) => {
                Err(bad(file, field("values"), x, format!("whole numbers: {} is an integer field", a.path)))
            }
            (Value::Integer(n), _, true) => Ok(Value::Float(*n as f64)),
            _ if v.same_type(current) => Ok(v),
            // The example is the field's own value, not that of an alternative it replaces.
            _ => Err(bad(
                file,
                field("values"),
                &v,
                match overrides::get(base, &a.path) {
                    Some(own) => format!("values of the field's type ({}, e.g. {own})", current.type_str()),
                    None => format!("values of the field's type ({})", current.type_str()),
                },
            )),
        })
        .collect::<Result<Vec<Value>>>()?;
    // A table, an array or a text can be malformed inside (an unknown key in a stage, a
    // method no integrator has), and a whole number below 0 or beyond 2³² does not read as a
    // count: refused now, not found as an invalid row after the others have run. A value out
    // of its range stays a row of its own. (A real always reads: a range's points need no
    // look.)
    let unread = |v: &&Value| match v {
        Value::Table(_) | Value::Array(_) | Value::String(_) => true,
        Value::Integer(n) => !(0..=i64::from(u32::MAX)).contains(n),
        _ => false,
    };
    for v in typed.iter().filter(unread) {
        let mut scene = base.clone();
        if overrides::set(&mut scene, &a.path, v.clone()).is_ok() {
            if let Err(SceneError::Parse { message, .. }) = Scene::from_value(scene, "") {
                let why = kanestop_runtime::scene::plain_types(&message).replace('\n', " ");
                return Err(bad(file, field("values"), v, why));
            }
        }
    }
    Ok(Axis { path: a.path, values: typed })
}

fn uncertain(file: &Path, base: &Value, i: usize, u: UncertainFile) -> Result<Uncertain> {
    let field = |f: &str| format!("uncertain[{i}].{f}");
    if !overrides::get_or_alternative(base, &u.path).is_some_and(Value::is_float) {
        return Err(bad(file, field("path"), &u.path, "a real-valued (float) field of the scene, e.g. ship.mass"));
    }
    let need = |name: &str, v: Option<f64>, ok: fn(f64) -> bool, expected: &str| {
        v.filter(|&x| ok(x)).ok_or_else(|| {
            bad(file, field(name), v.map(|x| x.to_string()).unwrap_or("(missing)".into()), expected.to_string())
        })
    };
    let finite = |x: f64| x.is_finite();
    let positive = |x: f64| x.is_finite() && x > 0.0;
    let given: Vec<&str> =
        [("low", u.low), ("high", u.high), ("mean", u.mean), ("sd", u.sd), ("median", u.median), ("sigma", u.sigma)]
            .into_iter()
            .filter_map(|(n, v)| v.map(|_| n))
            .collect();
    let (distribution, fields): (Distribution, [&str; 2]) = match u.distribution.as_str() {
        "uniform" => {
            let low = need("low", u.low, finite, "a finite number")?;
            let high = need("high", u.high, finite, "a finite number")?;
            if high <= low {
                return Err(bad(file, field("high"), high, format!("> low = {low}")));
            }
            (Distribution::Uniform { low, high }, ["low", "high"])
        }
        "normal" => (
            Distribution::Normal {
                mean: need("mean", u.mean, finite, "a finite number")?,
                sd: need("sd", u.sd, positive, "finite and > 0")?,
            },
            ["mean", "sd"],
        ),
        "lognormal" => (
            Distribution::Lognormal {
                median: need("median", u.median, positive, "finite and > 0")?,
                sigma: need("sigma", u.sigma, positive, "finite and > 0 (the sd of ln x)")?,
            },
            ["median", "sigma"],
        ),
        other => return Err(bad(file, field("distribution"), other, "one of uniform, normal, lognormal")),
    };
    if let Some(extra) = given.iter().find(|g| !fields.contains(g)) {
        return Err(bad(
            file,
            field(extra),
            "set",
            format!("not a parameter of {} (give {} and {})", u.distribution, fields[0], fields[1]),
        ));
    }
    Ok(Uncertain { path: u.path, distribution })
}

#[cfg(test)]
mod tests {
    use super::*;

    fn case01() -> Scene {
        Scene::from_toml(kanestop_runtime::paper::DEFAULT_SCENE, "case01.toml").unwrap()
    }

    fn field(e: Error) -> String {
        match e {
            Error::Spec { field, .. } => field,
            other => panic!("not a spec error: {other}"),
        }
    }

    #[test]
    fn a_table_or_text_with_a_given_scene_plans_as_a_file_would() {
        let text = "[[axis]]\npath = \"ship.mass\"\nvalues = [4e5, 5e5]\n";
        let spec = Spec::from_toml(text, Path::new("<string>"), Path::new(""), Some(case01())).unwrap();
        assert_eq!((spec.name.as_str(), spec.rows()), ("sweep", 2));
        let table: toml::Table = toml::from_str(text).unwrap();
        let same = Spec::from_table(table, Path::new("<dict>"), Path::new(""), Some(case01())).unwrap();
        let inputs = |s: &Spec| s.plan().into_iter().map(|r| (r.name, r.inputs)).collect::<Vec<_>>();
        assert_eq!(inputs(&spec), inputs(&same));
        assert_eq!(field(Spec::from_toml(text, Path::new("<string>"), Path::new(""), None).unwrap_err()), "base");
        let bad: toml::Table =
            toml::from_str("[sampling]\nmethod = \"random\"\nsamples = \"many\"\nseed = 1\n").unwrap();
        let e = Spec::from_table(bad, Path::new("<dict>"), Path::new(""), Some(case01())).unwrap_err();
        // The value as given is said with its field (it was left empty for a type error).
        assert!(e.to_string().contains("sampling.samples = \"many\": invalid type"), "{e}");
        assert_eq!(field(e), "sampling.samples");
    }

    #[test]
    fn a_name_that_could_reach_outside_the_folder_or_into_a_script_is_refused() {
        let spec = |name: &str| {
            let text = format!("name = {name:?}\n[[axis]]\npath = \"ship.mass\"\nvalues = [4e5]\n");
            Spec::from_toml(&text, Path::new("<string>"), Path::new(""), Some(case01()))
        };
        for fine in ["mass speed", "study-2.b_c+d", "Schiffsmasse"] {
            assert_eq!(spec(fine).unwrap().name, fine);
        }
        for bad in ["a/b", "../../escaped", "/tmp/abs", "g\ntouch x", "$(touch x)", ".hidden", "", "a\\b"] {
            let e = spec(bad).unwrap_err();
            assert!(e.to_string().contains("it names the rows' files"), "{bad:?}: {e}");
            assert_eq!(field(e), "name", "{bad:?}");
        }
        // A name from elsewhere (Python's scene name, an edited shard file) still writes in
        // its folder.
        assert_eq!(super::super::file_stem("../../x"), "_._.._x");
        assert_eq!(super::super::file_stem("a/b\nc"), "a_b_c");
        assert_eq!(super::super::file_stem(""), "_");
    }

    /// Errors of what the spec did not write itself say where they come from: a base scene
    /// the spec names, a name taken from the spec file's.
    #[test]
    fn a_base_or_a_default_name_is_named_as_the_spec_s() {
        use kanestop_runtime::scene::SceneError;
        let e = Spec::from_toml("base = \"no-such.toml\"\n", Path::new("s.toml"), Path::new("d"), None).unwrap_err();
        let text = e.to_string();
        assert!(text.starts_with("cannot read scene d/no-such.toml: "), "{text}");
        assert!(text.ends_with("\n  (the base scene of sweep spec s.toml)"), "{text}");
        // The scene's own error, its file the path as given.
        let Error::BaseScene { error, .. } = e else { panic!("{e:?}") };
        let SceneError::Io { file, .. } = *error else { panic!("{error:?}") };
        assert_eq!(file, "d/no-such.toml");
        let e = Spec::from_toml("", Path::new("short (1).toml"), Path::new(""), Some(case01())).unwrap_err();
        let text = e.to_string();
        assert!(text.contains("name = \"short (1)\" (the spec file's name: the spec has no `name`)"), "{text}");
        assert!(text.ends_with("set name = \"…\""), "{text}");
        let e = Spec::from_toml("name = \"a (1)\"\n", Path::new("s.toml"), Path::new(""), Some(case01())).unwrap_err();
        assert!(!e.to_string().contains("the spec has no"), "{e}");
    }

    /// A malformed table or text among an axis's values is the spec's error, found before any
    /// run (it was an invalid row, exit 3); a value out of range is still a row of its own.
    #[test]
    fn a_malformed_axis_value_is_refused_and_one_out_of_range_is_a_row() {
        let spec = |text: &str| Spec::from_toml(text, Path::new("<string>"), Path::new(""), Some(case01()));
        let e = spec("[[axis]]\npath = \"solver.integrator\"\nvalues = [\"rk4\", \"bogus\"]\n").unwrap_err();
        assert!(
            e.to_string().contains("axis[0].values = \"bogus\": bogus: unknown method (valid: rk4, dp5, sdirk4)"),
            "{e}"
        );
        let stages =
            "[[axis]]\npath = \"cable.stages\"\nvalues = [[{elements = 30, element_length = 5.0, bogus = 1}]]\n";
        let e = spec(stages).unwrap_err();
        assert!(e.to_string().contains("unknown field `bogus`") && !e.to_string().contains('\n'), "{e}");
        // A path past an array's end says its length.
        let e = spec("[[axis]]\npath = \"cable.stages[7].elements\"\nvalues = [3]\n").unwrap_err();
        assert!(e.to_string().contains("index 7 is out of range (the array has 3 entries)"), "{e}");
        // An invalid [set] value names the spec's base scene, not the spec as a scene.
        let e = spec("[set]\n\"ship.mass\" = -5.0\n").unwrap_err();
        assert!(
            e.to_string().contains("(the base of sweep spec <string> with its [checks], [solver] and [set])"),
            "{e}"
        );
        // A count below 0 reads as no count (it was an invalid row, as a stage's was refused).
        let e = spec("[[axis]]\npath = \"chain.elements\"\nvalues = [-1, 14]\n").unwrap_err();
        assert!(e.to_string().contains("axis[0].values = -1"), "{e}");
        let out_of_range = spec("[[axis]]\npath = \"ship.mass\"\nvalues = [5e5, -1.0]\n").unwrap();
        assert!(out_of_range.plan()[1].scene.is_err());
    }

    #[test]
    fn an_input_path_given_twice_is_refused() {
        let spec = |text: &str| Spec::from_toml(text, Path::new("<string>"), Path::new(""), Some(case01()));
        let axis = |values: &str| format!("[[axis]]\npath = \"ship.mass\"\nvalues = [{values}]\n");
        let e = spec(&format!("{}{}", axis("5e5"), axis("6e5"))).unwrap_err();
        assert_eq!(field(e), "axis[1].path");
        let uncertain = "[[uncertain]]\npath = \"ship.mass\"\ndistribution = \"normal\"\nmean = 5e5\nsd = 1e4\n\
                         [sampling]\nmethod = \"random\"\nsamples = 2\nseed = 1\n";
        let e = spec(&format!("{}{uncertain}", axis("5e5"))).unwrap_err();
        assert_eq!(field(e), "uncertain[0].path");
        // A path fixed for every row by [set] or [solver] is no input too (the input won).
        let e = spec(&format!("[set]\n\"ship.mass\" = 4e5\n{}", axis("5e5"))).unwrap_err();
        assert!(
            e.to_string()
                .contains("axis[0].path = ship.mass: a path not fixed for every row: set.\"ship.mass\" sets it too"),
            "{e}"
        );
        let end = "[[axis]]\npath = \"solver.end_time\"\nvalues = [0.2]\n";
        let e = spec(&format!("[solver]\nend_time = 0.1\n{end}")).unwrap_err();
        assert!(e.to_string().contains("solver.end_time sets it too"), "{e}");
        let e = spec("[solver]\nend_time = 0.1\n[set]\n\"solver.end_time\" = 0.2\n").unwrap_err();
        assert_eq!(field(e), "set.\"solver.end_time\"");
        // Unless the base needs the fixed value to be valid: an output interval as long as the
        // [solver] dt, the interval an axis (case 1's own 0.02 s is below dt = 0.05 s).
        let interval = "[[axis]]\npath = \"solver.output_interval\"\nvalues = [0.05, 0.5]\n";
        let ok = spec(&format!("[solver]\ndt = 0.05\noutput_interval = 0.05\n{interval}")).unwrap();
        assert_eq!(ok.rows(), 2);
        // Set on a spec for every row (Python's solver keywords), an input's path is refused,
        // unless the base needs it: a dt of 0.1 s needs an interval of 0.1 s at least.
        let e = ok.clone().with_set(&[("solver.output_interval", Value::Float(0.1))]).unwrap_err();
        assert_eq!(field(e), "solver.output_interval");
        let needed = [("solver.dt", Value::Float(0.1)), ("solver.output_interval", Value::Float(0.1))];
        assert_eq!(ok.with_set(&needed).unwrap().base.solver.dt, 0.1);
    }

    #[test]
    fn messages_name_a_field_once_and_no_rust_type() {
        let message = |text: &str| {
            Spec::from_toml(text, Path::new("s.toml"), Path::new(""), Some(case01())).unwrap_err().to_string()
        };
        // A scene given for a spec says what a sweep needs.
        let e = message("[meta]\nname = \"x\"\n[ship]\nmass = 1.0\n");
        assert!(e.contains("this is a scene file") && e.contains("rows=[…]"), "{e}");
        let e = message("[[axis]\n");
        assert!(e.starts_with("sweep spec s.toml: TOML parse error at line 1"), "{e}");
        let e = message("[set]\n\"ship.mas\" = 1.0\n");
        assert!(e.starts_with("sweep spec s.toml: ship.mas: no field `mas` here (valid: beam, "), "{e}");
        let e = message("[[uncertain]]\npath = \"ship.mass\"\ndistribution = \"normal\"\nmean = 5e5\nsd = 1e4\n[sampling]\nmethod = \"random\"\nsamples = 2.5\nseed = 1\n");
        assert!(e.contains("expected a whole number ≥ 0") && !e.contains("usize"), "{e}");
        let e = message("[[axis]]\npath = \"ship.mass\"\nvalues = [4e5]\n[[axis]]\npath = \"anchor.mass\"\nrange = { from = 1.0, to = 2.0, steps = 0 }\n");
        assert!(e.starts_with("sweep spec s.toml: axis[1].range.steps = 0: in [1, 100000]"), "{e}");
    }

    #[test]
    fn an_axis_may_run_over_a_design_check() {
        // Regression: an axis on checks.* over a base without [checks] was "not a field of the
        // scene", and with the spec's own [checks] its values were dropped for the spec's.
        let text =
            "[checks]\nsafety_factor = 1.5\n[[axis]]\npath = \"checks.max_stopping_distance\"\nvalues = [20.0, 40.0]\n";
        let spec = Spec::from_toml(text, Path::new("s.toml"), Path::new(""), Some(case01())).unwrap();
        let limits: Vec<_> = spec.plan().iter().map(|r| r.scene.as_ref().unwrap().checks.clone().unwrap()).collect();
        assert_eq!(limits[0].max_stopping_distance, Some(20.0));
        assert_eq!(limits[1].max_stopping_distance, Some(40.0));
        assert!(limits.iter().all(|c| c.safety_factor == Some(1.5)), "the spec's own checks kept");
    }

    #[test]
    fn a_range_s_points_carry_no_rounding_noise() {
        // Regression: a log range from 1e4 to 8e4 gave 20000.00000000002 in the tables,
        // sweep.csv and the refusals.
        let points = |path: &str, range: &str| -> Vec<String> {
            let text = format!("[[axis]]\npath = \"{path}\"\nrange = {{ {range} }}\n");
            let spec = Spec::from_toml(&text, Path::new("s.toml"), Path::new(""), Some(case01())).unwrap();
            spec.plan().iter().map(|r| r.inputs[0].1.to_string()).collect()
        };
        let log = points("anchor.mass", "from = 1e4, to = 8e4, steps = 4, scale = \"log\"");
        assert_eq!(log, ["10000.0", "20000.0", "40000.0", "80000.0"]);
        let linear = points("environment.seabed_friction", "from = 0.1, to = 0.5, steps = 5");
        assert_eq!(linear, ["0.1", "0.2", "0.3", "0.4", "0.5"]);
        // Through zero: 0, not -1.4e-17; the ends as given.
        let through = points("environment.current_surface_speed", "from = -0.1, to = 0.5, steps = 7");
        assert_eq!(through, ["-0.1", "0.0", "0.1", "0.2", "0.3", "0.4", "0.5"]);
        let ends = points("anchor.mass", "from = 12345.678901234567, to = 2e4, steps = 3");
        assert_eq!(ends[0], "12345.678901234567");
        let zero = points("environment.current_surface_speed", "from = 0.0, to = 0.0, steps = 3");
        assert_eq!(zero, ["0.0", "0.0", "0.0"]);
    }

    #[test]
    fn a_range_over_an_integer_field_gives_whole_numbers_up_to_its_rounding() {
        let spec = |range: &str| {
            let text = format!("[[axis]]\npath = \"chain.elements\"\nrange = {{ {range} }}\n");
            Spec::from_toml(&text, Path::new("s.toml"), Path::new(""), Some(case01()))
        };
        let elements = |range: &str| -> Vec<String> {
            spec(range).unwrap().plan().iter().map(|r| r.inputs[0].1.to_string()).collect()
        };
        // ln 1 … ln 100 in 3 steps computes 10.000000000000002 for the middle point.
        assert_eq!(elements("from = 1.0, to = 100.0, steps = 3, scale = \"log\""), ["1", "10", "100"]);
        let ten_to_twenty: Vec<String> = (10..=20).map(|n| n.to_string()).collect();
        assert_eq!(elements("from = 10.0, to = 20.0, steps = 11"), ten_to_twenty);
        // A point that is not whole is still refused, by its value, at the range that gave it.
        let e = spec("from = 10.0, to = 20.0, steps = 3, scale = \"log\"").unwrap_err().to_string();
        assert!(e.contains("axis[0].range = a point 14.1421356237:"), "{e}");
        assert!(e.contains("whole points: chain.elements is an integer field"), "{e}");
    }

    #[test]
    fn a_check_set_in_set_joins_the_spec_s_checks() {
        // Regression: the spec's [checks] replaced the base's checks after [set], so a check
        // given in [set] was dropped silently (a 27 m stop passed a 20 m limit).
        let text = "[set]\n\"checks.max_stopping_distance\" = 20.0\n[checks]\nmax_anchor_drag = 30.0\n";
        let spec = Spec::from_toml(text, Path::new("s.toml"), Path::new(""), Some(case01())).unwrap();
        let checks = spec.plan()[0].scene.as_ref().unwrap().checks.clone().unwrap();
        assert_eq!((checks.max_stopping_distance, checks.max_anchor_drag), (Some(20.0), Some(30.0)));
        // [set] over the spec's own value of the same check: [set] is applied after.
        let text = "[set]\n\"checks.max_stopping_distance\" = 20.0\n[checks]\nmax_stopping_distance = 30.0\n";
        let spec = Spec::from_toml(text, Path::new("s.toml"), Path::new(""), Some(case01())).unwrap();
        assert_eq!(spec.base.checks.as_ref().unwrap().max_stopping_distance, Some(20.0));
    }

    #[test]
    fn inputs_a_row_cannot_take_are_refused_before_any_run() {
        let message = |text: &str| {
            Spec::from_toml(text, Path::new("s.toml"), Path::new(""), Some(case01())).unwrap_err().to_string()
        };
        // A row's name replaces meta.name.
        let e = message("[[axis]]\npath = \"meta.name\"\nvalues = [\"a\", \"b\"]\n");
        assert!(e.contains("axis[0].path = meta.name: a field other than meta.name"), "{e}");
        let e = message("[set]\n\"meta.name\" = \"a\"\n");
        assert!(e.contains("set.\"meta.name\" = \"a\": a field other than meta.name"), "{e}");
        // Not finite: refused with the spec, not row by row.
        for v in ["nan", "inf", "-inf"] {
            let e = message(&format!("[[axis]]\npath = \"ship.mass\"\nvalues = [4e5, {v}]\n"));
            assert!(e.contains("axis[0].values =") && e.ends_with("finite numbers"), "{e}");
        }
        // Two ways to lay the line in [set]: the refusal shows the value given.
        let e = message("[set]\n\"initial.horizontal_tension\" = 150.0\n\"initial.horizontal_projection\" = 148.0\n");
        assert!(
            e.contains("set.\"initial.horizontal_tension\" = 150.0: not set with initial.horizontal_projection"),
            "{e}"
        );
        assert!(!e.contains("\" = initial."), "{e}");
    }

    #[test]
    fn a_spec_s_table_over_its_base_gives_the_spec_back() {
        let text = "name = \"all\"\n[solver]\nend_time = 1.0\n[[axis]]\npath = \"chain.elements\"\nvalues = [10, 12]\n\
                    [[axis]]\npath = \"ship.mass\"\nrange = { from = 4e5, to = 6e5, steps = 3, scale = \"log\" }\n\
                    [sampling]\nmethod = \"latin-hypercube\"\nsamples = 4\nseed = 7\n\
                    [[uncertain]]\npath = \"anchor.mass\"\ndistribution = \"uniform\"\nlow = 3e4\nhigh = 5e4\n\
                    [[uncertain]]\npath = \"initial.ship_speed\"\ndistribution = \"normal\"\nmean = 3.0\nsd = 0.1\n\
                    [[uncertain]]\npath = \"environment.seabed_friction\"\ndistribution = \"lognormal\"\nmedian = 0.3\nsigma = 0.2\n\
                    [checks]\nmax_stopping_distance = 40.0\nsafety_factor = 1.5\n";
        let spec = Spec::from_toml(text, Path::new("all.toml"), Path::new(""), Some(case01())).unwrap();
        let back =
            Spec::from_table(spec.to_table(), Path::new("all.toml"), Path::new(""), Some(spec.base.clone())).unwrap();
        assert_eq!(back, spec);
        assert_eq!(back.plan().len(), 24);
    }

    #[test]
    fn explicit_rows_are_named_and_built_as_planned_rows() {
        let spec = Spec::of_scene(case01(), "case01").with_set(&[("solver.end_time", Value::Float(1.0))]).unwrap();
        let rows = spec.plan_inputs([
            vec![("ship.mass".to_string(), Value::Float(4e5))],
            vec![("ship.nope".to_string(), Value::Float(1.0))],
        ]);
        assert_eq!(rows[0].name, "case01-000");
        let scene = rows[0].scene.as_ref().unwrap();
        assert_eq!((scene.ship.mass, scene.solver.end_time, scene.meta.name.as_str()), (4e5, 1.0, "case01-000"));
        assert!(rows[1].scene.as_ref().unwrap_err().contains("nope"));
    }
}

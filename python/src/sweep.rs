//! Sweeps from Python on the command line's machinery (`kanestop_workflow::sweep`): a spec
//! read by `Spec::load` / `from_toml` / `from_table`, planned by `Spec::plan` (or
//! `Spec::plan_inputs` for explicit rows), each row run by `sweep::run_row_cancellable`, and the rows
//! handed back as the cells of `sweep.csv` (`sweep::cells`) or the objects of `sweep.json`.
//!
//! The rows run on a rayon pool of their own while the calling thread waits with the GIL
//! released, waking only to call the progress callback and to check for Ctrl-C (which stops
//! the rows running at their next step or within their start-up analysis).

use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::mpsc;
use std::time::Duration;

use kanestop_workflow::kernels;
use kanestop_workflow::sweep::{self, Cell, PlannedRow, Spec, SweepRow};
use pyo3::exceptions::{PyTypeError, PyValueError};
use pyo3::prelude::*;
use pyo3::types::{PyDict, PyList};
use toml::Value;

use crate::errors::{scene_error, workflow_error};
use crate::{convert, kernel_choice, override_list, PyScene, SolverArgs};

/// A checked sweep spec (docs/sweeps.md): the base scene, grid axes, uncertain inputs and
/// design checks. Immutable.
#[pyclass(module = "kanestop._kanestop", name = "Spec", frozen)]
pub struct PySpec {
    inner: Spec,
}

#[pymethods]
impl PySpec {
    /// Reads and checks a spec file (`kanestop sweep SPEC.toml`); its `base` is relative to
    /// it. Raises SpecError (a field of the spec) or SceneError (the base scene).
    #[staticmethod]
    fn load(py: Python<'_>, path: PathBuf) -> PyResult<Self> {
        let inner = py.allow_threads(|| Spec::load(&path)).map_err(|e| workflow_error(py, e))?;
        Ok(PySpec { inner })
    }

    /// A spec from TOML text (a spec file's content); `base` is relative to `base_dir`
    /// (default: the current directory), or `base` is the given `Scene`.
    #[staticmethod]
    #[pyo3(signature = (text, *, base_dir = None, base = None))]
    fn from_toml(py: Python<'_>, text: &str, base_dir: Option<PathBuf>, base: Option<&PyScene>) -> PyResult<Self> {
        let dir = base_dir.unwrap_or_default();
        let scene = base.map(|s| s.inner.clone());
        let inner = Spec::from_toml(text, Path::new("<string>"), &dir, scene).map_err(|e| workflow_error(py, e))?;
        Ok(PySpec { inner })
    }

    /// A spec from a dict of the spec file's fields (`{"base": ..., "axis": [{"path": ...,
    /// "values": [...]}], "checks": {...}}`); `base` is a path relative to `base_dir`
    /// (default: the current directory) or a `Scene`.
    #[staticmethod]
    #[pyo3(signature = (d, *, base_dir = None))]
    fn from_dict(py: Python<'_>, d: &Bound<'_, PyAny>, base_dir: Option<PathBuf>) -> PyResult<Self> {
        let d = d.downcast::<PyDict>().map_err(|_| {
            PyTypeError::new_err(format!(
                "Spec.from_dict takes a dict of the spec's fields, not {}",
                convert::a_type_name(d)
            ))
        })?;
        let d = d.copy()?;
        let mut scene = None;
        if let Some(base) = d.get_item("base")? {
            if let Ok(s) = base.downcast::<PyScene>() {
                scene = Some(s.get().inner.clone());
                d.del_item("base")?;
            } else if base.is_instance_of::<PyDict>() {
                // A dict of the scene's tables, as `Scene.from_dict` takes (it was refused as
                // no file name, its whole text in the message).
                let value = convert::to_toml(&base, "")?;
                let named = "<the spec's base dict>";
                let s = kanestop_runtime::scene::Scene::from_value(value, named).map_err(|e| scene_error(py, e))?;
                scene = Some(s);
                d.del_item("base")?;
            }
        }
        let Value::Table(table) = convert::to_toml(d.as_any(), "")? else { unreachable!("a dict converts to a table") };
        let dir = base_dir.unwrap_or_default();
        let inner = Spec::from_table(table, Path::new("<dict>"), &dir, scene).map_err(|e| workflow_error(py, e))?;
        Ok(PySpec { inner })
    }

    /// The spec of one scene (no axis, no sampling): the rows are given to `sweep`.
    #[staticmethod]
    #[pyo3(signature = (scene, name = None))]
    fn from_scene(scene: &PyScene, name: Option<&str>) -> Self {
        let name = name.unwrap_or(&scene.inner.meta.name);
        PySpec { inner: Spec::of_scene(scene.inner.clone(), name) }
    }

    /// The sweep's name: rows are `name-000`, ….
    #[getter]
    fn name(&self) -> String {
        self.inner.name.clone()
    }

    /// The base scene with the spec's `[solver]` and `[set]` applied.
    #[getter]
    fn base(&self) -> PyScene {
        PyScene { inner: self.inner.base.clone() }
    }

    /// The spec file (or `<string>`, `<dict>`, `<scene name>`).
    #[getter]
    fn file(&self) -> String {
        self.inner.file.display().to_string()
    }

    /// Every row's inputs in spec order, as dicts of dotted path to value.
    fn inputs(&self, py: Python<'_>) -> PyResult<Vec<PyObject>> {
        self.inner.plan().iter().map(|row| inputs_dict(py, &row.inputs)).collect()
    }

    /// The number of rows (the grid's size times the samples).
    fn __len__(&self) -> usize {
        self.inner.rows()
    }

    fn __repr__(&self) -> String {
        let rows = self.inner.rows();
        let word = if rows == 1 { "row" } else { "rows" };
        format!("Spec({:?}, {rows} {word}, base {:?})", self.inner.name, self.inner.base.meta.name)
    }

    /// Pickles as its own fields (`Spec::to_table`) and its base scene's TOML, checked again
    /// when read back: a spec travels to worker processes as a scene does.
    fn __reduce__(&self, py: Python<'_>) -> PyResult<(PyObject, (String, String, String, String))> {
        let f = py.import("kanestop._kanestop")?.getattr("_spec_from_parts")?.unbind();
        let fields = toml::to_string(&self.inner.to_table()).map_err(|e| PyValueError::new_err(e.to_string()))?;
        let base = &self.inner.base;
        Ok((f, (fields, base.to_toml(), base.meta.name.clone(), self.inner.file.display().to_string())))
    }

    fn __eq__(&self, other: &Bound<'_, PyAny>) -> bool {
        other.downcast::<PySpec>().is_ok_and(|o| o.get().inner == self.inner)
    }

    /// Equal specs hash alike: by name, row count and base scene's name (`==` decides).
    fn __hash__(&self) -> u64 {
        use std::hash::{Hash, Hasher};
        let mut h = std::collections::hash_map::DefaultHasher::new();
        (&self.inner.name, self.inner.rows(), &self.inner.base.meta.name).hash(&mut h);
        h.finish()
    }
}

/// Unpickles a spec (`Spec.__reduce__`): its fields over its base scene, named by its file.
#[pyfunction]
pub fn _spec_from_parts(py: Python<'_>, fields: &str, base: &str, base_name: &str, file: &str) -> PyResult<PySpec> {
    let scene = PyScene::from_toml(py, base, base_name, None)?.inner;
    let mut table: toml::Table = fields.parse().map_err(|e: toml::de::Error| PyValueError::new_err(e.to_string()))?;
    // The name as it was: `Spec.from_scene` takes a scene's name unchecked, which a spec
    // file's `name` could not be.
    let name = table.remove("name").and_then(|n| n.as_str().map(String::from)).unwrap_or_default();
    let mut inner =
        Spec::from_table(table, Path::new(file), Path::new(""), Some(scene)).map_err(|e| workflow_error(py, e))?;
    inner.name = name;
    Ok(PySpec { inner })
}

fn inputs_dict(py: Python<'_>, inputs: &[(String, Value)]) -> PyResult<PyObject> {
    let d = PyDict::new(py);
    for (k, v) in inputs {
        d.set_item(k, convert::to_py(py, v)?)?;
    }
    Ok(d.into_any().unbind())
}

fn cell(py: Python<'_>, c: &Cell) -> PyResult<PyObject> {
    Ok(match c {
        Cell::Empty => py.None(),
        Cell::Number(x) => x.into_pyobject(py)?.into_any().unbind(),
        Cell::Count(n) => n.into_pyobject(py)?.into_any().unbind(),
        // An empty message is an empty CSV field: None, as the docs say.
        Cell::Text(s) if s.is_empty() => py.None(),
        Cell::Text(s) => s.into_pyobject(py)?.into_any().unbind(),
        Cell::Input(v) => convert::to_py(py, v)?,
    })
}

/// Runs a spec: every planned row (or one row per dict of `rows`, for a spec without axes
/// and sampling), on `jobs` threads (every core when None), with the solver keywords set
/// on the base scene as `[solver]` would; `progress(done, total)` is called as rows finish.
/// Returns `(columns, rows of cells, units)`, `sweep.csv`'s table with each column's unit
/// (`sweep.units.csv`'s), or with `records` the `sweep.json` text.
#[pyfunction]
#[pyo3(signature = (spec, rows=None, *, jobs=None, progress=None, integrator=None, dt=None, rtol=None, atol=None, end_time=None, output_interval=None, kernel="generated", records=false))]
#[allow(clippy::too_many_arguments)]
pub fn _sweep(
    py: Python<'_>,
    spec: &PySpec,
    rows: Option<&Bound<'_, PyAny>>,
    jobs: Option<usize>,
    progress: Option<PyObject>,
    integrator: Option<String>,
    dt: Option<f64>,
    rtol: Option<f64>,
    atol: Option<f64>,
    end_time: Option<f64>,
    output_interval: Option<f64>,
    kernel: &str,
    records: bool,
) -> PyResult<PyObject> {
    let choice = kernel_choice(kernel)?;
    check_jobs(jobs)?;
    check_progress(py, progress.as_ref())?;
    let solver = SolverArgs { integrator, dt, rtol, atol, end_time, output_interval }.on(py, &spec.inner.base)?;
    let values: Vec<(&str, Value)> = solver.iter().map(|(k, v)| (k.as_str(), v.clone())).collect();
    let spec = spec.inner.clone().with_set(&values).map_err(|e| workflow_error(py, e))?;
    let plan = match rows {
        None => spec.plan(),
        Some(rows) => {
            if !spec.axes.is_empty() || spec.sampling.is_some() {
                return Err(PyValueError::new_err(format!(
                    "rows are given, but the spec {} has axes or sampling: give one or the other",
                    spec.file.display()
                )));
            }
            let rows = row_list(py, rows)?;
            let base = spec.base.to_value();
            for (i, row) in rows.iter().enumerate() {
                // A path that names no field of the scene is found before any run, as an
                // axis's is (its rows came back invalid after the others had run).
                let mut value = base.clone();
                for (path, v) in row {
                    kanestop_runtime::overrides::set(&mut value, path, v.clone())
                        .map_err(|e| PyValueError::new_err(format!("row {i}: {e}")))?;
                }
                // A row's value on a path a keyword sets would silently override the keyword.
                if let Some((path, v)) = row.iter().find(|(p, _)| solver.iter().any(|(k, _)| k == p)) {
                    let keyword = path.trim_start_matches("solver.");
                    return Err(PyValueError::new_err(format!(
                        "row {i}: {path} = {v}: the keyword {keyword}= sets it for every row too: set it in one place"
                    )));
                }
            }
            spec.plan_inputs(rows)
        }
    };
    match run_rows(py, &plan, choice, jobs, progress.as_ref()) {
        Ok(done) => output(py, &done, records),
        Err((e, Some(finished))) => {
            // The rows that had finished ride on the exception, in the form a return would
            // have had; the package's `sweep` makes them its `partial` attribute.
            let value = e.value(py);
            value.setattr("_kanestop_partial", output(py, &finished, records)?)?;
            value.setattr("_kanestop_counts", (finished.len(), plan.len()))?;
            Err(e)
        }
        Err((e, None)) => Err(e),
    }
}

/// The rows `done` as `_sweep` returns them: `sweep.json`'s text with `records`, else
/// `(columns, rows of cells, units)`.
fn output(py: Python<'_>, done: &[SweepRow], records: bool) -> PyResult<PyObject> {
    if records {
        let json = serde_json::to_string(done).map_err(|e| PyValueError::new_err(e.to_string()))?;
        return Ok(json.into_pyobject(py)?.into_any().unbind());
    }
    let (head, body) = sweep::cells(done);
    let table = PyList::empty(py);
    for row in &body {
        let cells: Vec<PyObject> = row.iter().map(|c| cell(py, c)).collect::<PyResult<_>>()?;
        table.append(PyList::new(py, cells)?)?;
    }
    let units: Vec<&str> = sweep::column_units(done).into_iter().map(|(_, unit, _)| unit).collect();
    Ok((head, table, units).into_pyobject(py)?.into_any().unbind())
}

/// The rows' overrides, each a dict of dotted path to value; the row's index in errors.
fn row_list(py: Python<'_>, rows: &Bound<'_, PyAny>) -> PyResult<Vec<Vec<(String, Value)>>> {
    let mut out = Vec::new();
    for (i, row) in rows.try_iter()?.enumerate() {
        let values = override_list(&row?).map_err(|e| {
            let msg = format!("row {i}: {}", e.value(py));
            if e.is_instance_of::<PyTypeError>(py) {
                PyTypeError::new_err(msg)
            } else {
                PyValueError::new_err(msg)
            }
        })?;
        out.push(values);
    }
    Ok(out)
}

/// Runs every row with `sweep::run_row_cancellable` on a pool of `jobs` threads, in plan order; the
/// calling thread waits with the GIL released and calls `progress`. An exception in
/// `progress` (or Ctrl-C) cancels the rows not started, stops those running at their next
/// step, and is returned with the rows that had finished, in plan order (none for an error
/// of the pool itself, a panic, after which the rows done are not known).
fn run_rows(
    py: Python<'_>,
    plan: &[PlannedRow],
    choice: kernels::KernelChoice,
    jobs: Option<usize>,
    progress: Option<&PyObject>,
) -> Result<Vec<SweepRow>, (PyErr, Option<Vec<SweepRow>>)> {
    let total = plan.len();
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(jobs.unwrap_or(0))
        .build()
        .map_err(|e| (PyValueError::new_err(e.to_string()), None))?;
    let kernel = kernels::factory(choice);
    let cancel = AtomicBool::new(false);
    let (tx, rx) = mpsc::channel::<()>();
    // Receiver is Send but not Sync: the waiting loop borrows it through a mutex.
    let rx = std::sync::Mutex::new(rx);
    let run_row = |row: &PlannedRow, tx: &mpsc::Sender<()>| -> Option<SweepRow> {
        if cancel.load(Ordering::Relaxed) {
            return None;
        }
        let out = sweep::run_row_cancellable(row, &kernel, &cancel);
        let _ = tx.send(());
        out
    };
    let (outcomes, error) = std::thread::scope(|s| {
        // The worker owns the sender: the channel disconnects when every row is done (or a
        // row panicked), which ends the loop below.
        let worker = s.spawn(move || pool.install(|| kanestop_workflow::parallel::map(plan, |r| run_row(r, &tx))));
        let mut done = 0;
        let mut error: Option<PyErr> = None;
        loop {
            let got = py.allow_threads(|| {
                rx.lock().expect("only this thread locks it").recv_timeout(Duration::from_millis(50))
            });
            match got {
                Ok(()) => {
                    done += 1;
                    if let (Some(p), None) = (progress, &error) {
                        if let Err(e) = p.call1(py, (done, total)) {
                            cancel.store(true, Ordering::Relaxed);
                            error = Some(e);
                        }
                    }
                }
                Err(mpsc::RecvTimeoutError::Timeout) => {}
                Err(mpsc::RecvTimeoutError::Disconnected) => break,
            }
            if error.is_none() {
                if let Err(e) = py.check_signals() {
                    cancel.store(true, Ordering::Relaxed);
                    error = Some(e);
                }
            }
        }
        let outcomes = py.allow_threads(|| worker.join());
        (outcomes, error)
    });
    let outcomes = outcomes.map_err(|_| (PyValueError::new_err("a sweep worker panicked"), None))?;
    match error {
        Some(e) => Err((e, Some(outcomes.into_iter().flatten().collect()))),
        None => outcomes
            .into_iter()
            .map(|o| o.ok_or_else(|| (PyValueError::new_err("a sweep row was cancelled"), None)))
            .collect(),
    }
}

/// A progress callback that can be called as `progress(done, total)`, or none; else a TypeError.
pub(crate) fn check_progress(py: Python<'_>, progress: Option<&PyObject>) -> PyResult<()> {
    match progress {
        Some(p) if !p.bind(py).is_callable() => {
            Err(PyTypeError::new_err("progress must be callable as progress(done, total)"))
        }
        _ => Ok(()),
    }
}

/// `jobs` in [1, MAX_JOBS], or None (every core); else a ValueError naming it as Python does.
pub(crate) fn check_jobs(jobs: Option<usize>) -> PyResult<()> {
    match jobs.filter(|n| !(1..=kanestop_workflow::parallel::MAX_JOBS).contains(n)) {
        Some(n) => {
            let max = kanestop_workflow::parallel::MAX_JOBS;
            Err(PyValueError::new_err(format!("jobs = {n}: must be in [1, {max}] (or None for every core)")))
        }
        None => Ok(()),
    }
}

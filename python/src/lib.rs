//! The `kanestop._kanestop` extension module: the Rust core behind the `kanestop` Python
//! package (python/kanestop/__init__.py wraps it; docs/python.md documents it).
//!
//! Runs release the GIL; sweeps (`sweep.rs`) run the command line's sweep machinery on a
//! rayon thread pool while the calling thread waits with the GIL released, waking only to
//! call the progress callback. The channels of a run are the CSV history's
//! (`kanestop_workflow::history`), by the same names, with their units.

use std::ffi::CString;
use std::path::PathBuf;
use std::sync::atomic::{AtomicBool, AtomicUsize, Ordering};
use std::sync::mpsc;
use std::time::Duration;

use kanestop_runtime::eval::{evaluate, StateFile};
use kanestop_runtime::kernel::AnchorDof;
use kanestop_runtime::model::Model;
use kanestop_runtime::scene::{Scene, SceneError as RustSceneError};
use kanestop_runtime::simulate::{self, Stop};
use kanestop_workflow::history;
use kanestop_workflow::kernels::KernelChoice;
use kanestop_workflow::record::RunSummary;
use numpy::{PyArray1, PyArrayMethods};
use pyo3::exceptions::{PyTypeError, PyUserWarning, PyValueError};
use pyo3::prelude::*;
use pyo3::types::{PyDict, PyList, PyTuple};
use toml::Value;

mod convert;
mod errors;
mod sweep;

use errors::{scene_error, workflow_error, EvalError, ModelError, SceneError, SpecError};

/// A checked scene: every field present, finite and in range. Immutable: `with_overrides`
/// returns a new scene.
#[pyclass(module = "kanestop._kanestop", name = "Scene", frozen)]
#[derive(Clone)]
pub struct PyScene {
    pub(crate) inner: Scene,
}

#[pymethods]
impl PyScene {
    /// Reads and checks a scene file (with `extends` resolved). Raises SceneError.
    #[staticmethod]
    fn load(py: Python<'_>, path: PathBuf) -> PyResult<Self> {
        let inner = py.allow_threads(|| Scene::load(&path)).map_err(|e| scene_error(py, e))?;
        Ok(PyScene { inner })
    }

    /// Case `number` of the paper's Table 2 (1–19), built in: equal to
    /// `scenes/paper/caseNN.toml`, with no file needed. Raises ValueError outside 1–19.
    #[staticmethod]
    fn paper(number: &Bound<'_, PyAny>) -> PyResult<Self> {
        let cases = &kanestop_runtime::paper::CASES;
        let valid = || format!("in 1–{} (the cases of the paper's Table 2)", cases.len());
        if number.is_instance_of::<pyo3::types::PyBool>() {
            return Err(PyTypeError::new_err(format!("Scene.paper: number must be an int {}, not a bool", valid())));
        }
        if number.is_instance_of::<pyo3::types::PyInt>() && number.extract::<i64>().is_err() {
            return Err(PyValueError::new_err(format!("Scene.paper: number = {number}: {}", valid())));
        }
        let n: i64 = number.extract().map_err(|_| {
            PyTypeError::new_err(format!(
                "Scene.paper: number must be an int {}, not {}",
                valid(),
                convert::a_type_name(number)
            ))
        })?;
        let case = usize::try_from(n).ok().and_then(|n| n.checked_sub(1)).and_then(|i| cases.get(i));
        match case {
            Some(case) => Ok(PyScene { inner: case.scene() }),
            None => Err(PyValueError::new_err(format!("Scene.paper: number = {n}: {}", valid()))),
        }
    }

    /// A scene from a dict of its tables (as `to_dict` gives). Raises SceneError.
    #[staticmethod]
    #[pyo3(signature = (d, name = "<dict>"))]
    fn from_dict(py: Python<'_>, d: &Bound<'_, PyAny>, name: &str) -> PyResult<Self> {
        if !d.is_instance_of::<PyDict>() {
            return Err(PyTypeError::new_err(format!(
                "Scene.from_dict takes a dict of the scene's tables, not {}",
                convert::a_type_name(d)
            )));
        }
        let value = convert::to_toml(d, "")?;
        let inner = Scene::from_value(value, name).map_err(|e| scene_error(py, e))?;
        Ok(PyScene { inner })
    }

    /// A scene from TOML text; an `extends` is resolved from `base_dir` (default the current
    /// directory), as `load` resolves it from the file's folder. Raises SceneError.
    #[staticmethod]
    #[pyo3(signature = (text, name = "<string>", base_dir = None))]
    pub(crate) fn from_toml(py: Python<'_>, text: &str, name: &str, base_dir: Option<PathBuf>) -> PyResult<Self> {
        // Without base_dir the text is named `name` itself, as before.
        let at = base_dir.unwrap_or_default().join(name);
        let inner = py.allow_threads(|| Scene::from_toml_at(text, &at)).map_err(|e| scene_error(py, e))?;
        Ok(PyScene { inner })
    }

    /// The same scene with each dotted path set (`{"ship.mass": 1e6,
    /// "cable.stages[1].elements": 20}`), checked as a whole file would be.
    fn with_overrides(&self, py: Python<'_>, overrides: &Bound<'_, PyAny>) -> PyResult<Self> {
        let values = override_list(overrides)?;
        let refs: Vec<(&str, Value)> = values.iter().map(|(k, v)| (k.as_str(), v.clone())).collect();
        let inner = self.inner.with_overrides(&refs).map_err(|e| scene_error(py, e))?;
        Ok(PyScene { inner })
    }

    /// The scene's tables as a dict (every field present); `Scene.from_dict` reads it back.
    fn to_dict(&self, py: Python<'_>) -> PyResult<PyObject> {
        convert::to_py(py, &self.inner.to_value())
    }

    /// The scene as TOML text; `Scene.from_toml` reads it back.
    fn to_toml(&self) -> String {
        self.inner.to_toml()
    }

    /// `meta.name`.
    #[getter]
    fn name(&self) -> String {
        self.inner.meta.name.clone()
    }

    fn __reduce__(&self, py: Python<'_>) -> PyResult<(PyObject, (String, String))> {
        let f = py.import("kanestop._kanestop")?.getattr("_scene_from_toml")?.unbind();
        Ok((f, (self.inner.to_toml(), self.inner.meta.name.clone())))
    }

    fn __eq__(&self, other: &Bound<'_, PyAny>) -> bool {
        other.downcast::<PyScene>().is_ok_and(|o| o.get().inner == self.inner)
    }

    /// Equal scenes hash alike (a scene is a dict key, a set member): every field's value,
    /// a zero's sign dropped as `==` drops it.
    fn __hash__(&self) -> u64 {
        use std::hash::{Hash, Hasher};
        fn feed(v: &Value, h: &mut std::collections::hash_map::DefaultHasher) {
            match v {
                Value::Float(x) => (x + 0.0).to_bits().hash(h),
                Value::Table(t) => t.iter().for_each(|(k, v)| {
                    k.hash(h);
                    feed(v, h);
                }),
                Value::Array(a) => a.iter().for_each(|v| feed(v, h)),
                other => other.to_string().hash(h),
            }
        }
        let mut h = std::collections::hash_map::DefaultHasher::new();
        feed(&self.inner.to_value(), &mut h);
        h.finish()
    }

    /// The name and the values a study most often changes, so that two scenes of one name
    /// (a scene and its overrides) read apart: `Scene("case01": 46 bodies, ship 500 t at
    /// 3 m/s, anchor 40 t, chain 15 × 1 m)`.
    fn __repr__(&self) -> String {
        let s = &self.inner;
        format!(
            "Scene({:?}: {} bodies, ship {} t at {} m/s, anchor {} t, chain {} × {} m)",
            s.meta.name,
            s.body_count(),
            s.ship.mass / 1e3,
            s.initial.ship_speed,
            s.anchor.mass / 1e3,
            s.chain.elements,
            s.chain.element_length
        )
    }
}

/// Unpickles a scene (`Scene.__reduce__`).
#[pyfunction]
fn _scene_from_toml(py: Python<'_>, text: &str, name: &str) -> PyResult<PyScene> {
    PyScene::from_toml(py, text, name, None)
}

/// The top-level keys of a TOML file, or None when it cannot be read or parsed: tells a
/// sweep spec (`base`, `axis`) from a scene file for `sweep(path, rows)`'s message.
#[pyfunction]
fn _toml_keys(path: PathBuf) -> Option<Vec<String>> {
    let text = kanestop_runtime::scene::read_text_file(&path, kanestop_runtime::scene::MAX_SCENE_BYTES, "").ok()?;
    let table: toml::Table = text.parse().ok()?;
    Some(table.keys().cloned().collect())
}

/// (dotted path, value) pairs of a dict of overrides.
fn override_list(overrides: &Bound<'_, PyAny>) -> PyResult<Vec<(String, Value)>> {
    let d = overrides.downcast::<PyDict>().map_err(|_| {
        PyTypeError::new_err(format!(
            "overrides must be a dict of dotted paths to values ({{\"ship.mass\": 1e6}}), not {}",
            convert::a_type_name(overrides)
        ))
    })?;
    let mut out = Vec::with_capacity(d.len());
    for (k, v) in d.iter() {
        let path: String = k.extract().map_err(|_| {
            PyTypeError::new_err(format!("override keys must be dotted paths (str), not {}", convert::a_type_name(&k)))
        })?;
        let value = convert::to_toml(&v, &path)?;
        out.push((path, value));
    }
    Ok(out)
}

/// The `[solver]` keywords of `run` and `sweep`.
#[derive(Clone, Default)]
struct SolverArgs {
    integrator: Option<String>,
    dt: Option<f64>,
    rtol: Option<f64>,
    atol: Option<f64>,
    end_time: Option<f64>,
    output_interval: Option<f64>,
}

impl SolverArgs {
    /// The keywords' values set on `scene` for every run, a `dt` without `output_interval`
    /// raising the scene's shorter interval to it as the command line's `--dt` does
    /// ([`kanestop_runtime::overrides::raise_output_interval`]), with a UserWarning saying so.
    fn on(&self, py: Python<'_>, scene: &Scene) -> PyResult<Vec<(String, Value)>> {
        let mut out = self.overrides();
        if let (Some(dt), None) = (self.dt, self.output_interval) {
            if let Some(interval) = kanestop_runtime::overrides::raise_output_interval(&mut scene.to_value(), dt) {
                out.push(("solver.output_interval".into(), Value::Float(dt)));
                warn(
                    py,
                    &format!(
                        "solver.output_interval raised from the scene's {} s to the step, {dt} s (the output grid holds at least one step; output_interval= sets it)",
                        kanestop_workflow::output::CsvNumber(interval)
                    ),
                )?;
            }
        }
        Ok(out)
    }

    fn overrides(&self) -> Vec<(String, Value)> {
        let mut out = Vec::new();
        if let Some(m) = &self.integrator {
            out.push(("solver.integrator".to_string(), Value::String(m.clone())));
        }
        let floats = [
            ("solver.dt", self.dt),
            ("solver.rtol", self.rtol),
            ("solver.atol", self.atol),
            ("solver.end_time", self.end_time),
            ("solver.output_interval", self.output_interval),
        ];
        out.extend(floats.into_iter().filter_map(|(k, v)| v.map(|v| (k.to_string(), Value::Float(v)))));
        out
    }
}

/// `scene` with `values` set (the same scene when there are none).
fn apply(scene: &Scene, values: &[(String, Value)]) -> Result<Scene, RustSceneError> {
    if values.is_empty() {
        return Ok(scene.clone());
    }
    let refs: Vec<(&str, Value)> = values.iter().map(|(k, v)| (k.as_str(), v.clone())).collect();
    scene.with_overrides(&refs)
}

fn kernel_choice(name: &str) -> PyResult<KernelChoice> {
    name.parse().map_err(PyValueError::new_err)
}

fn model_error(e: impl std::fmt::Display) -> PyErr {
    ModelError::new_err(e.to_string())
}

fn warn(py: Python<'_>, note: &str) -> PyResult<()> {
    let message = CString::new(note.replace('\0', " ")).expect("no NUL left");
    PyErr::warn(py, &py.get_type::<PyUserWarning>(), &message, 2)
}

/// A run's time history, kept in Rust until Python asks for it: `kanestop.Result` turns it
/// into NumPy arrays on first use of its channels (a run whose channels are never read, as
/// in most sweeps and design checks, does not pay for them).
#[pyclass(module = "kanestop._kanestop", name = "_History", frozen)]
pub struct PyHistory {
    result: simulate::RunResult,
    /// The model's body count N: the channels exist (empty) for a run with no samples.
    bodies: usize,
}

#[pymethods]
impl PyHistory {
    /// (channels as a dict of NumPy arrays, channel info as (name, unit, group,
    /// description)): the CSV history's columns, by the same names.
    fn columns<'py>(&self, py: Python<'py>) -> PyResult<(Bound<'py, PyDict>, Bound<'py, PyList>)> {
        let arrays = PyDict::new(py);
        let info = PyList::empty(py);
        let channels = history::all_channels(self.bodies);
        for (c, values) in channels.iter().zip(history::columns(&self.result, &channels)) {
            arrays.set_item(&c.name, PyArray1::from_vec(py, values))?;
            info.append((c.name.as_str(), c.unit, c.group, c.description.as_str()))?;
        }
        Ok((arrays, info))
    }
}

/// Runs a scene: (summary JSON, history, events, failure, core time in s). The Python
/// `kanestop.run` wraps it into a `Result`. The core time is the wall time from the call's
/// start to its summary (the overrides, the model, the run, the summary): what the Rust
/// core did for the call.
#[pyfunction]
#[pyo3(signature = (scene, *, integrator=None, dt=None, rtol=None, atol=None, end_time=None, output_interval=None, kernel="generated"))]
#[allow(clippy::too_many_arguments)]
fn _run(
    py: Python<'_>,
    scene: &PyScene,
    integrator: Option<String>,
    dt: Option<f64>,
    rtol: Option<f64>,
    atol: Option<f64>,
    end_time: Option<f64>,
    output_interval: Option<f64>,
    kernel: &str,
) -> PyResult<PyObject> {
    let start = std::time::Instant::now();
    let choice = kernel_choice(kernel)?;
    let solver = SolverArgs { integrator, dt, rtol, atol, end_time, output_interval };
    let scene = apply(&scene.inner, &solver.on(py, &scene.inner)?).map_err(|e| scene_error(py, e))?;
    let model = Model::new(&scene).map_err(model_error)?;
    let (result, summary, note) = interruptible(py, |cancel| {
        let (k, note) = choice.build(&model);
        // As the command line's `run`: the starting state checked, for the same diagnosis.
        let result = simulate::run_checked_cancellable(&model, k, choice.build(&model).0, cancel).ok()?;
        let summary = RunSummary::of(&model, &result);
        Some((result, summary, note))
    })?;
    if let Some(note) = note {
        warn(py, &note)?;
    }
    let json = serde_json::to_string(&summary).map_err(|e| PyValueError::new_err(e.to_string()))?;
    let core_time = start.elapsed().as_secs_f64();
    let events = PyList::empty(py);
    for e in &result.anchor_events {
        let d = PyDict::new(py);
        d.set_item("t", e.t)?;
        d.set_item("anchor", anchor_name(e.now))?;
        events.append(d)?;
    }
    let failure: PyObject = match &result.stop {
        Stop::Failed(f) => {
            let d = PyDict::new(py);
            d.set_item("t", f.t)?;
            d.set_item("body", f.body)?;
            d.set_item("kind", f.kind.to_string())?;
            d.into_any().unbind()
        }
        _ => py.None(),
    };
    Ok(PyTuple::new(
        py,
        [
            json.into_pyobject(py)?.into_any(),
            Bound::new(py, PyHistory { result, bodies: model.body_count() })?.into_any(),
            events.into_any(),
            failure.into_bound(py),
            core_time.into_pyobject(py)?.into_any(),
        ],
    )?
    .into_any()
    .unbind())
}

/// Runs `work` on its own thread while this one waits with the GIL released, waking every
/// 50 ms to check for Ctrl-C: a signal sets the flag `work` polls (a run stops at its next
/// step, or within its start-up stability analysis), waits for it to return, and raises the signal's exception (KeyboardInterrupt).
/// `work` returns None only when cancelled.
fn interruptible<T: Send>(py: Python<'_>, work: impl FnOnce(&AtomicBool) -> Option<T> + Send) -> PyResult<T> {
    interruptible_polling(py, work, |_| Ok(()))
}

/// [`interruptible`], calling `poll` on this thread at each wake and once before returning
/// (a progress callback); an error from it cancels `work` as Ctrl-C does and is returned.
fn interruptible_polling<T: Send>(
    py: Python<'_>,
    work: impl FnOnce(&AtomicBool) -> Option<T> + Send,
    mut poll: impl FnMut(Python<'_>) -> PyResult<()>,
) -> PyResult<T> {
    let cancel = AtomicBool::new(false);
    std::thread::scope(|s| {
        let (tx, rx) = mpsc::channel();
        // Receiver is Send but not Sync: the waiting loop borrows it through a mutex.
        let rx = std::sync::Mutex::new(rx);
        let cancel = &cancel;
        let worker = s.spawn(move || {
            let _ = tx.send(work(cancel));
        });
        loop {
            let got = py.allow_threads(|| {
                rx.lock().expect("only this thread locks it").recv_timeout(Duration::from_millis(50))
            });
            match got {
                Ok(Some(out)) => return poll(py).map(|()| out),
                Ok(None) => return Err(PyValueError::new_err("the run was cancelled")),
                Err(mpsc::RecvTimeoutError::Disconnected) => {
                    let panic = py.allow_threads(|| worker.join()).err();
                    let what = panic
                        .as_deref()
                        .and_then(|p| {
                            p.downcast_ref::<&str>()
                                .map(|s| s.to_string())
                                .or_else(|| p.downcast_ref::<String>().cloned())
                        })
                        .unwrap_or_default();
                    return Err(PyValueError::new_err(format!("the run's thread panicked ({what}): please report it")));
                }
                Err(mpsc::RecvTimeoutError::Timeout) => {
                    if let Err(e) = py.check_signals().and_then(|()| poll(py)) {
                        cancel.store(true, Ordering::Relaxed);
                        let _ = py.allow_threads(|| worker.join());
                        return Err(e);
                    }
                }
            }
        }
    })
}

/// The sensitivity study of `kanestop report sensitivity` (central differences of the
/// stopping time, distance and peak tension in each continuous parameter's logarithm,
/// docs/sweeps.md) as its `sensitivity.json` record in JSON text. The runs release the GIL;
/// `progress(done, total)` is called on this thread as runs finish; Ctrl-C, or an exception
/// raised in `progress`, stops them at their next step and is raised. A bad step or job
/// count, or a base scene that fails, is a ValueError (the latter with the command line's
/// message).
#[pyfunction]
#[pyo3(signature = (scene, step=0.05, jobs=None, *, progress=None, integrator=None, dt=None, rtol=None, atol=None, end_time=None, output_interval=None))]
#[allow(clippy::too_many_arguments)]
fn _sensitivity(
    py: Python<'_>,
    scene: &PyScene,
    step: f64,
    jobs: Option<usize>,
    progress: Option<PyObject>,
    integrator: Option<String>,
    dt: Option<f64>,
    rtol: Option<f64>,
    atol: Option<f64>,
    end_time: Option<f64>,
    output_interval: Option<f64>,
) -> PyResult<String> {
    use kanestop_workflow::{kernels, sensitivity};
    // Named as Python names them (the command line's say --step and --jobs).
    if let Err(kanestop_workflow::Error::Argument { expected, .. }) = sensitivity::check_step(step) {
        return Err(PyValueError::new_err(format!("step = {step}: must be {expected}")));
    }
    sweep::check_jobs(jobs)?;
    // The solver keywords on the base scene, as `run`'s: every perturbed run takes them.
    let solver = SolverArgs { integrator, dt, rtol, atol, end_time, output_interval };
    let scene = apply(&scene.inner, &solver.on(py, &scene.inner)?).map_err(|e| scene_error(py, e))?;
    sweep::check_progress(py, progress.as_ref())?;
    // The runs finished and, once the worker has built the perturbed scenes, how many in all
    // (0 until then: no progress is told before it is known).
    let (finished, total) = (AtomicUsize::new(0), AtomicUsize::new(0));
    let mut told = 0;
    let poll = |py: Python<'_>| -> PyResult<()> {
        let (done, total) = (finished.load(Ordering::Relaxed), total.load(Ordering::Relaxed));
        match &progress {
            Some(p) if done > told && total > 0 => {
                told = done;
                p.call1(py, (done, total)).map(drop)
            }
            _ => Ok(()),
        }
    };
    let (finished, total) = (&finished, &total);
    let study = interruptible_polling(
        py,
        move |cancel| {
            let probes = sensitivity::probes(&scene, step);
            total.store(sensitivity::run_count(&probes), Ordering::Relaxed);
            let kernel = kernels::factory(kernels::KernelChoice::Generated);
            let done = || {
                finished.fetch_add(1, Ordering::Relaxed);
            };
            sensitivity::study_cancellable(&scene, step, &probes, &kernel, jobs, &done, cancel)
        },
        poll,
    )?
    .map_err(|e| workflow_error(py, e))?;
    serde_json::to_string(&study).map_err(|e| PyValueError::new_err(e.to_string()))
}

/// The unit of each column of `sensitivity.csv` (`sensitivity.units.csv`'s), by name.
#[pyfunction]
fn _sensitivity_units() -> Vec<(&'static str, &'static str)> {
    kanestop_workflow::sensitivity::COLUMNS.iter().map(|&(name, unit, _)| (name, unit)).collect()
}

fn anchor_name(a: AnchorDof) -> &'static str {
    match a {
        AnchorDof::Free => "free",
        AnchorDof::Stuck => "stuck",
    }
}

/// The equations of motion at the scene's initial state or at (q, u): the `eval` JSON as a
/// dict, with `M`, `f`, `qdd`, `q` and `u` as NumPy arrays.
#[pyfunction]
#[pyo3(signature = (scene, q=None, u=None, *, anchor=None, kernel="generated"))]
fn eval(
    py: Python<'_>,
    scene: &PyScene,
    q: Option<Vec<f64>>,
    u: Option<Vec<f64>>,
    anchor: Option<&str>,
    kernel: &str,
) -> PyResult<PyObject> {
    let choice = kernel_choice(kernel)?;
    let anchor = match anchor {
        None => None,
        Some("stuck") => Some(AnchorDof::Stuck),
        Some("free") => Some(AnchorDof::Free),
        Some(other) => return Err(PyValueError::new_err(format!("anchor = {other:?}: must be \"stuck\" or \"free\""))),
    };
    let state = match (q, u) {
        (Some(q), Some(u)) => Some(StateFile { q, u, anchor }),
        (None, None) if anchor.is_none() => None,
        (None, None) => return Err(PyValueError::new_err("anchor is given without a state: pass q and u too")),
        _ => return Err(PyValueError::new_err("give both q and u (N entries each), or neither")),
    };
    let model = Model::new(&scene.inner).map_err(model_error)?;
    let out = py
        .allow_threads(|| {
            let (k, _) = choice.build(&model);
            evaluate(&model, k, state.as_ref())
        })
        .map_err(|e| EvalError::new_err(e.to_string()))?;
    let json = serde_json::to_string(&out).map_err(|e| PyValueError::new_err(e.to_string()))?;
    let d = py.import("json")?.call_method1("loads", (json,))?;
    let n = out.active;
    let flat: Vec<f64> = out.mass_matrix.iter().flatten().copied().collect();
    d.set_item("M", PyArray1::from_vec(py, flat).reshape([n, n])?)?;
    d.set_item("f", PyArray1::from_vec(py, out.f))?;
    d.set_item("qdd", PyArray1::from_vec(py, out.qdd))?;
    d.set_item("q", PyArray1::from_vec(py, out.q))?;
    d.set_item("u", PyArray1::from_vec(py, out.u))?;
    Ok(d.unbind())
}

/// The extension module.
#[pymodule]
fn _kanestop(m: &Bound<'_, PyModule>) -> PyResult<()> {
    let py = m.py();
    m.add_class::<PyScene>()?;
    m.add_class::<PyHistory>()?;
    m.add_function(wrap_pyfunction!(_scene_from_toml, m)?)?;
    m.add_function(wrap_pyfunction!(_sensitivity, m)?)?;
    m.add_function(wrap_pyfunction!(_sensitivity_units, m)?)?;
    m.add_function(wrap_pyfunction!(_toml_keys, m)?)?;
    m.add_function(wrap_pyfunction!(sweep::_spec_from_parts, m)?)?;
    m.add_function(wrap_pyfunction!(_run, m)?)?;
    m.add_function(wrap_pyfunction!(eval, m)?)?;
    m.add_class::<sweep::PySpec>()?;
    m.add_function(wrap_pyfunction!(sweep::_sweep, m)?)?;
    m.add("SceneError", py.get_type::<SceneError>())?;
    m.add("SpecError", py.get_type::<SpecError>())?;
    m.add("ModelError", py.get_type::<ModelError>())?;
    m.add("EvalError", py.get_type::<EvalError>())?;
    m.add("__version__", env!("CARGO_PKG_VERSION"))?;
    m.add("MAX_JOBS", kanestop_workflow::parallel::MAX_JOBS)?;
    Ok(())
}

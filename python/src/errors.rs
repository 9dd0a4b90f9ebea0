//! The exceptions: `SceneError` (with `problems`, `file`, `kind`), `SpecError` (with `field`,
//! `value`, `expected`, `file`), `ModelError`, `EvalError`.

use kanestop_runtime::scene::SceneError as RustSceneError;
use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;
use pyo3::types::PyTuple;

pyo3::create_exception!(
    kanestop,
    SceneError,
    PyValueError,
    "A scene that could not be read or is not valid.\n\n`problems` is a list of (field, value, expected) for out-of-range values \
     (empty for a file that cannot be read or parsed), `file` names the scene and `kind` is `io`, `parse`, `invalid` \
     or `override`; `str(e)` is the command line's message."
);
pyo3::create_exception!(
    kanestop,
    ModelError,
    PyValueError,
    "A valid scene whose model cannot be built (e.g. no initial catenary exists)."
);
pyo3::create_exception!(
    kanestop,
    EvalError,
    PyValueError,
    "A state that `kanestop.eval` cannot evaluate (wrong length, not finite, refused by the kernel)."
);

/// The Python `SceneError` of a Rust one.
pub fn scene_error(py: Python<'_>, e: RustSceneError) -> PyErr {
    let message = e.to_string();
    scene_error_said(py, e, message)
}

/// [`scene_error`] whose `str(e)` is `message` (the command line's, with its context).
fn scene_error_said(py: Python<'_>, e: RustSceneError, message: String) -> PyErr {
    let (kind, file, problems) = match &e {
        RustSceneError::Io { file, .. } => ("io", file.clone(), Vec::new()),
        RustSceneError::Parse { file, .. } => ("parse", file.clone(), Vec::new()),
        RustSceneError::Invalid { file, problems } => ("invalid", file.clone(), problems.clone()),
        RustSceneError::Override { file, .. } => ("override", file.clone(), Vec::new()),
    };
    let err = SceneError::new_err(message);
    let value = err.value(py);
    let set = || -> PyResult<()> {
        let list: Vec<Bound<'_, PyTuple>> = problems
            .iter()
            .map(|p| PyTuple::new(py, [p.field.as_str(), p.value.as_str(), p.expected.as_str()]))
            .collect::<PyResult<_>>()?;
        value.setattr("problems", list)?;
        value.setattr("file", file)?;
        value.setattr("kind", kind)?;
        Ok(())
    };
    match set() {
        Ok(()) => err,
        Err(other) => other,
    }
}

pyo3::create_exception!(
    kanestop,
    SpecError,
    PyValueError,
    "A sweep spec that could not be read or is not valid (docs/sweeps.md).\n\n`field` names the spec's field \
     (`axis[0].range.steps`, `uncertain[1].sd`, `checks.safety_factor`; in a dict the key with its \
     position, e.g. `sampling.samples`, `axis[1].range.steps`, or an unknown key itself, `axes`; \
     `(file)` when a file's TOML does not parse or has an unknown key, `(spec)` when a dict is no \
     spec at all), `value` is its value as given, \
     `expected` the valid range, `file` the spec; `str(e)` is the command line's message."
);

/// The Python exception of a workflow error: `SpecError` for a spec's field (and a spec file
/// that cannot be read), `SceneError` for its base scene or a row's solver keywords.
pub fn workflow_error(py: Python<'_>, e: kanestop_workflow::Error) -> PyErr {
    use kanestop_workflow::Error;
    let (file, field, value, expected) = match &e {
        Error::Spec { file, field, value, expected } => {
            (file.display().to_string(), field.clone(), value.clone(), expected.clone())
        }
        Error::Io { path, cause, .. } => {
            (path.display().to_string(), "(file)".to_string(), path.display().to_string(), cause.to_string())
        }
        _ => {
            let message = e.to_string();
            return match e {
                Error::Scene(s) => scene_error(py, s),
                // The scene's error, `file` its path; `str(e)` says the spec too, as the CLI.
                Error::BaseScene { error, .. } => scene_error_said(py, *error, message),
                _ => PyValueError::new_err(message),
            };
        }
    };
    let err = SpecError::new_err(e.to_string());
    let v = err.value(py);
    let set = || -> PyResult<()> {
        v.setattr("file", file)?;
        v.setattr("field", field)?;
        v.setattr("value", value)?;
        v.setattr("expected", expected)?;
        Ok(())
    };
    match set() {
        Ok(()) => err,
        Err(other) => other,
    }
}

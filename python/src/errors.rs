//! The exceptions: `SceneError` (with `problems`, `file`, `kind`), `ModelError`, `EvalError`.

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
    let (kind, file, problems) = match &e {
        RustSceneError::Io { file, .. } => ("io", file.clone(), Vec::new()),
        RustSceneError::Parse { file, .. } => ("parse", file.clone(), Vec::new()),
        RustSceneError::Invalid { file, problems } => ("invalid", file.clone(), problems.clone()),
        RustSceneError::Override { file, .. } => ("override", file.clone(), Vec::new()),
    };
    let err = SceneError::new_err(e.to_string());
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

//! Python values ↔ TOML values (a scene's tables), with the field path in every error.

use pyo3::exceptions::{PyTypeError, PyValueError};
use pyo3::prelude::*;
use pyo3::types::{PyBool, PyDict, PyFloat, PyInt, PyList, PyString, PyTuple};
use toml::Value;

/// `obj` as a TOML value; `path` names it in errors (`ship.mass`).
pub fn to_toml(obj: &Bound<'_, PyAny>, path: &str) -> PyResult<Value> {
    let at = |p: &str| if p.is_empty() { "the scene".to_string() } else { p.to_string() };
    if obj.is_none() {
        return Err(PyTypeError::new_err(format!(
            "{}: None is not a scene value (give a number, a string, a bool, a list or a dict)",
            at(path)
        )));
    }
    if let Ok(b) = obj.downcast::<PyBool>() {
        return Ok(Value::Boolean(b.is_true()));
    }
    if obj.is_instance_of::<PyInt>() {
        // An integer beyond 64 bits as the real it is, for the scene's range check to refuse
        // by name (ship.mass = 1e30: must be in (0, 1e15] kg).
        return match (obj.extract::<i64>(), obj.extract::<f64>()) {
            (Ok(i), _) => Ok(Value::Integer(i)),
            (Err(_), Ok(x)) => Ok(Value::Float(x)),
            (Err(_), Err(_)) => Err(PyValueError::new_err(format!("{}: integer {obj} is beyond any real", at(path)))),
        };
    }
    if obj.is_instance_of::<PyFloat>() {
        return Ok(Value::Float(obj.extract::<f64>()?));
    }
    if let Ok(s) = obj.downcast::<PyString>() {
        return Ok(Value::String(s.extract::<String>()?));
    }
    // A path (pathlib.Path, any os.PathLike) where a string goes: a spec's base, extends.
    if obj.hasattr("__fspath__")? {
        let text = obj.py().import("os")?.call_method1("fspath", (obj,))?;
        if let Ok(s) = text.downcast::<PyString>() {
            return Ok(Value::String(s.extract::<String>()?));
        }
    }
    if let Ok(d) = obj.downcast::<PyDict>() {
        let mut table = toml::Table::new();
        for (k, v) in d.iter() {
            let key: String = k.extract().map_err(|_| {
                PyTypeError::new_err(format!("{}: keys must be strings, not {}", at(path), a_type_name(&k)))
            })?;
            let sub = if path.is_empty() { key.clone() } else { format!("{path}.{key}") };
            table.insert(key, to_toml(&v, &sub)?);
        }
        return Ok(Value::Table(table));
    }
    // NumPy arrays (`np.linspace(…)`) as the lists they hold, NumPy bools as bools (they
    // also convert to floats, below).
    if obj.hasattr("dtype")? {
        let ndim = obj.getattr("ndim").ok().and_then(|n| n.extract::<usize>().ok());
        if ndim.is_some_and(|n| n > 0) && obj.hasattr("tolist")? {
            return to_toml(&obj.call_method0("tolist")?, path);
        }
        let kind = obj.getattr("dtype").and_then(|d| d.getattr("kind")).ok().and_then(|k| k.extract::<String>().ok());
        if kind.as_deref() == Some("b") {
            return Ok(Value::Boolean(obj.is_truthy()?));
        }
    }
    let is_range = obj.get_type().name().is_ok_and(|n| n == "range");
    if obj.is_instance_of::<PyList>() || obj.is_instance_of::<PyTuple>() || is_range {
        let mut items = Vec::new();
        for (i, v) in obj.try_iter()?.enumerate() {
            items.push(to_toml(&v?, &format!("{path}[{i}]"))?);
        }
        return Ok(Value::Array(items));
    }
    // NumPy scalars and other numbers: integers through __index__, reals through __float__.
    if obj.hasattr("__index__")? {
        if let Ok(i) = obj.extract::<i64>() {
            return Ok(Value::Integer(i));
        }
    }
    if obj.hasattr("__float__")? {
        if let Ok(x) = obj.extract::<f64>() {
            return Ok(Value::Float(x));
        }
    }
    Err(PyTypeError::new_err(format!(
        "{}: {} is not a scene value (give a number, a string, a bool, a list or a dict)",
        at(path),
        a_type_name(obj)
    )))
}

/// A TOML value as plain Python objects (dict, list, float, int, str, bool).
pub fn to_py(py: Python<'_>, value: &Value) -> PyResult<PyObject> {
    Ok(match value {
        Value::String(s) => s.into_pyobject(py)?.into_any().unbind(),
        Value::Integer(i) => i.into_pyobject(py)?.into_any().unbind(),
        Value::Float(x) => x.into_pyobject(py)?.into_any().unbind(),
        Value::Boolean(b) => b.into_pyobject(py)?.to_owned().into_any().unbind(),
        Value::Datetime(d) => d.to_string().into_pyobject(py)?.into_any().unbind(),
        Value::Array(items) => {
            let list = PyList::empty(py);
            for v in items {
                list.append(to_py(py, v)?)?;
            }
            list.into_any().unbind()
        }
        Value::Table(t) => {
            let d = PyDict::new(py);
            for (k, v) in t {
                d.set_item(k, to_py(py, v)?)?;
            }
            d.into_any().unbind()
        }
    })
}

/// The type's name, for messages.
pub fn type_name(obj: &Bound<'_, PyAny>) -> String {
    obj.get_type().name().map(|n| n.to_string()).unwrap_or_else(|_| "value".into())
}

/// The type's name with its article: "a float", "an ellipsis".
pub fn a_type_name(obj: &Bound<'_, PyAny>) -> String {
    let name = type_name(obj);
    let article = if name.starts_with(['a', 'e', 'i', 'o', 'u']) { "an" } else { "a" };
    format!("{article} {name}")
}

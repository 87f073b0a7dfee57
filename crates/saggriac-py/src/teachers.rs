//! Teachers as data: the core's `Teacher` (one variant per teacher, serde-derived) to and from
//! Python dicts of parameters, by name. No teacher and no parameter is named here: the names,
//! types and defaults are read from the core's defaults, and the rules are the core's.

use pyo3::prelude::*;
use pyo3::types::{PyBool, PyDict, PyFloat, PyInt, PyString};
use pythonize::{depythonize, pythonize};
use saggriac_core::config::teachers::Teacher;
use saggriac_core::error::invalid;

use crate::errors::to_py;

/// The teacher's parameters as one flat dict, in order (the fields of a nested parameter
/// struct, such as SAGG-RIAC's tree and modes, in its place).
pub fn params<'py>(py: Python<'py>, t: &Teacher) -> PyResult<Bound<'py, PyDict>> {
    let out = PyDict::new(py);
    for (k, v) in nested(py, t)?.iter() {
        match v.cast::<PyDict>() {
            Ok(inner) => inner.iter().try_for_each(|(k, v)| out.set_item(k, v))?,
            Err(_) => out.set_item(k, v)?,
        }
    }
    Ok(out)
}

/// The teacher's parameters as serde gives them (nested structs as dicts).
fn nested<'py>(py: Python<'py>, t: &Teacher) -> PyResult<Bound<'py, PyDict>> {
    let outer = pythonize(py, t).map_err(PyErr::from)?;
    Ok(outer.cast_into::<PyDict>()?.get_item(t.kind())?.ok_or_else(|| pyo3::exceptions::PyRuntimeError::new_err("a teacher without parameters"))?.cast_into::<PyDict>()?)
}

/// The rule a value must follow to stand where `default` stands, if it does not.
fn wrong_type(value: &Bound<'_, PyAny>, default: &Bound<'_, PyAny>) -> Option<&'static str> {
    let is_bool = value.is_instance_of::<PyBool>();
    if default.is_instance_of::<PyBool>() {
        (!is_bool).then_some("a bool")
    } else if default.is_instance_of::<PyInt>() {
        (is_bool || !value.is_instance_of::<PyInt>() || value.extract::<u64>().is_err()).then_some("an int >= 0")
    } else if default.is_instance_of::<PyFloat>() {
        (is_bool || !(value.is_instance_of::<PyFloat>() || value.is_instance_of::<PyInt>())).then_some("a float")
    } else {
        (!value.is_instance_of::<PyString>()).then_some("a str")
    }
}

/// The teacher `kind` with the parameters `given` names, the others at their defaults. Messages
/// are `owner`'s: `what` for the dict itself, `prefix` + the name for a parameter. Only the
/// types are checked here; `Teacher::validate` checks the rules.
pub fn teacher(py: Python<'_>, default: Teacher, given: Option<&Bound<'_, PyDict>>, owner: &'static str, what: &str, prefix: &str) -> PyResult<Teacher> {
    let kind = default.kind();
    let Some(given) = given.filter(|g| !g.is_empty()) else { return Ok(default) };
    let flat = params(py, &default)?;
    let nested = nested(py, &default)?;
    for (k, v) in given.iter() {
        let key: String = k.extract().map_err(|_| to_py(py, invalid(owner, what, "a dict with str keys", "a key that is not a str")))?;
        let Some(d) = flat.get_item(&key)? else {
            let names: Vec<String> = flat.keys().iter().map(|k| k.to_string()).collect();
            let rule = format!("a dict of the '{kind}' teacher's parameters (those of saggriac.{}: {})", default.class(), names.join(", "));
            return Err(to_py(py, invalid(owner, what, rule, format!("a dict with key '{key}'"))));
        };
        let shown = || v.repr().map(|r| r.to_string()).unwrap_or_else(|_| "?".into());
        if let Some(rule) = wrong_type(&v, &d) {
            return Err(to_py(py, invalid(owner, &format!("{prefix}{key}"), rule, shown())));
        }
        // Where serde expects it: at the top, or in the nested struct holding it.
        let mut placed = false;
        for (_, inner) in nested.iter() {
            if let Ok(inner) = inner.cast::<PyDict>() {
                if inner.contains(&key)? {
                    inner.set_item(&key, &v)?;
                    placed = true;
                }
            }
        }
        if !placed {
            nested.set_item(&key, &v)?;
        }
        // A value of the right type serde still refuses (a str naming no choice) is named here.
        let one = PyDict::new(py);
        one.set_item(kind, &nested)?;
        if let Err(e) = depythonize::<Teacher>(&one) {
            let e = e.to_string().replace('`', "'");
            let rule = e.split_once("expected ").map(|(_, choices)| format!("one of {}", choices.replace(" or ", ", "))).unwrap_or(e);
            return Err(to_py(py, invalid(owner, &format!("{prefix}{key}"), rule, shown())));
        }
    }
    let outer = PyDict::new(py);
    outer.set_item(kind, nested)?;
    depythonize::<Teacher>(&outer).map_err(|e| to_py(py, saggriac_core::Error::InvalidInput(format!("{e}"))))
}

/// Every teacher's default parameters, by name (`_core.teacher_defaults()`).
pub fn defaults(py: Python<'_>) -> PyResult<Bound<'_, PyDict>> {
    let out = PyDict::new(py);
    for t in Teacher::all() {
        out.set_item(t.kind(), params(py, &t)?)?;
    }
    Ok(out)
}

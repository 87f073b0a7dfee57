//! Teachers as data, the one file of the binding about teachers: the core's `Teacher` (one
//! variant per teacher, serde-derived) to and from Python dicts of parameters, by name. No
//! teacher and no parameter is named here: the names, types and defaults are read from the
//! core's defaults, and the rules are the core's.

use pyo3::prelude::*;
use pyo3::types::{PyBool, PyDict, PyFloat, PyInt, PyList, PyString, PyTuple};
use pythonize::{depythonize, pythonize};
use saggriac_core::config::teachers::{PerDimension, Rule, Shape, Teacher};
use saggriac_core::error::invalid;
use saggriac_core::high_level::teachers::TeacherSpec;
use saggriac_core::Error;

use crate::errors::{to_py, wrap};

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

/// Whether `value` has the type of `default` (an int for an int, a number for a float, a bool
/// for a bool, a str for a choice): the one type check of a teacher's parameters.
pub fn right_type(value: &Bound<'_, PyAny>, default: &Bound<'_, PyAny>) -> bool {
    let is_bool = value.is_instance_of::<PyBool>();
    if default.is_instance_of::<PyBool>() {
        is_bool
    } else if default.is_instance_of::<PyInt>() {
        !is_bool && value.is_instance_of::<PyInt>() && value.extract::<u64>().is_ok()
    } else if default.is_instance_of::<PyFloat>() {
        !is_bool && (value.is_instance_of::<PyFloat>() || value.is_instance_of::<PyInt>())
    } else {
        value.is_instance_of::<PyString>()
    }
}

/// The type `default`'s value stands for, as a rule states it, if `value` is not of it (a run's
/// parameters, whose range the core's `validate` then tells).
pub fn wrong_type(value: &Bound<'_, PyAny>, default: &Bound<'_, PyAny>) -> Option<&'static str> {
    (!right_type(value, default)).then(|| {
        if default.is_instance_of::<PyBool>() {
            "a bool"
        } else if default.is_instance_of::<PyInt>() {
            "an int >= 0"
        } else if default.is_instance_of::<PyFloat>() {
            "a float"
        } else {
            "a str"
        }
    })
}

/// The rule of the parameter `key` of `teacher` as a message states it (a choice's from serde,
/// which names the choices), None for a name the teacher has not.
pub fn rule_text(py: Python<'_>, teacher: &Teacher, key: &str) -> PyResult<Option<String>> {
    Ok(match teacher.rule(key) {
        None => None,
        Some(Rule::Choice) => {
            // A name no choice has: serde's refusal lists the choices.
            let nested = nested(py, teacher)?;
            place(&nested, key, &PyString::new(py, "\u{1}").into_any())?;
            let one = PyDict::new(py);
            one.set_item(teacher.kind(), &nested)?;
            Some(depythonize::<Teacher>(&one).err().map(|e| serde_rule(&e.to_string())).unwrap_or_else(|| Rule::Choice.text()))
        }
        Some(rule) => Some(rule.text()),
    })
}

/// Put `value` under `key` where serde expects it: at the top, or in the nested struct holding it.
fn place(nested: &Bound<'_, PyDict>, key: &str, value: &Bound<'_, PyAny>) -> PyResult<()> {
    for (_, inner) in nested.iter() {
        if let Ok(inner) = inner.cast::<PyDict>() {
            if inner.contains(key)? {
                return inner.set_item(key, value);
            }
        }
    }
    nested.set_item(key, value)
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
        let shown = || v.repr().map(|r| r.to_string()).unwrap_or_else(|_| "?".into());
        let Some(d) = flat.get_item(&key)? else {
            if default.per_dimension().iter().any(|(n, _)| *n == key) {
                // A matrix (a covariance) has no single-number form a run could take.
                let rule = format!("given to the teacher's class, such as saggriac.{}({key}=...), not to a run, which takes single numbers", default.class());
                return Err(to_py(py, invalid(owner, &format!("{prefix}{key}"), rule, shown())));
            }
            let names: Vec<String> = flat.keys().iter().map(|k| k.to_string()).collect();
            let rule = format!("a dict of the '{kind}' teacher's parameters (those of saggriac.{}: {})", default.class(), names.join(", "));
            return Err(to_py(py, invalid(owner, what, rule, format!("a dict with key '{key}'"))));
        };
        if !right_type(&v, &d) {
            // The parameter's rule, the text a value out of range is told. A list reaches here
            // only by a route that takes single numbers (a run's): the class takes it.
            let rule = rule_text(py, &default, &key)?.unwrap_or_default();
            let mut got = shown();
            if is_list(&v) && default.per_dimension().iter().any(|(n, _)| *n == key) {
                got = format!("{got} (a value per dimension is taken by the teacher's class, such as saggriac.{}({key}=[...]), not by a run)", default.class());
            }
            return Err(to_py(py, invalid(owner, &format!("{prefix}{key}"), rule, got)));
        }
        place(&nested, &key, &v)?;
        // A value of the right type serde still refuses (a str naming no choice) is named here.
        let one = PyDict::new(py);
        one.set_item(kind, &nested)?;
        if let Err(e) = depythonize::<Teacher>(&one) {
            return Err(to_py(py, invalid(owner, &format!("{prefix}{key}"), serde_rule(&e.to_string()), shown())));
        }
    }
    let outer = PyDict::new(py);
    outer.set_item(kind, nested)?;
    depythonize::<Teacher>(&outer).map_err(|e| to_py(py, Error::InvalidInput(format!("{e}"))))
}

/// Every teacher's parameters taken per dimension, by name: "vector" or "matrix"
/// (`_core.teacher_per_dimension()`).
pub fn per_dimension_names(py: Python<'_>) -> PyResult<Bound<'_, PyDict>> {
    let out = PyDict::new(py);
    for t in Teacher::all() {
        let names = PyDict::new(py);
        for (name, shape) in t.per_dimension() {
            names.set_item(name, if *shape == Shape::Vector { "vector" } else { "matrix" })?;
        }
        out.set_item(t.kind(), names)?;
    }
    Ok(out)
}

/// A list or a tuple (a value per dimension, or a matrix's rows), not a str.
fn is_list(v: &Bound<'_, PyAny>) -> bool {
    v.is_instance_of::<PyList>() || v.is_instance_of::<PyTuple>()
}

/// The numbers of the list `v`, each of a float's type (`right_type`, the one type check), None
/// if `v` is no list of them.
fn floats(v: &Bound<'_, PyAny>) -> Option<Vec<f64>> {
    let float = PyFloat::new(v.py(), 0.0).into_any();
    if !is_list(v) {
        return None;
    }
    v.try_iter().ok()?.map(|x| x.ok().filter(|x| right_type(x, &float)).and_then(|x| x.extract::<f64>().ok())).collect()
}

/// The parameters of `given` that `default`'s teacher takes per dimension and that are given so,
/// apart: a list of numbers for a vector (a number stays in the dict returned, for `teacher`),
/// `d` rows of `d` numbers for a matrix (None: not given). Each value's type is a single
/// number's (`right_type`); a list of anything else is told the parameter's rule as a list
/// states it. The lengths and each value's rule are the core's (`PerDimension::check`).
pub fn split_per_dimension<'py>(py: Python<'py>, default: &Teacher, given: Option<&Bound<'py, PyDict>>, d: usize) -> PyResult<(Option<Bound<'py, PyDict>>, PerDimension)> {
    let Some(given) = given else { return Ok((None, PerDimension::default())) };
    let (rest, mut dims) = (PyDict::new(py), PerDimension::default());
    let owner = default.class();
    for (k, v) in given.iter() {
        let shape = k.extract::<String>().ok().and_then(|key| default.per_dimension().iter().find(|(n, _)| *n == key).copied());
        let shown = || v.repr().map(|r| r.to_string()).unwrap_or_else(|_| "?".into());
        let values = match shape {
            Some((name, Shape::Vector)) if is_list(&v) => {
                let rule = default.rule(name).unwrap_or(Rule::Finite).per_dimension_text();
                (name, floats(&v).ok_or_else(|| to_py(py, invalid(owner, name, rule, shown())))?)
            }
            Some((name, Shape::Matrix)) if !v.is_none() => {
                let rows: Option<Vec<Vec<f64>>> = if is_list(&v) { v.try_iter()?.map(|r| r.ok().and_then(|r| floats(&r)).filter(|r| r.len() == d)).collect() } else { None };
                let rows = rows.filter(|r| r.len() == d).ok_or_else(|| to_py(py, invalid(owner, name, PerDimension::matrix_rule(d), shown())))?;
                (name, rows.concat())
            }
            Some((_, Shape::Matrix)) => continue,
            _ => {
                rest.set_item(k, v)?;
                continue;
            }
        };
        dims.0.push((values.0.to_string(), values.1));
    }
    Ok((Some(rest), dims))
}

/// A teacher's parameters as it was built: `params`, a value given per dimension in place of
/// its number (a list; a matrix as its rows).
pub fn spec_params<'py>(py: Python<'py>, spec: &TeacherSpec) -> PyResult<Bound<'py, PyDict>> {
    let out = params(py, &spec.teacher)?;
    let d = spec.low.len().max(1);
    for (name, values) in &spec.dims.0 {
        match spec.teacher.per_dimension().iter().find(|(n, _)| n == name) {
            Some((_, Shape::Matrix)) => out.set_item(name, values.chunks(d).map(<[f64]>::to_vec).collect::<Vec<_>>())?,
            _ => out.set_item(name, values.clone())?,
        }
    }
    Ok(out)
}

/// Every teacher's default parameters, by name (`_core.teacher_defaults()`).
pub fn defaults(py: Python<'_>) -> PyResult<Bound<'_, PyDict>> {
    let out = PyDict::new(py);
    for t in Teacher::all() {
        out.set_item(t.kind(), params(py, &t)?)?;
    }
    Ok(out)
}

/// The rule in serde's words for a value it refused ("unknown variant `w`, expected `zeta` or
/// `window`" -> "one of 'zeta', 'window'").
pub fn serde_rule(e: &str) -> String {
    let e = e.replace('`', "'");
    match e.split_once("expected ").map(|(_, x)| x) {
        Some("u64" | "usize" | "u32") => "an int >= 0".into(),
        Some("f64") => "a float".into(),
        Some("a boolean") => "a bool".into(),
        Some(choices) => format!("one of {}", choices.trim_start_matches("one of ").replace(" or ", ", ")),
        // Python's own words when a value does not convert at all.
        None if e.contains("as an integer") => "an int >= 0".into(),
        None if e.contains("real number") => "a float".into(),
        None => e,
    }
}

/// The teacher of `Config`'s `teacher` and `teacher_params` (None: "own").
/// `min_c` is the run's: the papers' thresholds are for competences in [0, 1], a run's lie in
/// [min_c, 0], and the defaults move there (`Teacher::scaled_to_competences`).
pub fn of_config(d: &Bound<'_, PyDict>, min_c: f64) -> PyResult<Option<Teacher>> {
    let py = d.py();
    let kind: String = match d.get_item("teacher")?.filter(|t| !t.is_none()) {
        Some(t) => t.extract().map_err(|_| to_py(py, invalid("Config", "teacher", "a str", t.repr().map(|r| r.to_string()).unwrap_or_default())))?,
        None => "own".into(),
    };
    let given = match d.get_item("teacher_params")?.filter(|p| !p.is_none()) {
        Some(p) => Some(p.cast_into::<PyDict>().map_err(|_| to_py(py, invalid("Config", "teacher_params", "a dict of the teacher's parameters", "not a dict")))?),
        None => None,
    };
    Ok(match kind.as_str() {
        "own" => match given.filter(|p| !p.is_empty()) {
            None => None,
            Some(p) => {
                let own: Vec<String> = params(py, &Teacher::SaggRiac(Default::default()))?.keys().iter().map(|k| k.to_string()).collect();
                let rule = format!("empty with teacher 'own' (SAGG-RIAC's own high level is set by {})", own.join(", "));
                let key = p.keys().get_item(0).map(|k| k.to_string()).unwrap_or_default();
                return Err(to_py(py, invalid("Config", "teacher_params", rule, format!("a dict with key '{key}'"))));
            }
        },
        kind => {
            let default = Teacher::parse("Config", "teacher", kind).map_err(|e| match e {
                Error::InvalidParameter { owner, param, rule, value } => Error::InvalidParameter { owner, param, rule: rule.replacen("one of ", "one of 'own', ", 1), value },
                other => other,
            });
            let default = wrap(py, default)?.scaled_to_competences(min_c, 0.0);
            Some(teacher(py, default, given.as_ref(), "Config", "teacher_params", "teacher_params.")?)
        }
    })
}

//! A Python dict of flat parameters -> the core's `RunConfig`, as data: the core's structs carry
//! `Config`'s names (serde: `RunConfig` and the body's `BodyParams`), so the keys, their types
//! and their defaults are read from the core's defaults, serialised. Only the teacher, given by
//! two keys (`teacher`, `teacher_params`), is read by hand. Type problems are reported with the
//! parameter's name and the core's rule for it; the rules are checked once, by `validate()`.

use pyo3::prelude::*;
use pyo3::types::{PyBool, PyDict, PyFloat, PyInt, PyList, PyTuple};
use pythonize::{depythonize, pythonize};
use saggriac_core::body::params::BodyParams;
use saggriac_core::error::invalid;
use saggriac_core::{Error, RunConfig};
use serde::{de::DeserializeOwned, Serialize};

use crate::errors::to_py;
use crate::teachers::{serde_rule, wrong_type};

/// A value of the core's, by its serde names.
fn as_dict<'py, T: Serialize>(py: Python<'py>, v: &T) -> PyResult<Bound<'py, PyDict>> {
    Ok(pythonize(py, v).map_err(PyErr::from)?.cast_into::<PyDict>()?)
}

/// Every key `run_config_from_dict` understands.
pub fn keys(py: Python<'_>) -> PyResult<Vec<String>> {
    Ok(defaults(py)?.keys().iter().map(|k| k.to_string()).collect())
}

/// The core's default configuration in `Config`'s flat terms: the one declaration of every
/// default, which Python's `Config` reads (`_core.config_defaults()`). None where the default is
/// "not given" (lengths that follow the body are given here as the default arm's).
pub fn defaults(py: Python<'_>) -> PyResult<Bound<'_, PyDict>> {
    let d = as_dict(py, &RunConfig::default())?;
    as_dict(py, &BodyParams::default())?.iter().try_for_each(|(k, v)| d.set_item(k, v))?;
    d.set_item("teacher", "own")?;
    d.set_item("teacher_params", PyDict::new(py))?;
    Ok(d)
}

/// The core's messages name a parameter by its serde name, the `Config` key; their owner is
/// the part checking it (`Evaluation`), which a Python user knows as one `Config`.
pub fn in_config_terms(e: Error) -> Error {
    match e {
        Error::InvalidParameter { owner, param, rule, value } => {
            let (owner, param) = if param == "goal_selector" {
                // An argument of saggriac.run, not a Config key.
                ("run", param)
            } else if owner.ends_with("Selector") {
                // A rule of the teacher chosen by `teacher`, set through `teacher_params`.
                ("Config", format!("teacher_params.{param}"))
            } else {
                ("Config", param)
            };
            Error::InvalidParameter { owner, param, rule, value }
        }
        other => other,
    }
}

/// The configuration `d` describes, checked against every rule (`Config()` checks this way).
pub fn run_config_from_dict(d: &Bound<'_, PyDict>) -> PyResult<RunConfig> {
    let c = parse_config(d)?;
    c.validate().map_err(|e| to_py(d.py(), in_config_terms(e)))?;
    Ok(c)
}

/// The configuration `d` describes, with the type of every value checked but not the rules: a
/// learner built from it checks them itself (`Learner::from_parts`), once per run.
pub fn parse_config(d: &Bound<'_, PyDict>) -> PyResult<RunConfig> {
    let py = d.py();
    let known = keys(py)?;
    for k in d.keys() {
        let k: String = k.extract()?;
        if !known.contains(&k) {
            return Err(to_py(py, invalid("Config", &k, format!("one of the known parameters ({})", known.join(", ")), "an unknown key")));
        }
    }
    let mut c: RunConfig = typed(d, |c: &RunConfig| c.validate())?;
    let body: BodyParams = typed(d, |b: &BodyParams| b.clone().build().map(|_| ()))?;
    (c.arm, c.body_change) = body.build().map_err(|e| to_py(py, in_config_terms(e)))?;
    c.teacher = crate::teachers::of_config(d, c.competence.min_c)?;
    Ok(c)
}

/// The `T` (`RunConfig` or `BodyParams`) the keys of `d` that are its serde names describe, the
/// others at their defaults. Each value's type is checked against its default's; a number of
/// the wrong type (a negative count, a string) is named with the rule `check` gives that
/// parameter (`n_steps`: an int >= 1), found by putting 0 (or NaN for a float) in its place.
fn typed<T: Serialize + DeserializeOwned + Default>(d: &Bound<'_, PyDict>, check: impl Fn(&T) -> saggriac_core::Result<()>) -> PyResult<T> {
    let py = d.py();
    let defaults = as_dict(py, &T::default())?;
    let merged = defaults.copy()?;
    let mut wrong = None;
    let is_list = |o: &Bound<'_, PyAny>| o.is_instance_of::<PyList>() || o.is_instance_of::<PyTuple>();
    for (k, v) in d.iter() {
        let key: String = k.extract()?;
        let Some(default) = defaults.get_item(&key)?.filter(|_| !v.is_none()) else { continue };
        let shown = v.repr().map(|r| r.to_string()).unwrap_or_else(|_| "?".into());
        let number = default.is_instance_of::<PyFloat>() || (default.is_instance_of::<PyInt>() && !default.is_instance_of::<PyBool>());
        match wrong_type(&v, &default) {
            Some(rule) if number => {
                wrong.get_or_insert((key.clone(), rule, shown));
                merged.set_item(&key, if default.is_instance_of::<PyInt>() { 0u64.into_pyobject(py)?.into_any() } else { f64::NAN.into_pyobject(py)?.into_any() })?;
                continue;
            }
            Some(rule) if !default.is_none() && !is_list(&default) => return Err(to_py(py, invalid("Config", &key, rule, shown))),
            _ => merged.set_item(&key, &v)?,
        }
        // Serde would take 1.5 for a time step and True for a length: each element of a list
        // must be a number of its kind (the one type check of a run's parameters).
        if is_list(&v) {
            let ints = key.contains("schedule");
            let element_ok = |x: Bound<'_, PyAny>| !x.is_instance_of::<PyBool>() && if ints { x.extract::<u64>().is_ok() && x.is_instance_of::<PyInt>() } else { x.is_instance_of::<PyFloat>() || x.is_instance_of::<PyInt>() };
            if !v.try_iter()?.all(|x| x.map(element_ok).unwrap_or(false)) {
                let rule = if ints { "a list of ints >= 0" } else { "a list of floats" };
                return Err(to_py(py, invalid("Config", &key, rule, shown)));
            }
        }
        // What serde refuses of a value (a str naming no choice, a list of another type) is named here.
        if let Err(e) = depythonize::<T>(&merged) {
            let e = e.to_string();
            let rule = if is_list(&default) || is_list(&v) || e.contains("sequence") { if key.contains("schedule") { "a list of ints >= 0".into() } else { "a list of floats".into() } } else { serde_rule(&e) };
            return Err(to_py(py, invalid("Config", &key, rule, shown)));
        }
    }
    let c: T = depythonize(&merged).map_err(|e| to_py(py, Error::InvalidInput(e.to_string())))?;
    match wrong {
        None => Ok(c),
        Some((key, rule, shown)) => {
            let rule = match check(&c).map_err(in_config_terms) {
                Err(Error::InvalidParameter { param, rule, .. }) if param == key => rule,
                _ => rule.to_string(),
            };
            Err(to_py(py, invalid("Config", &key, rule, shown)))
        }
    }
}

//! Python values to the core's vectors: shape and finiteness checked, the problem said plainly.

use numpy::{PyArrayMethods, PyUntypedArrayMethods};
use pyo3::prelude::*;

/// Read a 1-D float vector of length `n` from a Python value, or say what is wrong.
pub fn vector(v: &Bound<'_, PyAny>, n: usize, what: &str) -> Result<Vec<f64>, String> {
    // Fast path: already a 1-D float64 array.
    if let Ok(a) = v.cast::<numpy::PyArray1<f64>>() {
        if let Ok(ro) = a.try_readonly() {
            let vals: Vec<f64> = ro.as_array().iter().copied().collect();
            return check_vector(vals, n, what);
        }
    }
    let np = v.py().import("numpy").map_err(|e| e.to_string())?;
    // Numbers only: numpy would turn '0.01' and True into floats without a word.
    let kind: String = np
        .call_method1("asarray", (v,))
        .and_then(|a| a.getattr("dtype")?.getattr("kind")?.extract())
        .map_err(|_| format!("{what} must be an array of {n} floats; got {}.", repr(v)))?;
    // numpy makes [0.5, True] a float array: look for a bool among a list's numbers.
    let bool_inside = (v.is_instance_of::<pyo3::types::PyList>() || v.is_instance_of::<pyo3::types::PyTuple>())
        && v.try_iter().map(|it| it.flatten().any(|x| x.is_instance_of::<pyo3::types::PyBool>() || x.get_type().name().map(|n| n == "bool" || n == "bool_").unwrap_or(false))).unwrap_or(false);
    if bool_inside || !matches!(kind.as_str(), "i" | "u" | "f") {
        return Err(format!("{what} must be an array of {n} numbers (ints or floats; strings and bools are refused, not converted); got {}.", repr(v)));
    }
    let arr = np.call_method1("asarray", (v, "float64")).map_err(|_| format!("{what} must be an array of {n} floats; got {}.", repr(v)))?;
    let arr = arr.cast_into::<numpy::PyArrayDyn<f64>>().map_err(|_| format!("{what} must be an array of {n} floats; got {}.", repr(v)))?;
    let ro = arr.readonly();
    let vals: Vec<f64> = ro.as_array().iter().copied().collect();
    if ro.shape() != [n] {
        return Err(format!("{what} must have shape ({n},); got shape {:?}.", ro.shape()));
    }
    check_vector(vals, n, what)
}

pub fn check_vector(vals: Vec<f64>, n: usize, what: &str) -> Result<Vec<f64>, String> {
    if vals.len() != n {
        return Err(format!("{what} must have shape ({n},); got shape ({},).", vals.len()));
    }
    if let Some(i) = vals.iter().position(|x| !x.is_finite()) {
        return Err(format!("{what} must be finite; element {i} is {}.", saggriac_core::error::Num(vals[i])));
    }
    Ok(vals)
}

pub fn repr(v: &Bound<'_, PyAny>) -> String {
    v.repr().map(|r| r.to_string()).unwrap_or_else(|_| "?".into())
}

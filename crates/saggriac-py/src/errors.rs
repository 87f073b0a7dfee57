//! Every conversion of a core error into a Python exception lives here, and the slot where a
//! user's Python part in the loop keeps its first failure. The Python classes are defined in
//! `saggriac/errors.py` (one base class, `SaggriacError`) and looked up once.

use std::sync::{Arc, Mutex};

use pyo3::prelude::*;
use pyo3::sync::PyOnceLock;
use pyo3::types::PyType;
use saggriac_core::Error;

static PARAMETER_ERROR: PyOnceLock<Py<PyType>> = PyOnceLock::new();
static INPUT_ERROR: PyOnceLock<Py<PyType>> = PyOnceLock::new();

fn class<'py>(py: Python<'py>, cell: &'static PyOnceLock<Py<PyType>>, name: &str) -> PyResult<Bound<'py, PyType>> {
    cell.import(py, "saggriac.errors", name).cloned()
}

/// Convert a core error into the matching `saggriac` exception.
pub fn to_py(py: Python<'_>, e: Error) -> PyErr {
    let (cell, name) = match &e {
        Error::InvalidParameter { .. } => (&PARAMETER_ERROR, "ParameterError"),
        Error::InvalidInput(_) => (&INPUT_ERROR, "InputError"),
    };
    match class(py, cell, name) {
        Ok(cls) => {
            let err = match &e {
                Error::InvalidParameter { param, value, .. } => cls.call1((e.to_string(), param.clone(), value.clone())),
                Error::InvalidInput(_) => cls.call1((e.to_string(),)),
            };
            match err {
                Ok(obj) => PyErr::from_value(obj),
                Err(err) => err,
            }
        }
        Err(err) => err,
    }
}

/// `PyResult` from a core `Result`.
pub fn wrap<T>(py: Python<'_>, r: saggriac_core::Result<T>) -> PyResult<T> {
    r.map_err(|e| to_py(py, e))
}

/// Why a user's Python part (environment or goal selector) failed inside the loop.
pub enum Failure {
    /// The Python code raised: re-raised as is, traceback included.
    Raised(PyErr),
    /// It returned something unusable: raised as `InputError` with this message.
    Invalid(String),
}

pub type Slot = Arc<Mutex<Option<Failure>>>;

pub fn keep_first(slot: &Slot, f: Failure) {
    let mut s = slot.lock().unwrap_or_else(|e| e.into_inner());
    if s.is_none() {
        *s = Some(f);
    }
}

/// The failure kept in `slot`, if any, as the Python exception to raise (`step`: when it happened).
pub fn take_failure(py: Python<'_>, slot: &Slot, step: u64) -> Option<PyErr> {
    let f = slot.lock().unwrap_or_else(|e| e.into_inner()).take()?;
    Some(match f {
        Failure::Raised(e) => e,
        Failure::Invalid(msg) => to_py(py, Error::InvalidInput(format!("{msg} (at time step {step}; nothing from that call was stored)"))),
    })
}

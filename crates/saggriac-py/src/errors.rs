//! Every conversion of a core error into a Python exception lives here. The Python classes are
//! defined in `saggriac/errors.py` (one base class, `SaggriacError`) and looked up once.

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

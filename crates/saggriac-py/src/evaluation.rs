//! The evaluation's test sets as numpy arrays.

use numpy::{IntoPyArray, PyArrayMethods};
use pyo3::prelude::*;
use pyo3::types::PyDict;
use saggriac_core::evaluation::TestSet;

use crate::recorder::xy;

/// Test goals (n x task dimension `m`) and test configurations (n x `n_joints`).
pub fn test_set<'py>(py: Python<'py>, t: &TestSet, m: usize, n_joints: usize) -> PyResult<Bound<'py, PyDict>> {
    let d = PyDict::new(py);
    d.set_item("goals", xy(py, t.goals.clone(), m)?)?;
    let n = t.configs.len();
    d.set_item("configs", t.configs.concat().into_pyarray(py).reshape([n, n_joints])?)?;
    Ok(d)
}

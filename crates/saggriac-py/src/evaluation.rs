//! The evaluation's test sets as numpy arrays.

use numpy::{IntoPyArray, PyArrayMethods};
use pyo3::prelude::*;
use pyo3::types::PyDict;
use saggriac_core::evaluation::TestSet;

use crate::recorder::xy;

/// Test goals (n x task dimension `m`), test configurations (n x `n_joints`) with their true
/// positions, the test motions (n x `n_joints`) with their true displacements, the kind of
/// configurations and, for ik_min_norm, each configuration's distance to its goal.
pub fn test_set<'py>(py: Python<'py>, t: &TestSet, m: usize, n_joints: usize) -> PyResult<Bound<'py, PyDict>> {
    let d = PyDict::new(py);
    d.set_item("goals", xy(py, t.goals.clone(), m)?)?;
    let n = t.configs.len();
    d.set_item("configs", t.configs.concat().into_pyarray(py).reshape([n, n_joints])?)?;
    d.set_item("true_x", xy(py, t.true_x.clone(), m)?)?;
    d.set_item("motions", t.motions.concat().into_pyarray(py).reshape([n, n_joints])?)?;
    d.set_item("true_dx", xy(py, t.true_dx.clone(), m)?)?;
    d.set_item("kind", t.kind.name())?;
    d.set_item("ik_residuals", t.ik_residuals.clone().into_pyarray(py))?;
    Ok(d)
}

//! Binding of the chain body's kinematics (`saggriac_core::body::chain`), so that Python can check a
//! chain read out of a MuJoCo model against MuJoCo, draw it, and tell where it reaches.

use numpy::{IntoPyArray, PyArray2, PyReadonlyArray2};
use pyo3::prelude::*;
use saggriac_core::body::chain::{reachable_cloud, Chain};
use saggriac_core::rng::rng_from_seed;

use crate::errors::wrap;

fn parse(py: Python<'_>, chain: Vec<f64>) -> PyResult<Chain> {
    wrap(py, Chain::from_flat(&chain))
}

fn rows<'py>(py: Python<'py>, pts: &[saggriac_core::task_space::Point]) -> Bound<'py, PyArray2<f64>> {
    let flat: Vec<f64> = pts.iter().flat_map(|p| p.iter().copied()).collect();
    numpy::ndarray::Array2::from_shape_vec((pts.len(), 3), flat).expect("three coordinates per point").into_pyarray(py)
}

/// chain_forward(chain, thetas) -> (k, 3) array: the end effector at each row of `thetas`.
#[pyfunction]
pub fn chain_forward<'py>(py: Python<'py>, chain: Vec<f64>, thetas: PyReadonlyArray2<'py, f64>) -> PyResult<Bound<'py, PyArray2<f64>>> {
    let c = parse(py, chain)?;
    let t = thetas.as_array();
    if t.ncols() != c.n_joints() {
        let msg = format!("thetas must have one column per joint of the chain ({}); got {}", c.n_joints(), t.ncols());
        return wrap(py, Err(saggriac_core::Error::InvalidInput(msg)));
    }
    let pts: Vec<_> = t.rows().into_iter().map(|r| c.forward(&r.to_vec())).collect();
    Ok(rows(py, &pts))
}

/// chain_points(chain, theta) -> (n + 1, 3) array: every joint's anchor, then the end effector.
#[pyfunction]
pub fn chain_points<'py>(py: Python<'py>, chain: Vec<f64>, theta: Vec<f64>) -> PyResult<Bound<'py, PyArray2<f64>>> {
    let c = parse(py, chain)?;
    if theta.len() != c.n_joints() {
        let msg = format!("theta must have one value per joint of the chain ({}); got {}", c.n_joints(), theta.len());
        return wrap(py, Err(saggriac_core::Error::InvalidInput(msg)));
    }
    Ok(rows(py, &c.points(&theta)))
}

/// chain_link_lengths(chain) -> list: distances between consecutive anchors, then to the tip.
#[pyfunction]
pub fn chain_link_lengths(py: Python<'_>, chain: Vec<f64>) -> PyResult<Vec<f64>> {
    Ok(parse(py, chain)?.link_lengths())
}

/// chain_cloud(chain, limit, n, seed) -> (n, 3) array: end effectors at uniform configurations.
#[pyfunction]
pub fn chain_cloud<'py>(py: Python<'py>, chain: Vec<f64>, limit: f64, n: usize, seed: u64) -> PyResult<Bound<'py, PyArray2<f64>>> {
    let c = parse(py, chain)?;
    let mut rng = rng_from_seed(seed);
    Ok(rows(py, &reachable_cloud(&c, limit, n, &mut rng)))
}

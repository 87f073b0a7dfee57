//! Binding of the Gaussian-mixture EM (`saggriac_core::high_level::teachers::gmm`), so that tests can hold
//! it against scikit-learn from the same start.

use numpy::{IntoPyArray, PyArrayMethods, PyReadonlyArray1, PyReadonlyArray2, PyReadonlyArray3};
use pyo3::prelude::*;
use pyo3::types::PyDict;
use saggriac_core::high_level::teachers::gmm::{fit_from, rows, EmConfig, Gmm};

use crate::errors::wrap;

/// gmm_fit(data, weights, means, covariances, max_iter=100, tol=1e-3, reg_covar=1e-6) -> dict:
/// EM from the given start; the fitted weights, means, covariances, lower_bound, n_iter,
/// converged and aic.
#[pyfunction]
#[pyo3(signature = (data, weights, means, covariances, max_iter=100, tol=1e-3, reg_covar=1e-6))]
#[allow(clippy::too_many_arguments)]
pub fn gmm_fit<'py>(
    py: Python<'py>,
    data: PyReadonlyArray2<'py, f64>,
    weights: PyReadonlyArray1<'py, f64>,
    means: PyReadonlyArray2<'py, f64>,
    covariances: PyReadonlyArray3<'py, f64>,
    max_iter: usize,
    tol: f64,
    reg_covar: f64,
) -> PyResult<Bound<'py, PyDict>> {
    let (x, m, c) = (data.as_array(), means.as_array(), covariances.as_array());
    let (n, d, k) = (x.nrows(), x.ncols(), m.nrows());
    if n == 0 || k == 0 || m.ncols() != d || c.shape() != [k, d, d] || weights.len()? != k {
        let msg = format!("gmm_fit needs data (n >= 1, d), weights (k), means (k, d) and covariances (k, d, d); got {:?}, {}, {:?}, {:?}", x.shape(), weights.len()?, m.shape(), c.shape());
        return wrap(py, Err(saggriac_core::Error::InvalidInput(msg)));
    }
    let flat = |a: numpy::ndarray::ArrayViewD<'_, f64>| a.iter().copied().collect::<Vec<f64>>();
    let samples = rows(&flat(x.into_dyn()), d);
    let start = Gmm::from_flat(d, weights.as_slice()?, &flat(m.into_dyn()), &flat(c.into_dyn()));
    let fit = fit_from(&samples, start, EmConfig { max_iter, tol, reg_covar });
    let g = &fit.gmm;
    let out = PyDict::new(py);
    out.set_item("weights", g.weights.clone().into_pyarray(py))?;
    let (means, covs) = g.to_flat();
    out.set_item("means", means.into_pyarray(py).reshape([k, d])?)?;
    out.set_item("covariances", covs.into_pyarray(py).reshape([k, d, d])?)?;
    out.set_item("lower_bound", fit.lower_bound)?;
    out.set_item("n_iter", fit.n_iter)?;
    out.set_item("converged", fit.converged)?;
    out.set_item("aic", g.aic(&samples))?;
    Ok(out)
}

//! Binding of the competence measure (`saggriac_core::high_level::competence`, paper eq. 7), so that Python
//! code outside a run (a Gymnasium wrapper, a user's loop) scores attempts exactly as a run does.

use numpy::{IntoPyArray, PyArray1, PyReadonlyArray2};
use pyo3::prelude::*;
use saggriac_core::error::{invalid, Num};
use saggriac_core::high_level::competence::{competence_of, CompetenceConfig, CompetenceKind};

use crate::errors::wrap;

/// competence(goals, reached, starts, min_c, eps_c, kind, reach) -> array: one competence per
/// row of the three (n, d) arrays.
#[pyfunction]
#[pyo3(signature = (goals, reached, starts, min_c=-1.0, eps_c=-0.05, kind="relative", reach=f64::NAN))]
#[allow(clippy::too_many_arguments)]
pub fn competence<'py>(
    py: Python<'py>,
    goals: PyReadonlyArray2<'py, f64>,
    reached: PyReadonlyArray2<'py, f64>,
    starts: PyReadonlyArray2<'py, f64>,
    min_c: f64,
    eps_c: f64,
    kind: &str,
    reach: f64,
) -> PyResult<Bound<'py, PyArray1<f64>>> {
    let kind = match CompetenceKind::parse(kind) {
        Some(k) => k,
        None => return wrap(py, Err(invalid("competence", "kind", "one of 'relative', 'absolute'", kind))),
    };
    let cfg = CompetenceConfig { min_c, eps_c, kind };
    wrap(py, cfg.validate())?;
    if kind == CompetenceKind::Absolute && !(reach.is_finite() && reach > 0.0) {
        return wrap(py, Err(invalid("competence", "reach", "a finite float > 0 (the scale of the absolute cost)", Num(reach))));
    }
    let (g, r, s) = (goals.as_array(), reached.as_array(), starts.as_array());
    if r.shape() != g.shape() || s.shape() != g.shape() {
        let msg = format!("goals, reached and starts must have one shape; got {:?}, {:?} and {:?}", g.shape(), r.shape(), s.shape());
        return wrap(py, Err(saggriac_core::Error::InvalidInput(msg)));
    }
    let out: Vec<f64> = (0..g.nrows())
        .map(|i| {
            let (gi, ri, si) = (g.row(i).to_vec(), r.row(i).to_vec(), s.row(i).to_vec());
            competence_of(&cfg, reach, &gi, &ri, &si)
        })
        .collect();
    Ok(out.into_pyarray(py))
}

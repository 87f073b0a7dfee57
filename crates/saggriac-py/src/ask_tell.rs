//! Binding of the ask/tell goal selectors (`saggriac_core::high_level::ask_tell`), numpy at the boundary.

use numpy::{IntoPyArray, PyArray1, PyArray2, PyArrayMethods, PyReadonlyArray1, PyReadonlyArray2, PyUntypedArrayMethods};
use pyo3::prelude::*;
use pyo3::types::PyDict;
use saggriac_core::config::high_level::InterestDivisor;
use saggriac_core::error::invalid;
use saggriac_core::high_level::ask_tell::AskTell;
use saggriac_core::high_level::goal_selection::ModeProbabilities;
use saggriac_core::high_level::region_tree::RegionTreeConfig;
use saggriac_core::high_level::teachers::alp_gmm::AlpGmmConfig;
use saggriac_core::high_level::teachers::covar_gmm::CovarGmmConfig;
use saggriac_core::high_level::teachers::discrete_lp::DiscreteLpConfig;
use saggriac_core::high_level::teachers::riac::RiacConfig;
use saggriac_core::high_level::teachers::TeacherSpec;
use saggriac_core::Error;

use crate::errors::{to_py, wrap};

#[pyclass(name = "AskTell", module = "saggriac._core")]
pub struct PyAskTell {
    inner: AskTell,
}

fn rows<'py>(py: Python<'py>, flat: Vec<f64>, d: usize) -> PyResult<Bound<'py, PyArray2<f64>>> {
    let n = flat.len() / d.max(1);
    flat.into_pyarray(py).reshape([n, d])
}

/// Messages name the Python class and its `low/high` arguments, not the core's parts.
fn named(r: saggriac_core::Result<AskTell>, owner: &'static str) -> saggriac_core::Result<AskTell> {
    r.map_err(|e| match e {
        Error::InvalidParameter { param, rule, value, .. } => Error::InvalidParameter { owner, param: if param == "bounds" { "low/high".into() } else { param }, rule, value },
        other => other,
    })
}

#[pymethods]
impl PyAskTell {
    /// AskTell(kind: "sagg_riac" | "random", low, high, seed, g_max, zeta, min_child, interest_divisor, p_interest, p_global, p_lowest);
    /// a parameter left out takes the core's default (saggriac.SaggRiacSelector passes them all).
    #[new]
    #[pyo3(signature = (kind, low, high, seed, g_max=None, zeta=None, min_child=None, interest_divisor=None, p_interest=None, p_global=None, p_lowest=None))]
    #[allow(clippy::too_many_arguments)]
    fn new(
        py: Python<'_>,
        kind: &str,
        low: Vec<f64>,
        high: Vec<f64>,
        seed: u64,
        g_max: Option<usize>,
        zeta: Option<usize>,
        min_child: Option<usize>,
        interest_divisor: Option<&str>,
        p_interest: Option<f64>,
        p_global: Option<f64>,
        p_lowest: Option<f64>,
    ) -> PyResult<Self> {
        let (t, m) = (RegionTreeConfig::default(), ModeProbabilities::default());
        let (g_max, zeta, min_child) = (g_max.unwrap_or(t.g_max), zeta.unwrap_or(t.zeta), min_child.unwrap_or(t.min_child));
        let interest_divisor = interest_divisor.unwrap_or(t.divisor.name());
        let (p_interest, p_global, p_lowest) = (p_interest.unwrap_or(m.p_interest), p_global.unwrap_or(m.p_global), p_lowest.unwrap_or(m.p_lowest));
        let inner = match kind {
            "sagg_riac" => InterestDivisor::parse("SaggRiacSelector", interest_divisor)
                .and_then(|divisor| AskTell::sagg_riac(&low, &high, RegionTreeConfig { g_max, zeta, min_child, divisor }, ModeProbabilities { p_interest, p_global, p_lowest }, seed)),
            "random" => AskTell::random(&low, &high, seed),
            other => return Err(to_py(py, invalid("GoalSelector", "kind", "one of 'sagg_riac', 'random'", format!("'{other}'")))),
        };
        // Messages name the Python class and its arguments, not the core's parts.
        let owner = if kind == "random" { "RandomSelector" } else { "SaggRiacSelector" };
        let inner = inner.map_err(|e| match e {
            Error::InvalidParameter { param, rule, value, .. } => Error::InvalidParameter { owner, param: if param == "bounds" { "low/high".into() } else { param }, rule, value },
            other => other,
        });
        Ok(PyAskTell { inner: wrap(py, inner)? })
    }

    /// riac(low, high, seed, ...) -> AskTell: RIAC (Portelas et al., CoRL 2019 baseline). Every
    /// parameter is given: their defaults are saggriac.RiacSelector's, read from the core.
    #[staticmethod]
    #[pyo3(signature = (low, high, seed, max_region_size, split_attempts, min_child_share, min_dims_range_ratio, p_alp, p_random))]
    #[allow(clippy::too_many_arguments)]
    fn riac(
        py: Python<'_>,
        low: Vec<f64>,
        high: Vec<f64>,
        seed: u64,
        max_region_size: usize,
        split_attempts: usize,
        min_child_share: f64,
        min_dims_range_ratio: f64,
        p_alp: f64,
        p_random: f64,
    ) -> PyResult<Self> {
        let cfg = RiacConfig { max_region_size, split_attempts, min_child_share, min_dims_range_ratio, p_alp, p_random };
        let inner = AskTell::new(TeacherSpec::Riac { low, high, cfg, seed }).map_err(|e| match e {
            Error::InvalidParameter { param, rule, value, .. } => Error::InvalidParameter { owner: "RiacSelector", param: if param == "bounds" { "low/high".into() } else { param }, rule, value },
            other => other,
        });
        Ok(PyAskTell { inner: wrap(py, inner)? })
    }

    /// discrete_lp(n_tasks, seed, alpha, theta) -> AskTell: learning progress over a task list
    /// (Kanitscheider et al., 2021).
    #[staticmethod]
    #[pyo3(signature = (n_tasks, seed, alpha, theta))]
    fn discrete_lp(py: Python<'_>, n_tasks: usize, seed: u64, alpha: f64, theta: f64) -> PyResult<Self> {
        Ok(PyAskTell { inner: wrap(py, AskTell::new(TeacherSpec::DiscreteLp { cfg: DiscreteLpConfig { n_tasks, alpha, theta }, seed }))? })
    }

    /// alp_gmm(low, high, seed, ...) -> AskTell: ALP-GMM (Portelas et al., CoRL 2019).
    #[staticmethod]
    #[pyo3(signature = (low, high, seed, fit_rate, max_components, random_task_ratio, bootstrap))]
    #[allow(clippy::too_many_arguments)]
    fn alp_gmm(py: Python<'_>, low: Vec<f64>, high: Vec<f64>, seed: u64, fit_rate: usize, max_components: usize, random_task_ratio: f64, bootstrap: usize) -> PyResult<Self> {
        let cfg = AlpGmmConfig { fit_rate, max_components, random_task_ratio, bootstrap };
        Ok(PyAskTell { inner: wrap(py, named(AskTell::new(TeacherSpec::AlpGmm { low, high, cfg, seed }), "AlpGmmSelector"))? })
    }

    /// covar_gmm(low, high, seed, ...) -> AskTell: Covar-GMM (Moulin-Frier, Nguyen & Oudeyer, 2014).
    #[staticmethod]
    #[pyo3(signature = (low, high, seed, fit_rate, max_components, random_task_ratio, bootstrap, absolute_lp))]
    #[allow(clippy::too_many_arguments)]
    fn covar_gmm(py: Python<'_>, low: Vec<f64>, high: Vec<f64>, seed: u64, fit_rate: usize, max_components: usize, random_task_ratio: f64, bootstrap: usize, absolute_lp: bool) -> PyResult<Self> {
        let cfg = CovarGmmConfig { mixture: AlpGmmConfig { fit_rate, max_components, random_task_ratio, bootstrap }, absolute_lp };
        Ok(PyAskTell { inner: wrap(py, named(AskTell::new(TeacherSpec::CovarGmm { low, high, cfg, seed }), "CovarGmmSelector"))? })
    }

    /// save() -> bytes: parameters, state and history (AskTell.restore rebuilds the teacher).
    fn save<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, pyo3::types::PyBytes>> {
        let bytes = wrap(py, self.inner.save())?;
        Ok(pyo3::types::PyBytes::new(py, &bytes))
    }

    /// restore(data: bytes) -> AskTell: the teacher `save` wrote, continuing where it stopped.
    #[staticmethod]
    fn restore(py: Python<'_>, data: &[u8]) -> PyResult<Self> {
        Ok(PyAskTell { inner: wrap(py, AskTell::restore(data))? })
    }

    /// The teacher's name ("sagg_riac", "random", ...).
    #[getter]
    fn kind(&self) -> &'static str {
        self.inner.spec().kind()
    }

    #[getter]
    fn seed(&self) -> u64 {
        self.inner.spec().seed()
    }

    #[getter]
    fn dim(&self) -> usize {
        self.inner.dim()
    }
    #[getter]
    fn low<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray1<f64>> {
        self.inner.selector().low().to_vec().into_pyarray(py)
    }
    #[getter]
    fn high<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray1<f64>> {
        self.inner.selector().high().to_vec().into_pyarray(py)
    }

    /// -> (goal array, mode code, region id or -1)
    fn sample<'py>(&mut self, py: Python<'py>) -> (Bound<'py, PyArray1<f64>>, u8, i64) {
        let c = self.inner.sample();
        (c.goal.into_pyarray(py), c.mode as u8, c.region.map(|r| r as i64).unwrap_or(-1))
    }

    fn sample_batch<'py>(&mut self, py: Python<'py>, n: usize) -> PyResult<Bound<'py, PyArray2<f64>>> {
        let d = self.inner.dim();
        let flat = wrap(py, self.inner.sample_batch(n))?;
        rows(py, flat, d)
    }

    fn update(&mut self, py: Python<'_>, goal: PyReadonlyArray1<'_, f64>, competence: f64) -> PyResult<i64> {
        let g = goal.as_slice()?.to_vec();
        wrap(py, self.inner.update(&g, competence))
    }

    fn update_batch<'py>(&mut self, py: Python<'py>, goals: PyReadonlyArray2<'py, f64>, competences: PyReadonlyArray1<'py, f64>) -> PyResult<Bound<'py, PyArray1<i64>>> {
        let shape = goals.shape();
        if shape[1] != self.inner.dim() {
            return Err(to_py(py, saggriac_core::Error::InvalidInput(format!("goals must have shape (n, {}); got {:?}.", self.inner.dim(), shape))));
        }
        let g = goals.as_array().iter().copied().collect::<Vec<f64>>();
        let c = competences.as_slice()?.to_vec();
        Ok(wrap(py, self.inner.update_batch(&g, &c))?.into_pyarray(py))
    }

    /// Every region of the tree (an empty table for a selector without regions).
    fn regions<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyDict>> {
        let d = PyDict::new(py);
        let dim = self.inner.dim();
        let leaves = self.inner.selector().leaf_table();
        if !leaves.is_empty() {
            // A selector with leaves but no region tree (RIAC): its leaves only.
            let n = leaves.len();
            d.set_item("low", rows(py, leaves.iter().flat_map(|r| r.low.clone()).collect(), dim)?)?;
            d.set_item("high", rows(py, leaves.iter().flat_map(|r| r.high.clone()).collect(), dim)?)?;
            d.set_item("interest", leaves.iter().map(|r| r.interest).collect::<Vec<_>>().into_pyarray(py))?;
            d.set_item("n_measurements", leaves.iter().map(|r| r.n_measurements as i64).collect::<Vec<_>>().into_pyarray(py))?;
            d.set_item("is_leaf", vec![true; n].into_pyarray(py))?;
            return Ok(d);
        }
        // A tree's regions: the table a run's regions.parquet holds.
        crate::goal_selection::regions(py, self.inner.selector())
    }

    /// What was asked (goal, mode, region) and told (goal, competence, region), in order.
    fn history<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyDict>> {
        let d = PyDict::new(py);
        let dim = self.inner.dim();
        let i = &self.inner;
        d.set_item("asked_goal", rows(py, i.asked.clone(), dim)?)?;
        d.set_item("asked_mode", i.asked_mode.clone().into_pyarray(py))?;
        d.set_item("asked_region", i.asked_region.clone().into_pyarray(py))?;
        d.set_item("told_goal", rows(py, i.told.clone(), dim)?)?;
        d.set_item("told_competence", i.told_competence.clone().into_pyarray(py))?;
        d.set_item("told_region", i.told_region.clone().into_pyarray(py))?;
        Ok(d)
    }
}

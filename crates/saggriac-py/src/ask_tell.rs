//! Binding of the ask/tell goal selectors (`saggriac_core::high_level::ask_tell`), numpy at the boundary.

use numpy::{IntoPyArray, PyArray1, PyArray2, PyArrayMethods, PyReadonlyArray1, PyReadonlyArray2, PyUntypedArrayMethods};
use pyo3::prelude::*;
use pyo3::types::PyDict;
use saggriac_core::high_level::ask_tell::AskTell;
use saggriac_core::high_level::goal_selection::leaves_table;
use saggriac_core::high_level::teachers::{Teacher, TeacherSpec};
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
    /// AskTell(kind, low, high, seed, params=None): the teacher `kind` over the box [low, high]
    /// (ignored by "discrete_lp", whose goals are task indices), with the parameters `params`
    /// names and the others at their defaults (`_core.teacher_defaults()[kind]`).
    #[new]
    #[pyo3(signature = (kind, low, high, seed, params=None))]
    fn new(py: Python<'_>, kind: &str, low: Vec<f64>, high: Vec<f64>, seed: u64, params: Option<Bound<'_, PyDict>>) -> PyResult<Self> {
        let default = wrap(py, Teacher::parse("GoalSelector", "kind", kind))?;
        let owner = default.class();
        let d = if default.has_box() { low.len() } else { 0 };
        let (params, dims) = crate::teachers::split_per_dimension(py, &default, params.as_ref(), d)?;
        let teacher = crate::teachers::teacher(py, default, params.as_ref(), owner, "params", "")?;
        let (low, high) = if teacher.has_box() { (low, high) } else { (Vec::new(), Vec::new()) };
        Ok(PyAskTell { inner: wrap(py, named(AskTell::new(TeacherSpec { teacher, low, high, seed, dims }), owner))? })
    }

    /// check_competences(lo, hi, whence): refuses thresholds no competence in [lo, hi] (told by
    /// `whence`) can meet, or every one meets.
    fn check_competences(&self, py: Python<'_>, lo: f64, hi: f64, whence: &str) -> PyResult<()> {
        wrap(py, self.inner.spec().teacher.check_competences(lo, hi, whence))
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

    /// The teacher's parameters, by name (its kind's defaults for those not given; a value given
    /// per dimension as its list, a matrix as its rows).
    fn params<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyDict>> {
        crate::teachers::spec_params(py, self.inner.spec())
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
        let leaves = self.inner.selector().leaf_table();
        if !leaves.is_empty() {
            // A selector with leaves but no region tree (RIAC): its leaves only.
            return crate::recorder::table(py, leaves_table(&leaves, self.inner.dim()));
        }
        // A tree's regions: the table a run's regions.parquet holds.
        crate::goal_selection::regions(py, self.inner.selector())
    }

    /// A task-list teacher's probability of each task at its next draw, or None if it does not
    /// say (every teacher but PLR).
    fn task_probabilities<'py>(&self, py: Python<'py>) -> Option<Bound<'py, PyArray1<f64>>> {
        self.inner.selector().task_probabilities().map(|p| p.into_pyarray(py))
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

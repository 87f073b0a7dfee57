//! Binding of the run loop: build a learner from a config dict (with a user's Python
//! environment or goal selector if given), run it with the GIL released, checkpoint and restore
//! it. Its records are converted by `recorder.rs`, `goal_selection.rs` and `evaluation.rs`.

use pyo3::prelude::*;
use pyo3::types::PyDict;
use saggriac_core::assembly::UserParts;
use saggriac_core::body::Body;
use saggriac_core::evaluation::reachable_cloud::Cloud;
use saggriac_core::high_level::goal_selection::GoalSelector;
use saggriac_core::recorder::{attempt_table, goal_table, metric_table, MetricRow};
use saggriac_core::task_space::point;
use saggriac_core::Learner;

use crate::body::PyBody;
use crate::config::{in_config_terms, parse_config};
use crate::errors::{take_failure, wrap, Slot};
use crate::goal_selection::PySelector;
use crate::{evaluation, goal_selection, recorder};

/// Test configurations and the positions they reach, row by row (a user's body's cloud).
type CloudRows = (Vec<Vec<f64>>, Vec<Vec<f64>>);

#[pyclass(name = "Learner", module = "saggriac._core")]
pub struct PyLearner {
    inner: Learner,
    /// First failure of a user's environment or goal selector during a run.
    slot: Slot,
}

impl PyLearner {
    fn take_failure(&mut self, py: Python<'_>) -> Option<PyErr> {
        take_failure(py, &self.slot, self.inner.steps())
    }
}

#[pymethods]
impl PyLearner {
    /// Learner(config: dict, seed: int, eval_seed: int, environment=None, goal_selector=None, env_seed=0, test_cloud=None)
    ///
    /// `test_cloud`: (configurations, positions), lists of rows, positions the environment
    /// reached: its test goals come from them instead of a ball about the origin.
    #[new]
    #[pyo3(signature = (config, seed, eval_seed, environment=None, goal_selector=None, env_seed=0, test_cloud=None))]
    #[allow(clippy::too_many_arguments)]
    fn new(
        py: Python<'_>,
        config: &Bound<'_, PyDict>,
        seed: u64,
        eval_seed: u64,
        environment: Option<Py<PyAny>>,
        goal_selector: Option<Py<PyAny>>,
        env_seed: u64,
        test_cloud: Option<CloudRows>,
    ) -> PyResult<Self> {
        let cfg = parse_config(config)?;
        let slot: Slot = Default::default();
        let (n, m) = (cfg.arm.link_lengths.len(), cfg.goal_low.len());
        let body = match environment {
            Some(env) => Some(Box::new(PyBody::new(py, env, n, m, env_seed, cfg.arm.joint_limit, slot.clone())?) as Box<dyn Body>),
            None => None,
        };
        let selector = match goal_selector {
            Some(s) => Some(Box::new(PySelector::new(py, s, slot.clone())?) as Box<dyn GoalSelector>),
            None => None,
        };
        let cloud = test_cloud.map(|(configs, positions)| cloud_from_rows(configs, positions, n, m)).transpose()?;
        let parts = UserParts { body, selector, cloud, ..UserParts::default() };
        let mut this = PyLearner { inner: wrap(py, Learner::from_parts(cfg, seed, eval_seed, parts).map_err(in_config_terms)).map_err(|e| take_failure(py, &slot, 0).unwrap_or(e))?, slot };
        // The environment may already have failed while the test set was measured.
        if let Some(e) = this.take_failure(py) {
            return Err(e);
        }
        Ok(this)
    }

    /// Run to the end of the step budget. `callback(row: dict) -> bool | None` sees each new
    /// evaluation; returning False stops the run. Ctrl-C also stops it (and raises).
    /// Returns True when the budget was spent.
    #[pyo3(signature = (callback=None))]
    fn run(&mut self, py: Python<'_>, callback: Option<Py<PyAny>>) -> PyResult<bool> {
        let learner = &mut self.inner;
        let mut pending: Option<PyErr> = None;
        let done = py.detach(|| {
            learner.run(&mut |row: &MetricRow| {
                Python::attach(|py| {
                    if let Err(e) = py.check_signals() {
                        pending = Some(e);
                        return false;
                    }
                    let Some(cb) = &callback else { return true };
                    let r = recorder::first_row(py, metric_table(std::slice::from_ref(row))).and_then(|d| cb.call1(py, (d,)));
                    match r {
                        // Only an explicit False stops the run; None or anything else goes on.
                        Ok(v) => !v.bind(py).is_instance_of::<pyo3::types::PyBool>() || v.extract::<bool>(py).unwrap_or(true),
                        Err(e) => {
                            pending = Some(e);
                            false
                        }
                    }
                })
            })
        });
        if let Some(e) = self.take_failure(py) {
            return Err(e);
        }
        match pending {
            Some(e) => Err(e),
            None => Ok(done),
        }
    }

    /// Let evaluations use `threads` threads, this one included (1: all in the learner's
    /// thread). Results do not depend on it.
    fn set_threads(&mut self, threads: usize) {
        self.inner.set_threads(threads);
    }

    /// The learner's whole state as bytes (between goal attempts, e.g. after run() was stopped).
    fn checkpoint<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, pyo3::types::PyBytes>> {
        let bytes = wrap(py, self.inner.checkpoint())?;
        Ok(pyo3::types::PyBytes::new(py, &bytes))
    }

    /// Learner.restore(config: dict, state: bytes): the learner a checkpoint was taken from.
    #[staticmethod]
    fn restore(py: Python<'_>, config: &Bound<'_, PyDict>, state: &[u8]) -> PyResult<Self> {
        let cfg = parse_config(config)?;
        let inner = wrap(py, py.detach(|| Learner::restore(cfg, state)))?;
        Ok(PyLearner { inner, slot: Default::default() })
    }

    #[getter]
    fn steps(&self) -> u64 {
        self.inner.steps()
    }

    /// (learner seed, evaluation seed) the learner was built with (a checkpoint's own).
    #[getter]
    fn seeds(&self) -> (u64, u64) {
        self.inner.seeds()
    }

    #[getter]
    fn n_samples(&self) -> usize {
        self.inner.memory().len()
    }

    /// Learning curve: dict of 1-D arrays (step, n_samples, reach_error, pred_error, dx_error,
    /// n_goals, n_regions).
    fn metrics<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyDict>> {
        recorder::table(py, metric_table(self.inner.recorder().metrics()))
    }

    /// Self-generated goals: one row per goal.
    fn goals<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyDict>> {
        recorder::table(py, goal_table(self.inner.recorder().goals(), self.inner.task_dim()))
    }

    /// Every (sub)goal attempt and the competence the high level received for it.
    fn attempts<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyDict>> {
        recorder::table(py, attempt_table(self.inner.recorder().attempts(), self.inner.task_dim()))
    }

    /// The region tree (all nodes, leaves and inner): bounds, parent, split, interest, count.
    /// Empty arrays for conditions without a tree.
    fn regions<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyDict>> {
        goal_selection::regions(py, self.inner.selector())
    }

    /// The evaluation's test sets: goals, configurations and their true positions, test motions
    /// and their true displacements, the kind of configurations and their IK residuals.
    fn test_set<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyDict>> {
        evaluation::test_set(py, self.inner.test_set(), self.inner.task_dim(), self.inner.body().n_joints())
    }

    /// Micro-action counts and wall time (s) per part of the loop.
    fn profile<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyDict>> {
        let l = &self.inner;
        recorder::record(py, l.recorder().profile(l.actuator_reset_period(), l.memory().rejected(), l.evaluation_split()))
    }
}

/// A test cloud from Python rows: as many configurations (n joints each) as positions (m
/// coordinates each), all finite.
fn cloud_from_rows(configs: Vec<Vec<f64>>, positions: Vec<Vec<f64>>, n: usize, m: usize) -> PyResult<Cloud> {
    let bad = |what: String| pyo3::exceptions::PyValueError::new_err(format!("test_cloud: {what}"));
    if configs.len() != positions.len() || configs.is_empty() {
        return Err(bad(format!("needs as many configurations as positions, at least one; got {} and {}", configs.len(), positions.len())));
    }
    if configs.iter().any(|c| c.len() != n || c.iter().any(|v| !v.is_finite())) {
        return Err(bad(format!("every configuration must be {n} finite floats")));
    }
    if positions.iter().any(|p| p.len() != m || p.iter().any(|v| !v.is_finite())) {
        return Err(bad(format!("every position must be {m} finite floats")));
    }
    Ok(Cloud { configs, positions: positions.iter().map(|p| point(p)).collect() })
}

//! Binding of the run loop: build a learner from a config dict, run it with the GIL released,
//! and hand back its records as numpy arrays.

use numpy::{IntoPyArray, PyArray1, PyArray2, PyArrayMethods};
use pyo3::prelude::*;
use pyo3::types::PyDict;
use saggriac_core::run_loop::MetricRow;
use saggriac_core::task_space::Point;
use saggriac_core::Learner;

use crate::config::{in_config_terms, run_config_from_dict};
use crate::errors::{to_py, wrap};
use crate::python_parts::{Failure, PyBody, PySelector, Slot};

#[pyclass(name = "Learner", module = "saggriac._core")]
pub struct PyLearner {
    inner: Learner,
    /// First failure of a user's environment or goal selector during a run.
    slot: Slot,
}

fn col<'py, T: numpy::Element>(py: Python<'py>, v: Vec<T>) -> Bound<'py, PyArray1<T>> {
    v.into_pyarray(py)
}

/// Task-space points as an (n, m) array: the first m coordinates of each.
fn xy<'py>(py: Python<'py>, v: Vec<Point>, m: usize) -> PyResult<Bound<'py, PyArray2<f64>>> {
    let n = v.len();
    let flat: Vec<f64> = v.into_iter().flat_map(|p| p.into_iter().take(m)).collect();
    flat.into_pyarray(py).reshape([n, m])
}

fn metric_dict<'py>(py: Python<'py>, m: &MetricRow) -> PyResult<Bound<'py, PyDict>> {
    let d = PyDict::new(py);
    d.set_item("step", m.step)?;
    d.set_item("n_samples", m.n_samples)?;
    d.set_item("reach_error", m.reach_error)?;
    d.set_item("pred_error", m.pred_error)?;
    d.set_item("n_goals", m.n_goals)?;
    d.set_item("n_regions", m.n_regions)?;
    Ok(d)
}

impl PyLearner {
    fn failure(py: Python<'_>, slot: &Slot, step: u64) -> Option<PyErr> {
        let f = slot.lock().unwrap_or_else(|e| e.into_inner()).take()?;
        Some(match f {
            Failure::Raised(e) => e,
            Failure::Invalid(msg) => to_py(py, saggriac_core::Error::InvalidInput(format!("{msg} (at time step {step}; nothing from that call was stored)"))),
        })
    }
    fn take_failure(&mut self, py: Python<'_>) -> Option<PyErr> {
        Self::failure(py, &self.slot, self.inner.steps())
    }
}

#[pymethods]
impl PyLearner {
    /// Learner(config: dict, seed: int, eval_seed: int, environment=None, goal_selector=None, env_seed=0)
    #[new]
    #[pyo3(signature = (config, seed, eval_seed, environment=None, goal_selector=None, env_seed=0))]
    fn new(py: Python<'_>, config: &Bound<'_, PyDict>, seed: u64, eval_seed: u64, environment: Option<Py<PyAny>>, goal_selector: Option<Py<PyAny>>, env_seed: u64) -> PyResult<Self> {
        let cfg = run_config_from_dict(config)?;
        let slot: Slot = Default::default();
        let (n, m) = (cfg.arm.link_lengths.len(), cfg.goal_low.len());
        let body = match environment {
            Some(env) => Some(Box::new(PyBody::new(py, env, n, m, env_seed, slot.clone())?) as Box<dyn saggriac_core::body::Body>),
            None => None,
        };
        let selector = match goal_selector {
            Some(s) => Some(Box::new(PySelector::new(py, s, slot.clone())?) as Box<dyn saggriac_core::goal_selection::GoalSelector>),
            None => None,
        };
        let mut this = PyLearner { inner: wrap(py, Learner::with_parts(cfg, seed, eval_seed, body, selector).map_err(in_config_terms)).map_err(|e| Self::failure(py, &slot, 0).unwrap_or(e))?, slot };
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
                    let r = metric_dict(py, row).and_then(|d| cb.call1(py, (d,)));
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

    /// The learner's whole state as bytes (between goal attempts, e.g. after run() was stopped).
    fn checkpoint<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, pyo3::types::PyBytes>> {
        let bytes = wrap(py, self.inner.checkpoint())?;
        Ok(pyo3::types::PyBytes::new(py, &bytes))
    }

    /// Learner.restore(config: dict, state: bytes): the learner a checkpoint was taken from.
    #[staticmethod]
    fn restore(py: Python<'_>, config: &Bound<'_, PyDict>, state: &[u8]) -> PyResult<Self> {
        let cfg = run_config_from_dict(config)?;
        let inner = wrap(py, py.detach(|| Learner::restore(cfg, state)))?;
        Ok(PyLearner { inner, slot: Default::default() })
    }

    #[getter]
    fn steps(&self) -> u64 {
        self.inner.steps()
    }

    #[getter]
    fn n_samples(&self) -> usize {
        self.inner.memory().len()
    }

    /// Learning curve: dict of 1-D arrays (step, n_samples, reach_error, pred_error, n_goals, n_regions).
    fn metrics<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyDict>> {
        let m = &self.inner.metrics;
        let d = PyDict::new(py);
        d.set_item("step", col(py, m.iter().map(|r| r.step).collect()))?;
        d.set_item("n_samples", col(py, m.iter().map(|r| r.n_samples).collect()))?;
        d.set_item("reach_error", col(py, m.iter().map(|r| r.reach_error).collect()))?;
        d.set_item("pred_error", col(py, m.iter().map(|r| r.pred_error).collect()))?;
        d.set_item("n_goals", col(py, m.iter().map(|r| r.n_goals).collect()))?;
        d.set_item("n_regions", col(py, m.iter().map(|r| r.n_regions).collect()))?;
        Ok(d)
    }

    /// Self-generated goals: one row per goal.
    fn goals<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyDict>> {
        let g = &self.inner.goals;
        let m = self.inner.task_dim();
        let d = PyDict::new(py);
        d.set_item("goal_index", col(py, g.iter().map(|r| r.goal_index).collect()))?;
        d.set_item("step_start", col(py, g.iter().map(|r| r.step_start).collect()))?;
        d.set_item("step_end", col(py, g.iter().map(|r| r.step_end).collect()))?;
        d.set_item("goal", xy(py, g.iter().map(|r| r.goal).collect(), m)?)?;
        d.set_item("start", xy(py, g.iter().map(|r| r.start).collect(), m)?)?;
        d.set_item("end", xy(py, g.iter().map(|r| r.end).collect(), m)?)?;
        d.set_item("mode", col(py, g.iter().map(|r| r.mode as u8).collect()))?;
        d.set_item("region", col(py, g.iter().map(|r| r.region.map(|x| x as i64).unwrap_or(-1)).collect()))?;
        d.set_item("competence", col(py, g.iter().map(|r| r.competence).collect()))?;
        Ok(d)
    }

    /// Every (sub)goal attempt and the competence the high level received for it.
    fn attempts<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyDict>> {
        let a = &self.inner.attempts;
        let m = self.inner.task_dim();
        let d = PyDict::new(py);
        d.set_item("goal_index", col(py, a.iter().map(|r| r.goal_index).collect()))?;
        d.set_item("subgoal", col(py, a.iter().map(|r| r.subgoal).collect()))?;
        d.set_item("step_end", col(py, a.iter().map(|r| r.step_end).collect()))?;
        d.set_item("target", xy(py, a.iter().map(|r| r.target).collect(), m)?)?;
        d.set_item("end", xy(py, a.iter().map(|r| r.end).collect(), m)?)?;
        d.set_item("competence", col(py, a.iter().map(|r| r.competence).collect()))?;
        d.set_item("reached", col(py, a.iter().map(|r| r.reached).collect()))?;
        d.set_item("region", col(py, a.iter().map(|r| r.region.map(|x| x as i64).unwrap_or(-1)).collect()))?;
        Ok(d)
    }

    /// The region tree (all nodes, leaves and inner): bounds, parent, split, interest, count.
    /// Empty arrays for conditions without a tree.
    fn regions<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyDict>> {
        let d = PyDict::new(py);
        let regs = self.inner.selector().tree().map(|t| t.regions().to_vec()).unwrap_or_default();
        let dim = self.inner.selector().dim();
        let n = regs.len();
        let low: Vec<f64> = regs.iter().flat_map(|r| r.low.clone()).collect();
        let high: Vec<f64> = regs.iter().flat_map(|r| r.high.clone()).collect();
        d.set_item("low", low.into_pyarray(py).reshape([n, dim])?)?;
        d.set_item("high", high.into_pyarray(py).reshape([n, dim])?)?;
        d.set_item("parent", col(py, regs.iter().map(|r| r.parent.map(|p| p as i64).unwrap_or(-1)).collect()))?;
        d.set_item("is_leaf", col(py, regs.iter().map(|r| r.is_leaf()).collect()))?;
        d.set_item("split_dim", col(py, regs.iter().map(|r| if r.is_leaf() { -1 } else { r.split_dim as i64 }).collect()))?;
        d.set_item("split_value", col(py, regs.iter().map(|r| r.split_value).collect()))?;
        d.set_item("interest", col(py, regs.iter().map(|r| r.interest).collect()))?;
        d.set_item("n_measurements", col(py, regs.iter().map(|r| r.entries.len() as u64).collect()))?;
        d.set_item("mean_competence", col(py, regs.iter().map(|r| r.mean().unwrap_or(f64::NAN)).collect()))?;
        d.set_item("created_at", col(py, regs.iter().map(|r| r.created_at).collect()))?;
        d.set_item("depth", col(py, regs.iter().map(|r| r.depth).collect()))?;
        Ok(d)
    }

    /// Test goals (n x task dimension) and test configurations (n x joints) of the evaluation.
    fn test_set<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyDict>> {
        let t = self.inner.test_set();
        let d = PyDict::new(py);
        d.set_item("goals", xy(py, t.goals.clone(), self.inner.task_dim())?)?;
        let n = t.configs.len();
        let j = self.inner.body().n_joints();
        d.set_item("configs", t.configs.concat().into_pyarray(py).reshape([n, j])?)?;
        Ok(d)
    }

    /// Micro-action counts and wall time (s) per part of the loop.
    fn profile<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyDict>> {
        let c = self.inner.counters();
        let t = self.inner.timers();
        let d = PyDict::new(py);
        d.set_item("reaching_steps", c.reaching_steps)?;
        d.set_item("exploration_steps", c.exploration_steps)?;
        d.set_item("babbling_steps", c.babbling_steps)?;
        d.set_item("actuator_reset_period", self.inner.actuator_reset_period())?;
        d.set_item("explorations", c.explorations)?;
        d.set_item("fit_failures", c.fit_failures)?;
        d.set_item("test_steps", c.test_steps)?;
        d.set_item("rejected_samples", self.inner.memory().rejected())?;
        d.set_item("time_knn", t.knn)?;
        d.set_item("time_fit", t.fit)?;
        d.set_item("time_goal_selection", t.goal_selection)?;
        d.set_item("time_evaluation", t.evaluation)?;
        let (eval_knn, eval_fit) = self.inner.evaluation_split();
        d.set_item("time_evaluation_knn", eval_knn)?;
        d.set_item("time_evaluation_fit", eval_fit)?;
        d.set_item("time_total", t.total)?;
        Ok(d)
    }
}

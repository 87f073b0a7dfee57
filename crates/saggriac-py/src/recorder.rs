//! The recorder's rows, counters and timers as Python dicts of numpy arrays.

use numpy::{IntoPyArray, PyArray1, PyArray2, PyArrayMethods};
use pyo3::prelude::*;
use pyo3::types::PyDict;
use saggriac_core::recorder::{MetricRow, Recorder};
use saggriac_core::task_space::Point;

// Counts and steps go out as int64, never unsigned: a user's difference of two steps must not
// wrap around (pandas, polars, the Parquet files).
fn col<'py, T: numpy::Element>(py: Python<'py>, v: Vec<T>) -> Bound<'py, PyArray1<T>> {
    v.into_pyarray(py)
}

/// Task-space points as an (n, m) array: the first m coordinates of each.
pub fn xy<'py>(py: Python<'py>, v: Vec<Point>, m: usize) -> PyResult<Bound<'py, PyArray2<f64>>> {
    let n = v.len();
    let flat: Vec<f64> = v.into_iter().flat_map(|p| p.into_iter().take(m)).collect();
    flat.into_pyarray(py).reshape([n, m])
}

/// One metric row, as the dict a run's callback receives.
pub fn metric_row<'py>(py: Python<'py>, m: &MetricRow) -> PyResult<Bound<'py, PyDict>> {
    let d = PyDict::new(py);
    d.set_item("step", m.step)?;
    d.set_item("n_samples", m.n_samples)?;
    d.set_item("reach_error", m.reach_error)?;
    d.set_item("pred_error", m.pred_error)?;
    d.set_item("dx_error", m.dx_error)?;
    d.set_item("n_goals", m.n_goals)?;
    d.set_item("n_regions", m.n_regions)?;
    Ok(d)
}

/// Learning curve: dict of 1-D arrays (step, n_samples, reach_error, pred_error, dx_error,
/// n_goals, n_regions).
pub fn metrics<'py>(py: Python<'py>, r: &Recorder) -> PyResult<Bound<'py, PyDict>> {
    let m = r.metrics();
    let d = PyDict::new(py);
    d.set_item("step", col(py, m.iter().map(|r| r.step as i64).collect()))?;
    d.set_item("n_samples", col(py, m.iter().map(|r| r.n_samples as i64).collect()))?;
    d.set_item("reach_error", col(py, m.iter().map(|r| r.reach_error).collect()))?;
    d.set_item("pred_error", col(py, m.iter().map(|r| r.pred_error).collect()))?;
    d.set_item("dx_error", col(py, m.iter().map(|r| r.dx_error).collect()))?;
    d.set_item("n_goals", col(py, m.iter().map(|r| r.n_goals as i64).collect()))?;
    d.set_item("n_regions", col(py, m.iter().map(|r| r.n_regions as i64).collect()))?;
    Ok(d)
}

/// Self-generated goals: one row per goal, points in an `m`-D task space.
pub fn goals<'py>(py: Python<'py>, r: &Recorder, m: usize) -> PyResult<Bound<'py, PyDict>> {
    let g = r.goals();
    let d = PyDict::new(py);
    d.set_item("goal_index", col(py, g.iter().map(|r| r.goal_index as i64).collect()))?;
    d.set_item("step_start", col(py, g.iter().map(|r| r.step_start as i64).collect()))?;
    d.set_item("step_end", col(py, g.iter().map(|r| r.step_end as i64).collect()))?;
    d.set_item("goal", xy(py, g.iter().map(|r| r.goal).collect(), m)?)?;
    d.set_item("start", xy(py, g.iter().map(|r| r.start).collect(), m)?)?;
    d.set_item("end", xy(py, g.iter().map(|r| r.end).collect(), m)?)?;
    d.set_item("mode", col(py, g.iter().map(|r| r.mode as i64).collect()))?;
    d.set_item("region", col(py, g.iter().map(|r| r.region.map(|x| x as i64).unwrap_or(-1)).collect()))?;
    d.set_item("competence", col(py, g.iter().map(|r| r.competence).collect()))?;
    Ok(d)
}

/// Every (sub)goal attempt and the competence the high level received for it.
pub fn attempts<'py>(py: Python<'py>, r: &Recorder, m: usize) -> PyResult<Bound<'py, PyDict>> {
    let a = r.attempts();
    let d = PyDict::new(py);
    d.set_item("goal_index", col(py, a.iter().map(|r| r.goal_index as i64).collect()))?;
    d.set_item("subgoal", col(py, a.iter().map(|r| r.subgoal as i64).collect()))?;
    d.set_item("step_end", col(py, a.iter().map(|r| r.step_end as i64).collect()))?;
    d.set_item("target", xy(py, a.iter().map(|r| r.target).collect(), m)?)?;
    d.set_item("end", xy(py, a.iter().map(|r| r.end).collect(), m)?)?;
    d.set_item("competence", col(py, a.iter().map(|r| r.competence).collect()))?;
    d.set_item("reached", col(py, a.iter().map(|r| r.reached).collect()))?;
    d.set_item("region", col(py, a.iter().map(|r| r.region.map(|x| x as i64).unwrap_or(-1)).collect()))?;
    Ok(d)
}

/// Micro-action counts and wall time (s) per part of the loop, with the counts kept by other
/// parts (the ACTUATOR reset period, the model's rejected samples, the evaluation's time split).
pub fn profile<'py>(py: Python<'py>, r: &Recorder, actuator_reset_period: usize, rejected_samples: u64, evaluation_split: (f64, f64)) -> PyResult<Bound<'py, PyDict>> {
    let (c, t) = (&r.counters, &r.timers);
    let d = PyDict::new(py);
    d.set_item("reaching_steps", c.reaching_steps)?;
    d.set_item("exploration_steps", c.exploration_steps)?;
    d.set_item("babbling_steps", c.babbling_steps)?;
    d.set_item("actuator_reset_period", actuator_reset_period)?;
    d.set_item("explorations", c.explorations)?;
    d.set_item("fit_failures", c.fit_failures)?;
    d.set_item("test_steps", c.test_steps)?;
    d.set_item("trigger_only_executed", c.trigger_only_executed)?;
    d.set_item("trigger_only_desired", c.trigger_only_desired)?;
    d.set_item("trigger_gap_sum", c.trigger_gap_sum)?;
    d.set_item("rejected_samples", rejected_samples)?;
    d.set_item("time_knn", t.knn)?;
    d.set_item("time_fit", t.fit)?;
    d.set_item("time_goal_selection", t.goal_selection)?;
    d.set_item("time_evaluation", t.evaluation)?;
    d.set_item("time_evaluation_knn", evaluation_split.0)?;
    d.set_item("time_evaluation_fit", evaluation_split.1)?;
    d.set_item("time_total", t.total)?;
    Ok(d)
}

//! A user's Python goal selector in the Rust run loop, through the core's `GoalSelector` trait
//! (failures handled as for environments, see `body.rs`), and the region tree of a selector as
//! numpy arrays.

use numpy::IntoPyArray;
use pyo3::prelude::*;
use pyo3::types::PyDict;
use saggriac_core::high_level::goal_selection::{GoalChoice, GoalSelector, Mode};
use saggriac_core::high_level::region_tree::region_table;
use saggriac_core::error::Num;

use crate::errors::{keep_first, Failure, Slot};
use crate::values::vector;

/// A Python goal selector: `sample() -> goal` and `update(goal, competence)`, with `low` and
/// `high` arrays giving its goal space.
pub struct PySelector {
    obj: Py<PyAny>,
    low: Vec<f64>,
    high: Vec<f64>,
    slot: Slot,
    failed: bool,
}

impl PySelector {
    pub fn new(py: Python<'_>, obj: Py<PyAny>, slot: Slot) -> PyResult<Self> {
        let b = obj.bind(py);
        let read = |name: &str| -> PyResult<Vec<f64>> {
            let v = b.getattr(name).map_err(|_| pyo3::exceptions::PyTypeError::new_err(format!("a goal selector needs a '{name}' attribute (the bounds of its goal space)")))?;
            vector(&v, v.len().unwrap_or(0), &format!("goal_selector.{name}")).map_err(pyo3::exceptions::PyValueError::new_err)
        };
        let (low, high) = (read("low")?, read("high")?);
        Ok(PySelector { obj, low, high, slot, failed: false })
    }
    fn fail(&mut self, f: Failure) {
        self.failed = true;
        keep_first(&self.slot, f);
    }
}

impl GoalSelector for PySelector {
    fn goal_box(&self) -> (&[f64], &[f64]) {
        (&self.low, &self.high)
    }
    fn sample(&mut self) -> GoalChoice {
        let centre: Vec<f64> = self.low.iter().zip(&self.high).map(|(l, h)| 0.5 * (l + h)).collect();
        if self.failed {
            return GoalChoice { goal: centre, mode: Mode::External, region: None };
        }
        let d = self.dim();
        let got = Python::attach(|py| match self.obj.bind(py).call_method0("sample") {
            Err(e) => Err(Failure::Raised(e)),
            Ok(v) => vector(&v, d, "the goal returned by goal_selector.sample()").map_err(Failure::Invalid),
        });
        match got {
            Ok(g) => {
                if let Some(i) = (0..d).find(|&i| !(g[i] >= self.low[i] && g[i] <= self.high[i])) {
                    self.fail(Failure::Invalid(format!(
                        "the goal returned by goal_selector.sample() must lie in [low, high]; coordinate {i} is {} but the bounds are [{}, {}].",
                        Num(g[i]), Num(self.low[i]), Num(self.high[i])
                    )));
                    return GoalChoice { goal: centre, mode: Mode::External, region: None };
                }
                GoalChoice { goal: g, mode: Mode::External, region: None }
            }
            Err(f) => {
                self.fail(f);
                GoalChoice { goal: centre, mode: Mode::External, region: None }
            }
        }
    }
    fn update(&mut self, point: &[f64], competence: f64) -> Option<usize> {
        if self.failed {
            return None;
        }
        // The run loop tells points of the selector's box (`Parts::tell`).
        let r = Python::attach(|py| self.obj.bind(py).call_method1("update", (point.to_vec().into_pyarray(py), competence)).map(|_| ()));
        if let Err(e) = r {
            self.fail(Failure::Raised(e));
        }
        None
    }
    fn failed(&self) -> bool {
        self.failed
    }
}

/// The selector's region tree (all nodes, leaves and inner): bounds, parent, split, interest,
/// count. Empty arrays for selectors without a tree.
pub fn regions<'py>(py: Python<'py>, selector: &dyn GoalSelector) -> PyResult<Bound<'py, PyDict>> {
    let regions = selector.tree().map(|t| t.regions()).unwrap_or_default();
    crate::recorder::table(py, region_table(regions, selector.dim()))
}

//! A user's Python environment and goal selector, plugged into the Rust run loop through the
//! core's `Body` and `GoalSelector` traits. Each call takes the GIL for the time of the Python
//! call only. The first failure (an exception, or a value of the wrong shape, NaN or inf) is
//! kept in a shared slot, the component reports `failed()`, the loop stops, and the binding
//! raises it; a bad value never reaches the memory.

use std::sync::{Arc, Mutex};

use numpy::{IntoPyArray, PyArrayMethods, PyUntypedArrayMethods};
use pyo3::prelude::*;
use pyo3::types::{PyDict, PyTuple};
use saggriac_core::body::Body;
use saggriac_core::goal_selection::{GoalChoice, GoalSelector, Mode};
use saggriac_core::task_space::{point, sub, Point, MAX_TASK_DIM};

pub enum Failure {
    /// The Python code raised: re-raised as is, traceback included.
    Raised(PyErr),
    /// It returned something unusable: raised as `InputError` with this message.
    Invalid(String),
}

pub type Slot = Arc<Mutex<Option<Failure>>>;

fn keep_first(slot: &Slot, f: Failure) {
    let mut s = slot.lock().unwrap_or_else(|e| e.into_inner());
    if s.is_none() {
        *s = Some(f);
    }
}

/// Read a 1-D float vector of length `n` from a Python value, or say what is wrong.
fn vector(v: &Bound<'_, PyAny>, n: usize, what: &str) -> Result<Vec<f64>, String> {
    // Fast path: already a 1-D float64 array.
    if let Ok(a) = v.cast::<numpy::PyArray1<f64>>() {
        if let Ok(ro) = a.try_readonly() {
            let vals: Vec<f64> = ro.as_array().iter().copied().collect();
            return check_vector(vals, n, what);
        }
    }
    let np = v.py().import("numpy").map_err(|e| e.to_string())?;
    let arr = np.call_method1("asarray", (v, "float64")).map_err(|_| format!("{what} must be an array of {n} floats; got {}.", repr(v)))?;
    let arr = arr.cast_into::<numpy::PyArrayDyn<f64>>().map_err(|_| format!("{what} must be an array of {n} floats; got {}.", repr(v)))?;
    let ro = arr.readonly();
    let vals: Vec<f64> = ro.as_array().iter().copied().collect();
    if ro.shape() != [n] {
        return Err(format!("{what} must have shape ({n},); got shape {:?}.", ro.shape()));
    }
    check_vector(vals, n, what)
}

fn check_vector(vals: Vec<f64>, n: usize, what: &str) -> Result<Vec<f64>, String> {
    if vals.len() != n {
        return Err(format!("{what} must have shape ({n},); got shape ({},).", vals.len()));
    }
    if let Some(i) = vals.iter().position(|x| !x.is_finite()) {
        return Err(format!("{what} must be finite; element {i} is {}.", vals[i]));
    }
    Ok(vals)
}

fn repr(v: &Bound<'_, PyAny>) -> String {
    v.repr().map(|r| r.to_string()).unwrap_or_else(|_| "?".into())
}

/// A Python environment: `reset(seed=None, options=None) -> (theta, x)` and
/// `step(dtheta) -> (theta, x)`; `reset(options={"theta": theta})` places it at once.
pub struct PyBody {
    env: Py<PyAny>,
    n: usize,
    m: usize,
    theta: Vec<f64>,
    x: Point,
    slot: Slot,
    failed: bool,
}

impl PyBody {
    /// Wrap `env` and reset it once with `seed` (later resets pass no seed, as in Gymnasium).
    /// `n` joints, an `m`-D task space (the goal space's dimension).
    pub fn new(py: Python<'_>, env: Py<PyAny>, n: usize, m: usize, seed: u64, slot: Slot) -> PyResult<Self> {
        let mut b = PyBody { env, n, m, theta: vec![0.0; n], x: [0.0; MAX_TASK_DIM], slot, failed: false };
        let kw = PyDict::new(py);
        kw.set_item("seed", seed)?;
        b.call(py, "reset", PyTuple::empty(py), Some(&kw));
        Ok(b)
    }

    fn call<'py>(&mut self, py: Python<'py>, method: &str, args: Bound<'py, PyTuple>, kw: Option<&Bound<'py, PyDict>>) {
        if self.failed {
            return;
        }
        let out = self.env.bind(py).call_method(method, args, kw);
        let parsed = match out {
            Err(e) => Err(Failure::Raised(e)),
            Ok(v) => self.parse(&v, method).map_err(Failure::Invalid),
        };
        match parsed {
            Ok((t, x)) => {
                self.theta = t;
                self.x = point(&x);
            }
            Err(f) => {
                self.failed = true;
                keep_first(&self.slot, f);
            }
        }
    }

    fn parse(&self, v: &Bound<'_, PyAny>, method: &str) -> Result<(Vec<f64>, Vec<f64>), String> {
        let pair: (Bound<'_, PyAny>, Bound<'_, PyAny>) = v.extract().map_err(|_| format!("environment.{method}() must return a pair (theta, x); got {}.", repr(v)))?;
        let t = vector(&pair.0, self.n, &format!("theta returned by environment.{method}()"))?;
        let x = vector(&pair.1, self.m, &format!("x returned by environment.{method}()")).map_err(|e| format!("{e} (the goal space goal_low/goal_high is {}-D)", self.m))?;
        Ok((t, x))
    }
}

impl Body for PyBody {
    fn n_joints(&self) -> usize {
        self.n
    }
    fn theta(&self) -> &[f64] {
        &self.theta
    }
    fn task_dim(&self) -> usize {
        self.m
    }
    fn position(&self) -> Point {
        self.x
    }
    fn reset(&mut self) {
        Python::attach(|py| self.call(py, "reset", PyTuple::empty(py), None));
    }
    fn set_theta(&mut self, theta: &[f64]) {
        Python::attach(|py| {
            let kw = PyDict::new(py);
            let opts = PyDict::new(py);
            if opts.set_item("theta", theta.to_vec().into_pyarray(py)).is_ok() && kw.set_item("options", opts).is_ok() {
                self.call(py, "reset", PyTuple::empty(py), Some(&kw));
            }
        });
    }
    fn step(&mut self, dtheta: &mut [f64]) -> Point {
        let (t0, x0) = (self.theta.clone(), self.x);
        Python::attach(|py| match PyTuple::new(py, [dtheta.to_vec().into_pyarray(py)]) {
            Ok(args) => self.call(py, "step", args, None),
            Err(e) => {
                self.failed = true;
                keep_first(&self.slot, Failure::Raised(e));
            }
        });
        if self.failed {
            dtheta.iter_mut().for_each(|d| *d = 0.0);
            return [0.0; MAX_TASK_DIM];
        }
        for ((d, t), s) in dtheta.iter_mut().zip(&self.theta).zip(&t0) {
            *d = t - s;
        }
        sub(&self.x, &x0)
    }
    fn failed(&self) -> bool {
        self.failed
    }
}

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
    fn low(&self) -> &[f64] {
        &self.low
    }
    fn high(&self) -> &[f64] {
        &self.high
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
                        g[i], self.low[i], self.high[i]
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

//! A user's Python environment in the Rust run loop, through the core's `Body` trait. Each call
//! takes the GIL for the time of the Python call only; the first failure (an exception, or a
//! value of the wrong shape, NaN or inf) goes to the shared slot, the body reports `failed()`,
//! the loop stops and the binding raises it: a bad value never reaches the model.

use numpy::IntoPyArray;
use pyo3::prelude::*;
use pyo3::types::{PyDict, PyTuple};
use saggriac_core::body::Body;
use saggriac_core::task_space::{point, sub, Point, MAX_TASK_DIM};

use crate::errors::{keep_first, Failure, Slot};
use crate::values::{repr, vector};

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
    /// The joint limit of the run (the environment's joint_space): a theta beyond it is refused.
    limit: f64,
}

impl PyBody {
    /// Wrap `env` and reset it once with `seed` (later resets pass no seed, as in Gymnasium).
    /// `n` joints, an `m`-D task space (the goal space's dimension).
    pub fn new(py: Python<'_>, env: Py<PyAny>, n: usize, m: usize, seed: u64, limit: f64, slot: Slot) -> PyResult<Self> {
        let mut b = PyBody { env, n, m, theta: vec![0.0; n], x: [0.0; MAX_TASK_DIM], slot, failed: false, limit };
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
        // A float32 joint space rounds its limit: a hair of slack, not a new range.
        let bound = self.limit * (1.0 + 1e-6) + 1e-12;
        if let Some(i) = t.iter().position(|a| a.abs() > bound) {
            return Err(format!("theta returned by environment.{method}() must stay within the joint limits [-{0}, {0}] (environment.joint_space); joint {i} is {1}", saggriac_core::error::G(self.limit), saggriac_core::error::Num(t[i])));
        }
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

//! The sensorimotor model (paper III.B): what the learner knows of its body. For micro-actions,
//! the memory of every (theta, dtheta, dx, x) with its neighbour index over theta, and a local
//! linear model fitted on the neighbours of the current configuration (inverse: dtheta = J+ dx;
//! forward: J dtheta). For the episodic paradigm, the memory of every movement's (theta, x).
//!
//! Learning goes through `&mut SensorimotorModel`; readers get a `ModelView`, which holds shared
//! references only, so a reader (the evaluation) cannot change what was learnt.

use std::time::Instant;

use serde::{Deserialize, Serialize};

use crate::config::RunConfig;
use crate::model::episodic_memory::EpisodicMemory;
use crate::model::local_model::FitFailure;
use crate::model::local_query::LocalQuery;
use crate::model::memory::SensorimotorMemory;
use crate::task_space::{Point, MAX_TASK_DIM};
use crate::timers::Timers;

pub struct SensorimotorModel {
    samples: SensorimotorMemory,
    /// The inverse model's query along the learner's trajectory (the evaluator has its own).
    query: LocalQuery,
    /// The episodic paradigm's movements (None for micro-actions).
    episodes: Option<EpisodicMemory>,
}

/// What readers see of the model: the stored samples and movements, read-only.
#[derive(Clone, Copy)]
pub struct ModelView<'a> {
    samples: &'a SensorimotorMemory,
    episodes: Option<&'a EpisodicMemory>,
}

impl<'a> ModelView<'a> {
    pub fn samples(&self) -> &'a SensorimotorMemory {
        self.samples
    }
    pub fn episodes(&self) -> Option<&'a EpisodicMemory> {
        self.episodes
    }
    /// Samples learnt from: micro-actions, or movements in the episodic paradigm.
    pub fn len(&self) -> usize {
        self.episodes.map(|m| m.len()).unwrap_or(self.samples.len())
    }
    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }
}

impl SensorimotorModel {
    /// The empty model of a run with `n` joints and an `m`-D task space.
    pub fn new(cfg: &RunConfig, n: usize, m: usize, episodic: bool, index_theta: bool) -> Self {
        SensorimotorModel {
            samples: SensorimotorMemory::new(n, m, cfg.index),
            query: LocalQuery::new(n, m, cfg.local.clone(), cfg.warm_start_recent),
            episodes: episodic.then(|| EpisodicMemory::new(n, m, index_theta)),
        }
    }

    pub fn view(&self) -> ModelView<'_> {
        ModelView { samples: &self.samples, episodes: self.episodes.as_ref() }
    }
    pub fn samples(&self) -> &SensorimotorMemory {
        &self.samples
    }
    pub fn episodes(&self) -> Option<&EpisodicMemory> {
        self.episodes.as_ref()
    }
    pub fn len(&self) -> usize {
        self.view().len()
    }
    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }
    pub fn task_dim(&self) -> usize {
        self.samples.task_dim()
    }

    /// Store one micro-action (refused, and counted, if a value is not finite).
    pub fn store(&mut self, theta: &[f64], dtheta: &[f64], dx: &[f64], x: &[f64]) -> bool {
        self.samples.add(theta, dtheta, dx, x)
    }

    /// Store one movement of the episodic paradigm (None: this model, of the micro-action
    /// paradigm, has no memory of movements).
    pub fn store_movement(&mut self, theta: &[f64], x: &[f64]) -> Option<bool> {
        self.episodes.as_mut().map(|e| e.add(theta, x))
    }

    /// The arm jumped (back to rest): the trajectory's warm start no longer applies.
    pub fn forget_trajectory(&mut self) {
        self.query.forget_trajectory();
    }

    /// Fit the local model on the nearest stored configurations of `theta`.
    pub fn fit_at(&mut self, theta: &[f64], timers: &mut Timers) -> Result<(), FitFailure> {
        if self.samples.len() < self.query.k() {
            return Err(FitFailure::NotEnoughData);
        }
        let t0 = Instant::now();
        self.query.find(&self.samples, theta);
        let t1 = Instant::now();
        let r = self.query.fit(&self.samples);
        timers.knn += (t1 - t0).as_secs_f64();
        timers.fit += t1.elapsed().as_secs_f64();
        r
    }

    /// Inverse model: dtheta = J+ dx with J fitted on the nearest stored configurations of theta.
    pub fn inverse(&mut self, theta: &[f64], dx: &Point, dtheta: &mut [f64], timers: &mut Timers) -> Result<(), FitFailure> {
        self.fit_at(theta, timers)?;
        let t0 = Instant::now();
        let r = self.query.inverse(&dx[..self.task_dim()], dtheta);
        timers.fit += t0.elapsed().as_secs_f64();
        r
    }

    /// Forward model: J dtheta with the last fitted J.
    pub fn expected_dx(&self, dtheta: &[f64]) -> Point {
        let j = self.query.local().jacobian();
        let mut e = [0.0; MAX_TASK_DIM];
        for (r, v) in e.iter_mut().take(j.nrows()).enumerate() {
            *v = (0..dtheta.len()).map(|a| j[(r, a)] * dtheta[a]).sum();
        }
        e
    }

    /// What a checkpoint keeps of the model: the stored samples (the indexes are rebuilt).
    pub(crate) fn save(&self) -> ModelState {
        let [t, d, x, p] = self.samples.arrays();
        ModelState {
            samples: [t.to_vec(), d.to_vec(), x.to_vec(), p.to_vec()],
            rejected: self.samples.rejected(),
            episodes: self.episodes.as_ref().map(|m| (m.arrays().0.to_vec(), m.arrays().1.to_vec())),
        }
    }

    /// Rebuild the stored samples from a checkpoint (the indexes answer as before: every search
    /// is exact).
    pub(crate) fn restore(&mut self, state: &ModelState) {
        let (n, m) = (self.samples.n_joints(), self.samples.task_dim());
        let [t, d, x, p] = &state.samples;
        for i in 0..t.len() / n {
            self.samples.add(&t[i * n..(i + 1) * n], &d[i * n..(i + 1) * n], &x[i * m..(i + 1) * m], &p[i * m..(i + 1) * m]);
        }
        self.samples.set_rejected(state.rejected);
        if let (Some(mem), Some((thetas, xs))) = (self.episodes.as_mut(), &state.episodes) {
            for i in 0..xs.len() / m {
                mem.add(&thetas[i * n..(i + 1) * n], &xs[i * m..(i + 1) * m]);
            }
        }
    }
}

/// The model's part of a checkpoint: every sample in storage order (theta, dtheta, dx, x), the
/// count of refused ones, and the episodic paradigm's movements (theta, x).
#[derive(Serialize, Deserialize)]
pub(crate) struct ModelState {
    samples: [Vec<f64>; 4],
    rejected: u64,
    episodes: Option<(Vec<f64>, Vec<f64>)>,
}

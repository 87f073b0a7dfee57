//! One query of the learnt inverse model at a configuration (paper III.B): the k nearest stored
//! configurations of theta (warm started along a trajectory), the local linear model fitted on
//! them, and dtheta = J+ dx. The learner (`SensorimotorModel`) and the evaluator's test reaches
//! (`evaluation::micro`) both ask it, so both read the model the same way.

use crate::config::LocalModelConfig;
use crate::model::local_model::{FitFailure, LocalModel};
use crate::model::memory::SensorimotorMemory;
use crate::model::neighbours::{Neighbour, WarmStart};

pub struct LocalQuery {
    /// The local model fitted last (its J is the forward model until the next fit).
    local: LocalModel,
    /// Warm start of the neighbour search along the current trajectory.
    warm: WarmStart,
    warm_start: bool,
    neighbours: Vec<Neighbour>,
}

impl LocalQuery {
    /// A query of an `n`-joint, `m`-D model; `warm_start_recent` = 0 searches cold every time.
    pub fn new(n: usize, m: usize, local: LocalModelConfig, warm_start_recent: usize) -> Self {
        LocalQuery { local: LocalModel::new(n, m, local), warm: WarmStart::new(warm_start_recent), warm_start: warm_start_recent > 0, neighbours: Vec::new() }
    }

    /// Neighbours a fit needs.
    pub fn k(&self) -> usize {
        self.local.cfg.k_neighbours
    }

    /// The arm jumped: the trajectory's warm start no longer applies.
    pub fn forget_trajectory(&mut self) {
        self.warm.clear();
    }

    /// Find the k nearest stored configurations of `theta` (exact, warm or cold alike).
    pub fn find(&mut self, memory: &SensorimotorMemory, theta: &[f64]) {
        let k = self.k();
        if self.warm_start {
            memory.knn_warm(&mut self.warm, theta, k, &mut self.neighbours);
        } else {
            memory.knn(theta, k, &mut self.neighbours);
        }
    }

    /// Take the answer `find` gave before at the same configuration of the same memory; it also
    /// seeds the warm start, as a search would have.
    pub fn reuse(&mut self, neighbours: &[Neighbour]) {
        self.neighbours.clear();
        self.neighbours.extend_from_slice(neighbours);
        self.warm.remember(neighbours);
    }

    /// The neighbours found last.
    pub fn neighbours(&self) -> &[Neighbour] {
        &self.neighbours
    }

    /// Fit the local model on the neighbours found last.
    pub fn fit(&mut self, memory: &SensorimotorMemory) -> Result<(), FitFailure> {
        self.local.fit(memory, &self.neighbours)
    }

    /// dtheta = J+ dx with the last fit.
    pub fn inverse(&self, dx: &[f64], dtheta: &mut [f64]) -> Result<(), FitFailure> {
        self.local.inverse(dx, dtheta)
    }

    /// The local model itself (the forward model J of the last fit; the evaluator also fits it on
    /// neighbours it keeps itself).
    pub fn local(&self) -> &LocalModel {
        &self.local
    }
    pub fn local_mut(&mut self) -> &mut LocalModel {
        &mut self.local
    }
}

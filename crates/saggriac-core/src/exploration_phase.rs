//! Exploration phase of the low level (paper III.D.2): q small random micro-actions around the
//! current configuration, so the local model learns (theta, dtheta) -> dx there.

use crate::error::{Check, Result};
use crate::rng::uniform;
use crate::run_loop::{ActionKind, Learner};

#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ExplorationConfig {
    /// Number of random micro-actions per exploration phase.
    pub q: usize,
    /// Half-width of the box around the phase's starting configuration in which the random
    /// configurations are drawn (radians, per joint).
    pub step: f64,
}

impl Default for ExplorationConfig {
    fn default() -> Self {
        ExplorationConfig { q: 20, step: 0.01 }
    }
}

impl ExplorationConfig {
    pub fn validate(&self) -> Result<()> {
        let c = Check { owner: "Exploration" };
        c.at_least("q", self.q, 1)?;
        c.positive("step", self.step)?;
        Ok(())
    }
}

impl Learner {
    /// Run one exploration phase: q micro-actions, each moving to a random configuration in a
    /// small box around the theta the phase started from. Staying around that centre (rather
    /// than a drifting random walk) keeps the new samples where the local model must be good.
    /// Stops early only when the run's step budget is spent.
    pub(crate) fn explore(&mut self) {
        let step = self.cfg.exploration.step;
        let centre = self.body.theta().to_vec();
        for _ in 0..self.cfg.exploration.q {
            let mut d = std::mem::take(&mut self.buf_dtheta);
            for ((v, c), t) in d.iter_mut().zip(&centre).zip(self.body.theta()) {
                *v = c + uniform(&mut self.rng, -step, step) - t;
            }
            let done = self.micro_action(&mut d, ActionKind::Exploration).is_none();
            self.buf_dtheta = d;
            if done {
                return;
            }
        }
    }
}

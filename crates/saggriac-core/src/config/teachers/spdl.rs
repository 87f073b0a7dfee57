//! SPDL's parameters (Klink et al., NeurIPS 2020 / JMLR 2021).

use serde::{Deserialize, Serialize};

use crate::config::teachers::{Registered, TeacherParams};
use crate::error::{invalid, Check, Num, Result, MAX_COUNT};

/// SPDL's parameters (Klink et al., NeurIPS 2020 / JMLR 2021), in the box scaled to [0, 1]:
/// both Gaussians are diagonal, with one mean and one standard deviation for every dimension.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct SpdlConfig {
    /// Mean of the initial distribution in every scaled dimension (0.5: the box's centre).
    pub init_mean: f64,
    /// Its standard deviation, in box widths (0.1, TeachMyAgent's initial distribution).
    pub init_std: f64,
    /// Mean of the target distribution mu in every scaled dimension (0.5).
    pub target_mean: f64,
    /// Its standard deviation, in box widths (0.25: TeachMyAgent's Gaussian for a uniform box).
    pub target_std: f64,
    /// Bound on KL(p_new || p_old) at each update (0.05).
    pub epsilon: f64,
    /// Least expected competence of a new distribution (0.5, for competences in [0, 1]).
    pub delta: f64,
    /// Told goals between updates (100).
    pub update_every: usize,
    /// Told goals before the first update (200, TeachMyAgent's offset of two periods).
    pub warmup: usize,
}

impl Default for SpdlConfig {
    fn default() -> Self {
        SpdlConfig { init_mean: 0.5, init_std: 0.1, target_mean: 0.5, target_std: 0.25, epsilon: 0.05, delta: 0.5, update_every: 100, warmup: 200 }
    }
}

impl TeacherParams for SpdlConfig {
    fn validate(&self) -> Result<()> {
        let c = Check { owner: Self::CLASS };
        for (name, v) in [("init_mean", self.init_mean), ("target_mean", self.target_mean)] {
            if !(v.is_finite() && (0.0..=1.0).contains(&v)) {
                return Err(invalid(Self::CLASS, name, "a float in [0, 1] (a position in the box scaled to [0, 1])", Num(v)));
            }
        }
        for (name, v) in [("init_std", self.init_std), ("target_std", self.target_std)] {
            if !(v.is_finite() && (1e-4..=10.0).contains(&v)) {
                return Err(invalid(Self::CLASS, name, "a float in [1e-4, 10] (box widths)", Num(v)));
            }
        }
        c.positive("epsilon", self.epsilon)?;
        if !(self.delta.is_finite() && self.delta.abs() <= 1e100) {
            return Err(invalid(Self::CLASS, "delta", "a finite float of absolute value <= 1e100", Num(self.delta)));
        }
        c.within("update_every", self.update_every, 1, MAX_COUNT)?;
        c.within("warmup", self.warmup, 0, MAX_COUNT)?;
        Ok(())
    }

    fn scaled_to_competences(self, lo: f64, hi: f64) -> Self {
        SpdlConfig { delta: lo + self.delta * (hi - lo), ..self }
    }

    fn check_competences(&self, lo: f64, hi: f64, told: &str) -> Result<()> {
        if !(lo..=hi).contains(&self.delta) {
            return Err(invalid(Self::CLASS, "delta", format!("a float in [{}, {}] ({told}; the distribution moves only while the expected competence is >= delta, so outside it would never move, or never be held back)", Num(lo), Num(hi)), Num(self.delta)));
        }
        Ok(())
    }
}

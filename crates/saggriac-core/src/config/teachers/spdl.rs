//! SPDL's parameters (Klink et al., NeurIPS 2020 / JMLR 2021).

use serde::{Deserialize, Serialize};

use crate::config::teachers::{Registered, TeacherParams};
use crate::config::rules::{check_fields, COUNT, POSITIVE, Rule};
use crate::error::{invalid, Num, Result, MAX_COUNT};

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

const MEAN: Rule = Rule::Float { lo: 0.0, lo_in: true, hi: 1.0, hi_in: true, note: "a position in the box scaled to [0, 1]" };
const STD: Rule = Rule::Float { lo: 1e-4, lo_in: true, hi: 10.0, hi_in: true, note: "box widths" };

impl TeacherParams for SpdlConfig {
    const RULES: &'static [(&'static str, Rule)] = &[
        ("init_mean", MEAN),
        ("init_std", STD),
        ("target_mean", MEAN),
        ("target_std", STD),
        ("epsilon", POSITIVE),
        ("delta", Rule::Finite),
        ("update_every", COUNT),
        ("warmup", Rule::Int(0, MAX_COUNT)),
    ];

    fn validate(&self) -> Result<()> {
        let (o, r) = (Self::CLASS, Self::RULES);
        check_fields!(o, r, self, float init_mean, float init_std, float target_mean, float target_std, float epsilon, float delta, int update_every, int warmup);
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

//! RIAC's parameters, as the baseline of Portelas et al. (CoRL 2019).

use serde::{Deserialize, Serialize};

use crate::config::rules::{check_fields, open_closed, PROBABILITY, Rule};
use crate::config::teachers::{Registered, TeacherParams};
use crate::error::{invalid, Num, Result, MAX_COUNT};

#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct RiacConfig {
    /// Measurements a leaf holds before it is split (200 in Portelas et al.).
    pub max_region_size: usize,
    /// Random cuts tried per split (50).
    pub split_attempts: usize,
    /// Least share of the leaf's measurements in each child (1/4).
    pub min_child_share: f64,
    /// Least width of a child in every dimension, as a share of the initial range (1/6).
    pub min_dims_range_ratio: f64,
    /// Share of goals from a leaf drawn by ALP, uniform in it (0.7).
    pub p_alp: f64,
    /// Share of goals uniform in the whole box (0.2); the rest go near a leaf's worst goal.
    pub p_random: f64,
}

impl Default for RiacConfig {
    fn default() -> Self {
        RiacConfig { max_region_size: 200, split_attempts: 50, min_child_share: 0.25, min_dims_range_ratio: 1.0 / 6.0, p_alp: 0.7, p_random: 0.2 }
    }
}

impl TeacherParams for RiacConfig {
    const RULES: &'static [(&'static str, Rule)] = &[
        ("max_region_size", Rule::Int(2, MAX_COUNT)),
        // Each attempt scans the leaf: 10^4 attempts of 10^6 measurements is already long.
        ("split_attempts", Rule::Int(1, 10_000)),
        ("min_child_share", open_closed(0.0, 0.5)),
        ("min_dims_range_ratio", open_closed(0.0, 0.5)),
        ("p_alp", PROBABILITY),
        ("p_random", PROBABILITY),
    ];

    fn validate(&self) -> Result<()> {
        let (o, r) = (Self::CLASS, Self::RULES);
        check_fields!(o, r, self, int max_region_size, int split_attempts, float min_child_share, float min_dims_range_ratio, float p_alp, float p_random);
        if self.p_alp + self.p_random > 1.0 + 1e-12 {
            return Err(invalid(o, "p_alp", format!("a float with p_alp + p_random <= 1 (p_random = {})", Num(self.p_random)), Num(self.p_alp)));
        }
        Ok(())
    }
}

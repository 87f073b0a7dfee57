//! Covar-GMM's parameters (Moulin-Frier, Nguyen & Oudeyer, 2014).

use serde::{Deserialize, Serialize};

use crate::config::teachers::{AlpGmmConfig, Registered, TeacherParams};
use crate::config::rules::{Rule, PROBABILITY};
use crate::error::{Result, MAX_COUNT};

impl TeacherParams for CovarGmmConfig {
    const RULES: &'static [(&'static str, Rule)] = &[
        ("fit_rate", Rule::Int(2, MAX_COUNT)),
        ("max_components", Rule::Int(2, 100)),
        ("random_task_ratio", PROBABILITY),
        ("bootstrap", Rule::Int(0, MAX_COUNT)),
        ("absolute_lp", Rule::Bool),
    ];

    fn validate(&self) -> Result<()> {
        self.mixture.check(Self::CLASS)
    }
}

#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct CovarGmmConfig {
    /// Window, refit period, number of components, random share and bootstrap, as ALP-GMM's.
    pub mixture: AlpGmmConfig,
    /// Draw components by |progress| (true) or by positive progress only.
    pub absolute_lp: bool,
}

impl Default for CovarGmmConfig {
    fn default() -> Self {
        CovarGmmConfig { mixture: AlpGmmConfig::default(), absolute_lp: true }
    }
}

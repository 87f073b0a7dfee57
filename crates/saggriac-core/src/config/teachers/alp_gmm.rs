//! ALP-GMM's parameters (Portelas et al., CoRL 2019), which Covar-GMM shares.

use serde::{Deserialize, Serialize};

use crate::config::rules::{check_fields, PROBABILITY, Rule};
use crate::config::teachers::{Registered, TeacherParams};
use crate::error::{invalid, Result, MAX_COUNT};

/// The parameters both mixture teachers share (ALP-GMM's names and defaults).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct AlpGmmConfig {
    /// Tasks between refits, and the window they are fitted on (250).
    pub fit_rate: usize,
    /// Mixtures of 2 to this many components are tried (10).
    pub max_components: usize,
    /// Share of uniform goals after the bootstrap (0.2).
    pub random_task_ratio: f64,
    /// Uniform goals first (250, as fit_rate).
    pub bootstrap: usize,
}

impl Default for AlpGmmConfig {
    fn default() -> Self {
        AlpGmmConfig { fit_rate: 250, max_components: 10, random_task_ratio: 0.2, bootstrap: 250 }
    }
}

impl TeacherParams for AlpGmmConfig {
    const RULES: &'static [(&'static str, Rule)] = &[
        ("fit_rate", Rule::Int(2, MAX_COUNT)),
        // EM tries every number of components up to this one at each refit.
        ("max_components", Rule::Int(2, 100)),
        ("random_task_ratio", PROBABILITY),
        ("bootstrap", Rule::Int(0, MAX_COUNT)),
    ];

    fn validate(&self) -> Result<()> {
        self.check(Self::CLASS)
    }
}

impl AlpGmmConfig {
    /// The rules, with `owner`'s name in the messages (Covar-GMM shares them).
    pub fn check(&self, owner: &'static str) -> Result<()> {
        let r = <Self as TeacherParams>::RULES;
        check_fields!(owner, r, self, int fit_rate, int max_components, int bootstrap, float random_task_ratio);
        if self.max_components > self.fit_rate {
            return Err(invalid(owner, "max_components", format!("an int <= fit_rate (fit_rate = {})", self.fit_rate), self.max_components));
        }
        Ok(())
    }
}

//! ALP-GMM's parameters (Portelas et al., CoRL 2019), which Covar-GMM shares.

use serde::{Deserialize, Serialize};

use crate::config::rules::check_int;
use crate::config::teachers::{Registered, TeacherParams};
use crate::error::{invalid, Check, Result};

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
    fn validate(&self) -> Result<()> {
        self.check(Self::CLASS)
    }
}

impl AlpGmmConfig {
    /// The rules, with `owner`'s name in the messages (Covar-GMM shares them).
    pub fn check(&self, owner: &'static str) -> Result<()> {
        let c = Check { owner };
        check_int(&c, "fit_rate", self.fit_rate)?;
        check_int(&c, "max_components", self.max_components)?;
        check_int(&c, "bootstrap", self.bootstrap)?;
        c.probability("random_task_ratio", self.random_task_ratio)?;
        if self.max_components > self.fit_rate {
            return Err(invalid(owner, "max_components", format!("an int <= fit_rate (fit_rate = {})", self.fit_rate), self.max_components));
        }
        Ok(())
    }
}

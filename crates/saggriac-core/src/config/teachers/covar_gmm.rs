//! Covar-GMM's parameters (Moulin-Frier, Nguyen & Oudeyer, 2014).

use serde::{Deserialize, Serialize};

use crate::config::teachers::{AlpGmmConfig, Registered, TeacherParams};
use crate::error::Result;

impl TeacherParams for CovarGmmConfig {
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

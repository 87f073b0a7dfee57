//! SAGG-RIAC's high level as a teacher (Baranes & Oudeyer, IROS 2010): the region tree's and the
//! goal modes' parameters.

use serde::{Deserialize, Serialize};

use crate::config::high_level::{Mode3Config, ModeProbabilities, RegionTreeConfig, SAGG_RIAC_RULES};
use crate::config::rules::Rule;
use crate::config::teachers::TeacherParams;
use crate::error::Result;

/// SAGG-RIAC's high level: the region tree's and the goal modes' parameters (by their names in
/// `Config`, which sets them for a run's own high level).
#[derive(Debug, Clone, Copy, PartialEq, Default, Serialize, Deserialize)]
pub struct SaggRiacConfig {
    pub tree: RegionTreeConfig,
    pub modes: ModeProbabilities,
    /// Mode 3's reading (the paper's by default).
    pub mode3: Mode3Config,
}

impl TeacherParams for SaggRiacConfig {
    const RULES: &'static [(&'static str, Rule)] = SAGG_RIAC_RULES;

    fn validate(&self) -> Result<()> {
        self.tree.validate().and_then(|_| self.modes.validate()).and_then(|_| self.mode3.validate())
    }
}

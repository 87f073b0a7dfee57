//! SAGG-RIAC's high level as a teacher: the region tree and goal modes of
//! `crate::high_level::goal_selection` (Baranes & Oudeyer, IROS 2010).

pub use crate::config::teachers::SaggRiacConfig;
use crate::error::Result;
use crate::high_level::goal_selection::{GoalSelector, SaggRiac};
use crate::high_level::teachers::Build;

impl Build for SaggRiacConfig {
    fn build(&self, low: &[f64], high: &[f64], seed: u64) -> Result<Box<dyn GoalSelector>> {
        Ok(Box::new(SaggRiac::new(low, high, self.tree, self.modes, seed)?.with_mode3(self.mode3)?))
    }
}

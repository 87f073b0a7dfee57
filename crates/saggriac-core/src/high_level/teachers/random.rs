//! Goals uniform in the box (SAGG-Random): `crate::high_level::goal_selection::RandomGoals`.

pub use crate::config::teachers::RandomConfig;
use crate::error::Result;
use crate::high_level::goal_selection::{GoalSelector, RandomGoals};
use crate::high_level::teachers::Build;

impl Build for RandomConfig {
    fn build(&self, low: &[f64], high: &[f64], seed: u64) -> Result<Box<dyn GoalSelector>> {
        Ok(Box::new(RandomGoals::new(low, high, seed)?))
    }
}

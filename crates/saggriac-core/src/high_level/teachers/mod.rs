//! The teachers: goal selectors of the curriculum literature behind one ask/tell API
//! (`crate::high_level::ask_tell`). A `TeacherSpec` names a teacher and every parameter it was built with, so
//! that a saved teacher (`AskTell::save`) can be rebuilt and continue exactly where it stopped.

pub mod alp_gmm;
pub mod covar_gmm;
pub mod discrete_lp;
pub mod gmm;
pub(crate) mod mixture;
pub mod riac;

use serde::{Deserialize, Serialize};

use crate::error::Result;
use crate::high_level::goal_selection::{GoalSelector, ModeProbabilities, RandomGoals, SaggRiac};
use crate::high_level::region_tree::RegionTreeConfig;
use alp_gmm::{AlpGmm, AlpGmmConfig};
use covar_gmm::{CovarGmm, CovarGmmConfig};
use discrete_lp::{DiscreteLp, DiscreteLpConfig};
use riac::{Riac, RiacConfig};

/// A teacher and its parameters.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub enum TeacherSpec {
    /// SAGG-RIAC's high level (Baranes & Oudeyer, IROS 2010).
    SaggRiac { low: Vec<f64>, high: Vec<f64>, tree: RegionTreeConfig, modes: ModeProbabilities, seed: u64 },
    /// Goals uniform in the box (SAGG-Random).
    Random { low: Vec<f64>, high: Vec<f64>, seed: u64 },
    /// RIAC as the baseline of Portelas et al. (CoRL 2019).
    Riac { low: Vec<f64>, high: Vec<f64>, cfg: RiacConfig, seed: u64 },
    /// Learning progress over a task list (Kanitscheider et al., 2021).
    DiscreteLp { cfg: DiscreteLpConfig, seed: u64 },
    /// ALP-GMM (Portelas et al., CoRL 2019).
    AlpGmm { low: Vec<f64>, high: Vec<f64>, cfg: AlpGmmConfig, seed: u64 },
    /// Covar-GMM (Moulin-Frier, Nguyen & Oudeyer, 2014).
    CovarGmm { low: Vec<f64>, high: Vec<f64>, cfg: CovarGmmConfig, seed: u64 },
}

impl TeacherSpec {
    /// The teacher's name, as the Python classes and the CLI know it.
    pub fn kind(&self) -> &'static str {
        match self {
            TeacherSpec::SaggRiac { .. } => "sagg_riac",
            TeacherSpec::Random { .. } => "random",
            TeacherSpec::Riac { .. } => "riac",
            TeacherSpec::DiscreteLp { .. } => "discrete_lp",
            TeacherSpec::AlpGmm { .. } => "alp_gmm",
            TeacherSpec::CovarGmm { .. } => "covar_gmm",
        }
    }

    /// The seed of the teacher's generator.
    pub fn seed(&self) -> u64 {
        match self {
            TeacherSpec::SaggRiac { seed, .. }
            | TeacherSpec::Random { seed, .. }
            | TeacherSpec::Riac { seed, .. }
            | TeacherSpec::DiscreteLp { seed, .. }
            | TeacherSpec::AlpGmm { seed, .. }
            | TeacherSpec::CovarGmm { seed, .. } => *seed,
        }
    }

    /// A new teacher with these parameters (checked).
    pub fn build(&self) -> Result<Box<dyn GoalSelector>> {
        Ok(match self {
            TeacherSpec::SaggRiac { low, high, tree, modes, seed } => Box::new(SaggRiac::new(low, high, *tree, *modes, *seed)?),
            TeacherSpec::Random { low, high, seed } => Box::new(RandomGoals::new(low, high, *seed)?),
            TeacherSpec::Riac { low, high, cfg, seed } => Box::new(Riac::new(low, high, *cfg, *seed)?),
            TeacherSpec::DiscreteLp { cfg, seed } => Box::new(DiscreteLp::new(*cfg, *seed)?),
            TeacherSpec::AlpGmm { low, high, cfg, seed } => Box::new(AlpGmm::new(low, high, *cfg, *seed)?),
            TeacherSpec::CovarGmm { low, high, cfg, seed } => Box::new(CovarGmm::new(low, high, *cfg, *seed)?),
        })
    }
}

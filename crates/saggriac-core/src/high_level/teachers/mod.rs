//! The teachers: goal selectors of the curriculum literature behind one ask/tell API
//! (`crate::high_level::ask_tell`). A `TeacherSpec` names a teacher and every parameter it was
//! built with, so that a saved teacher (`AskTell::save`) can be rebuilt and continue exactly
//! where it stopped. Adding a teacher: its file here, its parameters and one variant in
//! `crate::config::teachers::Teacher`, one line in `TeacherSpec::build` (docs/teachers.md).

pub mod adr;
pub mod alp_gmm;
pub mod covar_gmm;
pub mod discrete_lp;
pub mod gmm;
mod gmm_lanes;
pub mod goal_gan;
pub(crate) mod mixture;
pub mod mlp;
pub mod plr;
pub mod riac;
pub mod spdl;

use serde::{Deserialize, Serialize};

pub use crate::config::teachers::Teacher;
use crate::error::Result;
use crate::high_level::goal_selection::{GoalSelector, RandomGoals, SaggRiac};
use adr::Adr;
use alp_gmm::AlpGmm;
use covar_gmm::CovarGmm;
use discrete_lp::DiscreteLp;
use goal_gan::GoalGan;
use plr::Plr;
use riac::Riac;
use spdl::Spdl;

/// A teacher built over a goal space: which teacher with which parameters (`Teacher`, the one
/// declaration), its box [low, high] (empty for the task-list teacher, whose goals are task
/// indices) and its seed.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct TeacherSpec {
    pub teacher: Teacher,
    pub low: Vec<f64>,
    pub high: Vec<f64>,
    pub seed: u64,
}

impl TeacherSpec {
    /// The teacher's name, as the Python classes and the CLI know it.
    pub fn kind(&self) -> &'static str {
        self.teacher.kind()
    }

    /// The seed of the teacher's generator.
    pub fn seed(&self) -> u64 {
        self.seed
    }

    /// A new teacher with these parameters (checked): one line per teacher.
    pub fn build(&self) -> Result<Box<dyn GoalSelector>> {
        let (low, high, seed) = (&self.low, &self.high, self.seed);
        Ok(match self.teacher {
            Teacher::SaggRiac(c) => Box::new(SaggRiac::new(low, high, c.tree, c.modes, seed)?),
            Teacher::Random(_) => Box::new(RandomGoals::new(low, high, seed)?),
            Teacher::Riac(c) => Box::new(Riac::new(low, high, c, seed)?),
            Teacher::DiscreteLp(c) => Box::new(DiscreteLp::new(c, seed)?),
            Teacher::AlpGmm(c) => Box::new(AlpGmm::new(low, high, c, seed)?),
            Teacher::CovarGmm(c) => Box::new(CovarGmm::new(low, high, c, seed)?),
            Teacher::Adr(c) => Box::new(Adr::new(low, high, c, seed)?),
            Teacher::Plr(c) => Box::new(Plr::new(c, seed)?),
            Teacher::Spdl(c) => Box::new(Spdl::new(low, high, c, seed)?),
            Teacher::GoalGan(c) => Box::new(GoalGan::new(low, high, c, seed)?),
        })
    }
}

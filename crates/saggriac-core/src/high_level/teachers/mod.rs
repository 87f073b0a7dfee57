//! The teachers: goal selectors of the curriculum literature behind one ask/tell API
//! (`crate::high_level::ask_tell`). A `TeacherSpec` names a teacher and every parameter it was
//! built with, so that a saved teacher (`AskTell::save`) can be rebuilt and continue exactly
//! where it stopped. Each teacher of the registry (`crate::config::teachers::registry`) has its
//! file here, named as the teacher, holding its algorithm and its `Build`.

pub mod gaussian;
pub mod gmm;
mod gmm_lanes;
mod kmeans;
pub(crate) mod mixture;
pub mod mlp;
pub mod refit_threads;
pub(crate) mod task_index;

use serde::{Deserialize, Serialize};

use crate::config::teachers::registry;
use crate::config::teachers::TeacherParams;
pub use crate::config::teachers::{PerDimension, Teacher};
use crate::error::Result;
use crate::high_level::goal_selection::GoalSelector;

/// A teacher's parameters build the teacher over a box [low, high] (ignored by the task-list
/// teachers, whose goals are task indices) with a seed.
pub trait Build: TeacherParams {
    fn build(&self, low: &[f64], high: &[f64], seed: u64) -> Result<Box<dyn GoalSelector>>;

    /// The teacher with some of its parameters given per dimension (none: `build`). The values
    /// are checked here (`PerDimension::check`); a teacher whose `PER_DIMENSION` names some
    /// writes `build_per_dimension`.
    fn build_with(&self, low: &[f64], high: &[f64], dims: &PerDimension, seed: u64) -> Result<Box<dyn GoalSelector>> {
        dims.check::<Self>(low.len())?;
        if dims.is_empty() {
            self.build(low, high, seed)
        } else {
            self.build_per_dimension(low, high, dims, seed)
        }
    }

    /// `build` with the values given per dimension (only names of `PER_DIMENSION` reach it).
    fn build_per_dimension(&self, low: &[f64], high: &[f64], _dims: &PerDimension, seed: u64) -> Result<Box<dyn GoalSelector>> {
        self.build(low, high, seed)
    }
}

/// `Build` for the parameters `$params` of a teacher built by `$teacher::new(low, high, params,
/// seed)` (`box`) or `$teacher::new(params, seed)` (`tasks`: its goals are task indices); with
/// `box, per_dimension`, the values given per dimension build it by `$teacher::with_dims(low,
/// high, params, dims, seed)`.
macro_rules! build_by_new {
    ($params:ty => $teacher:ty, box) => {
        impl $crate::high_level::teachers::Build for $params {
            fn build(&self, low: &[f64], high: &[f64], seed: u64) -> $crate::error::Result<Box<dyn $crate::high_level::goal_selection::GoalSelector>> {
                Ok(Box::new(<$teacher>::new(low, high, *self, seed)?))
            }
        }
    };
    ($params:ty => $teacher:ty, box, per_dimension) => {
        impl $crate::high_level::teachers::Build for $params {
            fn build(&self, low: &[f64], high: &[f64], seed: u64) -> $crate::error::Result<Box<dyn $crate::high_level::goal_selection::GoalSelector>> {
                Ok(Box::new(<$teacher>::new(low, high, *self, seed)?))
            }
            fn build_per_dimension(
                &self,
                low: &[f64],
                high: &[f64],
                dims: &$crate::config::teachers::PerDimension,
                seed: u64,
            ) -> $crate::error::Result<Box<dyn $crate::high_level::goal_selection::GoalSelector>> {
                Ok(Box::new(<$teacher>::with_dims(low, high, *self, dims, seed)?))
            }
        }
    };
    ($params:ty => $teacher:ty, tasks) => {
        impl $crate::high_level::teachers::Build for $params {
            fn build(&self, _low: &[f64], _high: &[f64], seed: u64) -> $crate::error::Result<Box<dyn $crate::high_level::goal_selection::GoalSelector>> {
                Ok(Box::new(<$teacher>::new(*self, seed)?))
            }
        }
    };
}

/// Each teacher's module, and `TeacherSpec::build` dispatching to its `Build`.
macro_rules! declare_builds {
    ($($file:ident: $variant:ident($params:ident),)*) => {
        $(pub mod $file;)*

        impl TeacherSpec {
            /// A new teacher with these parameters (checked).
            pub fn build(&self) -> Result<Box<dyn GoalSelector>> {
                match self.teacher {
                    $(Teacher::$variant(c) => c.build_with(&self.low, &self.high, &self.dims, self.seed),)*
                }
            }
        }
    };
}
registry!(declare_builds);

/// A teacher built over a goal space: which teacher with which parameters (`Teacher`, the one
/// declaration), its box [low, high] (empty for the task-list teacher, whose goals are task
/// indices), its seed, and the parameters given per dimension (empty: none).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct TeacherSpec {
    pub teacher: Teacher,
    pub low: Vec<f64>,
    pub high: Vec<f64>,
    pub seed: u64,
    pub dims: PerDimension,
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
}

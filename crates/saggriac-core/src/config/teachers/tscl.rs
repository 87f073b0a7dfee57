//! TSCL's parameters (Matiisen, Oliver, Cohen & Schulman, "Teacher-Student Curriculum
//! Learning", arXiv 2017 / IEEE TNNLS 2019).

use serde::{Deserialize, Serialize};

use crate::config::teachers::{Registered, TeacherParams};
use crate::config::rules::{check_fields, COUNT, PROBABILITY, Rule};
use crate::error::Result;

/// How a task's learning progress is estimated (the paper's Algorithms 3 and 4).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum TsclVariant {
    /// The slope of a linear regression of the task's last `window` scores on the steps they
    /// were told at.
    Window,
    /// One of the task's last `window` score changes, drawn at random (Thompson-like sampling).
    Sampling,
}

/// How a task is chosen from the tasks' learning progress.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum TsclPolicy {
    /// The task of largest progress, or with probability `epsilon` a task drawn uniformly.
    EpsilonGreedy,
    /// A task drawn with probability proportional to exp(progress / `temperature`).
    Boltzmann,
}

#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct TsclConfig {
    pub n_tasks: usize,
    pub variant: TsclVariant,
    /// K: the scores (window) or score changes (sampling) kept per task (10, the authors' code).
    pub window: usize,
    pub policy: TsclPolicy,
    /// The uniform share of the epsilon-greedy policy (0.1).
    pub epsilon: f64,
    /// The Boltzmann policy's temperature, in units of progress per step (0.01; our choice).
    pub temperature: f64,
    /// Choose by |progress| (true, the paper's: a task being forgotten is practised again) or
    /// by progress itself.
    pub absolute: bool,
}

impl Default for TsclConfig {
    /// `n_tasks` has no default worth the name (the Python class requires it), 1 is the least
    /// valid.
    fn default() -> Self {
        TsclConfig { n_tasks: 1, variant: TsclVariant::Window, window: 10, policy: TsclPolicy::EpsilonGreedy, epsilon: 0.1, temperature: 0.01, absolute: true }
    }
}

impl TeacherParams for TsclConfig {
    const HAS_BOX: bool = false;

    const RULES: &'static [(&'static str, Rule)] = &[
        ("n_tasks", COUNT),
        ("variant", Rule::Choice),
        // A slope needs two scores.
        ("window", Rule::Int(2, 10_000)),
        ("policy", Rule::Choice),
        ("epsilon", PROBABILITY),
        ("temperature", Rule::Float { lo: 1e-12, lo_in: true, hi: f64::INFINITY, hi_in: false, note: "" }),
        ("absolute", Rule::Bool),
    ];

    fn validate(&self) -> Result<()> {
        let (o, r) = (Self::CLASS, Self::RULES);
        check_fields!(o, r, self, int n_tasks, int window, float epsilon, float temperature);
        Ok(())
    }
}

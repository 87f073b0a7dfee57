//! The low level's parameters: the SSA reacher (reaching phase, exploration phase, timeout) and
//! the episodic paradigm.

use crate::error::{Check, Result};

#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct ReachingConfig {
    /// Length of the desired displacement per micro-action (paper: v = 0.5). Near the target the
    /// step is shortened to the remaining distance ("v bounded by v_max").
    pub v: f64,
    /// Subgoals per goal, the goal being the last (paper: l = 5).
    pub n_subgoals: usize,
    /// Explore when |realised dx - expected dx| > eps_max; `trigger` says what is expected.
    pub eps_max: f64,
    /// The expected dx of the exploration trigger.
    #[serde(rename = "exploration_trigger")]
    pub trigger: ExplorationTrigger,
    /// Timeout of one (sub)goal attempt, in micro-actions of any kind (reaching and
    /// exploration): ceil(timeout_factor * distance / v) + timeout_min. It is checked between
    /// phases, so an exploration phase that starts before the timeout runs its q actions,
    /// unless `timeout_in_exploration`, which also ends a phase at the timeout.
    pub timeout_factor: f64,
    pub timeout_min: usize,
    pub timeout_in_exploration: bool,
}

impl Default for ReachingConfig {
    fn default() -> Self {
        ReachingConfig { v: 0.5, n_subgoals: 5, eps_max: 0.1, timeout_factor: 2.0, timeout_min: 10, timeout_in_exploration: false, trigger: ExplorationTrigger::Executed }
    }
}

/// What the exploration trigger compares the realised displacement with.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, serde::Serialize, serde::Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum ExplorationTrigger {
    /// J dtheta of the command actually executed (saggriac's reading, the default): a command cut
    /// by `max_joint_step` or a joint limit is not held against the model.
    #[default]
    Executed,
    /// The desired step dx (the paper's epsilon = |realised dx - desired dx|): also triggers where
    /// J+ truncates small singular values or J is rank-deficient (the straight rest pose).
    Desired,
}

impl ExplorationTrigger {
    pub fn parse(s: &str) -> Option<Self> {
        match s {
            "executed" => Some(ExplorationTrigger::Executed),
            "desired" => Some(ExplorationTrigger::Desired),
            _ => None,
        }
    }
    pub fn name(&self) -> &'static str {
        match self {
            ExplorationTrigger::Executed => "executed",
            ExplorationTrigger::Desired => "desired",
        }
    }
}

impl ReachingConfig {
    pub fn validate(&self) -> Result<()> {
        let c = Check { owner: "Reaching" };
        c.positive("v", self.v)?;
        c.at_least("n_subgoals", self.n_subgoals, 1)?;
        c.positive("eps_max", self.eps_max)?;
        c.non_negative("timeout_factor", self.timeout_factor)?;
        c.at_least("timeout_min", self.timeout_min, 1)?;
        Ok(())
    }

    /// Largest number of reaching micro-actions for a target at `distance`.
    pub fn timeout(&self, distance: f64) -> usize {
        (self.timeout_factor * distance / self.v).ceil() as usize + self.timeout_min
    }
}

#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct ExplorationConfig {
    /// Number of random micro-actions per exploration phase.
    pub q: usize,
    /// Half-width of the box around the phase's starting configuration in which the random
    /// configurations are drawn (radians, per joint).
    #[serde(rename = "explore_step")]
    pub step: f64,
}

impl Default for ExplorationConfig {
    fn default() -> Self {
        ExplorationConfig { q: 20, step: 0.01 }
    }
}

impl ExplorationConfig {
    pub fn validate(&self) -> Result<()> {
        let c = Check { owner: "Exploration" };
        c.at_least("q", self.q, 1)?;
        c.positive("explore_step", self.step)?;
        Ok(())
    }
}

#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct EpisodicConfig {
    /// Standard deviation of the Gaussian noise added to every joint of a proposal (rad).
    #[serde(rename = "episodic_noise")]
    pub noise: f64,
    /// Refine the nearest neighbour's configuration with a local linear model.
    #[serde(rename = "episodic_refine")]
    pub refine: bool,
    /// Neighbours (in joint space) of the local linear model used by `refine`.
    #[serde(rename = "episodic_k")]
    pub k_refine: usize,
}

impl Default for EpisodicConfig {
    fn default() -> Self {
        EpisodicConfig { noise: 0.1, refine: false, k_refine: 20 }
    }
}

impl EpisodicConfig {
    pub fn validate(&self, n_joints: usize) -> Result<()> {
        let c = Check { owner: "Episodic" };
        c.non_negative("episodic_noise", self.noise)?;
        c.at_least("episodic_k", self.k_refine, n_joints.min(2))?;
        Ok(())
    }
}

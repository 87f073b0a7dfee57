//! The evaluation's parameters: test set sizes, test reach stopping rules, schedule.

use crate::error::{invalid, Check, Result};

/// Where the forward model is tested (docs/reproduction.md, "What is measured").
#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum TestConfigs {
    /// For each test goal (in order; more goals are drawn if there are more configurations than
    /// goals), the configuration of least joint norm that reaches it within the joint limits.
    IkMinNorm,
    /// Uniform in the joint limits ("joint-space coverage"): curled postures far from anything a
    /// learner visits, so this error measures extrapolation more than learning.
    Uniform,
}

impl TestConfigs {
    pub fn parse(s: &str) -> Option<Self> {
        match s {
            "ik_min_norm" => Some(TestConfigs::IkMinNorm),
            "uniform" => Some(TestConfigs::Uniform),
            _ => None,
        }
    }
    pub fn name(&self) -> &'static str {
        match self {
            TestConfigs::IkMinNorm => "ik_min_norm",
            TestConfigs::Uniform => "uniform",
        }
    }
}

/// Serialised by its `Config` names (`eval_tolerance`, ...).
#[derive(Debug, Clone, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct EvalConfig {
    pub n_test_goals: usize,
    pub n_test_configs: usize,
    pub test_configs: TestConfigs,
    /// A test reach stops once closer than this to its goal.
    #[serde(rename = "eval_tolerance")]
    pub tolerance: f64,
    /// ... or after this many micro-actions without getting closer.
    #[serde(rename = "eval_patience")]
    pub patience: usize,
    /// ... or after ceil(timeout_factor * distance / v) + timeout_min micro-actions.
    #[serde(rename = "eval_timeout_factor")]
    pub timeout_factor: f64,
    #[serde(rename = "eval_timeout_min")]
    pub timeout_min: usize,
    /// Time steps after which to evaluate (sorted, each <= n_steps; 0 = before learning).
    #[serde(rename = "eval_schedule")]
    pub schedule: Vec<u64>,
}

impl Default for EvalConfig {
    fn default() -> Self {
        EvalConfig { n_test_goals: 100, n_test_configs: 100, test_configs: TestConfigs::IkMinNorm, tolerance: 0.01, patience: 10, timeout_factor: 2.0, timeout_min: 20, schedule: vec![] }
    }
}

impl EvalConfig {
    pub fn validate(&self, n_steps: u64) -> Result<()> {
        let c = Check { owner: "Evaluation" };
        c.at_least("n_test_goals", self.n_test_goals, 1)?;
        c.at_least("n_test_configs", self.n_test_configs, 1)?;
        c.positive("eval_tolerance", self.tolerance)?;
        c.at_least("eval_patience", self.patience, 1)?;
        c.non_negative("eval_timeout_factor", self.timeout_factor)?;
        c.at_least("eval_timeout_min", self.timeout_min, 1)?;
        if self.schedule.windows(2).any(|w| w[0] >= w[1]) {
            return Err(invalid("Evaluation", "eval_schedule", "strictly increasing", format!("{:?}", self.schedule)));
        }
        if let Some(&last) = self.schedule.last() {
            if last > n_steps {
                return Err(invalid("Evaluation", "eval_schedule", format!("a list of steps <= n_steps (n_steps = {n_steps})"), last));
            }
        }
        Ok(())
    }
}

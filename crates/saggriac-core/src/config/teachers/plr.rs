//! PLR's parameters (Jiang, Grefenstette & Rocktäschel, ICML 2021).

use serde::{Deserialize, Serialize};

use crate::config::teachers::{Registered, TeacherParams};
use crate::config::rules::{check_fields, COUNT, PROBABILITY, Rule};
use crate::error::Result;

/// How PLR decides between a new level and a replay (P_D).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum ReplaySchedule {
    /// Replay with probability |seen| / n.
    Proportionate,
    /// Replay with probability `replay_prob` once a level is seen, always once all are.
    Fixed,
}

/// What PLR makes of the value `update` is told.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum PlrScore {
    /// A competence: the level's score is |competence - its previous competence|.
    Progress,
    /// The score itself (the paper's value loss, computed by the learner).
    Told,
}

/// How PLR's rank prioritisation ranks levels of equal score.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum PlrTies {
    /// As the authors' code and Syllabus rank (a reversed argsort of every level's score, unseen
    /// levels at 0): tied levels take distinct ranks, the later level in the list first, so one
    /// level of a tied group takes nearly all its mass.
    Order,
    /// Tied levels share the mean of their ranks, taken among the seen levels only (saggriac's
    /// rule before issue 46).
    Average,
}

/// Parameters of Prioritized Level Replay (Jiang, Grefenstette & Rocktäschel, ICML 2021).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct PlrConfig {
    pub n_tasks: usize,
    /// beta, the rank prioritisation's temperature (0.1 in the paper).
    pub temperature: f64,
    /// rho, the staleness share of the replay distribution (0.1 in the paper).
    pub staleness_coef: f64,
    pub replay_schedule: ReplaySchedule,
    /// The replay probability of the `fixed` schedule (0.5, Syllabus's and Robust PLR's).
    pub replay_prob: f64,
    pub score: PlrScore,
    /// How levels of equal score are ranked (`Order`, the authors').
    pub ties: PlrTies,
}

impl Default for PlrConfig {
    /// The paper's beta, rho and schedule; `n_tasks` has no default worth the name (the Python
    /// class requires it), 1 is the least valid.
    fn default() -> Self {
        PlrConfig { n_tasks: 1, temperature: 0.1, staleness_coef: 0.1, replay_schedule: ReplaySchedule::Proportionate, replay_prob: 0.5, score: PlrScore::Progress, ties: PlrTies::Order }
    }
}

impl TeacherParams for PlrConfig {
    const HAS_BOX: bool = false;

    const RULES: &'static [(&'static str, Rule)] = &[
        ("n_tasks", COUNT),
        // rank^(-1/beta) must not underflow to 0 for every rank > 1 too soon: beta >= 0.01.
        ("temperature", Rule::Float { lo: 0.01, lo_in: true, hi: f64::INFINITY, hi_in: false, note: "" }),
        ("staleness_coef", PROBABILITY),
        ("replay_schedule", Rule::Choice),
        ("replay_prob", PROBABILITY),
        ("score", Rule::Choice),
        ("ties", Rule::Choice),
    ];

    fn validate(&self) -> Result<()> {
        let (o, r) = (Self::CLASS, Self::RULES);
        check_fields!(o, r, self, int n_tasks, float temperature, float staleness_coef, float replay_prob);
        Ok(())
    }
}

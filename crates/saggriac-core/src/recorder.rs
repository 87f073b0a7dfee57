//! What a run leaves behind: the rows of the four tables (metrics, goals, attempts; the regions
//! come from the goal selector), the counters and the wall-time split of run.json, and the clock
//! (time steps so far, goals so far). Every part writes here; nothing here changes learning.

use serde::{Deserialize, Serialize};

use crate::high_level::goal_selection::Mode;
use crate::task_space::Point;
pub use crate::timers::Timers;

/// One evaluation point of the learning curve.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct MetricRow {
    pub step: u64,
    pub n_samples: u64,
    pub reach_error: f64,
    pub pred_error: f64,
    /// Mean relative error of the learnt differential model at the test configurations:
    /// |predicted dx - true dx| / |true dx| for each test motion (1 = no better than no motion).
    pub dx_error: f64,
    pub n_goals: u64,
    pub n_regions: u64,
}

/// One self-generated goal.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct GoalRow {
    pub goal_index: u64,
    pub step_start: u64,
    pub step_end: u64,
    pub goal: Point,
    pub start: Point,
    pub end: Point,
    pub mode: Mode,
    pub region: Option<usize>,
    /// Competence of the last attempt (the goal itself), NaN if interrupted by the step budget.
    pub competence: f64,
}

/// One (sub)goal attempt: the measurements given to the high level.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct AttemptRow {
    pub goal_index: u64,
    pub subgoal: u32,
    pub step_end: u64,
    pub target: Point,
    pub end: Point,
    pub competence: f64,
    pub reached: bool,
    pub region: Option<usize>,
}

#[derive(Debug, Clone, Default, PartialEq, Serialize, Deserialize)]
pub struct Counters {
    pub reaching_steps: u64,
    pub exploration_steps: u64,
    pub babbling_steps: u64,
    pub explorations: u64,
    pub fit_failures: u64,
    pub test_steps: u64,
    /// Reaching micro-actions where the exploration trigger's two readings disagree: only the
    /// one against J dtheta of the executed command fires, or only the one against the desired
    /// dx; and the sum of |J dtheta - desired dx| over reaching micro-actions. Counts only.
    /// A checkpoint keeps them apart (checkpoint.rs, `TriggerCounts`), so that the recorder of
    /// a format-5 checkpoint, written before they existed, still decodes.
    #[serde(skip)]
    pub trigger_only_executed: u64,
    #[serde(skip)]
    pub trigger_only_desired: u64,
    #[serde(skip)]
    pub trigger_gap_sum: f64,
}

/// The rows, counters, timers and clock of one run. A checkpoint keeps all of it but the
/// evaluations still running (a checkpoint is taken when none is).
#[derive(Debug, Clone, Default, Serialize, Deserialize)]
pub struct Recorder {
    /// Rows are added only through `Parts` (`record_attempt`, `finish_goal`, the evaluation).
    pub(crate) metrics: Vec<MetricRow>,
    pub(crate) goals: Vec<GoalRow>,
    pub(crate) attempts: Vec<AttemptRow>,
    pub counters: Counters,
    pub timers: Timers,
    /// Time steps so far (micro-actions, or movements in the episodic paradigm).
    pub(crate) steps: u64,
    /// Goals attempted so far (the index of the next goal row).
    pub(crate) goals_done: u64,
    /// Metric rows already shown to the caller of `run`.
    pub(crate) reported: usize,
    /// Metric rows whose evaluation is still running on another thread.
    #[serde(skip)]
    pub(crate) pending: Vec<usize>,
}

impl Recorder {
    pub fn steps(&self) -> u64 {
        self.steps
    }
    pub fn goals_done(&self) -> u64 {
        self.goals_done
    }
    pub fn metrics(&self) -> &[MetricRow] {
        &self.metrics
    }
    pub fn goals(&self) -> &[GoalRow] {
        &self.goals
    }
    pub fn attempts(&self) -> &[AttemptRow] {
        &self.attempts
    }
    /// One more time step has passed.
    pub(crate) fn tick(&mut self) {
        self.steps += 1;
    }
    /// A goal attempt is over: its row closes it and the next goal gets the next index.
    pub(crate) fn goal_done(&mut self, row: GoalRow) {
        self.goals.push(row);
        self.goals_done += 1;
    }

    /// Show `on_eval`, in order, every finished metric row it has not seen yet; false if it
    /// asked to stop.
    pub(crate) fn report(&mut self, on_eval: &mut dyn FnMut(&MetricRow) -> bool) -> bool {
        let mut keep_going = true;
        let finished = self.pending.iter().copied().min().unwrap_or(self.metrics.len());
        while self.reported < finished {
            keep_going &= on_eval(&self.metrics[self.reported]);
            self.reported += 1;
        }
        keep_going
    }
}

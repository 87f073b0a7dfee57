//! What a run leaves behind: the rows of the four tables (metrics, goals, attempts; the regions
//! come from the goal selector), the counters and the wall-time split of run.json, and the clock
//! (time steps so far, goals so far). Every part writes here; nothing here changes learning.

use serde::{Deserialize, Serialize};

use crate::high_level::goal_selection::Mode;
use crate::task_space::Point;
pub use crate::timers::Timers;
use crate::table::{bools, floats, index_or_none, ints, points, Number, Record, Table};
#[cfg(test)]
use crate::table::Column;

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

/// The learning curve: one row per evaluation.
pub fn metric_table(rows: &[MetricRow]) -> Table {
    vec![
        ("step", ints(rows, |r| r.step as i64)),
        ("n_samples", ints(rows, |r| r.n_samples as i64)),
        ("reach_error", floats(rows, |r| r.reach_error)),
        ("pred_error", floats(rows, |r| r.pred_error)),
        ("dx_error", floats(rows, |r| r.dx_error)),
        ("n_goals", ints(rows, |r| r.n_goals as i64)),
        ("n_regions", ints(rows, |r| r.n_regions as i64)),
    ]
}

/// Self-generated goals, points in an `m`-D task space.
pub fn goal_table(rows: &[GoalRow], m: usize) -> Table {
    vec![
        ("goal_index", ints(rows, |r| r.goal_index as i64)),
        ("step_start", ints(rows, |r| r.step_start as i64)),
        ("step_end", ints(rows, |r| r.step_end as i64)),
        ("goal", points(rows, m, |r| &r.goal)),
        ("start", points(rows, m, |r| &r.start)),
        ("end", points(rows, m, |r| &r.end)),
        ("mode", ints(rows, |r| r.mode as i64)),
        ("region", ints(rows, |r| index_or_none(r.region))),
        ("competence", floats(rows, |r| r.competence)),
    ]
}

/// Every (sub)goal attempt and the competence the high level received for it.
pub fn attempt_table(rows: &[AttemptRow], m: usize) -> Table {
    vec![
        ("goal_index", ints(rows, |r| r.goal_index as i64)),
        ("subgoal", ints(rows, |r| r.subgoal as i64)),
        ("step_end", ints(rows, |r| r.step_end as i64)),
        ("target", points(rows, m, |r| &r.target)),
        ("end", points(rows, m, |r| &r.end)),
        ("competence", floats(rows, |r| r.competence)),
        ("reached", bools(rows, |r| r.reached)),
        ("region", ints(rows, |r| index_or_none(r.region))),
    ]
}

impl Recorder {
    /// run.json's profile: micro-action counts and wall time (s) per part of the loop, with the
    /// counts kept by other parts (the ACTUATOR reset period, the model's rejected samples, the
    /// evaluation's time split between neighbour search and fitting).
    pub fn profile(&self, actuator_reset_period: usize, rejected_samples: u64, evaluation_split: (f64, f64)) -> Record {
        use Number::{Count, Float};
        let (c, t) = (&self.counters, &self.timers);
        vec![
            ("reaching_steps", Count(c.reaching_steps)),
            ("exploration_steps", Count(c.exploration_steps)),
            ("babbling_steps", Count(c.babbling_steps)),
            ("actuator_reset_period", Count(actuator_reset_period as u64)),
            ("explorations", Count(c.explorations)),
            ("fit_failures", Count(c.fit_failures)),
            ("test_steps", Count(c.test_steps)),
            ("trigger_only_executed", Count(c.trigger_only_executed)),
            ("trigger_only_desired", Count(c.trigger_only_desired)),
            ("trigger_gap_sum", Float(c.trigger_gap_sum)),
            ("rejected_samples", Count(rejected_samples)),
            ("time_knn", Float(t.knn)),
            ("time_fit", Float(t.fit)),
            ("time_goal_selection", Float(t.goal_selection)),
            ("time_evaluation", Float(t.evaluation)),
            ("time_evaluation_knn", Float(evaluation_split.0)),
            ("time_evaluation_fit", Float(evaluation_split.1)),
            ("time_total", Float(t.total)),
        ]
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn check(t: &Table, n: usize) {
        let mut names: Vec<_> = t.iter().map(|(name, _)| *name).collect();
        assert!(t.iter().all(|(_, c)| c.len() == n), "every column has one value per row");
        names.sort_unstable();
        names.dedup();
        assert_eq!(names.len(), t.len(), "column names are unique");
    }

    #[test]
    fn tables_have_one_value_per_row_and_unique_names() {
        let p = [0.5; crate::task_space::MAX_TASK_DIM];
        let goal = GoalRow { goal_index: 4, step_start: 1, step_end: 9, goal: p, start: p, end: p, mode: Mode::Global, region: None, competence: -0.5 };
        let attempt = AttemptRow { goal_index: 4, subgoal: 2, step_end: 9, target: p, end: p, competence: -0.1, reached: true, region: Some(3) };
        let metric = MetricRow { step: 10, n_samples: 8, reach_error: 0.1, pred_error: 0.2, dx_error: 0.3, n_goals: 1, n_regions: 1 };
        for n in [0, 1, 3] {
            check(&goal_table(&vec![goal.clone(); n], 2), n);
            check(&attempt_table(&vec![attempt.clone(); n], 2), n);
            check(&metric_table(&vec![metric.clone(); n]), n);
        }
        let t = attempt_table(&[attempt], 2);
        assert_eq!(t.iter().find(|(n, _)| *n == "region").unwrap().1, Column::Int(vec![3]));
        assert_eq!(t.iter().find(|(n, _)| *n == "target").unwrap().1, Column::Points { width: 2, values: vec![0.5, 0.5] });
        let t = goal_table(&[goal], 3);
        assert_eq!(t.iter().find(|(n, _)| *n == "region").unwrap().1, Column::Int(vec![-1]), "no region reads -1");
        let names: Vec<_> = Recorder::default().profile(7, 2, (0.0, 0.0)).into_iter().map(|(n, _)| n).collect();
        assert!(names.contains(&"actuator_reset_period") && names.contains(&"time_total"));
    }
}

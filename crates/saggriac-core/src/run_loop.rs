//! The learner: its parts (`parts.rs`), one low-level controller (`low_level/`), and the run
//! loop of the paper's Algorithm 1. Every r goal attempts the body goes back to rest; the high
//! level picks a goal; the low level reaches it (through l subgoals, exploring where its model
//! fails) and tells the high level each competence; evaluations happen at scheduled time steps,
//! inside the micro-action that reaches them.

use std::time::Instant;

use crate::body::Body;
use crate::config::RunConfig;
use crate::evaluation::TestSet;
use crate::high_level::goal_selection::GoalSelector;
use crate::low_level::LowLevel;
use crate::model::memory::SensorimotorMemory;
use crate::model::sensorimotor_model::SensorimotorModel;
use crate::parts::Parts;
use crate::recorder::{AttemptRow, Counters, GoalRow, MetricRow, Recorder};
use crate::timers::Timers;

pub struct Learner {
    pub(crate) cfg: RunConfig,
    pub(crate) parts: Parts,
    pub(crate) low_level: Box<dyn LowLevel>,
    /// The seeds the learner was built with (checked when a checkpoint is restored).
    pub(crate) seeds: (u64, u64),
    /// ACTUATOR conditions: rest reset period (the paper's `max`), reported for every condition.
    pub(crate) actuator_reset: usize,
}

impl Learner {
    /// Algorithm 1, one iteration: back to rest if due, the high level's choice if the low level
    /// wants one, one attempt (which tells the high level what it measured). Evaluations run at
    /// their scheduled steps: inside a micro-action, or after a movement's attempt.
    fn iteration(&mut self) {
        let (parts, low) = (&mut self.parts, &mut self.low_level);
        if low.rest_due(parts) {
            parts.rest();
        }
        let choice = low.asks_high_level().then(|| parts.select());
        low.attempt(choice, parts);
        parts.evaluate_due();
    }

    /// Run until the step budget is spent, evaluating on the schedule. `on_eval` sees each new
    /// metric row and may return false to stop early (e.g. on Ctrl-C, or for a checkpoint).
    pub fn run(&mut self, on_eval: &mut dyn FnMut(&MetricRow) -> bool) -> bool {
        let t0 = Instant::now();
        self.parts.evaluate_due();
        let mut completed = self.parts.recorder_mut().report(on_eval);
        while completed && !self.parts.budget_spent() && !self.parts.failed() {
            for _ in 0..self.low_level.attempts_per_report() {
                if self.parts.budget_spent() || self.parts.failed() {
                    break;
                }
                self.iteration();
            }
            self.parts.collect_evaluations(false);
            completed = self.parts.recorder_mut().report(on_eval);
        }
        // Nothing runs on after a return: a checkpoint taken now holds every row.
        self.parts.collect_evaluations(true);
        if completed {
            completed = self.parts.recorder_mut().report(on_eval);
        }
        self.parts.recorder_mut().timers.total += t0.elapsed().as_secs_f64();
        completed && self.parts.budget_spent()
    }

    pub fn config(&self) -> &RunConfig {
        &self.cfg
    }
    pub fn parts(&self) -> &Parts {
        &self.parts
    }
    /// The (learner, evaluation) seeds this learner was built with.
    pub fn seeds(&self) -> (u64, u64) {
        self.seeds
    }
    pub fn steps(&self) -> u64 {
        self.parts.recorder().steps()
    }
    /// Dimension of the task space.
    pub fn task_dim(&self) -> usize {
        self.parts.model().task_dim()
    }
    pub fn model(&self) -> &SensorimotorModel {
        self.parts.model()
    }
    pub fn memory(&self) -> &SensorimotorMemory {
        self.parts.model().samples()
    }
    pub fn selector(&self) -> &dyn GoalSelector {
        self.parts.selector()
    }
    pub fn recorder(&self) -> &Recorder {
        self.parts.recorder()
    }
    pub fn metrics(&self) -> &[MetricRow] {
        self.parts.recorder().metrics()
    }
    pub fn goals(&self) -> &[GoalRow] {
        self.parts.recorder().goals()
    }
    pub fn attempts(&self) -> &[AttemptRow] {
        self.parts.recorder().attempts()
    }
    pub fn counters(&self) -> &Counters {
        &self.parts.recorder().counters
    }
    pub fn timers(&self) -> &Timers {
        &self.parts.recorder().timers
    }
    pub fn test_set(&self) -> &TestSet {
        &self.parts.evaluator().tests
    }
    /// Seconds of neighbour search and of local fits spent inside evaluations.
    pub fn evaluation_split(&self) -> (f64, f64) {
        (self.parts.evaluator().time_knn, self.parts.evaluator().time_fit)
    }
    /// Rest-reset period of the ACTUATOR conditions (the paper's `max`).
    pub fn actuator_reset_period(&self) -> usize {
        self.actuator_reset
    }
    pub fn body(&self) -> &dyn Body {
        self.parts.body()
    }
    /// A user's body or goal selector failed: the run stops and the binding reports why.
    pub fn failed(&self) -> bool {
        self.parts.failed()
    }
    /// Let evaluations use `threads` threads, this one included (default 1: every evaluation in
    /// this thread). Results do not depend on it.
    pub fn set_threads(&mut self, threads: usize) {
        self.parts.evaluator_mut().set_threads(threads);
    }

    /// Run one evaluation now and record it.
    pub fn evaluate_now(&mut self) -> MetricRow {
        self.parts.evaluate_now()
    }
}

//! The learner: its parts (`parts.rs`), one low-level controller (`low_level/`), and the run
//! loop of the paper's Algorithm 1. Every r goal attempts the body goes back to rest; the high
//! level picks a goal; the low level reaches it (through l subgoals, exploring where its model
//! fails) and tells the high level each competence; evaluations happen at scheduled time steps,
//! inside the micro-action that reaches them.

use std::time::Instant;

use crate::body::arm::Arm;
use crate::body::Body;
use crate::config::{Condition, Paradigm, RunConfig, Teacher};
use crate::error::{invalid, Result};
use crate::evaluation::reachable_cloud::Cloud;
use crate::evaluation::{Evaluator, TestSet};
use crate::high_level::goal_selection::{GoalSelector, RandomGoals, SaggRiac};
use crate::high_level::teachers::alp_gmm::{AlpGmm, AlpGmmConfig};
use crate::high_level::teachers::covar_gmm::{CovarGmm, CovarGmmConfig};
use crate::high_level::teachers::riac::{Riac, RiacConfig};
use crate::low_level::actuator_babbling::{actuator_reset_period, ActuatorBabbling};
use crate::low_level::episodic::Episodic;
use crate::low_level::ssa_reacher::SsaReacher;
use crate::low_level::LowLevel;
use crate::model::memory::SensorimotorMemory;
use crate::model::sensorimotor_model::SensorimotorModel;
use crate::parts::Parts;
use crate::recorder::{AttemptRow, Counters, GoalRow, MetricRow, Recorder, Timers};
use crate::rng::{child_seed, rng_from_seed};

/// Which low-level controller acts under a configuration: one line per controller.
fn low_level_for(cfg: &RunConfig, actuator_reset: usize) -> Box<dyn LowLevel> {
    match (cfg.paradigm, cfg.condition) {
        (Paradigm::Episodic, _) => Box::new(Episodic::new(cfg)),
        (Paradigm::MicroActions, Condition::SaggRiac | Condition::SaggRandom) => Box::new(SsaReacher::new(cfg)),
        (Paradigm::MicroActions, Condition::ActuatorRandom | Condition::ActuatorRiac) => Box::new(ActuatorBabbling::new(cfg, actuator_reset)),
    }
}

/// Parts a user brings instead of the built-in ones (None: the configuration's own).
#[derive(Default)]
pub struct UserParts {
    pub body: Option<Box<dyn Body>>,
    pub selector: Option<Box<dyn GoalSelector>>,
    pub low_level: Option<Box<dyn LowLevel>>,
    /// Positions the user's body reached (with their configurations): test goals come from it
    /// instead of the ball of the configured reach about the origin.
    pub cloud: Option<Cloud>,
}

pub struct Learner {
    pub(crate) cfg: RunConfig,
    pub(crate) parts: Parts,
    pub(crate) low_level: Box<dyn LowLevel>,
    /// The seeds the learner was built with (checked when a checkpoint is restored).
    pub(crate) seeds: (u64, u64),
    /// ACTUATOR conditions: rest reset period (the paper's `max`), reported for every condition.
    actuator_reset: usize,
}

impl Learner {
    /// Algorithm 1, one iteration: back to rest if due, the high level's choice if the low level
    /// wants one, one attempt (which tells the high level what it measured, and evaluates at the
    /// scheduled steps).
    fn iteration(&mut self) {
        let (parts, low) = (&mut self.parts, &mut self.low_level);
        if low.rest_due(parts) {
            parts.rest();
        }
        let choice = low.asks_high_level().then(|| parts.select());
        low.attempt(choice, parts);
    }

    /// Run until the step budget is spent, evaluating on the schedule. `on_eval` sees each new
    /// metric row and may return false to stop early (e.g. on Ctrl-C, or for a checkpoint).
    pub fn run(&mut self, on_eval: &mut dyn FnMut(&MetricRow) -> bool) -> bool {
        let t0 = Instant::now();
        self.parts.evaluate_due();
        let mut completed = self.parts.recorder.report(on_eval);
        while completed && !self.parts.budget_spent() && !self.parts.failed() {
            for _ in 0..self.low_level.attempts_per_report() {
                if self.parts.budget_spent() || self.parts.failed() {
                    break;
                }
                self.iteration();
            }
            self.parts.collect_evaluations(false);
            completed = self.parts.recorder.report(on_eval);
        }
        // Nothing runs on after a return: a checkpoint taken now holds every row.
        self.parts.collect_evaluations(true);
        if completed {
            completed = self.parts.recorder.report(on_eval);
        }
        self.parts.recorder.timers.total += t0.elapsed().as_secs_f64();
        completed && self.parts.budget_spent()
    }

    /// Build a learner. `seed` drives the learner (goal choices, exploration); `eval_seed` draws
    /// the test sets, so every condition of one experiment seed meets the same tests.
    pub fn new(cfg: RunConfig, seed: u64, eval_seed: u64) -> Result<Self> {
        Self::from_parts(cfg, seed, eval_seed, UserParts::default())
    }

    /// A learner acting on `body` (default: the built-in arm of `cfg.arm`) and choosing goals
    /// with `selector` (default: the condition's own). A user's body must have the configured
    /// number of joints; a user's selector replaces the high level of a SAGG condition.
    pub fn with_parts(cfg: RunConfig, seed: u64, eval_seed: u64, body: Option<Box<dyn Body>>, selector: Option<Box<dyn GoalSelector>>) -> Result<Self> {
        Self::from_parts(cfg, seed, eval_seed, UserParts { body, selector, ..UserParts::default() })
    }

    /// A learner with any of its parts replaced, the low-level controller included.
    pub fn from_parts(cfg: RunConfig, seed: u64, eval_seed: u64, user: UserParts) -> Result<Self> {
        let UserParts { body, selector, low_level, cloud } = user;
        cfg.validate()?;
        if body.is_some() && (cfg.arm.motor_noise > 0.0 || cfg.arm.sensor_noise > 0.0) {
            return Err(invalid(
                "Run",
                "motor_noise/sensor_noise",
                "0 when a user's environment is given (add noise in the environment itself)",
                format!("{}/{}", cfg.arm.motor_noise, cfg.arm.sensor_noise),
            ));
        }
        if body.is_some() && cfg.body_change.is_some() {
            return Err(invalid("Run", "body_change_step", "unset when a user's environment is given (change the body in the environment itself)", cfg.body_change.map(|b| b.step).unwrap_or(0)));
        }
        let user_body = body.is_some();
        let mut body: Box<dyn Body> = match body {
            Some(b) => b,
            None => {
                let mut arm = cfg.arm.clone();
                arm.noise_seed = child_seed(seed, 3);
                Box::new(Arm::new(arm)?)
            }
        };
        let n = cfg.arm.link_lengths.len();
        if body.n_joints() != n {
            return Err(invalid("Run", "n_joints", format!("the number of joints of the environment ({})", body.n_joints()), n));
        }
        let m = cfg.goal_low.len();
        if body.task_dim() != m {
            let what = if user_body { "the environment's".to_string() } else { format!("the {}'s", cfg.arm.kind.name().replace('_', " ")) };
            return Err(invalid("Run", "goal_low", format!("a list of {} floats ({what} task space is {}-D)", body.task_dim(), body.task_dim()), format!("{:?}", cfg.goal_low)));
        }
        body.reset();
        let rest_x = body.position();
        if let Some(s) = &selector {
            if !cfg.condition.uses_goals() {
                return Err(invalid("Run", "condition", "'sagg_riac' or 'sagg_random' when a goal selector is given (the ACTUATOR conditions choose no goals)", format!("'{}'", cfg.condition.name())));
            }
            if s.dim() != cfg.goal_low.len() {
                return Err(invalid("Run", "goal_selector", format!("a selector over the {}-D goal space", cfg.goal_low.len()), format!("a {}-D selector", s.dim())));
            }
        }
        let own: Box<dyn GoalSelector> = match cfg.condition {
            Condition::SaggRiac => {
                let (low, high, s) = (&cfg.goal_low, &cfg.goal_high, child_seed(seed, 1));
                match cfg.teacher {
                    Teacher::Own => Box::new(SaggRiac::new(low, high, cfg.tree, cfg.modes, s)?),
                    Teacher::Riac => Box::new(Riac::new(low, high, RiacConfig::default(), s)?),
                    Teacher::AlpGmm => Box::new(AlpGmm::new(low, high, AlpGmmConfig::default(), s)?),
                    Teacher::CovarGmm => Box::new(CovarGmm::new(low, high, CovarGmmConfig::default(), s)?),
                }
            }
            Condition::SaggRandom | Condition::ActuatorRandom => Box::new(RandomGoals::new(&cfg.goal_low, &cfg.goal_high, child_seed(seed, 1))?),
            Condition::ActuatorRiac => {
                // R-IAC's space: joint angles within their limits, commands within the babbling step.
                let (lim, b) = (cfg.arm.joint_limit, cfg.babble_step);
                // Episodic movements are whole configurations: the space is theta alone.
                let dims = if cfg.paradigm == Paradigm::Episodic { n } else { 2 * n };
                let low: Vec<f64> = (0..dims).map(|i| if i < n { -lim } else { -b }).collect();
                let high: Vec<f64> = (0..dims).map(|i| if i < n { lim } else { b }).collect();
                Box::new(SaggRiac::new(&low, &high, cfg.tree, cfg.modes, child_seed(seed, 1))?)
            }
        };
        let selector = selector.unwrap_or(own);
        let actuator_reset = match cfg.actuator_reset_every {
            0 => actuator_reset_period(&cfg, rest_x),
            r => r,
        };
        let tests = TestSet::with_body(&cfg.arm, body.as_mut(), &cfg.goal_low, &cfg.goal_high, &cfg.eval, cfg.exploration.step, eval_seed, cloud.as_ref())?;
        body.reset();
        let evaluator = Evaluator::new(&cfg, tests, body.scratch(), n, m);
        let episodic = cfg.paradigm == Paradigm::Episodic;
        let model = SensorimotorModel::new(&cfg, n, m, episodic, cfg.episodic.refine || cfg.condition == Condition::ActuatorRiac);
        let parts = Parts::new(body, model, selector, rng_from_seed(child_seed(seed, 2)), evaluator, rest_x, cfg.n_steps, cfg.body_change);
        let low_level = low_level.unwrap_or_else(|| low_level_for(&cfg, actuator_reset));
        Ok(Learner { cfg, parts, low_level, seeds: (seed, eval_seed), actuator_reset })
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
        self.parts.recorder.steps()
    }
    /// Dimension of the task space.
    pub fn task_dim(&self) -> usize {
        self.parts.model.task_dim()
    }
    pub fn model(&self) -> &SensorimotorModel {
        &self.parts.model
    }
    pub fn memory(&self) -> &SensorimotorMemory {
        self.parts.model.samples()
    }
    pub fn selector(&self) -> &dyn GoalSelector {
        self.parts.selector.as_ref()
    }
    pub fn recorder(&self) -> &Recorder {
        &self.parts.recorder
    }
    pub fn metrics(&self) -> &[MetricRow] {
        &self.parts.recorder.metrics
    }
    pub fn goals(&self) -> &[GoalRow] {
        &self.parts.recorder.goals
    }
    pub fn attempts(&self) -> &[AttemptRow] {
        &self.parts.recorder.attempts
    }
    pub fn counters(&self) -> &Counters {
        &self.parts.recorder.counters
    }
    pub fn timers(&self) -> &Timers {
        &self.parts.recorder.timers
    }
    pub fn test_set(&self) -> &TestSet {
        &self.parts.evaluator.tests
    }
    /// Seconds of neighbour search and of local fits spent inside evaluations.
    pub fn evaluation_split(&self) -> (f64, f64) {
        (self.parts.evaluator.time_knn, self.parts.evaluator.time_fit)
    }
    /// Rest-reset period of the ACTUATOR conditions (the paper's `max`).
    pub fn actuator_reset_period(&self) -> usize {
        self.actuator_reset
    }
    pub fn body(&self) -> &dyn Body {
        self.parts.body.as_ref()
    }
    /// A user's body or goal selector failed: the run stops and the binding reports why.
    pub fn failed(&self) -> bool {
        self.parts.failed()
    }
    /// Let evaluations use `threads` threads, this one included (default 1: every evaluation in
    /// this thread). Results do not depend on it.
    pub fn set_threads(&mut self, threads: usize) {
        self.parts.evaluator.set_threads(threads);
    }

    /// Run one evaluation now and record it.
    pub fn evaluate_now(&mut self) -> MetricRow {
        self.parts.evaluate_now()
    }
}

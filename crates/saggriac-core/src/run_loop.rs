//! The run loop (paper Algorithm 1): every r goal attempts back to rest; the high level picks a
//! goal; the low level reaches it through l subgoals; each subgoal's competence goes to the high
//! level. Evaluation happens at scheduled time steps, where one time step is one micro-action.

use std::time::Instant;

use serde::{Deserialize, Serialize};

use crate::actuator_babbling::actuator_reset_period;
use crate::arm::Arm;
use crate::body::Body;
use crate::config::{Condition, Paradigm, RunConfig};
use crate::episodic::EpisodicMemory;
use crate::error::{invalid, Result};
use crate::evaluation::{Evaluator, TestSet};
use crate::goal_selection::{GoalSelector, Mode, RandomGoals, SaggRiac};
use crate::local_model::LocalModel;
use crate::memory::SensorimotorMemory;
use crate::neighbours::{Neighbour, WarmStart};
use crate::rng::{child_seed, rng_from_seed, CoreRng};
use crate::task_space::{lerp, point, Point};

#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum ActionKind {
    Reaching,
    Exploration,
    Babbling,
}

/// One evaluation point of the learning curve.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct MetricRow {
    pub step: u64,
    pub n_samples: u64,
    pub reach_error: f64,
    pub pred_error: f64,
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
}

/// Wall time spent in each part, in seconds.
#[derive(Debug, Clone, Default, PartialEq, Serialize, Deserialize)]
pub struct Timers {
    pub knn: f64,
    pub fit: f64,
    pub goal_selection: f64,
    pub evaluation: f64,
    pub total: f64,
}

pub struct Learner {
    pub(crate) cfg: RunConfig,
    pub(crate) body: Box<dyn Body>,
    /// End-effector position at rest (the start of every episodic movement).
    pub(crate) rest_x: Point,
    pub(crate) memory: SensorimotorMemory,
    pub(crate) model: LocalModel,
    pub(crate) selector: Box<dyn GoalSelector>,
    pub(crate) rng: CoreRng,
    pub(crate) warm: WarmStart,
    pub(crate) neighbours: Vec<Neighbour>,
    pub(crate) buf_dtheta: Vec<f64>,
    pub(crate) evaluator: Evaluator,
    pub(crate) steps: u64,
    pub(crate) next_eval: usize,
    pub(crate) goals_done: u64,
    /// The episodic paradigm's memory (None for micro-actions).
    pub(crate) episodic: Option<EpisodicMemory>,
    pub metrics: Vec<MetricRow>,
    pub goals: Vec<GoalRow>,
    pub attempts: Vec<AttemptRow>,
    pub(crate) counters: Counters,
    pub(crate) timers: Timers,
    pub(crate) reported: usize,
    /// The seeds the learner was built with (checked when a checkpoint is restored).
    pub(crate) seeds: (u64, u64),
    buf_theta: Vec<f64>,
    /// ACTUATOR conditions: rest reset period (the paper's `max`) and micro-actions so far.
    pub(crate) actuator_reset: usize,
    pub(crate) babble_steps: u64,
}

impl Learner {
    /// Build a learner. `seed` drives the learner (goal choices, exploration); `eval_seed` draws
    /// the test sets, so every condition of one experiment seed meets the same tests.
    pub fn new(cfg: RunConfig, seed: u64, eval_seed: u64) -> Result<Self> {
        Self::with_parts(cfg, seed, eval_seed, None, None)
    }

    /// A learner acting on `body` (default: the built-in arm of `cfg.arm`) and choosing goals
    /// with `selector` (default: the condition's own). A user's body must have the configured
    /// number of joints; a user's selector replaces the high level of a SAGG condition.
    pub fn with_parts(cfg: RunConfig, seed: u64, eval_seed: u64, body: Option<Box<dyn Body>>, selector: Option<Box<dyn GoalSelector>>) -> Result<Self> {
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
            Condition::SaggRiac => Box::new(SaggRiac::new(&cfg.goal_low, &cfg.goal_high, cfg.tree, cfg.modes, child_seed(seed, 1))?),
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
        let tests = TestSet::with_body(&cfg.arm, body.as_mut(), &cfg.goal_low, &cfg.goal_high, cfg.eval.n_test_goals, cfg.eval.n_test_configs, eval_seed)?;
        body.reset();
        let evaluator = Evaluator::new(cfg.eval.clone(), tests, body.scratch(), n, m, cfg.local.clone(), cfg.reaching.v, cfg.warm_start_recent);
        Ok(Learner {
            memory: SensorimotorMemory::new(n, m, cfg.index),
            model: LocalModel::new(n, m, cfg.local.clone()),
            selector,
            rng: rng_from_seed(child_seed(seed, 2)),
            warm: WarmStart::new(cfg.warm_start_recent),
            neighbours: Vec::new(),
            buf_dtheta: vec![0.0; n],
            evaluator,
            body,
            rest_x,
            steps: 0,
            next_eval: 0,
            goals_done: 0,
            metrics: Vec::new(),
            goals: Vec::new(),
            attempts: Vec::new(),
            counters: Counters::default(),
            timers: Timers::default(),
            reported: 0,
            seeds: (seed, eval_seed),
            buf_theta: vec![0.0; n],
            actuator_reset,
            babble_steps: 0,
            episodic: (cfg.paradigm == Paradigm::Episodic).then(|| EpisodicMemory::new(n, m, cfg.episodic.refine || cfg.condition == Condition::ActuatorRiac)),
            cfg,
        })
    }

    pub fn config(&self) -> &RunConfig {
        &self.cfg
    }
    pub fn steps(&self) -> u64 {
        self.steps
    }
    /// Dimension of the task space.
    pub fn task_dim(&self) -> usize {
        self.memory.task_dim()
    }
    pub fn memory(&self) -> &SensorimotorMemory {
        &self.memory
    }
    pub fn selector(&self) -> &dyn GoalSelector {
        self.selector.as_ref()
    }
    pub fn counters(&self) -> &Counters {
        &self.counters
    }
    pub fn timers(&self) -> &Timers {
        &self.timers
    }
    pub fn test_set(&self) -> &TestSet {
        &self.evaluator.tests
    }
    /// Seconds of neighbour search and of local fits spent inside evaluations.
    pub fn evaluation_split(&self) -> (f64, f64) {
        (self.evaluator.time_knn, self.evaluator.time_fit)
    }
    /// Rest-reset period of the ACTUATOR conditions (the paper's `max`).
    pub fn actuator_reset_period(&self) -> usize {
        self.actuator_reset
    }
    pub fn body(&self) -> &dyn Body {
        self.body.as_ref()
    }

    /// A user's body or goal selector failed: the run stops and the binding reports why.
    pub fn failed(&self) -> bool {
        self.body.failed() || self.selector.failed()
    }

    pub(crate) fn budget_spent(&self) -> bool {
        self.steps >= self.cfg.n_steps
    }

    /// Execute one micro-action on the arm and store it. Returns the realised dx, or None
    /// (without moving) when the step budget is spent.
    pub(crate) fn micro_action(&mut self, dtheta: &mut [f64], kind: ActionKind) -> Option<Point> {
        if self.budget_spent() || self.failed() {
            return None;
        }
        self.buf_theta.copy_from_slice(self.body.theta());
        let x0 = self.body.position();
        let dx = self.body.step(dtheta);
        if self.body.failed() {
            return None;
        }
        let m = self.task_dim();
        self.memory.add(&self.buf_theta, dtheta, &dx[..m], &x0[..m]);
        self.steps += 1;
        self.apply_body_change();
        match kind {
            ActionKind::Reaching => self.counters.reaching_steps += 1,
            ActionKind::Exploration => self.counters.exploration_steps += 1,
            ActionKind::Babbling => self.counters.babbling_steps += 1,
        }
        // Evaluate exactly at the scheduled step; it only reads the memory.
        self.evaluate_due();
        Some(dx)
    }

    /// At the configured step, change the body; the evaluation follows the new body.
    pub(crate) fn apply_body_change(&mut self) {
        if let Some(c) = self.cfg.body_change {
            if self.steps == c.step && self.body.set_link_length(c.link, c.length) {
                self.evaluator.body_changed(self.body.as_mut());
            }
        }
    }

    pub(crate) fn evaluate_due(&mut self) {
        while self.next_eval < self.cfg.eval.schedule.len() && self.cfg.eval.schedule[self.next_eval] <= self.steps {
            self.next_eval += 1;
            self.evaluate_now();
        }
    }

    /// Run one evaluation now and record it.
    pub fn evaluate_now(&mut self) -> MetricRow {
        let t0 = Instant::now();
        let body = self.body.as_mut();
        let r = match self.episodic.as_mut() {
            Some(mem) => self.evaluator.evaluate_episodic(mem, body, &self.cfg.episodic, self.cfg.local.pinv_rcond),
            None => self.evaluator.evaluate(&self.memory, body),
        };
        self.timers.evaluation += t0.elapsed().as_secs_f64();
        self.counters.test_steps += r.test_steps;
        let row = MetricRow {
            step: self.steps,
            n_samples: self.episodic.as_ref().map(|m| m.len()).unwrap_or(self.memory.len()) as u64,
            reach_error: r.mean_reach(),
            pred_error: r.mean_pred(),
            n_goals: self.goals_done,
            n_regions: self.selector.tree().map(|t| t.leaves().len() as u64).unwrap_or(1),
        };
        self.metrics.push(row.clone());
        row
    }

    /// Show the caller every metric row it has not seen yet.
    fn report(&mut self, on_eval: &mut dyn FnMut(&MetricRow) -> bool) -> bool {
        let mut keep_going = true;
        while self.reported < self.metrics.len() {
            keep_going &= on_eval(&self.metrics[self.reported]);
            self.reported += 1;
        }
        keep_going
    }

    /// One goal attempt: rest reset if due, goal choice, l subgoal attempts.
    fn goal_attempt(&mut self) {
        if self.goals_done % self.cfg.reset_every as u64 == 0 {
            self.body.reset();
            self.warm.clear();
        }
        let t0 = Instant::now();
        let choice = self.selector.sample();
        self.timers.goal_selection += t0.elapsed().as_secs_f64();
        let m = self.task_dim();
        let g = point(&choice.goal[..m]);
        let start = self.body.position();
        let step_start = self.steps;
        let l = self.cfg.reaching.n_subgoals;
        let mut last_c = f64::NAN;
        for i in 1..=l {
            // x_i = x_start + (i / l)(x_g - x_start); the last subgoal is the goal itself.
            let f = i as f64 / l as f64;
            let target = if i == l { g } else { lerp(&start, &g, f) };
            let out = self.reach(target);
            if out.interrupted {
                break;
            }
            let t1 = Instant::now();
            let region = self.selector.update(&target[..m], out.competence);
            self.timers.goal_selection += t1.elapsed().as_secs_f64();
            self.attempts.push(AttemptRow { goal_index: self.goals_done, subgoal: i as u32, step_end: self.steps, target, end: out.end, competence: out.competence, reached: out.reached, region });
            if i == l {
                last_c = out.competence;
            }
        }
        self.goals.push(GoalRow {
            goal_index: self.goals_done,
            step_start,
            step_end: self.steps,
            goal: g,
            start,
            end: self.body.position(),
            mode: choice.mode,
            region: choice.region,
            competence: last_c,
        });
        self.goals_done += 1;
    }

    /// Run until the step budget is spent, evaluating on the schedule. `on_eval` sees each new
    /// metric row and may return false to stop early (e.g. on Ctrl-C).
    pub fn run(&mut self, on_eval: &mut dyn FnMut(&MetricRow) -> bool) -> bool {
        let t0 = Instant::now();
        self.evaluate_due();
        let mut completed = self.report(on_eval);
        let goals = self.cfg.condition.uses_goals();
        let episodic = self.cfg.paradigm == Paradigm::Episodic;
        while completed && !self.budget_spent() && !self.failed() {
            if episodic {
                for _ in 0..64 {
                    if self.budget_spent() || self.failed() {
                        break;
                    }
                    self.episode();
                }
            } else if goals {
                self.goal_attempt();
            } else {
                // Babble until the next evaluation report could be due (a goal attempt's worth).
                for _ in 0..64 {
                    if self.budget_spent() || self.failed() {
                        break;
                    }
                    self.babble();
                }
            }
            completed = self.report(on_eval);
        }
        self.timers.total += t0.elapsed().as_secs_f64();
        completed && self.budget_spent()
    }
}

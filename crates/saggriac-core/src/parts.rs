//! The parts a learner is made of, and the path of one micro-action through them. Each part owns
//! its state, and saves and restores it for a checkpoint: the body, the sensorimotor model, the
//! goal selector (high level), the learner's generator, the evaluator and the recorder. A
//! low-level controller acts only through `Parts` (the contract is `crate::low_level::LowLevel`'s):
//! it reads the body and the model, draws from the generator, executes micro-actions (or whole
//! movements) with `micro_action` / `movement`, tells the high level what it measured (`tell`)
//! and records it (`record_attempt`, `finish_goal`).

use std::time::Instant;

use serde::{Deserialize, Serialize};

use crate::body::Body;
use crate::config::BodyChange;
use crate::error::Error;
use crate::evaluation::{Evaluator, EvaluatorStateAs};
use crate::high_level::goal_selection::{GoalChoice, GoalSelector};
use crate::model::local_model::FitFailure;
use crate::model::sensorimotor_model::{ModelState, SensorimotorModel};
use crate::recorder::{AttemptRow, Counters, GoalRow, MetricRow, Recorder};
use crate::timers::Timers;
use crate::rng::CoreRng;
use crate::task_space::Point;

/// What a micro-action was for (counted separately in the recorder).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum ActionKind {
    Reaching,
    Exploration,
    Babbling,
}

pub struct Parts {
    body: Box<dyn Body>,
    model: SensorimotorModel,
    selector: Box<dyn GoalSelector>,
    /// The learner's own draws (exploration, babbling, episodic noise).
    rng: CoreRng,
    evaluator: Evaluator,
    recorder: Recorder,
    /// End-effector position at rest (the start of every episodic movement).
    rest_x: Point,
    budget: u64,
    body_change: Option<BodyChange>,
    /// The configuration before the current micro-action.
    theta_before: Vec<f64>,
    /// The point the high level is told (`tell`).
    told: Vec<f64>,
    /// A controller called the other paradigm's time step: the run stops with this error.
    misuse: Option<Error>,
}

impl Parts {
    #[allow(clippy::too_many_arguments)]
    pub(crate) fn new(
        body: Box<dyn Body>,
        model: SensorimotorModel,
        selector: Box<dyn GoalSelector>,
        rng: CoreRng,
        evaluator: Evaluator,
        rest_x: Point,
        budget: u64,
        body_change: Option<BodyChange>,
    ) -> Self {
        let n = body.n_joints();
        Parts { body, model, selector, rng, evaluator, recorder: Recorder::default(), rest_x, budget, body_change, theta_before: vec![0.0; n], told: Vec::new(), misuse: None }
    }

    pub fn body(&self) -> &dyn Body {
        self.body.as_ref()
    }
    pub fn model(&self) -> &SensorimotorModel {
        &self.model
    }
    pub fn model_mut(&mut self) -> &mut SensorimotorModel {
        &mut self.model
    }
    pub fn selector(&self) -> &dyn GoalSelector {
        self.selector.as_ref()
    }
    pub fn rng(&mut self) -> &mut CoreRng {
        &mut self.rng
    }
    pub fn recorder(&self) -> &Recorder {
        &self.recorder
    }
    pub(crate) fn recorder_mut(&mut self) -> &mut Recorder {
        &mut self.recorder
    }
    /// The counters a controller keeps up (explorations, fit failures, steps by kind).
    pub fn counters_mut(&mut self) -> &mut Counters {
        &mut self.recorder.counters
    }
    /// The wall-time split a controller adds to (time in its own neighbour searches).
    pub fn timers_mut(&mut self) -> &mut Timers {
        &mut self.recorder.timers
    }
    pub fn rest_position(&self) -> Point {
        self.rest_x
    }
    pub fn evaluator(&self) -> &Evaluator {
        &self.evaluator
    }
    pub(crate) fn evaluator_mut(&mut self) -> &mut Evaluator {
        &mut self.evaluator
    }

    /// Every part's state, for a checkpoint. Only built-in bodies and goal selectors can be saved.
    pub(crate) fn save(&self) -> crate::error::Result<PartsState> {
        let refuse = |what: &str| Error::InvalidInput(format!("This run cannot be checkpointed: its {what} is a user's object, whose state saggriac cannot save."));
        Ok(PartsState {
            rng: self.rng.clone(),
            model: self.model.save(),
            selector: self.selector.save().ok_or_else(|| refuse("goal selector"))?,
            body: self.body.save().ok_or_else(|| refuse("environment"))?,
            evaluator: self.evaluator.save(),
            recorder: self.recorder.clone(),
        })
    }

    /// Put every part back in the state `save` recorded; false if the saved selector or body is
    /// not of this run's kind.
    pub(crate) fn restore(&mut self, state: PartsState) -> bool {
        if !self.selector.load(&state.selector) || !self.body.load(&state.body) {
            return false;
        }
        self.model.restore(&state.model);
        self.evaluator.restore(state.evaluator);
        self.rng = state.rng;
        self.recorder = state.recorder;
        true
    }

    /// Record one measurement told to the high level: the attempt at (sub)goal `target`, number
    /// `subgoal` of the current goal, ended at `end` with `competence` (0: reached), taken by
    /// `region`.
    pub fn record_attempt(&mut self, subgoal: u32, target: Point, end: Point, competence: f64, region: Option<usize>) {
        let r = &mut self.recorder;
        r.attempts.push(AttemptRow { goal_index: r.goals_done(), subgoal, step_end: r.steps(), target, end, competence, reached: competence == 0.0, region });
    }

    /// Close the current goal (the high level's `choice`), attempted from time step `step_start`
    /// and position `start`, ended at `end` (as measured then: a body change may follow the
    /// last step); `competence` is the last attempt's (NaN if the budget cut it).
    pub fn finish_goal(&mut self, choice: &GoalChoice, goal: Point, step_start: u64, start: Point, end: Point, competence: f64) {
        let r = &mut self.recorder;
        r.goal_done(GoalRow { goal_index: r.goals_done(), step_start, step_end: r.steps(), goal, start, end, mode: choice.mode, region: choice.region, competence });
    }

    pub fn budget_spent(&self) -> bool {
        self.recorder.steps >= self.budget
    }
    /// A user's body or goal selector failed, or a controller called the other paradigm's time
    /// step: the run stops (the binding reports why; `misuse` says it for a controller).
    pub fn failed(&self) -> bool {
        self.body.failed() || self.selector.failed() || self.misuse.is_some()
    }
    /// Why a controller's call stopped the run, if it did.
    pub fn misuse(&self) -> Option<&Error> {
        self.misuse.as_ref()
    }

    /// Back to the rest pose (not a time step).
    pub fn rest(&mut self) {
        self.body.reset();
        self.model.forget_trajectory();
    }

    /// The high level chooses (timed).
    pub fn select(&mut self) -> GoalChoice {
        let t0 = Instant::now();
        let choice = self.selector.sample();
        self.recorder.timers.goal_selection += t0.elapsed().as_secs_f64();
        choice
    }

    /// Let the high level choose one of `candidates` (None: it cannot choose).
    pub fn choose(&mut self, candidates: &[Vec<f64>]) -> Option<GoalChoice> {
        let t0 = Instant::now();
        let choice = self.selector.choose(candidates);
        self.recorder.timers.goal_selection += t0.elapsed().as_secs_f64();
        choice
    }

    /// Give the high level the competence measured at `point`; returns the region that took it.
    /// A subgoal on the way from a start outside the selector's box lies outside it too: the
    /// selector is told the nearest point of its box (every selector, a user's included, is told
    /// points of its own space).
    pub fn tell(&mut self, point: &[f64], competence: f64) -> Option<usize> {
        let t0 = Instant::now();
        let (low, high) = (self.selector.low(), self.selector.high());
        self.told.clear();
        self.told.extend(point.iter().zip(low.iter().zip(high)).map(|(v, (l, h))| v.clamp(*l, *h)));
        let region = self.selector.update(&self.told, competence);
        self.recorder.timers.goal_selection += t0.elapsed().as_secs_f64();
        region
    }

    /// Fit the local model at the body's configuration (timed).
    pub fn fit_here(&mut self) -> Result<(), FitFailure> {
        self.model.fit_at(self.body.theta(), &mut self.recorder.timers)
    }

    /// The inverse model at the body's configuration: dtheta = J+ dx (timed).
    pub fn inverse_here(&mut self, dx: &Point, dtheta: &mut [f64]) -> Result<(), FitFailure> {
        self.model.inverse(self.body.theta(), dx, dtheta, &mut self.recorder.timers)
    }

    /// Execute one micro-action on the body and store it. Returns the realised dx, or None
    /// (without moving) when the step budget is spent or a user's part failed.
    pub fn micro_action(&mut self, dtheta: &mut [f64], kind: ActionKind) -> Option<Point> {
        if self.budget_spent() || self.failed() {
            return None;
        }
        if self.model.episodes().is_some() {
            self.misuse = Some(Error::InvalidInput("Parts::micro_action was called in a run of the episodic paradigm, whose time step is Parts::movement: the controller does not fit the run's paradigm.".into()));
            return None;
        }
        self.theta_before.copy_from_slice(self.body.theta());
        let x0 = self.body.position();
        let dx = self.body.step(dtheta);
        if self.body.failed() {
            return None;
        }
        let m = self.model.task_dim();
        self.model.store(&self.theta_before, dtheta, &dx[..m], &x0[..m]);
        self.tick();
        let c = &mut self.recorder.counters;
        match kind {
            ActionKind::Reaching => c.reaching_steps += 1,
            ActionKind::Exploration => c.exploration_steps += 1,
            ActionKind::Babbling => c.babbling_steps += 1,
        }
        // Evaluate exactly at the scheduled step; it only reads the model.
        self.evaluate_due();
        Some(dx)
    }

    /// The episodic paradigm's time step: put the body in `theta` at once and store the movement.
    /// Returns the position reached. An evaluation due now runs after the attempt (the run loop
    /// calls `evaluate_due`), so that its row counts this goal and what the high level was told.
    /// An error, which also stops the run, in a run of the micro-action paradigm.
    pub fn movement(&mut self, theta: &[f64]) -> crate::error::Result<Point> {
        if self.model.episodes().is_none() {
            let e = Error::InvalidInput("Parts::movement was called in a run of the micro-action paradigm, whose time step is Parts::micro_action: the controller does not fit the run's paradigm.".into());
            self.misuse = Some(e.clone());
            return Err(e);
        }
        self.body.set_theta(theta);
        let x = self.body.position();
        let m = self.model.task_dim();
        self.model.store_movement(self.body.theta(), &x[..m]);
        self.tick();
        Ok(x)
    }

    /// One time step has passed; at the configured step the body changes, and the evaluation
    /// follows the new body.
    fn tick(&mut self) {
        self.recorder.tick();
        if let Some(c) = self.body_change {
            if self.recorder.steps == c.step && self.body.set_link_length(c.link, c.length) {
                self.evaluator.body_changed(self.body.as_mut());
            }
        }
    }

    /// Run every evaluation scheduled at or before the current time step (on another thread
    /// when the evaluator can: its row is filled in when it is done).
    pub fn evaluate_due(&mut self) {
        while self.evaluator.due(self.recorder.steps) {
            if self.evaluator.can_run_elsewhere(&self.model.view()) {
                let index = self.recorder.metrics.len();
                self.recorder.metrics.push(self.row(f64::NAN, f64::NAN, f64::NAN));
                self.recorder.pending.push(index);
                self.evaluator.start(index, self.model.view());
            } else {
                self.evaluate_now();
            }
        }
    }

    /// Fill in the rows of the evaluations finished on other threads; with `wait`, of all.
    pub(crate) fn collect_evaluations(&mut self, wait: bool) {
        for f in self.evaluator.finished(wait) {
            let row = &mut self.recorder.metrics[f.index];
            row.reach_error = f.result.mean_reach();
            row.pred_error = f.result.mean_pred();
            row.dx_error = f.result.mean_dx();
            self.recorder.counters.test_steps += f.result.test_steps;
            self.recorder.timers.evaluation += f.seconds;
            self.recorder.pending.retain(|&i| i != f.index);
        }
    }

    /// The metric row of an evaluation now, with its errors.
    fn row(&self, reach_error: f64, pred_error: f64, dx_error: f64) -> MetricRow {
        MetricRow {
            step: self.recorder.steps,
            n_samples: self.model.len() as u64,
            reach_error,
            pred_error,
            dx_error,
            n_goals: self.recorder.goals_done,
            n_regions: self.selector.tree().map(|t| t.leaves().len() as u64).unwrap_or(1),
        }
    }

    /// Run one evaluation now, in this thread, and record it (after those still running).
    pub fn evaluate_now(&mut self) -> MetricRow {
        self.collect_evaluations(true);
        let t0 = Instant::now();
        let r = self.evaluator.evaluate(self.model.view(), self.body.as_mut());
        self.recorder.timers.evaluation += t0.elapsed().as_secs_f64();
        self.recorder.counters.test_steps += r.test_steps;
        let row = self.row(r.mean_reach(), r.mean_pred(), r.mean_dx());
        self.recorder.metrics.push(row.clone());
        row
    }
}

/// Every part's state in a checkpoint (the low-level controller's is beside it). `Body` is how
/// the body's state is held: its own bytes (`Body::save`), or for a checkpoint of format 5 an
/// arm's state inline (`crate::body::arm::InlineState`).
#[derive(Serialize, Deserialize)]
pub(crate) struct PartsStateAs<Body> {
    rng: CoreRng,
    model: ModelState,
    /// The selector's own encoding of its state.
    selector: Vec<u8>,
    body: Body,
    evaluator: EvaluatorStateAs<Body>,
    recorder: Recorder,
}

pub(crate) type PartsState = PartsStateAs<Vec<u8>>;

impl<B: Into<Vec<u8>>> PartsStateAs<B> {
    /// The same state with the body's bytes as `Body::save` writes them today.
    pub(crate) fn upgraded(self) -> PartsState {
        let PartsStateAs { rng, model, selector, body, evaluator, recorder } = self;
        PartsStateAs { rng, model, selector, body: body.into(), evaluator: evaluator.upgraded(), recorder }
    }
}

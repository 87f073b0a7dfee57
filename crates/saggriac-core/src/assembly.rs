//! Assembly: the one place where a run's parts are chosen and built from its configuration (the
//! body, the high level's teacher, the test sets and evaluator, the model, the low-level
//! controller), or taken from the user (`UserParts`). The teacher of a run is a `TeacherSpec`,
//! built by the same code as an ask/tell teacher.

use crate::body::arm::Arm;
use crate::body::Body;
use crate::config::teachers::{RandomConfig, SaggRiacConfig, Teacher};
use crate::config::{Condition, Paradigm, RunConfig};
use crate::error::{invalid, Num, Result};
use crate::evaluation::reachable_cloud::Cloud;
use crate::evaluation::{Evaluator, TestSet};
use crate::high_level::goal_selection::GoalSelector;
use crate::high_level::teachers::TeacherSpec;
use crate::low_level::actuator_babbling::{actuator_reset_period, ActuatorBabbling};
use crate::low_level::episodic::Episodic;
use crate::low_level::ssa_reacher::SsaReacher;
use crate::low_level::LowLevel;
use crate::model::sensorimotor_model::SensorimotorModel;
use crate::parts::Parts;
use crate::rng::{child_seed, rng_from_seed};
use crate::run_loop::Learner;

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

/// The teacher a run's own high level is: by condition, and for `sagg_riac` by `cfg.teacher` (with
/// its parameters);
/// seeded with stream 1 of the learner's seed.
pub fn run_teacher(cfg: &RunConfig, seed: u64) -> TeacherSpec {
    let (low, high, seed) = (cfg.goal_low.clone(), cfg.goal_high.clone(), child_seed(seed, 1));
    let own = Teacher::SaggRiac(SaggRiacConfig { tree: cfg.tree, modes: cfg.modes, mode3: cfg.mode3 });
    let teacher = match cfg.condition {
        Condition::SaggRiac => cfg.teacher.unwrap_or(own),
        Condition::SaggRandom | Condition::ActuatorRandom => Teacher::Random(RandomConfig {}),
        Condition::ActuatorRiac => {
            // R-IAC's space: joint angles within their limits, commands within the babbling step.
            let (n, lim, b) = (cfg.arm.link_lengths.len(), cfg.arm.joint_limit, cfg.babble_step);
            // Episodic movements are whole configurations: the space is theta alone.
            let dims = if cfg.paradigm == Paradigm::Episodic { n } else { 2 * n };
            let low: Vec<f64> = (0..dims).map(|i| if i < n { -lim } else { -b }).collect();
            let high: Vec<f64> = (0..dims).map(|i| if i < n { lim } else { b }).collect();
            return TeacherSpec { teacher: own, low, high, seed, dims: Default::default() };
        }
    };
    TeacherSpec { teacher, low, high, seed, dims: Default::default() }
}

impl Learner {
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
                format!("{}/{}", Num(cfg.arm.motor_noise), Num(cfg.arm.sensor_noise)),
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
        let own = run_teacher(&cfg, seed).build()?;
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
}

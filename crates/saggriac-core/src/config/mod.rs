//! The full configuration of one run, validated in one place. A leaf: plain data and its rules,
//! importing no component (each component's parameters sit in a submodule and are re-exported
//! by the component that reads them).

pub mod body;
pub mod evaluation;
pub mod high_level;
pub mod low_level;
pub mod model;
pub mod rules;
pub mod teachers;

pub use body::{ArmConfig, ArmKind, BodyChange};
pub use evaluation::EvalConfig;
pub use high_level::{check_bounds, check_bounds_named, CompetenceConfig, InterestDivisor, Mode3Config, Mode3Reading, ModeProbabilities, RegionTreeConfig};
pub use teachers::{SaggRiacConfig, Teacher};
pub use low_level::{EpisodicConfig, ExplorationConfig, ExplorationTrigger, ReachingConfig};
pub use model::{IndexKind, LocalModelConfig, MIN_RCOND};

use crate::error::{invalid, Check, Num, Result};
use crate::task_space::MAX_TASK_DIM;

/// The experimental conditions of the paper.
#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Condition {
    /// Goals chosen by competence progress over the region tree.
    SaggRiac,
    /// Same low level, goals uniform in the goal space.
    SaggRandom,
    /// Small random dtheta at every step (motor babbling).
    ActuatorRandom,
    /// R-IAC over (theta, dtheta), interest from the forward model's prediction error.
    ActuatorRiac,
}

impl Condition {
    pub fn parse(s: &str) -> Result<Self> {
        match s {
            "sagg_riac" => Ok(Condition::SaggRiac),
            "sagg_random" => Ok(Condition::SaggRandom),
            "actuator_random" => Ok(Condition::ActuatorRandom),
            "actuator_riac" => Ok(Condition::ActuatorRiac),
            _ => Err(invalid("Run", "condition", "one of 'sagg_riac', 'sagg_random', 'actuator_random', 'actuator_riac'", format!("'{s}'"))),
        }
    }
    pub fn name(&self) -> &'static str {
        match self {
            Condition::SaggRiac => "sagg_riac",
            Condition::SaggRandom => "sagg_random",
            Condition::ActuatorRandom => "actuator_random",
            Condition::ActuatorRiac => "actuator_riac",
        }
    }
    /// Whether the condition explores with goals in the task space (the SAGG conditions).
    pub fn uses_goals(&self) -> bool {
        matches!(self, Condition::SaggRiac | Condition::SaggRandom)
    }
}

/// How the low level acts (see `low_level/episodic.rs`).
#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Paradigm {
    /// The paper's: goals reached through subgoals by micro-actions; one step = one micro-action.
    MicroActions,
    /// One whole configuration per goal, executed at once; one step = one movement.
    Episodic,
}

impl Paradigm {
    pub fn parse(s: &str) -> Result<Self> {
        match s {
            "micro_actions" => Ok(Paradigm::MicroActions),
            "episodic" => Ok(Paradigm::Episodic),
            _ => Err(invalid("Run", "paradigm", "one of 'micro_actions', 'episodic'", format!("'{s}'"))),
        }
    }
    pub fn name(&self) -> &'static str {
        match self {
            Paradigm::MicroActions => "micro_actions",
            Paradigm::Episodic => "episodic",
        }
    }
}

/// Serialised flat, by the names of Python's `Config` (each part's fields in its place, renamed
/// where two parts share a name). The body (`arm`, `body_change`) and the teacher are given in
/// `Config` by other keys than their fields (`n_joints`, `arm_length`, `teacher_params`...):
/// they are left to the caller (`#[serde(skip)]`), which sets them from those keys.
#[derive(Debug, Clone, PartialEq, serde::Serialize, serde::Deserialize)]
#[serde(default)]
pub struct RunConfig {
    #[serde(skip)]
    pub body_change: Option<BodyChange>,
    pub condition: Condition,
    pub paradigm: Paradigm,
    #[serde(flatten)]
    pub episodic: EpisodicConfig,
    pub n_steps: u64,
    #[serde(skip)]
    pub arm: ArmConfig,
    pub goal_low: Vec<f64>,
    pub goal_high: Vec<f64>,
    #[serde(flatten)]
    pub reaching: ReachingConfig,
    #[serde(flatten)]
    pub exploration: ExplorationConfig,
    #[serde(flatten)]
    pub local: LocalModelConfig,
    #[serde(flatten)]
    pub competence: CompetenceConfig,
    #[serde(flatten)]
    pub tree: RegionTreeConfig,
    #[serde(flatten)]
    pub modes: ModeProbabilities,
    #[serde(flatten)]
    pub mode3: Mode3Config,
    /// Who chooses the goals of the goal-babbling condition in place of its own high level
    /// (None, `Config`'s "own": SAGG-RIAC's, set by `tree` and `modes`).
    #[serde(skip)]
    pub teacher: Option<Teacher>,
    /// The arm returns to rest every `reset_every` goal attempts (paper: r = 2).
    pub reset_every: usize,
    #[serde(flatten)]
    pub eval: EvalConfig,
    #[serde(rename = "knn_index")]
    pub index: IndexKind,
    /// Newest samples added to the warm-start candidates of the neighbour search (0 = cold search).
    pub warm_start_recent: usize,
    /// ACTUATOR conditions: each joint moves by a value uniform in [-babble_step, babble_step].
    pub babble_step: f64,
    /// ACTUATOR-RIAC: candidate commands drawn at each step, among which R-IAC chooses in the
    /// current configuration's context; 0 = the earlier variant, where the region tree proposes
    /// a (theta, dtheta) anywhere and only its dtheta is executed.
    pub actuator_candidates: usize,
    /// ACTUATOR conditions: back to rest every this many micro-actions (0 = the paper's `max`,
    /// computed from the goal space, see `actuator_babbling`).
    pub actuator_reset_every: usize,
}

impl Default for RunConfig {
    fn default() -> Self {
        RunConfig {
            condition: Condition::SaggRiac,
            body_change: None,
            paradigm: Paradigm::MicroActions,
            episodic: EpisodicConfig::default(),
            n_steps: 50_000,
            arm: ArmConfig::uniform(15, body::DEFAULT_ARM_LENGTH, std::f64::consts::FRAC_PI_2, 0.05),
            goal_low: vec![0.0, -50.0],
            goal_high: vec![50.0, 50.0],
            reaching: ReachingConfig::default(),
            exploration: ExplorationConfig::default(),
            local: LocalModelConfig::default(),
            competence: CompetenceConfig::default(),
            tree: RegionTreeConfig::default(),
            modes: ModeProbabilities::default(),
            mode3: Mode3Config::default(),
            teacher: None,
            reset_every: 2,
            eval: EvalConfig::default(),
            index: IndexKind::Blocks,
            warm_start_recent: 8,
            babble_step: 0.02,
            actuator_candidates: 16,
            actuator_reset_every: 0,
        }
    }
}

/// A neighbour count up to this is taken whatever n_steps is (short test runs keep the defaults).
pub const MIN_NEIGHBOUR_BOUND: u64 = 1000;

impl RunConfig {
    /// Sizes bounded by what the run can use: neighbour counts by the samples the memory can
    /// hold (one per time step), lengths by the diameter of the body's reachable ball.
    fn check_sizes(&self) -> Result<()> {
        // One rule text for a value too small or too large (checked before the parts' own rules).
        let most = self.n_steps.max(MIN_NEIGHBOUR_BOUND);
        let neighbours = [("LocalModel", "k_neighbours", self.local.k_neighbours, 1), ("Episodic", "episodic_k", self.episodic.k_refine, self.arm.link_lengths.len().min(2))];
        for (owner, name, k, least) in neighbours {
            if k < least || k as u64 > most {
                let rule = format!("an int in [{least}, max(n_steps, {MIN_NEIGHBOUR_BOUND})] (the memory holds at most one sample per time step; n_steps = {})", self.n_steps);
                return Err(invalid(owner, name, rule, k));
            }
        }
        let reach: f64 = self.arm.link_lengths.iter().sum();
        let lengths = [("Reaching", "v", self.reaching.v), ("Reaching", "eps_max", self.reaching.eps_max), ("Evaluation", "eval_tolerance", self.eval.tolerance)];
        for (owner, name, value) in lengths {
            if !(value > 0.0 && value <= 2.0 * reach) {
                let rule = format!("a finite float > 0 and <= 2 * reach, the diameter of the ball the body reaches (reach = {})", crate::error::G(reach));
                return Err(invalid(owner, name, rule, Num(value)));
            }
        }
        Ok(())
    }

    pub fn validate(&self) -> Result<()> {
        let c = Check { owner: "Run" };
        if self.n_steps == 0 {
            return Err(invalid("Run", "n_steps", "an int >= 1", 0));
        }
        self.arm.validate()?;
        if !(1..=MAX_TASK_DIM).contains(&self.goal_low.len()) {
            return Err(invalid(
                "Run",
                "goal_low",
                format!("a list of 1 to {MAX_TASK_DIM} floats (the run loop's task spaces have at most {MAX_TASK_DIM} dimensions)"),
                format!("{:?}", self.goal_low),
            ));
        }
        check_bounds_named("Run", "goal_low/goal_high", &self.goal_low, &self.goal_high)?;
        self.check_sizes()?;
        self.reaching.validate()?;
        self.exploration.validate()?;
        self.local.validate()?;
        self.competence.validate()?;
        self.tree.validate()?;
        self.modes.validate()?;
        self.mode3.validate()?;
        c.at_least("reset_every", self.reset_every, 1)?;
        if let Some(t) = &self.teacher {
            self.validate_teacher(t)?;
        }
        c.positive("babble_step", self.babble_step)?;
        self.eval.validate(self.n_steps)?;
        self.episodic.validate(self.arm.link_lengths.len())?;
        if let Some(b) = self.body_change {
            if self.arm.kind == body::ArmKind::Chain {
                return Err(invalid("Run", "body_change_step", "none for body 'chain' (its links cannot change length)", b.step));
            }
            let n = self.arm.link_lengths.len();
            if b.link >= n {
                return Err(invalid("Run", "body_change_link", format!("an int in [0, {n}) (a link of the {n}-joint arm)"), b.link));
            }
            c.positive("body_change_length", b.length)?;
            if b.step == 0 || b.step > self.n_steps {
                return Err(invalid("Run", "body_change_step", format!("an int in [1, n_steps] (n_steps = {})", self.n_steps), b.step));
            }
        }
        Ok(())
    }

    /// A teacher replacing the high level of the goal-babbling condition: its rules, and
    /// SAGG-RIAC's own parameters left at their defaults (they would be ignored without a word).
    fn validate_teacher(&self, t: &Teacher) -> Result<()> {
        if self.condition != Condition::SaggRiac {
            return Err(invalid(
                "Run",
                "teacher",
                format!("'own' unless condition is 'sagg_riac' (the goal-babbling condition a teacher replaces the high level of; condition is '{}')", self.condition.name()),
                format!("'{}'", t.kind()),
            ));
        }
        if !t.has_box() {
            return Err(invalid("Run", "teacher", "'own' or a teacher of goals in a box (a run's goals are points of the goal space)", format!("'{}'", t.kind())));
        }
        t.validate()?;
        t.check_competences(self.competence.min_c, 0.0, "a run tells (min_c to 0)")?;
        // The whole parameter set, by name: a parameter added to SAGG-RIAC's is checked too.
        let flat = |c: SaggRiacConfig| teachers::flat_params(&c);
        let (own, default) = (flat(SaggRiacConfig { tree: self.tree, modes: self.modes, mode3: self.mode3 }), flat(SaggRiacConfig::default()));
        if let Some((name, value)) = own.iter().zip(&default).find(|(a, b)| a != b).map(|(a, _)| a) {
            return Err(invalid(
                "Run",
                name,
                format!("left at its default with teacher '{}' (it sets SAGG-RIAC's own high level, which that teacher replaces; set that teacher's parameters with teacher_params, those of saggriac.{})", t.kind(), t.class()),
                value,
            ));
        }
        Ok(())
    }
}

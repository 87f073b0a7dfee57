//! The teachers (`crate::high_level::teachers`) as data: one enum naming each teacher with its
//! parameters, with their papers' defaults and their rules. Python's classes, `Config`'s
//! `teacher_params` and the ask/tell constructor all go through this one declaration.

use serde::{Deserialize, Serialize};

use crate::config::high_level::{ModeProbabilities, RegionTreeConfig};
use crate::error::{invalid, Check, Num, Result, MAX_COUNT};

pub use crate::config::rules::param_rule;
use crate::config::rules::{check_int, float_rule};

#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct RiacConfig {
    /// Measurements a leaf holds before it is split (200 in Portelas et al.).
    pub max_region_size: usize,
    /// Random cuts tried per split (50).
    pub split_attempts: usize,
    /// Least share of the leaf's measurements in each child (1/4).
    pub min_child_share: f64,
    /// Least width of a child in every dimension, as a share of the initial range (1/6).
    pub min_dims_range_ratio: f64,
    /// Share of goals from a leaf drawn by ALP, uniform in it (0.7).
    pub p_alp: f64,
    /// Share of goals uniform in the whole box (0.2); the rest go near a leaf's worst goal.
    pub p_random: f64,
}

impl Default for RiacConfig {
    fn default() -> Self {
        RiacConfig { max_region_size: 200, split_attempts: 50, min_child_share: 0.25, min_dims_range_ratio: 1.0 / 6.0, p_alp: 0.7, p_random: 0.2 }
    }
}

impl RiacConfig {
    pub fn validate(&self) -> Result<()> {
        let c = Check { owner: "RiacSelector" };
        check_int(&c, "max_region_size", self.max_region_size)?;
        check_int(&c, "split_attempts", self.split_attempts)?;
        if !(self.min_child_share.is_finite() && self.min_child_share > 0.0 && self.min_child_share <= 0.5) {
            return Err(invalid("RiacSelector", "min_child_share", float_rule("min_child_share"), Num(self.min_child_share)));
        }
        if !(self.min_dims_range_ratio.is_finite() && self.min_dims_range_ratio > 0.0 && self.min_dims_range_ratio <= 0.5) {
            return Err(invalid("RiacSelector", "min_dims_range_ratio", float_rule("min_dims_range_ratio"), Num(self.min_dims_range_ratio)));
        }
        c.probability("p_alp", self.p_alp)?;
        c.probability("p_random", self.p_random)?;
        if self.p_alp + self.p_random > 1.0 + 1e-12 {
            return Err(invalid("RiacSelector", "p_alp", format!("a float with p_alp + p_random <= 1 (p_random = {})", Num(self.p_random)), Num(self.p_alp)));
        }
        Ok(())
    }
}

/// The parameters both mixture teachers share (ALP-GMM's names and defaults).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct AlpGmmConfig {
    /// Tasks between refits, and the window they are fitted on (250).
    pub fit_rate: usize,
    /// Mixtures of 2 to this many components are tried (10).
    pub max_components: usize,
    /// Share of uniform goals after the bootstrap (0.2).
    pub random_task_ratio: f64,
    /// Uniform goals first (250, as fit_rate).
    pub bootstrap: usize,
}

impl Default for AlpGmmConfig {
    fn default() -> Self {
        AlpGmmConfig { fit_rate: 250, max_components: 10, random_task_ratio: 0.2, bootstrap: 250 }
    }
}

impl AlpGmmConfig {
    pub fn validate(&self, owner: &'static str) -> Result<()> {
        let c = Check { owner };
        check_int(&c, "fit_rate", self.fit_rate)?;
        check_int(&c, "max_components", self.max_components)?;
        check_int(&c, "bootstrap", self.bootstrap)?;
        c.probability("random_task_ratio", self.random_task_ratio)?;
        if self.max_components > self.fit_rate {
            return Err(invalid(owner, "max_components", format!("an int <= fit_rate (fit_rate = {})", self.fit_rate), self.max_components));
        }
        Ok(())
    }
}

impl CovarGmmConfig {
    pub fn validate(&self) -> Result<()> {
        self.mixture.validate("CovarGmmSelector")
    }
}

#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct CovarGmmConfig {
    /// Window, refit period, number of components, random share and bootstrap, as ALP-GMM's.
    pub mixture: AlpGmmConfig,
    /// Draw components by |progress| (true) or by positive progress only.
    pub absolute_lp: bool,
}

impl Default for CovarGmmConfig {
    fn default() -> Self {
        CovarGmmConfig { mixture: AlpGmmConfig::default(), absolute_lp: true }
    }
}

/// Parameters of the discrete learning-progress teacher.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct DiscreteLpConfig {
    pub n_tasks: usize,
    /// Step of both moving averages (the paper's and Syllabus's 0.1).
    pub alpha: f64,
    /// theta of the reweighting (0.1 in the paper); 0.5 makes r the identity.
    pub theta: f64,
}

impl Default for DiscreteLpConfig {
    /// The paper's alpha and theta; `n_tasks` has no default worth the name (the Python class
    /// requires it), 1 is the least valid.
    fn default() -> Self {
        DiscreteLpConfig { n_tasks: 1, alpha: 0.1, theta: 0.1 }
    }
}

impl DiscreteLpConfig {
    pub fn validate(&self) -> Result<()> {
        let c = Check { owner: "DiscreteLpSelector" };
        c.within("n_tasks", self.n_tasks, 1, MAX_COUNT)?;
        c.in_open_closed("alpha", self.alpha, 0.0, 1.0)?;
        if !(self.theta.is_finite() && self.theta > 0.0 && self.theta < 1.0) {
            return Err(invalid("DiscreteLpSelector", "theta", "a float in (0, 1)", Num(self.theta)));
        }
        Ok(())
    }
}

/// Parameters of Automatic Domain Randomization (Akkaya et al., 2019, Algorithm 1).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct AdrConfig {
    /// p_b: the share of goals with one dimension set to one of its bounds (the paper's 0.5).
    pub boundary_prob: f64,
    /// m: the boundary performances averaged before a bound moves (TeachMyAgent's 10; the paper
    /// sets it per experiment).
    pub buffer_size: usize,
    /// t_L: a mean competence at a bound <= t_low moves it inwards. Competence units.
    pub t_low: f64,
    /// t_H: a mean competence at a bound >= t_high moves it outwards. Competence units.
    pub t_high: f64,
    /// Delta: how far a bound moves, as a share of its dimension's width.
    pub step: f64,
    /// Where the initial region sits in each dimension, as a share of its width from low: 0.5
    /// is the box's centre, 0 its low corner.
    pub initial: f64,
    /// The initial region's width, as a share of each dimension's width: 0 (the default) is the
    /// paper's single initial value.
    pub initial_width: f64,
}

impl Default for AdrConfig {
    fn default() -> Self {
        AdrConfig { boundary_prob: 0.5, buffer_size: 10, t_low: 0.2, t_high: 0.8, step: 0.05, initial: 0.5, initial_width: 0.0 }
    }
}

impl AdrConfig {
    pub fn validate(&self) -> Result<()> {
        let c = Check { owner: "AdrSelector" };
        c.probability("boundary_prob", self.boundary_prob)?;
        c.within("buffer_size", self.buffer_size, 1, MAX_COUNT)?;
        for (name, v) in [("t_low", self.t_low), ("t_high", self.t_high)] {
            if !(v.is_finite() && v.abs() <= 1e100) {
                return Err(invalid("AdrSelector", name, "a finite float with |value| <= 1e100", Num(v)));
            }
        }
        if self.t_low >= self.t_high {
            return Err(invalid("AdrSelector", "t_low", format!("a float < t_high (t_high = {})", Num(self.t_high)), Num(self.t_low)));
        }
        c.in_open_closed("step", self.step, 0.0, 1.0)?;
        c.probability("initial", self.initial)?;
        c.probability("initial_width", self.initial_width)?;
        Ok(())
    }
}

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
}

impl Default for PlrConfig {
    /// The paper's beta, rho and schedule; `n_tasks` has no default worth the name (the Python
    /// class requires it), 1 is the least valid.
    fn default() -> Self {
        PlrConfig { n_tasks: 1, temperature: 0.1, staleness_coef: 0.1, replay_schedule: ReplaySchedule::Proportionate, replay_prob: 0.5, score: PlrScore::Progress }
    }
}

impl PlrConfig {
    pub fn validate(&self) -> Result<()> {
        let c = Check { owner: "PlrSelector" };
        c.within("n_tasks", self.n_tasks, 1, MAX_COUNT)?;
        // rank^(-1/beta) must not underflow to 0 for every rank > 1 too soon: beta >= 0.01.
        if !(self.temperature.is_finite() && self.temperature >= 0.01) {
            return Err(invalid("PlrSelector", "temperature", "a finite float >= 0.01", Num(self.temperature)));
        }
        c.probability("staleness_coef", self.staleness_coef)?;
        c.probability("replay_prob", self.replay_prob)?;
        Ok(())
    }
}

/// SPDL's parameters (Klink et al., NeurIPS 2020 / JMLR 2021), in the box scaled to [0, 1]:
/// both Gaussians are diagonal, with one mean and one standard deviation for every dimension.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct SpdlConfig {
    /// Mean of the initial distribution in every scaled dimension (0.5: the box's centre).
    pub init_mean: f64,
    /// Its standard deviation, in box widths (0.1, TeachMyAgent's initial distribution).
    pub init_std: f64,
    /// Mean of the target distribution mu in every scaled dimension (0.5).
    pub target_mean: f64,
    /// Its standard deviation, in box widths (0.25: TeachMyAgent's Gaussian for a uniform box).
    pub target_std: f64,
    /// Bound on KL(p_new || p_old) at each update (0.05).
    pub epsilon: f64,
    /// Least expected competence of a new distribution (0.5, for competences in [0, 1]).
    pub delta: f64,
    /// Told goals between updates (100).
    pub update_every: usize,
    /// Told goals before the first update (200, TeachMyAgent's offset of two periods).
    pub warmup: usize,
}

impl Default for SpdlConfig {
    fn default() -> Self {
        SpdlConfig { init_mean: 0.5, init_std: 0.1, target_mean: 0.5, target_std: 0.25, epsilon: 0.05, delta: 0.5, update_every: 100, warmup: 200 }
    }
}

impl SpdlConfig {
    pub fn validate(&self) -> Result<()> {
        let c = Check { owner: "SpdlSelector" };
        for (name, v) in [("init_mean", self.init_mean), ("target_mean", self.target_mean)] {
            if !(v.is_finite() && (0.0..=1.0).contains(&v)) {
                return Err(invalid("SpdlSelector", name, "a float in [0, 1] (a position in the box scaled to [0, 1])", Num(v)));
            }
        }
        for (name, v) in [("init_std", self.init_std), ("target_std", self.target_std)] {
            if !(v.is_finite() && (1e-4..=10.0).contains(&v)) {
                return Err(invalid("SpdlSelector", name, "a float in [1e-4, 10] (box widths)", Num(v)));
            }
        }
        c.positive("epsilon", self.epsilon)?;
        if !(self.delta.is_finite() && self.delta.abs() <= 1e100) {
            return Err(invalid("SpdlSelector", "delta", "a finite float of absolute value <= 1e100", Num(self.delta)));
        }
        c.within("update_every", self.update_every, 1, MAX_COUNT)?;
        c.within("warmup", self.warmup, 0, MAX_COUNT)?;
        Ok(())
    }
}

/// Goal GAN's parameters (Florensa et al., ICML 2018).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct GoalGanConfig {
    /// A told competence of at least this is a success (0.5, for competences in [0, 1]).
    pub success_threshold: f64,
    /// A goal of intermediate difficulty has a success rate in [r_min, r_max] (0.1, 0.9).
    pub r_min: f64,
    pub r_max: f64,
    /// Times each proposed goal is asked in a row, its success rate being theirs (2).
    pub n_rollouts: usize,
    /// Labelled goals between trainings of the GAN (100).
    pub update_size: usize,
    /// Steps of each training: one of the discriminator, one of the generator (250).
    pub gan_iterations: usize,
    /// Share of goals replayed from those labelled so far (1/3).
    pub p_old: f64,
    /// Dimension of the generator's noise (4).
    pub noise_dim: usize,
    /// Units of each of the two hidden layers of both networks (32; the paper's 128).
    pub hidden: usize,
    /// Adam's step size for both networks (0.001).
    pub learning_rate: f64,
}

impl Default for GoalGanConfig {
    fn default() -> Self {
        GoalGanConfig { success_threshold: 0.5, r_min: 0.1, r_max: 0.9, n_rollouts: 2, update_size: 100, gan_iterations: 250, p_old: 1.0 / 3.0, noise_dim: 4, hidden: 32, learning_rate: 0.001 }
    }
}

impl GoalGanConfig {
    pub fn validate(&self) -> Result<()> {
        let c = Check { owner: "GoalGanSelector" };
        if !(self.success_threshold.is_finite() && self.success_threshold.abs() <= 1e100) {
            return Err(invalid("GoalGanSelector", "success_threshold", "a finite float of absolute value <= 1e100", Num(self.success_threshold)));
        }
        c.probability("r_min", self.r_min)?;
        c.probability("r_max", self.r_max)?;
        if self.r_min > self.r_max {
            return Err(invalid("GoalGanSelector", "r_max", format!("a float >= r_min (r_min = {})", Num(self.r_min)), Num(self.r_max)));
        }
        c.within("n_rollouts", self.n_rollouts, 1, 255)?;
        // A goal's success rate is k / n_rollouts: none in [r_min, r_max] and no goal is ever
        // good, so the GAN would never train.
        let n = self.n_rollouts as f64;
        if !(0..=self.n_rollouts).any(|k| (self.r_min..=self.r_max).contains(&(k as f64 / n))) {
            return Err(invalid("GoalGanSelector", "r_max", format!("a float such that [r_min, r_max] holds a success rate k / n_rollouts (r_min = {}, n_rollouts = {})", Num(self.r_min), self.n_rollouts), Num(self.r_max)));
        }
        c.within("update_size", self.update_size, 1, 100_000)?;
        c.within("gan_iterations", self.gan_iterations, 0, 100_000)?;
        c.probability("p_old", self.p_old)?;
        c.within("noise_dim", self.noise_dim, 1, 1024)?;
        c.within("hidden", self.hidden, 1, 1024)?;
        c.in_open_closed("learning_rate", self.learning_rate, 0.0, 1.0)?;
        Ok(())
    }
}

/// SAGG-RIAC's high level: the region tree's and the goal modes' parameters (by their names in
/// `Config`, which sets them for a run's own high level).
#[derive(Debug, Clone, Copy, PartialEq, Default, Serialize, Deserialize)]
pub struct SaggRiacConfig {
    pub tree: RegionTreeConfig,
    pub modes: ModeProbabilities,
}

/// Goals uniform in the box: no parameter.
#[derive(Debug, Clone, Copy, PartialEq, Default, Serialize, Deserialize)]
pub struct RandomConfig {}

/// A teacher and its parameters: one variant per teacher, named as the ask/tell constructor,
/// `Config(teacher=...)` and the saved teachers name it.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Teacher {
    /// SAGG-RIAC's high level (Baranes & Oudeyer, IROS 2010).
    SaggRiac(SaggRiacConfig),
    /// Goals uniform in the box (SAGG-Random).
    Random(RandomConfig),
    /// RIAC as the baseline of Portelas et al. (CoRL 2019).
    Riac(RiacConfig),
    /// Learning progress over a task list (Kanitscheider et al., 2021); goals are task indices.
    DiscreteLp(DiscreteLpConfig),
    /// ALP-GMM (Portelas et al., CoRL 2019).
    AlpGmm(AlpGmmConfig),
    /// Covar-GMM (Moulin-Frier, Nguyen & Oudeyer, 2014).
    CovarGmm(CovarGmmConfig),
    /// Automatic Domain Randomization (Akkaya et al., 2019).
    Adr(AdrConfig),
    /// Prioritized Level Replay (Jiang et al., ICML 2021); goals are task indices.
    Plr(PlrConfig),
    /// SPDL (Klink et al., NeurIPS 2020; JMLR 2021).
    Spdl(SpdlConfig),
    /// Goal GAN (Florensa et al., ICML 2018).
    GoalGan(GoalGanConfig),
}

impl Teacher {
    /// Every teacher with its papers' parameters (`_core.teacher_defaults()` shows them).
    pub fn all() -> [Teacher; 10] {
        [
            Teacher::SaggRiac(SaggRiacConfig::default()),
            Teacher::Random(RandomConfig::default()),
            Teacher::Riac(RiacConfig::default()),
            Teacher::DiscreteLp(DiscreteLpConfig::default()),
            Teacher::AlpGmm(AlpGmmConfig::default()),
            Teacher::CovarGmm(CovarGmmConfig::default()),
            Teacher::Adr(AdrConfig::default()),
            Teacher::Plr(PlrConfig::default()),
            Teacher::Spdl(SpdlConfig::default()),
            Teacher::GoalGan(GoalGanConfig::default()),
        ]
    }

    /// The teacher `kind` with its papers' parameters.
    pub fn parse(owner: &'static str, param: &str, kind: &str) -> Result<Self> {
        Self::all().into_iter().find(|t| t.kind() == kind).ok_or_else(|| {
            let names: Vec<String> = Self::all().iter().map(|t| format!("'{}'", t.kind())).collect();
            invalid(owner, param, format!("one of {}", names.join(", ")), format!("'{kind}'"))
        })
    }

    /// The teacher's name, as the Python classes, the CLI and saved teachers know it.
    pub fn kind(&self) -> &'static str {
        match self {
            Teacher::SaggRiac(_) => "sagg_riac",
            Teacher::Random(_) => "random",
            Teacher::Riac(_) => "riac",
            Teacher::DiscreteLp(_) => "discrete_lp",
            Teacher::AlpGmm(_) => "alp_gmm",
            Teacher::CovarGmm(_) => "covar_gmm",
            Teacher::Adr(_) => "adr",
            Teacher::Plr(_) => "plr",
            Teacher::Spdl(_) => "spdl",
            Teacher::GoalGan(_) => "goal_gan",
        }
    }

    /// The Python class of the teacher (its messages' owner).
    pub fn class(&self) -> &'static str {
        match self {
            Teacher::SaggRiac(_) => "SaggRiacSelector",
            Teacher::Random(_) => "RandomSelector",
            Teacher::Riac(_) => "RiacSelector",
            Teacher::DiscreteLp(_) => "DiscreteLpSelector",
            Teacher::AlpGmm(_) => "AlpGmmSelector",
            Teacher::CovarGmm(_) => "CovarGmmSelector",
            Teacher::Adr(_) => "AdrSelector",
            Teacher::Plr(_) => "PlrSelector",
            Teacher::Spdl(_) => "SpdlSelector",
            Teacher::GoalGan(_) => "GoalGanSelector",
        }
    }

    /// Whether the teacher chooses goals in a box (all but the task-list teacher), so that it
    /// can choose a run's goals.
    pub fn has_box(&self) -> bool {
        !matches!(self, Teacher::DiscreteLp(_) | Teacher::Plr(_))
    }

    /// The parameters' rules (the box is checked by the teacher).
    pub fn validate(&self) -> Result<()> {
        match self {
            Teacher::SaggRiac(c) => c.tree.validate().and_then(|_| c.modes.validate()),
            Teacher::Random(_) => Ok(()),
            Teacher::Riac(c) => c.validate(),
            Teacher::DiscreteLp(c) => c.validate(),
            Teacher::AlpGmm(c) => c.validate("AlpGmmSelector"),
            Teacher::CovarGmm(c) => c.validate(),
            Teacher::Adr(c) => c.validate(),
            Teacher::Plr(c) => c.validate(),
            Teacher::Spdl(c) => c.validate(),
            Teacher::GoalGan(c) => c.validate(),
        }
    }
}

/// A parameter struct's fields by their serde names, with their values as text, in order
/// (fields of nested structs in their place): a set of parameters compared and named without a
/// list of names.
pub fn flat_params<T: Serialize>(params: &T) -> Vec<(String, String)> {
    fn walk(prefix: Option<&str>, v: serde_json::Value, out: &mut Vec<(String, String)>) {
        match v {
            serde_json::Value::Object(m) => m.into_iter().for_each(|(k, v)| walk(Some(&k), v, out)),
            serde_json::Value::String(s) => out.push((prefix.unwrap_or_default().to_string(), format!("'{s}'"))),
            other => out.push((prefix.unwrap_or_default().to_string(), other.to_string())),
        }
    }
    let mut out = Vec::new();
    walk(None, serde_json::to_value(params).unwrap_or_default(), &mut out);
    out
}

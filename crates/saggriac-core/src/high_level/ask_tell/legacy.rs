//! The layouts of formats 1 (saggriac <= 0.2: SAGG-RIAC's tree parameters without the divisor),
//! 2 (saggriac 0.3-0.4, whose teachers' states were variants of one enum), 3 (saggriac 0.5,
//! the parameters as one enum of teachers with their boxes and seeds), 4 (saggriac 0.6, PLR's
//! parameters without `ties`), 5 (PLR's with `ties`; before #46: no parameters per dimension,
//! SPDL's and Goal GAN's parameters as they were) and 6 (SAGG-RIAC without mode 3's reading).

use super::*;
use crate::config::high_level::InterestDivisor;
use crate::config::teachers::{AdrConfig, GoalGanConfig, PerDimension, PlrConfig, PlrScore, PlrTies, RandomConfig, ReplaySchedule, SaggRiacConfig, SpdlConfig, SpdlCovariance, SpdlForm, Teacher, TsclConfig};
use crate::high_level::teachers::alp_gmm::AlpGmmConfig;
use crate::high_level::teachers::covar_gmm::CovarGmmConfig;
use crate::high_level::teachers::discrete_lp::DiscreteLpConfig;
use crate::high_level::teachers::riac::RiacConfig;
use crate::rng::CoreRng;

/// `TeacherSpec` as formats 2 and 3 wrote it.
#[derive(Deserialize)]
pub enum SpecV3 {
    SaggRiac { low: Vec<f64>, high: Vec<f64>, tree: RegionTreeConfig, modes: ModeProbabilities, seed: u64 },
    Random { low: Vec<f64>, high: Vec<f64>, seed: u64 },
    Riac { low: Vec<f64>, high: Vec<f64>, cfg: RiacConfig, seed: u64 },
    DiscreteLp { cfg: DiscreteLpConfig, seed: u64 },
    AlpGmm { low: Vec<f64>, high: Vec<f64>, cfg: AlpGmmConfig, seed: u64 },
    CovarGmm { low: Vec<f64>, high: Vec<f64>, cfg: CovarGmmConfig, seed: u64 },
}

impl From<SpecV3> for TeacherSpec {
    fn from(s: SpecV3) -> Self {
        let (teacher, low, high, seed) = match s {
            SpecV3::SaggRiac { low, high, tree, modes, seed } => (Teacher::SaggRiac(SaggRiacConfig { tree, modes, ..Default::default() }), low, high, seed),
            SpecV3::Random { low, high, seed } => (Teacher::Random(RandomConfig {}), low, high, seed),
            SpecV3::Riac { low, high, cfg, seed } => (Teacher::Riac(cfg), low, high, seed),
            SpecV3::DiscreteLp { cfg, seed } => (Teacher::DiscreteLp(cfg), Vec::new(), Vec::new(), seed),
            SpecV3::AlpGmm { low, high, cfg, seed } => (Teacher::AlpGmm(cfg), low, high, seed),
            SpecV3::CovarGmm { low, high, cfg, seed } => (Teacher::CovarGmm(cfg), low, high, seed),
        };
        TeacherSpec { teacher, low, high, seed, dims: Default::default() }
    }
}

#[derive(Deserialize)]
pub struct TreeV1 {
    g_max: usize,
    zeta: usize,
    min_child: usize,
}

/// `TeacherSpec` as format 1 wrote it (variants in the same order).
#[derive(Deserialize)]
pub enum SpecV1 {
    SaggRiac { low: Vec<f64>, high: Vec<f64>, tree: TreeV1, modes: ModeProbabilities, seed: u64 },
    Random { low: Vec<f64>, high: Vec<f64>, seed: u64 },
    Riac { low: Vec<f64>, high: Vec<f64>, cfg: RiacConfig, seed: u64 },
    DiscreteLp { cfg: DiscreteLpConfig, seed: u64 },
    AlpGmm { low: Vec<f64>, high: Vec<f64>, cfg: AlpGmmConfig, seed: u64 },
    CovarGmm { low: Vec<f64>, high: Vec<f64>, cfg: CovarGmmConfig, seed: u64 },
}

/// A mixture's weights, means and covariances, flattened.
type GmmV2 = (Vec<f64>, (Vec<f64>, Vec<f64>));

/// Every teacher's state as formats 1 and 2 wrote it: one enum, variants in this order.
#[derive(Deserialize)]
pub enum StateV2 {
    SaggRiac { rng: CoreRng, points: Vec<f64>, values: Vec<f64> },
    Random { rng: CoreRng },
    Riac { rng: CoreRng, points: Vec<f64>, values: Vec<f64> },
    DiscreteLp { rng: CoreRng, fast: Vec<f64>, slow: Vec<f64> },
    Mixture { rng: CoreRng, fit_rng: CoreRng, points: Vec<f64>, values: Vec<f64>, window: Vec<f64>, gmm: Option<GmmV2> },
}

impl From<StateV2> for Vec<u8> {
    /// The same state in its teacher's own encoding: a variant's fields in order, which is
    /// how each teacher encodes its state struct.
    fn from(s: StateV2) -> Vec<u8> {
        let r = match s {
            StateV2::SaggRiac { rng, points, values } | StateV2::Riac { rng, points, values } => postcard::to_stdvec(&(rng, points, values)),
            StateV2::Random { rng } => postcard::to_stdvec(&(rng,)),
            StateV2::DiscreteLp { rng, fast, slow } => postcard::to_stdvec(&(rng, fast, slow)),
            StateV2::Mixture { rng, fit_rng, points, values, window, gmm } => postcard::to_stdvec(&(rng, fit_rng, points, values, window, gmm)),
        };
        r.unwrap_or_default()
    }
}

/// PLR's parameters as format 4 wrote them, before `ties`.
#[derive(Deserialize)]
pub struct PlrConfigV4 {
    n_tasks: usize,
    temperature: f64,
    staleness_coef: f64,
    replay_schedule: ReplaySchedule,
    replay_prob: f64,
    score: PlrScore,
}

impl From<PlrConfigV4> for PlrConfig {
    /// Its ties shared their mean rank then: it keeps that rule.
    fn from(c: PlrConfigV4) -> Self {
        PlrConfig {
            n_tasks: c.n_tasks,
            temperature: c.temperature,
            staleness_coef: c.staleness_coef,
            replay_schedule: c.replay_schedule,
            replay_prob: c.replay_prob,
            score: c.score,
            ties: PlrTies::Average,
        }
    }
}

/// SPDL's parameters as formats 4 and 5 wrote them: the delta form with diagonal Gaussians.
#[derive(Deserialize)]
pub struct SpdlConfigV5 {
    init_mean: f64,
    init_std: f64,
    target_mean: f64,
    target_std: f64,
    epsilon: f64,
    delta: f64,
    update_every: usize,
    warmup: usize,
}

impl From<SpdlConfigV5> for SpdlConfig {
    fn from(c: SpdlConfigV5) -> Self {
        let SpdlConfigV5 { init_mean, init_std, target_mean, target_std, epsilon, delta, update_every, warmup } = c;
        SpdlConfig { init_mean, init_std, target_mean, target_std, epsilon, delta, update_every, warmup, form: SpdlForm::Delta, covariance: SpdlCovariance::Diagonal, ..SpdlConfig::default() }
    }
}

/// Goal GAN's parameters as formats 4 and 5 wrote them: first goals uniform in the whole box.
#[derive(Deserialize)]
pub struct GoalGanConfigV5 {
    success_threshold: f64,
    r_min: f64,
    r_max: f64,
    n_rollouts: usize,
    update_size: usize,
    gan_iterations: usize,
    p_old: f64,
    noise_dim: usize,
    hidden: usize,
    learning_rate: f64,
}

impl From<GoalGanConfigV5> for GoalGanConfig {
    fn from(c: GoalGanConfigV5) -> Self {
        let GoalGanConfigV5 { success_threshold, r_min, r_max, n_rollouts, update_size, gan_iterations, p_old, noise_dim, hidden, learning_rate } = c;
        GoalGanConfig { success_threshold, r_min, r_max, n_rollouts, update_size, gan_iterations, p_old, noise_dim, hidden, learning_rate, initial: 0.5, initial_width: 1.0 }
    }
}

/// SAGG-RIAC's parameters as formats 4 to 6 wrote them: mode 3 as the paper reads it.
#[derive(Deserialize)]
pub struct SaggRiacConfigV6 {
    tree: RegionTreeConfig,
    modes: ModeProbabilities,
}

impl From<SaggRiacConfigV6> for SaggRiacConfig {
    fn from(c: SaggRiacConfigV6) -> Self {
        SaggRiacConfig { tree: c.tree, modes: c.modes, ..Default::default() }
    }
}

/// `Teacher` as formats 4 and 5 wrote it: the registry's variants in its order, SPDL's and Goal
/// GAN's parameters before #46, and PLR's as `Plr` (format 4: without `ties`; 5: with).
#[derive(Deserialize)]
pub enum TeacherV5<Plr> {
    SaggRiac(SaggRiacConfigV6),
    Random(RandomConfig),
    Riac(RiacConfig),
    DiscreteLp(DiscreteLpConfig),
    AlpGmm(AlpGmmConfig),
    CovarGmm(CovarGmmConfig),
    Adr(AdrConfig),
    Plr(Plr),
    Spdl(SpdlConfigV5),
    GoalGan(GoalGanConfigV5),
    Tscl(TsclConfig),
}

/// `TeacherSpec` as formats 4 and 5 wrote it: no parameters per dimension.
#[derive(Deserialize)]
pub struct SpecV5<Plr> {
    teacher: TeacherV5<Plr>,
    low: Vec<f64>,
    high: Vec<f64>,
    seed: u64,
}

impl<Plr: Into<PlrConfig>> From<SpecV5<Plr>> for TeacherSpec {
    /// The parameters added since at the values the teachers of then ran with.
    fn from(s: SpecV5<Plr>) -> Self {
        let teacher = match s.teacher {
            TeacherV5::SaggRiac(c) => Teacher::SaggRiac(c.into()),
            TeacherV5::Random(c) => Teacher::Random(c),
            TeacherV5::Riac(c) => Teacher::Riac(c),
            TeacherV5::DiscreteLp(c) => Teacher::DiscreteLp(c),
            TeacherV5::AlpGmm(c) => Teacher::AlpGmm(c),
            TeacherV5::CovarGmm(c) => Teacher::CovarGmm(c),
            TeacherV5::Adr(c) => Teacher::Adr(c),
            TeacherV5::Plr(c) => Teacher::Plr(c.into()),
            TeacherV5::Spdl(c) => Teacher::Spdl(c.into()),
            TeacherV5::GoalGan(c) => Teacher::GoalGan(c.into()),
            TeacherV5::Tscl(c) => Teacher::Tscl(c),
        };
        TeacherSpec { teacher, low: s.low, high: s.high, seed: s.seed, dims: Default::default() }
    }
}

/// `Teacher` as format 6 wrote it: SAGG-RIAC without mode 3's reading.
#[derive(Deserialize)]
pub enum TeacherV6 {
    SaggRiac(SaggRiacConfigV6),
    Random(RandomConfig),
    Riac(RiacConfig),
    DiscreteLp(DiscreteLpConfig),
    AlpGmm(AlpGmmConfig),
    CovarGmm(CovarGmmConfig),
    Adr(AdrConfig),
    Plr(PlrConfig),
    Spdl(SpdlConfig),
    GoalGan(GoalGanConfig),
    Tscl(TsclConfig),
}

/// `TeacherSpec` as format 6 wrote it.
#[derive(Deserialize)]
pub struct SpecV6 {
    teacher: TeacherV6,
    low: Vec<f64>,
    high: Vec<f64>,
    seed: u64,
    dims: PerDimension,
}

impl From<SpecV6> for TeacherSpec {
    fn from(s: SpecV6) -> Self {
        let teacher = match s.teacher {
            TeacherV6::SaggRiac(c) => Teacher::SaggRiac(c.into()),
            TeacherV6::Random(c) => Teacher::Random(c),
            TeacherV6::Riac(c) => Teacher::Riac(c),
            TeacherV6::DiscreteLp(c) => Teacher::DiscreteLp(c),
            TeacherV6::AlpGmm(c) => Teacher::AlpGmm(c),
            TeacherV6::CovarGmm(c) => Teacher::CovarGmm(c),
            TeacherV6::Adr(c) => Teacher::Adr(c),
            TeacherV6::Plr(c) => Teacher::Plr(c),
            TeacherV6::Spdl(c) => Teacher::Spdl(c),
            TeacherV6::GoalGan(c) => Teacher::GoalGan(c),
            TeacherV6::Tscl(c) => Teacher::Tscl(c),
        };
        TeacherSpec { teacher, low: s.low, high: s.high, seed: s.seed, dims: s.dims }
    }
}

pub type SavedV1 = SavedAs<SpecV1, StateV2>;
pub type SavedV2 = SavedAs<SpecV3, StateV2>;
pub type SavedV3 = SavedAs<SpecV3, Vec<u8>>;
pub type SavedV4 = SavedAs<SpecV5<PlrConfigV4>, Vec<u8>>;
pub type SavedV5 = SavedAs<SpecV5<PlrConfig>, Vec<u8>>;
pub type SavedV6 = SavedAs<SpecV6, Vec<u8>>;

impl From<SpecV1> for TeacherSpec {
    fn from(s: SpecV1) -> Self {
        SpecV3::from(s).into()
    }
}

impl From<SpecV1> for SpecV3 {
    fn from(s: SpecV1) -> Self {
        match s {
            // saggriac <= 0.2 divided a young region's eq. 2 by its own window.
            SpecV1::SaggRiac { low, high, tree, modes, seed } => {
                let tree = RegionTreeConfig { g_max: tree.g_max, zeta: tree.zeta, min_child: tree.min_child, divisor: InterestDivisor::Window };
                SpecV3::SaggRiac { low, high, tree, modes, seed }
            }
            SpecV1::Random { low, high, seed } => SpecV3::Random { low, high, seed },
            SpecV1::Riac { low, high, cfg, seed } => SpecV3::Riac { low, high, cfg, seed },
            SpecV1::DiscreteLp { cfg, seed } => SpecV3::DiscreteLp { cfg, seed },
            SpecV1::AlpGmm { low, high, cfg, seed } => SpecV3::AlpGmm { low, high, cfg, seed },
            SpecV1::CovarGmm { low, high, cfg, seed } => SpecV3::CovarGmm { low, high, cfg, seed },
        }
    }
}

/// A saved teacher of an older format in this format's terms.
pub fn upgrade<Spec: Into<TeacherSpec>, State: Into<Vec<u8>>>(s: SavedAs<Spec, State>) -> Saved {
    let SavedAs { version, spec, state, asked, asked_mode, asked_region, told, told_competence, told_region, .. } = s;
    SavedAs { format: FORMAT, version, spec: spec.into(), state: state.into(), asked, asked_mode, asked_region, told, told_competence, told_region }
}

//! What ALP-GMM and Covar-GMM share: the task box scaled to [0, 1], their two generators, what
//! was told, the window the mixtures are fitted on, the current mixture, and how a goal is drawn
//! from it. Each teacher adds only its own coordinates (ALP; time and competence).

use std::collections::VecDeque;
use std::ops::Range;

use nalgebra::DVector;

use crate::config::high_level::check_bounds;
use crate::error::Result;
use crate::high_level::goal_selection::{load_state, save_state, GoalChoice, Mode};
use crate::high_level::teachers::gmm::{best_by_aic, EmConfig, Gmm};
use crate::high_level::teachers::refit_threads;
use crate::rng::{child_seed, index, pick_weighted, rng_from_seed, uniform, unit, CoreRng};

pub use crate::config::teachers::AlpGmmConfig;

/// A mixture as saved: weights, then means and covariances flattened.
pub type SavedGmm = (Vec<f64>, (Vec<f64>, Vec<f64>));

/// The mixture teachers' state: generators, what was told, the fitting window (rows
/// flattened) and the mixture (weights, then means and covariances flattened).
#[derive(Debug, Clone, serde::Serialize, serde::Deserialize)]
struct MixtureState {
    rng: CoreRng,
    fit_rng: CoreRng,
    points: Vec<f64>,
    values: Vec<f64>,
    window: Vec<f64>,
    gmm: Option<SavedGmm>,
}

/// The box and its scaling to [0, 1].
#[derive(Debug, Clone)]
pub(crate) struct UnitBox {
    pub low: Vec<f64>,
    pub high: Vec<f64>,
}

impl UnitBox {
    pub fn to_unit(&self, p: &[f64]) -> Vec<f64> {
        p.iter().zip(self.low.iter().zip(&self.high)).map(|(v, (l, h))| ((v - l) / (h - l)).clamp(0.0, 1.0)).collect()
    }
    pub fn scale_back(&self, u: &[f64]) -> Vec<f64> {
        u.iter().zip(self.low.iter().zip(&self.high)).map(|(v, (l, h))| (l + v.clamp(0.0, 1.0) * (h - l)).clamp(*l, *h)).collect()
    }
    pub fn uniform(&self, rng: &mut CoreRng) -> Vec<f64> {
        self.low.iter().zip(&self.high).map(|(l, h)| uniform(rng, *l, *h)).collect()
    }
}

/// A component drawn in proportion to `weight(j)` (uniformly if none has weight).
fn proportional_component(gmm: &Gmm, weight: impl Fn(usize) -> f64, rng: &mut CoreRng) -> usize {
    let w: Vec<f64> = (0..gmm.n_components()).map(|j| weight(j).max(0.0)).collect();
    let total: f64 = w.iter().sum();
    if !(total > 0.0 && total.is_finite()) {
        return index(rng, w.len());
    }
    pick_weighted(&w, unit(rng) * total)
}

pub(crate) struct MixtureCore {
    pub cfg: AlpGmmConfig,
    pub unit_box: UnitBox,
    rng: CoreRng,
    /// The mixtures' k-means starts draw from their own generator.
    fit_rng: CoreRng,
    /// Every told task (raw) and competence, in order.
    pub points: Vec<f64>,
    pub values: Vec<f64>,
    /// The last `fit_rate` rows of the teacher's own coordinates.
    pub window: VecDeque<Vec<f64>>,
    pub gmm: Option<Gmm>,
    /// The cap on a refit's threads (`SAGGRIAC_FIT_THREADS`), read when built; never saved, as
    /// it changes no result.
    fit_threads: Option<usize>,
}

/// The most dimensions a mixture teacher takes: EM's cost per refit grows as d^3 (10^4
/// dimensions did not finish 300 updates in 2 minutes); teacher-student curricula use a few to a
/// few tens.
pub const MAX_MIXTURE_DIM: usize = 100;

impl MixtureCore {
    pub fn new(owner: &'static str, low: &[f64], high: &[f64], cfg: AlpGmmConfig, seed: u64) -> Result<Self> {
        check_bounds(owner, low, high)?;
        if low.len() > MAX_MIXTURE_DIM {
            let rule = format!("bounds of at most {MAX_MIXTURE_DIM} dimensions (each refit runs EM on full covariance matrices, whose cost grows as the cube of the dimension)");
            return Err(crate::error::invalid(owner, "bounds", rule, format!("{} dimensions", low.len())));
        }
        cfg.check(owner)?;
        let fit_threads = refit_threads::cap_from_env(owner)?;
        Ok(MixtureCore {
            cfg,
            unit_box: UnitBox { low: low.to_vec(), high: high.to_vec() },
            rng: rng_from_seed(seed),
            fit_rng: rng_from_seed(child_seed(seed, 1)),
            points: Vec::new(),
            values: Vec::new(),
            window: VecDeque::new(),
            gmm: None,
            fit_threads,
        })
    }

    /// Record a told task and its window row; true when a refit is due.
    pub fn record(&mut self, point: &[f64], competence: f64, row: Vec<f64>) -> bool {
        self.points.extend_from_slice(point);
        self.values.push(competence);
        self.window.push_back(row);
        if self.window.len() > self.cfg.fit_rate {
            self.window.pop_front();
        }
        self.values.len() % self.cfg.fit_rate == 0
    }

    /// The mixture of 2 to `max_components` components of lowest AIC on `data`.
    pub fn fit(&mut self, data: &[DVector<f64>]) {
        let ks: Vec<usize> = (2..=self.cfg.max_components).collect();
        self.gmm = best_by_aic(data, &ks, EmConfig::default(), &mut self.fit_rng, self.fit_threads);
    }

    /// Uniform during the bootstrap and with probability `random_task_ratio`; otherwise the
    /// coordinates `task` of a draw from a component drawn in proportion to `weight`.
    pub fn sample(&mut self, weight: impl Fn(&Gmm, usize) -> f64, task: Range<usize>) -> GoalChoice {
        let random = self.values.len() < self.cfg.bootstrap || unit(&mut self.rng) < self.cfg.random_task_ratio;
        match (&self.gmm, random) {
            (Some(g), false) => {
                let j = proportional_component(g, |j| weight(g, j), &mut self.rng);
                let x = g.sample_component(j, &mut self.rng);
                GoalChoice { goal: self.unit_box.scale_back(&x.as_slice()[task]), mode: Mode::Interest, region: Some(j) }
            }
            _ => GoalChoice { goal: self.unit_box.uniform(&mut self.rng), mode: Mode::Global, region: None },
        }
    }

    pub fn save(&self) -> Option<Vec<u8>> {
        save_state(&MixtureState {
            rng: self.rng.clone(),
            fit_rng: self.fit_rng.clone(),
            points: self.points.clone(),
            values: self.values.clone(),
            window: self.window.iter().flatten().copied().collect(),
            gmm: self.gmm.as_ref().map(|g| (g.weights.clone(), g.to_flat())),
        })
    }

    /// Restore what `save` wrote for rows of `row_len` numbers and a mixture in `gmm_dim`
    /// dimensions; false (nothing changed) if the state does not fit.
    pub fn load(&mut self, state: &[u8], row_len: usize, gmm_dim: usize) -> bool {
        let Some(MixtureState { rng, fit_rng, points, values, window, gmm }) = load_state(state) else { return false };
        if points.len() != values.len() * self.unit_box.low.len() || window.len() % row_len != 0 {
            return false;
        }
        (self.points, self.values) = (points, values);
        self.window = window.chunks_exact(row_len).map(|r| r.to_vec()).collect();
        self.gmm = gmm.as_ref().map(|(w, (m, c))| Gmm::from_flat(gmm_dim, w, m, c));
        (self.rng, self.fit_rng) = (rng, fit_rng);
        true
    }
}

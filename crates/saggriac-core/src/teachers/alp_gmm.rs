//! ALP-GMM (Portelas, Colas, Hofmann & Oudeyer, "Teacher algorithms for curriculum learning of
//! Deep RL in continuously parameterized environments", CoRL 2019).
//!
//! Each told task gets an absolute learning progress: |competence - the competence told for the
//! nearest earlier task| (0 for the first). Every `fit_rate` tasks, Gaussian mixtures of 2 to
//! `max_components` components are fitted to the last `fit_rate` (task, ALP) pairs, and the one
//! of lowest AIC is kept. A goal is uniform in the box during the first `bootstrap` tasks, and
//! afterwards with probability `random_task_ratio`; otherwise a component is drawn in
//! proportion to the ALP coordinate of its mean and the goal is the task part of a draw from it,
//! clipped to the box. Tasks are scaled to [0, 1] per dimension for the neighbour search and the
//! mixtures (the paper leaves the scale open; without it a wide dimension would swamp ALP).

use std::collections::VecDeque;

use nalgebra::DVector;
use serde::{Deserialize, Serialize};

use crate::config::high_level::check_bounds;
use crate::error::{invalid, Check, Result};
use crate::goal_selection::{GoalChoice, GoalSelector, Mode, SelectorState};
use crate::kd_tree::KdTree;
use crate::neighbours::{Neighbour, NeighbourIndex};
use crate::rng::{child_seed, rng_from_seed, uniform, unit, CoreRng};
use crate::teachers::gmm::{best_by_aic, EmConfig, Gmm};

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
        c.at_least("fit_rate", self.fit_rate, 2)?;
        c.at_least("max_components", self.max_components, 2)?;
        c.probability("random_task_ratio", self.random_task_ratio)?;
        if self.max_components > self.fit_rate {
            return Err(invalid(owner, "max_components", format!("an int <= fit_rate (fit_rate = {})", self.fit_rate), self.max_components));
        }
        Ok(())
    }
}

/// The box and its scaling to [0, 1], shared by the mixture teachers.
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
pub(crate) fn proportional_component(gmm: &Gmm, weight: impl Fn(usize) -> f64, rng: &mut CoreRng) -> usize {
    let w: Vec<f64> = (0..gmm.n_components()).map(|j| weight(j).max(0.0)).collect();
    let total: f64 = w.iter().sum();
    if !(total > 0.0 && total.is_finite()) {
        return crate::rng::index(rng, w.len());
    }
    let mut u = unit(rng) * total;
    for (j, x) in w.iter().enumerate() {
        if u < *x {
            return j;
        }
        u -= x;
    }
    w.iter().rposition(|x| *x > 0.0).unwrap_or(0)
}

pub struct AlpGmm {
    cfg: AlpGmmConfig,
    unit_box: UnitBox,
    seed: u64,
    rng: CoreRng,
    /// The mixtures' k-means starts draw from their own generator.
    fit_rng: CoreRng,
    index: KdTree,
    /// Every told task (raw) and competence, in order.
    points: Vec<f64>,
    values: Vec<f64>,
    /// The last `fit_rate` (scaled task, ALP) rows.
    window: VecDeque<Vec<f64>>,
    gmm: Option<Gmm>,
    scratch: Vec<Neighbour>,
}

impl AlpGmm {
    pub fn new(low: &[f64], high: &[f64], cfg: AlpGmmConfig, seed: u64) -> Result<Self> {
        check_bounds("AlpGmmSelector", low, high)?;
        cfg.validate("AlpGmmSelector")?;
        Ok(AlpGmm {
            cfg,
            unit_box: UnitBox { low: low.to_vec(), high: high.to_vec() },
            seed,
            rng: rng_from_seed(seed),
            fit_rng: rng_from_seed(child_seed(seed, 1)),
            index: KdTree::new(low.len()),
            points: Vec::new(),
            values: Vec::new(),
            window: VecDeque::new(),
            gmm: None,
            scratch: Vec::new(),
        })
    }

    /// The current mixture over (scaled task, ALP), once fitted.
    pub fn gmm(&self) -> Option<&Gmm> {
        self.gmm.as_ref()
    }

    fn refit(&mut self) {
        let data: Vec<DVector<f64>> = self.window.iter().map(|r| DVector::from_column_slice(r)).collect();
        let ks: Vec<usize> = (2..=self.cfg.max_components).collect();
        self.gmm = best_by_aic(&data, &ks, EmConfig::default(), &mut self.fit_rng);
    }

    fn tell(&mut self, point: &[f64], competence: f64) {
        let t = self.unit_box.to_unit(point);
        let alp = if self.index.is_empty() {
            0.0
        } else {
            self.index.knn(&t, 1, &mut self.scratch);
            (competence - self.values[self.scratch[0].id as usize]).abs()
        };
        self.index.add(&t);
        self.points.extend_from_slice(point);
        self.values.push(competence);
        let mut row = t;
        row.push(alp);
        self.window.push_back(row);
        if self.window.len() > self.cfg.fit_rate {
            self.window.pop_front();
        }
        if self.values.len() % self.cfg.fit_rate == 0 {
            self.refit();
        }
    }
}

impl GoalSelector for AlpGmm {
    fn low(&self) -> &[f64] {
        &self.unit_box.low
    }
    fn high(&self) -> &[f64] {
        &self.unit_box.high
    }
    fn sample(&mut self) -> GoalChoice {
        let d = self.unit_box.low.len();
        let random = self.values.len() < self.cfg.bootstrap || unit(&mut self.rng) < self.cfg.random_task_ratio;
        match (&self.gmm, random) {
            (Some(g), false) => {
                let j = proportional_component(g, |j| g.means[j][d], &mut self.rng);
                let x = g.sample_component(j, &mut self.rng);
                GoalChoice { goal: self.unit_box.scale_back(&x.as_slice()[..d]), mode: Mode::Interest, region: Some(j) }
            }
            _ => GoalChoice { goal: self.unit_box.uniform(&mut self.rng), mode: Mode::Global, region: None },
        }
    }
    fn update(&mut self, point: &[f64], competence: f64) -> Option<usize> {
        self.tell(point, competence);
        None
    }
    fn save(&self) -> Option<SelectorState> {
        Some(SelectorState::Mixture {
            rng: self.rng.clone(),
            fit_rng: self.fit_rng.clone(),
            points: self.points.clone(),
            values: self.values.clone(),
            window: self.window.iter().flatten().copied().collect(),
            gmm: self.gmm.as_ref().map(|g| (g.weights.clone(), g.to_flat())),
        })
    }
    fn load(&mut self, state: &SelectorState) -> bool {
        let SelectorState::Mixture { rng, fit_rng, points, values, window, gmm } = state else { return false };
        let d = self.unit_box.low.len();
        if points.len() != values.len() * d || window.len() % (d + 1) != 0 {
            return false;
        }
        let Ok(mut fresh) = AlpGmm::new(&self.unit_box.low, &self.unit_box.high, self.cfg, self.seed) else { return false };
        for p in points.chunks_exact(d) {
            fresh.index.add(&fresh.unit_box.to_unit(p));
        }
        (fresh.points, fresh.values) = (points.clone(), values.clone());
        fresh.window = window.chunks_exact(d + 1).map(|r| r.to_vec()).collect();
        fresh.gmm = gmm.as_ref().map(|(w, (m, c))| Gmm::from_flat(d + 1, w, m, c));
        (fresh.rng, fresh.fit_rng) = (rng.clone(), fit_rng.clone());
        *self = fresh;
        true
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn alp_is_against_the_nearest_earlier_task_and_goals_follow_progress() {
        let cfg = AlpGmmConfig { fit_rate: 100, bootstrap: 100, ..AlpGmmConfig::default() };
        let mut t = AlpGmm::new(&[0.0, 0.0], &[10.0, 10.0], cfg, 3).unwrap();
        t.update(&[1.0, 1.0], -0.5);
        t.update(&[9.0, 9.0], -0.1);
        t.update(&[1.2, 1.0], -0.2);
        let alps: Vec<f64> = t.window.iter().map(|r| r[2]).collect();
        assert_eq!(alps[0], 0.0);
        assert!((alps[1] - 0.4).abs() < 1e-12 && (alps[2] - 0.3).abs() < 1e-12, "{alps:?}");
        // Progress only for x < 3: competence there alternates (high ALP); flat elsewhere.
        let mut flip = false;
        for _ in 0..2000 {
            let g = t.sample().goal;
            flip = !flip;
            let c = if g[0] < 3.0 {
                if flip {
                    -0.9
                } else {
                    -0.1
                }
            } else {
                -0.5
            };
            t.update(&g, c);
        }
        assert!(t.gmm().is_some());
        let late: Vec<Vec<f64>> = t.points.chunks_exact(2).skip(1500).map(|p| p.to_vec()).collect();
        let share = late.iter().filter(|p| p[0] < 3.0).count() as f64 / late.len() as f64;
        assert!(share > 0.5, "{share}"); // uniform would give 0.3
        assert!(late.iter().all(|p| p.iter().all(|v| (0.0..=10.0).contains(v))));
    }

    #[test]
    fn bad_parameters_are_named() {
        let e = AlpGmm::new(&[0.0], &[1.0], AlpGmmConfig { max_components: 300, ..AlpGmmConfig::default() }, 0).err().unwrap().to_string();
        assert!(e.contains("'max_components' parameter of AlpGmmSelector") && e.contains("fit_rate = 250"), "{e}");
        assert!(AlpGmm::new(&[0.0], &[1.0], AlpGmmConfig { random_task_ratio: 1.5, ..AlpGmmConfig::default() }, 0).is_err());
    }
}

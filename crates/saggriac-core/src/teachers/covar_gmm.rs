//! Covar-GMM (Moulin-Frier, Nguyen & Oudeyer, "Self-organization of early vocal development in
//! infants and machines: the role of intrinsic motivation", Frontiers in Psychology 2014).
//!
//! Gaussian mixtures are fitted to (time, task, competence) over the last `fit_rate` told tasks,
//! time being the task's rank in that window scaled to [0, 1] and tasks scaled to [0, 1] per
//! dimension; every `fit_rate` tasks the mixture of 2 to `max_components` components of lowest
//! AIC is kept. A component's learning progress is the covariance of time and competence in it:
//! where competence rises (or falls) with time. A goal is uniform during the first `bootstrap`
//! tasks and afterwards with probability `random_task_ratio`; otherwise a component is drawn in
//! proportion to its absolute progress (its positive progress with `absolute_lp = false`) and
//! the goal is the task part of a draw from it, clipped to the box.

use std::collections::VecDeque;

use nalgebra::DVector;
use serde::{Deserialize, Serialize};

use crate::config::high_level::check_bounds;
use crate::error::Result;
use crate::goal_selection::{GoalChoice, GoalSelector, Mode, SelectorState};
use crate::rng::{child_seed, rng_from_seed, unit, CoreRng};
use crate::teachers::alp_gmm::{proportional_component, AlpGmmConfig, UnitBox};
use crate::teachers::gmm::{best_by_aic, EmConfig, Gmm};

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

pub struct CovarGmm {
    cfg: CovarGmmConfig,
    unit_box: UnitBox,
    seed: u64,
    rng: CoreRng,
    fit_rng: CoreRng,
    points: Vec<f64>,
    values: Vec<f64>,
    /// The last `fit_rate` (scaled task, competence) rows; time is added at the fit.
    window: VecDeque<Vec<f64>>,
    gmm: Option<Gmm>,
}

impl CovarGmm {
    pub fn new(low: &[f64], high: &[f64], cfg: CovarGmmConfig, seed: u64) -> Result<Self> {
        check_bounds("CovarGmmSelector", low, high)?;
        cfg.mixture.validate("CovarGmmSelector")?;
        Ok(CovarGmm {
            cfg,
            unit_box: UnitBox { low: low.to_vec(), high: high.to_vec() },
            seed,
            rng: rng_from_seed(seed),
            fit_rng: rng_from_seed(child_seed(seed, 1)),
            points: Vec::new(),
            values: Vec::new(),
            window: VecDeque::new(),
            gmm: None,
        })
    }

    /// The current mixture over (time, scaled task, competence), once fitted.
    pub fn gmm(&self) -> Option<&Gmm> {
        self.gmm.as_ref()
    }

    /// Component j's progress: the covariance of time (first coordinate) and competence (last).
    pub fn progress(&self, j: usize) -> Option<f64> {
        self.gmm.as_ref().map(|g| g.covariances[j][(0, g.means[j].len() - 1)])
    }

    fn refit(&mut self) {
        let n = self.window.len();
        let data: Vec<DVector<f64>> = self
            .window
            .iter()
            .enumerate()
            .map(|(i, r)| {
                let mut v = Vec::with_capacity(r.len() + 1);
                v.push(i as f64 / (n.max(2) - 1) as f64);
                v.extend_from_slice(r);
                DVector::from_vec(v)
            })
            .collect();
        let ks: Vec<usize> = (2..=self.cfg.mixture.max_components).collect();
        self.gmm = best_by_aic(&data, &ks, EmConfig::default(), &mut self.fit_rng);
    }
}

impl GoalSelector for CovarGmm {
    fn low(&self) -> &[f64] {
        &self.unit_box.low
    }
    fn high(&self) -> &[f64] {
        &self.unit_box.high
    }
    fn sample(&mut self) -> GoalChoice {
        let d = self.unit_box.low.len();
        let m = &self.cfg.mixture;
        let random = self.values.len() < m.bootstrap || unit(&mut self.rng) < m.random_task_ratio;
        match (&self.gmm, random) {
            (Some(g), false) => {
                let abs = self.cfg.absolute_lp;
                let j = proportional_component(
                    g,
                    |j| {
                        let c = g.covariances[j][(0, d + 1)];
                        if abs {
                            c.abs()
                        } else {
                            c
                        }
                    },
                    &mut self.rng,
                );
                let x = g.sample_component(j, &mut self.rng);
                GoalChoice { goal: self.unit_box.scale_back(&x.as_slice()[1..=d]), mode: Mode::Interest, region: Some(j) }
            }
            _ => GoalChoice { goal: self.unit_box.uniform(&mut self.rng), mode: Mode::Global, region: None },
        }
    }
    fn update(&mut self, point: &[f64], competence: f64) -> Option<usize> {
        let mut row = self.unit_box.to_unit(point);
        row.push(competence);
        self.points.extend_from_slice(point);
        self.values.push(competence);
        self.window.push_back(row);
        if self.window.len() > self.cfg.mixture.fit_rate {
            self.window.pop_front();
        }
        if self.values.len() % self.cfg.mixture.fit_rate == 0 {
            self.refit();
        }
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
        let Ok(mut fresh) = CovarGmm::new(&self.unit_box.low, &self.unit_box.high, self.cfg, self.seed) else { return false };
        (fresh.points, fresh.values) = (points.clone(), values.clone());
        fresh.window = window.chunks_exact(d + 1).map(|r| r.to_vec()).collect();
        fresh.gmm = gmm.as_ref().map(|(w, (m, c))| Gmm::from_flat(d + 2, w, m, c));
        (fresh.rng, fresh.fit_rng) = (rng.clone(), fit_rng.clone());
        *self = fresh;
        true
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn goals_go_where_competence_changes_with_time() {
        let cfg = CovarGmmConfig { mixture: AlpGmmConfig { fit_rate: 150, bootstrap: 150, ..AlpGmmConfig::default() }, absolute_lp: true };
        let mut t = CovarGmm::new(&[0.0, 0.0], &[1.0, 1.0], cfg, 5).unwrap();
        // Competence rises with time for x < 0.3 and is flat elsewhere.
        for k in 0..3000 {
            let g = t.sample().goal;
            let c = if g[0] < 0.3 { (-1.0 + k as f64 / 1500.0).min(0.0) } else { -0.5 };
            t.update(&g, c);
        }
        assert!(t.gmm().is_some());
        // While competence still rises there (it saturates at task 1500), and after.
        let share = |from: usize, to: usize| t.points.chunks_exact(2).skip(from).take(to - from).filter(|p| p[0] < 0.3).count() as f64 / (to - from) as f64;
        assert!(share(500, 1500) > 0.5, "{}", share(500, 1500)); // uniform would give 0.3
        assert!(share(2500, 3000) < share(500, 1500), "{} {}", share(2500, 3000), share(500, 1500));
    }
}

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

use nalgebra::DVector;

use crate::error::Result;
use crate::high_level::goal_selection::{GoalChoice, GoalSelector};
use crate::high_level::teachers::gmm::Gmm;
use crate::high_level::teachers::mixture::MixtureCore;

pub use crate::config::teachers::CovarGmmConfig;

pub struct CovarGmm {
    core: MixtureCore,
    absolute_lp: bool,
}

impl CovarGmm {
    pub fn new(low: &[f64], high: &[f64], cfg: CovarGmmConfig, seed: u64) -> Result<Self> {
        Ok(CovarGmm { core: MixtureCore::new("CovarGmmSelector", low, high, cfg.mixture, seed)?, absolute_lp: cfg.absolute_lp })
    }

    /// The current mixture over (time, scaled task, competence), once fitted.
    pub fn gmm(&self) -> Option<&Gmm> {
        self.core.gmm.as_ref()
    }

    /// Component j's progress: the covariance of time (first coordinate) and competence (last).
    pub fn progress(&self, j: usize) -> Option<f64> {
        self.core.gmm.as_ref().map(|g| g.covariances[j][(0, g.means[j].len() - 1)])
    }
}

impl GoalSelector for CovarGmm {
    fn goal_box(&self) -> (&[f64], &[f64]) {
        (&self.core.unit_box.low, &self.core.unit_box.high)
    }
    fn sample(&mut self) -> GoalChoice {
        let d = self.core.unit_box.low.len();
        let abs = self.absolute_lp;
        self.core.sample(
            |g, j| {
                let c = g.covariances[j][(0, d + 1)];
                if abs {
                    c.abs()
                } else {
                    c
                }
            },
            1..d + 1,
        )
    }
    fn update(&mut self, point: &[f64], competence: f64) -> Option<usize> {
        let mut row = self.core.unit_box.to_unit(point);
        row.push(competence);
        if self.core.record(point, competence, row) {
            // Time: each row's rank in the window, scaled to [0, 1].
            let n = self.core.window.len();
            let data: Vec<DVector<f64>> = self
                .core
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
            self.core.fit(&data);
        }
        None
    }
    fn save(&self) -> Option<Vec<u8>> {
        self.core.save()
    }
    fn load(&mut self, state: &[u8]) -> bool {
        let d = self.core.unit_box.low.len();
        self.core.load(state, d + 1, d + 2)
    }
}

build_by_new!(CovarGmmConfig => CovarGmm, box);

#[cfg(test)]
mod tests {
    use super::*;
    use crate::config::teachers::AlpGmmConfig;

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
        let share = |from: usize, to: usize| t.core.points.chunks_exact(2).skip(from).take(to - from).filter(|p| p[0] < 0.3).count() as f64 / (to - from) as f64;
        assert!(share(500, 1500) > 0.5, "{}", share(500, 1500)); // uniform would give 0.3
        assert!(share(2500, 3000) < share(500, 1500), "{} {}", share(2500, 3000), share(500, 1500));
    }
}

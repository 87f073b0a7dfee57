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

use nalgebra::DVector;

use crate::error::Result;
use crate::high_level::goal_selection::{GoalChoice, GoalSelector};
use crate::high_level::teachers::gmm::Gmm;
pub use crate::high_level::teachers::mixture::AlpGmmConfig;
use crate::high_level::teachers::mixture::MixtureCore;
use crate::model::kd_tree::KdTree;
use crate::model::neighbours::{Neighbour, NeighbourIndex};

pub struct AlpGmm {
    core: MixtureCore,
    index: KdTree,
    scratch: Vec<Neighbour>,
}

impl AlpGmm {
    pub fn new(low: &[f64], high: &[f64], cfg: AlpGmmConfig, seed: u64) -> Result<Self> {
        Ok(AlpGmm { core: MixtureCore::new("AlpGmmSelector", low, high, cfg, seed)?, index: KdTree::new(low.len()), scratch: Vec::new() })
    }

    /// The current mixture over (scaled task, ALP), once fitted.
    pub fn gmm(&self) -> Option<&Gmm> {
        self.core.gmm.as_ref()
    }
}

impl GoalSelector for AlpGmm {
    fn goal_box(&self) -> (&[f64], &[f64]) {
        (&self.core.unit_box.low, &self.core.unit_box.high)
    }
    fn sample(&mut self) -> GoalChoice {
        let d = self.core.unit_box.low.len();
        self.core.sample(|g, j| g.means[j][d], 0..d)
    }
    fn update(&mut self, point: &[f64], competence: f64) -> Option<usize> {
        let t = self.core.unit_box.to_unit(point);
        let alp = if self.index.is_empty() {
            0.0
        } else {
            self.index.knn(&t, 1, &mut self.scratch);
            (competence - self.core.values[self.scratch[0].id as usize]).abs()
        };
        self.index.add(&t);
        let mut row = t;
        row.push(alp);
        if self.core.record(point, competence, row) {
            let data: Vec<DVector<f64>> = self.core.window.iter().map(|r| DVector::from_column_slice(r)).collect();
            self.core.fit(&data);
        }
        None
    }
    fn save(&self) -> Option<Vec<u8>> {
        self.core.save()
    }
    fn load(&mut self, state: &[u8]) -> bool {
        let d = self.core.unit_box.low.len();
        if !self.core.load(state, d + 1, d + 1) {
            return false;
        }
        self.index = KdTree::new(d);
        for p in self.core.points.chunks_exact(d) {
            self.index.add(&self.core.unit_box.to_unit(p));
        }
        true
    }
}

build_by_new!(AlpGmmConfig => AlpGmm, box);

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
        let alps: Vec<f64> = t.core.window.iter().map(|r| r[2]).collect();
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
        let late: Vec<Vec<f64>> = t.core.points.chunks_exact(2).skip(1500).map(|p| p.to_vec()).collect();
        let share = late.iter().filter(|p| p[0] < 3.0).count() as f64 / late.len() as f64;
        assert!(share > 0.5, "{share}"); // uniform would give 0.3
        assert!(late.iter().all(|p| p.iter().all(|v| (0.0..=10.0).contains(v))));
    }

    #[test]
    fn bad_parameters_are_named() {
        let e = AlpGmm::new(&[0.0], &[1.0], AlpGmmConfig { max_components: 60, fit_rate: 50, ..AlpGmmConfig::default() }, 0).err().unwrap().to_string();
        assert!(e.contains("'max_components' parameter of AlpGmmSelector") && e.contains("fit_rate = 50"), "{e}");
        let e = AlpGmm::new(&[0.0], &[1.0], AlpGmmConfig { max_components: 300, ..AlpGmmConfig::default() }, 0).err().unwrap().to_string();
        assert!(e.contains("an int in [2, 100]"), "{e}");
        assert!(AlpGmm::new(&[0.0], &[1.0], AlpGmmConfig { random_task_ratio: 1.5, ..AlpGmmConfig::default() }, 0).is_err());
    }
}

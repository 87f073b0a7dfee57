//! Learning progress over a list of tasks, from fast and slow moving averages of success
//! (Kanitscheider et al., "Multi-task curriculum learning in a complex, visual, hard-exploration
//! domain: Minecraft", 2021).
//!
//! Each task i keeps two exponential moving averages of its success s in [0, 1]: a fast one,
//! f_i <- f_i + alpha (s - f_i), and a slow one that follows the fast one,
//! g_i <- g_i + alpha (f_i - g_i). Both are mapped through the paper's reweighting
//! r(p) = p (1 - theta) / (p + theta (1 - 2 p)), which stretches small success rates (where
//! progress on a hard task begins), and the learning progress is |r(f_i) - r(g_i)|. Tasks are
//! sampled with probabilities proportional to the sigmoid of their progress z-scored over all
//! tasks, uniformly while every task has the same progress. (Syllabus's implementation gives no
//! probability to tasks without progress, which stops trying untried tasks once one progresses;
//! the paper does not say so, and we follow the paper.)
//!
//! Goals are task indices 0..n-1, given as one-coordinate points (the ask/tell API's goals).

use serde::{Deserialize, Serialize};

pub use crate::config::teachers::DiscreteLpConfig;
use crate::error::Result;
use crate::config::teachers::TeacherParams;
use crate::high_level::teachers::task_index::{check_task, task_of};
use crate::high_level::goal_selection::{load_state, save_state, GoalChoice, GoalSelector, Mode};
use crate::rng::{pick_weighted, rng_from_seed, unit, CoreRng};

/// The teacher's state: its generator and both moving averages of every task.
#[derive(Debug, Clone, Serialize, Deserialize)]
struct DiscreteLpState {
    rng: CoreRng,
    fast: Vec<f64>,
    slow: Vec<f64>,
}

#[derive(Debug, Clone)]
pub struct DiscreteLp {
    cfg: DiscreteLpConfig,
    low: Vec<f64>,
    high: Vec<f64>,
    fast: Vec<f64>,
    slow: Vec<f64>,
    rng: CoreRng,
}

impl DiscreteLp {
    pub fn new(cfg: DiscreteLpConfig, seed: u64) -> Result<Self> {
        cfg.validate()?;
        let n = cfg.n_tasks;
        Ok(DiscreteLp { cfg, low: vec![0.0], high: vec![(n - 1) as f64], fast: vec![0.0; n], slow: vec![0.0; n], rng: rng_from_seed(seed) })
    }

    fn reweight(&self, p: f64) -> f64 {
        let t = self.cfg.theta;
        let d = p + t * (1.0 - 2.0 * p);
        if d == 0.0 {
            0.0
        } else {
            p * (1.0 - t) / d
        }
    }

    /// Each task's learning progress |r(fast) - r(slow)|.
    pub fn progress(&self) -> Vec<f64> {
        self.fast.iter().zip(&self.slow).map(|(f, s)| (self.reweight(*f) - self.reweight(*s)).abs()).collect()
    }

    /// The probability of sampling each task.
    pub fn distribution(&self) -> Vec<f64> {
        let lp = self.progress();
        let n = lp.len() as f64;
        let mean = lp.iter().sum::<f64>() / n;
        let sd = (lp.iter().map(|v| (v - mean).powi(2)).sum::<f64>() / n).sqrt();
        if sd <= 0.0 || sd.is_nan() {
            return vec![1.0 / n; lp.len()];
        }
        let w: Vec<f64> = lp.iter().map(|v| 1.0 / (1.0 + (-(v - mean) / sd).exp())).collect();
        let total: f64 = w.iter().sum();
        w.iter().map(|x| x / total).collect()
    }

    fn task(&self, goal: &[f64]) -> Option<usize> {
        task_of(goal, self.cfg.n_tasks)
    }

    pub fn check_goal(&self, goal: &[f64], competence: f64) -> Result<()> {
        check_task(goal, self.cfg.n_tasks)?;
        if !(0.0..=1.0).contains(&competence) {
            return Err(crate::Error::InvalidInput(format!("competence must be a success rate in [0, 1] for the discrete learning-progress teacher; got {}.", crate::error::Num(competence))));
        }
        Ok(())
    }
}

impl GoalSelector for DiscreteLp {
    fn goal_box(&self) -> (&[f64], &[f64]) {
        (&self.low, &self.high)
    }
    fn sample(&mut self) -> GoalChoice {
        let p = self.distribution();
        let task = pick_weighted(&p, unit(&mut self.rng));
        GoalChoice { goal: vec![task as f64], mode: Mode::Interest, region: Some(task) }
    }
    fn check_told(&self, goal: &[f64], competence: f64) -> Result<()> {
        self.check_goal(goal, competence)
    }
    fn update(&mut self, point: &[f64], competence: f64) -> Option<usize> {
        let i = self.task(point)?;
        let a = self.cfg.alpha;
        self.fast[i] += a * (competence - self.fast[i]);
        self.slow[i] += a * (self.fast[i] - self.slow[i]);
        Some(i)
    }
    fn save(&self) -> Option<Vec<u8>> {
        save_state(&DiscreteLpState { rng: self.rng.clone(), fast: self.fast.clone(), slow: self.slow.clone() })
    }
    fn load(&mut self, state: &[u8]) -> bool {
        match load_state(state) {
            Some(DiscreteLpState { rng, fast, slow }) if fast.len() == self.cfg.n_tasks && slow.len() == self.cfg.n_tasks => {
                (self.rng, self.fast, self.slow) = (rng, fast, slow);
                true
            }
            _ => false,
        }
    }
}

build_by_new!(DiscreteLpConfig => DiscreteLp, tasks);

#[cfg(test)]
mod tests {
    use super::*;

    fn teacher(n: usize) -> DiscreteLp {
        DiscreteLp::new(DiscreteLpConfig { n_tasks: n, alpha: 0.1, theta: 0.1 }, 1).unwrap()
    }

    #[test]
    fn uniform_until_progress_then_by_progress() {
        let mut t = teacher(4);
        assert_eq!(t.distribution(), vec![0.25; 4]);
        // Task 2 starts to succeed; task 0 keeps failing; 1 and 3 are never tried.
        for _ in 0..5 {
            t.update(&[2.0], 1.0);
            t.update(&[0.0], 0.0);
        }
        let p = t.distribution();
        assert!(p[2] > p[0] && p[0] == p[1] && p[1] == p[3] && p[0] > 0.0, "{p:?}");
        // sigmoid(z) with z = +sqrt(3) for task 2 and -1/sqrt(3) for the others.
        let s = |z: f64| 1.0 / (1.0 + (-z).exp());
        let expect = s(3f64.sqrt()) / (s(3f64.sqrt()) + 3.0 * s(-1.0 / 3f64.sqrt()));
        assert!((p[2] - expect).abs() < 1e-12, "{} vs {expect}", p[2]);
        let n2 = (0..2000).filter(|_| t.sample().goal == vec![2.0]).count() as f64 / 2000.0;
        assert!((n2 - expect).abs() < 0.05, "{n2} vs {expect}");
        // A second task with faster progress gets the larger share.
        for _ in 0..3 {
            t.update(&[3.0], 1.0);
        }
        let lp = t.progress();
        let p = t.distribution();
        assert!(lp[3] > lp[2] && p[3] > p[2] && (p.iter().sum::<f64>() - 1.0).abs() < 1e-12, "{lp:?} {p:?}");
    }

    #[test]
    fn the_reweighting_stretches_small_success_rates() {
        let t = teacher(1);
        assert_eq!(t.reweight(0.0), 0.0);
        assert!((t.reweight(1.0) - 1.0).abs() < 1e-15);
        assert!((t.reweight(0.5) - 0.9).abs() < 1e-15);
        // theta = 0.1: r(0.1) = 0.09 / 0.18 = 0.5.
        assert!((t.reweight(0.1) - 0.5).abs() < 1e-12);
        let identity = DiscreteLp::new(DiscreteLpConfig { n_tasks: 1, alpha: 0.1, theta: 0.5 }, 0).unwrap();
        assert!((identity.reweight(0.3) - 0.3).abs() < 1e-15);
    }

    #[test]
    fn bad_parameters_and_goals_are_named() {
        let e = DiscreteLp::new(DiscreteLpConfig { n_tasks: 0, alpha: 0.1, theta: 0.1 }, 0).unwrap_err().to_string();
        assert!(e.contains("'n_tasks' parameter of DiscreteLpSelector"), "{e}");
        let e = DiscreteLp::new(DiscreteLpConfig { n_tasks: 3, alpha: 0.0, theta: 0.1 }, 0).unwrap_err().to_string();
        assert!(e.contains("'alpha'"), "{e}");
        let t = teacher(3);
        assert!(t.check_goal(&[1.5], 0.5).unwrap_err().to_string().contains("whole number in [0, 3)"));
        assert!(t.check_goal(&[1.0], -0.5).unwrap_err().to_string().contains("[0, 1]"));
        assert!(t.check_goal(&[2.0], 1.0).is_ok());
    }
}

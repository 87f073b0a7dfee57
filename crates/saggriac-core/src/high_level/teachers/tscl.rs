//! Teacher-Student Curriculum Learning over a list of tasks (Matiisen, Oliver, Cohen & Schulman,
//! "Teacher-Student Curriculum Learning", arXiv:1707.00183, 2017; IEEE TNNLS 2019).
//!
//! The teacher is a bandit whose arms are the tasks; the student's learning progress on a task
//! is its reward. Step t counts the scores told so far. Two of the paper's estimates:
//! - Window (Algorithm 3): each task keeps its last K scores with the steps they were told at;
//!   its value is the slope of their least-squares line (score per step).
//! - Sampling (Algorithm 4): each task keeps its last K score changes (its score minus its
//!   previous score, 0 before the first, as the authors' code starts it); its value is one of
//!   them drawn uniformly.
//!
//! A task is then chosen by |value| (`absolute`, the paper's: a task being forgotten has a
//! negative slope and is practised again) with an epsilon-greedy or a Boltzmann policy. The
//! paper prints the sampling variant's choice as the plain argmax, which is `epsilon = 0`; the
//! authors' code adds the epsilon-greedy draw, as we do by default. A task without enough
//! records for a value (two scores for the window, one change for sampling) is tried first,
//! the lowest index first: the authors' code gives it the value 1, above any change of a score
//! in [0, 1], and we do not tie that rule to the scores' scale. Ties go to the lowest index, as
//! numpy's argmax. Goals are task indices given as one-coordinate points.

use std::collections::VecDeque;

use serde::{Deserialize, Serialize};

use crate::config::teachers::TeacherParams;
pub use crate::config::teachers::{TsclConfig, TsclPolicy, TsclVariant};
use crate::error::{Error, Num, Result};
use crate::high_level::goal_selection::{load_state, save_state, GoalChoice, GoalSelector, Mode};
use crate::high_level::teachers::task_index::{check_task, task_of};
use crate::rng::{index, pick_weighted, rng_from_seed, unit, CoreRng};

/// What the teacher knows of one task: its last K scores with their steps (window), its last K
/// score changes (sampling), and its last score.
#[derive(Debug, Clone, Default, Serialize, Deserialize)]
struct TaskRecord {
    scores: VecDeque<(u64, f64)>,
    changes: VecDeque<f64>,
    last: f64,
}

#[derive(Debug, Clone, Serialize, Deserialize)]
struct TsclState {
    rng: CoreRng,
    step: u64,
    tasks: Vec<TaskRecord>,
}

#[derive(Debug, Clone)]
pub struct Tscl {
    cfg: TsclConfig,
    low: Vec<f64>,
    high: Vec<f64>,
    state: TsclState,
}

/// The slope of the least-squares line through (t, x).
fn slope(points: &VecDeque<(u64, f64)>) -> f64 {
    let n = points.len() as f64;
    let t_mean = points.iter().map(|p| p.0 as f64).sum::<f64>() / n;
    let x_mean = points.iter().map(|p| p.1).sum::<f64>() / n;
    let (mut sxy, mut sxx) = (0.0, 0.0);
    for &(t, x) in points {
        let dt = t as f64 - t_mean;
        sxy += dt * (x - x_mean);
        sxx += dt * dt;
    }
    // The steps are distinct, so sxx > 0 once there are two of them.
    sxy / sxx
}

impl Tscl {
    pub fn new(cfg: TsclConfig, seed: u64) -> Result<Self> {
        cfg.validate()?;
        let state = TsclState { rng: rng_from_seed(seed), step: 0, tasks: vec![TaskRecord::default(); cfg.n_tasks] };
        Ok(Tscl { cfg, low: vec![0.0], high: vec![(cfg.n_tasks - 1) as f64], state })
    }

    /// Each task's learning-progress estimate, None where it has too few records. The sampling
    /// variant draws (one draw per task with records, in task order).
    fn values(&mut self) -> Vec<Option<f64>> {
        let (variant, rng) = (self.cfg.variant, &mut self.state.rng);
        self.state
            .tasks
            .iter()
            .map(|r| match variant {
                TsclVariant::Window => (r.scores.len() >= 2).then(|| slope(&r.scores)),
                TsclVariant::Sampling => (!r.changes.is_empty()).then(|| r.changes[index(rng, r.changes.len())]),
            })
            .collect()
    }

    /// The window variant's slopes (None: fewer than two scores), without drawing anything.
    pub fn slopes(&self) -> Vec<Option<f64>> {
        self.state.tasks.iter().map(|r| (r.scores.len() >= 2).then(|| slope(&r.scores))).collect()
    }

    fn task(&self, goal: &[f64]) -> Option<usize> {
        task_of(goal, self.cfg.n_tasks)
    }

    fn choose(&mut self) -> (usize, Mode) {
        let n = self.cfg.n_tasks;
        if let Some(first) = self.state.tasks.iter().position(|r| match self.cfg.variant {
            TsclVariant::Window => r.scores.len() < 2,
            TsclVariant::Sampling => r.changes.is_empty(),
        }) {
            if self.cfg.policy == TsclPolicy::EpsilonGreedy && unit(&mut self.state.rng) < self.cfg.epsilon {
                return (index(&mut self.state.rng, n), Mode::Random);
            }
            return (first, Mode::Initial);
        }
        let abs = self.cfg.absolute;
        let q: Vec<f64> = self.values().into_iter().map(|v| v.map_or(0.0, |v| if abs { v.abs() } else { v })).collect();
        match self.cfg.policy {
            TsclPolicy::EpsilonGreedy => {
                if unit(&mut self.state.rng) < self.cfg.epsilon {
                    return (index(&mut self.state.rng, n), Mode::Random);
                }
                // The first of the largest, as numpy's argmax.
                let best = q.iter().enumerate().fold(0, |b, (i, &v)| if v > q[b] { i } else { b });
                (best, Mode::Interest)
            }
            TsclPolicy::Boltzmann => {
                let top = q.iter().cloned().fold(f64::NEG_INFINITY, f64::max);
                let w: Vec<f64> = q.iter().map(|v| ((v - top) / self.cfg.temperature).exp()).collect();
                let pick = pick_weighted(&w, unit(&mut self.state.rng) * w.iter().sum::<f64>());
                (pick, Mode::Interest)
            }
        }
    }
}

impl GoalSelector for Tscl {
    fn goal_box(&self) -> (&[f64], &[f64]) {
        (&self.low, &self.high)
    }
    fn sample(&mut self) -> GoalChoice {
        let (task, mode) = self.choose();
        GoalChoice { goal: vec![task as f64], mode, region: Some(task) }
    }
    fn check_told(&self, goal: &[f64], competence: f64) -> Result<()> {
        check_task(goal, self.cfg.n_tasks)?;
        if !(competence.is_finite() && competence.abs() <= 1e100) {
            return Err(Error::InvalidInput(format!("competence must be a finite score with |score| <= 1e100 for TSCL; got {}.", Num(competence))));
        }
        Ok(())
    }
    fn update(&mut self, point: &[f64], competence: f64) -> Option<usize> {
        let i = self.task(point)?;
        let (k, step) = (self.cfg.window, self.state.step);
        let r = &mut self.state.tasks[i];
        r.scores.push_back((step, competence));
        r.changes.push_back(competence - r.last);
        r.last = competence;
        for _ in k..r.scores.len() {
            r.scores.pop_front();
        }
        for _ in k..r.changes.len() {
            r.changes.pop_front();
        }
        self.state.step += 1;
        Some(i)
    }
    fn save(&self) -> Option<Vec<u8>> {
        save_state(&self.state)
    }
    fn load(&mut self, state: &[u8]) -> bool {
        match load_state::<TsclState>(state) {
            Some(s) if s.tasks.len() == self.cfg.n_tasks && s.tasks.iter().all(|r| r.scores.len() <= self.cfg.window && r.changes.len() <= self.cfg.window) => {
                self.state = s;
                true
            }
            _ => false,
        }
    }
}

build_by_new!(TsclConfig => Tscl, tasks);

#[cfg(test)]
mod tests {
    use super::*;

    fn cfg(n: usize, variant: TsclVariant) -> TsclConfig {
        TsclConfig { n_tasks: n, variant, epsilon: 0.0, ..TsclConfig::default() }
    }

    #[test]
    fn the_window_slope_is_the_least_squares_slope() {
        let pts: VecDeque<(u64, f64)> = [(0, 1.0), (2, 2.0), (5, 4.0)].into_iter().collect();
        // Brute force: minimise the squared error over a fine grid of slopes with the best intercept.
        let best = (-2000..2000)
            .map(|k| k as f64 / 1000.0)
            .min_by(|a, b| {
                let sse = |m: f64| {
                    let c = pts.iter().map(|p| p.1 - m * p.0 as f64).sum::<f64>() / 3.0;
                    pts.iter().map(|p| (p.1 - m * p.0 as f64 - c).powi(2)).sum::<f64>()
                };
                sse(*a).partial_cmp(&sse(*b)).unwrap()
            })
            .unwrap();
        assert!((slope(&pts) - best).abs() < 1e-3, "{} vs {best}", slope(&pts));
    }

    #[test]
    fn untried_tasks_first_then_the_steepest() {
        let mut t = Tscl::new(cfg(3, TsclVariant::Window), 0).unwrap();
        // Each task is tried twice before any slope decides, lowest index first.
        let mut asked = Vec::new();
        for _ in 0..6 {
            let g = t.sample();
            asked.push(g.goal[0] as usize);
            // Task 1 climbs fast, task 2 slowly, task 0 stays.
            let n = t.state.tasks[g.goal[0] as usize].scores.len() as f64;
            let score = [0.0, 0.3 * n, 0.05 * n][g.goal[0] as usize];
            t.update(&g.goal, score);
        }
        assert_eq!(asked, vec![0, 0, 1, 1, 2, 2]);
        assert_eq!(t.sample().goal, vec![1.0]);
    }

    #[test]
    fn a_task_being_forgotten_is_chosen_by_its_absolute_slope() {
        for (absolute, want) in [(true, 1.0), (false, 0.0)] {
            let mut t = Tscl::new(TsclConfig { absolute, ..cfg(2, TsclVariant::Window) }, 0).unwrap();
            for (i, x) in [(0, 0.5), (0, 0.5), (1, 0.9), (1, 0.5)] {
                t.update(&[i as f64], x);
            }
            assert_eq!(t.sample().goal, vec![want], "absolute = {absolute}");
        }
    }

    #[test]
    fn sampling_draws_one_of_the_recent_changes() {
        let mut t = Tscl::new(TsclConfig { window: 3, ..cfg(2, TsclVariant::Sampling) }, 5).unwrap();
        for x in [0.1, 0.2, 0.4, 0.8] {
            t.update(&[0.0], x);
        }
        t.update(&[1.0], 0.25);
        // Task 0 keeps its last three changes (0.1, 0.2, 0.4), task 1 one (0.25).
        let mut wins = 0;
        for _ in 0..3000 {
            let v = t.values();
            let d = v[0].unwrap();
            assert!([0.1, 0.2, 0.4].iter().any(|c| (c - d).abs() < 1e-12), "{d}");
            assert_eq!(v[1], Some(0.25));
            wins += (d > 0.25) as usize;
        }
        let share = wins as f64 / 3000.0;
        assert!((share - 1.0 / 3.0).abs() < 0.04, "{share}");
    }

    #[test]
    fn saved_and_loaded_it_asks_the_same() {
        let mut a = Tscl::new(TsclConfig { epsilon: 0.3, ..cfg(4, TsclVariant::Sampling) }, 9).unwrap();
        for s in 0..40 {
            let g = a.sample();
            a.update(&g.goal, (s % 7) as f64 / 7.0);
        }
        let mut b = Tscl::new(a.cfg, 1).unwrap();
        assert!(b.load(&a.save().unwrap()));
        for _ in 0..50 {
            let (ga, gb) = (a.sample(), b.sample());
            assert_eq!(ga.goal, gb.goal);
            a.update(&ga.goal, 0.5);
            b.update(&gb.goal, 0.5);
        }
    }
}

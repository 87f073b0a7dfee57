//! Prioritized Level Replay (Jiang, Grefenstette & Rocktäschel, ICML 2021, Algorithms 1-2) over a
//! list of levels 0..n-1.
//!
//! Each draw first decides between a new level and a replay (P_D). A new level is drawn
//! uniformly among the levels never drawn, and joins the seen levels with score 0. A replay
//! draws a seen level from P_replay = (1 - rho) P_S + rho P_C:
//! - P_S, rank prioritisation: h(S_i) = 1 / rank(S_i) among the seen levels' scores in
//!   descending order, P_S(i) = h(S_i)^(1/beta) / sum_j h(S_j)^(1/beta);
//! - P_C, staleness: P_C(i) = (c - C_i) / sum_j (c - C_j), c the number of draws so far and C_i
//!   the draw at which level i was last drawn (uniform over the seen levels while every
//!   staleness is 0).
//!
//! Readings of what the paper leaves open (docs/teachers.md):
//! - P_D: `Proportionate` replays with probability |seen| / n (so new levels first, and only
//!   replays once all are seen); `Fixed` replays with probability `replay_prob` once a level has
//!   been seen, and always once all have.
//! - Scores: the paper scores a level by the agent's value loss (mean |GAE|) on its last
//!   episode. Through ask/tell the teacher sees what `update` is told: with `score = Progress`
//!   (the default) a level's score is |competence - the level's previous competence| (0 on its
//!   first tell), its learning progress; with `score = Told` the told value is the score itself.
//! - Ties in rank share the mean of their ranks (the reference code orders them by numpy's sort).
//! - A level joins the seen levels when it is drawn (the paper's Algorithm 2), or when it is told
//!   without having been drawn.

use serde::{Deserialize, Serialize};

pub use crate::config::teachers::{PlrConfig, PlrScore, ReplaySchedule};
use crate::error::Result;
use crate::config::teachers::TeacherParams;
use crate::high_level::teachers::task_index::{check_task, task_of};
use crate::high_level::goal_selection::{load_state, save_state, GoalChoice, GoalSelector, Mode};
use crate::rng::{index, rng_from_seed, unit, CoreRng};

/// The teacher's state: its generator, the draw count c, and per level whether it was seen, its
/// score, the draw at which it was last drawn and its last told competence.
#[derive(Debug, Clone, Serialize, Deserialize)]
struct PlrState {
    rng: CoreRng,
    draws: u64,
    seen: Vec<bool>,
    score: Vec<f64>,
    last_drawn: Vec<u64>,
    last_competence: Vec<Option<f64>>,
}

#[derive(Debug, Clone)]
pub struct Plr {
    cfg: PlrConfig,
    low: Vec<f64>,
    high: Vec<f64>,
    s: PlrState,
    /// Cached, recomputed when a score or the seen set changed: the seen levels by descending
    /// score, P_S's cumulative sums in that order, and P_S by level.
    order: Vec<usize>,
    cum_score: Vec<f64>,
    p_score: Vec<f64>,
    dirty: bool,
    /// rank^(-1/beta) for the integer ranks 1..=n (ties need their mean rank's own power).
    rank_weight: Vec<f64>,
}

impl Plr {
    pub fn new(cfg: PlrConfig, seed: u64) -> Result<Self> {
        cfg.validate()?;
        let n = cfg.n_tasks;
        let s = PlrState { rng: rng_from_seed(seed), draws: 0, seen: vec![false; n], score: vec![0.0; n], last_drawn: vec![0; n], last_competence: vec![None; n] };
        Ok(Plr { cfg, low: vec![0.0], high: vec![(n - 1) as f64], s, order: Vec::new(), cum_score: Vec::new(), p_score: vec![0.0; n], dirty: true, rank_weight: Vec::new() })
    }

    /// Recompute the seen levels' order and P_S (rank prioritisation, ties at their mean rank).
    fn refresh(&mut self) {
        if !self.dirty {
            return;
        }
        let inv_beta = 1.0 / self.cfg.temperature;
        if self.rank_weight.is_empty() {
            self.rank_weight = (1..=self.cfg.n_tasks).map(|r| (r as f64).powf(-inv_beta)).collect();
        }
        let s = &self.s;
        // The previous order, with newly seen levels appended, is nearly sorted: the adaptive
        // sort makes this close to linear when one score changed.
        let mut in_order = vec![false; s.seen.len()];
        self.order.retain(|&i| s.seen[i] && !std::mem::replace(&mut in_order[i], true));
        self.order.extend((0..s.seen.len()).filter(|&i| s.seen[i] && !in_order[i]));
        self.order.sort_by(|a, b| s.score[*b].total_cmp(&s.score[*a]).then(a.cmp(b)));
        self.p_score.iter_mut().for_each(|x| *x = 0.0);
        let order = &self.order;
        let mut k = 0;
        while k < order.len() {
            let mut j = k;
            while j + 1 < order.len() && s.score[order[j + 1]] == s.score[order[k]] {
                j += 1;
            }
            // Ranks k+1 ..= j+1 share their mean.
            let h = if j == k { self.rank_weight[k] } else { ((k + j) as f64 / 2.0 + 1.0).powf(-inv_beta) };
            for &i in &order[k..=j] {
                self.p_score[i] = h;
            }
            k = j + 1;
        }
        let total: f64 = order.iter().map(|&i| self.p_score[i]).sum();
        let mut acc = 0.0;
        self.cum_score.clear();
        for &i in order {
            self.p_score[i] /= total;
            acc += self.p_score[i];
            self.cum_score.push(acc);
        }
        self.dirty = false;
    }

    /// The staleness weights c - C_i of the seen levels (in `order`) and their sum.
    fn staleness_total(&self) -> f64 {
        self.order.iter().map(|&i| (self.s.draws - self.s.last_drawn[i]) as f64).sum()
    }

    /// A replay: from P_S with probability 1 - rho, else from P_C (the same mixture, drawn in
    /// two steps so that P_S's draw is a binary search).
    fn replay(&mut self) -> usize {
        self.refresh();
        let m = self.order.len();
        if unit(&mut self.s.rng) < self.cfg.staleness_coef {
            let total = self.staleness_total();
            if total.is_nan() || total <= 0.0 {
                return self.order[index(&mut self.s.rng, m)];
            }
            let mut u = unit(&mut self.s.rng) * total;
            for &i in &self.order {
                let w = (self.s.draws - self.s.last_drawn[i]) as f64;
                if u < w {
                    return i;
                }
                u -= w;
            }
            // Rounding left u at the end: the last level with weight.
            *self.order.iter().rev().find(|&&i| self.s.draws > self.s.last_drawn[i]).unwrap_or(&self.order[m - 1])
        } else {
            let u = unit(&mut self.s.rng) * self.cum_score[m - 1];
            self.order[self.cum_score.partition_point(|&c| c <= u).min(m - 1)]
        }
    }

    /// P_replay over all levels (0 for unseen ones): what a replay draws from.
    pub fn replay_distribution(&mut self) -> Vec<f64> {
        self.refresh();
        let mut out = vec![0.0; self.cfg.n_tasks];
        let rho = self.cfg.staleness_coef;
        let total = self.staleness_total();
        let m = self.order.len() as f64;
        for &i in &self.order {
            let pc = if total > 0.0 { (self.s.draws - self.s.last_drawn[i]) as f64 / total } else { 1.0 / m };
            out[i] = (1.0 - rho) * self.p_score[i] + rho * pc;
        }
        out
    }

    /// The probability that the next draw is a replay (P_D(d = 1)).
    pub fn replay_probability(&self) -> f64 {
        let n = self.cfg.n_tasks;
        let seen = self.s.seen.iter().filter(|&&b| b).count();
        match self.cfg.replay_schedule {
            ReplaySchedule::Proportionate => seen as f64 / n as f64,
            ReplaySchedule::Fixed if seen == n => 1.0,
            ReplaySchedule::Fixed if seen == 0 => 0.0,
            ReplaySchedule::Fixed => self.cfg.replay_prob,
        }
    }

    /// Each level's score (0 for levels not yet told).
    pub fn scores(&self) -> &[f64] {
        &self.s.score
    }

    fn task(&self, goal: &[f64]) -> Option<usize> {
        task_of(goal, self.cfg.n_tasks)
    }

    fn mark_seen(&mut self, i: usize) {
        if !self.s.seen[i] {
            self.s.seen[i] = true;
            self.dirty = true;
        }
    }
}

impl GoalSelector for Plr {
    fn goal_box(&self) -> (&[f64], &[f64]) {
        (&self.low, &self.high)
    }
    fn sample(&mut self) -> GoalChoice {
        let n = self.cfg.n_tasks;
        let replay = unit(&mut self.s.rng) < self.replay_probability();
        self.s.draws += 1;
        let (task, mode) = if replay {
            (self.replay(), Mode::Interest)
        } else {
            let unseen: Vec<usize> = (0..n).filter(|&i| !self.s.seen[i]).collect();
            (unseen[index(&mut self.s.rng, unseen.len())], Mode::Initial)
        };
        self.s.last_drawn[task] = self.s.draws;
        self.mark_seen(task);
        GoalChoice { goal: vec![task as f64], mode, region: Some(task) }
    }
    fn check_told(&self, goal: &[f64], _competence: f64) -> Result<()> {
        check_task(goal, self.cfg.n_tasks)?;
        Ok(())
    }
    fn update(&mut self, point: &[f64], competence: f64) -> Option<usize> {
        let i = self.task(point)?;
        let score = match self.cfg.score {
            PlrScore::Told => competence,
            PlrScore::Progress => self.s.last_competence[i].map_or(0.0, |prev| (competence - prev).abs()),
        };
        self.s.last_competence[i] = Some(competence);
        if self.s.score[i].to_bits() != score.to_bits() {
            self.s.score[i] = score;
            self.dirty = true;
        }
        self.mark_seen(i);
        Some(i)
    }
    fn save(&self) -> Option<Vec<u8>> {
        save_state(&self.s)
    }
    fn load(&mut self, state: &[u8]) -> bool {
        let n = self.cfg.n_tasks;
        match load_state::<PlrState>(state) {
            Some(s) if s.seen.len() == n && s.score.len() == n && s.last_drawn.len() == n && s.last_competence.len() == n && s.last_drawn.iter().all(|&d| d <= s.draws) => {
                self.s = s;
                self.dirty = true;
                true
            }
            _ => false,
        }
    }
}

build_by_new!(PlrConfig => Plr, tasks);

#[cfg(test)]
mod tests {
    use super::*;

    fn plr(n: usize, f: impl FnOnce(&mut PlrConfig)) -> Plr {
        let mut c = PlrConfig { n_tasks: n, ..PlrConfig::default() };
        f(&mut c);
        Plr::new(c, 7).unwrap()
    }

    #[test]
    fn unseen_levels_first_then_replay_only() {
        let mut t = plr(6, |_| {});
        let mut first: Vec<usize> = (0..6).map(|_| t.sample().goal[0] as usize).collect::<Vec<_>>();
        // Proportionate: the first draw is always new; all 6 are seen before long.
        assert_eq!(t.replay_probability(), t.s.seen.iter().filter(|&&b| b).count() as f64 / 6.0);
        for _ in 0..200 {
            first.push(t.sample().goal[0] as usize);
        }
        assert!(t.s.seen.iter().all(|&b| b));
        assert_eq!(t.replay_probability(), 1.0);
        let mut f = plr(5, |c| {
            c.replay_schedule = ReplaySchedule::Fixed;
            c.replay_prob = 0.0;
        });
        let mut got: Vec<usize> = (0..5).map(|_| f.sample().goal[0] as usize).collect();
        got.sort();
        assert_eq!(got, vec![0, 1, 2, 3, 4], "replay_prob = 0 draws every level once first");
    }

    #[test]
    fn the_replay_distribution_is_the_papers() {
        // Told scores: 3 levels seen, scores 0.5, 0.2, 0.9; drawn at 1, 2, 3 (c = 3).
        let mut t = plr(4, |c| c.score = PlrScore::Told);
        for (i, s) in [(0, 0.5), (1, 0.2), (2, 0.9)] {
            t.s.draws += 1;
            t.s.last_drawn[i] = t.s.draws;
            t.mark_seen(i);
            t.update(&[i as f64], s);
        }
        let p = t.replay_distribution();
        // Ranks 2, 3, 1 -> h^(1/0.1); staleness 2, 1, 0 (sum 3).
        let h = [2f64.powi(-10), 3f64.powi(-10), 1.0];
        let z: f64 = h.iter().sum();
        let stale = [2.0 / 3.0, 1.0 / 3.0, 0.0];
        for i in 0..3 {
            assert!((p[i] - (0.9 * h[i] / z + 0.1 * stale[i])).abs() < 1e-15, "{p:?}");
        }
        assert_eq!(p[3], 0.0);
        // Ties share the mean rank.
        t.update(&[0.0], 0.9);
        let p = t.replay_distribution();
        let h = [1.5f64.powi(-10), 3f64.powi(-10), 1.5f64.powi(-10)];
        let z: f64 = h.iter().sum();
        assert!((p[0] - (0.9 * h[0] / z + 0.1 * stale[0])).abs() < 1e-15, "{p:?}");
    }

    #[test]
    fn progress_scores_are_the_change_of_competence() {
        let mut t = plr(3, |_| {});
        t.update(&[1.0], 0.4);
        assert_eq!(t.scores()[1], 0.0);
        t.update(&[1.0], 0.1);
        assert!((t.scores()[1] - 0.3).abs() < 1e-15);
        assert!(t.check_told(&[2.5], 0.0).unwrap_err().to_string().contains("whole number in [0, 3)"));
        let e = Plr::new(PlrConfig { n_tasks: 3, temperature: 0.0, ..PlrConfig::default() }, 0).unwrap_err().to_string();
        assert!(e.contains("'temperature' parameter of PlrSelector"), "{e}");
    }
}

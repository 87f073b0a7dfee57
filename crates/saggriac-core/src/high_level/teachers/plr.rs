//! Prioritized Level Replay (Jiang, Grefenstette & Rocktäschel, ICML 2021, Algorithms 1-2) over a
//! list of levels 0..n-1.
//!
//! Each draw first decides between a new level and a replay (P_D). A new level is drawn
//! uniformly among the levels never drawn, and joins the seen levels with score 0. A replay
//! draws a seen level from P_replay = (1 - rho) P_S + rho P_C:
//! - P_S, rank prioritisation: h(S_i) = 1 / rank(S_i), ranks by descending score (ties below),
//!   P_S(i) = h(S_i)^(1/beta) / sum_j h(S_j)^(1/beta) over the seen levels;
//! - P_C, staleness: P_C(i) = (c - C_i) / sum_j (c - C_j), c the number of draws before this one
//!   and C_i the draw at which level i was last drawn, as the authors' code counts it: the level
//!   drawn last has staleness 0, so P_C never redraws it (uniform over the seen levels while
//!   every staleness is 0).
//!
//! Readings of what the paper leaves open (docs/teachers.md):
//! - P_D: `Proportionate` replays with probability |seen| / n (so new levels first, and only
//!   replays once all are seen); `Fixed` replays with probability `replay_prob` once a level has
//!   been seen, and always once all have.
//! - Scores: the paper scores a level by the agent's value loss (mean |GAE|) on its last
//!   episode. Through ask/tell the teacher sees what `update` is told: with `score = Progress`
//!   (the default) a level's score is |competence - the level's previous competence| (0 on its
//!   first tell), its learning progress; with `score = Told` the told value is the score itself.
//! - Ties (`PlrTies`): by default as the authors' code ranks, a reversed argsort of every level's
//!   score (unseen levels at 0), read with a stable sort: tied levels take distinct ranks, the
//!   later level first. `Average` gives tied levels the mean of their ranks among the seen levels.
//! - A level joins the seen levels when it is drawn (the paper's Algorithm 2), or when it is told
//!   without having been drawn.

use serde::{Deserialize, Serialize};

pub use crate::config::teachers::{PlrConfig, PlrScore, PlrTies, ReplaySchedule};
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

    /// Recompute the seen levels' order and P_S (rank prioritisation, ties as `cfg.ties` says).
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
        self.p_score.iter_mut().for_each(|x| *x = 0.0);
        match self.cfg.ties {
            PlrTies::Order => self.rank_in_order(),
            PlrTies::Average => self.rank_on_average(inv_beta),
        }
        let total: f64 = self.order.iter().map(|&i| self.p_score[i]).sum();
        let mut acc = 0.0;
        self.cum_score.clear();
        for &i in &self.order {
            self.p_score[i] /= total;
            acc += self.p_score[i];
            self.cum_score.push(acc);
        }
        self.dirty = false;
    }

    /// `PlrTies::Order`: every level ranked by descending score, unseen ones at score 0, and
    /// among equal scores the later level first (numpy's stable argsort, reversed). A seen
    /// level's weight is its rank's; the order of the seen levels is theirs.
    fn rank_in_order(&mut self) {
        let s = &self.s;
        // -0.0 and 0.0 are one score, as numpy compares them.
        let key = |i: usize| s.score[i] + 0.0;
        self.order.sort_by(|&a, &b| key(b).total_cmp(&key(a)).then(b.cmp(&a)));
        // Unseen levels rank above every seen level of a negative score, and above a seen level
        // of score 0 when they come later in the list.
        let unseen = s.seen.iter().filter(|&&b| !b).count();
        let mut unseen_later = vec![0; s.seen.len()];
        let mut later = 0;
        for i in (0..s.seen.len()).rev() {
            unseen_later[i] = later;
            later += usize::from(!s.seen[i]);
        }
        for (pos, &i) in self.order.iter().enumerate() {
            let ahead = match key(i) {
                k if k > 0.0 => 0,
                k if k < 0.0 => unseen,
                _ => unseen_later[i],
            };
            self.p_score[i] = self.rank_weight[pos + ahead];
        }
    }

    /// `PlrTies::Average`: the seen levels ranked by descending score, tied ones at the mean of
    /// their ranks.
    fn rank_on_average(&mut self, inv_beta: f64) {
        let s = &self.s;
        self.order.sort_by(|a, b| s.score[*b].total_cmp(&s.score[*a]).then(a.cmp(b)));
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

    /// The probability of each level at the next draw: a new level (uniform among the unseen)
    /// with probability 1 - P_D(d = 1), else a replay from P_replay.
    pub fn next_distribution(&mut self) -> Vec<f64> {
        let replay = self.replay_probability();
        let mut out = if replay > 0.0 { self.replay_distribution() } else { vec![0.0; self.cfg.n_tasks] };
        let unseen = self.s.seen.iter().filter(|&&b| !b).count();
        for (p, &seen) in out.iter_mut().zip(&self.s.seen) {
            *p = replay * *p + if seen { 0.0 } else { (1.0 - replay) / unseen as f64 };
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
        let (task, mode) = if replay {
            (self.replay(), Mode::Interest)
        } else {
            let unseen: Vec<usize> = (0..n).filter(|&i| !self.s.seen[i]).collect();
            (unseen[index(&mut self.s.rng, unseen.len())], Mode::Initial)
        };
        // Counted after the draw: the staleness it read gave the level drawn last 0.
        self.s.draws += 1;
        self.s.last_drawn[task] = self.s.draws;
        self.mark_seen(task);
        GoalChoice { goal: vec![task as f64], mode, region: Some(task) }
    }
    fn task_probabilities(&self) -> Option<Vec<f64>> {
        Some(self.clone().next_distribution())
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
        // Tied with level 2, level 0 ranks after it (the later level first); with
        // `ties = Average` the two share rank 1.5.
        t.update(&[0.0], 0.9);
        let mut avg = t.clone();
        avg.cfg.ties = PlrTies::Average;
        avg.dirty = true;
        for (t, h) in [(&mut t, [2f64.powi(-10), 3f64.powi(-10), 1.0]), (&mut avg, [1.5f64.powi(-10), 3f64.powi(-10), 1.5f64.powi(-10)])] {
            let p = t.replay_distribution();
            let z: f64 = h.iter().sum();
            for i in 0..3 {
                assert!((p[i] - (0.9 * h[i] / z + 0.1 * stale[i])).abs() < 1e-15, "{:?}: {p:?}", t.cfg.ties);
            }
        }
    }

    /// Seen levels told `scores` (None: unseen), nothing drawn: P_S by level.
    fn p_score(ties: PlrTies, scores: &[Option<f64>]) -> Vec<f64> {
        let mut t = plr(scores.len(), |c| {
            c.score = PlrScore::Told;
            c.staleness_coef = 0.0;
            c.ties = ties;
        });
        for (i, s) in scores.iter().enumerate() {
            if let Some(s) = s {
                t.update(&[i as f64], *s);
            }
        }
        t.replay_distribution()
    }

    fn normalised(h: &[f64]) -> Vec<f64> {
        let z: f64 = h.iter().sum();
        h.iter().map(|x| x / z).collect()
    }

    #[test]
    fn ties_take_ranks_in_the_order_of_the_authors_code() {
        let r = |k: i32| (k as f64).powi(-10);
        // Three levels tied at 0.5 under one at 1: ranks 4, 3, 2, 1 (a reversed stable argsort).
        let p = p_score(PlrTies::Order, &[Some(0.5), Some(0.5), Some(0.5), Some(1.0)]);
        let want = normalised(&[r(4), r(3), r(2), r(1)]);
        assert!(p.iter().zip(&want).all(|(a, b)| (a - b).abs() < 1e-15), "{p:?}");
        assert!(p[2] > 0.98 * (p[0] + p[1] + p[2]), "one level takes nearly all of its tied group's mass: {p:?}");
        let p = p_score(PlrTies::Average, &[Some(0.5), Some(0.5), Some(0.5), Some(1.0)]);
        assert!(p[0] == p[1] && p[1] == p[2] && (p[3] - 1.0 / (1.0 + 3.0 * 3f64.powi(-10))).abs() < 1e-15, "{p:?}");
        // Unseen levels are ranked at score 0: above a seen 0 listed before them, below a seen 0
        // listed after them, above every negative score: level 4 (unseen) ranks 2, level 1 rank
        // 3, level 0 rank 4, level 3 (score -1) rank 5 ...
        let p = p_score(PlrTies::Order, &[Some(0.0), Some(0.0), Some(1.0), Some(-1.0), None]);
        let want = normalised(&[r(4), r(3), r(1), r(5)]);
        assert!(p[..4].iter().zip(&want).all(|(a, b)| (a - b).abs() < 1e-15) && p[4] == 0.0, "{p:?}");
        // ... and -0.0 is the score 0: levels 3 (unseen), 2, 1 (unseen), 0 rank 1 to 4.
        let p = p_score(PlrTies::Order, &[Some(-0.0), None, Some(0.0), None]);
        let want = normalised(&[r(4), r(2)]);
        assert!((p[0] - want[0]).abs() < 1e-15 && (p[2] - want[1]).abs() < 1e-15, "{p:?}");
        // Among the seen levels only, ties sharing their mean rank.
        let p = p_score(PlrTies::Average, &[Some(0.0), Some(0.0), Some(1.0), Some(-1.0), None]);
        let want = normalised(&[2.5f64.powi(-10), 2.5f64.powi(-10), 1.0, r(4)]);
        assert!(p[..4].iter().zip(&want).all(|(a, b)| (a - b).abs() < 1e-15), "{p:?}");
    }

    #[test]
    fn staleness_never_redraws_the_level_drawn_last() {
        // Every level once, then replays by staleness alone (rho = 1): the level drawn last has
        // staleness 0.
        for n in [2, 3, 10] {
            let mut t = plr(n, |c| {
                c.staleness_coef = 1.0;
                c.replay_schedule = ReplaySchedule::Fixed;
                c.replay_prob = 0.0;
            });
            let mut last = usize::MAX;
            for k in 0..3000 {
                let i = t.sample().goal[0] as usize;
                assert!(i != last, "{n} levels: level {i} drawn twice in a row at draw {k}");
                t.update(&[i as f64], 0.5);
                if k >= 1 {
                    // Two levels seen: what a replay would draw leaves the last one out.
                    let p = t.replay_distribution();
                    assert_eq!(p[i], 0.0, "{p:?}");
                }
                last = i;
            }
        }
    }

    #[test]
    fn the_next_draws_distribution_is_the_mixture() {
        let mut t = plr(5, |c| {
            c.score = PlrScore::Told;
            c.staleness_coef = 0.3;
        });
        assert_eq!(t.next_distribution(), vec![0.2; 5]);
        for k in 0..40 {
            let p = t.next_distribution();
            assert!((p.iter().sum::<f64>() - 1.0).abs() < 1e-12 && p.iter().all(|&x| x >= 0.0), "{p:?}");
            let seen = t.s.seen.iter().filter(|&&b| b).count();
            let replay = t.replay_distribution();
            for i in 0..5 {
                let new = if t.s.seen[i] { 0.0 } else { 1.0 / (5 - seen) as f64 };
                let want = seen as f64 / 5.0 * replay[i] + (1.0 - seen as f64 / 5.0) * new;
                assert!((p[i] - want).abs() < 1e-15, "{p:?}");
            }
            let i = t.sample().goal[0];
            t.update(&[i], (k % 3) as f64);
        }
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

//! Automatic Domain Randomization (OpenAI: Akkaya et al., "Solving Rubik's Cube with a Robot
//! Hand", 2019, Algorithm 1).
//!
//! Each dimension i of the box has a current range [phi_L_i, phi_H_i], starting at an initial
//! region (the paper's single value by default). Goals are uniform in the current ranges; with
//! probability `boundary_prob` (the paper's p_b) one dimension i is drawn uniformly and set to
//! its low or its high bound (1/2 each): a boundary sample. The competence told for a boundary
//! sample goes to that bound's buffer; once the buffer holds `buffer_size` values (m) its mean
//! is compared with the thresholds and the buffer is cleared: a mean >= `t_high` moves the bound
//! outwards by `step` (within the box), a mean <= `t_low` moves it inwards (never past the other
//! bound).
//!
//! Readings of what the paper leaves open, and where we depart from TeachMyAgent's ADR:
//! - A told goal counts for the bound it was boundary-sampled at, and for nothing else (the
//!   paper's D_i). The teacher remembers its pending boundary samples by their bits (as
//!   float32, so that a goal told back in a float32 box still finds its sample);
//!   TeachMyAgent instead credits every bound a coordinate equals, so from a single initial
//!   value each goal fills all 2d buffers.
//! - A bound already at the box's edge can still be boundary-sampled (the paper draws i and the
//!   side uniformly); TeachMyAgent skips capped bounds.
//! - A pending boundary sample whose bound has moved since it was asked is not credited: its
//!   performance was measured at a value that is no longer the bound.
//! - `step` is a share of each dimension's width, so one value fits every box.

use std::collections::{BTreeMap, VecDeque};

use serde::{Deserialize, Serialize};

use crate::config::high_level::check_bounds;
pub use crate::config::teachers::AdrConfig;
use crate::config::teachers::PerDimension;
use crate::error::Result;
use crate::config::teachers::TeacherParams;
use crate::high_level::goal_selection::{load_state, save_state, GoalChoice, GoalSelector, LeafRow, Mode};
use crate::rng::{index, rng_from_seed, uniform, unit, CoreRng};

/// Boundary samples asked and not yet told, beyond which the oldest are forgotten (a learner
/// that never tells would otherwise grow the teacher without bound).
const MAX_PENDING: usize = 1_000_000;

/// The teacher's state: its generator, the current ranges, both buffers of every dimension and
/// the boundary samples not yet told (goal bits -> (ask number, dimension, high side), in asking
/// order). A deque encodes as a Vec did, so saved teachers read the same.
#[derive(Debug, Clone, Serialize, Deserialize)]
struct AdrState {
    rng: CoreRng,
    phi_low: Vec<f64>,
    phi_high: Vec<f64>,
    buf_low: Vec<Vec<f64>>,
    buf_high: Vec<Vec<f64>>,
    pending: BTreeMap<Vec<u64>, VecDeque<(u64, u32, bool)>>,
    n_pending: usize,
    asked: u64,
    /// The pending samples by ask number (-> their goal's bits): the oldest is found at once
    /// instead of by a scan of every pending entry. Not saved; rebuilt from `pending` on load.
    #[serde(skip)]
    by_ask: BTreeMap<u64, Vec<u64>>,
}

#[derive(Debug, Clone)]
pub struct Adr {
    cfg: AdrConfig,
    low: Vec<f64>,
    high: Vec<f64>,
    /// Delta of each dimension, as a share of its width (`step`, or the values given per
    /// dimension).
    step: Vec<f64>,
    s: AdrState,
}

impl Adr {
    pub fn new(low: &[f64], high: &[f64], cfg: AdrConfig, seed: u64) -> Result<Self> {
        Self::with_dims(low, high, cfg, &PerDimension::default(), seed)
    }

    /// ADR with `initial`, `initial_width` and `step` given per dimension where `dims` has them
    /// (checked by `PerDimension::check`).
    pub fn with_dims(low: &[f64], high: &[f64], cfg: AdrConfig, dims: &PerDimension, seed: u64) -> Result<Self> {
        check_bounds("AdrSelector", low, high)?;
        cfg.validate()?;
        let d = low.len();
        let (initial, width) = (dims.vector("initial", cfg.initial, d), dims.vector("initial_width", cfg.initial_width, d));
        let (mut pl, mut ph) = (vec![0.0; d], vec![0.0; d]);
        for i in 0..d {
            let w = high[i] - low[i];
            let c = low[i] + initial[i] * w;
            let half = 0.5 * width[i] * w;
            pl[i] = (c - half).max(low[i]);
            ph[i] = (c + half).min(high[i]);
        }
        let s = AdrState { rng: rng_from_seed(seed), phi_low: pl, phi_high: ph, buf_low: vec![Vec::new(); d], buf_high: vec![Vec::new(); d], pending: BTreeMap::new(), n_pending: 0, asked: 0, by_ask: BTreeMap::new() };
        Ok(Adr { cfg, low: low.to_vec(), high: high.to_vec(), step: dims.vector("step", cfg.step, d), s })
    }

    /// The current ranges [phi_L, phi_H] of every dimension.
    pub fn bounds(&self) -> (&[f64], &[f64]) {
        (&self.s.phi_low, &self.s.phi_high)
    }

    fn forget_oldest(&mut self) {
        if self.s.n_pending <= MAX_PENDING {
            return;
        }
        // The oldest ask among the pending ones goes: the first of its goal's queue, since each
        // queue is in asking order and loses only its first entry.
        if let Some((a, k)) = self.s.by_ask.pop_first() {
            let v = self.s.pending.get_mut(&k).expect("present");
            debug_assert_eq!(v.front().map(|e| e.0), Some(a));
            v.pop_front();
            if v.is_empty() {
                self.s.pending.remove(&k);
            }
            self.s.n_pending -= 1;
        }
    }

    /// Put `p` in the buffer of dimension `i`'s low or high bound; move the bound once full.
    fn record(&mut self, i: usize, high_side: bool, p: f64) {
        let m = self.cfg.buffer_size;
        let buf = if high_side { &mut self.s.buf_high[i] } else { &mut self.s.buf_low[i] };
        buf.push(p);
        if buf.len() < m {
            return;
        }
        let mean = buf.iter().sum::<f64>() / buf.len() as f64;
        buf.clear();
        let delta = self.step[i] * (self.high[i] - self.low[i]);
        let (pl, ph) = (&mut self.s.phi_low[i], &mut self.s.phi_high[i]);
        if mean >= self.cfg.t_high {
            if high_side {
                *ph = (*ph + delta).min(self.high[i]);
            } else {
                *pl = (*pl - delta).max(self.low[i]);
            }
        } else if mean <= self.cfg.t_low {
            if high_side {
                *ph = (*ph - delta).max(*pl);
            } else {
                *pl = (*pl + delta).min(*ph);
            }
        }
    }
}

/// A goal's key among the pending boundary samples: its coordinates rounded to float32, so that
/// a goal told back as float32 (Syllabus's and Gymnasium's boxes) finds the sample it came from.
fn bits(goal: &[f64]) -> Vec<u64> {
    goal.iter().map(|v| (*v as f32).to_bits() as u64).collect()
}

impl GoalSelector for Adr {
    fn goal_box(&self) -> (&[f64], &[f64]) {
        (&self.low, &self.high)
    }
    fn sample(&mut self) -> GoalChoice {
        let d = self.low.len();
        let s = &mut self.s;
        let mut goal: Vec<f64> = (0..d).map(|i| uniform(&mut s.rng, s.phi_low[i], s.phi_high[i])).collect();
        if unit(&mut s.rng) >= self.cfg.boundary_prob {
            return GoalChoice { goal, mode: Mode::Random, region: None };
        }
        let i = index(&mut s.rng, d);
        let high_side = unit(&mut s.rng) >= 0.5;
        goal[i] = if high_side { s.phi_high[i] } else { s.phi_low[i] };
        s.asked += 1;
        let ask = s.asked;
        let key = bits(&goal);
        s.pending.entry(key.clone()).or_default().push_back((ask, i as u32, high_side));
        s.by_ask.insert(ask, key);
        s.n_pending += 1;
        self.forget_oldest();
        GoalChoice { goal, mode: Mode::Interest, region: Some(2 * i + high_side as usize) }
    }
    fn update(&mut self, point: &[f64], competence: f64) -> Option<usize> {
        let key = bits(point);
        let (i, high_side) = {
            let v = self.s.pending.get_mut(&key)?;
            let (ask, i, h) = v.pop_front().expect("a pending queue is never empty");
            if v.is_empty() {
                self.s.pending.remove(&key);
            }
            self.s.by_ask.remove(&ask);
            self.s.n_pending -= 1;
            (i as usize, h)
        };
        // Measured at a value that is no longer the bound: not this bound's performance.
        let bound = if high_side { self.s.phi_high[i] } else { self.s.phi_low[i] };
        if (point[i] as f32).to_bits() != (bound as f32).to_bits() {
            return None;
        }
        self.record(i, high_side, competence);
        Some(2 * i + high_side as usize)
    }
    /// The current ranges as one region, with the boundary samples held in the buffers.
    fn leaf_table(&self) -> Vec<LeafRow> {
        let held = self.s.buf_low.iter().chain(&self.s.buf_high).map(Vec::len).sum();
        vec![LeafRow { low: self.s.phi_low.clone(), high: self.s.phi_high.clone(), interest: 0.0, n_measurements: held }]
    }
    fn save(&self) -> Option<Vec<u8>> {
        save_state(&self.s)
    }
    fn load(&mut self, state: &[u8]) -> bool {
        let d = self.low.len();
        match load_state::<AdrState>(state) {
            Some(mut s) if s.phi_low.len() == d && s.phi_high.len() == d && s.buf_low.len() == d && s.buf_high.len() == d => {
                s.n_pending = s.pending.values().map(VecDeque::len).sum();
                // Each queue in asking order, every ask once, a dimension of the box: what `sample`
                // writes.
                for (k, v) in &s.pending {
                    if v.is_empty() || !v.iter().zip(v.iter().skip(1)).all(|(a, b)| a.0 < b.0) || v.iter().any(|e| e.1 as usize >= d) {
                        return false;
                    }
                    for e in v {
                        if s.by_ask.insert(e.0, k.clone()).is_some() {
                            return false;
                        }
                    }
                }
                self.s = s;
                true
            }
            _ => false,
        }
    }
}

build_by_new!(AdrConfig => Adr, box, per_dimension);

#[cfg(test)]
mod tests {
    use super::*;

    fn cfg() -> AdrConfig {
        AdrConfig { buffer_size: 3, step: 0.1, ..AdrConfig::default() }
    }

    /// Tell every boundary sample `perf(goal)`, and nothing for the others.
    fn run(t: &mut Adr, n: usize, perf: impl Fn(&[f64]) -> f64) {
        for _ in 0..n {
            let g = t.sample();
            t.update(&g.goal, perf(&g.goal));
        }
    }

    #[test]
    fn starts_at_the_initial_value_and_grows_where_performance_is_high() {
        let mut t = Adr::new(&[0.0, 0.0], &[1.0, 2.0], cfg(), 3).unwrap();
        assert_eq!(t.bounds(), (&[0.5, 1.0][..], &[0.5, 1.0][..]));
        // Competence 1 everywhere: every bound grows to the box's edge.
        run(&mut t, 2000, |_| 1.0);
        assert_eq!(t.bounds(), (&[0.0, 0.0][..], &[1.0, 2.0][..]));
        for _ in 0..200 {
            let g = t.sample().goal;
            assert!(g[0] >= 0.0 && g[0] <= 1.0 && g[1] >= 0.0 && g[1] <= 2.0);
        }
    }

    #[test]
    fn grows_above_t_high_shrinks_below_t_low_and_never_crosses() {
        // Performance high below x0 = 0.7, low above: the high bound of dimension 0 settles near
        // 0.7 and the low bound reaches 0; dimension 1 grows everywhere.
        let mut t = Adr::new(&[0.0, 0.0], &[1.0, 1.0], cfg(), 5).unwrap();
        run(&mut t, 20_000, |g| if g[0] <= 0.7 + 1e-9 { 1.0 } else { 0.0 });
        let (l, h) = t.bounds();
        assert_eq!(l[0], 0.0);
        assert!((0.6..=0.8 + 1e-9).contains(&h[0]), "{h:?}");
        assert_eq!((l[1], h[1]), (0.0, 1.0));
        // Competence 0 everywhere: bounds shrink but never cross.
        run(&mut t, 20_000, |_| 0.0);
        let (l, h) = t.bounds();
        assert!(l[0] <= h[0] && l[1] <= h[1], "{l:?} {h:?}");
        assert!(h[0] - l[0] <= 0.1 + 1e-9 && h[1] - l[1] <= 0.1 + 1e-9, "{l:?} {h:?}");
    }

    #[test]
    fn only_boundary_samples_fill_buffers_and_in_between_keeps_bounds() {
        let mut t = Adr::new(&[0.0], &[1.0], AdrConfig { initial: 0.0, initial_width: 0.5, ..cfg() }, 1).unwrap();
        assert_eq!(t.bounds(), (&[0.0][..], &[0.25][..]));
        // A goal never asked is not credited; a mean strictly between the thresholds moves nothing.
        assert_eq!(t.update(&[0.1], 1.0), None);
        run(&mut t, 3000, |_| 0.5);
        assert_eq!(t.bounds(), (&[0.0][..], &[0.25][..]));
    }

    #[test]
    fn past_max_pending_the_oldest_asks_are_forgotten_and_a_reload_keeps_the_order() {
        // Every goal a boundary sample, none told: the first asks are forgotten, in order.
        let c = AdrConfig { boundary_prob: 1.0, initial_width: 0.5, ..cfg() };
        let mut t = Adr::new(&[0.0, 0.0], &[1.0, 1.0], c, 7).unwrap();
        let first: Vec<Vec<f64>> = (0..MAX_PENDING + 5).map(|_| t.sample().goal).collect();
        assert_eq!((t.s.n_pending, t.s.by_ask.len()), (MAX_PENDING, MAX_PENDING));
        assert_eq!(t.s.by_ask.keys().next(), Some(&6));
        let mut u = Adr::new(&[0.0, 0.0], &[1.0, 1.0], c, 0).unwrap();
        assert!(u.load(&t.save().unwrap()));
        assert_eq!(u.s.by_ask, t.s.by_ask);
        for _ in 0..3 {
            assert_eq!(t.sample().goal, u.sample().goal);
        }
        assert_eq!(u.s.by_ask.keys().next(), Some(&9));
        // A forgotten goal is not credited; a pending one is, and leaves the ask index.
        assert_eq!(u.update(&first[0], 1.0), None);
        assert!(u.update(&first[MAX_PENDING + 4], 1.0).is_some());
        assert_eq!((u.s.n_pending, u.s.by_ask.len()), (MAX_PENDING - 1, MAX_PENDING - 1));
    }

    #[test]
    fn a_start_and_a_step_per_dimension_are_each_dimension_own() {
        // A start thin in x (a point at 0.1) and wide in y ([0.25, 0.75] of [0, 2]); x moves by
        // 2 % of its width, y by 20 %.
        let dims = PerDimension(vec![("initial".into(), vec![0.1, 0.5]), ("initial_width".into(), vec![0.0, 0.5]), ("step".into(), vec![0.02, 0.2])]);
        let mut t = Adr::with_dims(&[0.0, 0.0], &[1.0, 2.0], cfg(), &dims, 3).unwrap();
        assert_eq!(t.bounds(), (&[0.1, 0.5][..], &[0.1, 1.5][..]));
        run(&mut t, 60, |_| 1.0);
        let (l, h) = t.bounds();
        // Every move of x is 0.02, of y 0.4 (within the box).
        for (v, from, by) in [(l[0], 0.1, 0.02), (h[0], 0.1, 0.02), (l[1], 0.5, 0.4), (h[1], 1.5, 0.4)] {
            let k = ((v - from) / by).round();
            assert!(((v - from) - k * by).abs() < 1e-9 || v == 0.0 || v == 2.0, "{v} {from} {by}");
        }
        assert!(h[0] - l[0] > 0.0 && h[0] - l[0] < 0.2 && h[1] - l[1] > 1.0, "{l:?} {h:?}");
        // One value per dimension gives the same teacher as the single number.
        let same = PerDimension(vec![("step".into(), vec![0.1, 0.1]), ("initial".into(), vec![0.5, 0.5])]);
        let (mut a, mut b) = (Adr::new(&[0.0, 0.0], &[1.0, 2.0], cfg(), 9).unwrap(), Adr::with_dims(&[0.0, 0.0], &[1.0, 2.0], cfg(), &same, 9).unwrap());
        run(&mut a, 500, |g| if g[0] < 0.7 { 1.0 } else { 0.0 });
        run(&mut b, 500, |g| if g[0] < 0.7 { 1.0 } else { 0.0 });
        assert_eq!(a.bounds(), b.bounds());
    }

    #[test]
    fn bad_parameters_are_named() {
        let e = Adr::new(&[0.0], &[1.0], AdrConfig { t_low: 0.9, t_high: 0.1, ..cfg() }, 0).unwrap_err().to_string();
        assert!(e.contains("'t_low' parameter of AdrSelector"), "{e}");
        let e = Adr::new(&[0.0], &[1.0], AdrConfig { buffer_size: 0, ..cfg() }, 0).unwrap_err().to_string();
        assert!(e.contains("'buffer_size'"), "{e}");
        let e = Adr::new(&[0.0], &[1.0], AdrConfig { step: 0.0, ..cfg() }, 0).unwrap_err().to_string();
        assert!(e.contains("'step'"), "{e}");
    }
}

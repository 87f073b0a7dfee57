//! Goal self-generation (paper II.D.3): which goal to try next. SAGG-RIAC picks goals by
//! competence progress over the region tree; SAGG-Random picks them uniformly. Both are usable
//! on their own, ask/tell style: `sample()` a goal, `update(goal, competence)`.

use crate::config::high_level::check_bounds;
pub use crate::config::high_level::{Mode3Config, Mode3Reading, ModeProbabilities};
use crate::error::Result;
use crate::high_level::region_tree::{RegionTree, RegionTreeConfig};
use crate::table::{bools, floats, ints, slices, Table};
use crate::rng::{index, normal, pick_weighted, rng_from_seed, uniform, unit, CoreRng};

/// How a goal was chosen.
#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
#[repr(u8)]
pub enum Mode {
    /// Uniform in the space before the first split.
    Initial = 0,
    /// mode(1): a region drawn with probability proportional to interest - min interest (eq. 3).
    Interest = 1,
    /// mode(2): uniform in the whole space.
    Global = 2,
    /// mode(3): the region of lowest mean competence (or, by `Mode3Reading::InterestWorst`, near
    /// the worst goal of a region drawn by interest).
    LowestCompetence = 3,
    /// A selector without a high level (SAGG-Random).
    Random = 4,
    /// A goal from a user's selector.
    External = 5,
}

#[derive(Debug, Clone, PartialEq)]
pub struct GoalChoice {
    pub goal: Vec<f64>,
    pub mode: Mode,
    /// The leaf the goal was drawn in (modes 1 and 3).
    pub region: Option<usize>,
}

/// One leaf of `GoalSelector::leaf_table`.
#[derive(Debug, Clone, PartialEq)]
pub struct LeafRow {
    pub low: Vec<f64>,
    pub high: Vec<f64>,
    pub interest: f64,
    pub n_measurements: usize,
}

/// Leaves as a table (the same column names as a region tree's, each row a leaf).
pub fn leaves_table(leaves: &[LeafRow], dim: usize) -> Table {
    vec![
        ("low", slices(leaves, dim, |r| &r.low)),
        ("high", slices(leaves, dim, |r| &r.high)),
        ("interest", floats(leaves, |r| r.interest)),
        ("n_measurements", ints(leaves, |r| r.n_measurements as i64)),
        ("is_leaf", bools(leaves, |_| true)),
    ]
}

/// A goal selector, usable inside the run loop or on its own.
pub trait GoalSelector: Send + Sync {
    /// The box goals are drawn in: (low, high).
    fn goal_box(&self) -> (&[f64], &[f64]);
    fn low(&self) -> &[f64] {
        self.goal_box().0
    }
    fn high(&self) -> &[f64] {
        self.goal_box().1
    }
    fn dim(&self) -> usize {
        self.low().len()
    }
    fn sample(&mut self) -> GoalChoice;
    /// Report the competence obtained for a goal (or subgoal) at `point`; returns the region
    /// that recorded it, if the selector has regions.
    fn update(&mut self, point: &[f64], competence: f64) -> Option<usize>;
    /// Choose one of `candidates` (points of the selector's space, at least one) rather than
    /// draw a point anywhere: how R-IAC picks an action in the current context. None for a
    /// selector without regions to choose by.
    fn choose(&mut self, _candidates: &[Vec<f64>]) -> Option<GoalChoice> {
        None
    }
    fn tree(&self) -> Option<&RegionTree> {
        None
    }
    /// The leaves of a selector with regions but no `RegionTree` (RIAC): bounds, interest and
    /// measurements held.
    fn leaf_table(&self) -> Vec<LeafRow> {
        Vec::new()
    }
    /// A task-list teacher's probability of each task at its next draw, where it says (PLR);
    /// None otherwise.
    fn task_probabilities(&self) -> Option<Vec<f64>> {
        None
    }
    /// The selector's state for a checkpoint or a saved teacher, in the selector's own encoding
    /// of its own state type (None: this selector cannot be saved). `save_state` encodes one.
    fn save(&self) -> Option<Vec<u8>> {
        None
    }
    /// Restore a state saved by `save` on a selector built with the same parameters; false if
    /// it is not such a state.
    fn load(&mut self, _state: &[u8]) -> bool {
        false
    }
    /// Checks of a told goal and competence beyond the box and finiteness (a task index, a
    /// success rate), made before anything is recorded.
    fn check_told(&self, _goal: &[f64], _competence: f64) -> Result<()> {
        Ok(())
    }
    /// True once a user's selector has failed; the run loop stops.
    fn failed(&self) -> bool {
        false
    }
}

fn uniform_in(rng: &mut CoreRng, low: &[f64], high: &[f64]) -> Vec<f64> {
    low.iter().zip(high).map(|(l, h)| uniform(rng, *l, *h)).collect()
}

/// A selector's state in its own encoding (postcard: its fields in order).
pub fn save_state<T: serde::Serialize>(state: &T) -> Option<Vec<u8>> {
    postcard::to_stdvec(state).ok()
}

/// The state `save_state` encoded, if `bytes` are exactly one.
pub fn load_state<T: serde::de::DeserializeOwned>(bytes: &[u8]) -> Option<T> {
    match postcard::take_from_bytes::<T>(bytes) {
        Ok((t, [])) => Some(t),
        _ => None,
    }
}

/// SAGG-RIAC's state: its generator and every measurement in order (replaying them rebuilds the
/// same tree, splits and interests included).
#[derive(Debug, Clone, serde::Serialize, serde::Deserialize)]
struct SaggRiacState {
    rng: CoreRng,
    points: Vec<f64>,
    values: Vec<f64>,
}

/// Uniform goals' state: the generator.
#[derive(Debug, Clone, serde::Serialize, serde::Deserialize)]
struct RandomState {
    rng: CoreRng,
}

/// SAGG-RIAC's high level.
#[derive(Debug, Clone)]
pub struct SaggRiac {
    tree: RegionTree,
    modes: ModeProbabilities,
    mode3: Mode3Config,
    rng: CoreRng,
}

impl SaggRiac {
    /// With mode 3 as the paper reads it (`with_mode3` sets another reading).
    pub fn new(low: &[f64], high: &[f64], tree: RegionTreeConfig, modes: ModeProbabilities, seed: u64) -> Result<Self> {
        modes.validate()?;
        Ok(SaggRiac { tree: RegionTree::new(low, high, tree)?, modes, mode3: Mode3Config::default(), rng: rng_from_seed(seed) })
    }

    pub fn with_mode3(mut self, mode3: Mode3Config) -> Result<Self> {
        mode3.validate()?;
        self.mode3 = mode3;
        Ok(self)
    }

    /// The measurement of lowest competence `leaf` holds, the newest of equals (an older equal
    /// failure says less about the region now); None for an empty leaf.
    fn worst_in(&self, leaf: usize) -> Option<u32> {
        let entries = &self.tree.region(leaf).entries;
        entries.iter().rev().copied().fold(None, |best: Option<u32>, e| match best {
            Some(b) if self.tree.value(b as usize) <= self.tree.value(e as usize) => Some(b),
            _ => Some(e),
        })
    }

    /// Mode 3 as `Mode3Reading::InterestWorst` reads it: a leaf by interest, then a Gaussian about
    /// its worst goal (sd sigma times the box's width in each dimension) clipped to the leaf;
    /// uniform in the leaf if it holds nothing.
    fn near_worst(&mut self) -> (Vec<f64>, usize) {
        let leaf = self.interest_leaf();
        let Some(w) = self.worst_in(leaf) else {
            let r = self.tree.region(leaf);
            return (uniform_in(&mut self.rng, &r.low, &r.high), leaf);
        };
        let centre = self.tree.point(w as usize).to_vec();
        let sigma = self.mode3.sigma;
        let (lo, hi) = (self.tree.low().to_vec(), self.tree.high().to_vec());
        let r = self.tree.region(leaf);
        let (rlo, rhi) = (r.low.clone(), r.high.clone());
        let goal = (0..centre.len()).map(|j| (centre[j] + sigma * (hi[j] - lo[j]) * normal(&mut self.rng)).clamp(rlo[j], rhi[j])).collect();
        (goal, leaf)
    }

    /// Draw a leaf with probability |interest - min interest| / sum (eq. 3); uniform when all
    /// interests are equal.
    fn interest_leaf(&mut self) -> usize {
        let total = self.tree.interest_weight_total();
        let leaves = self.tree.leaves();
        let interest = self.tree.leaf_interests();
        let min = self.tree.min_leaf_interest();
        if !(total > 0.0 && total.is_finite()) {
            return leaves[index(&mut self.rng, leaves.len())];
        }
        let mut u = unit(&mut self.rng) * total;
        for (&l, i) in leaves.iter().zip(interest) {
            let w = (i - min).abs();
            if u < w {
                return l;
            }
            u -= w;
        }
        // Rounding left u just above the last weight: take the last leaf with weight.
        leaves.iter().zip(interest).rev().find(|(_, &i)| i > min).map(|(&l, _)| l).unwrap_or(leaves[leaves.len() - 1])
    }

    /// The leaf of lowest mean competence among leaves holding measurements.
    fn lowest_leaf(&self) -> usize {
        let mut best = (f64::INFINITY, self.tree.leaves()[0]);
        for (&l, &m) in self.tree.leaves().iter().zip(self.tree.leaf_means()) {
            // NaN marks an empty leaf, which `m < best` skips.
            if m < best.0 {
                best = (m, l);
            }
        }
        best.1
    }
}

impl GoalSelector for SaggRiac {
    fn goal_box(&self) -> (&[f64], &[f64]) {
        (self.tree.low(), self.tree.high())
    }
    fn sample(&mut self) -> GoalChoice {
        if self.tree.leaves().len() < 2 {
            let goal = uniform_in(&mut self.rng, self.tree.low(), self.tree.high());
            return GoalChoice { goal, mode: Mode::Initial, region: None };
        }
        let u = unit(&mut self.rng);
        let mode3 = self.modes.p_interest + self.modes.p_global <= u;
        if mode3 && self.mode3.reading == Mode3Reading::InterestWorst {
            let (goal, leaf) = self.near_worst();
            return GoalChoice { goal, mode: Mode::LowestCompetence, region: Some(leaf) };
        }
        let (mode, leaf) = if u < self.modes.p_interest {
            (Mode::Interest, Some(self.interest_leaf()))
        } else if u < self.modes.p_interest + self.modes.p_global {
            (Mode::Global, None)
        } else {
            (Mode::LowestCompetence, Some(self.lowest_leaf()))
        };
        let goal = match leaf {
            Some(l) => {
                let r = self.tree.region(l);
                uniform_in(&mut self.rng, &r.low, &r.high)
            }
            None => uniform_in(&mut self.rng, self.tree.low(), self.tree.high()),
        };
        GoalChoice { goal, mode, region: leaf }
    }
    fn update(&mut self, point: &[f64], competence: f64) -> Option<usize> {
        Some(self.tree.add(point, competence).0)
    }
    /// R-IAC in the current context (docs/parameters.md, "ACTUATOR-RIAC"): each candidate is
    /// located in its leaf, and the three modes choose among the candidates through their
    /// leaves: mode 1 with probability |interest - min interest| (eq. 3, the minimum over all
    /// leaves), mode 2 uniformly, mode 3 the candidate in the leaf of lowest mean competence (by
    /// `Mode3Reading::InterestWorst`: a candidate drawn as in mode 1, then the candidate of its
    /// leaf nearest the leaf's worst goal, distances in shares of the box's width).
    /// Uniform before the first split, and in mode 1 when no candidate's leaf has weight.
    fn choose(&mut self, candidates: &[Vec<f64>]) -> Option<GoalChoice> {
        let pick = |c: usize, mode: Mode, leaf: Option<usize>| Some(GoalChoice { goal: candidates[c].clone(), mode, region: leaf });
        if candidates.is_empty() {
            return None;
        }
        if self.tree.leaves().len() < 2 {
            return pick(index(&mut self.rng, candidates.len()), Mode::Initial, None);
        }
        let leaves: Vec<usize> = candidates.iter().map(|c| self.tree.leaf_of(c)).collect();
        let u = unit(&mut self.rng);
        // A candidate drawn by its leaf's interest (mode 1's draw).
        let by_interest = |s: &mut Self| {
            let min = s.tree.min_leaf_interest();
            let w: Vec<f64> = leaves.iter().map(|&l| (s.tree.region(l).interest - min).abs()).collect();
            let total: f64 = w.iter().sum();
            if !(total > 0.0 && total.is_finite()) {
                return index(&mut s.rng, candidates.len());
            }
            pick_weighted(&w, unit(&mut s.rng) * total)
        };
        if u < self.modes.p_interest {
            let chosen = by_interest(self);
            pick(chosen, Mode::Interest, Some(leaves[chosen]))
        } else if self.modes.p_interest + self.modes.p_global <= u && self.mode3.reading == Mode3Reading::InterestWorst {
            let drawn = by_interest(self);
            let leaf = leaves[drawn];
            let Some(w) = self.worst_in(leaf) else { return pick(drawn, Mode::LowestCompetence, Some(leaf)) };
            let (worst, lo, hi) = (self.tree.point(w as usize), self.tree.low(), self.tree.high());
            let dist = |c: usize| candidates[c].iter().enumerate().map(|(j, x)| ((x - worst[j]) / (hi[j] - lo[j])).powi(2)).sum::<f64>();
            let c = (0..candidates.len()).filter(|&c| leaves[c] == leaf).min_by(|&a, &b| dist(a).total_cmp(&dist(b))).unwrap_or(drawn);
            pick(c, Mode::LowestCompetence, Some(leaf))
        } else if u < self.modes.p_interest + self.modes.p_global {
            let c = index(&mut self.rng, candidates.len());
            pick(c, Mode::Global, Some(leaves[c]))
        } else {
            // Empty leaves (no mean) are skipped; if all are empty, the first candidate.
            let c = (0..candidates.len()).filter_map(|c| self.tree.region(leaves[c]).mean().map(|m| (m, c))).min_by(|a, b| a.0.total_cmp(&b.0)).map_or(0, |(_, c)| c);
            pick(c, Mode::LowestCompetence, Some(leaves[c]))
        }
    }
    fn tree(&self) -> Option<&RegionTree> {
        Some(&self.tree)
    }
    fn save(&self) -> Option<Vec<u8>> {
        let n = self.tree.n_measurements();
        let points = (0..n).flat_map(|i| self.tree.point(i).to_vec()).collect();
        let values = (0..n).map(|i| self.tree.value(i)).collect();
        save_state(&SaggRiacState { rng: self.rng.clone(), points, values })
    }
    fn load(&mut self, state: &[u8]) -> bool {
        let Some(SaggRiacState { rng, points, values }) = load_state(state) else { return false };
        let Ok(mut tree) = RegionTree::new(self.tree.low(), self.tree.high(), *self.tree.config()) else { return false };
        let d = tree.dim();
        for (p, v) in points.chunks_exact(d).zip(&values) {
            tree.add(p, *v);
        }
        self.tree = tree;
        self.rng = rng;
        true
    }
}

/// Goals uniform in the box, no high level (SAGG-Random).
#[derive(Debug, Clone)]
pub struct RandomGoals {
    low: Vec<f64>,
    high: Vec<f64>,
    rng: CoreRng,
}

impl RandomGoals {
    pub fn new(low: &[f64], high: &[f64], seed: u64) -> Result<Self> {
        check_bounds("RandomGoals", low, high)?;
        Ok(RandomGoals { low: low.to_vec(), high: high.to_vec(), rng: rng_from_seed(seed) })
    }
}

impl GoalSelector for RandomGoals {
    fn goal_box(&self) -> (&[f64], &[f64]) {
        (&self.low, &self.high)
    }
    fn sample(&mut self) -> GoalChoice {
        GoalChoice { goal: uniform_in(&mut self.rng, &self.low, &self.high), mode: Mode::Random, region: None }
    }
    fn update(&mut self, _point: &[f64], _competence: f64) -> Option<usize> {
        None
    }
    fn save(&self) -> Option<Vec<u8>> {
        save_state(&RandomState { rng: self.rng.clone() })
    }
    fn load(&mut self, state: &[u8]) -> bool {
        let Some(RandomState { rng }) = load_state(state) else { return false };
        self.rng = rng;
        true
    }
}

#[cfg(test)]
mod tests;

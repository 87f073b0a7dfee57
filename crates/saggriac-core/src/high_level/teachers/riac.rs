//! RIAC as Portelas et al. ("Teacher algorithms for curriculum learning of Deep RL in
//! continuously parameterized environments", CoRL 2019) use it as a baseline, after R-IAC
//! (Baranes & Oudeyer, "R-IAC: Robust intrinsically motivated exploration and active learning",
//! IEEE TAMD 2009).
//!
//! The task box is split recursively. A region's absolute learning progress (ALP) is
//! |mean of the newer half - mean of the older half| of the competences it has recorded. When a
//! leaf holds more than `max_region_size` of them, `split_attempts` random cuts (a dimension,
//! then a value, uniform) are tried; a cut is kept only if each child holds at least
//! `min_child_share` of the leaf's measurements and spans at least `min_dims_range_ratio` of the
//! initial range in every dimension, and the kept cut with the largest |ALP(child 1) -
//! ALP(child 2)| splits the leaf. A leaf that cannot be split keeps only its newest
//! `max_region_size` measurements. Goals come from three modes: a leaf drawn in proportion to
//! its ALP, uniformly inside it (`p_alp`); uniformly in the whole box (`p_random`); or a leaf
//! drawn by ALP and a Gaussian around the goal of lowest competence it holds (the rest).
//!
//! The cuts draw from their own generator, so the regions depend only on the measurements: a
//! saved teacher is restored by replaying them.

use crate::config::high_level::check_bounds;
use crate::error::Result;
use crate::config::teachers::TeacherParams;
use crate::high_level::goal_selection::{load_state, save_state, GoalChoice, GoalSelector, LeafRow, Mode};
use crate::rng::{child_seed, index, normal, rng_from_seed, uniform, unit, CoreRng};

pub use crate::config::teachers::RiacConfig;

/// RIAC's state: its generator and every measurement told, in order (the regions replay from
/// them; the cuts' generator restarts from the seed and so draws the same cuts).
#[derive(Debug, Clone, serde::Serialize, serde::Deserialize)]
struct RiacState {
    rng: CoreRng,
    points: Vec<f64>,
    values: Vec<f64>,
}

#[derive(Debug, Clone)]
struct Leaf {
    low: Vec<f64>,
    high: Vec<f64>,
    /// Measurements in the order they came: points row by row, and competences.
    points: Vec<f64>,
    values: Vec<f64>,
    alp: f64,
}

/// |mean of the newer half - mean of the older half| (0 below two measurements).
fn alp(values: &[f64]) -> f64 {
    let n = values.len();
    if n < 2 {
        return 0.0;
    }
    let h = n / 2;
    let mean = |v: &[f64]| v.iter().sum::<f64>() / v.len() as f64;
    (mean(&values[n - h..]) - mean(&values[..n - h])).abs()
}

#[derive(Debug, Clone)]
pub struct Riac {
    cfg: RiacConfig,
    low: Vec<f64>,
    high: Vec<f64>,
    leaves: Vec<Leaf>,
    rng: CoreRng,
    /// The cuts' generator (see the module's last paragraph).
    split_rng: CoreRng,
    seed: u64,
    /// Every measurement in order (for saving).
    told_points: Vec<f64>,
    told_values: Vec<f64>,
}

impl Riac {
    pub fn new(low: &[f64], high: &[f64], cfg: RiacConfig, seed: u64) -> Result<Self> {
        check_bounds("RiacSelector", low, high)?;
        cfg.validate()?;
        let root = Leaf { low: low.to_vec(), high: high.to_vec(), points: Vec::new(), values: Vec::new(), alp: 0.0 };
        Ok(Riac {
            cfg,
            low: low.to_vec(),
            high: high.to_vec(),
            leaves: vec![root],
            rng: rng_from_seed(seed),
            split_rng: rng_from_seed(child_seed(seed, 1)),
            seed,
            told_points: Vec::new(),
            told_values: Vec::new(),
        })
    }

    pub fn n_leaves(&self) -> usize {
        self.leaves.len()
    }

    /// Each leaf's bounds and ALP.
    pub fn leaves(&self) -> impl Iterator<Item = (&[f64], &[f64], f64)> {
        self.leaves.iter().map(|l| (l.low.as_slice(), l.high.as_slice(), l.alp))
    }

    fn leaf_of(&self, p: &[f64]) -> usize {
        // Leaves tile the box; a point on a shared face goes to the first leaf holding it.
        self.leaves.iter().position(|l| p.iter().zip(l.low.iter().zip(&l.high)).all(|(v, (lo, hi))| v >= lo && v <= hi)).unwrap_or(0)
    }

    /// A leaf drawn in proportion to its ALP (uniformly when no leaf has any).
    fn alp_leaf(&mut self) -> usize {
        let total: f64 = self.leaves.iter().map(|l| l.alp).sum();
        if !(total > 0.0 && total.is_finite()) {
            return index(&mut self.rng, self.leaves.len());
        }
        let mut u = unit(&mut self.rng) * total;
        for (i, l) in self.leaves.iter().enumerate() {
            if u < l.alp {
                return i;
            }
            u -= l.alp;
        }
        self.leaves.iter().rposition(|l| l.alp > 0.0).unwrap_or(0)
    }

    fn try_split(&mut self, i: usize) {
        let d = self.low.len();
        let leaf = &self.leaves[i];
        let n = leaf.values.len();
        let min_count = (self.cfg.min_child_share * n as f64).ceil() as usize;
        let mut best: Option<(f64, usize, f64)> = None;
        for _ in 0..self.cfg.split_attempts {
            let dim = index(&mut self.split_rng, d);
            let min_width = self.cfg.min_dims_range_ratio * (self.high[dim] - self.low[dim]);
            let (lo, hi) = (leaf.low[dim] + min_width, leaf.high[dim] - min_width);
            if lo >= hi {
                continue;
            }
            let cut = uniform(&mut self.split_rng, lo, hi);
            let (mut a, mut b) = (Vec::new(), Vec::new());
            for (k, v) in leaf.values.iter().enumerate() {
                if leaf.points[k * d + dim] < cut {
                    a.push(*v)
                } else {
                    b.push(*v)
                }
            }
            if a.len() < min_count || b.len() < min_count {
                continue;
            }
            let score = (alp(&a) - alp(&b)).abs();
            if best.is_none_or(|(s, _, _)| score > s) {
                best = Some((score, dim, cut));
            }
        }
        let Some((_, dim, cut)) = best else {
            // No admissible cut: a sliding window of the newest measurements.
            let keep = self.cfg.max_region_size;
            let leaf = &mut self.leaves[i];
            let drop = leaf.values.len() - keep;
            leaf.values.drain(..drop);
            leaf.points.drain(..drop * d);
            leaf.alp = alp(&leaf.values);
            return;
        };
        let leaf = self.leaves.swap_remove(i);
        let mut children = [leaf.clone(), leaf.clone()];
        children[0].high[dim] = cut;
        children[1].low[dim] = cut;
        for c in &mut children {
            c.points.clear();
            c.values.clear();
        }
        for (k, v) in leaf.values.iter().enumerate() {
            let p = &leaf.points[k * d..(k + 1) * d];
            let c = &mut children[usize::from(p[dim] >= cut)];
            c.points.extend_from_slice(p);
            c.values.push(*v);
        }
        for mut c in children {
            c.alp = alp(&c.values);
            self.leaves.push(c);
        }
    }
}

impl GoalSelector for Riac {
    fn goal_box(&self) -> (&[f64], &[f64]) {
        (&self.low, &self.high)
    }
    fn sample(&mut self) -> GoalChoice {
        let u = unit(&mut self.rng);
        if u < self.cfg.p_random || self.told_values.is_empty() {
            let goal = self.low.iter().zip(&self.high).map(|(l, h)| uniform(&mut self.rng, *l, *h)).collect();
            return GoalChoice { goal, mode: Mode::Global, region: None };
        }
        let i = self.alp_leaf();
        let leaf = &self.leaves[i];
        if u < self.cfg.p_random + self.cfg.p_alp || leaf.values.is_empty() {
            let (lo, hi) = (leaf.low.clone(), leaf.high.clone());
            let goal = lo.iter().zip(&hi).map(|(l, h)| uniform(&mut self.rng, *l, *h)).collect();
            return GoalChoice { goal, mode: Mode::Interest, region: Some(i) };
        }
        // Near the leaf's goal of lowest competence, a tenth of the leaf's width away.
        let d = self.low.len();
        let worst = leaf.values.iter().enumerate().fold(0, |b, (k, v)| if *v < leaf.values[b] { k } else { b });
        let centre = leaf.points[worst * d..(worst + 1) * d].to_vec();
        let (lo, hi) = (leaf.low.clone(), leaf.high.clone());
        let goal = (0..d).map(|j| (centre[j] + 0.1 * (hi[j] - lo[j]) * normal(&mut self.rng)).clamp(lo[j], hi[j])).collect();
        GoalChoice { goal, mode: Mode::LowestCompetence, region: Some(i) }
    }
    fn update(&mut self, point: &[f64], competence: f64) -> Option<usize> {
        let p: Vec<f64> = point.iter().zip(self.low.iter().zip(&self.high)).map(|(v, (l, h))| v.clamp(*l, *h)).collect();
        self.told_points.extend_from_slice(&p);
        self.told_values.push(competence);
        let i = self.leaf_of(&p);
        let leaf = &mut self.leaves[i];
        leaf.points.extend_from_slice(&p);
        leaf.values.push(competence);
        leaf.alp = alp(&leaf.values);
        if leaf.values.len() > self.cfg.max_region_size {
            self.try_split(i);
        }
        Some(self.leaf_of(&p))
    }
    fn leaf_table(&self) -> Vec<LeafRow> {
        self.leaves.iter().map(|l| LeafRow { low: l.low.clone(), high: l.high.clone(), interest: l.alp, n_measurements: l.values.len() }).collect()
    }
    fn save(&self) -> Option<Vec<u8>> {
        save_state(&RiacState { rng: self.rng.clone(), points: self.told_points.clone(), values: self.told_values.clone() })
    }
    fn load(&mut self, state: &[u8]) -> bool {
        let Some(RiacState { rng, points, values }) = load_state(state) else { return false };
        if points.len() != values.len() * self.low.len() {
            return false;
        }
        let Ok(mut fresh) = Riac::new(&self.low, &self.high, self.cfg, self.seed) else { return false };
        for (p, v) in points.chunks_exact(self.low.len()).zip(&values) {
            fresh.update(p, *v);
        }
        fresh.rng = rng;
        *self = fresh;
        true
    }
}

build_by_new!(RiacConfig => Riac, box);

#[cfg(test)]
mod tests {
    use super::*;

    fn riac(d: usize) -> Riac {
        Riac::new(&vec![0.0; d], &vec![1.0; d], RiacConfig { max_region_size: 40, ..RiacConfig::default() }, 5).unwrap()
    }

    #[test]
    fn alp_is_the_change_between_halves() {
        assert_eq!(alp(&[]), 0.0);
        assert_eq!(alp(&[-0.5]), 0.0);
        assert!((alp(&[-1.0, -1.0, 0.0, 0.0]) - 1.0).abs() < 1e-15);
        // Odd count: the older half has the extra measurement.
        assert!((alp(&[-1.0, -1.0, -1.0, 0.0, 0.0]) - 1.0).abs() < 1e-15);
    }

    #[test]
    fn splits_where_progress_differs_and_respects_child_limits() {
        let mut t = riac(2);
        let mut rng = rng_from_seed(2);
        // Progress only for x < 0.3: competence rises with time there, flat elsewhere.
        for k in 0..400 {
            let p = [unit(&mut rng), unit(&mut rng)];
            let c = if p[0] < 0.3 { -1.0 + k as f64 / 400.0 } else { -0.5 };
            t.update(&p, c);
        }
        assert!(t.n_leaves() > 1);
        for (lo, hi, _) in t.leaves() {
            assert!((0..2).all(|j| hi[j] - lo[j] >= 1.0 / 6.0 - 1e-12), "{lo:?} {hi:?}");
        }
        // The leaves with progress are those left of the cut near 0.3.
        let (best_lo, best_hi, _) = t.leaves().max_by(|a, b| a.2.total_cmp(&b.2)).unwrap();
        assert!(best_hi[0] <= 0.5 && best_lo[0] == 0.0, "{best_lo:?} {best_hi:?}");
        // And ALP-driven goals go there more than uniform ones would.
        let left = (0..2000).filter(|_| t.sample().goal[0] < 0.3).count() as f64 / 2000.0;
        assert!(left > 0.45, "{left}");
    }

    #[test]
    fn a_leaf_that_cannot_split_keeps_a_window() {
        // Every point identical: no cut leaves a quarter on each side.
        let mut t = riac(1);
        for k in 0..100 {
            t.update(&[0.5], -(k as f64) / 100.0);
        }
        assert_eq!(t.n_leaves(), 1);
        assert_eq!(t.leaves[0].values.len(), 40);
    }

    #[test]
    fn bad_parameters_are_named() {
        let e = Riac::new(&[0.0], &[1.0], RiacConfig { p_alp: 0.9, ..RiacConfig::default() }, 0).unwrap_err().to_string();
        assert!(e.contains("'p_alp' parameter of RiacSelector") && e.contains("p_alp + p_random <= 1"), "{e}");
        let e = Riac::new(&[0.0], &[1.0], RiacConfig { max_region_size: 1, ..RiacConfig::default() }, 0).unwrap_err().to_string();
        assert!(e.contains("'max_region_size'"), "{e}");
        assert!(Riac::new(&[1.0], &[0.0], RiacConfig::default(), 0).is_err());
    }
}

//! The episodic paradigm's part of the sensorimotor model: every movement's (theta, x). Its
//! inverse model is the nearest neighbour of a goal among the reached positions, optionally with
//! a first-order correction from a local linear model around that neighbour; its forward model
//! is the nearest stored configuration's position, corrected the same way. Readers (the
//! evaluation) use it through `&self` only; the neighbour buffers are the caller's.

use nalgebra::DMatrix;

pub use crate::config::low_level::EpisodicConfig;
use crate::model::block_index::BlockIndex;
use crate::model::kd_tree::KdTree;
use crate::model::local_model::pinv_apply_wide;
use crate::model::neighbours::distances;
use crate::model::neighbours::{dist_sq, merge_newer, Neighbour, NeighbourIndex};
use crate::task_space::{point, sub, Point};

/// Every movement's (theta, x), indexed by x (for the inverse model) and, when the learner
/// needs neighbours of arbitrary configurations (local fits, ACTUATOR-RIAC's predictions), by
/// theta. The evaluation's fixed test configurations use an incremental scan instead.
pub struct EpisodicMemory {
    n: usize,
    m: usize,
    thetas: Vec<f64>,
    xs: Vec<f64>,
    /// Reached positions, in a few dimensions: a k-d tree (examples/episodic_index_probe: 0.7 us
    /// against 152 us for the block index, 1-NN among 50,000 unordered 2-D points).
    by_x: KdTree,
    /// Whole configurations, in n dimensions: the block index (590 us against 2,400 us for the
    /// k-d tree, 20-NN among 50,000 unordered 15-D points).
    by_theta: Option<BlockIndex>,
}

impl EpisodicMemory {
    /// Memory of movements of `n` joints reaching a `m`-D task space.
    pub fn new(n: usize, m: usize, index_theta: bool) -> Self {
        EpisodicMemory { n, m, thetas: Vec::new(), xs: Vec::new(), by_x: KdTree::new(m), by_theta: index_theta.then(|| BlockIndex::new(n)) }
    }

    fn knn_theta(&self, theta: &[f64], k: usize, out: &mut Vec<Neighbour>) {
        match &self.by_theta {
            Some(t) => t.knn(theta, k, out),
            None => {
                let mut upto = 0;
                out.clear();
                self.knn_theta_since(theta, k, out, &mut upto);
            }
        }
    }

    /// Exact k nearest stored configurations, kept up to date: `best` holds the answer for the
    /// first `*upto` samples; the samples stored since are scanned and merged in (distance, id)
    /// order, so the answer equals a full search.
    pub fn knn_theta_since(&self, theta: &[f64], k: usize, best: &mut Vec<Neighbour>, upto: &mut usize) {
        if k > 0 {
            for id in *upto..self.len() {
                merge_newer(best, k, id, dist_sq(theta, self.theta(id)));
            }
        }
        *upto = self.len();
    }

    /// `knn_theta_since` for many fixed queries at once, with the same answers: `queries` holds
    /// them dimension-major (coordinate d of query i at d * nq + i) and `caches[i]` is query i's
    /// (best, upto). Each new sample is compared with every query in one SIMD pass, which reads
    /// the samples once instead of once per query.
    pub fn knn_theta_since_many(&self, queries: &[f64], k: usize, caches: &mut [(Vec<Neighbour>, usize)], acc: &mut Vec<f64>) {
        let nq = caches.len();
        debug_assert_eq!(queries.len(), nq * self.n);
        acc.resize(nq, 0.0);
        let start = caches.iter().map(|c| c.1).min().unwrap_or(self.len());
        if k > 0 {
            for id in start..self.len() {
                distances(self.theta(id), queries, nq, nq, acc);
                for ((best, upto), &d) in caches.iter_mut().zip(acc.iter()) {
                    if id >= *upto {
                        merge_newer(best, k, id, d);
                    }
                }
            }
        }
        caches.iter_mut().for_each(|c| c.1 = self.len());
    }
    pub fn len(&self) -> usize {
        self.xs.len() / self.m
    }
    pub fn is_empty(&self) -> bool {
        self.xs.is_empty()
    }
    /// Every movement as (thetas, xs), row by row (for checkpoints).
    pub fn arrays(&self) -> (&[f64], &[f64]) {
        (&self.thetas, &self.xs)
    }
    pub fn theta(&self, i: usize) -> &[f64] {
        &self.thetas[i * self.n..(i + 1) * self.n]
    }
    pub fn task_dim(&self) -> usize {
        self.m
    }
    pub fn x(&self, i: usize) -> Point {
        point(&self.xs[self.m * i..self.m * (i + 1)])
    }

    /// Store one movement; a non-finite value is refused (returns false) and never indexed.
    pub fn add(&mut self, theta: &[f64], x: &[f64]) -> bool {
        debug_assert!(theta.len() == self.n && x.len() == self.m);
        if !(theta.iter().all(|v| v.is_finite()) && x.iter().all(|v| v.is_finite())) {
            return false;
        }
        self.thetas.extend_from_slice(theta);
        self.xs.extend_from_slice(x);
        self.by_x.add(x);
        if let Some(t) = &mut self.by_theta {
            t.add(theta);
        }
        true
    }

    /// Inverse model without noise: the configuration that reached closest to `goal`, optionally
    /// moved by J+ (goal - x_nn), `nb` being scratch space. Returns false when the memory is empty.
    pub fn inverse(&self, goal: &Point, cfg: &EpisodicConfig, rcond: f64, nb: &mut Vec<Neighbour>, out: &mut [f64]) -> bool {
        self.by_x.knn(&goal[..self.m], 1, nb);
        let Some(first) = nb.first().copied() else {
            return false;
        };
        let i = first.id as usize;
        out.copy_from_slice(self.theta(i));
        if cfg.refine {
            let base = self.theta(i).to_vec();
            self.knn_theta(&base, cfg.k_refine + 1, nb);
            if let Some(j) = self.local_jacobian(&base, self.x(i), nb) {
                let x0 = self.x(i);
                let dx = sub(goal, &x0);
                let mut d = vec![0.0; self.n];
                if pinv_apply_wide(&j, &dx[..self.m], rcond, &mut d).is_ok() {
                    // A first-order step is only trusted as far as the neighbourhood extends.
                    let reach = nb.iter().map(|b| b.dist_sq).fold(0.0, f64::max).sqrt();
                    let norm = d.iter().map(|v| v * v).sum::<f64>().sqrt();
                    let s = if norm > reach && norm > 0.0 { reach / norm } else { 1.0 };
                    out.iter_mut().zip(&d).for_each(|(o, v)| *o += s * v);
                }
            }
        }
        true
    }

    /// Forward model: the nearest stored configuration's position, optionally corrected by the
    /// local linear model (`nb` is scratch space). None when the memory is empty.
    pub fn predict(&self, theta: &[f64], cfg: &EpisodicConfig, nb: &mut Vec<Neighbour>) -> Option<Point> {
        self.knn_theta(theta, Self::forward_k(cfg), nb);
        self.predict_from(theta, nb, cfg)
    }

    /// Neighbours the forward model uses.
    pub fn forward_k(cfg: &EpisodicConfig) -> usize {
        if cfg.refine {
            cfg.k_refine
        } else {
            1
        }
    }

    /// The forward model's prediction at `theta` from its neighbours `nb` (sorted).
    pub fn predict_from(&self, theta: &[f64], nb: &[Neighbour], cfg: &EpisodicConfig) -> Option<Point> {
        nb.first().map(|f| {
            let i = f.id as usize;
            let mut x = self.x(i);
            if cfg.refine {
                let base = self.theta(i).to_vec();
                if let Some(j) = self.local_jacobian(&base, x, nb) {
                    let d: Vec<f64> = theta.iter().zip(&base).map(|(a, b)| a - b).collect();
                    for (r, xr) in x.iter_mut().take(self.m).enumerate() {
                        *xr += (0..self.n).map(|a| j[(r, a)] * d[a]).sum::<f64>();
                    }
                }
            }
            x
        })
    }

    /// Least squares J with x_i - x0 ~ J (theta_i - theta0) over the neighbours, ridge-damped
    /// so that fewer neighbours than joints still give the minimum-norm answer. None if the
    /// neighbours carry no information (all at theta0).
    fn local_jacobian(&self, theta0: &[f64], x0: Point, nb: &[Neighbour]) -> Option<DMatrix<f64>> {
        let n = self.n;
        let rows: Vec<usize> = nb.iter().map(|b| b.id as usize).filter(|&i| self.theta(i) != theta0).collect();
        if rows.is_empty() {
            return None;
        }
        let dth = DMatrix::from_fn(rows.len(), n, |r, a| self.theta(rows[r])[a] - theta0[a]);
        let dx = DMatrix::from_fn(rows.len(), self.m, |r, c| self.x(rows[r])[c] - x0[c]);
        let mut gram = dth.transpose() * &dth;
        let trace = gram.trace();
        if !(trace.is_finite() && trace > 0.0) {
            return None;
        }
        for a in 0..n {
            gram[(a, a)] += 1e-6 * trace / n as f64;
        }
        let jt = gram.cholesky()?.solve(&(dth.transpose() * dx));
        jt.iter().all(|v| v.is_finite()).then(|| jt.transpose())
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::model::neighbours::BruteForce;
    use crate::rng::{rng_from_seed, uniform};

    /// The incremental scan of the evaluation gives exactly a full search's neighbours, ties
    /// (duplicate configurations) included, however the samples arrive between two calls.
    #[test]
    fn incremental_neighbours_match_brute_force() {
        let n = 4;
        let mut mem = EpisodicMemory::new(n, 2, false);
        let mut bf = BruteForce::new(n);
        let mut rng = rng_from_seed(5);
        let queries: Vec<Vec<f64>> = (0..6).map(|_| (0..n).map(|_| uniform(&mut rng, -1.0, 1.0)).collect()).collect();
        let mut cache: Vec<(Vec<Neighbour>, usize)> = vec![(Vec::new(), 0); queries.len()];
        // The batched scan, with its own caches; query 0's starts late to mix the starting points.
        let nq = queries.len();
        let qt: Vec<f64> = (0..n * nq).map(|j| queries[j % nq][j / nq]).collect();
        let mut many: Vec<Vec<(Vec<Neighbour>, usize)>> = vec![vec![(Vec::new(), 0); nq]; 2];
        let mut acc = Vec::new();
        let mut expected = Vec::new();
        for round in 0..30 {
            for _ in 0..(round * 7) % 23 {
                // Coarse coordinates so that equal distances and duplicates occur.
                let t: Vec<f64> = (0..n).map(|_| (uniform(&mut rng, -1.0, 1.0) * 4.0).round() / 4.0).collect();
                mem.add(&t, &[0.0, 0.0]);
                bf.add(&t);
            }
            for k in [1, 5] {
                let caches = &mut many[if k == 1 { 0 } else { 1 }];
                if round == 3 {
                    caches[0] = (Vec::new(), 0);
                }
                mem.knn_theta_since_many(&qt, k, caches, &mut acc);
                for (q, (nb, upto)) in queries.iter().zip(cache.iter_mut()) {
                    let (mut nb_k, mut upto_k) = if k == 1 { (nb.clone(), *upto) } else { (Vec::new(), 0) };
                    mem.knn_theta_since(q, k, &mut nb_k, &mut upto_k);
                    bf.knn(q, k, &mut expected);
                    assert_eq!(nb_k, expected, "round {round}, k {k}");
                    let i = queries.iter().position(|p| p == q).unwrap();
                    assert_eq!(many[if k == 1 { 0 } else { 1 }][i], (expected.clone(), mem.len()), "batched, round {round}, k {k}");
                    if k == 1 {
                        *nb = nb_k;
                        *upto = upto_k;
                    }
                }
            }
        }
    }
}

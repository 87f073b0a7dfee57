//! Exact k-nearest-neighbour search over stored joint configurations, behind our own trait so
//! the index can change without touching the learner. Ties are broken by insertion id so that
//! every implementation returns the same answer as the brute-force reference.

/// One neighbour: the id of the stored point (its insertion order) and its squared distance.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Neighbour {
    pub id: u32,
    pub dist_sq: f64,
}

#[inline]
fn order(a: &Neighbour, b: &Neighbour) -> std::cmp::Ordering {
    a.dist_sq.total_cmp(&b.dist_sq).then(a.id.cmp(&b.id))
}

/// Squared Euclidean distance; every index uses this one function so that a radius computed
/// outside the index compares bit for bit with the distances inside it.
#[inline]
pub fn dist_sq(a: &[f64], b: &[f64]) -> f64 {
    a.iter().zip(b).map(|(x, y)| (x - y) * (x - y)).sum()
}

pub(crate) use crate::model::block_distances::{distances, distances_within, full_block_distances_within, screen_full_block};

/// The k best so far, sorted by (distance, id), within the radius; k is small (tens), so
/// insertion into a sorted array beats a heap.
pub(crate) struct TopK<'a> {
    out: &'a mut Vec<Neighbour>,
    k: usize,
    radius_sq: f64,
}

impl<'a> TopK<'a> {
    pub(crate) fn new(out: &'a mut Vec<Neighbour>, k: usize, radius_sq: f64) -> Self {
        out.clear();
        TopK { out, k, radius_sq }
    }
    /// Distance a point must not exceed to matter (the k-th so far, or the radius).
    #[inline]
    pub(crate) fn bound(&self) -> f64 {
        if self.out.len() < self.k {
            self.radius_sq
        } else {
            self.out[self.k - 1].dist_sq
        }
    }
    #[inline]
    pub(crate) fn offer(&mut self, id: u32, d: f64) {
        if d > self.bound() {
            return;
        }
        if self.out.len() >= self.k {
            let w = self.out[self.k - 1];
            if d == w.dist_sq && id > w.id {
                return;
            }
            self.out.pop();
        }
        // One step of insertion sort from the back: most newcomers land near the end, and a
        // compare-and-move loop costs less than a binary search's unpredictable branches and a
        // call to memmove.
        let new = Neighbour { id, dist_sq: d };
        self.out.push(new);
        let v = &mut self.out[..];
        let mut j = v.len() - 1;
        while j > 0 && (v[j - 1].dist_sq > d || (v[j - 1].dist_sq == d && v[j - 1].id > id)) {
            v[j] = v[j - 1];
            j -= 1;
        }
        v[j] = new;
    }
}

/// Merge sample `id` at squared distance `d` into `best`, the k (> 0) nearest so far sorted by
/// (distance, id), every one of them older than `id`: a later id loses ties, so it must be
/// strictly closer than the k-th to get in.
pub(crate) fn merge_newer(best: &mut Vec<Neighbour>, k: usize, id: usize, d: f64) {
    if best.len() == k && d >= best[k - 1].dist_sq {
        return;
    }
    let pos = best.partition_point(|b| b.dist_sq <= d);
    best.insert(pos, Neighbour { id: id as u32, dist_sq: d });
    best.truncate(k);
}

/// An incremental, exact neighbour index. Points get ids 0, 1, 2, ... in insertion order.
pub trait NeighbourIndex: Send + Sync {
    fn dim(&self) -> usize;
    fn len(&self) -> usize;
    fn is_empty(&self) -> bool {
        self.len() == 0
    }
    fn add(&mut self, point: &[f64]);
    /// The k nearest points to `query` with squared distance <= `radius_sq`, sorted by
    /// (distance, id). Fewer than k come back only when fewer lie within the radius.
    fn knn_within(&self, query: &[f64], k: usize, radius_sq: f64, out: &mut Vec<Neighbour>);
    /// The k nearest points, sorted by (distance, id).
    fn knn(&self, query: &[f64], k: usize, out: &mut Vec<Neighbour>) {
        self.knn_within(query, k, f64::INFINITY, out)
    }
}

/// An index that is also where its points' coordinates live (the memory keeps theta only in
/// its index), so they can be read back by id.
pub trait PointIndex: NeighbourIndex {
    /// The coordinates of point `id`, written into `out`.
    fn point(&self, id: usize, out: &mut [f64]);
    /// `dist_sq(query, point id)`, with the same bits.
    fn dist_sq_to(&self, id: usize, query: &[f64]) -> f64;
    /// `visit(id, dist_sq(query, point id))` for every point from id `from` on, in id order.
    fn scan_from(&self, from: usize, query: &[f64], visit: &mut dyn FnMut(usize, f64)) {
        for id in from..self.len() {
            visit(id, self.dist_sq_to(id, query));
        }
    }
}

/// Full scan: the reference every other index is tested against, and the fastest choice for a
/// few hundred points.
#[derive(Debug, Clone)]
pub struct BruteForce {
    dim: usize,
    data: Vec<f64>,
}

impl BruteForce {
    pub fn new(dim: usize) -> Self {
        BruteForce { dim, data: Vec::new() }
    }
}

impl NeighbourIndex for BruteForce {
    fn dim(&self) -> usize {
        self.dim
    }
    fn len(&self) -> usize {
        self.data.len() / self.dim.max(1)
    }
    fn add(&mut self, point: &[f64]) {
        debug_assert_eq!(point.len(), self.dim);
        self.data.extend_from_slice(point);
    }
    fn knn_within(&self, query: &[f64], k: usize, radius_sq: f64, out: &mut Vec<Neighbour>) {
        out.clear();
        if k == 0 {
            return;
        }
        for (i, p) in self.data.chunks_exact(self.dim).enumerate() {
            let d = dist_sq(query, p);
            if d <= radius_sq {
                out.push(Neighbour { id: i as u32, dist_sq: d });
            }
        }
        if out.len() > k {
            out.select_nth_unstable_by(k - 1, order);
            out.truncate(k);
        }
        out.sort_unstable_by(order);
    }
}

impl PointIndex for BruteForce {
    fn point(&self, id: usize, out: &mut [f64]) {
        out.copy_from_slice(&self.data[id * self.dim..(id + 1) * self.dim]);
    }
    fn dist_sq_to(&self, id: usize, query: &[f64]) -> f64 {
        dist_sq(query, &self.data[id * self.dim..(id + 1) * self.dim])
    }
}

/// Warm-started exact search. Between two micro-actions the query barely moves, so the previous
/// neighbours and the newest samples are already close: the k-th smallest of their distances to
/// the new query bounds the true k-th distance, and a radius-bounded tree search with that
/// bound prunes almost everything while staying exact.
#[derive(Debug, Clone, Default)]
pub struct WarmStart {
    previous: Vec<u32>,
    candidates: Vec<f64>,
    /// How many of the newest samples join the candidates.
    pub recent: usize,
}

impl WarmStart {
    pub fn new(recent: usize) -> Self {
        WarmStart { previous: Vec::new(), candidates: Vec::new(), recent }
    }

    /// Forget the previous neighbours (after a jump such as a reset to rest).
    pub fn clear(&mut self) {
        self.previous.clear();
    }

    /// Take `answer`, found some other way, as the previous query's neighbours.
    pub fn remember(&mut self, answer: &[Neighbour]) {
        self.previous.clear();
        self.previous.extend(answer.iter().map(|nb| nb.id));
    }

    /// The exact k nearest neighbours of `query` among the points of `index`.
    pub fn knn<I: PointIndex + ?Sized>(&mut self, index: &I, query: &[f64], k: usize, out: &mut Vec<Neighbour>) {
        let n = index.len();
        self.candidates.clear();
        let first_recent = n.saturating_sub(self.recent);
        for &id in &self.previous {
            let id = id as usize;
            // Recent ids are added below; skipping them here keeps candidates distinct.
            if id < first_recent {
                self.candidates.push(index.dist_sq_to(id, query));
            }
        }
        for id in first_recent..n {
            self.candidates.push(index.dist_sq_to(id, query));
        }
        let radius = if k > 0 && self.candidates.len() >= k {
            let (_, kth, _) = self.candidates.select_nth_unstable_by(k - 1, |a, b| a.total_cmp(b));
            *kth
        } else {
            f64::INFINITY
        };
        index.knn_within(query, k, radius, out);
        if out.len() < k.min(n) {
            // Cannot happen with distinct candidates; kept as a guard so the answer stays exact.
            index.knn(query, k, out);
        }
        self.previous.clear();
        self.previous.extend(out.iter().map(|nb| nb.id));
    }
}

/// Checks shared by the tests of every index: same answers as the brute-force reference.
#[cfg(test)]
pub(crate) mod reference {
    use super::*;
    use crate::rng::{rng_from_seed, uniform};

    /// Fill `index` with `points` and compare every query's answer with a full scan.
    pub fn assert_matches_brute(index: &mut dyn NeighbourIndex, points: &[f64], queries: &[f64], k: usize) {
        let dim = index.dim();
        let mut bf = BruteForce::new(dim);
        for p in points.chunks_exact(dim) {
            bf.add(p);
            index.add(p);
        }
        let (mut a, mut b) = (Vec::new(), Vec::new());
        for q in queries.chunks_exact(dim) {
            bf.knn(q, k, &mut a);
            index.knn(q, k, &mut b);
            assert_eq!(a, b);
        }
    }

    /// Drive a warm-started search along a random walk with resets to zero (the arm's pattern)
    /// and compare each answer with a full scan.
    pub fn assert_warm_start_exact<I: PointIndex + ?Sized>(index: &mut I, steps: usize, reset_every: usize, k: usize, seed: u64) {
        let dim = index.dim();
        let mut bf = BruteForce::new(dim);
        let mut r = rng_from_seed(seed);
        let mut theta = vec![0.0; dim];
        let mut ws = WarmStart::new(8);
        let (mut a, mut b) = (Vec::new(), Vec::new());
        for step in 0..steps {
            if step % reset_every == 0 {
                theta.iter_mut().for_each(|t| *t = 0.0);
                ws.clear();
            }
            theta.iter_mut().for_each(|t| *t += uniform(&mut r, -0.02, 0.02));
            bf.knn(&theta, k, &mut a);
            ws.knn(index, &theta, k, &mut b);
            assert_eq!(a, b, "step {step}");
            bf.add(&theta);
            index.add(&theta);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::reference::{assert_matches_brute, assert_warm_start_exact};
    use super::*;
    use crate::model::block_index::BlockIndex;
    use crate::rng::{rng_from_seed, uniform};

    fn random_points(n: usize, dim: usize, seed: u64) -> Vec<f64> {
        let mut r = rng_from_seed(seed);
        (0..n * dim).map(|_| uniform(&mut r, -1.0, 1.0)).collect()
    }

    fn check_against_brute(points: &[f64], dim: usize, queries: &[f64], k: usize) {
        assert_matches_brute(&mut BlockIndex::new(dim), points, queries, k);
    }

    #[test]
    fn block_index_matches_brute_force_random() {
        let dim = 15;
        let pts = random_points(3000, dim, 1);
        let qs = random_points(50, dim, 2);
        check_against_brute(&pts, dim, &qs, 30);
    }

    #[test]
    fn block_index_matches_brute_force_with_duplicates() {
        // Many identical rest poses plus a trajectory leaving them, like the arm's data.
        let dim = 15;
        let mut pts = vec![0.0; 500 * dim];
        let mut r = rng_from_seed(3);
        let mut theta = vec![0.0; dim];
        for _ in 0..2000 {
            for t in theta.iter_mut() {
                *t += uniform(&mut r, -0.01, 0.01);
            }
            pts.extend_from_slice(&theta);
        }
        pts.extend(vec![0.0; 300 * dim]);
        let mut qs = vec![0.0; dim];
        qs.extend_from_slice(&pts[700 * dim..701 * dim]);
        qs.extend(random_points(10, dim, 4).iter().map(|v| v * 0.05));
        check_against_brute(&pts, dim, &qs, 45);
    }

    #[test]
    fn warm_start_is_exact_along_a_trajectory() {
        assert_warm_start_exact(&mut BlockIndex::new(15), 4000, 300, 20, 5);
    }

    #[test]
    fn fewer_points_than_k() {
        let mut kd = BlockIndex::new(2);
        kd.add(&[0.0, 0.0]);
        kd.add(&[1.0, 0.0]);
        let mut out = Vec::new();
        kd.knn(&[0.9, 0.0], 5, &mut out);
        assert_eq!(out.iter().map(|n| n.id).collect::<Vec<_>>(), vec![1, 0]);
    }
}

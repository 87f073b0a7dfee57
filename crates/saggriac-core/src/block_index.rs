//! Exact k nearest neighbours shaped to the memory's structure: boxes over runs of consecutive
//! samples (the measurement and design are in the project's neighbour-index note).
//!
//! The memory is a trajectory: a micro-action moves each joint by at most `max_joint_step`, so
//! `BLOCK` consecutive samples span a tiny box, far smaller than a k-d leaf in 15-D. Samples are
//! kept in blocks of `BLOCK`, dimension-major within a block (so distances run in SIMD lanes),
//! under a hierarchy of bounding boxes over insertion order: one per block, one per `FANOUT`
//! blocks, one per `FANOUT` of those, and so on (append-only: an insert widens one box per
//! level). A query descends it depth first, opening only boxes whose lower bound does not
//! exceed the k-th distance so far, and ranks the points of open blocks by (distance, id).
//!
//! Exactness: the bound of a box is `sum_d gap_d^2`, summed in the same order as `dist_sq`, with
//! `gap_d` the distance from the query to the box along dimension d. For a point inside the box
//! every computed `|q_d - p_d|` is >= the computed gap (rounding is monotone), so the computed
//! bound never exceeds the point's computed distance. A box is skipped only when its bound is
//! strictly above the k-th distance found so far, which never falls below the final one: every
//! point at or inside the final k-th distance is ranked, ties included. Boxes are stored in f32,
//! rounded outward, so they still contain their points.

use crate::kd_tree::distances;
use crate::neighbours::{Neighbour, NeighbourIndex};

/// Samples per block (the unit whose distances are computed together).
const BLOCK: usize = 16;
/// Boxes per box of the level above: level 0 boxes one block, level i boxes FANOUT^i blocks.
const FANOUT: usize = 8;

#[derive(Debug, Clone)]
pub struct BlockIndex {
    dim: usize,
    len: usize,
    /// Block b holds its points at `coords[b * dim * BLOCK + d * BLOCK + j]`.
    coords: Vec<f64>,
    /// `boxes[level]`: box i of that level (over blocks i * FANOUT^level ..): lows at
    /// `[i * 2 * dim..][..dim]`, highs right after. The top level has at most FANOUT boxes.
    boxes: Vec<Vec<f32>>,
}

/// The largest f32 <= v and the smallest f32 >= v (v finite).
fn outward(v: f64) -> (f32, f32) {
    let f = v as f32;
    let fd = f as f64;
    let below = if fd > v { step_down(f) } else { f };
    let above = if fd < v { step_up(f) } else { f };
    (below, above)
}

fn step_up(f: f32) -> f32 {
    if f.is_nan() || f == f32::INFINITY {
        return f;
    }
    if f == 0.0 {
        return f32::from_bits(1);
    }
    let b = f.to_bits();
    f32::from_bits(if f > 0.0 { b + 1 } else { b - 1 })
}

fn step_down(f: f32) -> f32 {
    -step_up(-f)
}

/// Lower bound of the squared distance from q to any point of the box (lows, then highs).
#[inline]
fn box_bound(q: &[f64], bx: &[f32]) -> f64 {
    let dim = q.len();
    let (lo, hi) = bx.split_at(dim);
    let mut s = 0.0;
    for d in 0..dim {
        let (l, h, x) = (lo[d] as f64, hi[d] as f64, q[d]);
        // One of the two terms is zero (l <= h), so gap is l - x, x - h or 0, exactly.
        let gap = (l - x).max(0.0) + (x - h).max(0.0);
        s += gap * gap;
    }
    s
}

/// Whether the box's lower bound is <= limit. The partial sums only grow, so the sum stops as
/// soon as it passes the limit (the same sums as `box_bound`, so the same answer).
#[inline]
fn box_within(q: &[f64], bx: &[f32], limit: f64) -> bool {
    let dim = q.len();
    let (lo, hi) = bx.split_at(dim);
    let mut s = 0.0;
    for d in 0..dim {
        let (l, h, x) = (lo[d] as f64, hi[d] as f64, q[d]);
        let gap = (l - x).max(0.0) + (x - h).max(0.0);
        s += gap * gap;
        if s > limit {
            return false;
        }
    }
    true
}

fn widen(bx: &mut [f32], dim: usize, p: &[f64]) {
    for (d, &v) in p.iter().enumerate() {
        let (down, up) = outward(v);
        if down < bx[d] {
            bx[d] = down;
        }
        if up > bx[dim + d] {
            bx[dim + d] = up;
        }
    }
}

fn empty_box(dim: usize) -> impl Iterator<Item = f32> {
    std::iter::repeat_n(f32::INFINITY, dim).chain(std::iter::repeat_n(f32::NEG_INFINITY, dim))
}

/// The k best so far, sorted by (distance, id), within the radius.
struct TopK<'a> {
    out: &'a mut Vec<Neighbour>,
    k: usize,
    radius_sq: f64,
}

impl TopK<'_> {
    /// Distance a point must not exceed to matter (the k-th so far, or the radius).
    #[inline]
    fn bound(&self) -> f64 {
        if self.out.len() < self.k {
            self.radius_sq
        } else {
            self.out[self.k - 1].dist_sq
        }
    }
    #[inline]
    fn offer(&mut self, id: u32, d: f64) {
        if d > self.bound() {
            return;
        }
        let full = self.out.len() >= self.k;
        if full {
            let w = self.out[self.k - 1];
            if d == w.dist_sq && id > w.id {
                return;
            }
        }
        let pos = self.out.partition_point(|n| n.dist_sq < d || (n.dist_sq == d && n.id < id));
        if full {
            self.out.pop();
        }
        self.out.insert(pos, Neighbour { id, dist_sq: d });
    }
}

impl BlockIndex {
    pub fn new(dim: usize) -> Self {
        BlockIndex { dim, len: 0, coords: Vec::new(), boxes: vec![Vec::new()] }
    }

    /// The coordinates of point `id`, gathered into `out`.
    pub fn point(&self, id: usize, out: &mut [f64]) {
        let (b, j) = (id / BLOCK, id % BLOCK);
        let base = b * self.dim * BLOCK;
        for (d, o) in out.iter_mut().enumerate().take(self.dim) {
            *o = self.coords[base + d * BLOCK + j];
        }
    }

    /// Bytes held per stored point (coordinates and boxes), for the memory benchmark.
    pub fn bytes_per_point(&self) -> f64 {
        let bytes = self.coords.capacity() * 8 + self.boxes.iter().map(|b| b.capacity() * 4).sum::<usize>();
        bytes as f64 / self.len.max(1) as f64
    }

    fn n_boxes(&self, level: usize) -> usize {
        self.boxes[level].len() / (2 * self.dim)
    }

    #[inline]
    fn bound(&self, level: usize, i: usize, q: &[f64]) -> f64 {
        box_bound(q, &self.boxes[level][i * 2 * self.dim..(i + 1) * 2 * self.dim])
    }

    #[inline]
    fn within(&self, level: usize, i: usize, q: &[f64], limit: f64) -> bool {
        box_within(q, &self.boxes[level][i * 2 * self.dim..(i + 1) * 2 * self.dim], limit)
    }

    fn visit_block(&self, b: usize, q: &[f64], best: &mut TopK<'_>, acc: &mut [f64; BLOCK]) {
        let first = b * BLOCK;
        let count = (self.len - first).min(BLOCK);
        distances(q, &self.coords[b * self.dim * BLOCK..(b + 1) * self.dim * BLOCK], BLOCK, count, acc);
        for (j, &d) in acc.iter().enumerate().take(count) {
            best.offer((first + j) as u32, d);
        }
    }

    /// Depth first through box `i` of `level`, in insertion order, opening only boxes whose
    /// bound does not exceed the k-th distance so far; `skip` is a level-1 box already done.
    fn search(&self, level: usize, i: usize, q: &[f64], best: &mut TopK<'_>, acc: &mut [f64; BLOCK], skip: Option<usize>) {
        if level == 0 {
            return self.visit_block(i, q, best, acc);
        }
        if level == 1 && skip == Some(i) {
            return;
        }
        let last = ((i + 1) * FANOUT).min(self.n_boxes(level - 1));
        for c in i * FANOUT..last {
            if self.within(level - 1, c, q, best.bound()) {
                self.search(level - 1, c, q, best, acc, skip);
            }
        }
    }

    /// Without k points in hand the bound is only the radius: first take every point of the
    /// level-1 box reached by always descending into the child of smallest bound.
    fn seed(&self, q: &[f64], best: &mut TopK<'_>, acc: &mut [f64; BLOCK]) -> Option<usize> {
        let top = self.boxes.len() - 1;
        if top == 0 {
            return None;
        }
        let nearest = |level: usize, from: usize, to: usize| (from..to).map(|c| (self.bound(level, c, q), c)).min_by(|a, b| a.0.total_cmp(&b.0));
        let (mut lb, mut i) = nearest(top, 0, self.n_boxes(top))?;
        for level in (1..top).rev() {
            (lb, i) = nearest(level, i * FANOUT, ((i + 1) * FANOUT).min(self.n_boxes(level)))?;
        }
        if lb > best.bound() {
            return None;
        }
        let last = ((i + 1) * FANOUT).min(self.n_boxes(0));
        for b in i * FANOUT..last {
            if self.within(0, b, q, best.bound()) {
                self.visit_block(b, q, best, acc);
            }
        }
        Some(i)
    }
}

impl NeighbourIndex for BlockIndex {
    fn dim(&self) -> usize {
        self.dim
    }
    fn len(&self) -> usize {
        self.len
    }

    fn add(&mut self, point: &[f64]) {
        debug_assert_eq!(point.len(), self.dim);
        let dim = self.dim;
        let (b, j) = (self.len / BLOCK, self.len % BLOCK);
        if j == 0 {
            self.coords.resize(self.coords.len() + dim * BLOCK, 0.0);
            // A new block: a new box on every level whose span it starts.
            let mut span = 1;
            for level in 0..self.boxes.len() {
                if b % span == 0 {
                    self.boxes[level].extend(empty_box(dim));
                }
                span *= FANOUT;
            }
            // The top level outgrew its fan-out: a level above it, boxing all of it.
            let top = self.boxes.len() - 1;
            if self.n_boxes(top) > FANOUT {
                let mut above: Vec<f32> = Vec::new();
                for chunk in self.boxes[top].chunks(2 * dim * FANOUT) {
                    let mut bx: Vec<f32> = empty_box(dim).collect();
                    for child in chunk.chunks_exact(2 * dim) {
                        for d in 0..dim {
                            bx[d] = bx[d].min(child[d]);
                            bx[dim + d] = bx[dim + d].max(child[dim + d]);
                        }
                    }
                    above.extend(bx);
                }
                self.boxes.push(above);
            }
        }
        let base = b * dim * BLOCK;
        for (d, &v) in point.iter().enumerate() {
            self.coords[base + d * BLOCK + j] = v;
        }
        let mut i = b;
        for level in self.boxes.iter_mut() {
            widen(&mut level[i * 2 * dim..(i + 1) * 2 * dim], dim, point);
            i /= FANOUT;
        }
        self.len += 1;
    }

    fn knn_within(&self, query: &[f64], k: usize, radius_sq: f64, out: &mut Vec<Neighbour>) {
        out.clear();
        if k == 0 || self.len == 0 {
            return;
        }
        let mut best = TopK { out, k, radius_sq };
        let mut acc = [0.0; BLOCK];
        let seeded = if best.out.len() < k { self.seed(query, &mut best, &mut acc) } else { None };
        let top = self.boxes.len() - 1;
        for i in 0..self.n_boxes(top) {
            if self.within(top, i, query, best.bound()) {
                self.search(top, i, query, &mut best, &mut acc, seeded);
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::neighbours::reference::{assert_matches_brute, assert_warm_start_exact};
    use crate::neighbours::BruteForce;
    use crate::rng::{rng_from_seed, uniform};

    fn trajectory(n: usize, dim: usize, step: f64, reset_every: usize, seed: u64) -> Vec<f64> {
        let mut r = rng_from_seed(seed);
        let mut t = vec![0.0; dim];
        let mut pts = Vec::with_capacity(n * dim);
        for i in 0..n {
            if i % reset_every == 0 {
                t.iter_mut().for_each(|v| *v = 0.0);
            }
            t.iter_mut().for_each(|v| *v += uniform(&mut r, -step, step));
            pts.extend_from_slice(&t);
        }
        pts
    }

    #[test]
    fn outward_rounding_contains_the_value() {
        for &v in &[0.0, -0.0, 1e-40, -1e-40, 0.1, -0.1, 1.0 / 3.0, 1e30, -1e30, 1e300, -1e300, f64::MIN_POSITIVE] {
            let (lo, hi) = outward(v);
            assert!((lo as f64) <= v && v <= (hi as f64), "{v}: [{lo}, {hi}]");
        }
    }

    #[test]
    fn matches_brute_force_in_every_dimension_from_1_to_100() {
        let mut r = rng_from_seed(3);
        for dim in (1..=20).chain([31, 45, 64, 100]) {
            let pts = trajectory(700, dim, 0.05, 230, dim as u64);
            let qs: Vec<f64> = (0..12 * dim).map(|_| uniform(&mut r, -0.6, 0.6)).collect();
            for &k in &[1usize, 45, 900] {
                assert_matches_brute(&mut BlockIndex::new(dim), &pts, &qs, k);
            }
        }
    }

    #[test]
    fn matches_brute_force_with_hundreds_of_identical_rest_poses_and_ties() {
        let dim = 15;
        let mut pts = vec![0.0; 600 * dim];
        for i in 0..300 {
            let mut p = vec![0.0; dim];
            p[i % dim] = ((i / dim) % 3) as f64 * 0.5; // a grid: equal distances everywhere
            pts.extend(p);
        }
        pts.extend(trajectory(2000, dim, 0.05, 500, 9));
        pts.extend(vec![0.0; 300 * dim]);
        let mut qs = vec![0.0; dim];
        let mut q = vec![0.0; dim];
        q[2] = 0.25;
        qs.extend(q);
        qs.extend_from_slice(&pts[1700 * dim..1701 * dim]);
        let mut r = rng_from_seed(4);
        qs.extend((0..20 * dim).map(|_| uniform(&mut r, -2.0, 2.0)));
        for &k in &[1usize, 45, 599, 600, 601, 1300] {
            assert_matches_brute(&mut BlockIndex::new(dim), &pts, &qs, k);
        }
    }

    #[test]
    fn warm_start_is_exact_along_a_growing_trajectory() {
        for &dim in &[2usize, 15, 40] {
            assert_warm_start_exact(&mut BlockIndex::new(dim), 3000, 250, 45, dim as u64);
        }
    }

    #[test]
    fn radius_and_growth_match_brute_force() {
        let dim = 15;
        // 9,000 points: 563 blocks under four levels of boxes, each level growing in turn.
        let pts = trajectory(9000, dim, 0.05, 700, 21);
        let mut idx = BlockIndex::new(dim);
        let mut bf = BruteForce::new(dim);
        let mut r = rng_from_seed(5);
        let (mut a, mut b) = (Vec::new(), Vec::new());
        for (i, p) in pts.chunks_exact(dim).enumerate() {
            idx.add(p);
            bf.add(p);
            if i % 211 == 0 || i < 40 || (i + 1) % (BLOCK * FANOUT * FANOUT) == 0 {
                let q: Vec<f64> = (0..dim).map(|_| uniform(&mut r, -0.8, 0.8)).collect();
                for &radius in &[0.0, 0.05, 0.5, 4.0, f64::INFINITY] {
                    bf.knn_within(&q, 45, radius, &mut a);
                    idx.knn_within(&q, 45, radius, &mut b);
                    assert_eq!(a, b, "after {} points, radius {radius}", i + 1);
                }
            }
        }
        let mut p = vec![0.0; dim];
        idx.point(1234, &mut p);
        assert_eq!(p, &pts[1234 * dim..1235 * dim]);
    }
}

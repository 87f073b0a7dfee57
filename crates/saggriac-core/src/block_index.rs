//! Exact k nearest neighbours shaped to the memory's structure: boxes over runs of consecutive
//! samples (the measurement and design are in the project's neighbour-index note).
//!
//! The memory is a trajectory: a micro-action moves each joint by at most `max_joint_step`, so
//! `BLOCK` consecutive samples span a tiny box, far smaller than a k-d leaf in 15-D. Samples are
//! kept in blocks of `BLOCK`, dimension-major within a block (so distances run in SIMD lanes),
//! under a hierarchy of bounding boxes over insertion order: one per block, one per `FANOUT`
//! blocks, one per `FANOUT` of those, and so on (append-only: an insert widens one box per
//! level). The `FANOUT` children of a box are stored together in a row, dimension-major. A query
//! goes down level by level: the rows of the boxes it could not skip are bounded `BATCH` at a
//! time (independent sums in SIMD lanes), and the points of the blocks it could not skip are
//! ranked. A query with nothing to bound it yet first descends to the nearest blocks.
//!
//! Exactness: the bound of a box is `sum_d gap_d^2`, summed in the same order as `dist_sq`, with
//! `gap_d` the distance from the query to the box along dimension d. For a point inside the box
//! every computed `|q_d - p_d|` is >= the computed gap (rounding is monotone), so the computed
//! bound never exceeds the point's computed distance. A box is skipped only when its bound is
//! strictly above the k-th distance found so far, which never falls below the final one: every
//! point at or inside the final k-th distance is ranked, ties included. Boxes are stored in f32,
//! rounded outward, so they still contain their points.
//!
//! Storage is `Chunked`, so a clone is a cheap snapshot that later inserts do not change.

use crate::chunked::Chunked;
use crate::neighbours::{distances, Neighbour, NeighbourIndex, PointIndex, TopK};

/// Samples per block (the unit whose distances are computed together).
const BLOCK: usize = 16;
/// Blocks per group, and boxes per row of boxes.
const FANOUT: usize = 8;
/// Rows of boxes whose bounds are computed together.
const BATCH: usize = 4;
/// Blocks per chunk of storage (1,024 samples).
const CHUNK_BLOCKS: usize = 64;

#[derive(Debug, Clone)]
pub struct BlockIndex {
    dim: usize,
    len: usize,
    /// Row b is block b: coordinate d of its point j at `d * BLOCK + j`.
    coords: Chunked<f64>,
    /// `boxes[level]`, row r: boxes r * FANOUT .. of that level (box i of level l covers blocks
    /// i * FANOUT^l ..), dimension-major: the low of box c along d at `d * FANOUT + c`, the highs
    /// after all lows. Row r holds the children of box r of the level above; the top level has
    /// a single row.
    boxes: Vec<Chunked<f32>>,
    /// A row of empty boxes (pads the last batch).
    empty: Vec<f32>,
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

type Bounds = [[f64; FANOUT]; BATCH];

/// Lower bounds of the squared distance from q to each box of `BATCH` rows of boxes.
/// `x > 0 ? x : 0` rather than `max`, which keeps NaN rules out of the way of vectorisation
/// (nothing here is NaN: the memory refuses non-finite samples and queries are finite).
#[inline(always)]
fn bounds_generic(q: &[f64], rows: &[&[f32]; BATCH], out: &mut Bounds) {
    let dim = q.len();
    let mut acc = [[0.0; FANOUT]; BATCH];
    for (d, &x) in q.iter().enumerate() {
        for (a, row) in acc.iter_mut().zip(rows) {
            let l = &row[d * FANOUT..(d + 1) * FANOUT];
            let h = &row[(dim + d) * FANOUT..(dim + d + 1) * FANOUT];
            for c in 0..FANOUT {
                let below = l[c] as f64 - x;
                let above = x - h[c] as f64;
                // At most one of the two is positive (l <= h): the gap is exact.
                let gap = if below > 0.0 { below } else { 0.0 } + if above > 0.0 { above } else { 0.0 };
                a[c] += gap * gap;
            }
        }
    }
    *out = acc;
}

#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2")]
unsafe fn bounds_avx2(q: &[f64], rows: &[&[f32]; BATCH], out: &mut Bounds) {
    // Same code in 4-wide lanes; no FMA is enabled, so the bounds are bit-identical.
    bounds_generic(q, rows, out)
}

#[inline]
fn bounds(q: &[f64], rows: &[&[f32]; BATCH], out: &mut Bounds) {
    #[cfg(target_arch = "x86_64")]
    {
        if std::arch::is_x86_feature_detected!("avx2") {
            // SAFETY: the CPU supports AVX2, checked just above.
            return unsafe { bounds_avx2(q, rows, out) };
        }
    }
    bounds_generic(q, rows, out)
}

fn empty_row(dim: usize) -> Vec<f32> {
    let mut row = vec![f32::INFINITY; 2 * dim * FANOUT];
    row[dim * FANOUT..].iter_mut().for_each(|v| *v = f32::NEG_INFINITY);
    row
}

/// Widen box `lane` of a row of boxes to hold `p`.
fn widen(row: &mut [f32], lane: usize, p: &[f64]) {
    let dim = p.len();
    for (d, &v) in p.iter().enumerate() {
        let (down, up) = outward(v);
        let (lo, hi) = (d * FANOUT + lane, (dim + d) * FANOUT + lane);
        if down < row[lo] {
            row[lo] = down;
        }
        if up > row[hi] {
            row[hi] = up;
        }
    }
}

impl BlockIndex {
    pub fn new(dim: usize) -> Self {
        BlockIndex { dim, len: 0, coords: Chunked::new(dim * BLOCK, CHUNK_BLOCKS), boxes: vec![Self::level(dim)], empty: empty_row(dim) }
    }

    fn level(dim: usize) -> Chunked<f32> {
        Chunked::new(2 * dim * FANOUT, CHUNK_BLOCKS / FANOUT)
    }

    fn n_blocks(&self) -> usize {
        self.len.div_ceil(BLOCK)
    }

    /// Boxes on `level`: one per FANOUT^level blocks.
    fn n_boxes(&self, level: usize) -> usize {
        self.n_blocks().div_ceil(FANOUT.pow(level as u32))
    }

    /// The coordinates of point `id`, gathered into `out`.
    pub fn point(&self, id: usize, out: &mut [f64]) {
        let block = self.coords.row(id / BLOCK);
        let j = id % BLOCK;
        for (d, o) in out.iter_mut().enumerate().take(self.dim) {
            *o = block[d * BLOCK + j];
        }
    }

    /// Bytes held per stored point (coordinates and boxes).
    pub fn bytes_per_point(&self) -> f64 {
        let bytes = self.coords.bytes() + self.boxes.iter().map(|b| b.bytes()).sum::<usize>();
        bytes as f64 / self.len.max(1) as f64
    }

    fn visit_block(&self, b: usize, q: &[f64], best: &mut TopK<'_>, acc: &mut [f64; BLOCK]) {
        let first = b * BLOCK;
        let count = (self.len - first).min(BLOCK);
        distances(q, self.coords.row(b), BLOCK, count, acc);
        for (j, &d) in acc.iter().enumerate().take(count) {
            best.offer((first + j) as u32, d);
        }
    }

    /// Bound the boxes of `rows` of `level` (at most BATCH rows), BATCH rows at a time; the
    /// boxes within the k-th distance so far are visited (blocks, on level 0) or pushed to `next`.
    fn open(&self, level: usize, rows: &[usize], q: &[f64], best: &mut TopK<'_>, acc: &mut [f64; BLOCK], next: &mut Vec<usize>) {
        let boxes = &self.boxes[level];
        let batch: [&[f32]; BATCH] = std::array::from_fn(|i| rows.get(i).map_or(&self.empty[..], |&r| boxes.row(r)));
        let mut b = [[0.0; FANOUT]; BATCH];
        bounds(q, &batch, &mut b);
        let n = self.n_boxes(level);
        for (&r, lanes) in rows.iter().zip(&b) {
            for (c, &lb) in lanes.iter().enumerate() {
                let i = r * FANOUT + c;
                if i < n && lb <= best.bound() {
                    if level == 0 {
                        self.visit_block(i, q, best, acc);
                    } else {
                        next.push(i);
                    }
                }
            }
        }
    }

    /// Down from the top, always into the nearest box, to a row of blocks; visits them and
    /// returns that row (of level 0).
    fn seed(&self, q: &[f64], best: &mut TopK<'_>, acc: &mut [f64; BLOCK]) -> usize {
        let mut row = 0;
        for level in (1..self.boxes.len()).rev() {
            let mut b = [[0.0; FANOUT]; BATCH];
            let mut batch = [&self.empty[..]; BATCH];
            batch[0] = self.boxes[level].row(row);
            bounds(q, &batch, &mut b);
            let n = (self.n_boxes(level) - row * FANOUT).min(FANOUT);
            let c = (0..n).min_by(|&x, &y| b[0][x].total_cmp(&b[0][y])).unwrap_or(0);
            row = row * FANOUT + c;
        }
        self.open(0, &[row], q, best, acc, &mut Vec::new());
        row
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
            self.coords.push(&vec![0.0; dim * BLOCK]);
            // A new block: a new box on every level whose span it starts, in a new row when it
            // is the first of its row.
            let mut span = 1;
            for level in 0..self.boxes.len() {
                if b % (span * FANOUT) == 0 {
                    self.boxes[level].push(&self.empty);
                }
                span *= FANOUT;
            }
            // The top level outgrew its single row: a level above, boxing each of its rows.
            let top = self.boxes.len() - 1;
            if self.boxes[top].len() > 1 {
                let mut row = self.empty.clone();
                for g in 0..self.boxes[top].len() {
                    let child = self.boxes[top].row(g);
                    for c in 0..FANOUT {
                        for d in 0..dim {
                            let (lo, hi) = (d * FANOUT, (dim + d) * FANOUT);
                            row[lo + g] = row[lo + g].min(child[lo + c]);
                            row[hi + g] = row[hi + g].max(child[hi + c]);
                        }
                    }
                }
                let mut above = Self::level(dim);
                above.push(&row);
                self.boxes.push(above);
            }
        }
        let block = self.coords.last_mut();
        for (d, &v) in point.iter().enumerate() {
            block[d * BLOCK + j] = v;
        }
        let mut i = b;
        for level in self.boxes.iter_mut() {
            widen(level.last_mut(), i % FANOUT, point);
            i /= FANOUT;
        }
        self.len += 1;
    }

    fn knn_within(&self, query: &[f64], k: usize, radius_sq: f64, out: &mut Vec<Neighbour>) {
        if k == 0 || self.len == 0 {
            out.clear();
            return;
        }
        let mut best = TopK::new(out, k, radius_sq);
        let mut acc = [0.0; BLOCK];
        // Nothing bounds the search yet: the nearest blocks first give it a k-th distance.
        let seeded = (best.bound() == f64::INFINITY).then(|| self.seed(query, &mut best, &mut acc));
        let (mut rows, mut next) = (vec![0usize], Vec::new());
        for level in (0..self.boxes.len()).rev() {
            if level == 0 {
                rows.retain(|&r| Some(r) != seeded);
            }
            for batch in rows.chunks(BATCH) {
                self.open(level, batch, query, &mut best, &mut acc, &mut next);
            }
            std::mem::swap(&mut rows, &mut next);
            next.clear();
        }
    }
}

impl PointIndex for BlockIndex {
    fn point(&self, id: usize, out: &mut [f64]) {
        BlockIndex::point(self, id, out)
    }

    fn dist_sq_to(&self, id: usize, query: &[f64]) -> f64 {
        let block = self.coords.row(id / BLOCK);
        let j = id % BLOCK;
        // Summed in dimension order from 0, as `dist_sq` sums: the same bits.
        query.iter().enumerate().map(|(d, q)| (q - block[d * BLOCK + j]) * (q - block[d * BLOCK + j])).sum()
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
        // 9,000 points: 563 blocks under four levels of boxes, queried as rows and levels begin.
        let pts = trajectory(9000, dim, 0.05, 700, 21);
        let mut idx = BlockIndex::new(dim);
        let mut bf = BruteForce::new(dim);
        let mut r = rng_from_seed(5);
        let (mut a, mut b) = (Vec::new(), Vec::new());
        for (i, p) in pts.chunks_exact(dim).enumerate() {
            idx.add(p);
            bf.add(p);
            if i % 211 == 0 || i < 40 || (i + 1) % (BLOCK * FANOUT * FANOUT) == 0 || (i + 1) % (BLOCK * FANOUT) == 1 {
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

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
//! Exactness: boxes are stored in f32, rounded outward, so they contain their points. The bound
//! of a box is `sum_d gap_d^2` in f32 (eight lanes to a register), `gap_d` the distance from the
//! f32-rounded query to the box along dimension d; `Query::limit(t)` is the largest such bound a
//! box holding a point at computed distance <= t can get, rounding included (its comment gives
//! the proof). A box is skipped only when its bound is above `limit` of the k-th distance found
//! so far, which never falls below the final one: every point at or inside the final k-th
//! distance is ranked with the f64 `dist_sq`, ties included.
//!
//! Each full block's points are screened before they are ranked: an f32 copy of the block gives
//! eight f32 distances in one register, and only a block with a point at or below
//! `Query::point_limit` of the k-th distance is ranked in f64. That limit is proved the same way
//! (the stored points' own f32 rounding added to the query's), so no point within the k-th
//! distance is screened out. Half the bytes and half the lanes of the f64 kernel, for 60 more
//! bytes per sample at n = 15 (docs/performance.md, issue 49 item 2).
//!
//! Storage is `Chunked`, so a clone is a cheap snapshot that later inserts do not change.

mod bounds;
#[cfg(test)]
mod tests;

use bounds::{bounds, outward, Query, BATCH, FANOUT};

use crate::model::chunked::Chunked;
use crate::model::neighbours::{distances, distances_within, full_block_distances_within, screen_full_block, Neighbour, NeighbourIndex, PointIndex, TopK};

/// Samples per block (the unit whose distances are computed together). 8 rather than 16: on an
/// exp1 ACTUATOR-RIAC memory a query must rank the points of 67 blocks of 8 (539 points) instead
/// of 80 of 16 (1,282), about 10 % off the ACTUATOR runs; 4 gained nothing more
/// (docs/performance.md, "Blocks of 8").
const BLOCK: usize = 8;
/// Blocks per chunk of storage (512 samples).
const CHUNK_BLOCKS: usize = 64;

#[derive(Debug, Clone)]
pub struct BlockIndex {
    dim: usize,
    len: usize,
    /// Row b is block b: coordinate d of its point j at `d * BLOCK + j`.
    coords: Chunked<f64>,
    /// `coords` rounded to the nearest f32, same layout: a full block's points are screened
    /// with these (eight lanes at once) before their exact distances are computed.
    coords32: Chunked<f32>,
    /// The largest |p - p'| over stored points p and their f32 copies p' (see `Query`).
    rounding: f64,
    /// `boxes[level]`, row r: boxes r * FANOUT .. of that level (box i of level l covers blocks
    /// i * FANOUT^l ..), dimension-major: the low of box c along d at `d * FANOUT + c`, the highs
    /// after all lows. Row r holds the children of box r of the level above; the top level has
    /// a single row.
    boxes: Vec<Chunked<f32>>,
    /// A row of empty boxes (pads the last batch).
    empty: Vec<f32>,
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
        BlockIndex {
            dim,
            len: 0,
            coords: Chunked::new(dim * BLOCK, CHUNK_BLOCKS),
            coords32: Chunked::new(dim * BLOCK, CHUNK_BLOCKS),
            rounding: 0.0,
            boxes: vec![Self::level(dim)],
            empty: empty_row(dim),
        }
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
        let bytes = self.coords.bytes() + self.coords32.bytes() + self.boxes.iter().map(|b| b.bytes()).sum::<usize>();
        bytes as f64 / self.len.max(1) as f64
    }

    /// `plimit` is `q.point_limit(best.bound())`.
    fn visit_block(&self, b: usize, q: &Query<'_>, best: &mut TopK<'_>, acc: &mut [f64; BLOCK], plimit: f32) {
        let first = b * BLOCK;
        let count = (self.len - first).min(BLOCK);
        let bound = best.bound();
        let q32 = &q.q32;
        let q = q.q;
        // The points within the k-th distance as bits (most are beyond it); `offer` tests each
        // again against the k-th distance as it falls, in id order, as a scan of all would.
        let mut within = if count == BLOCK {
            // Only a block with a point that passes the f32 screen is ranked in f64: every point
            // within `bound` passes it (`Query::point_limit`), so the bits are those of a scan.
            if plimit != f32::INFINITY && screen_full_block::<BLOCK>(q32, self.coords32.row(b), plimit) == 0 {
                0
            } else {
                full_block_distances_within(q, self.coords.row(b), acc, bound)
            }
        } else if distances_within(q, self.coords.row(b), BLOCK, count, acc, bound) {
            acc.iter().take(count).enumerate().fold(0u32, |m, (j, &d)| m | (u32::from(d <= bound) << j))
        } else {
            0
        };
        while within != 0 {
            let j = within.trailing_zeros() as usize;
            within &= within - 1;
            best.offer((first + j) as u32, acc[j]);
        }
    }

    /// Bound the boxes of `rows` of `level` (at most BATCH rows), BATCH rows at a time; the
    /// boxes within the k-th distance so far are visited (blocks, on level 0) or pushed to `next`.
    fn open(&self, level: usize, rows: &[usize], q: &Query<'_>, best: &mut TopK<'_>, acc: &mut [f64; BLOCK], next: &mut Vec<usize>) {
        let boxes = &self.boxes[level];
        let batch: [&[f32]; BATCH] = std::array::from_fn(|i| rows.get(i).map_or(&self.empty[..], |&r| boxes.row(r)));
        let mut b = [[0.0; FANOUT]; BATCH];
        bounds(&q.q32, &batch, &mut b);
        let n = self.n_boxes(level);
        let mut bound = best.bound();
        let mut limit = q.limit(bound);
        let mut plimit = if level == 0 { q.point_limit(bound) } else { f32::INFINITY };
        for (&r, lanes) in rows.iter().zip(&b) {
            // The lanes to open, as bits (blocks are tested again as the limit falls).
            let real = (n - r * FANOUT).min(FANOUT);
            let mut open = lanes.iter().enumerate().fold(0u32, |m, (c, &lb)| m | (u32::from(lb <= limit) << c)) & ((1u32 << real) - 1);
            while open != 0 {
                let c = open.trailing_zeros() as usize;
                open &= open - 1;
                let i = r * FANOUT + c;
                if level == 0 {
                    if lanes[c] > limit {
                        continue;
                    }
                    self.visit_block(i, q, best, acc, plimit);
                    // Most blocks add nothing: the limits (square roots) change only with the
                    // k-th distance.
                    if best.bound() != bound {
                        bound = best.bound();
                        limit = q.limit(bound);
                        plimit = q.point_limit(bound);
                    }
                } else {
                    next.push(i);
                }
            }
        }
    }

    /// Down from the top, always into the nearest box, to a row of blocks; visits them and
    /// returns that row (of level 0).
    fn seed(&self, q: &Query<'_>, best: &mut TopK<'_>, acc: &mut [f64; BLOCK]) -> usize {
        let mut row = 0;
        for level in (1..self.boxes.len()).rev() {
            let mut b = [[0.0; FANOUT]; BATCH];
            let mut batch = [&self.empty[..]; BATCH];
            batch[0] = self.boxes[level].row(row);
            bounds(&q.q32, &batch, &mut b);
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
            self.coords32.push(&vec![0.0; dim * BLOCK]);
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
        // v - v' is exact in f64 (or infinite when v' overflows); the norm is bounded by
        // sqrt(dim) times the largest, which cannot underflow as a sum of squares could.
        let block32 = self.coords32.last_mut();
        let mut worst = 0.0f64;
        for (d, &v) in point.iter().enumerate() {
            let v32 = v as f32;
            block32[d * BLOCK + j] = v32;
            worst = worst.max((v - v32 as f64).abs());
        }
        self.rounding = self.rounding.max(worst * (dim as f64).sqrt() * (1.0 + 1e-12));
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
        let query = &Query::new(query, self.rounding);
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

    fn scan_from(&self, from: usize, query: &[f64], visit: &mut dyn FnMut(usize, f64)) {
        let mut acc = [0.0; BLOCK];
        for b in from / BLOCK..self.len.div_ceil(BLOCK) {
            let first = b * BLOCK;
            let count = (self.len - first).min(BLOCK);
            if count == BLOCK {
                full_block_distances_within(query, self.coords.row(b), &mut acc, f64::INFINITY);
            } else {
                distances(query, self.coords.row(b), BLOCK, count, &mut acc);
            }
            for (j, &d) in acc.iter().enumerate().take(count) {
                if first + j >= from {
                    visit(first + j, d);
                }
            }
        }
    }

    fn dist_sq_to(&self, id: usize, query: &[f64]) -> f64 {
        let block = self.coords.row(id / BLOCK);
        let j = id % BLOCK;
        // Summed in dimension order from 0, as `dist_sq` sums: the same bits.
        query.iter().enumerate().map(|(d, q)| (q - block[d * BLOCK + j]) * (q - block[d * BLOCK + j])).sum()
    }
}

//! Sensorimotor memory: every executed micro-action (theta, dtheta, dx) with the end-effector
//! position x before it. The configurations theta live in the neighbour index itself (the block
//! index keeps them in its blocks), so each is stored once. A clone is a snapshot: the storage is
//! chunked and shared, so an evaluation can read the memory as it was while learning goes on.

pub use crate::config::model::IndexKind;
use crate::model::block_index::BlockIndex;
use crate::model::chunked::Chunked;
use crate::model::neighbours::{merge_newer, BruteForce, Neighbour, PointIndex, WarmStart};

/// Samples per chunk of the dtheta, dx and x arrays.
const CHUNK: usize = 1024;

#[derive(Debug, Clone)]
enum Index {
    Blocks(BlockIndex),
    BruteForce(BruteForce),
}

impl Index {
    fn get(&self) -> &dyn PointIndex {
        match self {
            Index::Blocks(b) => b,
            Index::BruteForce(b) => b,
        }
    }
    fn get_mut(&mut self) -> &mut dyn PointIndex {
        match self {
            Index::Blocks(b) => b,
            Index::BruteForce(b) => b,
        }
    }
}

#[derive(Debug, Clone)]
pub struct SensorimotorMemory {
    n: usize,
    m: usize,
    index: Index,
    dtheta: Chunked<f64>,
    dx: Chunked<f64>,
    x: Chunked<f64>,
    rejected: u64,
}

impl SensorimotorMemory {
    pub fn new(n: usize, m: usize, kind: IndexKind) -> Self {
        let index = match kind {
            IndexKind::Blocks => Index::Blocks(BlockIndex::new(n)),
            IndexKind::BruteForce => Index::BruteForce(BruteForce::new(n)),
        };
        SensorimotorMemory { n, m, index, dtheta: Chunked::new(n, CHUNK), dx: Chunked::new(m, CHUNK), x: Chunked::new(m, CHUNK), rejected: 0 }
    }

    pub fn n_joints(&self) -> usize {
        self.n
    }
    pub fn task_dim(&self) -> usize {
        self.m
    }
    pub fn len(&self) -> usize {
        self.dx.len()
    }
    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }
    /// Every stored sample as (theta, dtheta, dx, x) arrays, row by row (for checkpoints).
    pub fn arrays(&self) -> [Vec<f64>; 4] {
        let mut theta = vec![0.0; self.len() * self.n];
        for (i, row) in theta.chunks_exact_mut(self.n.max(1)).enumerate().take(self.len()) {
            self.index.get().point(i, row);
        }
        [theta, self.dtheta.to_vec(), self.dx.to_vec(), self.x.to_vec()]
    }
    pub(crate) fn set_rejected(&mut self, n: u64) {
        self.rejected = n;
    }
    /// Samples refused because a value was NaN or infinite.
    pub fn rejected(&self) -> u64 {
        self.rejected
    }

    /// Store one micro-action. A sample with a non-finite value is refused (and counted), so
    /// NaN never enters the index or a fit. Returns whether it was stored.
    pub fn add(&mut self, theta: &[f64], dtheta: &[f64], dx: &[f64], x: &[f64]) -> bool {
        debug_assert!(theta.len() == self.n && dtheta.len() == self.n && dx.len() == self.m && x.len() == self.m);
        let finite = theta.iter().chain(dtheta).chain(dx).chain(x).all(|v| v.is_finite());
        if !finite {
            self.rejected += 1;
            return false;
        }
        self.index.get_mut().add(theta);
        self.dtheta.push(dtheta);
        self.dx.push(dx);
        self.x.push(x);
        true
    }

    /// Configuration of sample `i`, written into `out`.
    pub fn theta_into(&self, i: usize, out: &mut [f64]) {
        self.index.get().point(i, out)
    }
    /// Configuration of sample `i` (allocates; `theta_into` does not).
    pub fn theta(&self, i: usize) -> Vec<f64> {
        let mut t = vec![0.0; self.n];
        self.theta_into(i, &mut t);
        t
    }
    pub fn dtheta(&self, i: usize) -> &[f64] {
        self.dtheta.row(i)
    }
    pub fn dx(&self, i: usize) -> &[f64] {
        self.dx.row(i)
    }
    pub fn x(&self, i: usize) -> &[f64] {
        self.x.row(i)
    }

    /// Exact k nearest stored configurations, cold search.
    pub fn knn(&self, query: &[f64], k: usize, out: &mut Vec<Neighbour>) {
        self.index.get().knn(query, k, out)
    }

    /// Exact k nearest stored configurations of a fixed query, kept up to date: `best` holds
    /// the answer for the first `*upto` samples; those stored since are scanned and merged in
    /// (distance, id) order, so the answer equals a full search. The memory only grows, so the
    /// evaluation's fixed test configurations pay only for the new samples.
    pub fn knn_since(&self, query: &[f64], k: usize, best: &mut Vec<Neighbour>, upto: &mut usize) {
        if k > 0 {
            self.index.get().scan_from(*upto, query, &mut |id, d| merge_newer(best, k, id, d));
        }
        *upto = self.len();
    }

    /// Exact k nearest stored configurations, warm-started from `ws` (see `WarmStart`).
    pub fn knn_warm(&self, ws: &mut WarmStart, query: &[f64], k: usize, out: &mut Vec<Neighbour>) {
        ws.knn(self.index.get(), query, k, out)
    }

    /// Bytes of payload per stored sample (theta, dtheta, dx and x as f64; the index's boxes
    /// and the last chunk's spare room come on top).
    pub fn sample_bytes(&self) -> usize {
        (2 * self.n + 2 * self.m) * std::mem::size_of::<f64>()
    }
}

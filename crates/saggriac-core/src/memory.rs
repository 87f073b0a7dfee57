//! Sensorimotor memory: every executed micro-action (theta, dtheta, dx) with the end-effector
//! position x before it, plus the neighbour index over theta that the local models query.

use crate::block_index::BlockIndex;
pub use crate::config::model::IndexKind;
use crate::kd_tree::KdTree;
use crate::neighbours::{BruteForce, KdTreeIndex, Neighbour, NeighbourIndex, WarmStart};

pub struct SensorimotorMemory {
    n: usize,
    m: usize,
    theta: Vec<f64>,
    dtheta: Vec<f64>,
    dx: Vec<f64>,
    x: Vec<f64>,
    index: Box<dyn NeighbourIndex>,
    rejected: u64,
}

impl SensorimotorMemory {
    pub fn new(n: usize, m: usize, kind: IndexKind) -> Self {
        let index: Box<dyn NeighbourIndex> = match kind {
            IndexKind::KdTree => Box::new(KdTree::new(n)),
            IndexKind::KdTreeCrate => Box::new(KdTreeIndex::new(n)),
            IndexKind::BruteForce => Box::new(BruteForce::new(n)),
            IndexKind::Blocks => Box::new(BlockIndex::new(n)),
        };
        SensorimotorMemory { n, m, theta: Vec::new(), dtheta: Vec::new(), dx: Vec::new(), x: Vec::new(), index, rejected: 0 }
    }

    pub fn n_joints(&self) -> usize {
        self.n
    }
    pub fn task_dim(&self) -> usize {
        self.m
    }
    pub fn len(&self) -> usize {
        self.index.len()
    }
    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }
    /// Every stored sample as (theta, dtheta, dx, x) arrays, row by row (for checkpoints).
    pub fn arrays(&self) -> [&[f64]; 4] {
        [&self.theta, &self.dtheta, &self.dx, &self.x]
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
        self.theta.extend_from_slice(theta);
        self.dtheta.extend_from_slice(dtheta);
        self.dx.extend_from_slice(dx);
        self.x.extend_from_slice(x);
        self.index.add(theta);
        true
    }

    pub fn theta(&self, i: usize) -> &[f64] {
        &self.theta[i * self.n..(i + 1) * self.n]
    }
    pub fn dtheta(&self, i: usize) -> &[f64] {
        &self.dtheta[i * self.n..(i + 1) * self.n]
    }
    pub fn dx(&self, i: usize) -> &[f64] {
        &self.dx[i * self.m..(i + 1) * self.m]
    }
    pub fn x(&self, i: usize) -> &[f64] {
        &self.x[i * self.m..(i + 1) * self.m]
    }

    /// Exact k nearest stored configurations, cold search.
    pub fn knn(&self, query: &[f64], k: usize, out: &mut Vec<Neighbour>) {
        self.index.knn(query, k, out)
    }

    /// Exact k nearest stored configurations, warm-started from `ws` (see `WarmStart`).
    pub fn knn_warm(&self, ws: &mut WarmStart, query: &[f64], k: usize, out: &mut Vec<Neighbour>) {
        ws.knn(self.index.as_ref(), &self.theta, query, k, out)
    }

    /// Bytes held per stored sample by the arrays of this struct (the index adds its own).
    pub fn sample_bytes(&self) -> usize {
        (2 * self.n + 2 * self.m) * std::mem::size_of::<f64>()
    }
}

//! The sensorimotor model's parameters: the local linear models and the neighbour index.

use crate::error::{invalid, Check, Num, Result};

#[derive(Debug, Clone, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct LocalModelConfig {
    /// Neighbours used for each local fit.
    pub k_neighbours: usize,
    /// Ridge strength relative to the mean diagonal of the Gram matrix of dtheta.
    pub ridge: f64,
    /// Singular values below `pinv_rcond * sigma_max` are treated as zero in J+.
    pub pinv_rcond: f64,
    /// Width of the Gaussian weights, in units of the median neighbour's squared distance
    /// (0 = unweighted least squares).
    pub bandwidth: f64,
}

impl Default for LocalModelConfig {
    fn default() -> Self {
        LocalModelConfig { k_neighbours: 45, ridge: 1e-3, pinv_rcond: 1e-2, bandwidth: 1.0 }
    }
}

impl LocalModelConfig {
    pub fn validate(&self) -> Result<()> {
        let c = Check { owner: "LocalModel" };
        c.at_least("k_neighbours", self.k_neighbours, 1)?;
        c.positive("ridge", self.ridge)?;
        if !(self.pinv_rcond.is_finite() && (MIN_RCOND..=1.0).contains(&self.pinv_rcond)) {
            return Err(invalid("LocalModel", "pinv_rcond", format!("a float in [{MIN_RCOND:e}, 1]"), Num(self.pinv_rcond)));
        }
        c.non_negative("bandwidth", self.bandwidth)?;
        Ok(())
    }
}

/// Smallest relative cutoff of the pseudo-inverse (see `local_model::pinv_apply_wide`).
pub const MIN_RCOND: f64 = 1e-6;

/// Which exact neighbour index backs the memory (both give the same answers, bit for bit).
#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum IndexKind {
    /// Boxes over runs of consecutive samples (`block_index.rs`), the default.
    Blocks,
    /// A full scan: the reference the block index is tested against.
    BruteForce,
}

impl IndexKind {
    pub fn parse(s: &str) -> Option<Self> {
        match s {
            "blocks" => Some(IndexKind::Blocks),
            "brute_force" => Some(IndexKind::BruteForce),
            _ => None,
        }
    }
    pub fn name(&self) -> &'static str {
        match self {
            IndexKind::Blocks => "blocks",
            IndexKind::BruteForce => "brute_force",
        }
    }
}

//! The region tree of R-IAC / SAGG-RIAC (paper II.D.3): a box that is split recursively; each
//! leaf keeps the values (competences) measured in it in time order, and its interest (eq. 2).
//! Works in any dimension: the goal space S' for SAGG-RIAC, (theta, dtheta) for ACTUATOR-RIAC.

use crate::config::high_level::check_bounds;
pub use crate::config::high_level::RegionTreeConfig;
use crate::error::Result;
use crate::high_level::interest::interest;
use crate::table::{bools, floats, index_or_none, ints, slices, Table};

mod cut;
use cut::Cuts;

/// One node of the tree. Leaves hold measurements; inner nodes keep their split.
#[derive(Debug, Clone)]
pub struct Region {
    pub low: Vec<f64>,
    pub high: Vec<f64>,
    pub parent: Option<usize>,
    pub children: Option<[usize; 2]>,
    pub split_dim: usize,
    pub split_value: f64,
    /// Ids of the measurements in this leaf, in time order (empty once split).
    pub entries: Vec<u32>,
    pub interest: f64,
    sum: f64,
    /// Number of measurements the whole tree held when this region was created.
    pub created_at: u64,
    pub depth: u32,
}

impl Region {
    pub fn is_leaf(&self) -> bool {
        self.children.is_none()
    }
    /// Mean value of its measurements (eq. 1), None when empty.
    pub fn mean(&self) -> Option<f64> {
        if self.entries.is_empty() {
            None
        } else {
            Some(self.sum / self.entries.len() as f64)
        }
    }
}

/// Every node of a tree (leaves and inner): bounds, parent, split, interest, count; the
/// columns' names and kinds with no rows when there is no tree.
pub fn region_table(regions: &[Region], dim: usize) -> Table {
    vec![
        ("low", slices(regions, dim, |r| &r.low)),
        ("high", slices(regions, dim, |r| &r.high)),
        ("parent", ints(regions, |r| index_or_none(r.parent))),
        ("is_leaf", bools(regions, |r| r.is_leaf())),
        ("split_dim", ints(regions, |r| if r.is_leaf() { -1 } else { r.split_dim as i64 })),
        ("split_value", floats(regions, |r| r.split_value)),
        ("interest", floats(regions, |r| r.interest)),
        ("n_measurements", ints(regions, |r| r.entries.len() as i64)),
        ("mean_competence", floats(regions, |r| r.mean().unwrap_or(f64::NAN))),
        ("created_at", ints(regions, |r| r.created_at as i64)),
        ("depth", ints(regions, |r| r.depth as i64)),
    ]
}

#[derive(Debug, Clone)]
pub struct RegionTree {
    cfg: RegionTreeConfig,
    dim: usize,
    regions: Vec<Region>,
    leaves: Vec<usize>,
    /// Interest and mean value (NaN when empty) of each leaf, in the order of `leaves`: goal
    /// selection scans these on every draw, so they are kept contiguous.
    leaf_interest: Vec<f64>,
    leaf_mean: Vec<f64>,
    /// Position of each region in `leaves` (usize::MAX for inner regions).
    leaf_pos: Vec<usize>,
    /// The smallest leaf interest and how many leaves have it, kept up to date so that a draw
    /// needs no scan for it. A minimum does not depend on the order it is taken in, so this is
    /// exactly the value a scan would find.
    min_interest: (f64, usize),
    /// Running sums of the draw weights |interest - min| in leaf order: weight_sums[j] adds the
    /// first j weights left to right, as a plain sum does, so the total has the same bits. Only
    /// the sums after the first changed leaf are redone (sums_valid: how many leaves are
    /// unchanged since they were computed).
    weight_sums: Vec<f64>,
    sums_valid: usize,
    /// Scratch space for a leaf's last zeta values.
    window: Vec<f64>,
    points: Vec<f64>,
    values: Vec<f64>,
}

impl RegionTree {
    pub fn new(low: &[f64], high: &[f64], cfg: RegionTreeConfig) -> Result<Self> {
        cfg.validate()?;
        check_bounds("RegionTree", low, high)?;
        let root =
            Region { low: low.to_vec(), high: high.to_vec(), parent: None, children: None, split_dim: 0, split_value: f64::NAN, entries: Vec::new(), interest: 0.0, sum: 0.0, created_at: 0, depth: 0 };
        Ok(RegionTree {
            cfg,
            dim: low.len(),
            regions: vec![root],
            leaves: vec![0],
            leaf_interest: vec![0.0],
            leaf_mean: vec![f64::NAN],
            leaf_pos: vec![0],
            min_interest: (0.0, 1),
            weight_sums: vec![0.0],
            sums_valid: 0,
            window: Vec::new(),
            points: Vec::new(),
            values: Vec::new(),
        })
    }

    pub fn config(&self) -> &RegionTreeConfig {
        &self.cfg
    }
    pub fn dim(&self) -> usize {
        self.dim
    }
    pub fn regions(&self) -> &[Region] {
        &self.regions
    }
    pub fn region(&self, i: usize) -> &Region {
        &self.regions[i]
    }
    /// Leaf ids, in creation order.
    pub fn leaves(&self) -> &[usize] {
        &self.leaves
    }
    /// Interest of each leaf, in the order of `leaves()`.
    pub fn leaf_interests(&self) -> &[f64] {
        &self.leaf_interest
    }
    /// The smallest value of `leaf_interests()` (a scan's `fold(inf, f64::min)`).
    pub fn min_leaf_interest(&self) -> f64 {
        self.min_interest.0
    }

    /// Sum over leaves, in order, of |interest - min leaf interest| (the normaliser of eq. 3).
    pub fn interest_weight_total(&mut self) -> f64 {
        let n = self.leaves.len();
        let min = self.min_interest.0;
        self.weight_sums.resize(n + 1, 0.0);
        let from = self.sums_valid;
        let mut acc = self.weight_sums[from];
        for (s, i) in self.weight_sums[from + 1..].iter_mut().zip(&self.leaf_interest[from..]) {
            acc += (i - min).abs();
            *s = acc;
        }
        self.sums_valid = n;
        self.weight_sums[n]
    }
    /// Mean value of each leaf (NaN when it holds none), in the order of `leaves()`.
    pub fn leaf_means(&self) -> &[f64] {
        &self.leaf_mean
    }
    pub fn n_measurements(&self) -> usize {
        self.values.len()
    }
    pub fn point(&self, id: usize) -> &[f64] {
        &self.points[id * self.dim..(id + 1) * self.dim]
    }
    pub fn value(&self, id: usize) -> f64 {
        self.values[id]
    }
    pub fn low(&self) -> &[f64] {
        &self.regions[0].low
    }
    pub fn high(&self) -> &[f64] {
        &self.regions[0].high
    }

    /// The leaf containing `p` (coordinates outside the root box are clamped into it).
    pub fn leaf_of(&self, p: &[f64]) -> usize {
        let mut i = 0;
        while let Some([l, r]) = self.regions[i].children {
            let reg = &self.regions[i];
            i = if p[reg.split_dim] < reg.split_value { l } else { r };
        }
        i
    }

    /// Record a measurement at `p`; returns the leaf it went to (before any split) and whether
    /// that leaf was split (it is once it holds more than g_max measurements, unless they all
    /// sit at one point, where no cut can separate them).
    pub fn add(&mut self, p: &[f64], value: f64) -> (usize, bool) {
        let root = &self.regions[0];
        let start = self.points.len();
        self.points.extend(p.iter().zip(root.low.iter().zip(&root.high)).map(|(v, (lo, hi))| v.clamp(*lo, *hi)));
        let id = self.values.len() as u32;
        self.values.push(value);
        let leaf = self.leaf_of(&self.points[start..]);
        let zeta = self.cfg.zeta;
        {
            let reg = &mut self.regions[leaf];
            reg.entries.push(id);
            reg.sum += value;
        }
        self.refresh_interest(leaf, zeta);
        self.sync_leaf(leaf);
        let split = self.regions[leaf].entries.len() > self.cfg.g_max && self.split(leaf);
        (leaf, split)
    }

    fn sync_leaf(&mut self, leaf: usize) {
        let pos = self.leaf_pos[leaf];
        let old = self.leaf_interest[pos];
        self.leaf_interest[pos] = self.regions[leaf].interest;
        if old.to_bits() != self.leaf_interest[pos].to_bits() {
            self.sums_valid = self.sums_valid.min(pos);
        }
        self.leaf_mean[pos] = self.regions[leaf].mean().unwrap_or(f64::NAN);
        self.track_min(Some(old), Some(self.leaf_interest[pos]));
    }

    /// Update the minimum after a leaf interest `old` left and `new` arrived; scan again only
    /// when the last leaf at the minimum rose (or a NaN is involved).
    fn track_min(&mut self, old: Option<f64>, new: Option<f64>) {
        let (mut min, mut count) = self.min_interest;
        let nan = old.is_some_and(f64::is_nan) || new.is_some_and(f64::is_nan);
        if old == Some(min) {
            count -= 1;
        }
        if let Some(v) = new {
            if v < min {
                (min, count) = (v, 1);
            } else if v == min {
                count += 1;
            }
        }
        let before = self.min_interest.0;
        self.min_interest = if nan || count == 0 {
            let m = self.leaf_interest.iter().copied().fold(f64::INFINITY, f64::min);
            (m, self.leaf_interest.iter().filter(|&&v| v == m).count())
        } else {
            (min, count)
        };
        if before.to_bits() != self.min_interest.0.to_bits() {
            // Every weight moved with the minimum.
            self.sums_valid = 0;
        }
    }

    fn refresh_interest(&mut self, leaf: usize, zeta: usize) {
        let reg = &self.regions[leaf];
        let start = reg.entries.len().saturating_sub(self.cfg.divisor.window_len(zeta));
        self.window.clear();
        self.window.extend(reg.entries[start..].iter().map(|&e| self.values[e as usize]));
        self.regions[leaf].interest = interest(&self.window, zeta, self.cfg.divisor);
    }

    /// Choose the cut (dimension, position) that maximises |interest(left) - interest(right)|
    /// over the midpoints between consecutive distinct coordinates of the leaf's measurements,
    /// each child receiving at least `min_child` of them. Ties go to the most balanced cut.
    pub fn best_cut(&self, leaf: usize) -> Option<(usize, f64, f64)> {
        self.cuts().best(&self.regions[leaf].entries)
    }

    fn cuts(&self) -> Cuts<'_> {
        Cuts { points: &self.points, values: &self.values, dim: self.dim, zeta: self.cfg.zeta, min_child: self.cfg.min_child, divisor: self.cfg.divisor }
    }

    /// Split a leaf; false when no cut can separate its measurements.
    fn split(&mut self, leaf: usize) -> bool {
        // The best cut under the min_child rule; failing that, any cut between distinct
        // coordinates (most balanced). Measurements all at one point cannot be separated by any
        // cut, so such a leaf is left whole until a distinct measurement arrives.
        let entries = &self.regions[leaf].entries;
        let cut = self.cuts().best(entries).or_else(|| self.cuts().any(entries));
        let Some((dim, value, _)) = cut else {
            return false;
        };
        let created_at = self.values.len() as u64;
        let parent = &self.regions[leaf];
        let depth = parent.depth + 1;
        let mut lhigh = parent.high.clone();
        lhigh[dim] = value;
        let mut rlow = parent.low.clone();
        rlow[dim] = value;
        let mk = |low: Vec<f64>, high: Vec<f64>| Region {
            low,
            high,
            parent: Some(leaf),
            children: None,
            split_dim: 0,
            split_value: f64::NAN,
            entries: Vec::new(),
            interest: 0.0,
            sum: 0.0,
            created_at,
            depth,
        };
        let l = mk(parent.low.clone(), lhigh);
        let r = mk(rlow, parent.high.clone());
        let entries = std::mem::take(&mut self.regions[leaf].entries);
        let (li, ri) = (self.regions.len(), self.regions.len() + 1);
        self.regions.push(l);
        self.regions.push(r);
        for e in entries {
            let target = if self.points[e as usize * self.dim + dim] < value { li } else { ri };
            self.regions[target].entries.push(e);
            self.regions[target].sum += self.values[e as usize];
        }
        {
            let p = &mut self.regions[leaf];
            p.children = Some([li, ri]);
            p.split_dim = dim;
            p.split_value = value;
            p.sum = 0.0;
            p.interest = 0.0;
        }
        let zeta = self.cfg.zeta;
        self.refresh_interest(li, zeta);
        self.refresh_interest(ri, zeta);
        let pos = self.leaf_pos[leaf];
        self.sums_valid = self.sums_valid.min(pos);
        self.leaves.remove(pos);
        self.leaves.push(li);
        self.leaves.push(ri);
        self.leaf_pos.resize(self.regions.len(), usize::MAX);
        self.leaf_pos[leaf] = usize::MAX;
        for (i, &l) in self.leaves.iter().enumerate() {
            self.leaf_pos[l] = i;
        }
        let removed = self.leaf_interest.remove(pos);
        self.track_min(Some(removed), None);
        self.leaf_mean.remove(pos);
        self.leaf_interest.extend([0.0, 0.0]);
        self.track_min(None, Some(0.0));
        self.track_min(None, Some(0.0));
        self.leaf_mean.extend([f64::NAN, f64::NAN]);
        self.sync_leaf(li);
        self.sync_leaf(ri);
        true
    }
}

#[cfg(test)]
mod tests;

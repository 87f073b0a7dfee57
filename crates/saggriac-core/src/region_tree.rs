//! The region tree of R-IAC / SAGG-RIAC (paper II.D.3): a box that is split recursively; each
//! leaf keeps the values (competences) measured in it in time order, and its interest (eq. 2).
//! Works in any dimension: the goal space S' for SAGG-RIAC, (theta, dtheta) for ACTUATOR-RIAC.

use crate::error::{invalid, Check, Result};
use crate::interest::interest;

#[derive(Debug, Clone, Copy, PartialEq)]
pub struct RegionTreeConfig {
    /// A leaf holding more than g_max measurements is split.
    pub g_max: usize,
    /// Interest window (eq. 2).
    pub zeta: usize,
    /// Fewest measurements each child of a split must receive.
    pub min_child: usize,
}

impl Default for RegionTreeConfig {
    fn default() -> Self {
        RegionTreeConfig { g_max: 50, zeta: 20, min_child: 5 }
    }
}

impl RegionTreeConfig {
    pub fn validate(&self) -> Result<()> {
        let c = Check { owner: "RegionTree" };
        c.at_least("g_max", self.g_max, 2)?;
        c.at_least("zeta", self.zeta, 2)?;
        c.at_least("min_child", self.min_child, 1)?;
        if 2 * self.min_child > self.g_max + 1 {
            return Err(invalid("RegionTree", "min_child", format!("an int with 2 * min_child <= g_max + 1 (g_max = {})", self.g_max), self.min_child));
        }
        Ok(())
    }
}

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
        let start = reg.entries.len().saturating_sub(zeta);
        self.window.clear();
        self.window.extend(reg.entries[start..].iter().map(|&e| self.values[e as usize]));
        self.regions[leaf].interest = interest(&self.window, zeta);
    }

    /// Interest of the last zeta (in time order) of a leaf's measurements whose bit in `left`
    /// equals `side`; `vals` are their values in time order. Bits are read from the top, so the
    /// scan stops after zeta members without visiting the others.
    fn window_interest(&self, vals: &[f64], left: &[u64], side: bool, window: &mut Vec<f64>) -> f64 {
        let zeta = self.cfg.zeta;
        window.clear();
        'words: for w in (0..left.len()).rev() {
            let mut word = if side { left[w] } else { !left[w] };
            let tail = vals.len() - 64 * w;
            if tail < 64 {
                word &= (1u64 << tail) - 1;
            }
            while word != 0 && zeta > 0 {
                let b = 63 - word.leading_zeros() as usize;
                window.push(vals[64 * w + b]);
                if window.len() == zeta {
                    break 'words;
                }
                word &= !(1u64 << b);
            }
        }
        // `interest` of the window, read from its newest-first order: each half is summed
        // oldest first, as `interest` sums it.
        let w = window.len();
        let half = w / 2;
        if half == 0 {
            return 0.0;
        }
        let older: f64 = window[w - half..].iter().rev().sum();
        let newer: f64 = window[..half].iter().rev().sum();
        (older - newer).abs() / w as f64
    }

    /// Choose the cut (dimension, position) that maximises |interest(left) - interest(right)|
    /// over the midpoints between consecutive distinct coordinates of the leaf's measurements,
    /// each child receiving at least `min_child` of them. Ties go to the most balanced cut.
    pub fn best_cut(&self, leaf: usize) -> Option<(usize, f64, f64)> {
        let entries = &self.regions[leaf].entries;
        let n = entries.len();
        // (score, imbalance, dim, value)
        let mut best: Option<(f64, usize, usize, f64)> = None;
        // Positions in `entries`, which is in time order; a child's interest needs its last
        // zeta measurements in time order, read off a membership bitset from the top.
        let mut order: Vec<usize> = (0..n).collect();
        let mut cd = vec![0.0; n];
        // Membership of the left child as a bitset over positions.
        let mut left = vec![0u64; n.div_ceil(64)];
        let vals: Vec<f64> = entries.iter().map(|&e| self.values[e as usize]).collect();
        let mut window = Vec::with_capacity(self.cfg.zeta);
        let mc = self.cfg.min_child.max(1);
        let to_left = |left: &mut [u64], p: usize| left[p / 64] |= 1u64 << (p % 64);
        for d in 0..self.dim {
            cd.iter_mut().zip(entries).for_each(|(c, &e)| *c = self.points[e as usize * self.dim + d]);
            let coord = |p: usize| cd[p];
            // Positions break ties, so the order is total and an unstable sort gives it exactly.
            order.sort_unstable_by(|a, b| coord(*a).total_cmp(&coord(*b)).then(a.cmp(b)));
            left.iter_mut().for_each(|w| *w = 0);
            for &p in &order[..mc - 1] {
                to_left(&mut left, p);
            }
            for i in mc..=(n - mc) {
                to_left(&mut left, order[i - 1]);
                let (a, b) = (coord(order[i - 1]), coord(order[i]));
                if a == b {
                    continue;
                }
                let cut = midpoint(a, b);
                let il = self.window_interest(&vals, &left, true, &mut window);
                let ir = self.window_interest(&vals, &left, false, &mut window);
                let score = (il - ir).abs();
                let imbalance = (2 * i).abs_diff(n);
                let better = match best {
                    None => true,
                    Some((s, imb, _, _)) => score > s || (score == s && imbalance < imb),
                };
                if better {
                    best = Some((score, imbalance, d, cut));
                }
            }
        }
        best.map(|(s, _, d, v)| (d, v, s))
    }

    /// The most balanced cut between distinct coordinates, with no minimum per child.
    fn any_cut(&self, leaf: usize) -> Option<(usize, f64, f64)> {
        let entries = &self.regions[leaf].entries;
        let n = entries.len();
        let mut best: Option<(usize, usize, f64)> = None; // (imbalance, dim, value)
        for d in 0..self.dim {
            let mut v: Vec<f64> = entries.iter().map(|&e| self.points[e as usize * self.dim + d]).collect();
            v.sort_by(|a, b| a.total_cmp(b));
            for i in 1..n {
                if v[i - 1] != v[i] {
                    let imbalance = (2 * i).abs_diff(n);
                    if best.is_none_or(|(imb, _, _)| imbalance < imb) {
                        best = Some((imbalance, d, midpoint(v[i - 1], v[i])));
                    }
                }
            }
        }
        best.map(|(_, d, v)| (d, v, 0.0))
    }

    /// Split a leaf; false when no cut can separate its measurements.
    fn split(&mut self, leaf: usize) -> bool {
        // The best cut under the min_child rule; failing that, any cut between distinct
        // coordinates (most balanced). Measurements all at one point cannot be separated by any
        // cut, so such a leaf is left whole until a distinct measurement arrives.
        let cut = self.best_cut(leaf).or_else(|| self.any_cut(leaf));
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

/// A cut c with a < c <= b, so `x < c` sends a left and b right even when a and b are adjacent
/// floats (where the midpoint rounds onto a).
fn midpoint(a: f64, b: f64) -> f64 {
    let m = 0.5 * (a + b);
    if m > a && m <= b {
        m
    } else {
        b
    }
}

/// Bounds must be finite, of equal non-zero length, and strictly ordered.
pub(crate) fn check_bounds(owner: &'static str, low: &[f64], high: &[f64]) -> Result<()> {
    if low.is_empty() || low.len() != high.len() {
        return Err(invalid(owner, "bounds", format!("low and high of equal non-zero length (low has {})", low.len()), high.len()));
    }
    for (i, (l, h)) in low.iter().zip(high).enumerate() {
        if !(l.is_finite() && h.is_finite() && l < h) {
            return Err(invalid(owner, "bounds", format!("finite with low < high in every dimension (dimension {i}: low = {l})"), h));
        }
        // Goals are drawn as low + u * (high - low): the width itself must be a finite float.
        if !(h - l).is_finite() {
            return Err(invalid(owner, "bounds", format!("such that high - low is a finite float in every dimension (dimension {i}: low = {l:?})"), format!("{h:?}")));
        }
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::rng::{rng_from_seed, uniform};

    /// The tracked minimum and the draw's total weight equal a scan after every measurement,
    /// with ties (many leaves at the same interest: constant competences give interest exactly
    /// 0) and splits.
    #[test]
    fn min_interest_and_weight_total_match_a_scan_after_every_add() {
        for (seed, levels) in [(1u64, 0.0), (2, 4.0), (3, 1.0)] {
            let cfg = RegionTreeConfig { g_max: 8, zeta: 6, min_child: 2 };
            let mut t = RegionTree::new(&[0.0, 0.0], &[1.0, 1.0], cfg).unwrap();
            let mut r = rng_from_seed(seed);
            for i in 0..3000 {
                let p = [uniform(&mut r, 0.0, 1.0), uniform(&mut r, 0.0, 1.0)];
                // levels > 0: competences on a coarse grid, so equal interests are common.
                let c = -uniform(&mut r, 0.0, 1.0);
                let c = if levels > 0.0 {
                    (c * levels).round() / levels
                } else if p[0] < 0.5 {
                    -1.0
                } else {
                    c
                };
                t.add(&p, c);
                let scan = t.leaf_interests().iter().copied().fold(f64::INFINITY, f64::min);
                assert_eq!(t.min_leaf_interest().to_bits(), scan.to_bits(), "seed {seed}, add {i}");
                assert_eq!(t.min_interest.1, t.leaf_interests().iter().filter(|&&v| v == scan).count());
                // The draw's normaliser, asked after one to three changes, has a plain sum's bits.
                if i % 3 != 1 {
                    let plain: f64 = t.leaf_interests().iter().map(|v| (v - scan).abs()).sum();
                    assert_eq!(t.interest_weight_total().to_bits(), plain.to_bits(), "seed {seed}, add {i}");
                }
            }
            assert!(t.leaves().len() > 100);
        }
    }

    /// The cut search equals a direct reading of its definition: every midpoint between
    /// distinct coordinates, children's interests from their own time-ordered measurements.
    /// Leaves of up to 200 measurements cover bitsets of several words.
    #[test]
    fn best_cut_matches_its_definition() {
        let reference = |t: &RegionTree, leaf: usize| -> Option<(usize, f64, f64)> {
            let cfg = t.config();
            let entries = &t.region(leaf).entries;
            let n = entries.len();
            let mut best: Option<(f64, usize, usize, f64)> = None;
            for d in 0..t.dim() {
                let mut cs: Vec<f64> = entries.iter().map(|&e| t.point(e as usize)[d]).collect();
                cs.sort_by(f64::total_cmp);
                cs.dedup();
                for w in cs.windows(2) {
                    let cut = midpoint(w[0], w[1]);
                    let side = |left: bool| -> Vec<f64> { entries.iter().filter(|&&e| (t.point(e as usize)[d] < cut) == left).map(|&e| t.value(e as usize)).collect() };
                    let (l, r) = (side(true), side(false));
                    if l.len() < cfg.min_child.max(1) || r.len() < cfg.min_child.max(1) {
                        continue;
                    }
                    let score = (interest(&l, cfg.zeta) - interest(&r, cfg.zeta)).abs();
                    let imbalance = (2 * l.len()).abs_diff(n);
                    if best.is_none_or(|(s, imb, _, _)| score > s || (score == s && imbalance < imb)) {
                        best = Some((score, imbalance, d, cut));
                    }
                }
            }
            best.map(|(s, _, d, v)| (d, v, s))
        };
        let mut r = rng_from_seed(9);
        for (case, &(n, zeta, min_child, grid)) in
            [(10, 4, 1, 0.0), (63, 20, 5, 8.0), (64, 20, 5, 0.0), (65, 64, 3, 4.0), (130, 100, 5, 16.0), (200, 20, 1, 3.0), (200, 300, 5, 0.0)].iter().enumerate()
        {
            let cfg = RegionTreeConfig { g_max: 200, zeta, min_child };
            let mut t = RegionTree::new(&[0.0, 0.0, 0.0], &[1.0, 1.0, 1.0], cfg).unwrap();
            for _ in 0..n {
                // grid > 0: coarse coordinates and competences, so ties are common.
                let mut q = || {
                    let v = uniform(&mut r, 0.0, 1.0);
                    if grid > 0.0 {
                        (v * grid).floor() / grid
                    } else {
                        v
                    }
                };
                let p = [q(), q(), q()];
                t.add(&p, -q());
            }
            let (got, want) = (t.best_cut(0), reference(&t, 0));
            assert!(want.is_some(), "case {case}");
            assert_eq!(got.map(|(d, v, s)| (d, v.to_bits(), s.to_bits())), want.map(|(d, v, s)| (d, v.to_bits(), s.to_bits())), "case {case}");
        }
    }

    fn grow(n: usize, seed: u64) -> RegionTree {
        let mut t = RegionTree::new(&[0.0, -50.0], &[50.0, 50.0], RegionTreeConfig::default()).unwrap();
        let mut r = rng_from_seed(seed);
        for _ in 0..n {
            let p = [uniform(&mut r, 0.0, 50.0), uniform(&mut r, -50.0, 50.0)];
            // Competence good near the origin, bad far away: heterogeneous interest.
            let c = if p[0] < 20.0 { -uniform(&mut r, 0.0, 0.2) } else { -uniform(&mut r, 0.5, 1.0) };
            t.add(&p, c);
        }
        t
    }

    #[test]
    fn leaves_partition_the_space_and_hold_their_points() {
        let t = grow(3000, 1);
        let mut total = 0;
        for &l in t.leaves() {
            let reg = t.region(l);
            assert!(reg.is_leaf());
            assert!(reg.entries.len() <= t.config().g_max, "no leaf above g_max");
            for &e in &reg.entries {
                let p = t.point(e as usize);
                assert_eq!(t.leaf_of(p), l, "every point in exactly the leaf that contains it");
                for (d, v) in p.iter().enumerate() {
                    assert!(*v >= reg.low[d] && (*v < reg.high[d] || reg.high[d] == t.high()[d]));
                }
            }
            total += reg.entries.len();
        }
        assert_eq!(total, 3000);
        // The contiguous copies goal selection scans agree with the regions, bit for bit.
        for (i, &l) in t.leaves().iter().enumerate() {
            assert_eq!(t.leaf_interests()[i].to_bits(), t.region(l).interest.to_bits());
            let scan = t.leaf_interests().iter().copied().fold(f64::INFINITY, f64::min);
            assert_eq!(t.min_leaf_interest(), scan);
            assert_eq!(t.leaf_means()[i].to_bits(), t.region(l).mean().unwrap_or(f64::NAN).to_bits());
        }
        // Leaf volumes sum to the root volume, and a linear scan agrees with the descent.
        let vol: f64 = t.leaves().iter().map(|&l| (0..2).map(|d| t.region(l).high[d] - t.region(l).low[d]).product::<f64>()).sum();
        assert!((vol - 5000.0).abs() < 1e-6);
        let mut r = rng_from_seed(9);
        for _ in 0..1000 {
            let p = [uniform(&mut r, 0.0, 50.0), uniform(&mut r, -50.0, 50.0)];
            let scan: Vec<usize> = t.leaves().iter().copied().filter(|&l| (0..2).all(|d| p[d] >= t.region(l).low[d] && p[d] < t.region(l).high[d])).collect();
            assert_eq!(scan, vec![t.leaf_of(&p)]);
        }
    }

    #[test]
    fn splits_only_above_g_max() {
        let mut t = RegionTree::new(&[0.0], &[1.0], RegionTreeConfig { g_max: 10, zeta: 4, min_child: 2 }).unwrap();
        for i in 0..10 {
            let (_, split) = t.add(&[i as f64 / 10.0], -0.5);
            assert!(!split);
        }
        assert_eq!(t.leaves().len(), 1);
        let (_, split) = t.add(&[0.95], -0.5);
        assert!(split);
        assert_eq!(t.leaves().len(), 2);
    }

    #[test]
    fn cut_separates_progress_from_no_progress() {
        // Left half: competence improving over time; right half: constant. The cut must fall
        // between them.
        let mut t = RegionTree::new(&[0.0], &[1.0], RegionTreeConfig { g_max: 20, zeta: 10, min_child: 2 }).unwrap();
        for i in 0..21 {
            if i % 2 == 0 {
                t.add(&[0.1 + 0.01 * i as f64], -1.0 + 0.09 * i as f64);
            } else {
                t.add(&[0.7 + 0.01 * i as f64], -0.5);
            }
        }
        let root = t.region(0);
        assert!(root.split_value > 0.3 && root.split_value < 0.71, "cut at {}", root.split_value);
    }

    #[test]
    fn identical_points_wait_for_a_distinct_one() {
        let mut t = RegionTree::new(&[0.0, 0.0], &[1.0, 2.0], RegionTreeConfig { g_max: 5, zeta: 4, min_child: 3 }).unwrap();
        for _ in 0..20 {
            t.add(&[0.5, 0.5], -1.0);
        }
        // No cut can separate measurements at one point: no useless splits pile up.
        assert_eq!(t.leaves().len(), 1);
        // One distinct point: no cut gives both sides 3, but a cut exists and is taken.
        t.add(&[0.5, 1.5], -0.5);
        assert_eq!(t.leaves().len(), 2);
        assert_eq!((t.region(0).split_dim, t.region(0).split_value), (1, 1.0));
    }

    #[test]
    fn bad_bounds_and_parameters() {
        assert!(RegionTree::new(&[0.0], &[0.0], RegionTreeConfig::default()).is_err());
        let e = RegionTreeConfig { g_max: 1, zeta: 4, min_child: 1 }.validate().unwrap_err();
        assert_eq!(e.to_string(), "The 'g_max' parameter of RegionTree must be an int >= 2. Got 1 instead.");
    }
}

//! The cut search of the region tree (paper II.D.3): where to split a leaf so that the two
//! children differ most in interest. A function of the leaf's measurements only, kept apart
//! from the tree's bookkeeping.

use crate::high_level::interest::InterestDivisor;

/// The measurements of a tree (points row by row, values in time order) and its split rules.
pub struct Cuts<'a> {
    pub points: &'a [f64],
    pub values: &'a [f64],
    pub dim: usize,
    pub zeta: usize,
    pub min_child: usize,
    pub divisor: InterestDivisor,
}

impl Cuts<'_> {
    /// Interest of the last zeta (zeta + 1 when `Printed`), in time order, of a leaf's measurements whose bit in `left`
    /// equals `side`; `vals` are their values in time order. Bits are read from the top, so the
    /// scan stops after zeta members without visiting the others.
    fn window_interest(&self, vals: &[f64], left: &[u64], side: bool, window: &mut Vec<f64>) -> f64 {
        let zeta = self.zeta;
        let len = self.divisor.window_len(zeta);
        window.clear();
        'words: for w in (0..left.len()).rev() {
            let mut word = if side { left[w] } else { !left[w] };
            let tail = vals.len() - 64 * w;
            if tail < 64 {
                word &= (1u64 << tail) - 1;
            }
            while word != 0 && len > 0 {
                let b = 63 - word.leading_zeros() as usize;
                window.push(vals[64 * w + b]);
                if window.len() == len {
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
        (older - newer).abs() / self.divisor.of(w, zeta)
    }

    /// Choose the cut (dimension, position) that maximises |interest(left) - interest(right)|
    /// over the midpoints between consecutive distinct coordinates of the measurements `entries`
    /// (ids, in time order), each child receiving at least `min_child` of them. Ties go to the
    /// most balanced cut. Returns (dimension, position, score).
    pub fn best(&self, entries: &[u32]) -> Option<(usize, f64, f64)> {
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
        let mut window = Vec::with_capacity(self.zeta);
        let mc = self.min_child.max(1);
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
    pub fn any(&self, entries: &[u32]) -> Option<(usize, f64, f64)> {
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
}

/// A cut c with a < c <= b, so `x < c` sends a left and b right even when a and b are adjacent
/// floats (where the midpoint rounds onto a).
pub(crate) fn midpoint(a: f64, b: f64) -> f64 {
    let m = 0.5 * (a + b);
    if m > a && m <= b {
        m
    } else {
        b
    }
}

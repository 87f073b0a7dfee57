//! Property tests of the region tree: partition, split rule, interests.
//!
//! proptest chooses the shape of each case (sizes, dimensions, scales, adversarial modes, k);
//! bulk coordinates come from the crate's seeded generator with a proptest-chosen seed, which
//! keeps cases cheap to generate while the shape parameters still shrink.

mod common;

use proptest::prelude::*;

use common::{cases, TestResult};
use saggriac_core::high_level::interest::InterestDivisor;
use saggriac_core::high_level::region_tree::{RegionTree, RegionTreeConfig};
use saggriac_core::rng::{index, rng_from_seed, uniform, unit, CoreRng};

/// Bounds of one dimension: ordinary, tiny, huge, and far from zero with coarse float spacing.
fn interval() -> impl Strategy<Value = (f64, f64)> {
    prop_oneof![Just((0.0, 1.0)), Just((0.0, 1e-9)), Just((-1e12, 1e12)), Just((1e9, 1e9 + 1e-3)), (-100.0..100.0f64, 1e-6..1e3f64).prop_map(|(l, w)| (l, l + w)),]
}

fn divisor() -> impl Strategy<Value = InterestDivisor> {
    prop_oneof![Just(InterestDivisor::Zeta), Just(InterestDivisor::Window), Just(InterestDivisor::Printed)]
}

fn tree_config() -> impl Strategy<Value = RegionTreeConfig> {
    (2usize..=12, 2usize..=12, divisor())
        .prop_flat_map(|(g_max, zeta, divisor)| (Just(g_max), Just(zeta), 1usize..=g_max.div_ceil(2), Just(divisor)))
        .prop_map(|(g_max, zeta, min_child, divisor)| RegionTreeConfig { g_max, zeta, min_child, divisor })
}

/// Eq. 2 written out term by term, with the paper's 1-based time index j over a region's n
/// competences C_1..C_n. The window is the last m = min(n, zeta) of them, split into an older
/// half j = n-m+1 .. n-m+h and a newer half j = n-h+1 .. n with h = floor(m / 2) (an odd m
/// leaves its middle term out); the difference of the half-sums is divided by zeta as printed,
/// or by m under the `Window` reading. `Printed` takes the printed index ranges literally: the
/// window is the last min(n, zeta + 1) values (the middle one, in both sums, cancels).
fn eq2_by_hand(c: &[f64], zeta: usize, divisor: InterestDivisor) -> f64 {
    let n = c.len();
    let m = n.min(if divisor == InterestDivisor::Printed { zeta + 1 } else { zeta });
    let h = m / 2;
    if h == 0 {
        return 0.0;
    }
    let term = |j: usize| c[j - 1];
    let mut older = 0.0;
    for j in (n - m + 1)..=(n - m + h) {
        older += term(j);
    }
    let mut newer = 0.0;
    for j in (n - h + 1)..=n {
        newer += term(j);
    }
    let denominator = match divisor {
        InterestDivisor::Zeta | InterestDivisor::Printed => zeta as f64,
        InterestDivisor::Window => m as f64,
    };
    (older - newer).abs() / denominator
}

/// Equal up to rounding: the brute force and the tree may add the same terms in another order.
fn close(a: f64, b: f64, scale: f64) -> bool {
    (a - b).abs() <= 1e-12 * scale.max(1e-300)
}

/// The best cut score of a leaf by brute force: every axis-aligned cut between distinct
/// coordinates that gives each child at least min_child measurements, scored by eq. 2 by hand.
fn best_cut_by_hand(t: &RegionTree, leaf: usize) -> Option<f64> {
    let cfg = t.config();
    let entries = &t.region(leaf).entries;
    let mut best: Option<f64> = None;
    for d in 0..t.dim() {
        let mut cs: Vec<f64> = entries.iter().map(|&e| t.point(e as usize)[d]).collect();
        cs.sort_by(f64::total_cmp);
        cs.dedup();
        for w in cs.windows(2) {
            // Any cut strictly between two consecutive distinct coordinates parts them alike.
            let side = |left: bool| -> Vec<f64> { entries.iter().filter(|&&e| (t.point(e as usize)[d] <= w[0]) == left).map(|&e| t.value(e as usize)).collect() };
            let (l, r) = (side(true), side(false));
            if l.len() < cfg.min_child || r.len() < cfg.min_child {
                continue;
            }
            let score = (eq2_by_hand(&l, cfg.zeta, cfg.divisor) - eq2_by_hand(&r, cfg.zeta, cfg.divisor)).abs();
            best = Some(best.map_or(score, |b: f64| b.max(score)));
        }
    }
    best
}

/// How the measurement points are laid out, as fractions of the box in each dimension.
#[derive(Debug, Clone, Copy)]
enum Layout {
    /// Uniform in the box.
    Uniform,
    /// Every point identical.
    Identical,
    /// Coordinates on a coarse grid {0, 1/4, ..., 1}: many duplicates, faces of the box.
    Grid,
    /// Drawn from a handful of distinct points.
    Pool(usize),
    /// Partly outside the box (the tree clamps them onto its faces and corners).
    Outside,
}

fn layout() -> impl Strategy<Value = Layout> {
    prop_oneof![Just(Layout::Uniform), Just(Layout::Identical), Just(Layout::Grid), (1usize..5).prop_map(Layout::Pool), Just(Layout::Outside),]
}

/// How measurement values evolve.
#[derive(Debug, Clone, Copy)]
enum Values {
    /// Competences in [-1, 0].
    Competence,
    /// One constant value: every interest is 0, every cut ties.
    Constant,
    /// Large values of both signs.
    Wide,
}

fn values() -> impl Strategy<Value = Values> {
    prop_oneof![Just(Values::Competence), Just(Values::Constant), Just(Values::Wide)]
}

fn fractions(r: &mut CoreRng, layout: Layout, dim: usize, n: usize) -> Vec<Vec<f64>> {
    let grid = [0.0, 0.25, 0.5, 0.75, 1.0];
    let fixed: Vec<f64> = (0..dim).map(|_| unit(r)).collect();
    let pool: Vec<Vec<f64>> = (0..5).map(|_| (0..dim).map(|_| grid[index(r, grid.len())]).collect()).collect();
    (0..n)
        .map(|_| match layout {
            Layout::Uniform => (0..dim).map(|_| unit(r)).collect(),
            Layout::Identical => fixed.clone(),
            Layout::Grid => (0..dim).map(|_| grid[index(r, grid.len())]).collect(),
            Layout::Pool(k) => pool[index(r, k)].clone(),
            Layout::Outside => (0..dim).map(|_| uniform(r, -1.0, 2.0)).collect(),
        })
        .collect()
}

fn to_point(f: &[f64], low: &[f64], high: &[f64]) -> Vec<f64> {
    f.iter().zip(low.iter().zip(high)).map(|(f, (l, h))| l + f * (h - l)).collect()
}

fn value(r: &mut CoreRng, kind: Values) -> f64 {
    match kind {
        Values::Competence => -unit(r),
        Values::Constant => -0.5,
        Values::Wide => uniform(r, -1e6, 1e6),
    }
}

fn clamp_to(p: &[f64], low: &[f64], high: &[f64]) -> Vec<f64> {
    p.iter().zip(low.iter().zip(high)).map(|(v, (l, h))| v.clamp(*l, *h)).collect()
}

/// For every region and dimension: is the region's upper face the root's (closed) upper face?
/// A region's box is [low, high) in each dimension except where its upper bound was inherited
/// from the root without passing through the left side of a split on that dimension, where it
/// is [low, high]. Computed from the structure alone (parents are created before children).
fn closed_tops(t: &RegionTree) -> Vec<Vec<bool>> {
    let regions = t.regions();
    let mut closed = vec![vec![true; t.dim()]; regions.len()];
    for (i, r) in regions.iter().enumerate() {
        if let Some([a, b]) = r.children {
            assert!(a > i && b > i, "children are created after their parent");
            let mut left = closed[i].clone();
            left[r.split_dim] = false;
            closed[a] = left;
            closed[b] = closed[i].clone();
        }
    }
    closed
}

fn contains(t: &RegionTree, closed: &[Vec<bool>], leaf: usize, p: &[f64]) -> bool {
    let r = t.region(leaf);
    (0..t.dim()).all(|d| r.low[d] <= p[d] && (p[d] < r.high[d] || (closed[leaf][d] && p[d] == r.high[d])))
}

/// The leaves whose box holds `p`, by a linear scan.
fn scan(t: &RegionTree, closed: &[Vec<bool>], p: &[f64]) -> Vec<usize> {
    t.leaves().iter().copied().filter(|&l| contains(t, closed, l, p)).collect()
}

fn volume(low: &[f64], high: &[f64]) -> f64 {
    low.iter().zip(high).map(|(l, h)| h - l).product()
}

/// Largest number of entries held by a leaf.
fn fullest_leaf(t: &RegionTree) -> usize {
    t.leaves().iter().map(|&l| t.region(l).entries.len()).max().unwrap_or(0)
}

/// The g_max rule as the tree implements it: a leaf holding more than g_max measurements is
/// split, unless every one of its measurements sits at the same point (no cut can separate
/// them); then it waits, whole, for a distinct measurement.
fn check_g_max(t: &RegionTree, after: &str) -> TestResult {
    let g_max = t.config().g_max;
    for &l in t.leaves() {
        let r = t.region(l);
        if r.entries.len() > g_max {
            let first = t.point(r.entries[0] as usize).to_vec();
            prop_assert!(r.entries.iter().all(|&e| t.point(e as usize) == &first[..]), "leaf {} holds {} > g_max = {} entries {} that are not all at one point", l, r.entries.len(), g_max, after);
        }
    }
    Ok(())
}

/// After an add to a leaf that held `held` measurements: split iff it now holds more than g_max,
/// unless no cut can separate its measurements (all at one point).
fn check_split_rule(t: &RegionTree, leaf: usize, held: usize, split: bool) -> TestResult {
    if held + 1 > t.config().g_max {
        let es = &t.region(leaf).entries;
        let one_point = !split && es.iter().all(|&e| t.point(e as usize) == t.point(es[0] as usize));
        prop_assert!(split || one_point, "a leaf over g_max with distinct measurements was not split");
    } else {
        prop_assert!(!split, "split below g_max");
    }
    Ok(())
}

/// Some region has zero width in some dimension (a split fell on the region's face).
fn has_flat_region(t: &RegionTree) -> bool {
    t.regions().iter().any(|r| r.low.iter().zip(&r.high).any(|(l, h)| l >= h))
}

/// Every structural invariant of the tree.
fn check_tree(t: &RegionTree) -> TestResult {
    let regions = t.regions();
    let dim = t.dim();
    let (root_low, root_high) = (t.low(), t.high());

    // The leaf list is exactly the set of childless regions, without repeats.
    let mut listed = vec![false; regions.len()];
    for &l in t.leaves() {
        prop_assert!(!listed[l], "leaf {} listed twice", l);
        listed[l] = true;
    }
    for (i, r) in regions.iter().enumerate() {
        prop_assert_eq!(r.is_leaf(), listed[i], "region {} leaf status vs leaf list", i);
    }

    // Each split tiles its parent exactly: the children share the parent's box except on the
    // split dimension, where they meet at the split value.
    for (i, r) in regions.iter().enumerate() {
        let Some([a, b]) = r.children else { continue };
        let (d, v) = (r.split_dim, r.split_value);
        prop_assert!(d < dim);
        prop_assert!(r.low[d] <= v && v <= r.high[d], "split {} of region {} outside [{}, {}]", v, i, r.low[d], r.high[d]);
        prop_assert!(r.entries.is_empty(), "inner region {} holds entries", i);
        let (ra, rb) = (t.region(a), t.region(b));
        prop_assert_eq!(ra.parent, Some(i));
        prop_assert_eq!(rb.parent, Some(i));
        prop_assert_eq!(ra.depth, r.depth + 1);
        prop_assert_eq!(rb.depth, r.depth + 1);
        for e in 0..dim {
            prop_assert_eq!(ra.low[e], r.low[e]);
            prop_assert_eq!(rb.high[e], r.high[e]);
            if e == d {
                prop_assert_eq!(ra.high[e], v);
                prop_assert_eq!(rb.low[e], v);
            } else {
                prop_assert_eq!(ra.high[e], r.high[e]);
                prop_assert_eq!(rb.low[e], r.low[e]);
            }
        }
    }

    // The leaves' volumes add up to the root's.
    let root_vol = volume(root_low, root_high);
    let leaf_vol: f64 = t.leaves().iter().map(|&l| volume(&t.region(l).low, &t.region(l).high)).sum();
    prop_assert!((leaf_vol - root_vol).abs() <= 1e-9 * root_vol, "leaf volumes {} vs root volume {} ({} leaves)", leaf_vol, root_vol, t.leaves().len());

    // Every measurement sits in exactly one leaf, in time order; that leaf is the one leaf_of
    // finds and the only leaf a linear scan finds.
    let n = t.n_measurements();
    let mut owner = vec![usize::MAX; n];
    for &l in t.leaves() {
        let entries = &t.region(l).entries;
        prop_assert!(entries.windows(2).all(|w| w[0] < w[1]), "entries of leaf {} not in time order", l);
        for &e in entries {
            prop_assert!((e as usize) < n);
            prop_assert_eq!(owner[e as usize], usize::MAX, "measurement {} in two leaves", e);
            owner[e as usize] = l;
        }
        // Mean of the leaf (eq. 1) matches its entries.
        if let Some(m) = t.region(l).mean() {
            let vals: Vec<f64> = entries.iter().map(|&e| t.value(e as usize)).collect();
            let expect = vals.iter().sum::<f64>() / vals.len() as f64;
            let scale = vals.iter().fold(0.0f64, |s, v| s.max(v.abs()));
            prop_assert!((m - expect).abs() <= 1e-9 * scale.max(1e-300), "leaf {} mean {} vs {}", l, m, expect);
        } else {
            prop_assert!(entries.is_empty());
        }
        prop_assert!(t.region(l).interest >= 0.0 && t.region(l).interest.is_finite());
        // Eq. 2 by hand on the leaf's competences, in time order.
        let vals: Vec<f64> = entries.iter().map(|&e| t.value(e as usize)).collect();
        let scale = vals.iter().fold(0.0f64, |s, v| s.max(v.abs()));
        let by_hand = eq2_by_hand(&vals, t.config().zeta, t.config().divisor);
        prop_assert!(close(t.region(l).interest, by_hand, scale), "leaf {} interest {} vs eq. 2 by hand {}", l, t.region(l).interest, by_hand);
        // The cut search finds the best score by hand whenever a cut obeys min_child.
        if let Some(hand) = best_cut_by_hand(t, l) {
            let found = t.best_cut(l).map(|c| c.2);
            prop_assert!(found.is_some_and(|f| close(f, hand, scale)), "leaf {} best cut score {:?} vs by hand {}", l, found, hand);
        }
    }
    let closed = closed_tops(t);
    for (id, &l) in owner.iter().enumerate() {
        prop_assert!(l != usize::MAX, "measurement {} in no leaf", id);
        let p = t.point(id);
        for d in 0..dim {
            prop_assert!(root_low[d] <= p[d] && p[d] <= root_high[d], "stored point {:?} outside the root box", p);
        }
        prop_assert_eq!(t.leaf_of(p), l, "leaf_of disagrees with the leaf holding measurement {} at {:?}", id, p);
        prop_assert_eq!(scan(t, &closed, p), vec![l], "linear scan for measurement {} at {:?}", id, p);
    }
    Ok(())
}

fn tree_case(dim: usize) -> impl Strategy<Value = (Vec<(f64, f64)>, RegionTreeConfig, Layout, Values, usize)> {
    (prop::collection::vec(interval(), dim), tree_config(), layout(), values(), 0usize..250)
}

fn run_tree_case(bounds: &[(f64, f64)], cfg: RegionTreeConfig, layout: Layout, vals: Values, n: usize, seed: u64) -> TestResult {
    let dim = bounds.len();
    let low: Vec<f64> = bounds.iter().map(|b| b.0).collect();
    let high: Vec<f64> = bounds.iter().map(|b| b.1).collect();
    let mut t = RegionTree::new(&low, &high, cfg).expect("valid tree");
    let mut r = rng_from_seed(seed);
    for (i, f) in fractions(&mut r, layout, dim, n).iter().enumerate() {
        let p = to_point(f, &low, &high);
        let v = value(&mut r, vals);
        let before = t.leaf_of(&clamp_to(&p, &low, &high));
        let held = t.region(before).entries.len();
        let (leaf, split) = t.add(&p, v);
        prop_assert_eq!(leaf, before, "add reported another leaf than leaf_of");
        prop_assert_eq!(t.n_measurements(), i + 1);
        prop_assert_eq!(split, !t.region(leaf).is_leaf());
        check_split_rule(&t, leaf, held, split)?;
        check_g_max(&t, &format!("after add {i}"))?;
        if matches!(layout, Layout::Uniform) && !low.iter().zip(&high).any(|(l, h)| *l == 1e9 && *h == 1e9 + 1e-3) {
            // Points in general position always admit a valid cut.
            prop_assert!(fullest_leaf(&t) <= cfg.g_max, "a leaf holds {} > g_max = {} entries after add {}", fullest_leaf(&t), cfg.g_max, i);
        }
    }
    check_tree(&t)?;

    // Adversarial second phase: measurements exactly on every split plane and on the corners of
    // every leaf.
    let mut extra = Vec::new();
    for reg in t.regions() {
        if reg.children.is_some() {
            // On the split plane, at the low corner and at the high corner.
            let mut p = reg.low.clone();
            p[reg.split_dim] = reg.split_value;
            extra.push(p);
            let mut p = reg.high.clone();
            p[reg.split_dim] = reg.split_value;
            extra.push(p);
        } else {
            extra.push(reg.low.clone());
            extra.push(reg.high.clone());
        }
    }
    extra.truncate(300);
    for p in &extra {
        let v = value(&mut r, vals);
        let held = t.region(t.leaf_of(p)).entries.len();
        let (leaf, split) = t.add(p, v);
        check_split_rule(&t, leaf, held, split)?;
        check_g_max(&t, &format!("after adding {p:?}"))?;
    }
    check_tree(&t)?;

    // Arbitrary queries, inside and outside the box: leaf_of agrees with the scan (after
    // clamping, as documented).
    let closed = closed_tops(&t);
    for _ in 0..50 {
        let f: Vec<f64> = (0..dim).map(|_| uniform(&mut r, -0.5, 1.5)).collect();
        let p = to_point(&f, &low, &high);
        let pc = clamp_to(&p, &low, &high);
        let l = t.leaf_of(&pc);
        prop_assert_eq!(scan(&t, &closed, &pc), vec![l], "scan at {:?}", pc);
        if !has_flat_region(&t) {
            // "Coordinates outside the root box are clamped into it": true unless a split fell
            // exactly on the root's face (only after the degenerate splits above).
            prop_assert_eq!(t.leaf_of(&p), l, "leaf_of({:?}) differs from leaf_of of its clamped {:?}", p, pc);
        }
    }
    Ok(())
}

proptest! {
    #![proptest_config(cases(96))]

    #[test]
    fn region_tree_invariants_1d(case in tree_case(1), seed in any::<u64>()) {
        let (b, cfg, lay, vals, n) = case;
        run_tree_case(&b, cfg, lay, vals, n, seed)?;
    }

    #[test]
    fn region_tree_invariants_2d(case in tree_case(2), seed in any::<u64>()) {
        let (b, cfg, lay, vals, n) = case;
        run_tree_case(&b, cfg, lay, vals, n, seed)?;
    }

    #[test]
    fn region_tree_invariants_3d(case in tree_case(3), seed in any::<u64>()) {
        let (b, cfg, lay, vals, n) = case;
        run_tree_case(&b, cfg, lay, vals, n, seed)?;
    }
}

/// Measurements at one point cannot be separated: they stay in one leaf and no useless splits
/// pile up; the first distinct measurement lets the leaf split.
#[test]
fn identical_measurements_do_not_pile_up_splits() {
    let cfg = RegionTreeConfig::default();
    let mut t = RegionTree::new(&[0.0, -50.0], &[50.0, 50.0], cfg).unwrap();
    for i in 0..200 {
        t.add(&[50.0, 0.0], -0.5 - 1e-3 * i as f64);
    }
    assert_eq!(t.regions().len(), 1, "no split can separate measurements at one point");
    t.add(&[10.0, 0.0], -0.5);
    assert_eq!(t.leaves().len(), 2);
    assert!(t.leaves().iter().all(|&l| !t.region(l).entries.is_empty()));
}

/// A cut between two adjacent floats a < b: 0.5 * (a + b) rounds to a, so the cut must be taken
/// as b for `x < cut` to separate them.
#[test]
fn cut_between_adjacent_floats() {
    let cfg = RegionTreeConfig { g_max: 2, zeta: 2, min_child: 1, ..Default::default() };
    let mut t = RegionTree::new(&[0.0], &[1.0], cfg).unwrap();
    let a = 0.5f64;
    let b = f64::from_bits(a.to_bits() + 1);
    for (p, c) in [(a, -1.0), (b, -0.2), (b, -0.3)] {
        t.add(&[p], c);
    }
    let root = t.region(0);
    assert!(a < root.split_value && root.split_value <= b, "cut {:e} not in ({a:e}, {b:e}]", root.split_value);
    assert!(fullest_leaf(&t) <= cfg.g_max, "a leaf holds {} > g_max = {}", fullest_leaf(&t), cfg.g_max);
}

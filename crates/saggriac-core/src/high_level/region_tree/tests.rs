//! Unit tests of the region tree: its bookkeeping against scans, the cut search against its
//! definition, and the partition and split rules.

use super::cut::midpoint;
use super::*;
use crate::high_level::interest::InterestDivisor;
use crate::rng::{rng_from_seed, uniform};

/// The tracked minimum and the draw's total weight equal a scan after every measurement,
/// with ties (many leaves at the same interest: constant competences give interest exactly
/// 0) and splits.
#[test]
fn min_interest_and_weight_total_match_a_scan_after_every_add() {
    for (seed, levels) in [(1u64, 0.0), (2, 4.0), (3, 1.0)] {
        let cfg = RegionTreeConfig { g_max: 8, zeta: 6, min_child: 2, ..Default::default() };
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
                let score = (interest(&l, cfg.zeta, cfg.divisor) - interest(&r, cfg.zeta, cfg.divisor)).abs();
                let imbalance = (2 * l.len()).abs_diff(n);
                if best.is_none_or(|(s, imb, _, _)| score > s || (score == s && imbalance < imb)) {
                    best = Some((score, imbalance, d, cut));
                }
            }
        }
        best.map(|(s, _, d, v)| (d, v, s))
    };
    let cases = [(10, 4, 1, 0.0), (63, 20, 5, 8.0), (64, 20, 5, 0.0), (65, 64, 3, 4.0), (130, 100, 5, 16.0), (200, 20, 1, 3.0), (200, 300, 5, 0.0)];
    for divisor in [InterestDivisor::Zeta, InterestDivisor::Window] {
        let mut r = rng_from_seed(9);
        for (case, &(n, zeta, min_child, grid)) in cases.iter().enumerate() {
            let cfg = RegionTreeConfig { g_max: 200, zeta, min_child, divisor };
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
            assert_eq!(got.map(|(d, v, s)| (d, v.to_bits(), s.to_bits())), want.map(|(d, v, s)| (d, v.to_bits(), s.to_bits())), "case {case}, {divisor:?}");
        }
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
    let mut t = RegionTree::new(&[0.0], &[1.0], RegionTreeConfig { g_max: 10, zeta: 4, min_child: 2, ..Default::default() }).unwrap();
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
    let mut t = RegionTree::new(&[0.0], &[1.0], RegionTreeConfig { g_max: 20, zeta: 10, min_child: 2, ..Default::default() }).unwrap();
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
    let mut t = RegionTree::new(&[0.0, 0.0], &[1.0, 2.0], RegionTreeConfig { g_max: 5, zeta: 4, min_child: 3, ..Default::default() }).unwrap();
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
    let e = RegionTreeConfig { g_max: 1, zeta: 4, min_child: 1, ..Default::default() }.validate().unwrap_err();
    assert_eq!(e.to_string(), "The 'g_max' parameter of RegionTree must be an int in [2, 1000000]. Got 1 instead.");
}

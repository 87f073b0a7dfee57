//! The block index against the brute-force reference.

use super::*;
use crate::model::neighbours::reference::{assert_matches_brute, assert_warm_start_exact};
use crate::model::neighbours::BruteForce;
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

/// Points closer together than f32 can tell apart, far from the origin or near it: the f32
/// boxes and bounds collapse, and only the rounding margins of `Query::limit` keep the
/// answer exact.
#[test]
fn matches_brute_force_below_f32_resolution() {
    let mut r = rng_from_seed(8);
    for &(dim, centre, spread) in &[(15usize, 1.2345678, 1e-9), (15, 3.0e6, 1e-4), (3, -7.5e11, 30.0), (40, 1e-30, 1e-38), (2, 0.0, 1e-12)] {
        let pts: Vec<f64> = (0..900 * dim).map(|_| centre + spread * (uniform(&mut r, -1.0, 1.0) * 8.0).round()).collect();
        let mut qs: Vec<f64> = (0..20 * dim).map(|_| centre + spread * uniform(&mut r, -3.0, 3.0)).collect();
        qs.extend_from_slice(&pts[..dim]);
        for &k in &[1usize, 45, 300] {
            assert_matches_brute(&mut BlockIndex::new(dim), &pts, &qs, k);
        }
    }
}

/// A case the margin of `Query::limit` decides. The query c + 0.5 + e (c = 1000) rounds to
/// c + 0.5 in f32. The point at c + 1.5e (searched first: its group's box holds the query) is
/// at distance 0.5 - 0.5e; the point at c + 1, in the next group, is nearer (0.5 - e), yet
/// its f32 bound, 0.25, is above the first one's squared distance even in f32. Without the
/// margin for the query's rounding it would be skipped.
#[test]
fn the_rounding_margin_keeps_a_nearer_point() {
    let (c, e) = (1000.0, 1e-5);
    let mut pts = vec![c + 1.5 * e];
    pts.extend(std::iter::repeat_n(c + 10.0, BLOCK * FANOUT - 1));
    pts.push(c + 1.0);
    pts.extend(std::iter::repeat_n(c + 10.0, 40));
    let mut idx = BlockIndex::new(1);
    pts.iter().for_each(|p| idx.add(&[*p]));
    let mut out = Vec::new();
    idx.knn(&[c + 0.5 + e], 1, &mut out);
    assert_eq!(out[0].id as usize, BLOCK * FANOUT);
    assert_matches_brute(&mut BlockIndex::new(1), &pts, &[c + 0.5 + e, c + 0.5 - e, c + 0.5], 1);
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

//! The block index against the brute-force reference.

use super::*;
use crate::model::neighbours::reference::{assert_matches_brute, assert_warm_start_exact};
use crate::model::neighbours::{dist_sq, BruteForce};
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

/// For every query, the search with the exact k-th distance as its radius (the tightest bound
/// a warm start can give, so the f32 screen decides every block from the first) and the cold
/// search both return the full scan's answer.
fn assert_matches_brute_with_tight_radius(dim: usize, pts: &[f64], qs: &[f64], k: usize) {
    let mut idx = BlockIndex::new(dim);
    let mut bf = BruteForce::new(dim);
    for p in pts.chunks_exact(dim) {
        idx.add(p);
        bf.add(p);
    }
    let (mut a, mut b) = (Vec::new(), Vec::new());
    for q in qs.chunks_exact(dim) {
        bf.knn(q, k, &mut a);
        idx.knn(q, k, &mut b);
        assert_eq!(a, b, "cold, dim {dim}, q {q:?}");
        idx.knn_within(q, k, a.last().unwrap().dist_sq, &mut b);
        assert_eq!(a, b, "tight radius, dim {dim}, q {q:?}");
    }
}

/// The coordinate regimes of the screen's tests: (dim, centre, spread). Far from the origin, below
/// f32 resolution, tiny (subnormal in f32, or zero there), and huge (f32 squares overflow).
const REGIMES: [(usize, f64, f64); 9] =
    [(15, 1.2345678, 1e-9), (15, 3.0e6, 1e-4), (3, -7.5e11, 30.0), (40, 1e-30, 1e-38), (2, 0.0, 1e-12), (15, 1e-200, 1e-201), (15, 1e18, 1e10), (15, -1e30, 1e25), (15, 0.3, 0.5)];

/// The screen's promise, point by point: a point at computed distance t from the query passes the
/// f32 screen at `point_limit(t)`, whatever the coordinates (ties: every point of a block at t).
#[test]
fn the_screen_passes_every_point_within_the_bound() {
    let mut r = rng_from_seed(12);
    for &(dim, centre, spread) in &REGIMES {
        for trial in 0..200 {
            // Coarse offsets, so that repeated points and equal distances occur.
            let mut pts: Vec<Vec<f64>> = (0..BLOCK).map(|_| (0..dim).map(|_| centre + spread * (uniform(&mut r, -1.0, 1.0) * 6.0).round()).collect()).collect();
            pts[BLOCK - 1] = pts[0].clone();
            let q: Vec<f64> = if trial % 5 == 0 { pts[1].clone() } else { (0..dim).map(|_| centre + spread * uniform(&mut r, -2.0, 2.0)).collect() };
            let mut block = vec![0.0f32; dim * BLOCK];
            let mut rounding = 0.0f64;
            for (j, p) in pts.iter().enumerate() {
                for d in 0..dim {
                    block[d * BLOCK + j] = p[d] as f32;
                    rounding = rounding.max((p[d] - p[d] as f32 as f64).abs() * (dim as f64).sqrt() * (1.0 + 1e-12));
                }
            }
            let query = Query::new(&q, rounding);
            for p in &pts {
                let t = dist_sq(&q, p);
                let within = screen_full_block::<BLOCK>(&query.q32, &block, query.point_limit(t));
                for (j, o) in pts.iter().enumerate() {
                    if dist_sq(&q, o) <= t {
                        assert!(within & (1 << j) != 0, "centre {centre}, spread {spread}: point {j} at {} screened out at t = {t}", dist_sq(&q, o));
                    }
                }
            }
        }
    }
}

/// A case the stored points' rounding decides. The query c (c = 1000, exact in f32) is at
/// 1 - 3e-5 from p = c + 1 - 3e-5, whose f32 copy is c + 1: its screen sum, 1.0, is above
/// (1 - 3e-5)^2 even with the f32 rounding of the sum. Without `rounding` in `point_limit`,
/// a warm start bounded by that distance would lose its only neighbour.
#[test]
fn the_rounding_of_the_stored_points_keeps_a_neighbour() {
    let c = 1000.0;
    let p = c + 1.0 - 3e-5;
    assert_eq!(p as f32 as f64, c + 1.0);
    let mut pts = vec![p];
    pts.extend(std::iter::repeat_n(c + 10.0, 3 * BLOCK - 1));
    let mut idx = BlockIndex::new(1);
    pts.iter().for_each(|v| idx.add(&[*v]));
    let t = dist_sq(&[c], &[p]);
    let mut out = Vec::new();
    idx.knn_within(&[c], 1, t, &mut out);
    assert_eq!(out, vec![Neighbour { id: 0, dist_sq: t }]);
    assert_matches_brute_with_tight_radius(1, &pts, &[c, c + 0.5, p, c + 1.0], 1);
}

#[test]
fn matches_brute_force_with_huge_tiny_and_far_coordinates() {
    let mut r = rng_from_seed(13);
    for &(dim, centre, spread) in &REGIMES {
        let pts: Vec<f64> = (0..700 * dim).map(|_| centre + spread * (uniform(&mut r, -1.0, 1.0) * 8.0).round()).collect();
        let mut qs: Vec<f64> = (0..15 * dim).map(|_| centre + spread * uniform(&mut r, -3.0, 3.0)).collect();
        qs.extend_from_slice(&pts[5 * dim..6 * dim]);
        for &k in &[1usize, 45, 300] {
            assert_matches_brute_with_tight_radius(dim, &pts, &qs, k);
        }
    }
}

/// Coordinates beyond f32's range turn the screen off (their copies are infinite); a query out
/// there too. The answers stay the full scan's, before and after such a point arrives.
#[test]
fn coordinates_beyond_f32_range_turn_the_screen_off_and_stay_exact() {
    let dim = 15;
    let mut pts = trajectory(1500, dim, 0.05, 400, 14);
    let mut r = rng_from_seed(15);
    let mut qs: Vec<f64> = (0..10 * dim).map(|_| uniform(&mut r, -0.6, 0.6)).collect();
    qs.extend(std::iter::repeat_n(1e300, dim));
    assert_matches_brute_with_tight_radius(dim, &pts, &qs, 45);
    let mut far = vec![0.1; dim];
    far[3] = 1e39;
    pts.extend(&far);
    pts.extend(trajectory(300, dim, 0.05, 400, 16));
    assert_matches_brute_with_tight_radius(dim, &pts, &qs, 45);
}

//! Property tests of the exact neighbour indexes and the warm start against brute force.
//!
//! proptest chooses the shape of each case (sizes, dimensions, scales, adversarial modes, k);
//! bulk coordinates come from the crate's seeded generator with a proptest-chosen seed, which
//! keeps cases cheap to generate while the shape parameters still shrink.

mod common;

use proptest::prelude::*;

use common::cases;
use saggriac_core::model::block_index::BlockIndex;
use saggriac_core::model::kd_tree::KdTree;
use saggriac_core::model::memory::{IndexKind, SensorimotorMemory};
use saggriac_core::model::neighbours::{BruteForce, Neighbour, NeighbourIndex, WarmStart};
use saggriac_core::rng::{index, rng_from_seed, uniform, unit};

#[derive(Debug, Clone, Copy)]
enum Cloud {
    /// Uniform in [-1, 1]^dim.
    Uniform,
    /// Copies of a few points with coordinates in {-1, 0, 1}: exact duplicates and exact ties.
    Duplicates(usize),
    /// An arm-like random walk from the zero vector, back to it every `reset` points.
    Walk(usize),
}

fn cloud() -> impl Strategy<Value = Cloud> {
    prop_oneof![Just(Cloud::Uniform), (1usize..6).prop_map(Cloud::Duplicates), (1usize..60).prop_map(Cloud::Walk)]
}

fn make_cloud(kind: Cloud, n: usize, dim: usize, seed: u64) -> Vec<f64> {
    let mut r = rng_from_seed(seed);
    let grid = [-1.0, 0.0, 1.0];
    let pool: Vec<Vec<f64>> = (0..6).map(|_| (0..dim).map(|_| grid[index(&mut r, 3)]).collect()).collect();
    let mut theta = vec![0.0; dim];
    let mut pts = Vec::with_capacity(n * dim);
    for i in 0..n {
        match kind {
            Cloud::Uniform => pts.extend((0..dim).map(|_| uniform(&mut r, -1.0, 1.0))),
            Cloud::Duplicates(k) => pts.extend_from_slice(&pool[index(&mut r, k)]),
            Cloud::Walk(reset) => {
                if i % reset == 0 {
                    theta.iter_mut().for_each(|t| *t = 0.0);
                } else {
                    theta.iter_mut().for_each(|t| *t += uniform(&mut r, -0.05, 0.05));
                }
                pts.extend_from_slice(&theta);
            }
        }
    }
    pts
}

/// Queries: random points, stored points, the origin, and grid midpoints (equidistant from
/// several grid points, hence exact ties).
fn make_queries(pts: &[f64], dim: usize, count: usize, seed: u64) -> Vec<Vec<f64>> {
    let mut r = rng_from_seed(seed ^ 0x5151);
    let n = pts.len() / dim;
    let halves = [-1.0, -0.5, 0.0, 0.5, 1.0];
    (0..count)
        .map(|i| match i % 4 {
            0 => (0..dim).map(|_| uniform(&mut r, -1.2, 1.2)).collect(),
            1 if n > 0 => {
                let j = index(&mut r, n);
                pts[j * dim..(j + 1) * dim].to_vec()
            }
            2 => vec![0.0; dim],
            _ => (0..dim).map(|_| halves[index(&mut r, halves.len())]).collect(),
        })
        .collect()
}

fn key(v: &[Neighbour]) -> Vec<(u32, u64)> {
    v.iter().map(|n| (n.id, n.dist_sq.to_bits())).collect()
}

/// The arm's 15 joints, the task spaces (1-3), and any other size up to 100 joints.
fn dims() -> impl Strategy<Value = usize> {
    prop_oneof![Just(1usize), Just(2), Just(3), Just(15), 4usize..=100]
}

proptest! {
    #![proptest_config(cases(128))]

    #[test]
    fn indexes_equal_brute_force(
        dim in dims(),
        kind in cloud(),
        n in prop_oneof![4 => 0usize..300, 1 => 1000usize..1400],
        k in 0usize..70,
        seed in any::<u64>(),
    ) {
        let pts = make_cloud(kind, n, dim, seed);
        let mut bf = BruteForce::new(dim);
        // The episodic memory's k-d tree, the block index, and the memory's default index.
        let mut kd = KdTree::new(dim);
        let mut blocks = BlockIndex::new(dim);
        let mut mem = SensorimotorMemory::new(dim, 1, IndexKind::Blocks);
        let zeros = vec![0.0; dim];
        for p in pts.chunks_exact(dim) {
            bf.add(p);
            kd.add(p);
            blocks.add(p);
            prop_assert!(mem.add(p, &zeros, &[0.0], &[0.0]));
        }
        prop_assert_eq!(kd.len(), n);
        prop_assert_eq!(blocks.len(), n);
        prop_assert_eq!(mem.len(), n);
        let (mut a, mut b) = (Vec::new(), Vec::new());
        let mut r = rng_from_seed(seed ^ 0xabc);
        for q in make_queries(&pts, dim, 24, seed) {
            for kk in [k, n + 3, 1] {
                bf.knn(&q, kk, &mut a);
                kd.knn(&q, kk, &mut b);
                prop_assert_eq!(a.len(), kk.min(n));
                prop_assert!(a.windows(2).all(|w| (w[0].dist_sq, w[0].id) < (w[1].dist_sq, w[1].id)), "brute force not sorted by (distance, id)");
                prop_assert_eq!(key(&a), key(&b), "k-d tree knn k={} q={:?}", kk, q);
                blocks.knn(&q, kk, &mut b);
                prop_assert_eq!(key(&a), key(&b), "block index knn k={} q={:?}", kk, q);
                mem.knn(&q, kk, &mut b);
                prop_assert_eq!(key(&a), key(&b), "memory knn k={} q={:?}", kk, q);
            }
            // Radius-bounded search, the radius sometimes exactly a stored point's distance.
            let radius = if n > 0 && unit(&mut r) < 0.7 {
                let j = index(&mut r, n);
                saggriac_core::model::neighbours::dist_sq(&q, &pts[j * dim..(j + 1) * dim])
            } else {
                uniform(&mut r, 0.0, 2.0)
            };
            bf.knn_within(&q, k, radius, &mut a);
            kd.knn_within(&q, k, radius, &mut b);
            prop_assert!(a.iter().all(|nb| nb.dist_sq <= radius));
            prop_assert_eq!(key(&a), key(&b), "k-d tree knn_within k={} radius={} q={:?}", k, radius, q);
            blocks.knn_within(&q, k, radius, &mut b);
            prop_assert_eq!(key(&a), key(&b), "block index knn_within k={} radius={} q={:?}", k, radius, q);
        }
    }

}

proptest! {
    #![proptest_config(cases(64))]

    #[test]
    fn warm_start_equals_brute_force_along_a_trajectory(
        dim in dims(),
        k in 1usize..60,
        recent in 0usize..12,
        steps in prop_oneof![5 => 1usize..350, 1 => 900usize..1300],
        reset_every in 1usize..120,
        step_size in prop_oneof![Just(0.0), 1e-4..0.1f64],
        clear_on_reset in any::<bool>(),
        jump_every in prop_oneof![Just(usize::MAX), 3usize..100],
        seed in any::<u64>(),
    ) {
        let mut r = rng_from_seed(seed);
        let mut bf = BruteForce::new(dim);
        let mut blocks = BlockIndex::new(dim);
        // Warm start over the block index, and over the brute-force index itself.
        let mut ws_blocks = WarmStart::new(recent);
        let mut ws_bf = WarmStart::new(recent);
        // And over the memory's default index.
        let mut mem = SensorimotorMemory::new(dim, 1, IndexKind::Blocks);
        let mut ws_mem = WarmStart::new(recent);
        let fixed: Vec<f64> = (0..dim).map(|_| uniform(&mut r, -0.5, 0.5)).collect();
        let mut since: (Vec<Neighbour>, usize) = (Vec::new(), 0);
        let zeros = vec![0.0; dim];
        let mut theta = vec![0.0; dim];
        let (mut a, mut b, mut c) = (Vec::new(), Vec::new(), Vec::new());
        for step in 0..steps {
            if step % reset_every == 0 {
                theta.iter_mut().for_each(|t| *t = 0.0);
                if clear_on_reset {
                    ws_blocks.clear();
                    ws_bf.clear();
                    ws_mem.clear();
                }
            } else if step % jump_every == 0 {
                // A jump the warm start is not told about: its previous neighbours are stale
                // but still a valid bound.
                theta.iter_mut().for_each(|t| *t = uniform(&mut r, -1.0, 1.0));
            } else {
                theta.iter_mut().for_each(|t| *t += uniform(&mut r, -step_size, step_size));
            }
            bf.knn(&theta, k, &mut a);
            ws_blocks.knn(&blocks, &theta, k, &mut b);
            ws_bf.knn(&bf, &theta, k, &mut c);
            prop_assert_eq!(a.len(), k.min(step));
            prop_assert_eq!(key(&a), key(&b), "warm start over the block index, step {}", step);
            prop_assert_eq!(key(&a), key(&c), "warm start over brute force, step {}", step);
            mem.knn_warm(&mut ws_mem, &theta, k, &mut c);
            prop_assert_eq!(key(&a), key(&c), "warm start over the memory's index, step {}", step);
            // A fixed query kept up to date as the memory grows (the evaluation's predictions).
            if step % 7 == 0 {
                bf.knn(&fixed, k, &mut a);
                mem.knn_since(&fixed, k, &mut since.0, &mut since.1);
                prop_assert_eq!(key(&a), key(&since.0), "knn_since, step {}", step);
            }
            mem.add(&theta, &zeros, &[0.0], &[0.0]);
            bf.add(&theta);
            blocks.add(&theta);
        }
    }
}

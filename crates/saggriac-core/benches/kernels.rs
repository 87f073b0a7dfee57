//! Micro-benchmarks of the kernels of the hot loop:
//!
//! * `knn_10k`, `knn_200k`: exact 45-NN over 15-D arm-like data (a random walk in joint space
//!   that returns to the zero rest pose every few hundred steps, storing the rest pose a few
//!   times at each return, so the data hold many exact duplicates). Queries walk along a
//!   stretch of the stored trajectory, in order, as the learner's queries do. Variants: the
//!   full scan, our k-d tree (`kd_tree.rs`, the episodic memory's index) searched cold, and
//!   the memory's default index (`IndexKind::Blocks`, whatever type backs it), cold and
//!   warm-started along the query trajectory (`WarmStart`).
//! * `local_model`: `LocalModel::fit` + `inverse` with k = 45 neighbours of a 15-joint arm.
//! * `region_tree`: `RegionTree::add` of 2-D goals with heterogeneous competence.
//! * `arm`: `Arm::forward` of a 15-joint arm.
//!
//! Data sets are built once per group. Run: `cargo bench -p saggriac-core`, or quicker:
//! `cargo bench -p saggriac-core -- --warm-up-time 0.5 --measurement-time 2`.

use std::hint::black_box;
use std::time::Duration;

use criterion::{criterion_group, criterion_main, BatchSize, Criterion, Throughput};

use saggriac_core::body::arm::{Arm, ArmConfig};
use saggriac_core::high_level::region_tree::{RegionTree, RegionTreeConfig};
use saggriac_core::model::kd_tree::KdTree;
use saggriac_core::model::local_model::{LocalModel, LocalModelConfig};
use saggriac_core::model::memory::{IndexKind, SensorimotorMemory};
use saggriac_core::model::neighbours::{BruteForce, Neighbour, NeighbourIndex, WarmStart};
use saggriac_core::rng::{index, rng_from_seed, uniform, CoreRng};

const DIM: usize = 15;
const K: usize = 45;
/// Queries cycled through by each kNN benchmark.
const N_QUERIES: usize = 2_000;

/// `n` arm-like joint configurations, stored row by row.
fn arm_walk(n: usize, seed: u64) -> Vec<f64> {
    let mut r = rng_from_seed(seed);
    let mut theta = [0.0f64; DIM];
    let mut pts = Vec::with_capacity((n + 8) * DIM);
    let mut until_reset = 0usize;
    while pts.len() < n * DIM {
        if until_reset == 0 {
            // Back to rest; the rest pose is stored once per attempt started there.
            theta = [0.0; DIM];
            for _ in 0..1 + index(&mut r, 4) {
                pts.extend_from_slice(&theta);
            }
            until_reset = 100 + index(&mut r, 300);
        }
        until_reset -= 1;
        // Mostly reaching steps; now and then tiny exploration moves.
        let s = if index(&mut r, 10) == 0 { 0.01 } else { 0.05 };
        for t in theta.iter_mut() {
            *t = (*t + uniform(&mut r, -s, s)).clamp(-std::f64::consts::FRAC_PI_2, std::f64::consts::FRAC_PI_2);
        }
        pts.extend_from_slice(&theta);
    }
    pts.truncate(n * DIM);
    pts
}

/// Queries as the learner makes them: the configurations of a stretch of the stored walk, in
/// order (so the stretch's past lies in the data, and it passes through rest poses), each moved
/// by less than a micro-action so that no query coincides with a stored point.
fn queries_along(pts: &[f64], n_queries: usize, seed: u64) -> Vec<f64> {
    let n = pts.len() / DIM;
    let start = n / 2;
    let mut r = rng_from_seed(seed);
    (start..start + n_queries.min(n - start)).flat_map(|i| pts[i * DIM..(i + 1) * DIM].to_vec()).map(|v| v + uniform(&mut r, -0.005, 0.005)).collect()
}

/// Cycles through the queries in order, clearing the warm start when it wraps around (a jump).
struct QueryCycle<'a> {
    queries: &'a [f64],
    next: usize,
}

impl<'a> QueryCycle<'a> {
    fn new(queries: &'a [f64]) -> Self {
        QueryCycle { queries, next: 0 }
    }
    fn next(&mut self, ws: Option<&mut WarmStart>) -> &'a [f64] {
        if self.next * DIM >= self.queries.len() {
            self.next = 0;
            if let Some(ws) = ws {
                ws.clear();
            }
        }
        let q = &self.queries[self.next * DIM..(self.next + 1) * DIM];
        self.next += 1;
        q
    }
}

fn bench_knn(c: &mut Criterion, n: usize) {
    let pts = arm_walk(n, 42);
    let queries = queries_along(&pts, N_QUERIES, 43);
    let mut bf = BruteForce::new(DIM);
    let mut kd = KdTree::new(DIM);
    let mut mem = SensorimotorMemory::new(DIM, 2, IndexKind::Blocks);
    let zeros = [0.0; DIM];
    for p in pts.chunks_exact(DIM) {
        bf.add(p);
        kd.add(p);
        mem.add(p, &zeros, &[0.0, 0.0], &[0.0, 0.0]);
    }
    let mut group = c.benchmark_group(format!("knn_{}k", n / 1000));
    group.throughput(Throughput::Elements(1));
    if n > 50_000 {
        // A full scan of 200k points takes milliseconds: keep the sample count low.
        group.sample_size(10);
    }
    let mut out: Vec<Neighbour> = Vec::with_capacity(K + 1);

    group.bench_function("brute_force", |b| {
        let mut qs = QueryCycle::new(&queries);
        b.iter(|| {
            bf.knn(black_box(qs.next(None)), K, &mut out);
            black_box(out.len())
        })
    });
    group.bench_function("kdtree_cold", |b| {
        let mut qs = QueryCycle::new(&queries);
        b.iter(|| {
            kd.knn(black_box(qs.next(None)), K, &mut out);
            black_box(out.len())
        })
    });
    group.bench_function("memory_default_cold", |b| {
        let mut qs = QueryCycle::new(&queries);
        b.iter(|| {
            mem.knn(black_box(qs.next(None)), K, &mut out);
            black_box(out.len())
        })
    });
    group.bench_function("memory_default_warm", |b| {
        let mut qs = QueryCycle::new(&queries);
        let mut ws = WarmStart::new(8);
        b.iter(|| {
            let q = qs.next(Some(&mut ws));
            mem.knn_warm(&mut ws, black_box(q), K, &mut out);
            black_box(out.len())
        })
    });
    group.finish();
}

fn knn_10k(c: &mut Criterion) {
    bench_knn(c, 10_000);
}

fn knn_200k(c: &mut Criterion) {
    bench_knn(c, 200_000);
}

/// A memory filled by a real 15-joint arm doing the arm-like walk, and the 45-NN lists of
/// configurations along the walk's continuation.
fn arm_memory(n: usize, n_queries: usize) -> (SensorimotorMemory, Vec<Vec<Neighbour>>) {
    let cfg = ArmConfig::uniform(DIM, 50.0, std::f64::consts::FRAC_PI_2, 0.05);
    let mut arm = Arm::new(cfg).unwrap();
    let pts = arm_walk(n + 1, 7);
    let queries = queries_along(&pts, n_queries, 8);
    let mut mem = SensorimotorMemory::new(DIM, 2, IndexKind::BruteForce);
    let mut dtheta = [0.0; DIM];
    for w in pts.chunks_exact(DIM).collect::<Vec<_>>().windows(2) {
        arm.set_theta(w[0]);
        let theta = arm.theta().to_vec();
        let x = arm.position();
        for (d, (a, b)) in dtheta.iter_mut().zip(w[1].iter().zip(w[0])) {
            *d = a - b;
        }
        let dx = arm.step(&mut dtheta);
        mem.add(&theta, &dtheta, &dx, &x);
    }
    let mut lists = Vec::with_capacity(n_queries);
    let mut out = Vec::new();
    for q in queries.chunks_exact(DIM) {
        mem.knn(q, K, &mut out);
        lists.push(out.clone());
    }
    (mem, lists)
}

fn local_model(c: &mut Criterion) {
    let (mem, lists) = arm_memory(10_000, 200);
    let mut model = LocalModel::new(DIM, 2, LocalModelConfig { k_neighbours: K, ..LocalModelConfig::default() });
    let mut dtheta = [0.0; DIM];
    let mut group = c.benchmark_group("local_model");
    group.throughput(Throughput::Elements(1));
    group.bench_function("fit_k45_n15", |b| {
        let mut i = 0;
        b.iter(|| {
            i = (i + 1) % lists.len();
            black_box(model.fit(&mem, black_box(&lists[i])).is_ok())
        })
    });
    group.bench_function("fit_inverse_k45_n15", |b| {
        let mut i = 0;
        b.iter(|| {
            i = (i + 1) % lists.len();
            let ok = model.fit(&mem, black_box(&lists[i])).and_then(|_| model.inverse(black_box(&[0.3, -0.4]), &mut dtheta)).is_ok();
            black_box((ok, dtheta[0]))
        })
    });
    group.finish();
}

fn region_tree(c: &mut Criterion) {
    const N: usize = 2_000;
    let mut r: CoreRng = rng_from_seed(3);
    let goals: Vec<([f64; 2], f64)> = (0..N)
        .map(|_| {
            let p = [uniform(&mut r, 0.0, 50.0), uniform(&mut r, -50.0, 50.0)];
            // Competence good near the base, poor far from it: heterogeneous interest.
            let c = if p[0] < 20.0 { -uniform(&mut r, 0.0, 0.2) } else { -uniform(&mut r, 0.5, 1.0) };
            (p, c)
        })
        .collect();
    let mut group = c.benchmark_group("region_tree");
    group.throughput(Throughput::Elements(N as u64));
    group.bench_function("add_2000_goals_2d", |b| {
        b.iter_batched(
            || RegionTree::new(&[0.0, -50.0], &[50.0, 50.0], RegionTreeConfig::default()).unwrap(),
            |mut t| {
                for (p, c) in &goals {
                    black_box(t.add(black_box(p), *c));
                }
                t
            },
            BatchSize::SmallInput,
        )
    });
    group.finish();
}

fn arm(c: &mut Criterion) {
    let arm = Arm::new(ArmConfig::uniform(DIM, 50.0, std::f64::consts::FRAC_PI_2, 0.05)).unwrap();
    let mut r = rng_from_seed(5);
    let thetas: Vec<[f64; DIM]> = (0..1024).map(|_| std::array::from_fn(|_| uniform(&mut r, -1.5, 1.5))).collect();
    let mut group = c.benchmark_group("arm");
    group.throughput(Throughput::Elements(1));
    group.bench_function("forward_15_joints", |b| {
        let mut i = 0;
        b.iter(|| {
            i = (i + 1) & 1023;
            black_box(arm.forward(black_box(&thetas[i])))
        })
    });
    group.finish();
}

criterion_group! {
    name = benches;
    config = Criterion::default().warm_up_time(Duration::from_secs(1)).measurement_time(Duration::from_secs(3));
    targets = knn_10k, knn_200k, local_model, region_tree, arm
}
criterion_main!(benches);

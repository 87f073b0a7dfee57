//! Time kNN queries on the memory of a real run: `cargo run --release --example knn_probe`.
use saggriac_core::kd_tree::KdTree;
use saggriac_core::neighbours::{BruteForce, KdTreeIndex, NeighbourIndex, WarmStart};
use saggriac_core::{Learner, RunConfig};

fn main() {
    let mut cfg = RunConfig { n_steps: std::env::args().nth(1).and_then(|s| s.parse().ok()).unwrap_or(50_000), ..RunConfig::default() };
    if std::env::args().nth(2).as_deref() == Some("exp2") {
        cfg.goal_low = vec![0.0, -150.0];
        cfg.goal_high = vec![150.0, 150.0];
        cfg.exploration.q = 100;
    }
    cfg.eval.schedule = vec![cfg.n_steps];
    cfg.eval.n_test_goals = 1;
    cfg.eval.n_test_configs = 1;
    let mut l = Learner::new(cfg, 0, 1).unwrap();
    l.run(&mut |_| true);
    let mem = l.memory();
    let n = mem.len();
    let dim = mem.n_joints();
    let pts: Vec<f64> = (0..n).flat_map(|i| mem.theta(i).to_vec()).collect();
    let mut bf = BruteForce::new(dim);
    let mut ours = KdTree::new(dim);
    let mut crate_ = KdTreeIndex::new(dim);
    for p in pts.chunks_exact(dim) {
        bf.add(p);
        ours.add(p);
        crate_.add(p);
    }
    // Queries along the stored trajectory (as the controller sees them).
    let mode = std::env::args().nth(3).unwrap_or_default();
    let zero = vec![0.0; dim];
    let mut rest_walk = Vec::new();
    let mut t = vec![0.0; dim];
    for i in 0..2000 {
        if i % 50 == 0 {
            t.iter_mut().for_each(|v| *v = 0.0);
        }
        t[i % dim] += 0.003;
        rest_walk.extend_from_slice(&t);
    }
    let qs: Vec<&[f64]> = match mode.as_str() {
        "rest" => (0..2000).map(|_| &zero[..]).collect(),
        "restwalk" => rest_walk.chunks_exact(dim).collect(),
        _ => (n / 2..n / 2 + 2000).map(|i| &pts[i * dim..(i + 1) * dim]).collect(),
    };
    let mut out = Vec::new();
    for (name, idx) in [("brute", &bf as &dyn NeighbourIndex), ("ours", &ours), ("crate", &crate_)] {
        let t = std::time::Instant::now();
        for q in &qs {
            idx.knn(q, 45, &mut out);
        }
        let cold = t.elapsed().as_secs_f64() / qs.len() as f64 * 1e6;
        let mut ws = WarmStart::new(8);
        let t = std::time::Instant::now();
        for q in &qs {
            ws.knn(idx, &pts, q, 45, &mut out);
        }
        let warm = t.elapsed().as_secs_f64() / qs.len() as f64 * 1e6;
        println!("{name:6} n={n} cold {cold:8.1} us  warm {warm:8.1} us  kth dist {:.4}", out.last().unwrap().dist_sq.sqrt());
    }
}

//! The block index and the brute-force reference answering the same recorded evaluation queries
//! of an exp2 memory (warm-started, as the evaluation asks them), checked equal, timed side by
//! side ("blocks" as the fourth argument: the block index alone, for profiling).
//!
//!     cargo run --release -p saggriac-core --example index_probe -- [steps] [condition] [repeats] [blocks]
#[path = "probe_setup/mod.rs"]
mod probe_setup;
use saggriac_core::config::Condition;
use saggriac_core::model::block_index::BlockIndex;
use saggriac_core::model::neighbours::{BruteForce, Neighbour, NeighbourIndex, PointIndex, WarmStart};

fn main() {
    let args: Vec<String> = std::env::args().collect();
    let steps: u64 = args.get(1).and_then(|s| s.parse().ok()).unwrap_or(200_000);
    let cond = Condition::parse(args.get(2).map(|s| s.as_str()).unwrap_or("actuator_random")).unwrap();
    let repeats: usize = args.get(3).and_then(|s| s.parse().ok()).unwrap_or(3);
    let blocks_only = args.get(4).map(|s| s == "blocks").unwrap_or(false);
    let (cfg, l) = probe_setup::exp2_learner(steps, cond);
    let mem = l.memory();
    let n = mem.n_joints();
    let k = cfg.local.k_neighbours;
    // Record the queries of 100 test reaches (what one evaluation asks).
    let mut queries: Vec<(bool, Vec<f64>)> = Vec::new();
    probe_setup::replay_test_reaches(&cfg, mem, 100, |fresh, th, _| queries.push((fresh, th.to_vec())));
    let [thetas, ..] = mem.arrays();
    let thetas = &thetas;
    let mut tree = BruteForce::new(n);
    let mut blocks = BlockIndex::new(n);
    for p in thetas.chunks_exact(n) {
        tree.add(p);
        blocks.add(p);
    }
    let replay = |index: &dyn PointIndex, answers: &mut Vec<Vec<Neighbour>>| {
        let mut ws = WarmStart::new(cfg.warm_start_recent);
        let mut out = Vec::new();
        answers.clear();
        let t0 = std::time::Instant::now();
        for (fresh, q) in &queries {
            if *fresh {
                ws.clear();
            }
            ws.knn(index, q, k, &mut out);
            answers.push(out.clone());
        }
        t0.elapsed().as_secs_f64() / queries.len() as f64 * 1e6
    };
    let (mut a, mut b) = (Vec::new(), Vec::new());
    let mut times = (Vec::new(), Vec::new());
    for _ in 0..repeats {
        if !blocks_only {
            times.0.push(replay(&tree, &mut a));
        }
        times.1.push(replay(&blocks, &mut b));
    }
    if blocks_only {
        println!("{} samples, {} queries: blocks {:.1} us per query", mem.len(), queries.len(), times.1.iter().cloned().fold(f64::INFINITY, f64::min));
        return;
    }
    assert_eq!(a, b, "the indexes disagree");
    let med = |v: &mut Vec<f64>| {
        v.sort_by(|x, y| x.total_cmp(y));
        v[v.len() / 2]
    };
    let (t, bl) = (med(&mut times.0), med(&mut times.1));
    println!("{} samples, {} queries, condition {}: brute force {t:.1} us, blocks {bl:.1} us per query ({:.2}x); same answers", mem.len(), queries.len(), cond.name(), t / bl);
    println!("block index: {:.1} bytes per point", blocks.bytes_per_point());
}

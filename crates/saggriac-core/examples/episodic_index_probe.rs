//! Which index suits the episodic memory: the k-d tree or the block index, on movements that come
//! in no useful order (the explauto preset's: reached positions in a disk of radius 50, whole
//! configurations in +-pi), answering the inverse model's 1-NN over x and the refinement's
//! 20-NN over theta. Both are checked against each other.
//!
//!     cargo run --release -p saggriac-core --example episodic_index_probe -- [movements] [queries]
use saggriac_core::model::block_index::BlockIndex;
use saggriac_core::model::kd_tree::KdTree;
use saggriac_core::model::neighbours::{Neighbour, NeighbourIndex};
use saggriac_core::rng::{rng_from_seed, uniform};

fn time(index: &dyn NeighbourIndex, queries: &[Vec<f64>], k: usize, out: &mut Vec<Vec<Neighbour>>) -> f64 {
    out.clear();
    let mut nb = Vec::new();
    let t0 = std::time::Instant::now();
    for q in queries {
        index.knn(q, k, &mut nb);
        out.push(nb.clone());
    }
    t0.elapsed().as_secs_f64() / queries.len() as f64 * 1e6
}

fn main() {
    let args: Vec<String> = std::env::args().collect();
    let n: usize = args.get(1).and_then(|s| s.parse().ok()).unwrap_or(50_000);
    let nq: usize = args.get(2).and_then(|s| s.parse().ok()).unwrap_or(5_000);
    let mut r = rng_from_seed(4);
    for (dim, scale, k) in [(2usize, 50.0, 1usize), (15, std::f64::consts::PI, 20)] {
        let (mut tree, mut blocks) = (KdTree::new(dim), BlockIndex::new(dim));
        for _ in 0..n {
            let p: Vec<f64> = (0..dim).map(|_| uniform(&mut r, -scale, scale)).collect();
            tree.add(&p);
            blocks.add(&p);
        }
        let queries: Vec<Vec<f64>> = (0..nq).map(|_| (0..dim).map(|_| uniform(&mut r, -scale, scale)).collect()).collect();
        let (mut a, mut b) = (Vec::new(), Vec::new());
        let (mut ta, mut tb) = (f64::INFINITY, f64::INFINITY);
        for _ in 0..3 {
            ta = ta.min(time(&tree, &queries, k, &mut a));
            tb = tb.min(time(&blocks, &queries, k, &mut b));
        }
        assert_eq!(a, b, "the indexes disagree");
        println!("{n} movements, {dim}-D, {k}-NN: k-d tree {ta:.2} us, blocks {tb:.2} us per query (best of 3); same answers");
    }
}

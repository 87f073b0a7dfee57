//! What an exact search of the evaluation must visit, by brute force: the memory's identical
//! points, and for the queries of the first 20 test reaches (warm-started, as the evaluation
//! asks them) the points within the final k-th distance T, the blocks of 16 holding them, the
//! blocks and groups of 128 whose exact boxes reach within T (no box search can skip those),
//! the blocks that a ball or a capsule around each block, or all three bounds, cannot skip, the
//! leaves whose boxes reach within T when the memory is regrouped in space (a static k-d
//! partition, leaves of 16), and the blocks of 4, 8, 32 and 64 consecutive samples whose boxes
//! reach within T. (Blocks of 16 are the probe's fixed unit, whatever the index's own size.)
//!
//!     cargo run --release -p saggriac-core --example search_probe -- exp1|exp2 CONDITION
#[path = "probe_setup/mod.rs"]
mod probe_setup;
use saggriac_core::config::Condition;
use saggriac_core::model::neighbours::dist_sq;
use saggriac_core::{Learner, RunConfig};
use std::collections::HashMap;

fn main() {
    let args: Vec<String> = std::env::args().collect();
    let exp = args[1].as_str();
    let cond = Condition::parse(&args[2]).unwrap();
    let (cfg, l) = if exp == "exp2" {
        probe_setup::exp2_learner(200_000, cond)
    } else {
        let mut cfg = RunConfig { condition: cond, ..RunConfig::default() };
        cfg.eval.schedule = vec![cfg.n_steps];
        cfg.eval.n_test_goals = 1;
        cfg.eval.n_test_configs = 1;
        let mut l = Learner::new(cfg.clone(), 0, 1).unwrap();
        l.run(&mut |_| true);
        (cfg, l)
    };
    let mem = l.memory();
    let n = mem.n_joints();
    let [thetas, ..] = mem.arrays();
    let npts = thetas.len() / n;
    let mut seen: HashMap<Vec<u64>, usize> = HashMap::new();
    let mut dup = vec![false; npts];
    for (i, p) in thetas.chunks_exact(n).enumerate() {
        let key: Vec<u64> = p.iter().map(|v| v.to_bits()).collect();
        let c = seen.entry(key).or_insert(0);
        if *c > 0 {
            dup[i] = true;
        }
        *c += 1;
    }
    let maxm = seen.values().max().unwrap();
    let ndup = dup.iter().filter(|&&d| d).count();
    println!("{exp} {}: {npts} points, {} distinct, {ndup} duplicates, largest multiplicity {maxm}", cond.name(), seen.len());
    let (mut nq, mut in_t, mut in_t_dup, mut blocks_pts, mut blocks_box, mut l1_box, mut blocks_dup_only) = (0usize, 0usize, 0usize, 0usize, 0usize, 0usize, 0usize);
    let (mut blocks_ball, mut blocks_capsule, mut blocks_both) = (0usize, 0usize, 0usize);
    let (mut leaves_box, mut leaves_pts) = (0usize, 0usize);
    let sizes = [4usize, 8, 32, 64];
    let mut by_size = [0usize; 4];
    let leaves = SpatialLeaves::new(&thetas, n, 16);
    let shapes: Vec<Shapes> = (0..npts.div_ceil(16)).map(|b| Shapes::new(&thetas, n, b * 16..((b + 1) * 16).min(npts))).collect();
    let mut d = vec![0.0; npts];
    probe_setup::replay_test_reaches(&cfg, mem, 20, |_, th, nb| {
        let t = nb.last().unwrap().dist_sq;
        nq += 1;
        // Every distance, then what each block and group of 128 holds and reaches.
        {
            for (j, p) in thetas.chunks_exact(n).enumerate() {
                d[j] = dist_sq(&th, p);
            }
            for b in 0..npts.div_ceil(16) {
                let r = b * 16..((b + 1) * 16).min(npts);
                let c = r.clone().filter(|&j| d[j] <= t).count();
                let cd = r.clone().filter(|&j| d[j] <= t && dup[j]).count();
                in_t += c;
                in_t_dup += cd;
                if c > 0 {
                    blocks_pts += 1;
                    if c == cd {
                        blocks_dup_only += 1;
                    }
                }
                let boxd = box_dist_sq(&thetas, n, r, &th);
                if boxd <= t {
                    blocks_box += 1;
                }
                let (ball, capsule) = shapes[b].bounds(&th);
                blocks_ball += usize::from(ball <= t);
                blocks_capsule += usize::from(capsule <= t);
                blocks_both += usize::from(boxd.max(ball).max(capsule) <= t);
            }
            for (c, &sz) in by_size.iter_mut().zip(&sizes) {
                *c += (0..npts.div_ceil(sz)).filter(|b| box_dist_sq(&thetas, n, b * sz..((b + 1) * sz).min(npts), &th) <= t).count();
            }
            for (lo, hi, members) in leaves.iter() {
                leaves_box += usize::from(leaves.box_dist_sq(lo, hi, &th) <= t);
                leaves_pts += usize::from(members.iter().any(|&j| d[j] <= t));
            }
            for b in 0..npts.div_ceil(128) {
                let r = b * 128..((b + 1) * 128).min(npts);
                if box_dist_sq(&thetas, n, r, &th) <= t {
                    l1_box += 1;
                }
            }
        }
    });
    let f = |x: usize| x as f64 / nq as f64;
    println!(
        "{nq} queries (first 20 test reaches): per query points within T {:.1} (dups {:.1}); blocks with such points {:.1} (dup-only {:.1}); blocks whose box is within T {:.1} of {}; level-1 boxes within T {:.1} of {}",
        f(in_t),
        f(in_t_dup),
        f(blocks_pts),
        f(blocks_dup_only),
        f(blocks_box),
        npts.div_ceil(16),
        f(l1_box),
        npts.div_ceil(128)
    );
    println!(
        "blocks within T by other bounds: ball {:.1}, capsule (segment first..last + radius) {:.1}, the largest of box, ball and capsule {:.1}",
        f(blocks_ball),
        f(blocks_capsule),
        f(blocks_both)
    );
    println!(
        "the same memory regrouped in space (median splits on the widest joint down to {} leaves of at most 16): leaves whose box is within T {:.1}, leaves holding points within T {:.1}",
        leaves.ranges.len(),
        f(leaves_box),
        f(leaves_pts)
    );
    for (c, sz) in by_size.iter().zip(sizes) {
        println!("blocks of {sz} consecutive samples whose box is within T: {:.1} ({:.0} points to rank)", f(*c), f(*c) * sz as f64);
    }
}

/// The memory grouped by space rather than by time: median splits on the joint of widest spread
/// until at most `leaf` points remain, each leaf with its exact box (a static k-d partition).
struct SpatialLeaves {
    n: usize,
    order: Vec<usize>,
    ranges: Vec<std::ops::Range<usize>>,
    boxes: Vec<f64>,
}

impl SpatialLeaves {
    fn new(thetas: &[f64], n: usize, leaf: usize) -> Self {
        let npts = thetas.len() / n;
        let mut order: Vec<usize> = (0..npts).collect();
        let mut ranges = Vec::new();
        let mut stack = vec![0..npts];
        while let Some(r) = stack.pop() {
            if r.len() <= leaf {
                ranges.push(r);
                continue;
            }
            let idx = &mut order[r.clone()];
            let spread = |d: usize| {
                let (lo, hi) = idx.iter().fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), &j| (lo.min(thetas[j * n + d]), hi.max(thetas[j * n + d])));
                hi - lo
            };
            let dim = (0..n).max_by(|&a, &b| spread(a).total_cmp(&spread(b))).unwrap();
            let mid = idx.len() / 2;
            idx.select_nth_unstable_by(mid, |&a, &b| thetas[a * n + dim].total_cmp(&thetas[b * n + dim]));
            stack.push(r.start..r.start + mid);
            stack.push(r.start + mid..r.end);
        }
        let mut boxes = Vec::with_capacity(ranges.len() * 2 * n);
        for r in &ranges {
            for d in 0..n {
                boxes.push(order[r.clone()].iter().map(|&j| thetas[j * n + d]).fold(f64::INFINITY, f64::min));
            }
            for d in 0..n {
                boxes.push(order[r.clone()].iter().map(|&j| thetas[j * n + d]).fold(f64::NEG_INFINITY, f64::max));
            }
        }
        SpatialLeaves { n, order, ranges, boxes }
    }

    fn iter(&self) -> impl Iterator<Item = (&[f64], &[f64], &[usize])> + '_ {
        self.ranges.iter().enumerate().map(|(i, r)| {
            let b = &self.boxes[i * 2 * self.n..(i + 1) * 2 * self.n];
            (&b[..self.n], &b[self.n..], &self.order[r.clone()])
        })
    }

    fn box_dist_sq(&self, lo: &[f64], hi: &[f64], q: &[f64]) -> f64 {
        (0..self.n).map(|d| (lo[d] - q[d]).max(0.0) + (q[d] - hi[d]).max(0.0)).map(|g| g * g).sum()
    }
}

/// A block's ball (centre = mean, radius = farthest point) and capsule (the segment from its
/// first to its last point, radius = farthest point from that segment).
struct Shapes {
    centre: Vec<f64>,
    ball_r: f64,
    a: Vec<f64>,
    ab: Vec<f64>,
    ab2: f64,
    cap_r: f64,
}

impl Shapes {
    fn new(thetas: &[f64], n: usize, r: std::ops::Range<usize>) -> Self {
        let pts: Vec<&[f64]> = r.map(|j| &thetas[j * n..(j + 1) * n]).collect();
        let centre: Vec<f64> = (0..n).map(|d| pts.iter().map(|p| p[d]).sum::<f64>() / pts.len() as f64).collect();
        let ball_r = pts.iter().map(|p| dist_sq(p, &centre).sqrt()).fold(0.0, f64::max);
        let a = pts[0].to_vec();
        let ab: Vec<f64> = (0..n).map(|d| pts[pts.len() - 1][d] - a[d]).collect();
        let ab2: f64 = ab.iter().map(|v| v * v).sum();
        let mut s = Shapes { centre, ball_r, a, ab, ab2, cap_r: 0.0 };
        s.cap_r = pts.iter().map(|p| s.segment_dist(p)).fold(0.0, f64::max);
        s
    }

    fn segment_dist(&self, q: &[f64]) -> f64 {
        let t = if self.ab2 > 0.0 { (q.iter().zip(&self.a).zip(&self.ab).map(|((q, a), ab)| (q - a) * ab).sum::<f64>() / self.ab2).clamp(0.0, 1.0) } else { 0.0 };
        q.iter().zip(&self.a).zip(&self.ab).map(|((q, a), ab)| (q - a - t * ab) * (q - a - t * ab)).sum::<f64>().sqrt()
    }

    /// Lower bounds of the squared distance from q to any point of the block.
    fn bounds(&self, q: &[f64]) -> (f64, f64) {
        let ball = (dist_sq(q, &self.centre).sqrt() - self.ball_r).max(0.0);
        let capsule = (self.segment_dist(q) - self.cap_r).max(0.0);
        (ball * ball, capsule * capsule)
    }
}

/// Squared distance from q to the exact bounding box of points `r` (rows of `n` in `thetas`).
fn box_dist_sq(thetas: &[f64], n: usize, r: std::ops::Range<usize>, q: &[f64]) -> f64 {
    let mut s = 0.0;
    for d in 0..n {
        let lo = r.clone().map(|j| thetas[j * n + d]).fold(f64::INFINITY, f64::min);
        let hi = r.clone().map(|j| thetas[j * n + d]).fold(f64::NEG_INFINITY, f64::max);
        let gap = (lo - q[d]).max(0.0) + (q[d] - hi).max(0.0);
        s += gap * gap;
    }
    s
}

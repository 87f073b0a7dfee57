//! Bytes per stored sample of the sensorimotor memory (arrays + block index), from the process's
//! resident memory: `cargo run --release --example memory_probe -- [samples] [joints]`.
use saggriac_core::model::memory::{IndexKind, SensorimotorMemory};
use saggriac_core::rng::{rng_from_seed, uniform};

fn rss_bytes() -> u64 {
    let s = std::fs::read_to_string("/proc/self/statm").unwrap_or_default();
    let pages: u64 = s.split_whitespace().nth(1).and_then(|v| v.parse().ok()).unwrap_or(0);
    pages * 4096
}

fn main() {
    let args: Vec<String> = std::env::args().collect();
    let n_samples: usize = args.get(1).and_then(|s| s.parse().ok()).unwrap_or(1_000_000);
    let n: usize = args.get(2).and_then(|s| s.parse().ok()).unwrap_or(15);
    let mut rng = rng_from_seed(1);
    let before = rss_bytes();
    let mut mem = SensorimotorMemory::new(n, 2, IndexKind::Blocks);
    // A random walk with returns to rest, like the learner's trajectories.
    let mut theta = vec![0.0; n];
    let mut d = vec![0.0; n];
    let t0 = std::time::Instant::now();
    for i in 0..n_samples {
        if i % 342 == 0 {
            theta.iter_mut().for_each(|t| *t = 0.0);
        }
        d.iter_mut().for_each(|v| *v = uniform(&mut rng, -0.01, 0.01));
        mem.add(&theta, &d, &[0.1, 0.2], &[1.0, 2.0]);
        theta.iter_mut().zip(&d).for_each(|(t, v)| *t += v);
    }
    let secs = t0.elapsed().as_secs_f64();
    let after = rss_bytes();
    let per = (after - before) as f64 / n_samples as f64;
    println!(
        "{n_samples} samples, {n} joints: resident memory +{:.1} MB, {per:.0} bytes per sample ({} of payload; the rest is the index's boxes, spare room and allocator overhead); inserts {:.2} us each",
        (after - before) as f64 / 1e6,
        mem.sample_bytes(),
        secs / n_samples as f64 * 1e6
    );
    let mut out = Vec::new();
    mem.knn(&theta, 45, &mut out);
    assert_eq!(out.len(), 45);
}

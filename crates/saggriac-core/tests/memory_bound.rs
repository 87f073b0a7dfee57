//! The memory bound of docs/performance.md, checked in CI on a smaller memory (its own test
//! binary, so no other test allocates meanwhile): at n = 15 a stored sample, arrays and the block
//! index together, takes at most 360 bytes of resident memory (300 until issue 49 item 2 added the
//! index's f32 copy of the points, 60 bytes). benchmarks/bench_memory.py checks
//! it at 1,000,000 samples.

use saggriac_core::model::memory::{IndexKind, SensorimotorMemory};
use saggriac_core::rng::{rng_from_seed, uniform};

fn rss_bytes() -> Option<u64> {
    let s = std::fs::read_to_string("/proc/self/statm").ok()?;
    let pages: u64 = s.split_whitespace().nth(1)?.parse().ok()?;
    Some(pages * 4096)
}

#[test]
fn bytes_per_sample_stay_within_the_bound() {
    let Some(before) = rss_bytes() else {
        eprintln!("no /proc/self/statm on this system: skipped");
        return;
    };
    let (n, samples) = (15, 300_000);
    let mut mem = SensorimotorMemory::new(n, 2, IndexKind::Blocks);
    let mut rng = rng_from_seed(3);
    let mut theta = vec![0.0; n];
    let mut d = vec![0.0; n];
    for i in 0..samples {
        if i % 342 == 0 {
            theta.iter_mut().for_each(|t| *t = 0.0);
        }
        d.iter_mut().for_each(|v| *v = uniform(&mut rng, -0.01, 0.01));
        assert!(mem.add(&theta, &d, &[0.1, 0.2], &[1.0, 2.0]));
        theta.iter_mut().zip(&d).for_each(|(t, v)| *t += v);
    }
    let per = (rss_bytes().unwrap() - before) as f64 / samples as f64;
    assert!(per <= 360.0, "{per:.0} bytes per sample, above the bound of 360");
    assert!(per >= mem.sample_bytes() as f64, "{per:.0} bytes per sample cannot be below the arrays' {}", mem.sample_bytes());
    assert_eq!(mem.len(), samples);
}

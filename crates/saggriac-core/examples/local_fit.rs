//! Time `LocalModel::fit` (and fit + inverse) with k = 45 neighbours of a 15-joint arm, and print
//! a digest of the bits of every Jacobian and pseudo-inverse step, so that two builds can be
//! compared for speed and for identical results:
//! `cargo run --release --example local_fit -- [repeats]`.
//!
//! Each repeat times one pass over all neighbour lists; the median and the minimum over repeats
//! are printed (the minimum is the least disturbed by other load on the machine).

use std::hint::black_box;
use std::time::Instant;

use saggriac_core::body::arm::{Arm, ArmConfig};
use saggriac_core::model::local_model::{LocalModel, LocalModelConfig};
use saggriac_core::model::memory::{IndexKind, SensorimotorMemory};
use saggriac_core::model::neighbours::Neighbour;
use saggriac_core::rng::{rng_from_seed, uniform};

const N: usize = 15;
const K: usize = 45;

/// A memory filled by a random walk of the arm (returning to rest now and then), and the 45-NN
/// lists of configurations near the walk.
fn data(n_samples: usize, n_lists: usize) -> (SensorimotorMemory, Vec<Vec<Neighbour>>) {
    let mut arm = Arm::new(ArmConfig::uniform(N, 50.0, std::f64::consts::FRAC_PI_2, 0.05)).unwrap();
    let mut mem = SensorimotorMemory::new(N, 2, IndexKind::BruteForce);
    let mut r = rng_from_seed(11);
    let mut stored = Vec::with_capacity(n_samples);
    for i in 0..n_samples {
        if i % 300 == 0 {
            arm.set_theta(&[0.0; N]);
        }
        let theta = arm.theta().to_vec();
        let x = arm.position();
        let mut dtheta: Vec<f64> = (0..N).map(|_| uniform(&mut r, -0.05, 0.05)).collect();
        let dx = arm.step(&mut dtheta);
        mem.add(&theta, &dtheta, &dx, &x);
        stored.push(theta);
    }
    let mut lists = Vec::with_capacity(n_lists);
    let mut out = Vec::new();
    for q in stored.iter().step_by(n_samples / n_lists).take(n_lists) {
        let q: Vec<f64> = q.iter().map(|v| v + uniform(&mut r, -0.005, 0.005)).collect();
        mem.knn(&q, K, &mut out);
        lists.push(out.clone());
    }
    (mem, lists)
}

fn digest(h: &mut u64, values: &[f64]) {
    for v in values {
        *h = (*h ^ v.to_bits()).wrapping_mul(0x100_0000_01b3);
    }
}

fn median(v: &mut [f64]) -> f64 {
    v.sort_by(f64::total_cmp);
    v[v.len() / 2]
}

fn main() {
    let repeats: usize = std::env::args().nth(1).and_then(|s| s.parse().ok()).unwrap_or(200);
    let (mem, lists) = data(10_000, 200);
    let mut model = LocalModel::new(N, 2, LocalModelConfig { k_neighbours: K, ..LocalModelConfig::default() });
    let mut dtheta = [0.0; N];

    let (mut h, mut ok) = (0xcbf2_9ce4_8422_2325u64, 0usize);
    for (i, nb) in lists.iter().enumerate() {
        if model.fit(&mem, nb).is_ok() {
            digest(&mut h, model.jacobian().as_slice());
            let dx = [0.3 * (i as f64).cos(), -0.4 * (i as f64).sin()];
            if model.inverse(&dx, &mut dtheta).is_ok() {
                digest(&mut h, &dtheta);
                ok += 1;
            }
        }
    }
    println!("digest {h:016x} over {ok} of {} fits", lists.len());

    let (mut fit, mut both) = (Vec::with_capacity(repeats), Vec::with_capacity(repeats));
    for _ in 0..repeats {
        let t = Instant::now();
        for nb in &lists {
            black_box(model.fit(&mem, black_box(nb)).is_ok());
        }
        fit.push(t.elapsed().as_secs_f64() * 1e6 / lists.len() as f64);
        let t = Instant::now();
        for nb in &lists {
            let r = model.fit(&mem, black_box(nb)).and_then(|_| model.inverse(black_box(&[0.3, -0.4]), &mut dtheta));
            black_box((r.is_ok(), dtheta[0]));
        }
        both.push(t.elapsed().as_secs_f64() * 1e6 / lists.len() as f64);
    }
    let (fit_min, both_min) = (fit.iter().cloned().fold(f64::INFINITY, f64::min), both.iter().cloned().fold(f64::INFINITY, f64::min));
    println!("fit          median {:.3} us  min {:.3} us", median(&mut fit), fit_min);
    println!("fit+inverse  median {:.3} us  min {:.3} us", median(&mut both), both_min);
}

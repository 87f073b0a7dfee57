//! Where a mixture refit starts to gain from threads (issue 49 item 4): the wall time of
//! `best_by_aic_on` with k = 2..=10 on one thread and on two, for samples of uniform noise in
//! [0, 1]^d, n samples. `cargo run --release -p saggriac-core --example refit_threads_probe --
//! [repeats]`. Prints the median of each and their ratio; the crossover sets
//! `refit_threads::MIN_PARALLEL_SAMPLES`.

use std::time::Instant;

use nalgebra::DVector;
use saggriac_core::high_level::teachers::gmm::{best_by_aic_on, EmConfig};
use saggriac_core::rng::{rng_from_seed, unit};

fn median(mut v: Vec<f64>) -> f64 {
    v.sort_by(f64::total_cmp);
    v[v.len() / 2]
}

fn main() {
    let repeats: usize = std::env::args().nth(1).map_or(7, |a| a.parse().expect("repeats: a whole number"));
    let ks: Vec<usize> = (2..=10).collect();
    println!("n d n*d^2 one_thread_us two_threads_us one/two");
    for d in [3, 4, 11, 12] {
        for n in [12, 25, 50, 100, 150, 200, 250, 400] {
            let mut rng = rng_from_seed(5);
            let data: Vec<DVector<f64>> = (0..n).map(|_| DVector::from_iterator(d, (0..d).map(|_| unit(&mut rng)))).collect();
            let mut times = [Vec::new(), Vec::new()];
            for _ in 0..repeats {
                for (t, threads) in [1, 2].into_iter().enumerate() {
                    let mut r = rng_from_seed(9);
                    let t0 = Instant::now();
                    std::hint::black_box(best_by_aic_on(&data, &ks, EmConfig::default(), &mut r, threads));
                    times[t].push(t0.elapsed().as_secs_f64() * 1e6);
                }
            }
            let (one, two) = (median(times[0].clone()), median(times[1].clone()));
            println!("{n} {d} {} {one:.0} {two:.0} {:.2}", n * d * d, one / two);
        }
    }
}

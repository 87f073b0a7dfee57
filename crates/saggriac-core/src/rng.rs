//! Explicitly seeded randomness. No global or OS-entropy generator exists in the core: every
//! component owns a generator built from a u64 that the caller derived from the run's root seed.

use rand::RngExt;
use rand_xoshiro::rand_core::SeedableRng;
pub use rand_xoshiro::Xoshiro256PlusPlus as CoreRng;

/// A generator from an explicit seed (SplitMix64 expansion inside `seed_from_u64`).
pub fn rng_from_seed(seed: u64) -> CoreRng {
    CoreRng::seed_from_u64(seed)
}

/// Derive an independent child seed from a parent seed and a stream label (SplitMix64 mixing),
/// so components never share a stream.
pub fn child_seed(parent: u64, stream: u64) -> u64 {
    let mut z = parent ^ stream.wrapping_mul(0x9E37_79B9_7F4A_7C15);
    z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
    z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
    z ^ (z >> 31)
}

/// Uniform in [lo, hi] (a degenerate interval returns lo).
#[inline]
pub fn uniform(rng: &mut CoreRng, lo: f64, hi: f64) -> f64 {
    if hi > lo {
        lo + (hi - lo) * rng.random::<f64>()
    } else {
        lo
    }
}

/// Uniform float in [0, 1).
#[inline]
pub fn unit(rng: &mut CoreRng) -> f64 {
    rng.random::<f64>()
}

/// Standard normal draw (Box-Muller; one of the pair is discarded so each call uses a fixed
/// number of draws, which keeps streams easy to reason about).
#[inline]
pub fn normal(rng: &mut CoreRng) -> f64 {
    let u1 = 1.0 - rng.random::<f64>(); // (0, 1]: ln is finite
    let u2 = rng.random::<f64>();
    (-2.0 * u1.ln()).sqrt() * (std::f64::consts::TAU * u2).cos()
}

/// Uniform index in [0, n).
#[inline]
pub fn index(rng: &mut CoreRng, n: usize) -> usize {
    rng.random_range(0..n)
}

/// The index a draw `u` in [0, sum of `w`) falls on when the weights `w` lie end to end: the
/// first i with u below its weight after the weights before it are taken off, or the last
/// positive weight when rounding carries u past the end.
pub fn pick_weighted(w: &[f64], mut u: f64) -> usize {
    for (i, &x) in w.iter().enumerate() {
        if u < x {
            return i;
        }
        u -= x;
    }
    w.iter().rposition(|&x| x > 0.0).unwrap_or(0)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The loop the teachers wrote out before (goal_selection, discrete LP, TSCL, the
    /// mixtures): a fallback to the last positive weight, replaced by the first weight u falls under.
    fn pick_by_scan(w: &[f64], mut u: f64) -> usize {
        let mut chosen = w.iter().rposition(|&x| x > 0.0).unwrap_or(0);
        for (i, &x) in w.iter().enumerate() {
            if u < x {
                chosen = i;
                break;
            }
            u -= x;
        }
        chosen
    }

    #[test]
    fn pick_weighted_is_the_scan_it_replaced() {
        let mut rng = rng_from_seed(7);
        for case in 0..20_000 {
            let n = 1 + index(&mut rng, 9);
            // Zeros, ties and tiny weights, and draws past the end that rounding can give.
            let w: Vec<f64> = (0..n).map(|_| [0.0, 1.0, 0.5, 1e-300, unit(&mut rng)][index(&mut rng, 5)]).collect();
            let total: f64 = w.iter().sum();
            let u = if case % 10 == 0 { total * (1.0 + 1e-12) } else { unit(&mut rng) * total };
            assert_eq!(pick_weighted(&w, u), pick_by_scan(&w, u), "{w:?} {u}");
        }
    }
}

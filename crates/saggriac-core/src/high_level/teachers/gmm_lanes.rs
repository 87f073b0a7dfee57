//! The two loops of the mixtures' EM (`gmm.rs`) in SIMD lanes, with the bits of the plain
//! one-sample loops: the E step's forward substitution four samples at a time, the M step's
//! weighted scatter a row at a time. AVX2 where the CPU has it, no FMA.

/// Samples whose forward substitutions run side by side in the E step.
pub(super) const LANES: usize = 4;

/// |L^-1 (x - m)|^2 for LANES samples at once, L a row-major lower-triangular factor: each
/// lane runs the serial substitution of one sample (whose chain of dependent steps is what
/// bounds its speed alone) with the same operations in the same order, so each result has the
/// bits of the one-sample loop.
#[inline(always)]
fn mahalanobis_sq_generic(rows: &[&[f64]; LANES], m: &[f64], l: &[f64], y: &mut [[f64; LANES]]) -> [f64; LANES] {
    let d = m.len();
    let mut sq = [0.0; LANES];
    for i in 0..d {
        let mut v: [f64; LANES] = std::array::from_fn(|s| rows[s][i] - m[i]);
        for j in 0..i {
            let lij = l[i * d + j];
            for (vs, ys) in v.iter_mut().zip(&y[j]) {
                *vs -= lij * ys;
            }
        }
        let lii = l[i * d + i];
        for (s, vs) in v.iter_mut().enumerate() {
            *vs /= lii;
            sq[s] += *vs * *vs;
        }
        y[i] = v;
    }
    sq
}

#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2")]
unsafe fn mahalanobis_sq_avx2(rows: &[&[f64]; LANES], m: &[f64], l: &[f64], y: &mut [[f64; LANES]]) -> [f64; LANES] {
    // The same code in 4-wide lanes; no FMA is enabled, so the bits are the same.
    mahalanobis_sq_generic(rows, m, l, y)
}

pub(super) fn mahalanobis_sq(rows: &[&[f64]; LANES], m: &[f64], l: &[f64], y: &mut [[f64; LANES]]) -> [f64; LANES] {
    #[cfg(target_arch = "x86_64")]
    {
        if std::arch::is_x86_feature_detected!("avx2") {
            // SAFETY: the CPU supports AVX2, checked just above.
            return unsafe { mahalanobis_sq_avx2(rows, m, l, y) };
        }
    }
    mahalanobis_sq_generic(rows, m, l, y)
}

/// The lower triangle of sum_i r_ij (x_i - mean)(x_i - mean)^T into `cov` (d x d, row-major),
/// summed over the samples in order; a row's entries are independent sums, so they run in SIMD
/// lanes with the bits of the one-by-one loop.
#[inline(always)]
fn weighted_scatter_generic(x: &[f64], resp: &[f64], k: usize, j: usize, mean: &[f64], cov: &mut [f64]) {
    let d = mean.len();
    let mut diff = vec![0.0; d];
    for (x, r) in x.chunks_exact(d).zip(resp.chunks_exact(k)) {
        let w = r[j];
        if w == 0.0 {
            continue;
        }
        for (t, (v, m)) in diff.iter_mut().zip(x.iter().zip(mean)) {
            *t = v - m;
        }
        for a in 0..d {
            let wa = w * diff[a];
            for (c, t) in cov[a * d..=a * d + a].iter_mut().zip(&diff[..=a]) {
                *c += wa * t;
            }
        }
    }
}

#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2")]
unsafe fn weighted_scatter_avx2(x: &[f64], resp: &[f64], k: usize, j: usize, mean: &[f64], cov: &mut [f64]) {
    // The same code in 4-wide lanes; no FMA is enabled, so the bits are the same.
    weighted_scatter_generic(x, resp, k, j, mean, cov)
}

pub(super) fn weighted_scatter(x: &[f64], resp: &[f64], k: usize, j: usize, mean: &[f64], cov: &mut [f64]) {
    #[cfg(target_arch = "x86_64")]
    {
        if std::arch::is_x86_feature_detected!("avx2") {
            // SAFETY: the CPU supports AVX2, checked just above.
            return unsafe { weighted_scatter_avx2(x, resp, k, j, mean, cov) };
        }
    }
    weighted_scatter_generic(x, resp, k, j, mean, cov)
}

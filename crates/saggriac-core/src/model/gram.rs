//! The local fit's kernels (`local_model.rs`): the weighted Gram matrix and right-hand sides in
//! register tiles, and the prefetch of the neighbours' rows.

/// Columns of the Gram matrix accumulated together by `fit`: enough independent sums to keep
/// the floating-point units busy, few enough to stay in registers.
pub(crate) const LANES: usize = 8;

/// Rows of the Gram matrix accumulated together: TILE_ROWS x LANES independent sums (eight AVX2
/// registers), so that the adds of one sum wait on nothing but their own latency.
pub(crate) const TILE_ROWS: usize = 4;

/// Entry (a, b) of [Gram | rhs] is sum_i wd_i[a] * row_i[b], summed over the `k` neighbours in
/// order from 0.0 as a plain running sum would (a multiply, then an add: no fused multiply-add,
/// so every build gives the same bits). The sums of a tile of TILE_ROWS x LANES entries are kept
/// in registers across the neighbours. Rows b >= a of column a of `gram` form the lower
/// triangle, which is all the Cholesky factorisation reads; columns b >= n go to `rhs`.
#[inline(always)]
#[allow(clippy::too_many_arguments)]
fn gram_and_rhs_generic(wd: &[f64], wstride: usize, rows: &[f64], stride: usize, k: usize, n: usize, width: usize, gram: &mut [f64], rhs: &mut [f64]) {
    for a0 in (0..n).step_by(TILE_ROWS) {
        for b0 in ((a0 / LANES) * LANES..width).step_by(LANES) {
            let mut acc = [[0.0f64; LANES]; TILE_ROWS];
            for (row, w) in rows.chunks_exact(stride).zip(wd.chunks_exact(wstride)).take(k) {
                let r: &[f64; LANES] = row[b0..b0 + LANES].try_into().unwrap();
                let w: &[f64; TILE_ROWS] = w[a0..a0 + TILE_ROWS].try_into().unwrap();
                for (sums, &da) in acc.iter_mut().zip(w) {
                    for (s, x) in sums.iter_mut().zip(r) {
                        *s += da * x;
                    }
                }
            }
            for (a, sums) in (a0..n.min(a0 + TILE_ROWS)).zip(&acc) {
                for (b, &v) in (b0..width.min(b0 + LANES)).zip(sums) {
                    if b < a {
                        continue;
                    }
                    if b < n {
                        gram[a * n + b] = v;
                    } else {
                        rhs[(b - n) * n + a] = v;
                    }
                }
            }
        }
    }
}

#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2")]
#[allow(clippy::too_many_arguments)]
unsafe fn gram_and_rhs_avx2(wd: &[f64], wstride: usize, rows: &[f64], stride: usize, k: usize, n: usize, width: usize, gram: &mut [f64], rhs: &mut [f64]) {
    // Same code in 4-wide lanes; no FMA is enabled, so the sums are bit-identical.
    gram_and_rhs_generic(wd, wstride, rows, stride, k, n, width, gram, rhs)
}

#[allow(clippy::too_many_arguments)]
pub(crate) fn gram_and_rhs(wd: &[f64], wstride: usize, rows: &[f64], stride: usize, k: usize, n: usize, width: usize, gram: &mut [f64], rhs: &mut [f64]) {
    #[cfg(target_arch = "x86_64")]
    {
        if std::arch::is_x86_feature_detected!("avx2") {
            // SAFETY: the CPU supports AVX2, checked just above.
            return unsafe { gram_and_rhs_avx2(wd, wstride, rows, stride, k, n, width, gram, rhs) };
        }
    }
    gram_and_rhs_generic(wd, wstride, rows, stride, k, n, width, gram, rhs)
}

/// Ask the CPU to bring the cache lines of `row` in (a hint: no effect on results).
#[inline(always)]
pub(crate) fn prefetch(row: &[f64]) {
    #[cfg(target_arch = "x86_64")]
    {
        use std::arch::x86_64::{_mm_prefetch, _MM_HINT_T0};
        // One address per 64-byte line the row may touch, and its last value.
        for v in row.iter().step_by(8).chain(row.last()) {
            // SAFETY: prefetching is a hint that never faults, here of an address in `row`.
            unsafe { _mm_prefetch::<_MM_HINT_T0>((v as *const f64).cast()) };
        }
    }
}

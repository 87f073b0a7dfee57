//! Squared distances from a query to a block of stored points, dimension-major (coordinate d of
//! point j at `d * cap + j`), in AVX2 lanes where the CPU has them: the kernels of the exact
//! searches. Every kernel sums over dimensions in order from 0.0, exactly as `dist_sq` does, and
//! no FMA is enabled, so each distance has `dist_sq`'s bits.

/// Squared distances from q to the first `len` points of a dimension-major block (coordinate d
/// of point j at `d * cap + j`), summed over dimensions in order, exactly as `dist_sq` sums
/// them (same bits).
#[inline(always)]
fn block_dist_sq(q: &[f64], coords: &[f64], cap: usize, len: usize, acc: &mut [f64]) {
    let acc = &mut acc[..len];
    acc.iter_mut().for_each(|a| *a = 0.0);
    for (d, &qd) in q.iter().enumerate() {
        let row = &coords[d * cap..d * cap + len];
        for (a, c) in acc.iter_mut().zip(row) {
            let e = qd - c;
            *a += e * e;
        }
    }
}

#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2")]
unsafe fn block_dist_sq_avx2(q: &[f64], coords: &[f64], cap: usize, len: usize, acc: &mut [f64]) {
    // Same code compiled for 4-wide lanes; no FMA is enabled, so results are bit-identical.
    block_dist_sq(q, coords, cap, len, acc)
}

/// `block_dist_sq` for a search with a bound: the sums are the same, but halfway through the
/// dimensions, if every point's partial sum is already above `bound`, it stops and returns
/// false (the squares are not negative, so no later term brings a sum back under it; a sum
/// that survives is finished in the same order, with the same bits).
#[inline(always)]
fn block_dist_sq_within(q: &[f64], coords: &[f64], cap: usize, len: usize, acc: &mut [f64], bound: f64) -> bool {
    let acc = &mut acc[..len];
    acc.iter_mut().for_each(|a| *a = 0.0);
    let half = q.len() / 2;
    for (d, &qd) in q.iter().enumerate() {
        if d == half && acc.iter().fold(true, |all, &a| all & (a > bound)) {
            return false;
        }
        let row = &coords[d * cap..d * cap + len];
        for (a, c) in acc.iter_mut().zip(row) {
            let e = qd - c;
            *a += e * e;
        }
    }
    true
}

#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2")]
unsafe fn block_dist_sq_within_avx2(q: &[f64], coords: &[f64], cap: usize, len: usize, acc: &mut [f64], bound: f64) -> bool {
    // As `block_dist_sq_avx2`: 4-wide lanes, no FMA, the same bits.
    block_dist_sq_within(q, coords, cap, len, acc, bound)
}

/// `block_dist_sq_within` in AVX2 lanes where the CPU has them: false when no point of the
/// block can be within `bound` (the distances in `acc` are then unfinished).
#[inline]
pub(crate) fn distances_within(q: &[f64], coords: &[f64], cap: usize, len: usize, acc: &mut [f64], bound: f64) -> bool {
    #[cfg(target_arch = "x86_64")]
    {
        if std::arch::is_x86_feature_detected!("avx2") {
            // SAFETY: the CPU supports AVX2, checked just above.
            return unsafe { block_dist_sq_within_avx2(q, coords, cap, len, acc, bound) };
        }
    }
    block_dist_sq_within(q, coords, cap, len, acc, bound)
}

/// `s[j] += (q[d] - rows[d][j])^2` for each dimension d of `q` in order (rows of `B`).
#[inline(always)]
fn add_squares<const B: usize>(s: &mut [f64; B], q: &[f64], rows: &[f64]) {
    for (&qd, row) in q.iter().zip(rows.chunks_exact(B)) {
        for (a, &c) in s.iter_mut().zip(row) {
            let e = qd - c;
            *a += e * e;
        }
    }
}

/// `block_dist_sq_within` for a full block of `B` points (B <= 32), with the block's size known
/// at compile time so that the `B` running sums stay in registers (with a run-time length they
/// went through memory at every dimension). The same operations in the same order: the same
/// bits. Returns the points within `bound` as bits (0 when the block stopped halfway).
#[inline(always)]
fn full_block_within<const B: usize>(q: &[f64], coords: &[f64], acc: &mut [f64; B], bound: f64) -> u32 {
    let mut s = [0.0f64; B];
    let half = q.len() / 2;
    let coords = &coords[..q.len() * B];
    add_squares(&mut s, &q[..half], &coords[..half * B]);
    if s.iter().fold(true, |all, &a| all & (a > bound)) {
        return 0;
    }
    add_squares(&mut s, &q[half..], &coords[half * B..]);
    *acc = s;
    s.iter().enumerate().fold(0u32, |m, (j, &a)| m | (u32::from(a <= bound) << j))
}

#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2")]
unsafe fn full_block_within_avx2<const B: usize>(q: &[f64], coords: &[f64], acc: &mut [f64; B], bound: f64) -> u32 {
    // As `block_dist_sq_avx2`: 4-wide lanes, no FMA, the same bits.
    full_block_within(q, coords, acc, bound)
}

/// The squared distances from q to the `B` points of a full dimension-major block, into `acc`,
/// and which of them are within `bound`, as bits (AVX2 lanes where the CPU has them). When the
/// answer is 0, `acc` may be unfinished (never with an infinite bound).
#[inline]
pub(crate) fn full_block_distances_within<const B: usize>(q: &[f64], coords: &[f64], acc: &mut [f64; B], bound: f64) -> u32 {
    const { assert!(B <= 32) };
    #[cfg(target_arch = "x86_64")]
    {
        if std::arch::is_x86_feature_detected!("avx2") {
            // SAFETY: the CPU supports AVX2, checked just above.
            return unsafe { full_block_within_avx2(q, coords, acc, bound) };
        }
    }
    full_block_within(q, coords, acc, bound)
}

/// f32 squared distances from `q` to the `B` points of a full dimension-major f32 block, and
/// which of them are at or below `limit`, as bits. A screen, not a distance: the caller proves
/// that no point within its exact bound can sum above `limit` (rounding included; any order of
/// the sum does, as each term still goes through at most dim additions).
#[inline(always)]
fn screen_block<const B: usize>(q: &[f32], coords: &[f32], limit: f32) -> u32 {
    let mut s = [0.0f32; B];
    for (&qd, row) in q.iter().zip(coords[..q.len() * B].chunks_exact(B)) {
        for (a, &c) in s.iter_mut().zip(row) {
            let e = qd - c;
            *a += e * e;
        }
    }
    s.iter().enumerate().fold(0u32, |m, (j, &a)| m | (u32::from(a <= limit) << j))
}

/// `screen_block` for blocks of 8 in one AVX2 register, written out: the compiler's own
/// vectorisation of the generic loop shuffled lanes. Two running sums (even and odd
/// dimensions) halve the chain of dependent additions; no FMA.
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2")]
unsafe fn screen_block8_avx2(q: &[f32], coords: &[f32], limit: f32) -> u32 {
    use std::arch::x86_64::*;
    let dim = q.len();
    let coords = &coords[..dim * 8];
    let p = coords.as_ptr();
    let (mut s0, mut s1) = (_mm256_setzero_ps(), _mm256_setzero_ps());
    let mut d = 0;
    while d + 1 < dim {
        let e0 = _mm256_sub_ps(_mm256_set1_ps(q[d]), _mm256_loadu_ps(p.add(d * 8)));
        let e1 = _mm256_sub_ps(_mm256_set1_ps(q[d + 1]), _mm256_loadu_ps(p.add(d * 8 + 8)));
        s0 = _mm256_add_ps(s0, _mm256_mul_ps(e0, e0));
        s1 = _mm256_add_ps(s1, _mm256_mul_ps(e1, e1));
        d += 2;
    }
    if d < dim {
        let e0 = _mm256_sub_ps(_mm256_set1_ps(q[d]), _mm256_loadu_ps(p.add(d * 8)));
        s0 = _mm256_add_ps(s0, _mm256_mul_ps(e0, e0));
    }
    let within = _mm256_cmp_ps::<_CMP_LE_OQ>(_mm256_add_ps(s0, s1), _mm256_set1_ps(limit));
    _mm256_movemask_ps(within) as u32
}

#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2")]
unsafe fn screen_block_avx2<const B: usize>(q: &[f32], coords: &[f32], limit: f32) -> u32 {
    if B == 8 {
        return screen_block8_avx2(q, coords, limit);
    }
    screen_block::<B>(q, coords, limit)
}

/// `screen_block` in AVX2 lanes where the CPU has them. `q` and `coords` must be finite (an
/// infinite pair would make NaN, which no limit admits).
#[inline]
pub(crate) fn screen_full_block<const B: usize>(q: &[f32], coords: &[f32], limit: f32) -> u32 {
    const { assert!(B <= 32) };
    #[cfg(target_arch = "x86_64")]
    {
        if std::arch::is_x86_feature_detected!("avx2") {
            // SAFETY: the CPU supports AVX2, checked just above.
            return unsafe { screen_block_avx2::<B>(q, coords, limit) };
        }
    }
    screen_block::<B>(q, coords, limit)
}

/// `block_dist_sq` in AVX2 lanes where the CPU has them.
#[inline]
pub(crate) fn distances(q: &[f64], coords: &[f64], cap: usize, len: usize, acc: &mut [f64]) {
    #[cfg(target_arch = "x86_64")]
    {
        if std::arch::is_x86_feature_detected!("avx2") {
            // SAFETY: the CPU supports AVX2, checked just above.
            return unsafe { block_dist_sq_avx2(q, coords, cap, len, acc) };
        }
    }
    block_dist_sq(q, coords, cap, len, acc)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::model::neighbours::dist_sq;
    use crate::rng::{rng_from_seed, uniform};

    /// The full-block kernel gives `dist_sq`'s bits for every point and exactly the points at
    /// or within the bound (ties included), in every dimension, early stop or not.
    #[test]
    fn full_block_kernel_matches_dist_sq_bit_for_bit() {
        const B: usize = 16;
        let mut r = rng_from_seed(11);
        for dim in (1..=20).chain([31, 40]) {
            for trial in 0..40 {
                // Some points repeated (identical rest poses), the rest scattered.
                let mut pts: Vec<Vec<f64>> = (0..B).map(|_| (0..dim).map(|_| uniform(&mut r, -0.5, 0.5)).collect()).collect();
                for j in (0..B).step_by(3) {
                    pts[j] = pts[0].clone();
                }
                let mut block = vec![0.0; dim * B];
                for (j, p) in pts.iter().enumerate() {
                    for d in 0..dim {
                        block[d * B + j] = p[d];
                    }
                }
                let q: Vec<f64> = (0..dim).map(|_| uniform(&mut r, -0.7, 0.7)).collect();
                let exact: Vec<f64> = pts.iter().map(|p| dist_sq(&q, p)).collect();
                let mut sorted = exact.clone();
                sorted.sort_by(f64::total_cmp);
                // Bounds: each distance itself (a tie), between, below all, above all, infinite.
                let bounds = [sorted[trial % B], sorted[0] * 0.5, sorted[B - 1] * 2.0, f64::INFINITY, 0.0, sorted[B / 2] + 1e-3];
                for &bound in &bounds {
                    let mut acc = [f64::NAN; B];
                    let within = full_block_distances_within(&q, &block, &mut acc, bound);
                    let want = exact.iter().enumerate().fold(0u32, |m, (j, &d)| m | (u32::from(d <= bound) << j));
                    assert_eq!(within, want, "dim {dim}, bound {bound}");
                    if within != 0 {
                        for j in 0..B {
                            assert_eq!(acc[j].to_bits(), exact[j].to_bits(), "dim {dim}, point {j}");
                        }
                    }
                }
            }
        }
    }
}

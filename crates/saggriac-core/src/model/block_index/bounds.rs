//! Lower bounds of distances to boxes, in f32 lanes, and the margin that keeps them safe for an
//! exact search in f64.

/// Boxes per row of boxes (the children of one box).
pub(super) const FANOUT: usize = 8;
/// Rows of boxes whose bounds are computed together.
pub(super) const BATCH: usize = 4;

/// The largest f32 <= v and the smallest f32 >= v (v finite).
pub(super) fn outward(v: f64) -> (f32, f32) {
    let f = v as f32;
    let fd = f as f64;
    let below = if fd > v { step_down(f) } else { f };
    let above = if fd < v { step_up(f) } else { f };
    (below, above)
}

pub(super) fn step_up(f: f32) -> f32 {
    if f.is_nan() || f == f32::INFINITY {
        return f;
    }
    if f == 0.0 {
        return f32::from_bits(1);
    }
    let b = f.to_bits();
    f32::from_bits(if f > 0.0 { b + 1 } else { b - 1 })
}

fn step_down(f: f32) -> f32 {
    -step_up(-f)
}

pub(super) type Bounds = [[f32; FANOUT]; BATCH];

/// Bounds of the squared distance from the f32-rounded query to each box of `BATCH` rows of
/// boxes, in f32 (eight lanes to a register; `Query::limit` says how far rounding can take them).
/// `x > 0 ? x : 0` rather than `max`, which keeps NaN rules out of the way of vectorisation
/// (nothing here is NaN: the memory refuses non-finite samples and queries are finite).
#[inline(always)]
fn bounds_generic(q: &[f32], rows: &[&[f32]; BATCH], out: &mut Bounds) {
    let dim = q.len();
    let mut acc = [[0.0f32; FANOUT]; BATCH];
    for (d, &x) in q.iter().enumerate() {
        for (a, row) in acc.iter_mut().zip(rows) {
            let l = &row[d * FANOUT..(d + 1) * FANOUT];
            let h = &row[(dim + d) * FANOUT..(dim + d + 1) * FANOUT];
            for c in 0..FANOUT {
                let below = l[c] - x;
                let above = x - h[c];
                // At most one of the two is positive (l <= h).
                let gap = if below > 0.0 { below } else { 0.0 } + if above > 0.0 { above } else { 0.0 };
                a[c] += gap * gap;
            }
        }
    }
    *out = acc;
}

#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2")]
unsafe fn bounds_avx2(q: &[f32], rows: &[&[f32]; BATCH], out: &mut Bounds) {
    // Same code in 8-wide lanes; no FMA is enabled, so the bounds are bit-identical.
    bounds_generic(q, rows, out)
}

#[inline]
pub(super) fn bounds(q: &[f32], rows: &[&[f32]; BATCH], out: &mut Bounds) {
    #[cfg(target_arch = "x86_64")]
    {
        if std::arch::is_x86_feature_detected!("avx2") {
            // SAFETY: the CPU supports AVX2, checked just above.
            return unsafe { bounds_avx2(q, rows, out) };
        }
    }
    bounds_generic(q, rows, out)
}

/// A query as the boxes see it: rounded to f32, with what the rounding can cost.
///
/// Why a box skipped by `limit` holds no point p with computed `dist_sq(q, p) <= t`. Let q' be
/// q rounded to f32 and delta = |q - q'|. In each dimension the exact gap from q' to the box is
/// at most |q'_d - p_d| <= |q_d - p_d| + |q_d - q'_d|. The f32 bound rounds each gap, square and
/// partial sum once (relative error u = 2^-24 each, in dim + 2 steps for a term), so it is at
/// most (1 + u)^(dim + 3) sum_d (|q_d - p_d| + |q_d - q'_d|)^2 <= (1 + u)^(dim + 3)
/// (|q - p| + delta)^2 (Minkowski). And |q - p|^2 <= t (1 + 2 (dim + 2) 2^-53), since dist_sq
/// rounds dim + 1 times. `limit(t)` is that bound, rounded up, plus 1e-37 for f32 results in the
/// subnormal range (absolute error 2^-150 each).
///
/// `point_limit(t)` is the same for the f32 copy of a point p' (p rounded to nearest) taken as a
/// box of one point: |q'_d - p'_d| <= |q_d - p_d| + |q_d - q'_d| + |p_d - p'_d|, so delta grows
/// by `rounding`, the largest |p - p'| of the stored points. The screen's sum rounds each
/// difference, square and partial sum once, as the box bound does.
pub(super) struct Query<'a> {
    pub q: &'a [f64],
    pub q32: Vec<f32>,
    delta: f64,
    /// The largest |p - p'| of the stored points (infinite when one overflows f32).
    rounding: f64,
    /// (1 + u)^(dim + 3), rounded up.
    grow: f64,
    /// 1 + 2 (dim + 2) 2^-53 and a margin for the few f64 operations of `limit`.
    exact: f64,
}

impl<'a> Query<'a> {
    pub fn new(q: &'a [f64], rounding: f64) -> Self {
        let q32: Vec<f32> = q.iter().map(|&v| v as f32).collect();
        // q - q' is exact in f64; the sum is rounded, so widened a little.
        let delta = q.iter().zip(&q32).map(|(&a, &b)| (a - b as f64) * (a - b as f64)).sum::<f64>().sqrt() * (1.0 + 1e-12);
        let n = q.len() as f64;
        Query { q, q32, delta, rounding, grow: 1.0 + 2.0 * (n + 3.0) * 2f64.powi(-24), exact: 1.0 + 2.0 * (n + 2.0) * 2f64.powi(-53) + 1e-12 }
    }

    /// The largest f32 bound that a box holding a point within squared distance `t` can get.
    pub fn limit(&self, t: f64) -> f32 {
        self.limit_with(t, self.delta)
    }

    /// The largest f32 screen sum that a stored point within squared distance `t` can get
    /// (infinite, so no screen, when a query or stored coordinate overflows f32).
    pub fn point_limit(&self, t: f64) -> f32 {
        self.limit_with(t, self.delta + self.rounding)
    }

    fn limit_with(&self, t: f64, delta: f64) -> f32 {
        if t == f64::INFINITY || !delta.is_finite() {
            return f32::INFINITY;
        }
        let r = (t * self.exact).sqrt() * (1.0 + 1e-12) + delta;
        let l = r * r * self.grow * (1.0 + 1e-12) + 1e-37;
        let f = l as f32;
        if (f as f64) < l {
            step_up(f)
        } else {
            f
        }
    }
}

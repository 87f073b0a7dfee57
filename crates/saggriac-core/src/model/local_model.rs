//! Local linear models learnt from nearest neighbours (paper III.B): the Jacobian J around theta
//! by ridge-regularised least squares dx ~ J dtheta, its Moore-Penrose pseudo-inverse by SVD for
//! the inverse model (eq. 6), and a forward prediction of x(theta) for the evaluation.

use nalgebra::{DMatrix, DVector};

pub use crate::config::model::{LocalModelConfig, MIN_RCOND};
use crate::model::gram::{gram_and_rhs, prefetch, LANES, TILE_ROWS};
use crate::model::memory::SensorimotorMemory;
use crate::model::neighbours::Neighbour;

/// Why a local fit could not be used. The controller answers by exploring, never by moving
/// with a NaN command.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum FitFailure {
    /// Fewer stored samples than `k_neighbours`.
    NotEnoughData,
    /// The neighbours carry no joint motion, or the fit is not finite.
    Degenerate,
}

/// Workspace for local fits; reused across calls so the hot loop does not allocate matrices.
pub struct LocalModel {
    pub cfg: LocalModelConfig,
    n: usize,
    m: usize,
    /// n x n, column-major, lower triangle: the regularised Gram matrix, then its Cholesky factor.
    gram: Vec<f64>,
    /// n x m, column-major: the right-hand side, then J^T.
    rhs: Vec<f64>,
    /// The current Jacobian estimate (m x n).
    jac: DMatrix<f64>,
    /// Per neighbour, its weighted joint motion w dtheta (n values, padded with zeros to
    /// `wstride`, a multiple of `TILE_ROWS`).
    wd: Vec<f64>,
    wstride: usize,
    /// Per neighbour, dtheta then dx, padded to `stride` values (plus `LANES` at the end).
    rows: Vec<f64>,
    stride: usize,
}

impl LocalModel {
    pub fn new(n: usize, m: usize, cfg: LocalModelConfig) -> Self {
        let stride = (n + m).div_ceil(LANES) * LANES;
        let wstride = n.div_ceil(TILE_ROWS) * TILE_ROWS;
        LocalModel { cfg, n, m, gram: vec![0.0; n * n], rhs: vec![0.0; n * m], jac: DMatrix::zeros(m, n), wd: Vec::new(), wstride, rows: Vec::new(), stride }
    }

    pub fn jacobian(&self) -> &DMatrix<f64> {
        &self.jac
    }

    /// Fit J on the given neighbours: J = argmin sum w_i |dx_i - J dtheta_i|^2 + lambda |J|_F^2.
    pub fn fit(&mut self, mem: &SensorimotorMemory, neighbours: &[Neighbour]) -> std::result::Result<(), FitFailure> {
        if neighbours.len() < self.cfg.k_neighbours.min(mem.len()).max(1) || mem.len() < self.cfg.k_neighbours {
            return Err(FitFailure::NotEnoughData);
        }
        let (n, m, stride) = (self.n, self.m, self.stride);
        let (k, width) = (neighbours.len(), n + m);
        // Gaussian weights with a bandwidth set by the median neighbour: the Jacobian changes
        // across the neighbourhood, so the closest samples should dominate.
        let h2 = neighbours[neighbours.len() / 2].dist_sq.max(1e-300) * self.cfg.bandwidth;
        // Padding entries (a >= n) are never written, so they stay 0.0.
        self.wd.resize(k * self.wstride, 0.0);
        self.rows.resize(k * stride + LANES, 0.0);
        // The neighbours' rows lie anywhere in a memory much larger than the caches: ask for
        // all of them at once, so that their misses overlap instead of following each other.
        for nb in neighbours {
            let id = nb.id as usize;
            prefetch(mem.dtheta(id));
            prefetch(mem.dx(id));
        }
        for (i, nb) in neighbours.iter().enumerate() {
            let w = if self.cfg.bandwidth > 0.0 { (-nb.dist_sq / h2).exp() } else { 1.0 };
            let dth = mem.dtheta(nb.id as usize);
            for (o, d) in self.wd[i * self.wstride..i * self.wstride + n].iter_mut().zip(dth) {
                *o = w * d;
            }
            let row = &mut self.rows[i * stride..i * stride + width];
            row[..n].copy_from_slice(dth);
            row[n..].copy_from_slice(mem.dx(nb.id as usize));
        }
        gram_and_rhs(&self.wd, self.wstride, &self.rows, stride, k, n, width, &mut self.gram, &mut self.rhs);
        let trace: f64 = (0..n).map(|a| self.gram[a * n + a]).sum();
        if !(trace.is_finite() && trace > 0.0) {
            return Err(FitFailure::Degenerate);
        }
        let lambda = self.cfg.ridge * trace / n as f64;
        // Off the diagonal the old code added 0.0, a no-op: a sum started at +0.0 is never -0.0.
        for a in 0..n {
            self.gram[a * n + a] += lambda;
        }
        if !cholesky_in_place(&mut self.gram, n) {
            return Err(FitFailure::Degenerate);
        }
        cholesky_solve_in_place(&self.gram, n, &mut self.rhs);
        if !self.rhs.iter().all(|v| v.is_finite()) {
            return Err(FitFailure::Degenerate);
        }
        for (a, col) in self.jac.as_mut_slice().chunks_exact_mut(m).enumerate() {
            for (j, v) in col.iter_mut().enumerate() {
                *v = self.rhs[j * n + a];
            }
        }
        Ok(())
    }

    /// dtheta = J+ dx with the Moore-Penrose pseudo-inverse of the fitted J.
    pub fn inverse(&self, dx: &[f64], dtheta: &mut [f64]) -> std::result::Result<(), FitFailure> {
        pinv_apply_wide(&self.jac, dx, self.cfg.pinv_rcond, dtheta)
    }

    /// Forward prediction of x(theta): x_mean + J d, with x_mean and theta_mean the neighbours'
    /// centroid and d = theta - theta_mean shortened to the neighbourhood's radius. Inside the
    /// data this is the local linear model; far outside it, a first-order expansion is
    /// meaningless, so it extrapolates no further than the data extends.
    pub fn predict_x(&self, mem: &SensorimotorMemory, neighbours: &[Neighbour], theta: &[f64], out: &mut [f64]) {
        let k = neighbours.len().max(1) as f64;
        let mut centre = vec![0.0; self.n];
        out.iter_mut().for_each(|v| *v = 0.0);
        for nb in neighbours {
            for (c, t) in centre.iter_mut().zip(mem.theta(nb.id as usize)) {
                *c += t / k;
            }
            for (o, x) in out.iter_mut().zip(mem.x(nb.id as usize)) {
                *o += x / k;
            }
        }
        let radius = neighbours.iter().map(|nb| crate::model::neighbours::dist_sq(&mem.theta(nb.id as usize), &centre)).fold(0.0, f64::max).sqrt();
        let mut d: Vec<f64> = theta.iter().zip(&centre).map(|(t, c)| t - c).collect();
        let norm = d.iter().map(|v| v * v).sum::<f64>().sqrt();
        if norm > radius && norm > 0.0 {
            d.iter_mut().for_each(|v| *v *= radius / norm);
        }
        for (j, o) in out.iter_mut().enumerate() {
            *o += (0..self.n).map(|a| self.jac[(j, a)] * d[a]).sum::<f64>();
        }
    }
}

/// `Cholesky::new` of nalgebra 0.35 on the lower triangle of the column-major n x n `g`, the
/// same operations in the same order, without its per-column views: false where nalgebra
/// returns None (a zero, negative or NaN pivot).
fn cholesky_in_place(g: &mut [f64], n: usize) -> bool {
    for j in 0..n {
        let (left, right) = g.split_at_mut(j * n);
        let col_j = &mut right[j..n];
        for k in 0..j {
            // nalgebra's axpy: y = (f * x) * 1 + 1 * y, which is y + f * x bit for bit.
            let f = -left[k * n + j];
            for (y, x) in col_j.iter_mut().zip(&left[k * n + j..(k + 1) * n]) {
                *y += f * x;
            }
        }
        let diag = col_j[0];
        if diag <= 0.0 || diag.is_nan() {
            return false;
        }
        let denom = diag.sqrt();
        col_j[0] = denom;
        for v in &mut col_j[1..] {
            *v /= denom;
        }
    }
    true
}

/// nalgebra 0.35's `Cholesky::solve_mut` for each column of `b` (n rows, column-major), given
/// the factor from `cholesky_in_place`: forward substitution, then back substitution with its
/// dot product. Every column gets the operations nalgebra gives it; the columns go through the
/// rows side by side so that their chains of divisions overlap.
fn cholesky_solve_in_place(l: &[f64], n: usize, b: &mut [f64]) {
    for i in 0..n {
        for b in b.chunks_exact_mut(n) {
            let coeff = b[i] / l[i * n + i];
            b[i] = coeff;
            for (y, x) in b[i + 1..].iter_mut().zip(&l[i * n + i + 1..(i + 1) * n]) {
                *y += -coeff * x;
            }
        }
    }
    for i in (0..n).rev() {
        for b in b.chunks_exact_mut(n) {
            let dot = nalgebra_dot(&l[i * n + i + 1..(i + 1) * n], &b[i + 1..n]);
            b[i] = (b[i] - dot) / l[i * n + i];
        }
    }
}

/// The dot product of two dynamically sized vectors as nalgebra 0.35 sums it (`dotx`): eight
/// running sums over blocks of eight, combined pairwise into a total, then the remainder.
fn nalgebra_dot(a: &[f64], b: &[f64]) -> f64 {
    let mut acc = [0.0f64; 8];
    let blocks = a.len() / 8;
    for (x, y) in a.chunks_exact(8).zip(b.chunks_exact(8)) {
        for t in 0..8 {
            acc[t] += x[t] * y[t];
        }
    }
    let mut res = 0.0;
    res += acc[0] + acc[4];
    res += acc[1] + acc[5];
    res += acc[2] + acc[6];
    res += acc[3] + acc[7];
    for (x, y) in a[blocks * 8..].iter().zip(&b[blocks * 8..]) {
        res += x * y;
    }
    res
}

/// J+ dx for a wide J (m x n, m <= n) through the symmetric eigen-decomposition of the small
/// m x m matrix J J^T = U S^2 U^T: J+ = J^T U S^-2 U^T, eigenvalues below (rcond * s_max)^2
/// dropped. This is the SVD pseudo-inverse with the same cutoff (the singular values of J are the
/// square roots of those eigenvalues), at the cost of an m x m problem instead of an m x n SVD.
///
/// Eigenvalues of J J^T below ~1e-16 s_max^2 are rounding noise, so the relative cutoff is never
/// taken below `MIN_RCOND` (the configuration refuses smaller values).
pub fn pinv_apply_wide(j: &DMatrix<f64>, dx: &[f64], rcond: f64, dtheta: &mut [f64]) -> std::result::Result<(), FitFailure> {
    let (m, n) = j.shape();
    if m > n {
        return pinv_apply_svd(j, dx, rcond, dtheta);
    }
    let rcond = rcond.max(MIN_RCOND);
    let jjt = j * j.transpose();
    if !jjt.iter().all(|v| v.is_finite()) {
        return Err(FitFailure::Degenerate);
    }
    let eig = jjt.symmetric_eigen();
    let smax2 = eig.eigenvalues.iter().cloned().fold(0.0f64, f64::max);
    if !(smax2.is_finite() && smax2 > 0.0) {
        return Err(FitFailure::Degenerate);
    }
    let cut = rcond * rcond * smax2;
    // y = U S^-2 U^T dx, then dtheta = J^T y.
    let mut y = vec![0.0; m];
    for c in 0..m {
        let s2 = eig.eigenvalues[c];
        if s2 <= cut {
            continue;
        }
        let u = eig.eigenvectors.column(c);
        let proj: f64 = (0..m).map(|r| u[r] * dx[r]).sum::<f64>() / s2;
        for r in 0..m {
            y[r] += u[r] * proj;
        }
    }
    for (a, out) in dtheta.iter_mut().enumerate() {
        *out = (0..m).map(|r| j[(r, a)] * y[r]).sum();
    }
    if !dtheta.iter().all(|v| v.is_finite()) {
        return Err(FitFailure::Degenerate);
    }
    Ok(())
}

/// Apply the Moore-Penrose pseudo-inverse of `j` (m x n) to `dx`, dropping singular values below
/// `rcond * sigma_max`: through J J^T for a wide J (the arm's case), by SVD otherwise.
pub fn pinv_apply(j: &DMatrix<f64>, dx: &[f64], rcond: f64, dtheta: &mut [f64]) -> std::result::Result<(), FitFailure> {
    pinv_apply_wide(j, dx, rcond, dtheta)
}

/// The same by nalgebra's SVD. Not used for wide matrices: nalgebra 0.35's SVD can be wrong on
/// exactly rank-one wide inputs (nalgebra issue 1172).
pub fn pinv_apply_svd(j: &DMatrix<f64>, dx: &[f64], rcond: f64, dtheta: &mut [f64]) -> std::result::Result<(), FitFailure> {
    let svd = j.clone().svd(true, true);
    let smax = svd.singular_values.iter().cloned().fold(0.0f64, f64::max);
    if !(smax.is_finite() && smax > 0.0) {
        return Err(FitFailure::Degenerate);
    }
    let pinv = svd.pseudo_inverse(rcond * smax).map_err(|_| FitFailure::Degenerate)?;
    let r = pinv * DVector::from_column_slice(dx);
    if !r.iter().all(|v| v.is_finite()) {
        return Err(FitFailure::Degenerate);
    }
    dtheta.copy_from_slice(r.as_slice());
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::model::memory::IndexKind;
    use crate::rng::{rng_from_seed, uniform};

    fn random_matrix(m: usize, n: usize, seed: u64) -> DMatrix<f64> {
        let mut r = rng_from_seed(seed);
        DMatrix::from_fn(m, n, |_, _| uniform(&mut r, -1.0, 1.0))
    }

    fn pinv(j: &DMatrix<f64>) -> DMatrix<f64> {
        let mut p = DMatrix::zeros(j.ncols(), j.nrows());
        for c in 0..j.nrows() {
            let mut e = vec![0.0; j.nrows()];
            e[c] = 1.0;
            let mut col = vec![0.0; j.ncols()];
            pinv_apply(j, &e, 1e-12, &mut col).unwrap();
            p.set_column(c, &DVector::from_vec(col));
        }
        p
    }

    #[test]
    fn penrose_identities() {
        for (seed, (m, n)) in [(2, 15), (3, 7), (2, 2)].iter().enumerate() {
            let j = random_matrix(*m, *n, seed as u64);
            let p = pinv(&j);
            assert!((&j * &p * &j - &j).norm() < 1e-10);
            assert!((&p * &j * &p - &p).norm() < 1e-10);
            assert!(((&j * &p).transpose() - &j * &p).norm() < 1e-10);
            assert!(((&p * &j).transpose() - &p * &j).norm() < 1e-10);
        }
    }

    #[test]
    fn eigen_route_equals_svd_pseudo_inverse() {
        for seed in 0..20u64 {
            let j = random_matrix(2, 15, seed);
            let dx = [0.3, -0.4];
            let (mut a, mut b) = (vec![0.0; 15], vec![0.0; 15]);
            pinv_apply_svd(&j, &dx, 1e-2, &mut a).unwrap();
            pinv_apply_wide(&j, &dx, 1e-2, &mut b).unwrap();
            for (x, y) in a.iter().zip(&b) {
                assert!((x - y).abs() < 1e-10 * (1.0 + x.abs()), "{x} vs {y}");
            }
        }
        // Rank one: both drop the null direction.
        let j = DMatrix::from_row_slice(2, 3, &[0.0, 0.0, 0.0, 3.0, 2.0, 1.0]);
        let (mut a, mut b) = (vec![0.0; 3], vec![0.0; 3]);
        pinv_apply_svd(&j, &[1.0, 1.0], 1e-6, &mut a).unwrap();
        pinv_apply_wide(&j, &[1.0, 1.0], 1e-6, &mut b).unwrap();
        assert!(a.iter().zip(&b).all(|(x, y)| (x - y).abs() < 1e-12));
        assert_eq!(pinv_apply_wide(&DMatrix::zeros(2, 3), &[1.0, 0.0], 1e-6, &mut b), Err(FitFailure::Degenerate));
    }

    #[test]
    fn rank_deficient_jacobian_is_handled() {
        // A straight arm: every joint moves the tip along y only, J has rank 1.
        let j = DMatrix::from_row_slice(2, 3, &[0.0, 0.0, 0.0, 3.0, 2.0, 1.0]);
        let mut d = vec![0.0; 3];
        pinv_apply(&j, &[1.0, 1.0], 1e-6, &mut d).unwrap();
        let dx = &j * DVector::from_column_slice(&d);
        assert!((dx[0]).abs() < 1e-12 && (dx[1] - 1.0).abs() < 1e-12);
        let zero = DMatrix::zeros(2, 3);
        assert_eq!(pinv_apply(&zero, &[1.0, 0.0], 1e-6, &mut d), Err(FitFailure::Degenerate));
    }

    #[test]
    fn fit_recovers_a_linear_map() {
        let (n, m) = (6, 2);
        let truth = random_matrix(m, n, 9);
        let mut mem = SensorimotorMemory::new(n, m, IndexKind::BruteForce);
        let mut r = rng_from_seed(1);
        for _ in 0..40 {
            let th: Vec<f64> = (0..n).map(|_| uniform(&mut r, -0.1, 0.1)).collect();
            let d: Vec<f64> = (0..n).map(|_| uniform(&mut r, -0.01, 0.01)).collect();
            let dx = &truth * DVector::from_vec(d.clone());
            mem.add(&th, &d, dx.as_slice(), &[0.0, 0.0]);
        }
        let mut lm = LocalModel::new(n, m, LocalModelConfig { k_neighbours: 30, ridge: 1e-9, pinv_rcond: 1e-6, bandwidth: 0.0 });
        let mut nb = Vec::new();
        mem.knn(&vec![0.0; n], 30, &mut nb);
        lm.fit(&mem, &nb).unwrap();
        assert!((lm.jacobian() - &truth).norm() < 1e-5);
    }

    /// The fit's kernels (tiled Gram sums, prefetches, solves side by side) give the bits of
    /// the plain formula: running sums over the neighbours in order, nalgebra's Cholesky.
    #[test]
    fn fit_gives_the_bits_of_the_plain_formula() {
        let (n, m, k) = (15, 2, 45);
        let mut mem = SensorimotorMemory::new(n, m, IndexKind::Blocks);
        let mut r = rng_from_seed(7);
        for _ in 0..3000 {
            let th: Vec<f64> = (0..n).map(|_| uniform(&mut r, -1.0, 1.0)).collect();
            let d: Vec<f64> = (0..n).map(|_| uniform(&mut r, -0.05, 0.05)).collect();
            let dx: Vec<f64> = (0..m).map(|j| d.iter().enumerate().map(|(a, v)| v * ((a + j) as f64).cos()).sum::<f64>() + uniform(&mut r, -1e-3, 1e-3)).collect();
            mem.add(&th, &d, &dx, &[0.0; 2]);
        }
        let cfg = LocalModelConfig { k_neighbours: k, ridge: 1e-3, pinv_rcond: 1e-2, bandwidth: 1.0 };
        let mut lm = LocalModel::new(n, m, cfg.clone());
        let mut nb = Vec::new();
        for q in 0..20 {
            let query: Vec<f64> = (0..n).map(|a| ((q * n + a) as f64).sin()).collect();
            mem.knn(&query, k, &mut nb);
            lm.fit(&mem, &nb).unwrap();
            let h2 = nb[k / 2].dist_sq.max(1e-300) * cfg.bandwidth;
            let (mut g, mut rhs) = (DMatrix::<f64>::zeros(n, n), DMatrix::<f64>::zeros(n, m));
            for e in &nb {
                let w = (-e.dist_sq / h2).exp();
                let (dth, dx) = (mem.dtheta(e.id as usize), mem.dx(e.id as usize));
                for a in 0..n {
                    for b in 0..n {
                        // Column a, row b: the product the fit forms for its lower triangle.
                        g[(b, a)] += (w * dth[a]) * dth[b];
                    }
                    for j in 0..m {
                        rhs[(a, j)] += (w * dth[a]) * dx[j];
                    }
                }
            }
            let trace: f64 = (0..n).map(|a| g[(a, a)]).sum();
            for a in 0..n {
                g[(a, a)] += cfg.ridge * trace / n as f64;
            }
            let jt = g.cholesky().unwrap().solve(&rhs);
            for a in 0..n {
                for j in 0..m {
                    assert_eq!(lm.jacobian()[(j, a)].to_bits(), jt[(a, j)].to_bits(), "query {q}, J[{j}, {a}]");
                }
            }
        }
    }

    #[test]
    fn degenerate_data_is_refused() {
        let mut mem = SensorimotorMemory::new(3, 2, IndexKind::BruteForce);
        for _ in 0..5 {
            mem.add(&[0.0; 3], &[0.0; 3], &[0.0; 2], &[0.0; 2]);
        }
        let mut lm = LocalModel::new(3, 2, LocalModelConfig { k_neighbours: 5, ridge: 1e-3, pinv_rcond: 1e-2, bandwidth: 1.0 });
        let mut nb = Vec::new();
        mem.knn(&[0.0; 3], 5, &mut nb);
        assert_eq!(lm.fit(&mem, &nb), Err(FitFailure::Degenerate));
        let mut small = LocalModel::new(3, 2, LocalModelConfig { k_neighbours: 10, ridge: 1e-3, pinv_rcond: 1e-2, bandwidth: 1.0 });
        assert_eq!(small.fit(&mem, &nb), Err(FitFailure::NotEnoughData));
        assert!(!mem.add(&[f64::NAN; 3], &[0.0; 3], &[0.0; 2], &[0.0; 2]));
        assert_eq!((mem.len(), mem.rejected()), (5, 1));
    }
}

//! SPDL's context distributions: Gaussians in the box scaled to [0, 1], with a diagonal or a full
//! covariance held by its Cholesky factor L (Sigma = L L^T), as the authors' code holds them: the
//! means, the logs of L's diagonal and L's entries below its diagonal. The optimisers see these
//! numbers as one vector (`vars`); the alpha form's natural-gradient step uses the gradients and
//! the Fisher-vector product written here (checked against finite differences in the tests).

use nalgebra::{DMatrix, DVector};
use serde::{Deserialize, Serialize};

use crate::rng::{normal, CoreRng};

/// A Gaussian in the unit box. A diagonal one has no `lower` entries; a full one has all
/// d (d - 1) / 2 of them (zeros included), and its optimisers move them.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Gaussian {
    pub mean: Vec<f64>,
    /// Logs of the Cholesky factor's diagonal: the log standard deviations when diagonal.
    pub log_std: Vec<f64>,
    /// The factor's entries below its diagonal, row by row: (1, 0), (2, 0), (2, 1), ...; empty
    /// for a diagonal covariance.
    pub lower: Vec<f64>,
}

/// Where L's entry (i, j), i > j, sits in `lower`.
fn at(i: usize, j: usize) -> usize {
    i * (i - 1) / 2 + j
}

impl Gaussian {
    /// N(mean, diag(std^2)), diagonal (`full`: with its d (d - 1) / 2 correlations free to move).
    pub fn diagonal(mean: Vec<f64>, std: &[f64], full: bool) -> Self {
        let d = mean.len();
        Gaussian { mean, log_std: std.iter().map(|s| s.ln()).collect(), lower: if full { vec![0.0; d * (d - 1) / 2] } else { Vec::new() } }
    }

    /// N(mean, cov), cov row by row; None unless it is positive definite. Not `full`: only its
    /// diagonal is kept.
    pub fn from_covariance(mean: Vec<f64>, cov: &[f64], full: bool) -> Option<Self> {
        let d = mean.len();
        if !full {
            let std: Vec<f64> = (0..d).map(|i| cov[i * d + i].sqrt()).collect();
            return std.iter().all(|s| s.is_finite() && *s > 0.0).then(|| Gaussian::diagonal(mean, &std, false));
        }
        let l = DMatrix::from_row_slice(d, d, cov).cholesky()?.unpack();
        let log_std: Vec<f64> = (0..d).map(|i| l[(i, i)].ln()).collect();
        let lower = (1..d).flat_map(|i| (0..i).map(move |j| (i, j))).map(|(i, j)| l[(i, j)]).collect();
        log_std.iter().all(|v| v.is_finite()).then_some(Gaussian { mean, log_std, lower })
    }

    pub fn dim(&self) -> usize {
        self.mean.len()
    }

    fn is_diagonal(&self) -> bool {
        self.lower.iter().all(|v| *v == 0.0)
    }

    /// The Cholesky factor L.
    pub fn factor(&self) -> DMatrix<f64> {
        let d = self.dim();
        DMatrix::from_fn(d, d, |i, j| match i.cmp(&j) {
            std::cmp::Ordering::Equal => self.log_std[i].exp(),
            std::cmp::Ordering::Greater if !self.lower.is_empty() => self.lower[at(i, j)],
            _ => 0.0,
        })
    }

    /// The covariance L L^T.
    pub fn covariance(&self) -> DMatrix<f64> {
        let l = self.factor();
        &l * l.transpose()
    }

    /// The standard deviation of each dimension.
    pub fn std(&self) -> Vec<f64> {
        if self.is_diagonal() {
            return self.log_std.iter().map(|s| s.exp()).collect();
        }
        let c = self.covariance();
        (0..self.dim()).map(|i| c[(i, i)].sqrt()).collect()
    }

    /// z = L^-1 (x - mean).
    fn whiten(&self, x: &[f64]) -> DVector<f64> {
        let r = DVector::from_iterator(self.dim(), x.iter().zip(&self.mean).map(|(a, m)| a - m));
        self.factor().solve_lower_triangular(&r).unwrap_or(r)
    }

    pub fn log_pdf(&self, x: &[f64]) -> f64 {
        let half_ln_2pi = 0.5 * (2.0 * std::f64::consts::PI).ln();
        if self.is_diagonal() {
            let mut s = 0.0;
            for ((xi, m), ls) in x.iter().zip(&self.mean).zip(&self.log_std) {
                let z = (xi - m) / ls.exp();
                s += -0.5 * z * z - ls - half_ln_2pi;
            }
            return s;
        }
        let z = self.whiten(x);
        -0.5 * z.norm_squared() - self.log_std.iter().sum::<f64>() - self.dim() as f64 * half_ln_2pi
    }

    /// A draw: mean + L z, z standard normal (d draws of the generator, in order).
    pub fn sample(&self, rng: &mut CoreRng) -> Vec<f64> {
        if self.is_diagonal() {
            return self.mean.iter().zip(&self.log_std).map(|(m, ls)| m + ls.exp() * normal(rng)).collect();
        }
        let z = DVector::from_fn(self.dim(), |_, _| normal(rng));
        let lz = self.factor() * z;
        self.mean.iter().zip(lz.iter()).map(|(m, v)| m + v).collect()
    }

    /// KL(self || other), closed form.
    pub fn kl(&self, other: &Gaussian) -> f64 {
        let d = self.dim();
        if self.is_diagonal() && other.is_diagonal() {
            let mut s = 0.0;
            for i in 0..d {
                let (v1, v2) = ((2.0 * self.log_std[i]).exp(), (2.0 * other.log_std[i]).exp());
                let dm = self.mean[i] - other.mean[i];
                s += 0.5 * ((v1 + dm * dm) / v2 - 1.0) + other.log_std[i] - self.log_std[i];
            }
            return s;
        }
        // tr(S2^-1 S1) = |L2^-1 L1|_F^2; the mean's term |L2^-1 (m1 - m2)|^2.
        let l2 = other.factor();
        let a = l2.solve_lower_triangular(&self.factor()).unwrap_or_else(|| DMatrix::from_element(d, d, f64::INFINITY));
        let dm = other.whiten(&self.mean);
        let logdet: f64 = other.log_std.iter().zip(&self.log_std).map(|(b, a)| b - a).sum();
        0.5 * (a.norm_squared() + dm.norm_squared() - d as f64) + logdet
    }

    /// The parameters as one vector: means, log diagonal, then the entries below it.
    pub fn vars(&self) -> Vec<f64> {
        self.mean.iter().chain(&self.log_std).chain(&self.lower).copied().collect()
    }

    /// A Gaussian of this one's shape with the parameters `v`.
    pub fn with_vars(&self, v: &[f64]) -> Gaussian {
        let d = self.dim();
        Gaussian { mean: v[..d].to_vec(), log_std: v[d..2 * d].to_vec(), lower: v[2 * d..].to_vec() }
    }

    /// Bounds of the parameters the optimisers keep to: means in [-1, 2] (the unit box and as
    /// much again around it), L's diagonal in [1e-4, 10], its other entries in [-10, 10].
    pub fn var_bounds(&self) -> Vec<(f64, f64)> {
        let d = self.dim();
        let (m, s) = ((-1.0, 2.0), (1e-4f64.ln(), 10f64.ln()));
        std::iter::repeat_n(m, d).chain(std::iter::repeat_n(s, d)).chain(std::iter::repeat_n((-10.0, 10.0), self.lower.len())).collect()
    }

    /// Lower(M) as parameters: a mean part `mean`, then M's diagonal times L's (the chain rule
    /// through the log) minus `shift`, then M's entries below the diagonal if full.
    fn pack(&self, mean: DVector<f64>, m: &DMatrix<f64>, l: &DMatrix<f64>, shift: f64) -> Vec<f64> {
        let d = self.dim();
        let mut out: Vec<f64> = mean.iter().copied().collect();
        out.extend((0..d).map(|i| m[(i, i)] * l[(i, i)] - shift));
        if !self.lower.is_empty() {
            out.extend((1..d).flat_map(|i| (0..i).map(move |j| (i, j))).map(|(i, j)| m[(i, j)]));
        }
        out
    }

    /// The gradient of log p(x) in the parameters: with z = L^-1 (x - mean) and u = L^-T z,
    /// d/dmean = u and d/dL = lower(u z^T) - diag(1 / L_ii).
    pub fn grad_log_pdf(&self, x: &[f64]) -> Vec<f64> {
        let l = self.factor();
        let z = self.whiten(x);
        let u = l.transpose().solve_upper_triangular(&z).unwrap_or_else(|| z.clone());
        self.pack(u.clone(), &(&u * z.transpose()), &l, 1.0)
    }

    /// The gradient of KL(self || target) in self's parameters: d/dmean = S_t^-1 (mean - mean_t)
    /// and d/dL = lower(S_t^-1 L) - diag(1 / L_ii).
    pub fn grad_kl(&self, target: &Gaussian) -> Vec<f64> {
        let d = self.dim();
        let lt = target.factor();
        let st_inv = |m: DMatrix<f64>| -> DMatrix<f64> {
            let y = lt.solve_lower_triangular(&m).unwrap_or_else(|| m.clone());
            lt.transpose().solve_upper_triangular(&y).unwrap_or(y)
        };
        let dm = DMatrix::from_iterator(d, 1, self.mean.iter().zip(&target.mean).map(|(a, b)| a - b));
        let l = self.factor();
        let g_mean = st_inv(dm).column(0).into_owned();
        self.pack(g_mean, &st_inv(l.clone()), &l, 1.0)
    }

    /// F v: the Hessian of KL(self || p) in p's parameters at p = self (the Fisher information)
    /// times `v`. The mean's block is S^-1; the factor's is 1/2 tr(S^-1 dS S^-1 dS'), which for
    /// dS = V L^T + L V^T gives lower(S^-1 dS S^-1 L).
    pub fn fisher_times(&self, v: &[f64]) -> Vec<f64> {
        let d = self.dim();
        let l = self.factor();
        let s_inv = |m: DMatrix<f64>| -> DMatrix<f64> {
            let y = l.solve_lower_triangular(&m).unwrap_or_else(|| m.clone());
            l.transpose().solve_upper_triangular(&y).unwrap_or(y)
        };
        let vm = DMatrix::from_column_slice(d, 1, &v[..d]);
        let mut dv = DMatrix::zeros(d, d);
        for i in 0..d {
            dv[(i, i)] = v[d + i] * l[(i, i)];
        }
        if !self.lower.is_empty() {
            for i in 1..d {
                for j in 0..i {
                    dv[(i, j)] = v[2 * d + at(i, j)];
                }
            }
        }
        let ds = &dv * l.transpose() + &l * dv.transpose();
        let m = s_inv(s_inv(ds).transpose());
        self.pack(s_inv(vm).column(0).into_owned(), &(m * &l), &l, 0.0)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::rng::rng_from_seed;

    fn full() -> Gaussian {
        Gaussian { mean: vec![0.3, 0.6, 0.5], log_std: vec![-1.2, -0.7, -1.6], lower: vec![0.05, -0.08, 0.02] }
    }

    fn numeric(f: impl Fn(&[f64]) -> f64, x: &[f64]) -> Vec<f64> {
        (0..x.len())
            .map(|k| {
                let (mut a, mut b) = (x.to_vec(), x.to_vec());
                a[k] += 1e-6;
                b[k] -= 1e-6;
                (f(&a) - f(&b)) / 2e-6
            })
            .collect()
    }

    fn close(a: &[f64], b: &[f64], tol: f64) {
        assert_eq!(a.len(), b.len());
        for (x, y) in a.iter().zip(b) {
            assert!((x - y).abs() <= tol * (1.0 + y.abs()), "{a:?}\n{b:?}");
        }
    }

    #[test]
    fn diagonal_and_full_agree_where_the_full_one_has_no_correlation() {
        let (a, b) = (Gaussian::diagonal(vec![0.2, 0.7], &[0.1, 0.3], false), Gaussian::diagonal(vec![0.2, 0.7], &[0.1, 0.3], true));
        let t = Gaussian::diagonal(vec![0.5, 0.5], &[0.25, 0.25], false);
        for x in [[0.1, 0.9], [0.5, 0.5]] {
            assert!((a.log_pdf(&x) - b.log_pdf(&x)).abs() < 1e-12);
        }
        assert!((a.kl(&t) - b.kl(&t)).abs() < 1e-12);
        // KL(N(0,1) || N(1,4)) = ln 2 + (1 + 1) / 8 - 1/2.
        let (p, q) = (Gaussian::diagonal(vec![0.0], &[1.0], false), Gaussian::diagonal(vec![1.0], &[2.0], false));
        assert!((p.kl(&q) - (2f64.ln() + 0.25 - 0.5)).abs() < 1e-12);
    }

    #[test]
    fn a_covariance_round_trips_through_its_factor_and_its_draws() {
        let cov = [0.04, 0.01, 0.0, 0.01, 0.09, -0.02, 0.0, -0.02, 0.16];
        let g = Gaussian::from_covariance(vec![0.5; 3], &cov, true).unwrap();
        close(g.covariance().as_slice(), &cov, 1e-12);
        assert!(Gaussian::from_covariance(vec![0.5; 2], &[1.0, 2.0, 2.0, 1.0], true).is_none());
        let mut rng = rng_from_seed(4);
        let n = 40_000;
        let xs: Vec<Vec<f64>> = (0..n).map(|_| g.sample(&mut rng)).collect();
        let c01 = xs.iter().map(|x| (x[0] - 0.5) * (x[1] - 0.5)).sum::<f64>() / n as f64;
        assert!((c01 - 0.01).abs() < 0.002, "{c01}");
        // The mean log-density of its draws is minus its entropy.
        let ent = 0.5 * (3.0 * (1.0 + (2.0 * std::f64::consts::PI).ln())) + g.log_std.iter().sum::<f64>();
        let mean_lp = xs.iter().map(|x| g.log_pdf(x)).sum::<f64>() / n as f64;
        assert!((mean_lp + ent).abs() < 0.03, "{mean_lp} {ent}");
    }

    #[test]
    fn gradients_and_the_fisher_product_match_finite_differences() {
        for g in [full(), Gaussian::diagonal(vec![0.3, 0.6, 0.5], &[0.3, 0.5, 0.2], false)] {
            let x = [0.1, 0.8, 0.45];
            close(&g.grad_log_pdf(&x), &numeric(|v| g.with_vars(v).log_pdf(&x), &g.vars()), 1e-5);
            let t = Gaussian { mean: vec![0.5; 3], log_std: vec![-1.0; 3], lower: vec![0.1, 0.0, -0.05] };
            close(&g.grad_kl(&t), &numeric(|v| g.with_vars(v).kl(&t), &g.vars()), 1e-5);
            // F v: the Hessian of p -> KL(g || p) at p = g times v, by finite differences of
            // that function's gradient along v.
            let v: Vec<f64> = (0..g.vars().len()).map(|k| 0.3 - 0.1 * k as f64).collect();
            let fd: Vec<f64> = {
                let grad = |w: &[f64]| numeric(|u| g.kl(&g.with_vars(u)), w);
                let base = g.vars();
                let (mut a, mut b) = (base.clone(), base.clone());
                for k in 0..base.len() {
                    a[k] += 1e-4 * v[k];
                    b[k] -= 1e-4 * v[k];
                }
                grad(&a).iter().zip(grad(&b)).map(|(p, q)| (p - q) / 2e-4).collect()
            };
            close(&g.fisher_times(&v), &fd, 1e-3);
        }
    }
}

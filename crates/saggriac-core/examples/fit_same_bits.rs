//! Checks that `LocalModel::fit`, `pinv_apply_wide` and `predict_x` give the same bits as the
//! code they replaced (kept below as `before`), on random neighbour sets over several shapes:
//! `cargo run --release --example fit_same_bits -- [cases]`. Panics at the first difference.

use saggriac_core::model::local_model::{pinv_apply_wide, LocalModel, LocalModelConfig};
use saggriac_core::model::memory::{IndexKind, SensorimotorMemory};
use saggriac_core::model::neighbours::Neighbour;
use saggriac_core::rng::{index, rng_from_seed, uniform, CoreRng};
/// The fit and pseudo-inverse as they were before the allocation-free rewrite, kept to check
/// that the rewrite gives the same bits.
mod before {
    use nalgebra::DMatrix;
    use saggriac_core::model::local_model::{FitFailure, LocalModelConfig, MIN_RCOND};
    use saggriac_core::model::memory::SensorimotorMemory;
    use saggriac_core::model::neighbours::{dist_sq, Neighbour};

    pub fn fit(cfg: &LocalModelConfig, n: usize, m: usize, mem: &SensorimotorMemory, neighbours: &[Neighbour]) -> Result<DMatrix<f64>, FitFailure> {
        if neighbours.len() < cfg.k_neighbours.min(mem.len()).max(1) || mem.len() < cfg.k_neighbours {
            return Err(FitFailure::NotEnoughData);
        }
        let mut gram_buf = vec![0.0; n * n];
        let mut rhs_buf = vec![0.0; n * m];
        let h2 = neighbours[neighbours.len() / 2].dist_sq.max(1e-300) * cfg.bandwidth;
        let mut wd = vec![0.0; n];
        for nb in neighbours {
            let w = if cfg.bandwidth > 0.0 { (-nb.dist_sq / h2).exp() } else { 1.0 };
            let dth = mem.dtheta(nb.id as usize);
            let dx = mem.dx(nb.id as usize);
            for (o, d) in wd.iter_mut().zip(dth) {
                *o = w * d;
            }
            for a in 0..n {
                let da = wd[a];
                let row = &mut gram_buf[a * n..(a + 1) * n];
                for (g, d) in row[a..].iter_mut().zip(&dth[a..]) {
                    *g += da * d;
                }
                let r = &mut rhs_buf[a * m..(a + 1) * m];
                for (o, x) in r.iter_mut().zip(dx) {
                    *o += da * x;
                }
            }
        }
        let trace: f64 = (0..n).map(|a| gram_buf[a * n + a]).sum();
        if !(trace.is_finite() && trace > 0.0) {
            return Err(FitFailure::Degenerate);
        }
        let lambda = cfg.ridge * trace / n as f64;
        let (mut gram, mut rhs) = (DMatrix::zeros(n, n), DMatrix::zeros(n, m));
        for a in 0..n {
            for b in a..n {
                let v = gram_buf[a * n + b] + if a == b { lambda } else { 0.0 };
                gram[(a, b)] = v;
                gram[(b, a)] = v;
            }
            for j in 0..m {
                rhs[(a, j)] = rhs_buf[a * m + j];
            }
        }
        let chol = gram.clone().cholesky().ok_or(FitFailure::Degenerate)?;
        let jt = chol.solve(&rhs);
        if !jt.iter().all(|v| v.is_finite()) {
            return Err(FitFailure::Degenerate);
        }
        Ok(jt.transpose())
    }

    /// `thetas` holds the stored configurations row by row (instead of `mem.theta`).
    pub fn predict_x(jac: &DMatrix<f64>, n: usize, mem: &SensorimotorMemory, thetas: &[f64], neighbours: &[Neighbour], theta: &[f64], out: &mut [f64]) {
        let stored = |i: u32| &thetas[i as usize * n..(i as usize + 1) * n];
        let k = neighbours.len().max(1) as f64;
        let mut centre = vec![0.0; n];
        out.iter_mut().for_each(|v| *v = 0.0);
        for nb in neighbours {
            for (c, t) in centre.iter_mut().zip(stored(nb.id)) {
                *c += t / k;
            }
            for (o, x) in out.iter_mut().zip(mem.x(nb.id as usize)) {
                *o += x / k;
            }
        }
        let radius = neighbours.iter().map(|nb| dist_sq(stored(nb.id), &centre)).fold(0.0, f64::max).sqrt();
        let mut d: Vec<f64> = theta.iter().zip(&centre).map(|(t, c)| t - c).collect();
        let norm = d.iter().map(|v| v * v).sum::<f64>().sqrt();
        if norm > radius && norm > 0.0 {
            d.iter_mut().for_each(|v| *v *= radius / norm);
        }
        for (j, o) in out.iter_mut().enumerate() {
            *o += (0..n).map(|a| jac[(j, a)] * d[a]).sum::<f64>();
        }
    }

    pub fn pinv_apply_wide(j: &DMatrix<f64>, dx: &[f64], rcond: f64, dtheta: &mut [f64]) -> Result<(), FitFailure> {
        let m = j.nrows();
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
}

fn same_bits(a: &[f64], b: &[f64]) -> bool {
    a.len() == b.len() && a.iter().zip(b).all(|(x, y)| x.to_bits() == y.to_bits())
}

/// A value of a sample: mostly uniform at `scale`, sometimes an exact (signed) zero, a tiny or
/// a repeated value, so that sums of zeros and ties happen.
fn sample_value(r: &mut CoreRng, scale: f64) -> f64 {
    match index(r, 20) {
        0 => 0.0,
        1 => -0.0,
        2 => 1e-160 * uniform(r, -1.0, 1.0),
        3 => scale,
        _ => uniform(r, -scale, scale),
    }
}

fn main() {
    let cases: usize = std::env::args().nth(1).and_then(|v| v.parse().ok()).unwrap_or(20_000);
    let mut r = rng_from_seed(77);
    let shapes = [(15, 2), (15, 3), (6, 2), (7, 7), (3, 1), (1, 1), (9, 6)];
    let (mut compared, mut fitted) = (0usize, 0usize);
    for &(n, m) in &shapes {
        let mut mem = SensorimotorMemory::new(n, m, IndexKind::BruteForce);
        let mut thetas = Vec::new();
        for i in 0..300 {
            let th: Vec<f64> = (0..n).map(|_| uniform(&mut r, -1.0, 1.0)).collect();
            // Some samples without joint motion, as a blocked arm stores.
            let scale = if i % 17 == 0 { 0.0 } else { 0.05 };
            let d: Vec<f64> = (0..n).map(|_| sample_value(&mut r, scale)).collect();
            let dx: Vec<f64> = (0..m).map(|_| sample_value(&mut r, 2.0)).collect();
            let x: Vec<f64> = (0..m).map(|_| sample_value(&mut r, 30.0)).collect();
            assert!(mem.add(&th, &d, &dx, &x));
            thetas.extend_from_slice(&th);
        }
        let mut models: Vec<(LocalModelConfig, LocalModel)> = [(45, 1e-3, 1.0), (10, 1e-9, 0.0), (3, 0.0, 2.0), (60, 1e-1, 0.5)]
            .iter()
            .map(|&(k, ridge, bandwidth)| {
                let cfg = LocalModelConfig { k_neighbours: k, ridge, pinv_rcond: 1e-2, bandwidth };
                (cfg.clone(), LocalModel::new(n, m, cfg))
            })
            .collect();
        let mut nb = Vec::new();
        for c in 0..cases / shapes.len() {
            let (cfg, model) = &mut models[c % 4];
            let k = cfg.k_neighbours + index(&mut r, 4);
            if c % 3 == 0 {
                // Arbitrary ids with duplicates and unsorted distances.
                nb = (0..k).map(|_| Neighbour { id: index(&mut r, mem.len()) as u32, dist_sq: sample_value(&mut r, 3.0).abs() }).collect();
            } else {
                let q: Vec<f64> = (0..n).map(|_| uniform(&mut r, -1.0, 1.0)).collect();
                mem.knn(&q, k, &mut nb);
            }
            let new = model.fit(&mem, &nb).map(|_| model.jacobian().clone());
            let old = before::fit(cfg, n, m, &mem, &nb);
            match (&new, &old) {
                (Ok(a), Ok(b)) => assert!(same_bits(a.as_slice(), b.as_slice()), "J differs for n {n} m {m} case {c}"),
                _ => assert_eq!(new.as_ref().err(), old.as_ref().err(), "n {n} m {m} case {c}"),
            }
            compared += 1;
            let Ok(j) = old else { continue };
            fitted += 1;
            // Near the neighbours (inside their radius) and far away (shortened).
            let spread = [0.01, 10.0][c % 2];
            let near = nb[0].id as usize * n;
            let theta: Vec<f64> = thetas[near..near + n].iter().map(|t| t + uniform(&mut r, -spread, spread)).collect();
            let (mut pa, mut pb) = (vec![0.0; m], vec![0.0; m]);
            model.predict_x(&mem, &nb, &theta, &mut pa);
            before::predict_x(&j, n, &mem, &thetas, &nb, &theta, &mut pb);
            assert!(same_bits(&pa, &pb), "prediction differs for n {n} m {m} case {c}");
            let dx: Vec<f64> = (0..m).map(|_| sample_value(&mut r, 1.0)).collect();
            let (mut a, mut b) = (vec![0.0; n], vec![0.0; n]);
            let rcond = [1e-2, 1e-6, 0.5][c % 3];
            let (ra, rb) = (pinv_apply_wide(&j, &dx, rcond, &mut a), before::pinv_apply_wide(&j, &dx, rcond, &mut b));
            assert_eq!(ra, rb);
            assert!(ra.is_err() || same_bits(&a, &b), "pinv differs for n {n} m {m} case {c}");
        }
    }
    assert!(fitted > compared / 2, "{fitted} of {compared} fits succeeded");
    println!("same bits on {compared} fits ({fitted} fitted: J, pinv step and prediction compared)");
}

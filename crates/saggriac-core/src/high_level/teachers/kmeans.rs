//! k-means clustering: k-means++ seeding (Arthur & Vassilvitskii, 2007) and Lloyd's iterations,
//! the start of the mixtures' EM (`gmm.rs`), as scikit-learn's default start.

use nalgebra::DVector;

use crate::rng::{index, unit, CoreRng};

/// The cluster of each sample after k-means++ seeding and Lloyd's iterations.
pub(crate) fn labels(data: &[DVector<f64>], k: usize, rng: &mut CoreRng) -> Vec<usize> {
    let n = data.len();
    let mut centres = vec![data[index(rng, n)].clone()];
    // Each sample's squared distance to its nearest centre so far, brought up to date with the
    // newest centre only (a running minimum: the same values as a minimum over all centres).
    let mut d2 = vec![f64::INFINITY; n];
    let mut seen = 0;
    while centres.len() < k {
        for c in &centres[seen..] {
            for (m, x) in d2.iter_mut().zip(data) {
                *m = m.min((x - c).norm_squared());
            }
        }
        seen = centres.len();
        let total: f64 = d2.iter().sum();
        if total <= 0.0 || total.is_nan() {
            centres.push(data[index(rng, n)].clone());
            continue;
        }
        let mut u = unit(rng) * total;
        let mut pick = n - 1;
        for (i, v) in d2.iter().enumerate() {
            if u < *v {
                pick = i;
                break;
            }
            u -= v;
        }
        centres.push(data[pick].clone());
    }
    let mut labels = vec![0usize; n];
    let d = data[0].len();
    let (mut sums, mut counts) = (vec![0.0; k * d], vec![0usize; k]);
    let mut dist = vec![0.0; k];
    for _ in 0..100 {
        let mut changed = false;
        for (i, x) in data.iter().enumerate() {
            // Each distance once (the comparison below would otherwise compute two per step).
            for (dc, c) in dist.iter_mut().zip(&centres) {
                *dc = x.iter().zip(c.iter()).map(|(a, b)| (a - b) * (a - b)).sum::<f64>();
            }
            let best = (0..k).min_by(|&a, &b| dist[a].total_cmp(&dist[b])).unwrap_or(0);
            changed |= best != labels[i];
            labels[i] = best;
        }
        sums.iter_mut().for_each(|v| *v = 0.0);
        counts.iter_mut().for_each(|v| *v = 0);
        for (x, &l) in data.iter().zip(&labels) {
            counts[l] += 1;
            for (s, v) in sums[l * d..(l + 1) * d].iter_mut().zip(x.iter()) {
                *s += v;
            }
        }
        for (j, c) in centres.iter_mut().enumerate() {
            if counts[j] > 0 {
                *c = DVector::from_iterator(d, sums[j * d..(j + 1) * d].iter().map(|s| s / counts[j] as f64));
            }
        }
        if !changed {
            break;
        }
    }
    labels
}

//! A small multilayer perceptron for GoalGAN's generator and discriminator: dense layers with
//! ReLU between them, a linear last layer, backpropagation and Adam. Rows are samples. Written
//! here rather than taken from a deep-learning crate so that the core stays small and a saved
//! teacher holds its weights in its own encoding (checked against finite differences below).

use nalgebra::{DMatrix, DVector};

use crate::rng::{normal, CoreRng};

#[derive(Debug, Clone, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct Layer {
    /// in x out, row-major when saved.
    pub w: Vec<f64>,
    pub b: Vec<f64>,
    pub n_in: usize,
    pub n_out: usize,
}

/// Adam's moments for every parameter, in the order of `Mlp::params`.
#[derive(Debug, Clone, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct Adam {
    m: Vec<f64>,
    v: Vec<f64>,
    t: u64,
    lr: f64,
}

#[derive(Debug, Clone, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct Mlp {
    pub layers: Vec<Layer>,
    adam: Adam,
}

/// What the forward pass keeps for the backward pass: each layer's input and pre-activation.
pub struct Tape {
    inputs: Vec<DMatrix<f64>>,
    pre: Vec<DMatrix<f64>>,
}

impl Mlp {
    /// Sizes [in, hidden..., out]; He-initialised weights, zero biases.
    pub fn new(sizes: &[usize], lr: f64, rng: &mut CoreRng) -> Mlp {
        let layers: Vec<Layer> = sizes
            .windows(2)
            .map(|s| {
                let scale = (2.0 / s[0] as f64).sqrt();
                Layer { w: (0..s[0] * s[1]).map(|_| normal(rng) * scale).collect(), b: vec![0.0; s[1]], n_in: s[0], n_out: s[1] }
            })
            .collect();
        let n: usize = layers.iter().map(|l| l.w.len() + l.b.len()).sum();
        Mlp { layers, adam: Adam { m: vec![0.0; n], v: vec![0.0; n], t: 0, lr } }
    }

    fn w(l: &Layer) -> DMatrix<f64> {
        DMatrix::from_row_slice(l.n_in, l.n_out, &l.w)
    }

    pub fn forward(&self, x: &DMatrix<f64>) -> (DMatrix<f64>, Tape) {
        let mut tape = Tape { inputs: Vec::new(), pre: Vec::new() };
        let mut h = x.clone();
        let last = self.layers.len() - 1;
        for (i, l) in self.layers.iter().enumerate() {
            let mut z = &h * Self::w(l);
            let b = DVector::from_row_slice(&l.b);
            for mut row in z.row_iter_mut() {
                row += b.transpose();
            }
            tape.inputs.push(h);
            h = if i < last { z.map(|v| v.max(0.0)) } else { z.clone() };
            tape.pre.push(z);
        }
        (h, tape)
    }

    /// Gradients of a loss with respect to every parameter (order of `params`) and to the
    /// input, given dLoss/dOutput.
    pub fn backward(&self, tape: &Tape, grad_out: &DMatrix<f64>) -> (Vec<f64>, DMatrix<f64>) {
        let mut grads: Vec<Vec<f64>> = vec![Vec::new(); self.layers.len()];
        let mut g = grad_out.clone();
        let last = self.layers.len() - 1;
        for i in (0..self.layers.len()).rev() {
            if i < last {
                g.zip_apply(&tape.pre[i], |gv, z| {
                    if z <= 0.0 {
                        *gv = 0.0
                    }
                });
            }
            let gw = tape.inputs[i].transpose() * &g;
            let gb: Vec<f64> = g.column_iter().map(|c| c.sum()).collect();
            let mut flat: Vec<f64> = gw.transpose().iter().copied().collect(); // row-major
            flat.extend(gb);
            grads[i] = flat;
            g = &g * Self::w(&self.layers[i]).transpose();
        }
        (grads.concat(), g)
    }

    pub fn params(&self) -> Vec<f64> {
        self.layers.iter().flat_map(|l| l.w.iter().chain(&l.b).copied()).collect()
    }

    fn set_params(&mut self, p: &[f64]) {
        let mut k = 0;
        for l in &mut self.layers {
            let (nw, nb) = (l.w.len(), l.b.len());
            l.w.copy_from_slice(&p[k..k + nw]);
            l.b.copy_from_slice(&p[k + nw..k + nw + nb]);
            k += nw + nb;
        }
    }

    /// One Adam step (beta1 0.9, beta2 0.999, eps 1e-8) down the gradient.
    pub fn adam_step(&mut self, grad: &[f64]) {
        let mut p = self.params();
        let a = &mut self.adam;
        a.t += 1;
        let (b1, b2) = (0.9f64, 0.999f64);
        let (c1, c2) = (1.0 - b1.powi(a.t.min(100_000) as i32), 1.0 - b2.powi(a.t.min(100_000) as i32));
        for i in 0..p.len() {
            a.m[i] = b1 * a.m[i] + (1.0 - b1) * grad[i];
            a.v[i] = b2 * a.v[i] + (1.0 - b2) * grad[i] * grad[i];
            p[i] -= a.lr * (a.m[i] / c1) / ((a.v[i] / c2).sqrt() + 1e-8);
        }
        self.set_params(&p);
    }

    pub fn shapes_fit(&self, sizes: &[usize]) -> bool {
        self.layers.len() + 1 == sizes.len()
            && self.layers.iter().zip(sizes.windows(2)).all(|(l, s)| l.n_in == s[0] && l.n_out == s[1] && l.w.len() == s[0] * s[1] && l.b.len() == s[1])
            && self.adam.m.len() == self.params().len()
            && self.adam.v.len() == self.adam.m.len()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::rng::rng_from_seed;

    /// Loss = sum of squares of the output / 2: dLoss/dOut = out.
    fn loss(m: &Mlp, x: &DMatrix<f64>) -> f64 {
        m.forward(x).0.iter().map(|v| v * v).sum::<f64>() / 2.0
    }

    #[test]
    fn gradients_match_finite_differences() {
        let mut rng = rng_from_seed(1);
        let mut m = Mlp::new(&[3, 7, 5, 2], 1e-3, &mut rng);
        // Non-zero biases, so that the check covers them.
        let p: Vec<f64> = m.params().iter().map(|v| v + 0.1 * normal(&mut rng)).collect();
        m.set_params(&p);
        let x = DMatrix::from_fn(6, 3, |_, _| normal(&mut rng));
        let (out, tape) = m.forward(&x);
        let (g, gx) = m.backward(&tape, &out);
        let h = 1e-6;
        for i in 0..p.len() {
            let (mut a, mut b) = (m.clone(), m.clone());
            let (mut pa, mut pb) = (p.clone(), p.clone());
            pa[i] += h;
            pb[i] -= h;
            a.set_params(&pa);
            b.set_params(&pb);
            let fd = (loss(&a, &x) - loss(&b, &x)) / (2.0 * h);
            assert!((fd - g[i]).abs() <= 1e-5 * (1.0 + fd.abs()), "param {i}: {fd} vs {}", g[i]);
        }
        for r in 0..6 {
            for c in 0..3 {
                let (mut xa, mut xb) = (x.clone(), x.clone());
                xa[(r, c)] += h;
                xb[(r, c)] -= h;
                let fd = (loss(&m, &xa) - loss(&m, &xb)) / (2.0 * h);
                assert!((fd - gx[(r, c)]).abs() <= 1e-5 * (1.0 + fd.abs()));
            }
        }
    }

    #[test]
    fn adam_fits_a_small_regression() {
        let mut rng = rng_from_seed(2);
        let mut m = Mlp::new(&[1, 16, 1], 1e-2, &mut rng);
        let x = DMatrix::from_fn(32, 1, |r, _| r as f64 / 31.0);
        let y = x.map(|v| (3.0 * v).sin());
        let err = |m: &Mlp| (m.forward(&x).0 - &y).iter().map(|v| v * v).sum::<f64>() / 32.0;
        let before = err(&m);
        for _ in 0..2000 {
            let (out, tape) = m.forward(&x);
            let (g, _) = m.backward(&tape, &((out - &y) * (2.0 / 32.0)));
            m.adam_step(&g);
        }
        assert!(err(&m) < 0.01 * before && err(&m) < 2e-3, "{before} -> {}", err(&m));
    }
}

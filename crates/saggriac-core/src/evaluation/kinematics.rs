//! Forward kinematics as the least-norm IK sees it (`Kinematics`; a body's, `BodyKinematics`),
//! and its Jacobian by central differences (one-sided at a joint limit) where the body has none
//! in closed form, or is at a limit where its closed form does not hold (a placement clips there).
//!
//! Two savings that keep every bit: the positions of all the moved joints come together where
//! the body can (`Kinematics::positions_moved`: the links before the moved joint are not
//! recomputed), and a Jacobian of such a body is kept for the next call at the same
//! configuration (a Levenberg-Marquardt step that is refused asks again at the same theta).

use nalgebra::DMatrix;

use crate::body::Body;
use crate::task_space::Point;

/// Forward kinematics as the solver sees it.
pub trait Kinematics {
    /// The position at a configuration.
    fn position(&mut self, theta: &[f64]) -> Point;
    /// The Jacobian at `theta` (one row per task dimension, row-major, into `out`, which has room
    /// for `MAX_TASK_DIM` rows) if known in closed form; false makes the solver use finite
    /// differences.
    fn jacobian(&mut self, _theta: &[f64], _out: &mut [f64]) -> bool {
        false
    }
    /// `position` at theta with joint i set to `values[i]`, for every joint i, into `out[i]`, if
    /// the kinematics can give them together with the same bits (see `Body::forward_moved`);
    /// false means one `position` each. True also says that positions are a function of theta
    /// alone (no noise, no state), so a Jacobian made of them can be kept.
    fn positions_moved(&mut self, _theta: &[f64], _values: &[f64], _out: &mut [Point]) -> bool {
        false
    }
}

/// A body's kinematics: its noise-free forward model and Jacobian where it has them, else a
/// placement and a reading per position.
pub struct BodyKinematics<'a>(pub &'a mut dyn Body);

impl Kinematics for BodyKinematics<'_> {
    fn position(&mut self, theta: &[f64]) -> Point {
        self.0.forward(theta).unwrap_or_else(|| {
            self.0.set_theta(theta);
            self.0.position()
        })
    }
    fn jacobian(&mut self, theta: &[f64], out: &mut [f64]) -> bool {
        self.0.jacobian(theta, out)
    }
    fn positions_moved(&mut self, theta: &[f64], values: &[f64], out: &mut [Point]) -> bool {
        self.0.forward_moved(theta, values, out)
    }
}

/// Finite-difference step of the Jacobian.
pub(crate) const FD_STEP: f64 = 1e-6;

#[derive(Default)]
pub(crate) struct Differences {
    /// The last Jacobian of a body whose positions depend on theta alone, and where.
    last: Option<(Vec<f64>, DMatrix<f64>)>,
    up: Vec<f64>,
    down: Vec<f64>,
    hi: Vec<Point>,
    lo: Vec<Point>,
}

impl Differences {
    /// d x / d theta (m x n) at `theta`, where the body is at `x`, joints limited to +-`lim`.
    pub(crate) fn jacobian(&mut self, fk: &mut dyn Kinematics, theta: &[f64], x: &Point, m: usize, lim: f64) -> DMatrix<f64> {
        let n = theta.len();
        if let Some((t, j)) = &self.last {
            if t.len() == n && t.iter().zip(theta).all(|(a, b)| a.to_bits() == b.to_bits()) {
                return j.clone();
            }
        }
        // The value each joint moves to, up and down; a joint that cannot move (at a limit)
        // keeps its own, and its position is x.
        self.up.clear();
        self.down.clear();
        self.up.extend(theta.iter().map(|&t| if t + FD_STEP <= lim { t + FD_STEP } else { t }));
        self.down.extend(theta.iter().map(|&t| if t - FD_STEP >= -lim { t - FD_STEP } else { t }));
        self.hi.resize(n, [0.0; crate::task_space::MAX_TASK_DIM]);
        self.lo.resize(n, [0.0; crate::task_space::MAX_TASK_DIM]);
        let together = fk.positions_moved(theta, &self.up, &mut self.hi) && fk.positions_moved(theta, &self.down, &mut self.lo);
        let mut jac = DMatrix::zeros(m, n);
        let mut t = theta.to_vec();
        for i in 0..n {
            let (up, down) = (theta[i] + FD_STEP <= lim, theta[i] - FD_STEP >= -lim);
            // One side of the difference: x where the joint cannot move, the position moved
            // together with the others when that worked, else joint i moved alone.
            let mut side = |moves: bool, moved: &Point, to: f64| match (moves, together) {
                (false, _) => *x,
                (true, true) => *moved,
                (true, false) => {
                    t[i] = to;
                    let p = fk.position(&t);
                    t[i] = theta[i];
                    p
                }
            };
            let hi = side(up, &self.hi[i], self.up[i]);
            let lo = side(down, &self.lo[i], self.down[i]);
            let h = if up && down { 2.0 * FD_STEP } else { FD_STEP };
            for j in 0..m {
                jac[(j, i)] = (hi[j] - lo[j]) / h;
            }
        }
        if together {
            self.last = Some((theta.to_vec(), jac.clone()));
        }
        jac
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::body::arm::{Arm, ArmConfig, ArmKind};
    use crate::evaluation::min_norm_ik::{min_norm_ik, IkSolution};
    use crate::rng::{rng_from_seed, uniform};

    /// The body's positions one at a time, never together: the solver's plain path.
    struct OneByOne<'a>(BodyKinematics<'a>, usize);
    impl Kinematics for OneByOne<'_> {
        fn position(&mut self, theta: &[f64]) -> Point {
            self.1 += 1;
            self.0.position(theta)
        }
        fn jacobian(&mut self, theta: &[f64], out: &mut [f64]) -> bool {
            self.0.jacobian(theta, out)
        }
    }

    /// The differences written out, one placement per moved joint.
    fn plain(a: &Arm, theta: &[f64], m: usize, lim: f64) -> DMatrix<f64> {
        let x = a.forward(theta);
        let mut j = DMatrix::zeros(m, theta.len());
        for i in 0..theta.len() {
            let (up, down) = (theta[i] + FD_STEP <= lim, theta[i] - FD_STEP >= -lim);
            let mut t = theta.to_vec();
            t[i] = theta[i] + FD_STEP;
            let hi = if up { a.forward(&t) } else { x };
            t[i] = theta[i] - FD_STEP;
            let lo = if down { a.forward(&t) } else { x };
            let h = if up && down { 2.0 * FD_STEP } else { FD_STEP };
            for r in 0..m {
                j[(r, i)] = (hi[r] - lo[r]) / h;
            }
        }
        j
    }

    fn bits(j: &DMatrix<f64>) -> Vec<u64> {
        j.iter().map(|v| v.to_bits()).collect()
    }

    #[test]
    fn positions_together_give_the_bits_of_one_by_one() {
        let mut r = rng_from_seed(7);
        for kind in [ArmKind::Planar, ArmKind::Spatial] {
            for n in [1, 2, 7, 15] {
                let mut cfg = ArmConfig::uniform(n, 50.0, 2.5, 0.05);
                cfg.kind = kind;
                let m = kind.task_dim();
                let mut a = Arm::new(cfg).unwrap();
                for trial in 0..30 {
                    // Some joints at or next to a limit, where the differences are one-sided.
                    let theta: Vec<f64> = (0..n)
                        .map(|i| match (trial + i) % 5 {
                            0 => 2.5,
                            1 => -2.5 + 0.3 * FD_STEP,
                            _ => uniform(&mut r, -2.5, 2.5),
                        })
                        .collect();
                    let want = plain(&a, &theta, m, 2.5);
                    let mut d = Differences::default();
                    let x = a.forward(&theta);
                    let mut fk = BodyKinematics(&mut a);
                    let got = d.jacobian(&mut fk, &theta, &x, m, 2.5);
                    assert_eq!(bits(&got), bits(&want), "{kind:?}, {n} joints, {theta:?}");
                    // Kept, and given again at the same configuration.
                    assert!(d.last.is_some());
                    assert_eq!(bits(&d.jacobian(&mut fk, &theta, &[f64::NAN; crate::task_space::MAX_TASK_DIM], m, 2.5)), bits(&want));
                }
            }
        }
    }

    #[test]
    fn least_norm_ik_is_the_same_with_or_without_the_savings() {
        // The explauto preset's arm: limits +-pi, which the solver meets.
        let pi = std::f64::consts::PI;
        let mut r = rng_from_seed(3);
        for kind in [ArmKind::Planar, ArmKind::Spatial] {
            let mut cfg = ArmConfig::uniform(15, 50.0, pi, 0.05);
            cfg.kind = kind;
            let m = kind.task_dim();
            let (mut fast, mut slow) = (Arm::new(cfg.clone()).unwrap(), Arm::new(cfg).unwrap());
            let mut placements = 0;
            for _ in 0..8 {
                let g: Point = std::array::from_fn(|i| if i < m { uniform(&mut r, -30.0, 30.0) } else { 0.0 });
                let a: IkSolution = min_norm_ik(&mut BodyKinematics(&mut fast), 15, m, pi, &g, 5e-8);
                let mut one = OneByOne(BodyKinematics(&mut slow), 0);
                let b = min_norm_ik(&mut one, 15, m, pi, &g, 5e-8);
                placements += one.1;
                assert_eq!(a.theta.iter().map(|v| v.to_bits()).collect::<Vec<_>>(), b.theta.iter().map(|v| v.to_bits()).collect::<Vec<_>>(), "{kind:?} goal {g:?}");
                assert_eq!(a.residual.to_bits(), b.residual.to_bits());
            }
            assert!(placements > 1000, "the differences were used: {placements} placements");
        }
    }
}

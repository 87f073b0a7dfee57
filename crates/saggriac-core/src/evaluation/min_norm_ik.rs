//! The configuration of least joint norm that puts the end effector on a goal, within the joint
//! limits: min |theta|^2 subject to f(theta) = x_g and |theta_i| <= limit (docs/reproduction.md, "What is measured":
//! the forward-model metric's test configurations).
//!
//! Only the body's forward kinematics is needed (the Jacobian by finite differences where the
//! body has none in closed form, `kinematics`), so the same code serves the built-in
//! arms and bodies written in Python. The solver is a sequential
//! quadratic programme (Wilson-Han-Powell SQP, as in Nocedal & Wright, "Numerical
//! Optimization", ch. 18): each step solves the quadratic model of the Lagrangian subject to the
//! linearised goal constraint, with an inverse-BFGS estimate of the Lagrangian's Hessian and a
//! backtracking search on an l1 merit function. Joint limits are handled by an active set: a
//! joint that reaches its limit is held there, and let go again when its multiplier says that
//! moving inward lowers the norm. It starts from a few fixed bends and keeps the least norm
//! among the starts that reach the goal; a goal no start reaches (out of reach within the
//! limits) gets the closest configuration found, and its residual says so.

use nalgebra::{DMatrix, DVector};

use crate::evaluation::kinematics::Differences;
pub use crate::evaluation::kinematics::{BodyKinematics, Kinematics};
use crate::task_space::Point;

/// Bends (the same angle at every joint) the solver starts from: both senses, slight and
/// marked, so that both mirror families of solutions are tried.
const START_BENDS: [f64; 4] = [0.05, -0.05, 0.2, -0.2];
/// Further starts scattered in the joint space (fixed draws), for bodies the bends do not suit.
const SCATTERED_STARTS: usize = 2;
/// Levenberg-Marquardt iterations that first bring a start onto the goal.
const REACH_ITERATIONS: usize = 100;
const MAX_ITERATIONS: usize = 150;
const MAX_HALVINGS: usize = 30;

/// The least-norm configuration found for one goal.
#[derive(Debug, Clone, PartialEq)]
pub struct IkSolution {
    pub theta: Vec<f64>,
    /// Distance from the goal to where `theta` puts the end effector.
    pub residual: f64,
}

/// The least-norm configuration reaching `goal` (first `m` coordinates) for a body with `n`
/// joints limited to +-`limit`; `tolerance` is the residual that counts as reached.
pub fn min_norm_ik(fk: &mut dyn Kinematics, n: usize, m: usize, limit: f64, goal: &Point, tolerance: f64) -> IkSolution {
    min_norm_ik_from(fk, n, m, limit, goal, tolerance, None)
}

/// `min_norm_ik` with one more start, such as a configuration known to reach the goal.
pub fn min_norm_ik_from(fk: &mut dyn Kinematics, n: usize, m: usize, limit: f64, goal: &Point, tolerance: f64, extra: Option<&[f64]>) -> IkSolution {
    let mut rng = crate::rng::rng_from_seed(0x1c0f_f1e5);
    let mut starts: Vec<Vec<f64>> = START_BENDS.iter().map(|b| vec![b.clamp(-limit, limit); n]).collect();
    starts.extend((0..SCATTERED_STARTS).map(|_| (0..n).map(|_| crate::rng::uniform(&mut rng, -limit / 2.0, limit / 2.0)).collect()));
    starts.extend(extra.map(|t| t.to_vec()));
    // First onto the goal from every start; then the norm is lowered from each start that got
    // there. A goal no start reaches keeps the closest configuration.
    let mut sqp = Sqp { fk, n, m, limit, goal, tolerance, differences: Differences::default() };
    let reached: Vec<(Vec<f64>, f64)> = starts.into_iter().map(|s| sqp.reach(s)).collect();
    let mut best: Option<IkSolution> = None;
    for (theta, residual) in reached {
        let s = if residual <= tolerance { sqp.solve(theta) } else { IkSolution { theta, residual } };
        if !(s.theta.iter().all(|v| v.is_finite()) && s.residual.is_finite()) {
            continue;
        }
        let better = match &best {
            None => true,
            Some(b) => match (s.residual <= tolerance, b.residual <= tolerance) {
                (true, true) => norm_sq(&s.theta) < norm_sq(&b.theta),
                (true, false) => true,
                (false, true) => false,
                (false, false) => s.residual < b.residual,
            },
        };
        if better {
            best = Some(s);
        }
    }
    // Every start is finite and no step to a non-finite configuration is taken, so some start
    // survives unless the body's own positions are not finite; then rest, with what it reports.
    best.unwrap_or_else(|| IkSolution { theta: vec![0.0; n], residual: f64::INFINITY })
}

fn norm_sq(v: &[f64]) -> f64 {
    v.iter().map(|x| x * x).sum()
}

struct Sqp<'f> {
    fk: &'f mut dyn Kinematics,
    n: usize,
    m: usize,
    limit: f64,
    goal: &'f Point,
    tolerance: f64,
    differences: Differences,
}

impl Sqp<'_> {
    /// The position at `t`, or None: a trial configuration that is not finite (a step from a
    /// singular system) is never handed to the body, and a body answering with a non-finite
    /// position does not steer the solver.
    fn place(&mut self, t: &[f64]) -> Option<Point> {
        if !t.iter().all(|v| v.is_finite()) {
            return None;
        }
        let x = self.fk.position(t);
        x[..self.m].iter().all(|v| v.is_finite()).then_some(x)
    }

    fn residual(&self, x: &Point) -> DVector<f64> {
        DVector::from_iterator(self.m, (0..self.m).map(|j| self.goal[j] - x[j]))
    }

    /// Jacobian of the position (m x n): the body's own, else central differences.
    fn jacobian(&mut self, theta: &[f64], x: &Point) -> DMatrix<f64> {
        let (n, m) = (self.n, self.m);
        // The body's rows (as many as its task dimensions), of which the goal uses the first m.
        let mut rows = vec![0.0; crate::task_space::MAX_TASK_DIM * n];
        if self.fk.jacobian(theta, &mut rows) {
            return DMatrix::from_row_slice(m, n, &rows[..m * n]);
        }
        self.differences.jacobian(&mut *self.fk, theta, x, m, self.limit)
    }

    /// Levenberg-Marquardt on the residual alone, within the limits: a configuration on the
    /// goal (or as close as it gets) for the norm minimisation to start from.
    fn reach(&mut self, start: Vec<f64>) -> (Vec<f64>, f64) {
        let lim = self.limit;
        let mut theta: Vec<f64> = start.iter().map(|t| t.clamp(-lim, lim)).collect();
        let mut x = self.fk.position(&theta);
        let mut r = self.residual(&x);
        let mut mu = 1e-3;
        for _ in 0..REACH_ITERATIONS {
            if r.norm() <= self.tolerance {
                break;
            }
            let mut j = self.jacobian(&theta, &x);
            // A joint at a limit that the descent direction pushes outward is held there (its
            // column dropped), so the other joints keep moving.
            let g = j.transpose() * &r;
            for i in 0..self.n {
                if (theta[i] >= lim && g[i] > 0.0) || (theta[i] <= -lim && g[i] < 0.0) {
                    j.column_mut(i).fill(0.0);
                }
            }
            let mut a = &j * j.transpose();
            let scale = a.trace().abs().max(1e-300) / self.m as f64;
            for k in 0..self.m {
                a[(k, k)] += mu * scale;
            }
            let Some(y) = a.cholesky().map(|c| c.solve(&r)) else { break };
            let d = j.transpose() * y;
            let t: Vec<f64> = theta.iter().zip(d.iter()).map(|(t, d)| (t + d).clamp(-lim, lim)).collect();
            let trial = self.place(&t).map(|xt| (self.residual(&xt), xt));
            if let Some((rt, xt)) = trial.filter(|(rt, _)| rt.norm() < r.norm()) {
                (theta, x, r) = (t, xt, rt);
                mu = (mu * 0.3).max(1e-12);
            } else {
                mu *= 10.0;
                if mu > 1e8 {
                    break;
                }
            }
        }
        (theta, r.norm())
    }

    fn solve(&mut self, start: Vec<f64>) -> IkSolution {
        let (n, lim) = (self.n, self.limit);
        let mut theta = start;
        // Joints held at a limit (+1 upper, -1 lower, 0 free).
        let mut held = vec![0i8; n];
        let mut x = self.fk.position(&theta);
        let mut jac = self.jacobian(&theta, &x);
        let mut h_inv = DMatrix::<f64>::identity(n, n);
        let mut penalty = 1.0;
        let mut releases = 0;
        let mut best = (f64::INFINITY, theta.clone());
        for _ in 0..MAX_ITERATIONS {
            let r = self.residual(&x);
            let rn = r.norm();
            if rn < best.0 || (rn <= self.tolerance && best.0 <= self.tolerance) {
                best = (rn, theta.clone());
            }
            // The free joints' quadratic programme: d = H (J^T lambda - theta), J d = r.
            let free: Vec<usize> = (0..n).filter(|&i| held[i] == 0).collect();
            if free.is_empty() {
                break;
            }
            let jf = jac.select_columns(&free);
            let hf = h_inv.select_rows(&free).select_columns(&free);
            let tf = DVector::from_iterator(free.len(), free.iter().map(|&i| theta[i]));
            let jh = &jf * &hf;
            let mut a = &jh * jf.transpose();
            let reg = 1e-12 * a.trace().abs().max(1e-300);
            for j in 0..self.m {
                a[(j, j)] += reg;
            }
            let Some(lambda) = a.clone().cholesky().map(|c| c.solve(&(&r + &jh * &tf))) else { break };
            // J J^T of the free joints, for the correction step below.
            let mut a = &jf * jf.transpose();
            let reg = 1e-12 * a.trace().abs().max(1e-300);
            for j in 0..self.m {
                a[(j, j)] += reg;
            }
            let d = &hf * (jf.transpose() * &lambda - &tf);
            if rn <= self.tolerance && d.norm() <= 1e-7 * (1.0 + tf.norm()) {
                // A KKT point of the free joints; let go of a held joint whose multiplier is
                // negative (moving it inward lowers the norm).
                let jt_l = jac.transpose() * &lambda;
                let worst = (0..n).filter(|&i| held[i] != 0).map(|i| (i, f64::from(held[i]) * (jt_l[i] - theta[i]))).min_by(|a, b| a.1.total_cmp(&b.1));
                match worst {
                    Some((i, nu)) if nu < -1e-9 && releases < 2 * n => {
                        held[i] = 0;
                        releases += 1;
                        continue;
                    }
                    _ => break,
                }
            }
            // Longest step inside the limits.
            let mut alpha_max = 1.0f64;
            let mut blocking = None;
            for (k, &i) in free.iter().enumerate() {
                let room = if d[k] > 0.0 { lim - theta[i] } else { -lim - theta[i] };
                if d[k] != 0.0 && room / d[k] < alpha_max {
                    alpha_max = (room / d[k]).max(0.0);
                    blocking = Some((i, d[k].signum() as i8));
                }
            }
            penalty = f64::max(penalty, 2.0 * lambda.amax() + 1e-9);
            // The goal and dimension copied out, so the merit does not hold `self` while the
            // body is placed.
            let (goal, m) = (self.goal, self.m);
            let merit = |t: &[f64], x: &Point| 0.5 * norm_sq(t) + penalty * (0..m).map(|j| (goal[j] - x[j]).abs()).sum::<f64>();
            let phi0 = merit(&theta, &x);
            let slope = tf.dot(&d) - penalty * r.iter().map(|v| v.abs()).sum::<f64>();
            let mut alpha = alpha_max;
            let mut next = None;
            for _ in 0..MAX_HALVINGS {
                let mut t = theta.clone();
                for (k, &i) in free.iter().enumerate() {
                    t[i] = (theta[i] + alpha * d[k]).clamp(-lim, lim);
                }
                let Some(xt) = self.place(&t) else {
                    alpha *= 0.5;
                    continue;
                };
                let wanted = phi0 + 1e-4 * alpha * slope.min(0.0);
                if merit(&t, &xt) <= wanted {
                    next = Some((t, xt));
                    break;
                }
                if alpha == alpha_max {
                    // Second-order correction (Nocedal & Wright 18.3): the full step may leave
                    // the curved solution set by a little, which the l1 merit punishes even when
                    // the step is good; step back onto it along J^T before giving up on it.
                    let rt = self.residual(&xt);
                    if let Some(y) = a.clone().cholesky().map(|c| c.solve(&rt)) {
                        let back = jf.transpose() * y;
                        let mut t2 = t.clone();
                        for (k, &i) in free.iter().enumerate() {
                            t2[i] = (t[i] + back[k]).clamp(-lim, lim);
                        }
                        if let Some(x2) = self.place(&t2).filter(|x2| merit(&t2, x2) <= wanted) {
                            next = Some((t2, x2));
                            break;
                        }
                    }
                }
                alpha *= 0.5;
            }
            // No progress along the step: as close to stationary as finite differences allow.
            let Some((mut t_new, x_new)) = next else { break };
            if alpha < alpha_max * 1e-4 && rn <= self.tolerance {
                theta = t_new;
                x = x_new;
                break;
            }
            if let (Some((i, side)), true) = (blocking, alpha == alpha_max && alpha_max < 1.0) {
                t_new[i] = f64::from(side) * lim;
                held[i] = side;
            }
            let jac_new = self.jacobian(&t_new, &x_new);
            // Inverse BFGS on the Lagrangian's gradient theta - J^T lambda, skipped when the
            // curvature along the step is not positive.
            let s = DVector::from_iterator(n, (0..n).map(|i| t_new[i] - theta[i]));
            let g_old = DVector::from_column_slice(&theta) - jac.transpose() * &lambda;
            let g_new = DVector::from_column_slice(&t_new) - jac_new.transpose() * &lambda;
            let y = g_new - g_old;
            let sy = s.dot(&y);
            if alpha < 0.1 * alpha_max {
                // A quasi-Newton model this far off is not worth updating: start it again.
                h_inv = DMatrix::identity(n, n);
            } else if sy > 1e-12 * s.norm() * y.norm() && sy > 0.0 {
                let rho = 1.0 / sy;
                let hy = &h_inv * &y;
                let yhy = y.dot(&hy);
                // H' = H - rho (H y s^T + s y^T H) + (rho^2 y^T H y + rho) s s^T
                h_inv -= (&hy * s.transpose() + &s * hy.transpose()) * rho;
                h_inv += (&s * s.transpose()) * (rho * rho * yhy + rho);
            }
            theta = t_new;
            x = x_new;
            jac = jac_new;
        }
        let r = self.residual(&x).norm();
        if r < best.0 || (r <= self.tolerance && norm_sq(&theta) < norm_sq(&best.1)) {
            best = (r, theta);
        }
        IkSolution { theta: best.1, residual: best.0 }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::body::arm::{Arm, ArmConfig};
    use crate::task_space::{distance, point};

    fn arm(n: usize, length: f64, limit: f64) -> Arm {
        Arm::new(ArmConfig::uniform(n, length, limit, 0.05)).unwrap()
    }

    /// Brute force for a planar 3-link arm: its solutions form curves; walk theta_1 over a fine
    /// grid, solve the last two links in closed form (both elbows), keep the least norm within
    /// the limits.
    fn brute_force_3link(l: f64, limit: f64, g: [f64; 2]) -> Option<f64> {
        let mut best: Option<f64> = None;
        let steps = 200_000;
        for s in 0..=steps {
            let t1 = -limit + 2.0 * limit * s as f64 / steps as f64;
            let (px, py) = (g[0] - l * t1.cos(), g[1] - l * t1.sin());
            let d2 = px * px + py * py;
            let c3 = (d2 - 2.0 * l * l) / (2.0 * l * l);
            if !(-1.0..=1.0).contains(&c3) {
                continue;
            }
            for t3 in [c3.acos(), -c3.acos()] {
                let phi = py.atan2(px) - (l * t3.sin()).atan2(l + l * t3.cos());
                let mut t2 = phi - t1;
                t2 = (t2 + std::f64::consts::PI).rem_euclid(std::f64::consts::TAU) - std::f64::consts::PI;
                if t2.abs() <= limit && t3.abs() <= limit {
                    let nrm = t1 * t1 + t2 * t2 + t3 * t3;
                    if best.is_none_or(|b| nrm < b) {
                        best = Some(nrm);
                    }
                }
            }
        }
        best
    }

    #[test]
    fn three_links_least_norm_matches_brute_force() {
        // Free joints, and limits tight enough to bind for goals near the base.
        for limit in [std::f64::consts::FRAC_PI_2, 1.2] {
            let mut a = arm(3, 3.0, limit);
            let mut fk = BodyKinematics(&mut a);
            for g in [[2.5, 0.8], [1.0, 1.5], [0.3, -1.2], [-0.5, 2.0], [2.9, 0.0], [1.2, 0.1]] {
                let s = min_norm_ik(&mut fk, 3, 2, limit, &point(&g), 1e-9);
                match brute_force_3link(1.0, limit, g) {
                    Some(b) => {
                        assert!(s.residual <= 1e-9, "goal {g:?} limit {limit}: residual {}", s.residual);
                        assert!(s.theta.iter().all(|t| t.abs() <= limit), "{:?}", s.theta);
                        let nrm = norm_sq(&s.theta);
                        // The grid (steps of 1.6e-5 rad) finds the minimum to about 1e-4.
                        assert!(nrm <= b + 1e-4, "goal {g:?} limit {limit}: norm {nrm} > brute force {b}");
                        assert!(nrm >= b - 1e-4, "goal {g:?} limit {limit}: norm {nrm} below the brute force {b}?");
                    }
                    None => assert!(s.residual > 1e-6, "goal {g:?} limit {limit}: brute force finds it out of reach"),
                }
            }
        }
    }

    /// The planar arm's 2 x n Jacobian, written out (checked against finite differences in
    /// arm.rs).
    fn planar_jacobian_2d(a: &Arm, theta: &[f64]) -> DMatrix<f64> {
        let mut rows = vec![0.0; 2 * theta.len()];
        assert!(a.jacobian(theta, &mut rows));
        DMatrix::from_row_slice(2, theta.len(), &rows)
    }

    #[test]
    fn fifteen_joints_reach_every_goal_at_a_stationary_point() {
        let a = arm(15, 50.0, std::f64::consts::FRAC_PI_2);
        let mut body = a.clone();
        let mut fk = BodyKinematics(&mut body);
        for g in [[30.0, 20.0], [5.0, -3.0], [49.9, 0.5], [0.5, 45.0], [12.0, -40.0], [1.0, 0.5]] {
            let s = min_norm_ik(&mut fk, 15, 2, std::f64::consts::FRAC_PI_2, &point(&g), 5e-8);
            assert!(s.residual <= 5e-8, "goal {g:?}: residual {}", s.residual);
            assert!(distance(&a.forward(&s.theta), &point(&g)) <= 5e-8);
            // Stationary for the norm on the solution set: theta is in the row space of J.
            let j = planar_jacobian_2d(&a, &s.theta);
            let th = DVector::from_column_slice(&s.theta);
            let proj = j.transpose() * (&j * j.transpose()).try_inverse().unwrap() * (&j * &th);
            assert!((&th - &proj).norm() <= 1e-4 * th.norm().max(1e-3), "goal {g:?}: theta not in J's row space: {} of {}", (&th - &proj).norm(), th.norm());
            // No perturbation along the solution set lowers the norm (a minimum, not a saddle):
            // project small random steps back onto the set and compare.
            let n0 = norm_sq(&s.theta);
            for k in 0..20 {
                let mut t: Vec<f64> = s.theta.iter().enumerate().map(|(i, v)| v + 0.02 * ((i * 7 + k * 13) as f64).sin()).collect();
                for _ in 0..50 {
                    let x = a.forward(&t);
                    let r = DVector::from_vec(vec![g[0] - x[0], g[1] - x[1]]);
                    let jt = planar_jacobian_2d(&a, &t);
                    let d = jt.transpose() * (&jt * jt.transpose()).try_inverse().unwrap() * r;
                    t.iter_mut().zip(d.iter()).for_each(|(a, b)| *a += b);
                }
                assert!(norm_sq(&t) >= n0 - 1e-7, "goal {g:?}: a nearby solution has a smaller norm");
            }
        }
    }

    #[test]
    fn a_goal_out_of_reach_within_the_limits_gets_the_closest_configuration() {
        // Two links limited to 0.3 rad cannot fold back to the base.
        let a = arm(2, 2.0, 0.3);
        let mut body = a.clone();
        let mut fk = BodyKinematics(&mut body);
        let s = min_norm_ik(&mut fk, 2, 2, 0.3, &point(&[0.2, 0.0]), 1e-9);
        assert!(s.residual > 1.0, "{}", s.residual);
        assert!(s.theta.iter().all(|t| t.abs() <= 0.3 + 1e-12));
        // The closest point within the limits, by a fine grid.
        let grid = 600;
        let at = |i: usize| -0.3 + 0.6 * i as f64 / grid as f64;
        let best = (0..=grid).flat_map(|i| (0..=grid).map(move |k| (at(i), at(k)))).map(|(p, q)| distance(&a.forward(&[p, q]), &point(&[0.2, 0.0]))).fold(f64::INFINITY, f64::min);
        assert!(s.residual <= best + 1e-6 && s.residual >= best - 1e-3, "{} vs {best}", s.residual);
    }

    #[test]
    fn one_dimensional_goals_and_the_spatial_arm() {
        let mut cfg = ArmConfig::uniform(6, 6.0, std::f64::consts::FRAC_PI_2, 0.05);
        cfg.kind = crate::body::arm::ArmKind::Spatial;
        let mut a = Arm::new(cfg).unwrap();
        let mut fk = BodyKinematics(&mut a);
        let s = min_norm_ik(&mut fk, 6, 3, std::f64::consts::FRAC_PI_2, &point(&[3.0, 2.0, -1.5]), 1e-9);
        assert!(s.residual <= 1e-9, "{}", s.residual);
        let mut b = arm(5, 10.0, std::f64::consts::FRAC_PI_2);
        let mut fk = BodyKinematics(&mut b);
        let s = min_norm_ik(&mut fk, 5, 1, std::f64::consts::FRAC_PI_2, &point(&[4.0]), 1e-9);
        assert!(s.residual <= 1e-9, "{}", s.residual);
    }
}

//! Reaching phase of the low level (paper III.D.1), inspired by SSA: from the current position,
//! ask for a displacement of length v towards the target, execute dtheta = J+ dx with J fitted on
//! the nearest stored samples, and explore locally when the realised displacement misses.

use crate::competence::{clip, cost};
use crate::error::{Check, Result};
use crate::local_model::FitFailure;
use crate::run_loop::{ActionKind, Learner};
use crate::task_space::{distance, norm, sub, Point, MAX_TASK_DIM};

#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ReachingConfig {
    /// Length of the desired displacement per micro-action (paper: v = 0.5). Near the target the
    /// step is shortened to the remaining distance ("v bounded by v_max").
    pub v: f64,
    /// Subgoals per goal, the goal being the last (paper: l = 5).
    pub n_subgoals: usize,
    /// Explore when |realised dx - expected dx| > eps_max, where the expected dx is J dtheta for
    /// the executed dtheta (the desired dx itself unless the command was cut by a bound).
    pub eps_max: f64,
    /// Timeout of one (sub)goal attempt, in micro-actions of any kind (reaching and
    /// exploration): ceil(timeout_factor * distance / v) + timeout_min. It is checked between
    /// phases, so an exploration phase that starts before the timeout runs its q actions.
    pub timeout_factor: f64,
    pub timeout_min: usize,
}

impl Default for ReachingConfig {
    fn default() -> Self {
        ReachingConfig { v: 0.5, n_subgoals: 5, eps_max: 0.25, timeout_factor: 2.0, timeout_min: 10 }
    }
}

impl ReachingConfig {
    pub fn validate(&self) -> Result<()> {
        let c = Check { owner: "Reaching" };
        c.positive("v", self.v)?;
        c.at_least("n_subgoals", self.n_subgoals, 1)?;
        c.positive("eps_max", self.eps_max)?;
        c.non_negative("timeout_factor", self.timeout_factor)?;
        c.at_least("timeout_min", self.timeout_min, 1)?;
        Ok(())
    }

    /// Largest number of reaching micro-actions for a target at `distance`.
    pub fn timeout(&self, distance: f64) -> usize {
        (self.timeout_factor * distance / self.v).ceil() as usize + self.timeout_min
    }
}

/// Result of one (sub)goal attempt.
#[derive(Debug, Clone, PartialEq)]
pub struct AttemptOutcome {
    pub start: Point,
    pub end: Point,
    pub competence: f64,
    pub reached: bool,
    /// The run's step budget ran out during the attempt: its competence is not a measurement.
    pub interrupted: bool,
}

/// Desired displacement: length min(v, |target - x|) towards the target (the paper's
/// x_c - x_g is a sign typo, see SPEC.md).
pub fn desired_step(x: &Point, target: &Point, v: f64) -> Point {
    let e = sub(target, x);
    let d = norm(&e);
    if d == 0.0 {
        return [0.0; MAX_TASK_DIM];
    }
    let s = v.min(d) / d;
    e.map(|v| v * s)
}

impl Learner {
    /// One attempt to reach `target` from where the arm is.
    pub(crate) fn reach(&mut self, target: Point) -> AttemptOutcome {
        let rc = self.cfg.reaching;
        let comp = self.cfg.competence;
        let start = self.body.position();
        let d0 = distance(&target, &start);
        let timeout = rc.timeout(d0) as u64;
        let step0 = self.steps();
        let mut interrupted = false;
        loop {
            let x = self.body.position();
            if cost(&target, &x, &start, comp.min_c) > comp.eps_c {
                break;
            }
            if self.steps() - step0 >= timeout {
                break;
            }
            if self.budget_spent() || self.failed() {
                interrupted = true;
                break;
            }
            let dx_des = desired_step(&x, &target, rc.v);
            let mut d = std::mem::take(&mut self.buf_dtheta);
            match self.inverse_model(&dx_des, &mut d) {
                Ok(()) => {
                    let dx = self.micro_action(&mut d, ActionKind::Reaching);
                    self.buf_dtheta = d;
                    match dx {
                        None => {
                            interrupted = true;
                            break;
                        }
                        Some(dx) => {
                            // Compare with what the model expected of the command actually
                            // executed: the same as the desired dx unless the joint-step bound or
                            // a joint limit cut the command, which is no fault of the model.
                            let expected = self.expected_dx(&self.buf_dtheta);
                            let err = distance(&dx, &expected);
                            if err > rc.eps_max {
                                self.counters.explorations += 1;
                                self.explore();
                            }
                        }
                    }
                }
                Err(_) => {
                    // No usable local model here yet: explore to build one.
                    self.buf_dtheta = d;
                    self.counters.fit_failures += 1;
                    self.counters.explorations += 1;
                    self.explore();
                }
            }
        }
        let end = self.body.position();
        let c = clip(cost(&target, &end, &start, comp.min_c), &comp);
        AttemptOutcome { start, end, competence: c, reached: c == 0.0, interrupted: interrupted && c != 0.0 }
    }

    /// J dtheta with the last fitted J.
    pub(crate) fn expected_dx(&self, dtheta: &[f64]) -> Point {
        let j = self.model.jacobian();
        let mut e = [0.0; MAX_TASK_DIM];
        for (r, v) in e.iter_mut().take(j.nrows()).enumerate() {
            *v = (0..dtheta.len()).map(|a| j[(r, a)] * dtheta[a]).sum();
        }
        e
    }

    /// Fit the local model on the nearest stored configurations of the current theta.
    pub(crate) fn fit_here(&mut self) -> std::result::Result<(), FitFailure> {
        let k = self.cfg.local.k_neighbours;
        if self.memory.len() < k {
            return Err(FitFailure::NotEnoughData);
        }
        let t0 = std::time::Instant::now();
        let theta = self.body.theta().to_vec();
        if self.cfg.warm_start_recent > 0 {
            self.memory.knn_warm(&mut self.warm, &theta, k, &mut self.neighbours);
        } else {
            self.memory.knn(&theta, k, &mut self.neighbours);
        }
        let t1 = std::time::Instant::now();
        let r = self.model.fit(&self.memory, &self.neighbours);
        self.timers.knn += (t1 - t0).as_secs_f64();
        self.timers.fit += t1.elapsed().as_secs_f64();
        r
    }

    /// dtheta = J+ dx with J fitted on the nearest stored configurations of the current theta.
    pub(crate) fn inverse_model(&mut self, dx: &Point, dtheta: &mut [f64]) -> std::result::Result<(), FitFailure> {
        self.fit_here()?;
        let t0 = std::time::Instant::now();
        let r = self.model.inverse(&dx[..self.task_dim()], dtheta);
        self.timers.fit += t0.elapsed().as_secs_f64();
        r
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn desired_step_points_at_the_target_and_stops_there() {
        let s = desired_step(&[0.0, 0.0, 0.0], &[3.0, 4.0, 0.0], 0.5);
        assert!((s[0] - 0.3).abs() < 1e-15 && (s[1] - 0.4).abs() < 1e-15 && s[2] == 0.0);
        let s = desired_step(&[0.0, 0.0, 0.0], &[0.03, 0.04, 0.0], 0.5);
        assert!((s[0] - 0.03).abs() < 1e-15 && (s[1] - 0.04).abs() < 1e-15);
        assert_eq!(desired_step(&[1.0, 1.0, 0.0], &[1.0, 1.0, 0.0], 0.5), [0.0, 0.0, 0.0]);
        let s = desired_step(&[1.0, 0.0, 0.0], &[2.0, 2.0, 2.0], 0.3);
        assert!((s[0] - 0.1).abs() < 1e-15 && (s[1] - 0.2).abs() < 1e-15 && (s[2] - 0.2).abs() < 1e-15);
    }

    #[test]
    fn timeout_grows_with_distance() {
        let rc = ReachingConfig::default();
        assert_eq!(rc.timeout(0.0), 10);
        assert_eq!(rc.timeout(5.0), 30);
    }
}

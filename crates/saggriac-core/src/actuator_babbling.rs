//! The ACTUATOR baselines of the paper (IV.B): motor babbling in the actuator space instead of
//! goals in the task space. ACTUATOR-Random executes a small random dtheta at every step;
//! ACTUATOR-RIAC chooses it with R-IAC over the 2n-dimensional (theta, dtheta) space, the
//! interest being the progress of the forward model's prediction error of dx. Both reset the arm
//! to rest every `max` steps, `max` being the time needed to reach, one after the other, the two
//! most distant reachable points.

use crate::config::{Condition, RunConfig};
use crate::rng::uniform;
use crate::run_loop::{ActionKind, Learner};

/// Points on the boundary of the reachable part of the goal box (the box intersected with the
/// disk of radius `reach`), `per_edge` per edge plus the arc.
fn reachable_boundary(low: &[f64], high: &[f64], reach: f64, per_edge: usize) -> Vec<[f64; 2]> {
    let mut pts = Vec::new();
    let corners = [[low[0], low[1]], [high[0], low[1]], [high[0], high[1]], [low[0], high[1]]];
    for e in 0..4 {
        let (a, b) = (corners[e], corners[(e + 1) % 4]);
        for i in 0..=per_edge {
            let t = i as f64 / per_edge as f64;
            pts.push([a[0] + t * (b[0] - a[0]), a[1] + t * (b[1] - a[1])]);
        }
    }
    for i in 0..(8 * per_edge) {
        let ang = i as f64 / (8 * per_edge) as f64 * std::f64::consts::TAU;
        pts.push([reach * ang.cos(), reach * ang.sin()]);
    }
    pts.retain(|p| p[0] * p[0] + p[1] * p[1] <= reach * reach * (1.0 + 1e-12) && p[0] >= low[0] - 1e-9 && p[0] <= high[0] + 1e-9 && p[1] >= low[1] - 1e-9 && p[1] <= high[1] + 1e-9);
    pts
}

/// The paper's `max`: micro-actions needed to go from rest to the nearer of the two most distant
/// reachable points of the goal space, then to the other, at speed v.
pub fn actuator_reset_period(cfg: &RunConfig, rest: [f64; 2]) -> usize {
    let reach: f64 = cfg.arm.link_lengths.iter().sum();
    let pts = reachable_boundary(&cfg.goal_low, &cfg.goal_high, reach, 200);
    let d = |a: [f64; 2], b: [f64; 2]| ((a[0] - b[0]).powi(2) + (a[1] - b[1]).powi(2)).sqrt();
    let mut best = (0.0, rest, rest);
    for (i, &a) in pts.iter().enumerate() {
        for &b in &pts[i + 1..] {
            let dab = d(a, b);
            if dab > best.0 {
                best = (dab, a, b);
            }
        }
    }
    let (dab, a, b) = best;
    let path = d(rest, a).min(d(rest, b)) + dab;
    ((path / cfg.reaching.v).ceil() as usize).max(1)
}

impl Learner {
    /// One babbling micro-action (ACTUATOR conditions).
    pub(crate) fn babble(&mut self) {
        if self.babble_steps % self.actuator_reset as u64 == 0 {
            self.body.reset();
            self.warm.clear();
        }
        self.babble_steps += 1;
        let step = self.cfg.babble_step;
        let theta0 = self.body.theta().to_vec();
        let mut d = std::mem::take(&mut self.buf_dtheta);
        match self.cfg.condition {
            Condition::ActuatorRiac => {
                let t0 = std::time::Instant::now();
                let choice = self.selector.sample();
                self.timers.goal_selection += t0.elapsed().as_secs_f64();
                // The region tree proposes a point (theta, dtheta); the arm cannot jump to
                // theta, so the proposed dtheta is executed from where the arm is, and the
                // prediction error is recorded at the point actually visited.
                d.copy_from_slice(&choice.goal[theta0.len()..]);
            }
            _ => {
                for v in d.iter_mut() {
                    *v = uniform(&mut self.rng, -step, step);
                }
            }
        }
        let predicted = if self.cfg.condition == Condition::ActuatorRiac { Some(self.predict_dx(&d)) } else { None };
        let dx = self.micro_action(&mut d, ActionKind::Babbling);
        if let (Some(p), Some(dx)) = (predicted, dx) {
            let err = ((dx[0] - p[0]).powi(2) + (dx[1] - p[1]).powi(2)).sqrt();
            let mut point = theta0;
            point.extend_from_slice(&d);
            let t0 = std::time::Instant::now();
            self.selector.update(&point, -err);
            self.timers.goal_selection += t0.elapsed().as_secs_f64();
        }
        self.buf_dtheta = d;
    }

    /// Forward prediction of dx for a command at the current theta: J dtheta with J fitted on the
    /// neighbours, or no motion when no model is available yet.
    fn predict_dx(&mut self, dtheta: &[f64]) -> [f64; 2] {
        match self.fit_here() {
            Ok(()) => self.expected_dx(dtheta),
            Err(_) => [0.0, 0.0],
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn reset_period_of_the_paper_goal_spaces() {
        // Both experiments: the farthest reachable pair is (0, 50), (0, -50); from rest (50, 0)
        // that is 50 sqrt(2) + 100 = 170.7 units, 342 steps at v = 0.5.
        let mut cfg = RunConfig::default();
        assert_eq!(actuator_reset_period(&cfg, [50.0, 0.0]), 342);
        cfg.goal_low = vec![0.0, -150.0];
        cfg.goal_high = vec![150.0, 150.0];
        assert_eq!(actuator_reset_period(&cfg, [50.0, 0.0]), 342);
    }
}

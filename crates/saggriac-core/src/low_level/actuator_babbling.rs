//! The ACTUATOR baselines of the paper (IV.B): motor babbling in the actuator space instead of
//! goals in the task space. ACTUATOR-Random executes a small random dtheta at every step;
//! ACTUATOR-RIAC chooses it with R-IAC over the 2n-dimensional (theta, dtheta) space, the
//! interest being the progress of the forward model's prediction error of dx. Both reset the arm
//! to rest every `max` steps, `max` being the time needed to reach, one after the other, the two
//! most distant reachable points.

use crate::config::{Condition, RunConfig};
use crate::high_level::goal_selection::GoalChoice;
use crate::low_level::LowLevel;
use crate::parts::{ActionKind, Parts};
use crate::rng::uniform;
use crate::task_space::{distance, point, Point, MAX_TASK_DIM};

/// Points on the boundary of the reachable part of the goal box (the box intersected with the
/// ball of radius `reach`).
fn reachable_boundary(low: &[f64], high: &[f64], reach: f64, per_edge: usize) -> Vec<Point> {
    match low.len() {
        1 => [low[0].max(-reach), high[0].min(reach)].iter().map(|&v| point(&[v])).collect(),
        2 => boundary_2d(low, high, reach, per_edge).iter().map(|p| point(p)).collect(),
        _ => boundary_3d(low, high, reach, per_edge / 10),
    }
}

/// The 2-D case: `per_edge` points per edge of the box plus the circle.
fn boundary_2d(low: &[f64], high: &[f64], reach: f64, per_edge: usize) -> Vec<[f64; 2]> {
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

/// The 3-D case: a `k` x `k` grid on each face of the box plus a Fibonacci lattice on the
/// sphere, kept where inside both.
fn boundary_3d(low: &[f64], high: &[f64], reach: f64, k: usize) -> Vec<Point> {
    let mut pts = Vec::new();
    for axis in 0..3 {
        let (u, w) = ((axis + 1) % 3, (axis + 2) % 3);
        for side in [low[axis], high[axis]] {
            for i in 0..=k {
                for j in 0..=k {
                    let mut p = [0.0; MAX_TASK_DIM];
                    p[axis] = side;
                    p[u] = low[u] + (high[u] - low[u]) * i as f64 / k as f64;
                    p[w] = low[w] + (high[w] - low[w]) * j as f64 / k as f64;
                    pts.push(p);
                }
            }
        }
    }
    let n = 100 * k;
    let golden = std::f64::consts::PI * (3.0 - 5f64.sqrt());
    for i in 0..n {
        let z = 1.0 - 2.0 * (i as f64 + 0.5) / n as f64;
        let rho = (1.0 - z * z).sqrt();
        let (s, c) = (golden * i as f64).sin_cos();
        pts.push([reach * rho * c, reach * rho * s, reach * z]);
    }
    let zero = [0.0; MAX_TASK_DIM];
    pts.retain(|p| distance(p, &zero) <= reach * (1.0 + 1e-12) && (0..3).all(|a| p[a] >= low[a] - 1e-9 && p[a] <= high[a] + 1e-9));
    pts
}

/// The paper's `max`: micro-actions needed to go from rest to the nearer of the two most distant
/// reachable points of the goal space, then to the other, at speed v.
pub fn actuator_reset_period(cfg: &RunConfig, rest: Point) -> usize {
    let reach: f64 = cfg.arm.link_lengths.iter().sum();
    let pts = match &cfg.arm.chain {
        // A chain's reachable set is no ball: a fixed sample of its positions in the goal box.
        Some(spec) => {
            let mut rng = crate::rng::rng_from_seed(0x5eed_c4a1);
            let inside = |p: &Point| (0..cfg.goal_low.len()).all(|i| p[i] >= cfg.goal_low[i] && p[i] <= cfg.goal_high[i]);
            let chain = crate::body::chain::Chain::new(spec);
            crate::body::chain::reachable_cloud(&chain, cfg.arm.joint_limit, 2_000, &mut rng).into_iter().filter(inside).collect()
        }
        None => reachable_boundary(&cfg.goal_low, &cfg.goal_high, reach, 200),
    };
    let d = |a: Point, b: Point| distance(&a, &b);
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

pub struct ActuatorBabbling {
    /// ACTUATOR-RIAC (commands from the region tree) rather than ACTUATOR-Random.
    riac: bool,
    /// ACTUATOR-RIAC: candidate commands per step, chosen among in context (0: free proposals).
    candidates: usize,
    step: f64,
    /// Back to rest every this many micro-actions (the paper's `max`).
    reset_period: u64,
    /// Micro-actions so far.
    babbled: u64,
    dtheta: Vec<f64>,
}

impl ActuatorBabbling {
    pub fn new(cfg: &RunConfig, reset_period: usize) -> Self {
        let n = cfg.arm.link_lengths.len();
        ActuatorBabbling {
            riac: cfg.condition == Condition::ActuatorRiac,
            candidates: cfg.actuator_candidates,
            step: cfg.babble_step,
            reset_period: reset_period as u64,
            babbled: 0,
            dtheta: vec![0.0; n],
        }
    }
}

impl LowLevel for ActuatorBabbling {
    fn rest_due(&self, _parts: &Parts) -> bool {
        self.babbled % self.reset_period == 0
    }
    /// R-IAC proposes the command in the free variant; in context it is chosen among this
    /// level's candidates (see `attempt`), and ACTUATOR-Random draws it itself.
    fn asks_high_level(&self) -> bool {
        self.riac && self.candidates == 0
    }
    /// Babble until the next evaluation report could be due (a goal attempt's worth).
    fn attempts_per_report(&self) -> usize {
        64
    }
    fn saved_progress(&self) -> u64 {
        self.babbled
    }
    fn restore_progress(&mut self, progress: u64) {
        self.babbled = progress;
    }

    /// One babbling micro-action.
    fn attempt(&mut self, choice: Option<GoalChoice>, parts: &mut Parts) {
        self.babbled += 1;
        let theta0 = parts.body().theta().to_vec();
        let n = theta0.len();
        // A point (theta, dtheta) of the region tree, whose dtheta is executed from here.
        let point = match choice {
            // Free variant: proposed anywhere; the arm cannot jump to its theta, so the prediction
            // error is recorded at the point actually visited.
            Some(c) => Some(c.goal),
            // In context: candidate commands from here, located at (theta, dtheta) in the tree.
            None if self.riac => {
                let mut candidates: Vec<Vec<f64>> = (0..self.candidates)
                    .map(|_| {
                        let mut p = theta0.clone();
                        p.extend((0..n).map(|_| uniform(parts.rng(), -self.step, self.step)));
                        p
                    })
                    .collect();
                Some(parts.choose(&candidates).map_or_else(|| candidates.swap_remove(0), |c| c.goal))
            }
            None => None,
        };
        let d = &mut self.dtheta;
        match &point {
            Some(p) => d.copy_from_slice(&p[n..]),
            None => {
                for v in d.iter_mut() {
                    *v = uniform(parts.rng(), -self.step, self.step);
                }
            }
        }
        // ACTUATOR-RIAC's interest: progress of the forward model's error (J dtheta with J fitted
        // on the neighbours, or no motion when no model is available yet).
        let predicted = self.riac.then(|| match parts.fit_here() {
            Ok(()) => parts.model().expected_dx(d),
            Err(_) => [0.0; MAX_TASK_DIM],
        });
        let dx = parts.micro_action(d, ActionKind::Babbling);
        if let (Some(p), Some(dx)) = (predicted, dx) {
            let err = distance(&dx, &p);
            let mut point = theta0;
            point.extend_from_slice(d);
            parts.tell(&point, -err);
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
        assert_eq!(actuator_reset_period(&cfg, [50.0, 0.0, 0.0]), 342);
        cfg.goal_low = vec![0.0, -150.0];
        cfg.goal_high = vec![150.0, 150.0];
        assert_eq!(actuator_reset_period(&cfg, [50.0, 0.0, 0.0]), 342);
    }

    #[test]
    fn reset_period_in_3d() {
        // Goal box [-50, 50]^3 around a ball of radius 50: the farthest pair is a diameter, and
        // from rest (50, 0, 0) the nearer end of a diameter is at most 50 sqrt(2) away: the
        // path is between 100 + 0 (the diameter through rest) and 170.7 units.
        let mut cfg = RunConfig { goal_low: vec![-50.0; 3], goal_high: vec![50.0; 3], ..RunConfig::default() };
        let p = actuator_reset_period(&cfg, [50.0, 0.0, 0.0]);
        assert!((200..=342).contains(&p), "{p}");
        // A thin slab z in [-1, 1]: nearly the 2-D disk of radius 50.
        cfg.goal_low = vec![0.0, -50.0, -1.0];
        cfg.goal_high = vec![50.0, 50.0, 1.0];
        let p = actuator_reset_period(&cfg, [50.0, 0.0, 0.0]);
        assert!((335..=343).contains(&p), "{p}");
    }
}

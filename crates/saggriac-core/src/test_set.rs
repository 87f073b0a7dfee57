//! The fixed test sets of an evaluation (SPEC.md "Evaluation") and what one evaluation measures.

use crate::arm::{Arm, ArmConfig};
use crate::body::Body;
use crate::error::{invalid, Result};
use crate::rng::{rng_from_seed, uniform};
use crate::task_space::{point, Point};

/// The fixed test sets of one experiment seed, independent of the learner.
#[derive(Debug, Clone)]
pub struct TestSet {
    pub goals: Vec<Point>,
    pub configs: Vec<Vec<f64>>,
    pub true_x: Vec<Point>,
}

impl TestSet {
    /// Goals uniform in the reachable part of the goal box (the box intersected with the ball of
    /// radius = arm length: a disk for the planar arm), by rejection; configurations uniform in
    /// the joint limits.
    pub fn new(arm: &ArmConfig, goal_low: &[f64], goal_high: &[f64], n_goals: usize, n_configs: usize, seed: u64) -> Result<Self> {
        let mut a = Arm::new(arm.clone())?;
        Self::with_body(arm, &mut a, goal_low, goal_high, n_goals, n_configs, seed)
    }

    /// The same draws, with the true positions of the test configurations measured on `body`
    /// (placed there at once; this is not a time step). `arm` gives the reach and joint limits.
    pub fn with_body(arm: &ArmConfig, body: &mut dyn Body, goal_low: &[f64], goal_high: &[f64], n_goals: usize, n_configs: usize, seed: u64) -> Result<Self> {
        let r: f64 = arm.link_lengths.iter().sum();
        let m = goal_low.len();
        let mut rng = rng_from_seed(seed);
        let mut goals = Vec::with_capacity(n_goals);
        // Clip the sampling box to the ball's bounding box so rejection stays cheap.
        let lo: Vec<f64> = goal_low.iter().map(|v| v.max(-r)).collect();
        let hi: Vec<f64> = goal_high.iter().map(|v| v.min(r)).collect();
        if !(0..m).all(|i| lo[i] < hi[i]) {
            return Err(invalid("Evaluation", "goal_low/goal_high", format!("a box that meets the reachable ball of radius {r}"), format!("{goal_low:?}..{goal_high:?}")));
        }
        let mut tries = 0usize;
        while goals.len() < n_goals {
            let g = point(&(0..m).map(|i| uniform(&mut rng, lo[i], hi[i])).collect::<Vec<f64>>());
            tries += 1;
            if g.iter().fold(0.0, |s, v| s + v * v) <= r * r {
                goals.push(g);
            } else if tries > 1000 * n_goals {
                return Err(invalid("Evaluation", "goal_low/goal_high", "a box with a reachable part of non-negligible area", format!("{goal_low:?}..{goal_high:?}")));
            }
        }
        let lim = arm.joint_limit;
        let n = arm.link_lengths.len();
        let configs: Vec<Vec<f64>> = (0..n_configs).map(|_| (0..n).map(|_| uniform(&mut rng, -lim, lim)).collect()).collect();
        let true_x = configs
            .iter()
            .map(|c| {
                body.set_theta(c);
                body.position()
            })
            .collect();
        Ok(TestSet { goals, configs, true_x })
    }
}

/// Errors measured at one evaluation.
#[derive(Debug, Clone, PartialEq)]
pub struct EvalResult {
    pub reach_errors: Vec<f64>,
    pub pred_errors: Vec<f64>,
    /// Micro-actions executed by the test reaches (on the scratch arm; not time).
    pub test_steps: u64,
}

impl EvalResult {
    pub fn mean_reach(&self) -> f64 {
        mean(&self.reach_errors)
    }
    pub fn mean_pred(&self) -> f64 {
        mean(&self.pred_errors)
    }
}

fn mean(v: &[f64]) -> f64 {
    v.iter().sum::<f64>() / v.len().max(1) as f64
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::arm::ArmKind;
    use crate::task_space::{distance, MAX_TASK_DIM};

    /// Test goals lie in the goal box and within the arm's reach, and fill that set: in 3-D,
    /// for the half ball x >= 0, their mean x is 3r/8 (the half ball's centroid).
    #[test]
    fn test_goals_fill_the_reachable_part_of_the_box() {
        let mut arm = ArmConfig::uniform(15, 50.0, std::f64::consts::FRAC_PI_2, 0.05);
        arm.kind = ArmKind::Spatial;
        let (lo, hi) = ([0.0, -50.0, -50.0], [50.0, 50.0, 50.0]);
        let t = TestSet::new(&arm, &lo, &hi, 4000, 3, 9).unwrap();
        let zero = [0.0; MAX_TASK_DIM];
        for g in &t.goals {
            assert!(distance(g, &zero) <= 50.0 && (0..3).all(|i| g[i] >= lo[i] && g[i] <= hi[i]), "{g:?}");
        }
        let mean_x = t.goals.iter().map(|g| g[0]).sum::<f64>() / 4000.0;
        assert!((mean_x - 3.0 * 50.0 / 8.0).abs() < 0.6, "{mean_x}");
        // A box out of reach is refused with the rule.
        let e = TestSet::new(&arm, &[60.0, 0.0, 0.0], &[70.0, 1.0, 1.0], 1, 1, 9).unwrap_err().to_string();
        assert!(e.contains("meets the reachable ball of radius 50"), "{e}");
        // The test configurations' positions are the arm's.
        let a = Arm::new(arm).unwrap();
        assert_eq!(t.true_x[0], a.forward(&t.configs[0]));
    }
}

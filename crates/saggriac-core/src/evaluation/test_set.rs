//! The fixed test sets of an evaluation (docs/reproduction.md, "What is measured") and what one evaluation measures.

use crate::body::arm::{Arm, ArmConfig};
use crate::body::Body;
use crate::config::evaluation::{EvalConfig, TestConfigs};
use crate::error::{invalid, Result};
use crate::evaluation::min_norm_ik::{min_norm_ik_from, BodyKinematics, Kinematics};
use crate::evaluation::reachable_cloud::Cloud;
use crate::rng::{rng_from_seed, uniform, CoreRng};
use crate::task_space::{point, sub, Point};

/// The fixed test sets of one experiment seed, independent of the learner.
#[derive(Debug, Clone)]
pub struct TestSet {
    pub goals: Vec<Point>,
    pub configs: Vec<Vec<f64>>,
    pub true_x: Vec<Point>,
    /// One small joint motion per configuration (uniform within +-`motion_step`, kept within
    /// the limits) and the displacement it causes there: the test of the learnt differential
    /// model (theta, dtheta) -> dx.
    pub motions: Vec<Vec<f64>>,
    pub true_dx: Vec<Point>,
    /// Distance from each configuration's position to the goal it was solved for (ik_min_norm;
    /// none for uniform configurations). Above `IK_TOLERANCE` times the reach, that goal is out
    /// of reach within the joint limits and its configuration is the closest one found.
    pub ik_residuals: Vec<f64>,
    pub kind: TestConfigs,
}

/// Residual, relative to the reach, under which a test configuration reaches its goal.
pub const IK_TOLERANCE: f64 = 1e-9;

/// The body's noise-free position at `theta` where it knows it, else a placement and a reading.
fn position_at(body: &mut dyn Body, theta: &[f64]) -> Point {
    BodyKinematics(body).position(theta)
}

/// Test goals, each with a configuration known to reach it where there is one (a chain's).
type Drawn = (Vec<Point>, Vec<Option<Vec<f64>>>);

/// Goals uniform in the reachable part of the goal box, by rejection.
fn draw_goals(rng: &mut CoreRng, r: f64, goal_low: &[f64], goal_high: &[f64], n_goals: usize) -> Result<Vec<Point>> {
    let m = goal_low.len();
    let mut goals = Vec::with_capacity(n_goals);
    // Clip the sampling box to the ball's bounding box so rejection stays cheap.
    let lo: Vec<f64> = goal_low.iter().map(|v| v.max(-r)).collect();
    let hi: Vec<f64> = goal_high.iter().map(|v| v.min(r)).collect();
    if !(0..m).all(|i| lo[i] < hi[i]) {
        return Err(invalid("Evaluation", "goal_low/goal_high", format!("a box that meets the reachable ball of radius {}", crate::error::G(r)), format!("{goal_low:?}..{goal_high:?}")));
    }
    let mut tries = 0usize;
    while goals.len() < n_goals {
        let g = point(&(0..m).map(|i| uniform(rng, lo[i], hi[i])).collect::<Vec<f64>>());
        tries += 1;
        if g.iter().fold(0.0, |s, v| s + v * v) <= r * r {
            goals.push(g);
        } else if tries > 1000 * n_goals.max(1) {
            return Err(invalid("Evaluation", "goal_low/goal_high", "a box with a reachable part of non-negligible area", format!("{goal_low:?}..{goal_high:?}")));
        }
    }
    Ok(goals)
}

impl TestSet {
    /// The test sets of seed `seed` on the built-in arm `arm`.
    pub fn new(arm: &ArmConfig, goal_low: &[f64], goal_high: &[f64], eval: &EvalConfig, motion_step: f64, seed: u64) -> Result<Self> {
        let mut a = Arm::new(arm.clone())?;
        Self::with_body(arm, &mut a, goal_low, goal_high, eval, motion_step, seed, None)
    }

    /// Goals uniform in the reachable part of the goal box (the box intersected with the ball of
    /// radius = arm length: a disk for the planar arm); configurations as `eval.test_configs`
    /// says, their positions measured on `body` (placed there at once; not a time step). `arm`
    /// gives the reach and the joint limits. With `cloud` (positions a user's body reached),
    /// goals come from it as a chain's do, wherever the body's base is.
    #[allow(clippy::too_many_arguments)]
    pub fn with_body(arm: &ArmConfig, body: &mut dyn Body, goal_low: &[f64], goal_high: &[f64], eval: &EvalConfig, motion_step: f64, seed: u64, cloud: Option<&Cloud>) -> Result<Self> {
        let r: f64 = arm.link_lengths.iter().sum();
        let (n, m, lim) = (arm.link_lengths.len(), goal_low.len(), arm.joint_limit);
        let mut rng = rng_from_seed(seed);
        // A chain's reachable set is no ball about the origin: goals come from a cloud of its positions.
        // Each goal of a chain comes with a configuration reaching it: one more start for the IK.
        let chain = arm.chain.as_ref().map(crate::body::chain::Chain::new);
        let draw = |rng: &mut CoreRng, k: usize| -> Result<Drawn> {
            Ok(match (&chain, cloud) {
                (_, Some(cloud)) => cloud.goals(goal_low, goal_high, k, rng, "the body's")?.into_iter().map(|(g, t)| (g, Some(t))).unzip(),
                (Some(chain), None) => crate::evaluation::reachable_cloud::chain_goals(chain, lim, goal_low, goal_high, k, rng)?.into_iter().map(|(g, t)| (g, Some(t))).unzip(),
                (None, None) => draw_goals(rng, r, goal_low, goal_high, k)?.into_iter().map(|g| (g, None)).unzip(),
            })
        };
        let (goals, mut known) = draw(&mut rng, eval.n_test_goals)?;
        let (configs, true_x, ik_residuals): (Vec<Vec<f64>>, Vec<Point>, Vec<f64>) = match eval.test_configs {
            TestConfigs::Uniform => {
                let configs: Vec<Vec<f64>> = (0..eval.n_test_configs).map(|_| (0..n).map(|_| uniform(&mut rng, -lim, lim)).collect()).collect();
                (configs, Vec::new(), Vec::new())
            }
            TestConfigs::IkMinNorm => {
                // The test goals in order, then more from the same distribution if needed.
                let (extra, extra_known) = draw(&mut rng, eval.n_test_configs.saturating_sub(goals.len()))?;
                known.extend(extra_known);
                let targets = goals.iter().chain(&extra).zip(&known).take(eval.n_test_configs);
                let mut kinematics = BodyKinematics(&mut *body);
                let solved: Vec<_> = targets.map(|(g, k)| min_norm_ik_from(&mut kinematics, n, m, lim, g, IK_TOLERANCE * r, k.as_deref())).collect();
                let residuals = solved.iter().map(|s| s.residual).collect();
                (solved.into_iter().map(|s| s.theta).collect(), Vec::new(), residuals)
            }
        };
        let motions: Vec<Vec<f64>> = configs.iter().map(|c| c.iter().map(|&t| (t + uniform(&mut rng, -motion_step, motion_step)).clamp(-lim, lim) - t).collect()).collect();
        let mut tests = TestSet { goals, configs, true_x, motions, true_dx: Vec::new(), ik_residuals, kind: eval.test_configs };
        tests.true_x = tests.measure_x(body);
        tests.true_dx = tests.measure_dx(body);
        Ok(tests)
    }

    /// The position of each test configuration on `body`.
    pub fn measure_x(&self, body: &mut dyn Body) -> Vec<Point> {
        self.configs
            .iter()
            .map(|c| match self.kind {
                // A placement and a reading, as before the IK test set existed (same bits).
                TestConfigs::Uniform => {
                    body.set_theta(c);
                    body.position()
                }
                TestConfigs::IkMinNorm => position_at(body, c),
            })
            .collect()
    }

    /// The displacement each test motion causes on `body` (noise-free where the body knows its
    /// kinematics).
    pub fn measure_dx(&self, body: &mut dyn Body) -> Vec<Point> {
        self.configs
            .iter()
            .zip(&self.motions)
            .map(|(c, d)| {
                let moved: Vec<f64> = c.iter().zip(d).map(|(t, d)| t + d).collect();
                let x0 = position_at(body, c);
                sub(&position_at(body, &moved), &x0)
            })
            .collect()
    }

    /// Test goals out of reach within the joint limits (their configurations are the closest
    /// ones found), for `reach` the arm's length.
    pub fn unreached(&self, reach: f64) -> usize {
        self.ik_residuals.iter().filter(|&&e| e > IK_TOLERANCE * reach).count()
    }
}

/// Errors measured at one evaluation.
#[derive(Debug, Clone, PartialEq)]
pub struct EvalResult {
    pub reach_errors: Vec<f64>,
    pub pred_errors: Vec<f64>,
    /// Relative errors of the differential model, one per test motion that moves the body.
    pub dx_errors: Vec<f64>,
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
    pub fn mean_dx(&self) -> f64 {
        mean(&self.dx_errors)
    }
}

/// |predicted - truth| / |truth|; None where the truth is no motion at all (a test motion
/// pushing against a joint limit on every joint).
pub(crate) fn relative_error(predicted: &Point, truth: &Point) -> Option<f64> {
    let zero = [0.0; crate::task_space::MAX_TASK_DIM];
    let norm = crate::task_space::distance(truth, &zero);
    (norm > 0.0).then(|| crate::task_space::distance(predicted, truth) / norm)
}

fn mean(v: &[f64]) -> f64 {
    v.iter().sum::<f64>() / v.len().max(1) as f64
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::body::arm::ArmKind;
    use crate::task_space::{distance, MAX_TASK_DIM};

    /// Test goals lie in the goal box and within the arm's reach, and fill that set: in 3-D,
    /// for the half ball x >= 0, their mean x is 3r/8 (the half ball's centroid).
    #[test]
    fn test_goals_fill_the_reachable_part_of_the_box() {
        let mut arm = ArmConfig::uniform(15, 50.0, std::f64::consts::FRAC_PI_2, 0.05);
        arm.kind = ArmKind::Spatial;
        let (lo, hi) = ([0.0, -50.0, -50.0], [50.0, 50.0, 50.0]);
        let eval = |g, c, k| EvalConfig { n_test_goals: g, n_test_configs: c, test_configs: k, ..EvalConfig::default() };
        let t = TestSet::new(&arm, &lo, &hi, &eval(4000, 3, TestConfigs::Uniform), 0.01, 9).unwrap();
        let zero = [0.0; MAX_TASK_DIM];
        for g in &t.goals {
            assert!(distance(g, &zero) <= 50.0 && (0..3).all(|i| g[i] >= lo[i] && g[i] <= hi[i]), "{g:?}");
        }
        let mean_x = t.goals.iter().map(|g| g[0]).sum::<f64>() / 4000.0;
        assert!((mean_x - 3.0 * 50.0 / 8.0).abs() < 0.6, "{mean_x}");
        // A box out of reach is refused with the rule.
        let e = TestSet::new(&arm, &[60.0, 0.0, 0.0], &[70.0, 1.0, 1.0], &eval(1, 1, TestConfigs::Uniform), 0.01, 9).unwrap_err().to_string();
        assert!(e.contains("meets the reachable ball of radius 50"), "{e}");
        // The test configurations' positions are the arm's.
        let a = Arm::new(arm).unwrap();
        assert_eq!(t.true_x[0], a.forward(&t.configs[0]));
    }

    /// The least-norm test configurations reach their goals, do not depend on anything but the
    /// seed, and their motions are small and measured on the arm.
    #[test]
    fn least_norm_configurations_reach_their_goals() {
        let arm = ArmConfig::uniform(15, 50.0, std::f64::consts::FRAC_PI_2, 0.05);
        let (lo, hi) = ([0.0, -50.0], [50.0, 50.0]);
        let eval = EvalConfig { n_test_goals: 12, n_test_configs: 15, ..EvalConfig::default() };
        let t = TestSet::new(&arm, &lo, &hi, &eval, 0.01, 4).unwrap();
        assert_eq!(t.kind, TestConfigs::IkMinNorm);
        assert_eq!((t.goals.len(), t.configs.len(), t.ik_residuals.len()), (12, 15, 15));
        assert_eq!(t.unreached(50.0), 0);
        let a = Arm::new(arm.clone()).unwrap();
        for (i, c) in t.configs.iter().enumerate() {
            assert!(c.iter().all(|v| v.abs() <= arm.joint_limit));
            assert_eq!(t.true_x[i], a.forward(c));
            if i < 12 {
                // The first configurations are the test goals'; three more goals were drawn.
                assert!(crate::task_space::distance(&t.true_x[i], &t.goals[i]) <= 1e-9 * 50.0);
            }
            assert!(t.motions[i].iter().all(|d| d.abs() <= 0.01));
            let moved: Vec<f64> = c.iter().zip(&t.motions[i]).map(|(c, d)| c + d).collect();
            assert_eq!(t.true_dx[i], sub(&a.forward(&moved), &a.forward(c)));
        }
        // The same seed, the same sets; another seed, other goals.
        let again = TestSet::new(&arm, &lo, &hi, &eval, 0.01, 4).unwrap();
        assert_eq!((&again.configs, &again.motions), (&t.configs, &t.motions));
        assert_ne!(TestSet::new(&arm, &lo, &hi, &eval, 0.01, 5).unwrap().goals, t.goals);
        // The reaching goals are those of the uniform test set of the same seed.
        let uniform = TestSet::new(&arm, &lo, &hi, &EvalConfig { test_configs: TestConfigs::Uniform, ..eval.clone() }, 0.01, 4).unwrap();
        assert_eq!(uniform.goals, t.goals);
    }
}

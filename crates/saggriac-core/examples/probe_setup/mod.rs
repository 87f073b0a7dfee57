//! What the probes share: an exp2 learner run to `steps` (one evaluation, at the end, of one
//! test goal), the 100 test goals of one evaluation, and the neighbour queries its reaches ask.

use saggriac_core::config::evaluation::{EvalConfig, TestConfigs};
use saggriac_core::evaluation::TestSet;
use saggriac_core::body::arm::Arm;
use saggriac_core::model::local_model::LocalModel;
use saggriac_core::model::memory::SensorimotorMemory;
use saggriac_core::model::neighbours::{Neighbour, WarmStart};
use saggriac_core::task_space::{desired_step, distance};
use saggriac_core::{config::Condition, Learner, RunConfig};

pub fn exp2_learner(steps: u64, cond: Condition) -> (RunConfig, Learner) {
    let mut cfg = RunConfig { n_steps: steps, condition: cond, goal_low: vec![0.0, -150.0], goal_high: vec![150.0, 150.0], ..RunConfig::default() };
    cfg.exploration.q = 100;
    cfg.eval.schedule = vec![steps];
    cfg.eval.n_test_goals = 1;
    cfg.eval.n_test_configs = 1;
    let mut l = Learner::new(cfg.clone(), 0, 1).unwrap();
    l.run(&mut |_| true);
    (cfg, l)
}

/// The test goals of one evaluation (100), with one uniform test configuration.
pub fn test_goals(cfg: &RunConfig) -> TestSet {
    let eval = EvalConfig { n_test_goals: 100, n_test_configs: 1, test_configs: TestConfigs::Uniform, ..cfg.eval.clone() };
    TestSet::new(&cfg.arm, &cfg.goal_low, &cfg.goal_high, &eval, cfg.exploration.step, 1).unwrap()
}

/// Reach the first `n_goals` test goals as the evaluation does (the arm reset every other goal,
/// steps of 0.5 towards the goal, the warm-started neighbour search), calling
/// `query(fresh, theta, neighbours)` at each search (`fresh`: the first of its goal).
#[allow(dead_code)] // not every probe replays the reaches
pub fn replay_test_reaches(cfg: &RunConfig, mem: &SensorimotorMemory, n_goals: usize, mut query: impl FnMut(bool, &[f64], &[Neighbour])) {
    let n = mem.n_joints();
    let tests = test_goals(cfg);
    let mut arm = Arm::new(cfg.arm.clone()).unwrap();
    let mut model = LocalModel::new(n, 2, cfg.local.clone());
    let mut ws = WarmStart::new(cfg.warm_start_recent);
    let mut nb: Vec<Neighbour> = Vec::new();
    let mut dtheta = vec![0.0; n];
    for (i, g) in tests.goals.iter().take(n_goals).enumerate() {
        if i % 2 == 0 {
            arm.reset();
        }
        ws.clear();
        let mut fresh = true;
        for _ in 0..(2.0 * distance(g, &arm.position()) / 0.5).ceil() as usize + 20 {
            let x = arm.position();
            if distance(g, &x) <= 0.01 {
                break;
            }
            let th = arm.theta().to_vec();
            mem.knn_warm(&mut ws, &th, cfg.local.k_neighbours, &mut nb);
            query(fresh, &th, &nb);
            fresh = false;
            let dx = desired_step(&x, g, 0.5);
            if model.fit(mem, &nb).and_then(|_| model.inverse(&dx[..2], &mut dtheta)).is_err() {
                break;
            }
            arm.step(&mut dtheta);
        }
    }
}

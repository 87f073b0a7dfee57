//! What the probes share: an exp2 learner run to `steps` (one evaluation, at the end, of one
//! test goal) and the 100 test goals of one evaluation.

use saggriac_core::config::evaluation::{EvalConfig, TestConfigs};
use saggriac_core::evaluation::TestSet;
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

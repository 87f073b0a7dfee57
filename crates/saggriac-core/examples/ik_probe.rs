//! Cost of the forward-model metric's test configurations: `cargo run --release --example ik_probe -- [n_goals]`.
use saggriac_core::body::arm::Arm;
use saggriac_core::evaluation::min_norm_ik::{min_norm_ik, BodyKinematics, Kinematics};
use saggriac_core::task_space::Point;

struct Counting<'a>(BodyKinematics<'a>, usize, usize);
impl Kinematics for Counting<'_> {
    fn position(&mut self, t: &[f64]) -> Point {
        self.1 += 1;
        self.0.position(t)
    }
    fn jacobian(&mut self, t: &[f64], out: &mut [f64]) -> bool {
        self.2 += 1;
        self.0.jacobian(t, out)
    }
}

fn main() {
    let n_goals: usize = std::env::args().nth(1).and_then(|s| s.parse().ok()).unwrap_or(100);
    let cfg = saggriac_core::RunConfig { goal_low: vec![0.0, -150.0], goal_high: vec![150.0, 150.0], ..Default::default() };
    let eval = saggriac_core::config::evaluation::EvalConfig { n_test_goals: n_goals, n_test_configs: 1, test_configs: saggriac_core::config::evaluation::TestConfigs::Uniform, ..cfg.eval.clone() };
    let tests = saggriac_core::evaluation::TestSet::new(&cfg.arm, &cfg.goal_low, &cfg.goal_high, &eval, 0.01, 1).unwrap();
    let mut arm = Arm::new(cfg.arm.clone()).unwrap();
    let mut k = Counting(BodyKinematics(&mut arm), 0, 0);
    let t0 = std::time::Instant::now();
    let mut norms = 0.0;
    for g in &tests.goals {
        let s = min_norm_ik(&mut k, 15, 2, cfg.arm.joint_limit, g, 5e-8);
        norms += s.theta.iter().map(|v| v * v).sum::<f64>();
    }
    println!("{n_goals} goals: {:.1} ms, {} positions, {} jacobians, mean |theta|^2 {:.6}", t0.elapsed().as_secs_f64() * 1e3, k.1, k.2, norms / n_goals as f64);
}

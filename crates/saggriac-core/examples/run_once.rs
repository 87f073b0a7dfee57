//! Run one learner from the command line and print its learning curve:
//! `cargo run --release --example run_once -- [exp1|exp2] [seed] [steps] [condition]`.

use saggriac_core::{Condition, Learner, RunConfig};

fn main() {
    let args: Vec<String> = std::env::args().collect();
    let exp = args.get(1).map(String::as_str).unwrap_or("exp1");
    let seed: u64 = args.get(2).and_then(|s| s.parse().ok()).unwrap_or(0);
    let mut cfg = RunConfig::default();
    if exp == "exp2" {
        cfg.n_steps = 200_000;
        cfg.goal_low = vec![0.0, -150.0];
        cfg.goal_high = vec![150.0, 150.0];
        cfg.exploration.q = 100;
    }
    if let Some(s) = args.get(3).and_then(|s| s.parse().ok()) {
        cfg.n_steps = s;
    }
    if let Some(c) = args.get(4) {
        cfg.condition = Condition::parse(c).expect("condition");
    }
    let mut threads = 1;
    for kv in args.iter().skip(5) {
        let (k, v) = kv.split_once('=').expect("key=value");
        if k == "threads" {
            threads = v.parse().expect("a number of threads");
            continue;
        }
        if k == "index" {
            cfg.index = saggriac_core::model::memory::IndexKind::parse(v).expect("index kind");
            continue;
        }
        let f: f64 = v.parse().expect("number");
        match k {
            "eps_max" => cfg.reaching.eps_max = f,
            "k" => cfg.local.k_neighbours = f as usize,
            "ridge" => cfg.local.ridge = f,
            "bw" => cfg.local.bandwidth = f,
            "rcond" => cfg.local.pinv_rcond = f,
            "step" => cfg.exploration.step = f,
            "q" => cfg.exploration.q = f as usize,
            "eps_c" => cfg.competence.eps_c = f,
            "tf" => cfg.reaching.timeout_factor = f,
            "maxstep" => cfg.arm.max_joint_step = f,
            "warm" => cfg.warm_start_recent = f as usize,
            "babble_step" => cfg.babble_step = f,
            _ => panic!("unknown key {k}"),
        }
    }
    cfg.eval.schedule = (0..=20).map(|i| i * cfg.n_steps / 20).collect();
    let mut l = Learner::new(cfg, seed, seed + 1000).expect("valid config");
    l.set_threads(threads);
    let t = std::time::Instant::now();
    l.run(&mut |m| {
        println!("step {:>7} samples {:>7} goals {:>5} regions {:>4} reach {:>8.3} pred {:>8.3}", m.step, m.n_samples, m.n_goals, m.n_regions, m.reach_error, m.pred_error);
        true
    });
    let wall = t.elapsed().as_secs_f64();
    println!("wall {wall:.2}s  {:.0} steps/s  timers {:?}", l.steps() as f64 / wall, l.timers());
    println!("counters {:?}", l.counters());
    println!("evaluation knn/fit {:?}", l.evaluation_split());
}

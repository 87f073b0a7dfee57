//! Replays the test reaches of one evaluation and records the neighbour queries (probe).
#[path = "probe_setup/mod.rs"]
mod probe_setup;
use saggriac_core::body::arm::Arm;
use saggriac_core::config::Condition;
use saggriac_core::model::local_model::LocalModel;
use saggriac_core::model::neighbours::{dist_sq, Neighbour, WarmStart};
use saggriac_core::task_space::desired_step;

fn main() {
    let args: Vec<String> = std::env::args().collect();
    let steps: u64 = args.get(1).and_then(|s| s.parse().ok()).unwrap_or(200_000);
    let cond = Condition::parse(args.get(2).map(|s| s.as_str()).unwrap_or("actuator_random")).unwrap();
    let (cfg, l) = probe_setup::exp2_learner(steps, cond);
    let mem = l.memory();
    let n = mem.n_joints();
    let tests = probe_setup::test_goals(&cfg);
    let mut arm = Arm::new(cfg.arm.clone()).unwrap();
    let mut model = LocalModel::new(n, 2, cfg.local.clone());
    let mut ws = WarmStart::new(8);
    let mut nb: Vec<Neighbour> = Vec::new();
    let k = cfg.local.k_neighbours;
    let mut qs: Vec<Vec<f64>> = Vec::new();
    let mut rk: Vec<f64> = Vec::new();
    let mut dtheta = vec![0.0; n];
    let t0 = std::time::Instant::now();
    for (i, g) in tests.goals.iter().enumerate() {
        if i % 2 == 0 {
            arm.reset();
        }
        ws.clear();
        let dist = |x: saggriac_core::task_space::Point| saggriac_core::task_space::distance(g, &x);
        let d0 = dist(arm.position());
        let timeout = (2.0 * d0 / 0.5).ceil() as usize + 20;
        let (mut best, mut since) = (d0, 0);
        for _ in 0..timeout {
            let x = arm.position();
            if dist(x) <= 0.01 {
                break;
            }
            let dx = desired_step(&x, g, 0.5);
            let th = arm.theta().to_vec();
            mem.knn_warm(&mut ws, &th, k, &mut nb);
            qs.push(th.clone());
            rk.push(nb.last().unwrap().dist_sq.sqrt());
            if model.fit(mem, &nb).and_then(|_| model.inverse(&dx[..2], &mut dtheta)).is_err() {
                break;
            }
            arm.step(&mut dtheta);
            let d = dist(arm.position());
            if d < best {
                best = d;
                since = 0;
            } else {
                since += 1;
                if since >= 10 {
                    break;
                }
            }
        }
    }
    let el = t0.elapsed().as_secs_f64();
    println!("{} queries, {:.1} us each (knn+fit)", qs.len(), el / qs.len() as f64 * 1e6);
    let mut s = rk.clone();
    s.sort_by(|a, b| a.total_cmp(b));
    println!("r_k quantiles 10/50/90: {:.3} {:.3} {:.3}", s[s.len() / 10], s[s.len() / 2], s[9 * s.len() / 10]);
    let steps: Vec<f64> = qs.windows(2).map(|w| dist_sq(&w[0], &w[1]).sqrt()).collect();
    let mut st = steps.clone();
    st.sort_by(|a, b| a.total_cmp(b));
    println!("query step quantiles 10/50/90: {:.3} {:.3} {:.3}", st[st.len() / 10], st[st.len() / 2], st[9 * st.len() / 10]);
    // Candidate-ball size for an anchor every query, for several margins (sampled).
    let pts: Vec<Vec<f64>> = (0..mem.len()).map(|i| mem.theta(i)).collect();
    for delta in [0.05, 0.1, 0.2, 0.4] {
        let mut sizes = Vec::new();
        let mut runs = Vec::new();
        let mut i = 0;
        while i < qs.len() {
            let r = rk[i] + 2.0 * delta;
            let c = pts.iter().filter(|p| dist_sq(p, &qs[i]) <= r * r).count();
            sizes.push(c);
            let mut j = i + 1;
            while j < qs.len() && dist_sq(&qs[j], &qs[i]).sqrt() <= delta {
                j += 1;
            }
            runs.push(j - i);
            i = j.max(i + 1);
            if sizes.len() > 300 {
                break;
            }
        }
        sizes.sort();
        let mr = runs.iter().sum::<usize>() as f64 / runs.len() as f64;
        println!("delta {delta}: candidates median {} p90 {} ; queries per anchor {:.1}", sizes[sizes.len() / 2], sizes[9 * sizes.len() / 10], mr);
    }
}

//! One evaluation of the micro-action paradigm, as a function of what it reads: the memory (a
//! snapshot), a body to run the test reaches on, the test sets and the parameters. The
//! evaluator calls it in the learner's thread or hands it to the pool (`pool.rs`).

use crate::body::Body;
use crate::config::evaluation::EvalConfig;
use crate::config::LocalModelConfig;
use crate::evaluation::test_set::{relative_error, EvalResult, TestSet};
use crate::model::local_query::LocalQuery;
use crate::model::memory::SensorimotorMemory;
use crate::model::neighbours::Neighbour;
use crate::task_space::{desired_step, distance, Point, MAX_TASK_DIM};

/// What a micro-action evaluation needs besides the memory, the body and the tests: the same
/// for every evaluation of a run, so a worker thread gets a copy.
#[derive(Debug, Clone)]
pub(crate) struct MicroParams {
    pub cfg: EvalConfig,
    pub local: LocalModelConfig,
    pub v: f64,
    pub warm_start_recent: usize,
}

/// The scratch state a micro-action evaluation works in. Nothing in it carries over from one
/// evaluation to the next (the warm start and the rest answer are cleared at its start, and a
/// local model is read only after a fit that overwrote it), so a fresh one gives the same results.
pub(crate) struct MicroScratch {
    /// The inverse model's query along the test reaches: the learner's (`LocalQuery`), on the
    /// evaluator's own scratch; its local model also makes the forward predictions.
    query: LocalQuery,
    /// The configuration the last reach from rest started at and its neighbours: half the test
    /// reaches start at rest, and the memory does not change during an evaluation.
    rest: Option<(Vec<f64>, Vec<Neighbour>)>,
    /// Whether `rest` is kept (always, but for the test that checks it changes nothing).
    keep_rest: bool,
    /// Seconds spent in neighbour search and in local fits.
    pub time_knn: f64,
    pub time_fit: f64,
}

impl MicroScratch {
    pub fn new(p: &MicroParams, n_joints: usize, task_dim: usize) -> Self {
        MicroScratch { query: LocalQuery::new(n_joints, task_dim, p.local.clone(), p.warm_start_recent), rest: None, keep_rest: true, time_knn: 0.0, time_fit: 0.0 }
    }
}

/// Micro-actions: closed-loop test reaches with the inverse model (on `arm`, from rest), forward
/// predictions by the local model fitted on `predict_neighbours[i]`, the exact k nearest stored
/// configurations of test configuration i (kept up to date by the evaluator).
pub(crate) fn evaluate_micro(p: &MicroParams, tests: &TestSet, memory: &SensorimotorMemory, arm: &mut dyn Body, s: &mut MicroScratch, predict_neighbours: &[Vec<Neighbour>]) -> EvalResult {
    let mut reach_errors = Vec::with_capacity(tests.goals.len());
    let mut test_steps = 0;
    s.rest = None;
    s.query.forget_trajectory();
    arm.reset();
    for (i, &g) in tests.goals.iter().enumerate() {
        // Even tests start from rest, odd ones from where the previous test ended (where the
        // previous neighbours still help a search).
        let from_rest = i % 2 == 0;
        if from_rest {
            arm.reset();
            s.query.forget_trajectory();
        }
        let (err, steps) = test_reach(p, memory, arm, g, from_rest, s);
        reach_errors.push(err);
        test_steps += steps;
    }
    let m = memory.task_dim();
    let mut pred_errors = Vec::with_capacity(tests.configs.len());
    let mut dx_errors = Vec::with_capacity(tests.configs.len());
    let mut xp = [0.0; MAX_TASK_DIM];
    for (i, (c, nb)) in tests.configs.iter().zip(predict_neighbours).enumerate() {
        let ok = memory.len() >= p.local.k_neighbours && s.query.local_mut().fit(memory, nb).is_ok();
        if ok {
            s.query.local().predict_x(memory, nb, c, &mut xp[..m]);
        } else if let Some(first) = nb.first() {
            // No fit possible: the nearest sample's position is the prediction.
            xp[..m].copy_from_slice(memory.x(first.id as usize));
        } else {
            xp = [0.0; MAX_TASK_DIM];
        }
        pred_errors.push(distance(&xp, &tests.true_x[i]));
        // The differential model J dtheta, or no motion without a fit.
        let mut dxp = [0.0; MAX_TASK_DIM];
        if ok {
            let j = s.query.local().jacobian();
            for (r, v) in dxp.iter_mut().take(m).enumerate() {
                *v = tests.motions[i].iter().enumerate().map(|(a, d)| j[(r, a)] * d).sum();
            }
        }
        dx_errors.extend(relative_error(&dxp, &tests.true_dx[i]));
    }
    EvalResult { reach_errors, pred_errors, dx_errors, test_steps }
}

/// Closed-loop reach with the learnt inverse model only: no exploration, no storing.
fn test_reach(p: &MicroParams, memory: &SensorimotorMemory, arm: &mut dyn Body, goal: Point, from_rest: bool, s: &mut MicroScratch) -> (f64, u64) {
    let dist = |x: Point| distance(&goal, &x);
    let d0 = dist(arm.position());
    let timeout = (p.cfg.timeout_factor * d0 / p.v).ceil() as usize + p.cfg.timeout_min;
    let k = p.local.k_neighbours;
    let mut best = d0;
    let mut since_best = 0;
    let mut steps = 0;
    let mut dtheta = vec![0.0; arm.n_joints()];
    if memory.len() < k {
        return (d0, 0);
    }
    for _ in 0..timeout {
        let x = arm.position();
        if dist(x) <= p.cfg.tolerance {
            break;
        }
        let dx = desired_step(&x, &goal, p.v);
        let theta = arm.theta().to_vec();
        let t0 = std::time::Instant::now();
        let at_rest = from_rest && steps == 0;
        match &s.rest {
            Some((t, nb)) if at_rest && *t == theta => s.query.reuse(nb),
            _ => {
                s.query.find(memory, &theta);
                if at_rest && s.keep_rest {
                    s.rest = Some((theta.clone(), s.query.neighbours().to_vec()));
                }
            }
        }
        let t1 = std::time::Instant::now();
        let fitted = s.query.fit(memory).and_then(|_| s.query.inverse(&dx[..memory.task_dim()], &mut dtheta));
        let t2 = std::time::Instant::now();
        s.time_knn += (t1 - t0).as_secs_f64();
        s.time_fit += (t2 - t1).as_secs_f64();
        if fitted.is_err() {
            break;
        }
        arm.step(&mut dtheta);
        steps += 1;
        let d = dist(arm.position());
        if d < best {
            best = d;
            since_best = 0;
        } else {
            since_best += 1;
            if since_best >= p.cfg.patience {
                break;
            }
        }
    }
    (dist(arm.position()), steps)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::body::arm::Arm;
    use crate::{Learner, RunConfig};

    /// The shortcuts of an evaluation (warm starts across odd tests, the answer at rest reused)
    /// change nothing: the same errors as cold searches without them, and a reused scratch
    /// gives what a fresh one does.
    #[test]
    fn shortcuts_give_the_errors_of_cold_searches() {
        let mut cfg = RunConfig { n_steps: 3000, ..RunConfig::default() };
        cfg.eval.schedule = vec![3000];
        let mut l = Learner::new(cfg.clone(), 4, 5).unwrap();
        l.run(&mut |_| true);
        let (mem, tests) = (l.memory(), l.test_set());
        let predict: Vec<Vec<Neighbour>> = tests
            .configs
            .iter()
            .map(|c| {
                let mut nb = Vec::new();
                mem.knn(c, cfg.local.k_neighbours, &mut nb);
                nb
            })
            .collect();
        let params = |recent| MicroParams { cfg: cfg.eval.clone(), local: cfg.local.clone(), v: cfg.reaching.v, warm_start_recent: recent };
        let run = |p: &MicroParams, s: &mut MicroScratch| evaluate_micro(p, tests, mem, &mut Arm::new(cfg.arm.clone()).unwrap(), s, &predict);
        let (warm, cold) = (params(8), params(0));
        let mut s = MicroScratch::new(&warm, mem.n_joints(), 2);
        let first = run(&warm, &mut s);
        assert!(first.test_steps > 100, "the test reaches moved: {}", first.test_steps);
        assert!(s.rest.is_some(), "the answer at rest was kept");
        assert_eq!(run(&warm, &mut s), first);
        let mut plain = MicroScratch::new(&cold, mem.n_joints(), 2);
        plain.keep_rest = false;
        assert_eq!(run(&cold, &mut plain), first);
        assert!(plain.rest.is_none());
    }
}

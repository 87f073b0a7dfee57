//! Evaluation (SPEC.md "Evaluation"): reaching error of the learnt inverse model on fixed test
//! goals, and prediction error of the learnt forward model on fixed test configurations. It gets
//! the model as a `ModelView` (shared references only: it cannot write what was learnt) and its
//! micro-actions run on a scratch copy of the body, so evaluation neither counts as time nor
//! changes what is learnt.

use crate::arm::{Arm, ArmConfig};
use crate::body::Body;
pub use crate::config::evaluation::EvalConfig;
use crate::config::{EpisodicConfig, RunConfig};
use crate::episodic_memory::EpisodicMemory;
use crate::error::{invalid, Result};
use crate::local_model::LocalModel;
use crate::memory::SensorimotorMemory;
use crate::neighbours::{Neighbour, WarmStart};
use crate::rng::{rng_from_seed, uniform};
use crate::sensorimotor_model::ModelView;
use crate::task_space::{desired_step, distance, point, Point, MAX_TASK_DIM};

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

pub struct Evaluator {
    pub cfg: EvalConfig,
    pub tests: TestSet,
    /// Episodic paradigm: each test configuration's neighbours so far, and how many samples
    /// they cover (the memory only grows, so each evaluation scans only the new samples).
    forward_cache: Vec<(Vec<Neighbour>, usize)>,
    scan_acc: Vec<f64>,
    /// The body the test reaches run on, when the learner's body can make a copy.
    pub(crate) scratch: Option<Box<dyn Body>>,
    model: LocalModel,
    warm: WarmStart,
    neighbours: Vec<Neighbour>,
    v: f64,
    warm_start: bool,
    episodic: EpisodicConfig,
    rcond: f64,
    /// Nearest-neighbour scratch of the episodic inverse model.
    nb: Vec<Neighbour>,
    /// Scheduled evaluations done so far.
    pub(crate) next_eval: usize,
    /// Seconds spent in neighbour search and in local fits during evaluations.
    pub time_knn: f64,
    pub time_fit: f64,
}

impl Evaluator {
    /// The evaluation of a run configured by `run`, on `tests`, with test reaches on `scratch`
    /// (None: on the learner's body, put back afterwards).
    pub fn new(run: &RunConfig, tests: TestSet, scratch: Option<Box<dyn Body>>, n_joints: usize, task_dim: usize) -> Self {
        Evaluator {
            cfg: run.eval.clone(),
            tests,
            forward_cache: Vec::new(),
            scan_acc: Vec::new(),
            scratch,
            model: LocalModel::new(n_joints, task_dim, run.local.clone()),
            warm: WarmStart::new(run.warm_start_recent),
            neighbours: Vec::new(),
            v: run.reaching.v,
            warm_start: run.warm_start_recent > 0,
            episodic: run.episodic,
            rcond: run.local.pinv_rcond,
            nb: Vec::new(),
            next_eval: 0,
            time_knn: 0.0,
            time_fit: 0.0,
        }
    }

    /// Whether an evaluation scheduled at or before time step `steps` is still to run; if so it
    /// counts as done from now.
    pub fn due(&mut self, steps: u64) -> bool {
        let due = self.next_eval < self.cfg.schedule.len() && self.cfg.schedule[self.next_eval] <= steps;
        self.next_eval += usize::from(due);
        due
    }

    /// Evaluate the model seen through `model`: test reaches run on the scratch body or, if the
    /// learner's body cannot be copied, on `body` itself, which is put back where it was.
    pub fn evaluate(&mut self, model: ModelView<'_>, body: &mut dyn Body) -> EvalResult {
        match model.episodes() {
            Some(mem) => self.evaluate_episodic(mem, body),
            None => self.evaluate_micro(model.samples(), body),
        }
    }

    /// The learner's body changed: copy it again and measure the test configurations anew.
    pub fn body_changed(&mut self, main: &mut dyn Body) {
        self.scratch = main.scratch();
        let configs = self.tests.configs.clone();
        self.tests.true_x = self.on_body(main, |_, b| {
            configs
                .iter()
                .map(|c| {
                    b.set_theta(c);
                    b.position()
                })
                .collect()
        });
    }

    /// Run `f` on the scratch body if there is one, else on `main`, put back afterwards.
    fn on_body<T>(&mut self, main: &mut dyn Body, f: impl FnOnce(&mut Self, &mut dyn Body) -> T) -> T {
        match self.scratch.take() {
            Some(mut s) => {
                let out = f(self, s.as_mut());
                self.scratch = Some(s);
                out
            }
            None => {
                let saved = main.theta().to_vec();
                let out = f(self, &mut *main);
                main.set_theta(&saved);
                out
            }
        }
    }

    /// Micro-actions: closed-loop test reaches with the inverse model, forward predictions by
    /// the local model.
    fn evaluate_micro(&mut self, memory: &SensorimotorMemory, body: &mut dyn Body) -> EvalResult {
        let (reach_errors, test_steps) = self.on_body(body, |ev, arm| {
            let mut reach_errors = Vec::with_capacity(ev.tests.goals.len());
            let mut test_steps = 0;
            arm.reset();
            for i in 0..ev.tests.goals.len() {
                // Even tests start from rest, odd ones from where the previous test ended.
                if i % 2 == 0 {
                    arm.reset();
                }
                ev.warm.clear();
                let g = ev.tests.goals[i];
                let (err, steps) = ev.test_reach(memory, arm, g);
                reach_errors.push(err);
                test_steps += steps;
            }
            (reach_errors, test_steps)
        });
        let k = self.model.cfg.k_neighbours;
        let m = memory.task_dim();
        let mut pred_errors = Vec::with_capacity(self.tests.configs.len());
        let mut xp = [0.0; MAX_TASK_DIM];
        for (c, xt) in self.tests.configs.iter().zip(&self.tests.true_x) {
            let t0 = std::time::Instant::now();
            memory.knn(c, k, &mut self.neighbours);
            self.time_knn += t0.elapsed().as_secs_f64();
            let ok = memory.len() >= k && self.model.fit(memory, &self.neighbours).is_ok();
            if ok {
                self.model.predict_x(memory, &self.neighbours, c, &mut xp[..m]);
            } else if let Some(nb) = self.neighbours.first() {
                // No fit possible: the nearest sample's position is the prediction.
                xp[..m].copy_from_slice(memory.x(nb.id as usize));
            } else {
                xp = [0.0; MAX_TASK_DIM];
            }
            pred_errors.push(distance(&xp, xt));
        }
        EvalResult { reach_errors, pred_errors, test_steps }
    }

    /// The same test sets for the episodic paradigm: each test goal gets one configuration from
    /// the inverse model without exploration noise, executed at once; each test configuration
    /// gets the forward model's prediction.
    fn evaluate_episodic(&mut self, memory: &EpisodicMemory, body: &mut dyn Body) -> EvalResult {
        let (cfg, rcond) = (&self.episodic.clone(), self.rcond);
        let mut nb = std::mem::take(&mut self.nb);
        let t0 = std::time::Instant::now();
        self.forward_cache.resize(self.tests.configs.len(), (Vec::new(), 0));
        let reach_errors = self.on_body(body, |ev, arm| {
            let mut theta = vec![0.0; arm.n_joints()];
            ev.tests
                .goals
                .iter()
                .map(|g| {
                    if !memory.inverse(g, cfg, rcond, &mut nb, &mut theta) {
                        theta.iter_mut().for_each(|t| *t = 0.0);
                    }
                    arm.set_theta(&theta);
                    distance(g, &arm.position())
                })
                .collect::<Vec<f64>>()
        });
        self.nb = nb;
        let configs = &self.tests.configs;
        let nq = configs.len();
        let n = configs.first().map_or(0, Vec::len);
        let queries: Vec<f64> = (0..n * nq).map(|j| configs[j % nq][j / nq]).collect();
        memory.knn_theta_since_many(&queries, EpisodicMemory::forward_k(cfg), &mut self.forward_cache, &mut self.scan_acc);
        let pred_errors = configs
            .iter()
            .zip(&self.tests.true_x)
            .zip(&self.forward_cache)
            .map(|((c, xt), (nb, _))| {
                let xp = memory.predict_from(c, nb, cfg).unwrap_or([0.0; MAX_TASK_DIM]);
                distance(&xp, xt)
            })
            .collect();
        self.time_knn += t0.elapsed().as_secs_f64();
        let steps = reach_errors.len() as u64;
        EvalResult { reach_errors, pred_errors, test_steps: steps }
    }

    /// Closed-loop reach with the learnt inverse model only: no exploration, no storing.
    fn test_reach(&mut self, memory: &SensorimotorMemory, arm: &mut dyn Body, goal: Point) -> (f64, u64) {
        let dist = |x: Point| distance(&goal, &x);
        let d0 = dist(arm.position());
        let timeout = (self.cfg.timeout_factor * d0 / self.v).ceil() as usize + self.cfg.timeout_min;
        let k = self.model.cfg.k_neighbours;
        let mut best = d0;
        let mut since_best = 0;
        let mut steps = 0;
        let mut dtheta = vec![0.0; arm.n_joints()];
        if memory.len() < k {
            return (d0, 0);
        }
        for _ in 0..timeout {
            let x = arm.position();
            if dist(x) <= self.cfg.tolerance {
                break;
            }
            let dx = desired_step(&x, &goal, self.v);
            let theta = arm.theta().to_vec();
            let t0 = std::time::Instant::now();
            if self.warm_start {
                memory.knn_warm(&mut self.warm, &theta, k, &mut self.neighbours);
            } else {
                memory.knn(&theta, k, &mut self.neighbours);
            }
            let t1 = std::time::Instant::now();
            let fitted = self.model.fit(memory, &self.neighbours).and_then(|_| self.model.inverse(&dx[..memory.task_dim()], &mut dtheta));
            let t2 = std::time::Instant::now();
            self.time_knn += (t1 - t0).as_secs_f64();
            self.time_fit += (t2 - t1).as_secs_f64();
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
                if since_best >= self.cfg.patience {
                    break;
                }
            }
        }
        (dist(arm.position()), steps)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::arm::ArmKind;

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

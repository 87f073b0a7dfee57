//! Evaluation (docs/reproduction.md, "What is measured"): reaching error of the learnt inverse model on fixed test
//! goals, and prediction error of the learnt forward model on fixed test configurations. It gets
//! the model as a `ModelView` (shared references only: it cannot write what was learnt) and its
//! micro-actions run on a scratch copy of the body, so evaluation neither counts as time nor
//! changes what is learnt.
//!
//! The parts of the evaluator: the fixed test sets (`test_set`, with the least-norm IK of the
//! test configurations, `min_norm_ik`, on a body's `kinematics`, and the draw of test goals from
//! a cloud of reached positions, `reachable_cloud`), one test reach by micro-actions (`micro`),
//! and the pool that runs evaluations beside learning (`pool`).

pub mod kinematics;
pub(crate) mod micro;
pub mod min_norm_ik;
pub(crate) mod pool;
pub mod reachable_cloud;
pub mod test_set;

use std::sync::Arc;

use serde::{Deserialize, Serialize};

use crate::body::Body;
pub use crate::config::evaluation::EvalConfig;
use crate::config::{EpisodicConfig, RunConfig};
use crate::evaluation::micro::{evaluate_micro, MicroParams, MicroScratch};
use crate::evaluation::pool::{Finished, Job, Pool};
use crate::evaluation::test_set::relative_error;
pub use crate::evaluation::test_set::{EvalResult, TestSet};
use crate::model::episodic_memory::EpisodicMemory;
use crate::model::memory::SensorimotorMemory;
use crate::model::neighbours::Neighbour;
use crate::model::sensorimotor_model::ModelView;
use crate::task_space::{distance, sub, Point, MAX_TASK_DIM};

pub struct Evaluator {
    pub cfg: EvalConfig,
    /// Shared with evaluations running on other threads (a body change makes a new one).
    pub tests: Arc<TestSet>,
    /// Episodic paradigm: each test configuration's neighbours so far, and how many samples
    /// they cover (the memory only grows, so each evaluation scans only the new samples).
    forward_cache: Vec<(Vec<Neighbour>, usize)>,
    scan_acc: Vec<f64>,
    /// Micro-actions: the same for the local model's predictions.
    predict_cache: Vec<(Vec<Neighbour>, usize)>,
    /// The body the test reaches run on, when the learner's body can make a copy.
    scratch: Option<Box<dyn Body>>,
    params: MicroParams,
    micro: MicroScratch,
    episodic: EpisodicConfig,
    /// The body's joint limit: an episodic answer is placed within it, as the controller places
    /// its own (a body need not clamp what it is given; a Python body refuses it).
    joint_limit: f64,
    rcond: f64,
    /// Nearest-neighbour scratch of the episodic inverse model.
    nb: Vec<Neighbour>,
    /// Scheduled evaluations done so far.
    next_eval: usize,
    /// Seconds spent in neighbour search and in local fits during evaluations (summed over
    /// threads).
    pub time_knn: f64,
    pub time_fit: f64,
    /// Threads evaluations may use, the learner's included (1: in the learner's thread).
    threads: usize,
    pool: Option<Pool>,
    /// Evaluations started on another thread so far.
    elsewhere: u64,
}

impl Evaluator {
    /// The evaluation of a run configured by `run`, on `tests`, with test reaches on `scratch`
    /// (None: on the learner's body, put back afterwards).
    pub fn new(run: &RunConfig, tests: TestSet, scratch: Option<Box<dyn Body>>, n_joints: usize, task_dim: usize) -> Self {
        let params = MicroParams { cfg: run.eval.clone(), local: run.local.clone(), v: run.reaching.v, warm_start_recent: run.warm_start_recent };
        Evaluator {
            cfg: run.eval.clone(),
            tests: Arc::new(tests),
            forward_cache: Vec::new(),
            scan_acc: Vec::new(),
            predict_cache: Vec::new(),
            scratch,
            micro: MicroScratch::new(&params, n_joints, task_dim),
            params,
            episodic: run.episodic,
            joint_limit: run.arm.joint_limit,
            rcond: run.local.pinv_rcond,
            nb: Vec::new(),
            next_eval: 0,
            time_knn: 0.0,
            time_fit: 0.0,
            threads: 1,
            pool: None,
            elsewhere: 0,
        }
    }

    /// What a checkpoint keeps of the evaluator: how far along the schedule it is, the scratch
    /// body's state, and the test motions' true outcomes (they follow a changed body).
    pub(crate) fn save(&self) -> EvaluatorState {
        EvaluatorState { next_eval: self.next_eval, scratch: self.scratch.as_ref().and_then(|s| s.save()), true_x: self.tests.true_x.clone(), true_dx: self.tests.true_dx.clone() }
    }

    pub(crate) fn restore(&mut self, state: EvaluatorState) {
        if let (Some(sc), Some(st)) = (self.scratch.as_mut(), &state.scratch) {
            sc.load(st);
        }
        let tests = Arc::make_mut(&mut self.tests);
        tests.true_x = state.true_x;
        tests.true_dx = state.true_dx;
        self.next_eval = state.next_eval;
    }

    /// Let evaluations use `threads` threads, the learner's included. They run on copies of the
    /// test body while learning goes on, with the same results as in the learner's thread; a
    /// body whose state outlives a reset (motor or sensor noise, a user's environment) and the
    /// episodic paradigm keep them in the learner's thread.
    pub fn set_threads(&mut self, threads: usize) {
        self.threads = threads.max(1);
    }

    /// Whether an evaluation scheduled at or before time step `steps` is still to run; if so it
    /// counts as done from now.
    pub fn due(&mut self, steps: u64) -> bool {
        let due = self.next_eval < self.cfg.schedule.len() && self.cfg.schedule[self.next_eval] <= steps;
        self.next_eval += usize::from(due);
        due
    }

    /// Whether the evaluation of `model` can run on another thread.
    pub(crate) fn can_run_elsewhere(&self, model: &ModelView<'_>) -> bool {
        self.threads > 1 && model.episodes().is_none() && self.scratch.as_ref().is_some_and(|b| b.forgets_on_reset())
    }

    /// The exact neighbours of every test configuration in `memory`: only the samples stored
    /// since the last evaluation are searched.
    fn predict_neighbours(&mut self, memory: &SensorimotorMemory) -> Vec<Vec<Neighbour>> {
        let t0 = std::time::Instant::now();
        let k = self.params.local.k_neighbours;
        self.predict_cache.resize(self.tests.configs.len(), (Vec::new(), 0));
        for (c, (best, upto)) in self.tests.configs.iter().zip(self.predict_cache.iter_mut()) {
            memory.knn_since(c, k, best, upto);
        }
        self.time_knn += t0.elapsed().as_secs_f64();
        self.predict_cache.iter().map(|(nb, _)| nb.clone()).collect()
    }

    /// Start evaluating `model` on another thread; its result comes back from `finished`.
    pub(crate) fn start(&mut self, index: usize, model: ModelView<'_>) {
        let body = self.scratch.as_ref().and_then(|b| b.scratch()).expect("a body that can be copied (see can_run_elsewhere)");
        let memory = model.samples();
        let predict_neighbours = self.predict_neighbours(memory);
        let job =
            Job { index, memory: memory.clone(), body, tests: Arc::clone(&self.tests), params: self.params.clone(), predict_neighbours, n_joints: memory.n_joints(), task_dim: memory.task_dim() };
        let threads = self.threads;
        self.pool.get_or_insert_with(|| Pool::new(threads - 1)).submit(job);
        self.elsewhere += 1;
    }

    /// Evaluations that ran on another thread so far.
    pub fn evaluations_elsewhere(&self) -> u64 {
        self.elsewhere
    }

    /// Evaluations finished on other threads since the last call; with `wait`, every one
    /// started (this thread helps with those not yet begun).
    pub(crate) fn finished(&mut self, wait: bool) -> Vec<Finished> {
        let Some(pool) = self.pool.as_mut() else { return Vec::new() };
        let done = pool.collect(wait);
        for f in &done {
            self.time_knn += f.time_knn;
            self.time_fit += f.time_fit;
        }
        done
    }

    /// Evaluate the model seen through `model`: test reaches run on the scratch body or, if the
    /// learner's body cannot be copied, on `body` itself, which is put back where it was.
    pub fn evaluate(&mut self, model: ModelView<'_>, body: &mut dyn Body) -> EvalResult {
        match model.episodes() {
            Some(mem) => self.evaluate_episodic(mem, body),
            None => {
                let memory = model.samples();
                let predict_neighbours = self.predict_neighbours(memory);
                let r = self.on_body(body, |ev, arm| {
                    let tests = Arc::clone(&ev.tests);
                    evaluate_micro(&ev.params, &tests, memory, arm, &mut ev.micro, &predict_neighbours)
                });
                self.time_knn += std::mem::take(&mut self.micro.time_knn);
                self.time_fit += std::mem::take(&mut self.micro.time_fit);
                r
            }
        }
    }

    /// The learner's body changed: copy it again and measure the test configurations anew.
    pub fn body_changed(&mut self, main: &mut dyn Body) {
        self.scratch = main.scratch();
        let tests = Arc::clone(&self.tests);
        let (true_x, true_dx) = self.on_body(main, |_, b| (tests.measure_x(b), tests.measure_dx(b)));
        let tests = Arc::make_mut(&mut self.tests);
        tests.true_x = true_x;
        tests.true_dx = true_dx;
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

    /// The same test sets for the episodic paradigm: each test goal gets one configuration from
    /// the inverse model without exploration noise, executed at once; each test configuration
    /// gets the forward model's prediction.
    fn evaluate_episodic(&mut self, memory: &EpisodicMemory, body: &mut dyn Body) -> EvalResult {
        let (cfg, rcond, lim) = (&self.episodic.clone(), self.rcond, self.joint_limit);
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
                    theta.iter_mut().for_each(|t| *t = t.clamp(-lim, lim));
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
        let mut dx_errors = Vec::with_capacity(nq);
        let pred_errors = configs
            .iter()
            .enumerate()
            .zip(&self.forward_cache)
            .map(|((i, c), (nb, _))| {
                let xp = memory.predict_from(c, nb, cfg).unwrap_or([0.0; MAX_TASK_DIM]);
                // The differential model: the same local model at the moved configuration.
                let moved: Vec<f64> = c.iter().zip(&self.tests.motions[i]).map(|(t, d)| t + d).collect();
                let dxp = memory.predict_from(&moved, nb, cfg).map_or([0.0; MAX_TASK_DIM], |x1| sub(&x1, &xp));
                dx_errors.extend(relative_error(&dxp, &self.tests.true_dx[i]));
                distance(&xp, &self.tests.true_x[i])
            })
            .collect();
        self.time_knn += t0.elapsed().as_secs_f64();
        let steps = reach_errors.len() as u64;
        EvalResult { reach_errors, pred_errors, dx_errors, test_steps: steps }
    }
}

/// The evaluator's part of a checkpoint; `Body` is the scratch body's saved state (its bytes; a
/// checkpoint of format 5 held an arm's state inline).
#[derive(Serialize, Deserialize)]
pub(crate) struct EvaluatorStateAs<Body> {
    next_eval: usize,
    scratch: Option<Body>,
    true_x: Vec<Point>,
    true_dx: Vec<Point>,
}

pub(crate) type EvaluatorState = EvaluatorStateAs<Vec<u8>>;

impl<B: Into<Vec<u8>>> EvaluatorStateAs<B> {
    /// The same state with the scratch body's bytes as `Body::save` writes them today.
    pub(crate) fn upgraded(self) -> EvaluatorState {
        let EvaluatorStateAs { next_eval, scratch, true_x, true_dx } = self;
        EvaluatorStateAs { next_eval, scratch: scratch.map(Into::into), true_x, true_dx }
    }
}

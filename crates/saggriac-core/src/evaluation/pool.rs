//! Evaluations on other threads while learning goes on. The memory is append-only and a clone of
//! it is a snapshot (its storage is shared in chunks), so the evaluation of step t reads exactly
//! the first n_t samples, on its own copy of the test body: the same inputs as in the learner's
//! thread, hence the same results. Workers take jobs in order from one queue; the learner takes
//! from it too when no worker is free, and when it is done, until all are finished.

use std::collections::VecDeque;
use std::panic::{catch_unwind, resume_unwind, AssertUnwindSafe};
use std::sync::mpsc::{channel, Receiver, Sender};
use std::sync::{Arc, Condvar, Mutex};
use std::thread::JoinHandle;
use std::time::Instant;

use crate::body::Body;
use crate::evaluation::micro::{evaluate_micro, MicroParams, MicroScratch};
use crate::evaluation::test_set::{EvalResult, TestSet};
use crate::model::memory::SensorimotorMemory;
use crate::model::neighbours::Neighbour;

/// One evaluation to run: everything it reads, owned.
pub(crate) struct Job {
    /// Its row in the metrics table.
    pub index: usize,
    pub memory: SensorimotorMemory,
    pub body: Box<dyn Body>,
    pub tests: Arc<TestSet>,
    pub params: MicroParams,
    /// The k nearest stored configurations of each test configuration.
    pub predict_neighbours: Vec<Vec<Neighbour>>,
    pub n_joints: usize,
    pub task_dim: usize,
}

/// A finished evaluation.
pub(crate) struct Finished {
    pub index: usize,
    pub result: EvalResult,
    /// Seconds it took, and its neighbour-search and fit parts.
    pub seconds: f64,
    pub time_knn: f64,
    pub time_fit: f64,
}

fn run(mut job: Job) -> Finished {
    let t0 = Instant::now();
    let mut scratch = MicroScratch::new(&job.params, job.n_joints, job.task_dim);
    let result = evaluate_micro(&job.params, &job.tests, &job.memory, job.body.as_mut(), &mut scratch, &job.predict_neighbours);
    Finished { index: job.index, result, seconds: t0.elapsed().as_secs_f64(), time_knn: scratch.time_knn, time_fit: scratch.time_fit }
}

type Outcome = std::thread::Result<Finished>;

#[derive(Default)]
struct Queue {
    jobs: VecDeque<Job>,
    closed: bool,
    /// Workers waiting for a job.
    idle: usize,
}

struct Shared {
    queue: Mutex<Queue>,
    ready: Condvar,
}

impl Shared {
    /// The next job, waiting for one unless `wait` is false; None once closed (or empty).
    fn next(&self, wait: bool) -> Option<Job> {
        let mut q = self.queue.lock().unwrap_or_else(|e| e.into_inner());
        loop {
            if let Some(job) = q.jobs.pop_front() {
                return Some(job);
            }
            if q.closed || !wait {
                return None;
            }
            q.idle += 1;
            q = self.ready.wait(q).unwrap_or_else(|e| e.into_inner());
            q.idle -= 1;
        }
    }
}

fn attempt(job: Job) -> Outcome {
    catch_unwind(AssertUnwindSafe(|| run(job)))
}

pub(crate) struct Pool {
    shared: Arc<Shared>,
    /// In a mutex only so that a learner can be shared between threads (`Receiver` is not Sync).
    results: Mutex<Receiver<Outcome>>,
    sender: Sender<Outcome>,
    workers: Vec<JoinHandle<()>>,
    /// Jobs submitted whose result has not been collected.
    pending: usize,
}

impl Pool {
    /// A pool of `workers` threads besides the caller's.
    pub fn new(workers: usize) -> Self {
        let shared = Arc::new(Shared { queue: Mutex::new(Queue::default()), ready: Condvar::new() });
        let (sender, results) = channel();
        let workers = (0..workers)
            .map(|i| {
                let (shared, sender) = (Arc::clone(&shared), sender.clone());
                std::thread::Builder::new()
                    .name(format!("saggriac-eval-{i}"))
                    .spawn(move || {
                        while let Some(job) = shared.next(true) {
                            if sender.send(attempt(job)).is_err() {
                                return;
                            }
                        }
                    })
                    .expect("the operating system starts a thread")
            })
            .collect();
        Pool { shared, results: Mutex::new(results), sender, workers, pending: 0 }
    }

    /// Queue `job`; if no worker is free for it, run queued jobs on this thread first. So the
    /// learner never runs far ahead of its evaluations: rows (and the checkpoints taken at
    /// them) come at most about one evaluation late, and no more snapshots wait than threads.
    pub fn submit(&mut self, job: Job) {
        self.shared.queue.lock().unwrap_or_else(|e| e.into_inner()).jobs.push_back(job);
        self.shared.ready.notify_one();
        self.pending += 1;
        loop {
            let job = {
                let mut q = self.shared.queue.lock().unwrap_or_else(|e| e.into_inner());
                if q.jobs.len() > q.idle {
                    q.jobs.pop_front()
                } else {
                    None
                }
            };
            let Some(job) = job else { break };
            self.sender.send(attempt(job)).expect("the pool holds its own receiver");
        }
    }

    /// Results that are in; with `wait`, all of them, running queued jobs on this thread too.
    /// A panic in an evaluation is raised again here.
    pub fn collect(&mut self, wait: bool) -> Vec<Finished> {
        let mut out = Vec::new();
        let results = self.results.get_mut().unwrap_or_else(|e| e.into_inner());
        let take = |o: Outcome, out: &mut Vec<Finished>| match o {
            Ok(f) => out.push(f),
            Err(panic) => resume_unwind(panic),
        };
        while let Ok(o) = results.try_recv() {
            self.pending -= 1;
            take(o, &mut out);
        }
        if wait {
            while let Some(job) = self.shared.next(false) {
                self.sender.send(attempt(job)).expect("the pool holds its own receiver");
            }
            while self.pending > 0 {
                let o = results.recv().expect("the pool holds a sender, so results can arrive");
                self.pending -= 1;
                take(o, &mut out);
            }
        }
        out
    }
}

impl Drop for Pool {
    fn drop(&mut self) {
        // Evaluations not begun are not wanted any more (the learner is gone).
        let mut q = self.shared.queue.lock().unwrap_or_else(|e| e.into_inner());
        q.closed = true;
        q.jobs.clear();
        drop(q);
        self.shared.ready.notify_all();
        for w in self.workers.drain(..) {
            let _ = w.join();
        }
    }
}

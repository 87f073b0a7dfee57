//! Checkpoints of a single run: everything the rest of the run depends on, so that a restored
//! learner continues exactly as the original would have, bit for bit. Taken between goal
//! attempts (where `run()` returns when stopped). Neighbour indexes are not stored: they are
//! rebuilt by re-adding the samples, and since every search is exact, they answer the same.

use serde::{Deserialize, Serialize};

use crate::body::arm::ArmState;
use crate::config::RunConfig;
use crate::error::{Error, Result};
use crate::high_level::goal_selection::SelectorState;
use crate::recorder::{AttemptRow, Counters, GoalRow, MetricRow, Recorder, Timers};
use crate::rng::CoreRng;
use crate::run_loop::Learner;
use crate::task_space::Point;

/// Bumped whenever the layout below changes; older checkpoints are then refused.
/// Format 3: the encoding is followed by a CRC-32 (Castagnoli) of it. Format 4: the test motions'
/// true displacements and the metric rows' dx_error.
const FORMAT: u32 = 4;

/// CRC-32C: detects every error of up to 32 consecutive bits, so any one damaged byte.
const CHECKSUM: crc::Crc<u32> = crc::Crc::<u32>::new(&crc::CRC_32_ISCSI);

/// What to do about a checkpoint that cannot be used: the run can only start over.
const START_OVER: &str = "Start the run over: run it again without --resume (from Python, saggriac.run instead of saggriac.resume).";

#[derive(Serialize, Deserialize)]
struct State {
    format: u32,
    version: String,
    /// The full configuration, printed: a checkpoint resumes only the run it came from.
    config: String,
    seeds: (u64, u64),
    steps: u64,
    next_eval: usize,
    goals_done: u64,
    reported: usize,
    babble_steps: u64,
    rng: CoreRng,
    memory: [Vec<f64>; 4],
    rejected: u64,
    episodic: Option<(Vec<f64>, Vec<f64>)>,
    selector: SelectorState,
    body: ArmState,
    scratch: Option<ArmState>,
    true_x: Vec<Point>,
    true_dx: Vec<Point>,
    counters: Counters,
    timers: Timers,
    metrics: Vec<MetricRow>,
    goals: Vec<GoalRow>,
    attempts: Vec<AttemptRow>,
}

fn refuse(why: impl Into<String>) -> Error {
    Error::InvalidInput(why.into())
}

impl Learner {
    /// Encode the learner's state. Only built-in bodies and goal selectors can be saved.
    pub fn checkpoint(&self) -> Result<Vec<u8>> {
        let p = &self.parts;
        let selector = p.selector.save().ok_or_else(|| refuse("This run cannot be checkpointed: its goal selector is a user's object, whose state saggriac cannot save."))?;
        let body = p.body.save().ok_or_else(|| refuse("This run cannot be checkpointed: its environment is a user's object, whose state saggriac cannot save."))?;
        let (samples, episodes, r) = (p.model.samples(), p.model.episodes(), &p.recorder);
        let [t, d, x, dx0] = samples.arrays();
        let state = State {
            format: FORMAT,
            version: env!("CARGO_PKG_VERSION").to_string(),
            config: format!("{:?}", self.cfg),
            seeds: self.seeds,
            steps: r.steps,
            next_eval: p.evaluator.next_eval,
            goals_done: r.goals_done,
            reported: r.reported,
            babble_steps: self.low_level.saved_progress(),
            rng: p.rng.clone(),
            memory: [t.to_vec(), d.to_vec(), x.to_vec(), dx0.to_vec()],
            rejected: samples.rejected(),
            episodic: episodes.map(|m| (m.arrays().0.to_vec(), m.arrays().1.to_vec())),
            selector,
            body,
            scratch: p.evaluator.scratch.as_ref().and_then(|s| s.save()),
            true_x: p.evaluator.tests.true_x.clone(),
            true_dx: p.evaluator.tests.true_dx.clone(),
            counters: r.counters.clone(),
            timers: r.timers.clone(),
            metrics: r.metrics.clone(),
            goals: r.goals.clone(),
            attempts: r.attempts.clone(),
        };
        postcard::to_stdvec_crc32(&state, CHECKSUM.digest()).map_err(|e| refuse(format!("Could not encode the checkpoint: {e}.")))
    }

    /// Rebuild a learner from a checkpoint of a run with configuration `cfg`.
    pub fn restore(cfg: RunConfig, bytes: &[u8]) -> Result<Learner> {
        let s: State = match postcard::take_from_bytes_crc32::<State>(bytes, CHECKSUM.digest()) {
            Ok((s, [])) => s,
            Ok(_) => return Err(refuse(format!("The checkpoint is damaged: bytes follow its end. {START_OVER}"))),
            Err(postcard::Error::DeserializeBadCrc) => return Err(refuse(format!("The checkpoint is damaged: its checksum does not match its content. {START_OVER}"))),
            Err(e) => return Err(refuse(format!("The checkpoint is damaged or not a saggriac checkpoint ({e}). {START_OVER}"))),
        };
        if s.format != FORMAT {
            return Err(refuse(format!("The checkpoint has format {} but this saggriac ({}) reads format {FORMAT}; it was written by saggriac {}.", s.format, env!("CARGO_PKG_VERSION"), s.version)));
        }
        if s.config != format!("{cfg:?}") {
            return Err(refuse("The checkpoint belongs to a run with another configuration; resume it with the configuration it was written with."));
        }
        let mut l = Learner::new(cfg, s.seeds.0, s.seeds.1)?;
        let p = &mut l.parts;
        p.model.restore(&s.memory, s.rejected, s.episodic.as_ref());
        if !p.selector.load(&s.selector) || !p.body.load(&s.body) {
            return Err(refuse("The checkpoint does not match this run's goal selector or body."));
        }
        if let (Some(sc), Some(st)) = (p.evaluator.scratch.as_mut(), &s.scratch) {
            sc.load(st);
        }
        let tests = std::sync::Arc::make_mut(&mut p.evaluator.tests);
        tests.true_x = s.true_x;
        tests.true_dx = s.true_dx;
        p.evaluator.next_eval = s.next_eval;
        p.rng = s.rng;
        p.recorder = Recorder {
            metrics: s.metrics,
            goals: s.goals,
            attempts: s.attempts,
            counters: s.counters,
            timers: s.timers,
            steps: s.steps,
            goals_done: s.goals_done,
            reported: s.reported,
            pending: Vec::new(),
        };
        l.low_level.restore_progress(s.babble_steps);
        Ok(l)
    }
}

//! Checkpoints of a single run: everything the rest of the run depends on, so that a restored
//! learner continues exactly as the original would have, bit for bit. Taken between goal
//! attempts (where `run()` returns when stopped). Neighbour indexes are not stored: they are
//! rebuilt by re-adding the samples, and since every search is exact, they answer the same.

use serde::{Deserialize, Serialize};

use crate::config::RunConfig;
use crate::error::{Error, Result};
use crate::parts::PartsState;
use crate::run_loop::Learner;

/// Bumped whenever the layout below changes; older checkpoints are then refused.
/// Format 3: the encoding is followed by a CRC-32 (Castagnoli) of it. Format 4: the test motions'
/// true displacements and the metric rows' dx_error. Format 5: each part's state in one piece.
const FORMAT: u32 = 5;

/// CRC-32C: detects every error of up to 32 consecutive bits, so any one damaged byte.
const CHECKSUM: crc::Crc<u32> = crc::Crc::<u32>::new(&crc::CRC_32_ISCSI);

/// What to do about a checkpoint that cannot be used: the run can only start over.
const START_OVER: &str = "Start the run over: run it again without --resume (from Python, saggriac.run instead of saggriac.resume).";

/// A checkpoint: the run's identity, then each part's own state (`Parts::save`) and the
/// low-level controller's progress.
#[derive(Serialize, Deserialize)]
struct State {
    format: u32,
    version: String,
    /// The full configuration, printed: a checkpoint resumes only the run it came from.
    config: String,
    seeds: (u64, u64),
    parts: PartsState,
    low_level: u64,
}

/// The first fields of every format's checkpoint.
#[derive(Deserialize)]
struct Head {
    format: u32,
    version: String,
}

/// The head of a checkpoint of another format, if `bytes` start like one: a format number other
/// than this one's and the version of saggriac that wrote it (so damaged bytes are not taken for
/// another format).
fn other_format(bytes: &[u8]) -> Option<Head> {
    let (h, _) = postcard::take_from_bytes::<Head>(bytes).ok()?;
    let version = h.version.split('.').count() == 3 && h.version.split('.').all(|p| !p.is_empty() && p.chars().all(|c| c.is_ascii_digit()));
    (h.format != FORMAT && (1..FORMAT + 100).contains(&h.format) && version).then_some(h)
}

fn wrong_format(h: Head) -> Error {
    refuse(format!("The checkpoint has format {} but this saggriac ({}) reads format {FORMAT}; it was written by saggriac {}.", h.format, env!("CARGO_PKG_VERSION"), h.version))
}

fn refuse(why: impl Into<String>) -> Error {
    Error::InvalidInput(why.into())
}

impl Learner {
    /// Encode the learner's state. Only built-in bodies and goal selectors can be saved.
    pub fn checkpoint(&self) -> Result<Vec<u8>> {
        let state = State {
            format: FORMAT,
            version: env!("CARGO_PKG_VERSION").to_string(),
            config: format!("{:?}", self.cfg),
            seeds: self.seeds,
            parts: self.parts.save()?,
            low_level: self.low_level.saved_progress(),
        };
        postcard::to_stdvec_crc32(&state, CHECKSUM.digest()).map_err(|e| refuse(format!("Could not encode the checkpoint: {e}.")))
    }

    /// Rebuild a learner from a checkpoint of a run with configuration `cfg`.
    pub fn restore(cfg: RunConfig, bytes: &[u8]) -> Result<Learner> {
        let decoded = postcard::take_from_bytes_crc32::<State>(bytes, CHECKSUM.digest());
        if !matches!(decoded, Ok((_, []))) {
            // Another format's parts do not decode as this one's: its head says which it is.
            if let Some(h) = other_format(bytes) {
                return Err(wrong_format(h));
            }
        }
        let s: State = match decoded {
            Ok((s, [])) => s,
            Ok(_) => return Err(refuse(format!("The checkpoint is damaged: bytes follow its end. {START_OVER}"))),
            Err(postcard::Error::DeserializeBadCrc) => return Err(refuse(format!("The checkpoint is damaged: its checksum does not match its content. {START_OVER}"))),
            Err(e) => return Err(refuse(format!("The checkpoint is damaged or not a saggriac checkpoint ({e}). {START_OVER}"))),
        };
        if s.format != FORMAT {
            return Err(wrong_format(Head { format: s.format, version: s.version }));
        }
        if s.config != format!("{cfg:?}") {
            return Err(refuse("The checkpoint belongs to a run with another configuration; resume it with the configuration it was written with."));
        }
        let mut l = Learner::new(cfg, s.seeds.0, s.seeds.1)?;
        if !l.parts.restore(s.parts) {
            return Err(refuse("The checkpoint does not match this run's goal selector or body."));
        }
        l.low_level.restore_progress(s.low_level);
        Ok(l)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn small() -> RunConfig {
        let mut cfg = RunConfig { n_steps: 300, ..RunConfig::default() };
        cfg.eval.n_test_goals = 5;
        cfg.eval.n_test_configs = 5;
        cfg.eval.schedule = vec![0, 300];
        cfg
    }

    #[test]
    fn another_format_is_named_and_damage_is_not_taken_for_one() {
        // A checkpoint of format 4 starts with its format and version like every format.
        #[derive(Serialize)]
        struct Old {
            format: u32,
            version: String,
            rest: Vec<u8>,
        }
        let old = postcard::to_stdvec(&Old { format: 4, version: "0.3.0".into(), rest: vec![7; 40] }).unwrap();
        let e = Learner::restore(small(), &old).err().unwrap().to_string();
        assert!(e.contains("format 4") && e.contains("reads format 5") && e.contains("saggriac 0.3.0"), "{e}");
        let e = Learner::restore(small(), b"\x00\x01garbage").err().unwrap().to_string();
        assert!(e.contains("damaged"), "{e}");
    }

    #[test]
    fn a_restored_learner_continues_exactly() {
        let mut cfg = small();
        cfg.eval.schedule = vec![0, 100, 200, 300];
        let (mut a, mut b) = (Learner::new(cfg.clone(), 3, 4).unwrap(), Learner::new(cfg.clone(), 3, 4).unwrap());
        a.run(&mut |_| true);
        // Stopped after the evaluation at step 100, between two goal attempts.
        assert!(!b.run(&mut |row| row.step < 100));
        assert!(b.steps() >= 100 && b.steps() < 300, "{}", b.steps());
        let mut c = Learner::restore(cfg, &b.checkpoint().unwrap()).unwrap();
        assert_eq!(c.steps(), b.steps());
        assert!(c.run(&mut |_| true));
        // Debug text compares NaN competences (a goal the budget cut) as equal.
        assert_eq!(format!("{:?}", a.metrics()), format!("{:?}", c.metrics()));
        assert_eq!(format!("{:?}", a.goals()), format!("{:?}", c.goals()));
        assert_eq!(format!("{:?}", a.attempts()), format!("{:?}", c.attempts()));
        assert_eq!(a.counters(), c.counters());
    }
}

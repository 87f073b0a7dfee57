//! Checkpoints of a single run: everything the rest of the run depends on, so that a restored
//! learner continues exactly as the original would have, bit for bit. Taken between goal
//! attempts (where `run()` returns when stopped). Neighbour indexes are not stored: they are
//! rebuilt by re-adding the samples, and since every search is exact, they answer the same.

use serde::{Deserialize, Serialize};

use crate::config::teachers::{SpdlConfig, Teacher};
use crate::config::{Mode3Config, RunConfig};
use crate::error::{Error, Result};
use crate::body::arm::InlineState;
use crate::parts::PartsStateAs;
use crate::run_loop::Learner;

/// Bumped whenever the layout below changes. Format 3: the encoding is followed by a CRC-32
/// (Castagnoli) of it. Format 4: the test motions' true displacements and the metric rows'
/// dx_error. Format 5: each part's state in one piece. Format 6: the body's state in the body's
/// own encoding (bytes), as the goal selector's. Format 7: the layout of 6, with configurations
/// that print the parameters SPDL and Goal GAN gained in #46. Format 8: the layout of 7, with
/// configurations that print SAGG-RIAC's mode 3 reading (#48). Formats 5 to 7 are still read;
/// older ones are refused.
const FORMAT: u32 = 8;

/// CRC-32C: detects every error of up to 32 consecutive bits, so any one damaged byte.
const CHECKSUM: crc::Crc<u32> = crc::Crc::<u32>::new(&crc::CRC_32_ISCSI);

/// What to do about a checkpoint that cannot be used: the run can only start over.
const START_OVER: &str = "Start the run over: run it again without --resume (from Python, saggriac.run instead of saggriac.resume).";

/// A checkpoint: the run's identity, then each part's own state (`Parts::save`) and the
/// low-level controller's progress.
/// Generic in how the body's state is held, so that format 5 is read with the same struct.
/// Generic in the counters added since format 5 too (`()` there: nothing encoded).
#[derive(Serialize, Deserialize)]
struct StateAs<Body, Since5> {
    format: u32,
    version: String,
    /// The full configuration, printed: a checkpoint resumes only the run it came from.
    config: String,
    seeds: (u64, u64),
    parts: PartsStateAs<Body>,
    low_level: u64,
    since_5: Since5,
}

/// The exploration trigger's counters (recorder.rs, `Counters`): only executed, only desired,
/// the gap's sum.
type TriggerCounts = (u64, u64, f64);

type State = StateAs<Vec<u8>, TriggerCounts>;

/// Format 5 (saggriac 0.5): the arm's state inline, no trigger counters.
type StateV5 = StateAs<InlineState, ()>;

fn decode<T: serde::de::DeserializeOwned>(bytes: &[u8]) -> std::result::Result<T, Error> {
    match postcard::take_from_bytes_crc32::<T>(bytes, CHECKSUM.digest()) {
        Ok((s, [])) => Ok(s),
        Ok(_) => Err(refuse(format!("The checkpoint is damaged: bytes follow its end. {START_OVER}"))),
        Err(postcard::Error::DeserializeBadCrc) => Err(refuse(format!("The checkpoint is damaged: its checksum does not match its content. {START_OVER}"))),
        Err(e) => Err(refuse(format!("The checkpoint is damaged or not a saggriac checkpoint ({e}). {START_OVER}"))),
    }
}

/// The first fields of every format's checkpoint.
#[derive(Deserialize)]
struct Head {
    format: u32,
    version: String,
}

/// The head of a checkpoint of a format this saggriac does not read, if `bytes` start like one:
/// a format number other than those read and the version of saggriac that wrote it (so damaged
/// bytes are not taken for another format).
fn other_format(bytes: &[u8]) -> Option<Head> {
    let (h, _) = postcard::take_from_bytes::<Head>(bytes).ok()?;
    let version = h.version.split('.').count() == 3 && h.version.split('.').all(|p| !p.is_empty() && p.chars().all(|c| c.is_ascii_digit()));
    (![5, 6, 7, FORMAT].contains(&h.format) && (1..FORMAT + 100).contains(&h.format) && version).then_some(h)
}

/// The configuration as a checkpoint of `format` printed it. Format 5 (saggriac 0.5) printed the
/// run's teacher as its own enum, `Own` for the condition's own high level, and no trigger.
/// Formats 5 and 6 printed SPDL and Goal GAN without the parameters of #46; formats 5 to 7 printed
/// SAGG-RIAC without mode 3's reading, which had only the paper's then.
fn config_text(cfg: &RunConfig, format: u32) -> String {
    let mut text = format!("{cfg:?}");
    if format < 8 {
        text = text.replace(&format!(", mode3: {:?}", Mode3Config::default()), "");
    }
    if format == 5 {
        // 0.5 had no choice of exploration trigger: its runs used today's default.
        text = text.replacen(", trigger: Executed", "", 1);
    }
    let Some(t) = &cfg.teacher else {
        return if format == 5 { text.replacen("teacher: None,", "teacher: Own,", 1) } else { text };
    };
    let now = format!("teacher: Some({t:?}),");
    match format {
        5 => text.replacen(&now, &format!("teacher: {},", teacher_before_46(t)), 1),
        6 => text.replacen(&now, &format!("teacher: Some({}),", teacher_before_46(t)), 1),
        _ => text,
    }
}

/// A teacher as saggriac printed it before #46: SPDL without its form, covariance and alpha
/// parameters, Goal GAN without its first goals' box. Runs of then ran them at the values these
/// take by default; with other values the text differs, and the checkpoint is another run's.
fn teacher_before_46(t: &Teacher) -> String {
    let text = format!("{t:?}");
    let d = SpdlConfig::default();
    let added = match t {
        Teacher::Spdl(c) if (c.form, c.covariance, c.alpha_offset, c.alpha_zeta) == (d.form, d.covariance, d.alpha_offset, d.alpha_zeta) => {
            format!(", form: {:?}, covariance: {:?}, alpha_offset: {:?}, alpha_zeta: {:?}", c.form, c.covariance, c.alpha_offset, c.alpha_zeta)
        }
        Teacher::GoalGan(c) if (c.initial, c.initial_width) == (0.5, 1.0) => format!(", initial: {:?}, initial_width: {:?}", c.initial, c.initial_width),
        _ => return text,
    };
    match text.strip_suffix(&format!("{added} }})")) {
        Some(head) => format!("{head} }})"),
        None => text,
    }
}

fn wrong_format(h: Head) -> Error {
    refuse(format!("The checkpoint has format {} but this saggriac ({}) reads formats 5 to {FORMAT}; it was written by saggriac {}.", h.format, env!("CARGO_PKG_VERSION"), h.version))
}

/// Which saggriac wrote a checkpoint, and which reads it: a checkpoint this one cannot use may
/// belong to another version.
fn versions(written: &str) -> String {
    format!("it was written by saggriac {written}, this is saggriac {}", env!("CARGO_PKG_VERSION"))
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
            since_5: {
                let c = &self.parts.recorder().counters;
                (c.trigger_only_executed, c.trigger_only_desired, c.trigger_gap_sum)
            },
        };
        postcard::to_stdvec_crc32(&state, CHECKSUM.digest()).map_err(|e| refuse(format!("Could not encode the checkpoint: {e}.")))
    }

    /// Rebuild a learner from a checkpoint of a run with configuration `cfg`.
    pub fn restore(cfg: RunConfig, bytes: &[u8]) -> Result<Learner> {
        // Another format's parts do not decode as this one's: its head says which it is.
        if let Some(h) = other_format(bytes) {
            return Err(wrong_format(h));
        }
        let format = postcard::take_from_bytes::<u32>(bytes).map(|(f, _)| f).unwrap_or(FORMAT);
        let s: State = if format == 5 {
            let StateAs { format, version, config, seeds, parts, low_level, since_5: () } = decode::<StateV5>(bytes)?;
            StateAs { format, version, config, seeds, parts: parts.upgraded(), low_level, since_5: (0, 0, 0.0) }
        } else {
            decode::<State>(bytes)?
        };
        if ![5, 6, 7, FORMAT].contains(&s.format) {
            return Err(wrong_format(Head { format: s.format, version: s.version }));
        }
        if s.config != config_text(&cfg, s.format) {
            return Err(refuse(format!("The checkpoint belongs to a run with another configuration ({}); resume it with the configuration it was written with.", versions(&s.version))));
        }
        let mut l = Learner::new(cfg, s.seeds.0, s.seeds.1)?;
        if !l.parts.restore(s.parts) {
            return Err(refuse(format!("The checkpoint does not match this run's goal selector or body ({}).", versions(&s.version))));
        }
        l.low_level.restore_progress(s.low_level);
        let c = l.parts.counters_mut();
        (c.trigger_only_executed, c.trigger_only_desired, c.trigger_gap_sum) = s.since_5;
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
        assert!(e.contains("format 4") && e.contains("reads formats 5 to 8") && e.contains("saggriac 0.3.0"), "{e}");
        let e = Learner::restore(small(), b"\x00\x01garbage").err().unwrap().to_string();
        assert!(e.contains("damaged"), "{e}");
    }

    #[test]
    fn a_checkpoint_of_another_run_names_the_version_that_wrote_it() {
        let l = Learner::new(small(), 1, 2).unwrap();
        let e = Learner::restore(RunConfig { n_steps: 400, ..small() }, &l.checkpoint().unwrap()).err().unwrap().to_string();
        let v = env!("CARGO_PKG_VERSION");
        assert!(e.contains(&format!("another configuration (it was written by saggriac {v}, this is saggriac {v})")), "{e}");
    }

    /// Checkpoints written by saggriac 0.5.0 (format 5, the arm's state inline; 4ffeabf, by
    /// tests/data/saved_checkpoints.py 5: stopped after step 100) resume, and the run evaluates
    /// what 0.5.0's resumed run evaluated, to the bit.
    #[test]
    fn checkpoints_of_saggriac_0_5_resume_exactly() {
        let files: [(&[u8], &str); 2] = [
            (include_bytes!("../tests/data/checkpoint_v5_micro.bin"), include_str!("../tests/data/checkpoint_v5_micro.next")),
            (include_bytes!("../tests/data/checkpoint_v5_episodic.bin"), include_str!("../tests/data/checkpoint_v5_episodic.next")),
        ];
        for (i, (bytes, next)) in files.into_iter().enumerate() {
            let mut cfg = small();
            cfg.eval.schedule = vec![0, 100, 200, 300];
            if i == 1 {
                cfg.paradigm = crate::config::Paradigm::Episodic;
                cfg.arm.joint_limit = std::f64::consts::PI;
                (cfg.goal_low, cfg.goal_high) = (vec![-50.0, -50.0], vec![50.0, 50.0]);
            }
            let mut l = Learner::restore(cfg.clone(), bytes).unwrap();
            assert!(l.steps() > 100 && l.steps() < 300);
            assert!(l.run(&mut |_| true));
            let bits: Vec<String> = l.metrics().iter().map(|m| format!("{} {}", m.reach_error.to_bits(), m.pred_error.to_bits())).collect();
            assert_eq!(bits, next.lines().collect::<Vec<_>>());
            // Checkpointed again, it is of this format and resumes as itself.
            let again = Learner::restore(cfg, &l.checkpoint().unwrap()).unwrap();
            assert_eq!(again.steps(), l.steps());
        }
    }

    /// Checkpoints of format 6 (saggriac 0.6.0 before #46, 164832d, by
    /// tests/data/saved_checkpoints.py 6) of runs whose goals ADR, Goal GAN and SPDL choose
    /// resume: ADR's and Goal GAN's runs evaluate what they did then, to the bit; SPDL's (whose
    /// update changed) resumes and runs to its end.
    #[test]
    fn checkpoints_of_runs_with_teachers_before_46_resume() {
        use crate::config::teachers::{AdrConfig, GoalGanConfig};
        let files: [(Teacher, &[u8], &str); 3] = [
            (Teacher::Adr(AdrConfig { step: 0.1, ..AdrConfig::default() }), include_bytes!("../tests/data/checkpoint_v6_adr.bin"), include_str!("../tests/data/checkpoint_v6_adr.next")),
            (Teacher::GoalGan(GoalGanConfig { update_size: 10, gan_iterations: 5, hidden: 8, ..GoalGanConfig::default() }), include_bytes!("../tests/data/checkpoint_v6_goal_gan.bin"), include_str!("../tests/data/checkpoint_v6_goal_gan.next")),
            (Teacher::Spdl(SpdlConfig { update_every: 20, warmup: 20, ..SpdlConfig::default() }), include_bytes!("../tests/data/checkpoint_v6_spdl.bin"), include_str!("../tests/data/checkpoint_v6_spdl.next")),
        ];
        for (teacher, bytes, next) in files {
            let mut cfg = small();
            cfg.eval.schedule = vec![0, 100, 200, 300];
            cfg.teacher = Some(teacher.scaled_to_competences(cfg.competence.min_c, 0.0));
            let mut l = Learner::restore(cfg.clone(), bytes).unwrap();
            assert!(l.steps() >= 100 && l.steps() < 300);
            assert!(l.run(&mut |_| true));
            let bits: Vec<String> = l.metrics().iter().map(|m| format!("{} {}", m.reach_error.to_bits(), m.pred_error.to_bits())).collect();
            if teacher.kind() != "spdl" {
                assert_eq!(bits, next.lines().collect::<Vec<_>>(), "{}", teacher.kind());
            }
            // With a parameter of #46 away from its default it is another run's checkpoint.
            let mut other = cfg.clone();
            other.teacher = match cfg.teacher {
                Some(Teacher::Spdl(c)) => Some(Teacher::Spdl(SpdlConfig { alpha_zeta: 0.5, ..c })),
                Some(Teacher::GoalGan(c)) => Some(Teacher::GoalGan(GoalGanConfig { initial_width: 0.5, ..c })),
                t => t,
            };
            if other.teacher != cfg.teacher {
                let e = Learner::restore(other, bytes).err().unwrap().to_string();
                assert!(e.contains("another configuration"), "{e}");
            }
        }
    }

    /// A checkpoint of format 7 (before mode 3 had a reading, by tests/data/saved_checkpoints.py
    /// 7) resumes with the paper's reading and evaluates what it did then, to the bit; with
    /// another reading it is another run's checkpoint.
    #[test]
    fn a_checkpoint_from_before_mode3_readings_resumes() {
        use crate::config::{Mode3Config, Mode3Reading};
        let (bytes, next) = (include_bytes!("../tests/data/checkpoint_v7_sagg_riac.bin"), include_str!("../tests/data/checkpoint_v7_sagg_riac.next"));
        let mut cfg = small();
        cfg.eval.schedule = vec![0, 100, 200, 300];
        (cfg.tree.g_max, cfg.tree.zeta, cfg.tree.min_child) = (12, 8, 2);
        let mut l = Learner::restore(cfg.clone(), bytes).unwrap();
        assert!(l.steps() >= 100 && l.steps() < 300);
        assert!(l.run(&mut |_| true));
        let bits: Vec<String> = l.metrics().iter().map(|m| format!("{} {}", m.reach_error.to_bits(), m.pred_error.to_bits())).collect();
        assert_eq!(bits, next.lines().collect::<Vec<_>>());
        cfg.mode3 = Mode3Config { reading: Mode3Reading::InterestWorst, ..Mode3Config::default() };
        let e = Learner::restore(cfg, bytes).err().unwrap().to_string();
        assert!(e.contains("another configuration"), "{e}");
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

//! Goal selection on its own (ask/tell): any learner asks for a goal, tries it, and tells the
//! competence it obtained. This is how later work uses SAGG-RIAC as a curriculum "teacher". The
//! wrapper checks every input, and keeps the history of what was asked and told.

use serde::{Deserialize, Serialize};

use crate::error::{invalid, Error, Num, Result};
use crate::high_level::goal_selection::{GoalChoice, GoalSelector, ModeProbabilities};
use crate::high_level::region_tree::RegionTreeConfig;
use crate::config::teachers::{RandomConfig, SaggRiacConfig, Teacher};
use crate::high_level::teachers::TeacherSpec;

/// Bumped whenever the saved layout changes. Format 7: SAGG-RIAC's mode 3 reading and sigma
/// after its modes. Format 6 (the parameters given per dimension after the seed, SPDL's form,
/// covariance and alpha parameters, Goal GAN's first goals' box; read with mode 3 as the paper
/// reads it, the only reading then), formats 5
/// (saggriac after 0.6.0, before #46's SPDL and Goal GAN parameters: PLR's parameters end with
/// `ties`), 4 (saggriac 0.6, the teacher's parameters as the one `Teacher` enum beside the box
/// and the seed; a PLR teacher read with the `Average` ties it ran), 3 (saggriac 0.5, each
/// teacher's state in its own encoding), 2 (saggriac 0.3-0.4, one enum of every teacher's
/// state) and 1 (saggriac <= 0.2, before SAGG-RIAC's tree had an eq.-2 divisor, read as the
/// `Window` reading it ran) are still read.
const FORMAT: u32 = 7;
/// Told competences are bounded so that every teacher's sums, squares and mixtures of them stay
/// finite (a mixture teacher squares differences of competences).
pub const MAX_COMPETENCE: f64 = 1e100;
/// The most goals one `sample_batch` returns, and the most coordinates in all.
pub const MAX_BATCH: usize = 10_000_000;
pub const MAX_BATCH_VALUES: usize = 100_000_000;

/// CRC-32C of the encoding, as checkpoints have: a damaged save is refused, never half-read.
const CHECKSUM: crc::Crc<u32> = crc::Crc::<u32>::new(&crc::CRC_32_ISCSI);

/// What `AskTell::save` writes: the teacher's parameters, its state (in the teacher's own
/// encoding) and the history. Generic in the parameters' and the state's layout, so that older
/// formats are read with the same struct.
#[derive(Serialize, Deserialize)]
struct SavedAs<Spec, State> {
    format: u32,
    version: String,
    spec: Spec,
    state: State,
    asked: Vec<f64>,
    asked_mode: Vec<u8>,
    asked_region: Vec<i64>,
    told: Vec<f64>,
    told_competence: Vec<f64>,
    told_region: Vec<i64>,
}

type Saved = SavedAs<TeacherSpec, Vec<u8>>;

enum DecodeError {
    Trailing,
    Postcard(postcard::Error),
}

fn decode<T: serde::de::DeserializeOwned>(bytes: &[u8]) -> std::result::Result<T, DecodeError> {
    match postcard::take_from_bytes_crc32::<T>(bytes, CHECKSUM.digest()) {
        Ok((s, [])) => Ok(s),
        Ok(_) => Err(DecodeError::Trailing),
        Err(e) => Err(DecodeError::Postcard(e)),
    }
}

/// The layouts of formats 1 (saggriac <= 0.2: SAGG-RIAC's tree parameters without the divisor),
/// 2 (saggriac 0.3-0.4, whose teachers' states were variants of one enum), 3 (saggriac 0.5,
/// the parameters as one enum of teachers with their boxes and seeds), 4 (saggriac 0.6, PLR's
/// parameters without `ties`), 5 (no parameters per dimension, SPDL's and Goal GAN's
/// parameters as they were before #46) and 6 (SAGG-RIAC without mode 3's reading).
mod legacy;

pub struct AskTell {
    spec: TeacherSpec,
    selector: Box<dyn GoalSelector>,
    /// Sampled goals, row by row, with their mode and region (-1: none).
    pub asked: Vec<f64>,
    pub asked_mode: Vec<u8>,
    pub asked_region: Vec<i64>,
    /// Told goals, row by row, with their competence and the region that recorded it.
    pub told: Vec<f64>,
    pub told_competence: Vec<f64>,
    pub told_region: Vec<i64>,
}

impl AskTell {
    /// The teacher `spec` describes, with an empty history.
    pub fn new(spec: TeacherSpec) -> Result<Self> {
        let selector = spec.build()?;
        Ok(AskTell { spec, selector, asked: Vec::new(), asked_mode: Vec::new(), asked_region: Vec::new(), told: Vec::new(), told_competence: Vec::new(), told_region: Vec::new() })
    }

    /// SAGG-RIAC over the box [low, high] of any dimension.
    pub fn sagg_riac(low: &[f64], high: &[f64], tree: RegionTreeConfig, modes: ModeProbabilities, seed: u64) -> Result<Self> {
        Self::new(TeacherSpec { teacher: Teacher::SaggRiac(SaggRiacConfig { tree, modes, ..Default::default() }), low: low.to_vec(), high: high.to_vec(), seed, dims: Default::default() })
    }

    /// Goals uniform in [low, high] (SAGG-Random's high level).
    pub fn random(low: &[f64], high: &[f64], seed: u64) -> Result<Self> {
        Self::new(TeacherSpec { teacher: Teacher::Random(RandomConfig {}), low: low.to_vec(), high: high.to_vec(), seed, dims: Default::default() })
    }

    pub fn spec(&self) -> &TeacherSpec {
        &self.spec
    }

    /// Everything needed to continue later: the parameters, the state (generator included) and
    /// the history. `restore` gives a teacher that asks exactly the goals this one would have.
    pub fn save(&self) -> Result<Vec<u8>> {
        let state = self.selector.save().ok_or_else(|| Error::InvalidInput(format!("The {} teacher cannot be saved.", self.spec.kind())))?;
        let saved = Saved {
            format: FORMAT,
            version: env!("CARGO_PKG_VERSION").to_string(),
            spec: self.spec.clone(),
            state,
            asked: self.asked.clone(),
            asked_mode: self.asked_mode.clone(),
            asked_region: self.asked_region.clone(),
            told: self.told.clone(),
            told_competence: self.told_competence.clone(),
            told_region: self.told_region.clone(),
        };
        postcard::to_stdvec_crc32(&saved, CHECKSUM.digest()).map_err(|e| Error::InvalidInput(format!("Could not encode the teacher: {e}.")))
    }

    /// The teacher `save` wrote.
    pub fn restore(bytes: &[u8]) -> Result<Self> {
        let refuse = |why: String| Error::InvalidInput(format!("{why} It cannot be restored; save the teacher again."));
        // The format comes first in every layout: read it alone, then the layout it names.
        let format = postcard::take_from_bytes::<u32>(bytes).map(|(f, _)| f).unwrap_or(FORMAT);
        let decoded = match format {
            1 => decode::<legacy::SavedV1>(bytes).map(legacy::upgrade),
            2 => decode::<legacy::SavedV2>(bytes).map(legacy::upgrade),
            3 => decode::<legacy::SavedV3>(bytes).map(legacy::upgrade),
            4 => decode::<legacy::SavedV4>(bytes).map(legacy::upgrade),
            5 => decode::<legacy::SavedV5>(bytes).map(legacy::upgrade),
            6 => decode::<legacy::SavedV6>(bytes).map(legacy::upgrade),
            _ => decode::<Saved>(bytes),
        };
        let s = match decoded {
            Ok(s) => s,
            Err(DecodeError::Trailing) => return Err(refuse("The saved teacher is damaged: bytes follow its end.".into())),
            Err(DecodeError::Postcard(postcard::Error::DeserializeBadCrc)) => return Err(refuse("The saved teacher is damaged: its checksum does not match its content.".into())),
            Err(DecodeError::Postcard(e)) => return Err(refuse(format!("The data is damaged or not a saved saggriac teacher ({e})."))),
        };
        if s.format != FORMAT {
            return Err(refuse(format!(
                "The saved teacher has format {} but this saggriac ({}) reads formats 1 to {FORMAT}; it was written by saggriac {}.",
                s.format,
                env!("CARGO_PKG_VERSION"),
                s.version
            )));
        }
        let by = format!("it was written by saggriac {}, this is saggriac {}", s.version, env!("CARGO_PKG_VERSION"));
        // A teacher this version no longer builds (a rule added since) is named as such.
        let mut t = AskTell::new(s.spec).map_err(|e| Error::InvalidInput(format!("The saved teacher cannot be rebuilt ({by}): {e}")))?;
        if !t.selector.load(&s.state) {
            return Err(refuse(format!("The saved state does not belong to a {} teacher ({by}).", t.spec.kind())));
        }
        (t.asked, t.asked_mode, t.asked_region) = (s.asked, s.asked_mode, s.asked_region);
        (t.told, t.told_competence, t.told_region) = (s.told, s.told_competence, s.told_region);
        Ok(t)
    }

    pub fn selector(&self) -> &dyn GoalSelector {
        self.selector.as_ref()
    }
    pub fn dim(&self) -> usize {
        self.selector.dim()
    }

    pub fn sample(&mut self) -> GoalChoice {
        let c = self.selector.sample();
        self.asked.extend_from_slice(&c.goal);
        self.asked_mode.push(c.mode as u8);
        self.asked_region.push(c.region.map(|r| r as i64).unwrap_or(-1));
        c
    }

    /// `n` goals in a row, flattened row by row (no update in between, so the same tree).
    pub fn sample_batch(&mut self, n: usize) -> Result<Vec<f64>> {
        if n > MAX_BATCH || n.saturating_mul(self.dim()) > MAX_BATCH_VALUES {
            return Err(invalid("sample_batch", "n", format!("an int with n <= {MAX_BATCH} and n * dim <= {MAX_BATCH_VALUES} (dim = {})", self.dim()), n));
        }
        let mut out = Vec::with_capacity(n * self.dim());
        for _ in 0..n {
            out.extend(self.sample().goal);
        }
        Ok(out)
    }

    /// Check a told goal: the right length, finite, inside the box; a finite competence.
    fn check(&self, goal: &[f64], competence: f64, row: Option<usize>) -> Result<()> {
        let at = row.map(|r| format!(" (row {r})")).unwrap_or_default();
        let d = self.dim();
        if goal.len() != d {
            return Err(Error::InvalidInput(format!("goal{at} must have {d} coordinates, the dimension of the goal space; got {}.", goal.len())));
        }
        if !(competence.is_finite() && competence.abs() <= MAX_COMPETENCE) {
            return Err(Error::InvalidInput(format!("competence{at} must be a finite float with |competence| <= 1e100; got {}.", Num(competence))));
        }
        let (lo, hi) = (self.selector.low(), self.selector.high());
        for i in 0..d {
            if !(goal[i] >= lo[i] && goal[i] <= hi[i]) {
                return Err(Error::InvalidInput(format!("goal{at} must lie in the goal space [low, high]; coordinate {i} is {} but the bounds are [{}, {}].", Num(goal[i]), Num(lo[i]), Num(hi[i]))));
            }
        }
        self.selector.check_told(goal, competence).map_err(|e| match (e, row) {
            (Error::InvalidInput(m), Some(r)) => Error::InvalidInput(m.replacen("goal ", &format!("goal (row {r}) "), 1).replacen("competence ", &format!("competence (row {r}) "), 1)),
            (e, _) => e,
        })
    }

    /// Tell the competence obtained at `goal`; returns the region that recorded it (-1: none).
    pub fn update(&mut self, goal: &[f64], competence: f64) -> Result<i64> {
        self.check(goal, competence, None)?;
        Ok(self.record(goal, competence))
    }

    /// Tell a batch (goals row by row). Every row is checked before any is recorded, so a bad
    /// batch changes nothing.
    pub fn update_batch(&mut self, goals: &[f64], competences: &[f64]) -> Result<Vec<i64>> {
        let d = self.dim();
        if goals.len() != competences.len() * d {
            return Err(Error::InvalidInput(format!("goals must have one row of {d} coordinates per competence; got {} values for {} competences.", goals.len(), competences.len())));
        }
        for (i, (g, c)) in goals.chunks_exact(d).zip(competences).enumerate() {
            self.check(g, *c, Some(i))?;
        }
        Ok(goals.chunks_exact(d).zip(competences).map(|(g, c)| self.record(g, *c)).collect())
    }

    fn record(&mut self, goal: &[f64], competence: f64) -> i64 {
        let r = self.selector.update(goal, competence).map(|r| r as i64).unwrap_or(-1);
        self.told.extend_from_slice(goal);
        self.told_competence.push(competence);
        self.told_region.push(r);
        r
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A teacher of 40 dimensions, as an older SPDL without a bound saved it: refused, naming
    /// the rule and both versions.
    #[test]
    fn a_saved_teacher_this_version_cannot_rebuild_names_its_writer() {
        let spec = TeacherSpec { teacher: Teacher::Spdl(crate::config::teachers::SpdlConfig::default()), low: vec![0.0; 40], high: vec![1.0; 40], seed: 0, dims: Default::default() };
        let saved = Saved { format: FORMAT, version: "0.5.9".into(), spec, state: vec![], asked: vec![], asked_mode: vec![], asked_region: vec![], told: vec![], told_competence: vec![], told_region: vec![] };
        let bytes = postcard::to_stdvec_crc32(&saved, CHECKSUM.digest()).unwrap();
        let e = AskTell::restore(&bytes).err().unwrap().to_string();
        let by = format!("it was written by saggriac 0.5.9, this is saggriac {}", env!("CARGO_PKG_VERSION"));
        assert!(e.starts_with(&format!("The saved teacher cannot be rebuilt ({by}): The 'bounds' parameter of SpdlSelector must be bounds of at most 30")), "{e}");
    }

    /// A SAGG-RIAC teacher saved by saggriac 0.2.0 (format 1; ac8c087, 200 goals told) restores
    /// with the reading it ran, and asks the 20 goals 0.2.0 asked next, to the bit.
    #[test]
    fn a_teacher_saved_by_saggriac_0_2_continues_exactly() {
        use crate::config::high_level::InterestDivisor;
        use crate::rng::{rng_from_seed, uniform};
        let bytes = include_bytes!("../../tests/data/teacher_v1_sagg_riac.bin");
        let next = include_str!("../../tests/data/teacher_v1_sagg_riac.next");
        let mut a = AskTell::restore(bytes).unwrap();
        let Teacher::SaggRiac(SaggRiacConfig { tree, .. }) = a.spec().teacher else { panic!("not SAGG-RIAC") };
        assert_eq!((tree.g_max, tree.zeta, tree.min_child, tree.divisor), (12, 8, 2, InterestDivisor::Window));
        assert_eq!(a.told_competence.len(), 200);
        // The competences 0.2.0's generator drew, replayed: the first 200 went into the save.
        let mut r = rng_from_seed(5);
        for _ in 0..200 {
            uniform(&mut r, 0.0, 1.0);
        }
        for line in next.lines() {
            let bits: Vec<u64> = line.split(' ').map(|b| b.parse().unwrap()).collect();
            let g = a.sample().goal;
            assert_eq!((g[0].to_bits(), g[1].to_bits()), (bits[0], bits[1]));
            a.update(&g, -uniform(&mut r, 0.0, 1.0) * (g[0] / 2.0)).unwrap();
        }
        // Saved again, it is a teacher of this format that restores as itself.
        let again = AskTell::restore(&a.save().unwrap()).unwrap();
        assert_eq!(again.spec(), a.spec());
    }

    /// Teachers saved in format 4 (saggriac 0.6.0 before #46, 164832d, by
    /// tests/data/saved_teachers.py 4) or 5 (saggriac after 0.6.0 with PLR's ties, 02d4afe, by
    /// tests/data/saved_teachers.py 5) continue exactly: ADR and Goal GAN with their parameters of
    /// then, SPDL of format 4 over its 20 goals before its next update (its update rule changed
    /// in 10bb97b, its draws did not) and of format 5 through an update, the task-list teachers
    /// as ever (format 4's PLR: `a_plr_teacher_saved_by_saggriac_0_6_restores_with_its_ties`).
    #[test]
    fn teachers_saved_before_per_dimension_parameters_continue_exactly() {
        let files: [(&str, &[u8], &str); 9] = [
            ("adr", include_bytes!("../../tests/data/teacher_v4_adr.bin"), include_str!("../../tests/data/teacher_v4_adr.next")),
            ("spdl", include_bytes!("../../tests/data/teacher_v4_spdl.bin"), include_str!("../../tests/data/teacher_v4_spdl.next")),
            ("goal_gan", include_bytes!("../../tests/data/teacher_v4_goal_gan.bin"), include_str!("../../tests/data/teacher_v4_goal_gan.next")),
            ("tscl", include_bytes!("../../tests/data/teacher_v4_tscl.bin"), include_str!("../../tests/data/teacher_v4_tscl.next")),
            ("adr", include_bytes!("../../tests/data/teacher_v5_adr.bin"), include_str!("../../tests/data/teacher_v5_adr.next")),
            ("spdl", include_bytes!("../../tests/data/teacher_v5_spdl.bin"), include_str!("../../tests/data/teacher_v5_spdl.next")),
            ("goal_gan", include_bytes!("../../tests/data/teacher_v5_goal_gan.bin"), include_str!("../../tests/data/teacher_v5_goal_gan.next")),
            ("tscl", include_bytes!("../../tests/data/teacher_v5_tscl.bin"), include_str!("../../tests/data/teacher_v5_tscl.next")),
            ("plr", include_bytes!("../../tests/data/teacher_v5_plr.bin"), include_str!("../../tests/data/teacher_v5_plr.next")),
        ];
        let told = |kind: &str, g: &[f64]| match kind {
            "tscl" | "plr" => (g[0] + 1.0) / 6.0,
            _ => f64::from(u8::from(g[0] + 0.5 * (g[1] + 1.0) + 0.25 * g[2] < 0.9)),
        };
        for (kind, bytes, next) in files {
            let format = postcard::take_from_bytes::<u32>(bytes).unwrap().0;
            assert!(format == 4 || format == 5, "{kind}: {format}");
            let a = continues_exactly(kind, bytes, next, told);
            assert!(a.spec().dims.is_empty());
        }
    }

    /// A SAGG-RIAC teacher saved before mode 3 had a reading (format 6, by
    /// tests/data/saved_teachers.py 6) restores with the paper's reading, asks the goals it asked
    /// then, to the bit, and saved again carries a reading chosen since.
    #[test]
    fn a_sagg_riac_teacher_saved_before_mode3_readings_continues_exactly() {
        use crate::config::high_level::{Mode3Config, Mode3Reading};
        let (bytes, next) = (include_bytes!("../../tests/data/teacher_v6_sagg_riac.bin"), include_str!("../../tests/data/teacher_v6_sagg_riac.next"));
        assert_eq!(postcard::take_from_bytes::<u32>(bytes).unwrap().0, 6);
        let told = |_: &str, g: &[f64]| f64::from(u8::from(g[0] + 0.5 * (g[1] + 1.0) + 0.25 * g[2] < 0.9));
        let a = continues_exactly("sagg_riac", bytes, next, told);
        let Teacher::SaggRiac(c) = a.spec().teacher else { panic!("not SAGG-RIAC") };
        assert_eq!(c.mode3, Mode3Config::default());
        assert_eq!((c.tree.g_max, c.tree.zeta, c.tree.min_child), (12, 8, 2));
        // Today's format carries another reading through a save and a restore.
        let mode3 = Mode3Config { reading: Mode3Reading::InterestWorst, sigma: 0.03 };
        let spec = TeacherSpec { teacher: Teacher::SaggRiac(SaggRiacConfig { mode3, ..c }), ..a.spec().clone() };
        let mut b = AskTell::new(spec).unwrap();
        for i in 0..200 {
            let g = b.sample().goal;
            b.update(&g, -((i % 5) as f64) / 5.0).unwrap();
        }
        let mut r = AskTell::restore(&b.save().unwrap()).unwrap();
        let Teacher::SaggRiac(rc) = r.spec().teacher else { panic!("not SAGG-RIAC") };
        assert_eq!(rc.mode3, mode3);
        for _ in 0..50 {
            assert_eq!(r.sample(), b.sample());
        }
    }

    /// The saved teacher `bytes` of `kind` restores and asks the goals of `next` (one per line,
    /// each coordinate's bits), told `told`; saved again in today's format, it asks the same.
    fn continues_exactly(kind: &str, bytes: &[u8], next: &str, told: impl Fn(&str, &[f64]) -> f64) -> AskTell {
        let mut a = AskTell::restore(bytes).unwrap();
        assert_eq!(a.spec().kind(), kind);
        let mut again = AskTell::restore(&a.save().unwrap()).unwrap();
        for line in next.lines() {
            let bits: Vec<u64> = line.split(' ').map(|b| b.parse().unwrap()).collect();
            let g = a.sample().goal;
            assert_eq!(g.iter().map(|v| v.to_bits()).collect::<Vec<_>>(), bits, "{kind}");
            a.update(&g, told(kind, &g)).unwrap();
            let h = again.sample().goal;
            assert_eq!(h, g, "{kind}");
            again.update(&h, told(kind, &h)).unwrap();
        }
        a
    }

    /// A teacher of every kind saved by saggriac 0.4 (format 2, one enum of all states; written at
    /// 4316e31) or 0.5 (format 3, one enum of teachers with their boxes; written at 4ffeabf by
    /// tests/data/saved_teachers.py 3) restores into today's types and asks the 20 goals 0.4 or 0.5
    /// asked next, to the bit.
    #[test]
    fn teachers_saved_by_saggriac_0_4_and_0_5_continue_exactly() {
        let files: [(&str, &[u8], &str); 12] = [
            ("sagg_riac", include_bytes!("../../tests/data/teacher_v3_sagg_riac.bin"), include_str!("../../tests/data/teacher_v3_sagg_riac.next")),
            ("random", include_bytes!("../../tests/data/teacher_v3_random.bin"), include_str!("../../tests/data/teacher_v3_random.next")),
            ("riac", include_bytes!("../../tests/data/teacher_v3_riac.bin"), include_str!("../../tests/data/teacher_v3_riac.next")),
            ("alp_gmm", include_bytes!("../../tests/data/teacher_v3_alp_gmm.bin"), include_str!("../../tests/data/teacher_v3_alp_gmm.next")),
            ("covar_gmm", include_bytes!("../../tests/data/teacher_v3_covar_gmm.bin"), include_str!("../../tests/data/teacher_v3_covar_gmm.next")),
            ("discrete_lp", include_bytes!("../../tests/data/teacher_v3_discrete_lp.bin"), include_str!("../../tests/data/teacher_v3_discrete_lp.next")),
            ("sagg_riac", include_bytes!("../../tests/data/teacher_v2_sagg_riac.bin"), include_str!("../../tests/data/teacher_v2_sagg_riac.next")),
            ("random", include_bytes!("../../tests/data/teacher_v2_random.bin"), include_str!("../../tests/data/teacher_v2_random.next")),
            ("riac", include_bytes!("../../tests/data/teacher_v2_riac.bin"), include_str!("../../tests/data/teacher_v2_riac.next")),
            ("alp_gmm", include_bytes!("../../tests/data/teacher_v2_alp_gmm.bin"), include_str!("../../tests/data/teacher_v2_alp_gmm.next")),
            ("covar_gmm", include_bytes!("../../tests/data/teacher_v2_covar_gmm.bin"), include_str!("../../tests/data/teacher_v2_covar_gmm.next")),
            ("discrete_lp", include_bytes!("../../tests/data/teacher_v2_discrete_lp.bin"), include_str!("../../tests/data/teacher_v2_discrete_lp.next")),
        ];
        // The competences the files were made with (tests/data was written by a script doing this).
        let told = |kind: &str, g: &[f64]| if kind == "discrete_lp" { (g[0] + 1.0) / 6.0 } else { -0.5 * g[0] - 0.25 * g[g.len() - 1] * g[g.len() - 1] };
        for (kind, bytes, next) in files {
            continues_exactly(kind, bytes, next, told);
        }
    }

    /// A PLR teacher saved by saggriac 0.6 (format 4, at 164832d: `PlrSelector(5, seed=1)`, 10
    /// levels drawn and told 0.3) restores with the ties rule it ran (`Average`), its history and
    /// state, and goes on drawing levels; saved again, it is a format-5 teacher.
    #[test]
    fn a_plr_teacher_saved_by_saggriac_0_6_restores_with_its_ties() {
        use crate::config::teachers::{PlrConfig, PlrScore, PlrTies, ReplaySchedule};
        let mut a = AskTell::restore(include_bytes!("../../tests/data/teacher_v4_plr.bin")).unwrap();
        let want = PlrConfig { n_tasks: 5, temperature: 0.1, staleness_coef: 0.1, replay_schedule: ReplaySchedule::Proportionate, replay_prob: 0.5, score: PlrScore::Progress, ties: PlrTies::Average };
        assert_eq!(a.spec().teacher, Teacher::Plr(want));
        assert_eq!((a.asked.len(), a.told_competence.len()), (10, 10));
        assert!(a.told_competence.iter().all(|&c| c == 0.3));
        // Every level has a chance at the next draw (a replay or, if unseen, a new level).
        let p = a.selector().task_probabilities().unwrap();
        assert!((p.iter().sum::<f64>() - 1.0).abs() < 1e-12 && p.iter().all(|&x| x > 0.0), "{p:?}");
        for _ in 0..20 {
            let g = a.sample().goal;
            assert!(g[0].fract() == 0.0 && (0.0..5.0).contains(&g[0]));
            a.update(&g, 0.3).unwrap();
        }
        let bytes = a.save().unwrap();
        assert_eq!(postcard::take_from_bytes::<u32>(&bytes).unwrap().0, FORMAT);
        assert_eq!(AskTell::restore(&bytes).unwrap().spec(), a.spec());
    }

    #[test]
    fn rejects_bad_input_and_keeps_state() {
        let mut a = AskTell::sagg_riac(&[0.0, 0.0], &[1.0, 1.0], RegionTreeConfig::default(), ModeProbabilities::default(), 1).unwrap();
        let e = a.update(&[0.5], -0.1).unwrap_err().to_string();
        assert!(e.contains("2 coordinates"), "{e}");
        let e = a.update(&[0.5, 1.5], -0.1).unwrap_err().to_string();
        assert!(e.contains("coordinate 1 is 1.5"), "{e}");
        let e = a.update(&[0.5, 0.5], f64::NAN).unwrap_err().to_string();
        assert!(e.contains("finite"), "{e}");
        let e = a.update_batch(&[0.1, 0.1, 0.2, f64::INFINITY], &[-0.1, -0.2]).unwrap_err().to_string();
        assert!(e.contains("row 1"), "{e}");
        assert!(a.told_competence.is_empty());
        assert_eq!(a.selector().tree().unwrap().n_measurements(), 0);
        assert_eq!(a.update_batch(&[0.1, 0.1, 0.2, 0.2], &[-0.1, -0.2]).unwrap(), vec![0, 0]);
    }

    /// Half a session, a save, a restore: the restored teacher asks the same goals as one that
    /// never stopped, and keeps the history.
    #[test]
    fn a_restored_teacher_continues_exactly() {
        let make = || AskTell::sagg_riac(&[0.0, 0.0, 0.0], &[1.0, 1.0, 1.0], RegionTreeConfig { g_max: 10, zeta: 5, min_child: 2, ..Default::default() }, ModeProbabilities::default(), 3).unwrap();
        let competence = |g: &[f64]| -(g[0] - 0.3).abs() - 0.5 * g[1];
        let (mut a, mut b) = (make(), make());
        for _ in 0..300 {
            let g = a.sample().goal;
            a.update(&g, competence(&g)).unwrap();
            let g = b.sample().goal;
            b.update(&g, competence(&g)).unwrap();
        }
        let bytes = b.save().unwrap();
        let mut b = AskTell::restore(&bytes).unwrap();
        assert_eq!((b.asked.len(), b.told_competence.len()), (900, 300));
        for _ in 0..300 {
            let (ga, gb) = (a.sample(), b.sample());
            assert_eq!(ga, gb);
            a.update(&ga.goal, competence(&ga.goal)).unwrap();
            b.update(&gb.goal, competence(&gb.goal)).unwrap();
        }
        assert_eq!(a.selector().tree().unwrap().regions().len(), b.selector().tree().unwrap().regions().len());
        // A damaged save is refused, naming the problem.
        let mut bad = bytes.clone();
        bad[bytes.len() / 2] ^= 1;
        let e = AskTell::restore(&bad).err().unwrap().to_string();
        assert!(e.contains("damaged"), "{e}");
        assert!(AskTell::restore(b"not a teacher").is_err());
    }
}

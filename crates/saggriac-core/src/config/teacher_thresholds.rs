//! Thresholds a teacher compares told competences with (ADR's t_low / t_high, SPDL's delta,
//! Goal GAN's success_threshold): the papers write them for a success rate in [0, 1], while a
//! run tells competences in [min_c, 0]. A threshold no told competence can meet would leave the
//! teacher idle without a word, so it is moved to the competences' scale or refused.

use super::teachers::{AdrConfig, GoalGanConfig, SpdlConfig, Teacher};
use crate::error::{invalid, Num, Result};

impl Teacher {
    /// The paper's defaults of the parameters compared with a told competence (written for a
    /// success rate in [0, 1]) moved to competences in [lo, hi] by the linear map
    /// 0 -> lo, 1 -> hi: a run chooses its teacher's defaults this way for its [min_c, 0].
    pub fn scaled_to_competences(self, lo: f64, hi: f64) -> Teacher {
        let at = |share: f64| lo + share * (hi - lo);
        match self {
            Teacher::Adr(c) => Teacher::Adr(AdrConfig { t_low: at(c.t_low), t_high: at(c.t_high), ..c }),
            Teacher::Spdl(c) => Teacher::Spdl(SpdlConfig { delta: at(c.delta), ..c }),
            Teacher::GoalGan(c) => Teacher::GoalGan(GoalGanConfig { success_threshold: at(c.success_threshold), ..c }),
            other => other,
        }
    }

    /// Every threshold a told competence is compared with must be one that competences in
    /// [lo, hi] (`whence`: who tells them, "a run tells") can both meet and miss: otherwise the
    /// teacher would sit still without a word (ADR's bounds never grow, SPDL never moves, Goal
    /// GAN never finds a goal of intermediate difficulty).
    pub fn check_competences(&self, lo: f64, hi: f64, whence: &str) -> Result<()> {
        let (lo_s, hi_s) = (Num(lo), Num(hi));
        let told = format!("the competences {whence} lie in [{lo_s}, {hi_s}]");
        let owner = self.class();
        match self {
            Teacher::Adr(c) => {
                if c.t_high > hi {
                    return Err(invalid(owner, "t_high", format!("a float <= {hi_s} ({told}, and a bound grows only when the mean competence at it is >= t_high)"), Num(c.t_high)));
                }
                if c.t_low < lo {
                    return Err(invalid(owner, "t_low", format!("a float >= {lo_s} ({told}, and a bound shrinks only when the mean competence at it is <= t_low)"), Num(c.t_low)));
                }
            }
            Teacher::Spdl(c) if !(lo..=hi).contains(&c.delta) => {
                return Err(invalid(owner, "delta", format!("a float in [{lo_s}, {hi_s}] ({told}; the distribution moves only while the expected competence is >= delta, so outside it would never move, or never be held back)"), Num(c.delta)));
            }
            Teacher::GoalGan(c) if !(c.success_threshold > lo && c.success_threshold <= hi) => {
                return Err(invalid(owner, "success_threshold", format!("a float in ({lo_s}, {hi_s}] ({told}; a competence >= success_threshold is a success, so outside every attempt would fail, or succeed)"), Num(c.success_threshold)));
            }
            _ => {}
        }
        Ok(())
    }
}

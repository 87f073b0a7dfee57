//! The high level's parameters: competence, the region tree, the goal selection modes, and the
//! rule every box of a goal space obeys.

use crate::config::rules::{check_fields, check_float, PROBABILITY, Rule};
use crate::error::{invalid, Num, Result, MAX_COUNT};

/// What an attempt's final distance to its goal is measured against.
#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum CompetenceKind {
    /// Eq. 7: C = -D(x_g, x_f) / D(x_start, x_g), the paper's.
    Relative,
    /// C = -D(x_g, x_f) / reach (the arm's length): the same distance costs the same wherever
    /// the attempt started. Beyond the paper; meant for the episodic paradigm, where every
    /// movement "starts" at rest and eq. 7 inflates small errors near it.
    Absolute,
}

impl CompetenceKind {
    pub fn parse(s: &str) -> Option<Self> {
        match s {
            "relative" => Some(CompetenceKind::Relative),
            "absolute" => Some(CompetenceKind::Absolute),
            _ => None,
        }
    }
    pub fn name(&self) -> &'static str {
        match self {
            CompetenceKind::Relative => "relative",
            CompetenceKind::Absolute => "absolute",
        }
    }
}

/// Thresholds of the competence measure.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct CompetenceConfig {
    /// Lowest competence; worse attempts are clipped to it (min_C < 0).
    pub min_c: f64,
    /// Tolerance: a cost above eps_C (min_C < eps_C < 0) counts as reached, competence 0.
    pub eps_c: f64,
    #[serde(rename = "competence")]
    pub kind: CompetenceKind,
}

impl Default for CompetenceConfig {
    fn default() -> Self {
        CompetenceConfig { min_c: -1.0, eps_c: -0.05, kind: CompetenceKind::Relative }
    }
}

impl CompetenceConfig {
    pub fn validate(&self) -> Result<()> {
        if !(self.min_c.is_finite() && self.min_c < 0.0) {
            return Err(invalid("Competence", "min_c", "a finite float < 0", Num(self.min_c)));
        }
        if !(self.eps_c.is_finite() && self.eps_c < 0.0 && self.eps_c > self.min_c) {
            return Err(invalid("Competence", "eps_c", format!("a float with min_c < eps_c < 0 (min_c = {})", Num(self.min_c)), Num(self.eps_c)));
        }
        Ok(())
    }
}

/// How eq. 2 reads a region's window: the denominator of a region holding fewer than zeta
/// measurements, and which values a full region compares. The paper prints zeta and says nothing
/// of young regions; its index ranges hold zeta + 1 values.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, serde::Serialize, serde::Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum InterestDivisor {
    /// Eq. 2 as printed: every region's half-sums are divided by zeta, so a young region's
    /// progress counts in proportion to the measurements behind it (saggriac >= 0.3).
    #[default]
    Zeta,
    /// The region's own window w = min(|R|, zeta): a young region gets the scale of a full one
    /// (saggriac <= 0.2; kept for comparisons and for the same bits as older builds).
    Window,
    /// Eq. 2's index ranges as printed: a full region compares the last zeta + 1 values, the
    /// middle one (in both printed sums) cancelling; divided by zeta. A region of at most zeta
    /// values reads as `Zeta`. (`Zeta` and `Window` compare the last zeta values.)
    Printed,
}

impl InterestDivisor {
    pub const NAMES: [&'static str; 3] = ["zeta", "window", "printed"];

    pub fn parse(owner: &'static str, s: &str) -> Result<Self> {
        match s {
            "zeta" => Ok(InterestDivisor::Zeta),
            "window" => Ok(InterestDivisor::Window),
            "printed" => Ok(InterestDivisor::Printed),
            _ => Err(invalid(owner, "interest_divisor", "one of 'zeta' (the default), 'window' (saggriac <= 0.2), 'printed' (eq. 2's index ranges, zeta + 1 values)", format!("'{s}'"))),
        }
    }
    pub fn name(&self) -> &'static str {
        Self::NAMES[*self as usize]
    }
    /// The denominator of a window of `w` values under window length `zeta`.
    pub fn of(&self, w: usize, zeta: usize) -> f64 {
        match self {
            InterestDivisor::Zeta | InterestDivisor::Printed => zeta as f64,
            InterestDivisor::Window => w as f64,
        }
    }
    /// How many of a region's most recent values eq. 2 reads under window length `zeta`.
    pub fn window_len(&self, zeta: usize) -> usize {
        match self {
            InterestDivisor::Zeta | InterestDivisor::Window => zeta,
            InterestDivisor::Printed => zeta + 1,
        }
    }
}

#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct RegionTreeConfig {
    /// A leaf holding more than g_max measurements is split.
    pub g_max: usize,
    /// Interest window (eq. 2).
    pub zeta: usize,
    /// Fewest measurements each child of a split must receive.
    pub min_child: usize,
    /// Eq. 2's denominator for regions younger than zeta measurements.
    #[serde(rename = "interest_divisor")]
    pub divisor: InterestDivisor,
}

impl Default for RegionTreeConfig {
    fn default() -> Self {
        RegionTreeConfig { g_max: 50, zeta: 20, min_child: 5, divisor: InterestDivisor::Zeta }
    }
}

/// The rules of SAGG-RIAC's high level: its region tree's and its goal modes' parameters.
pub const SAGG_RIAC_RULES: &[(&str, Rule)] = &[
    ("g_max", Rule::Int(2, MAX_COUNT)),
    ("zeta", Rule::Int(2, MAX_COUNT)),
    ("min_child", Rule::Int(1, MAX_COUNT)),
    ("interest_divisor", Rule::Choice),
    ("p_interest", PROBABILITY),
    ("p_global", PROBABILITY),
    ("p_lowest", PROBABILITY),
    ("mode3", Rule::Choice),
    ("mode3_sigma", Rule::Float { lo: 0.0, lo_in: false, hi: 1.0, hi_in: true, note: "a share of the box's width" }),
];

impl RegionTreeConfig {
    pub fn validate(&self) -> Result<()> {
        let (o, r) = ("RegionTree", SAGG_RIAC_RULES);
        check_fields!(o, r, self, int g_max, int zeta, int min_child);
        if 2 * self.min_child > self.g_max + 1 {
            return Err(invalid(o, "min_child", format!("an int with 2 * min_child <= g_max + 1 (g_max = {})", self.g_max), self.min_child));
        }
        Ok(())
    }
}

#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct ModeProbabilities {
    pub p_interest: f64,
    pub p_global: f64,
    pub p_lowest: f64,
}

impl Default for ModeProbabilities {
    fn default() -> Self {
        ModeProbabilities { p_interest: 0.7, p_global: 0.2, p_lowest: 0.1 }
    }
}

impl ModeProbabilities {
    pub fn validate(&self) -> Result<()> {
        let (o, r) = ("SaggRiac", SAGG_RIAC_RULES);
        check_fields!(o, r, self, float p_interest, float p_global, float p_lowest);
        let s = self.p_interest + self.p_global + self.p_lowest;
        if (s - 1.0).abs() > 1e-9 {
            return Err(invalid("SaggRiac", "p_lowest", format!("such that p_interest + p_global + p_lowest = 1 (p_interest = {}, p_global = {})", Num(self.p_interest), Num(self.p_global)), Num(self.p_lowest)));
        }
        Ok(())
    }
}

/// How mode 3 reads "a random experiment inside the region where the mean competence level is
/// the lowest" (paper II.D.3), and a reading beyond the paper.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, serde::Serialize, serde::Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Mode3Reading {
    /// The paper's: the leaf of lowest mean competence among leaves holding measurements, the
    /// goal uniform in it.
    #[default]
    LowestCompetence,
    /// A leaf drawn by interest as in mode 1 (eq. 3), the goal a Gaussian about the goal of lowest
    /// competence the leaf holds, clipped to the leaf: mode 3 of RIAC as Portelas et al. (CoRL
    /// 2019) run it.
    InterestWorst,
}

impl Mode3Reading {
    pub const NAMES: [&'static str; 2] = ["lowest_competence", "interest_worst"];

    pub fn parse(owner: &'static str, s: &str) -> Result<Self> {
        match s {
            "lowest_competence" => Ok(Mode3Reading::LowestCompetence),
            "interest_worst" => Ok(Mode3Reading::InterestWorst),
            _ => Err(invalid(owner, "mode3", "one of 'lowest_competence' (the default, the paper's), 'interest_worst' (a leaf by interest, near its worst goal)", format!("'{s}'"))),
        }
    }
    pub fn name(&self) -> &'static str {
        Self::NAMES[*self as usize]
    }
}

/// Mode 3's reading and, for `InterestWorst`, the Gaussian's sd as a share of the box's width
/// in each dimension (unused by the paper's reading).
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct Mode3Config {
    #[serde(rename = "mode3")]
    pub reading: Mode3Reading,
    #[serde(rename = "mode3_sigma")]
    pub sigma: f64,
}

impl Default for Mode3Config {
    fn default() -> Self {
        // sigma: chosen on tuning seeds by a rule written first (docs/sagg_riac_mode3.md).
        Mode3Config { reading: Mode3Reading::LowestCompetence, sigma: 0.05 }
    }
}

impl Mode3Config {
    pub fn validate(&self) -> Result<()> {
        check_float("SaggRiac", SAGG_RIAC_RULES, "mode3_sigma", self.sigma)?;
        // The paper's reading has no Gaussian: a sigma given with it would be ignored unseen.
        let default = Self::default().sigma;
        if self.reading == Mode3Reading::LowestCompetence && self.sigma != default {
            let rule = format!("left at its default {} with mode3 = 'lowest_competence' (it is the sd of mode3 = 'interest_worst' only)", Num(default));
            return Err(invalid("SaggRiac", "mode3_sigma", rule, Num(self.sigma)));
        }
        Ok(())
    }
}

/// Bounds must be finite, of equal non-zero length, and strictly ordered.
pub fn check_bounds(owner: &'static str, low: &[f64], high: &[f64]) -> Result<()> {
    check_bounds_named(owner, "bounds", low, high)
}

/// `check_bounds` with the messages naming the bounds `param` (a run's "goal_low/goal_high").
pub fn check_bounds_named(owner: &'static str, param: &str, low: &[f64], high: &[f64]) -> Result<()> {
    if low.is_empty() || low.len() != high.len() {
        return Err(invalid(owner, param, format!("low and high of equal non-zero length (low has {})", low.len()), high.len()));
    }
    for (i, (l, h)) in low.iter().zip(high).enumerate() {
        if !(l.is_finite() && h.is_finite() && l < h) {
            return Err(invalid(owner, param, format!("finite with low < high in every dimension (dimension {i}: low = {})", Num(*l)), Num(*h)));
        }
        // Goals are drawn as low + u * (high - low): the width itself must be a finite float.
        if !(h - l).is_finite() {
            return Err(invalid(owner, param, format!("such that high - low is a finite float in every dimension (dimension {i}: low = {l:?})"), format!("{h:?}")));
        }
    }
    Ok(())
}

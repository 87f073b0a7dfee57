//! The parameters of the teachers that can choose a run's goals in place of SAGG-RIAC's high
//! level (`crate::high_level::teachers`), with their papers' defaults and their rules.

use serde::{Deserialize, Serialize};

use crate::error::{invalid, Check, Num, Result, MAX_COUNT};

/// The int parameters of the teachers (and of SAGG-RIAC's region tree) with their bounds: the one
/// statement of each rule, read by `validate()` and by `param_rule`, so that a value of the wrong
/// type is told the same rule as a value out of range.
pub const INT_RULES: &[(&str, usize, usize)] = &[
    ("g_max", 2, MAX_COUNT),
    ("zeta", 2, MAX_COUNT),
    ("max_region_size", 2, MAX_COUNT),
    // Each attempt scans the leaf: 10^4 attempts of 10^6 measurements is already long.
    ("split_attempts", 1, 10_000),
    ("fit_rate", 2, MAX_COUNT),
    // EM tries every number of components up to this one at each refit.
    ("max_components", 2, 100),
    ("bootstrap", 0, MAX_COUNT),
];
/// The float parameters of the teachers with their rules (the checks are in `validate()`).
pub const FLOAT_RULES: &[(&str, &str)] = &[
    ("min_child_share", "a float in (0, 0.5]"),
    ("min_dims_range_ratio", "a float in (0, 0.5]"),
    ("p_alp", "a float in [0, 1]"),
    ("p_random", "a float in [0, 1]"),
    ("random_task_ratio", "a float in [0, 1]"),
];

/// The rule of a teacher parameter as its check states it, None for a name not listed.
pub fn param_rule(name: &str) -> Option<String> {
    if let Some(&(_, lo, hi)) = INT_RULES.iter().find(|r| r.0 == name) {
        return Some(format!("an int in [{lo}, {hi}]"));
    }
    if name == "absolute_lp" {
        return Some("a bool".into());
    }
    FLOAT_RULES.iter().find(|r| r.0 == name).map(|r| r.1.to_string())
}

/// `v` within its INT_RULES bounds.
pub(crate) fn check_int(c: &Check, name: &str, v: usize) -> Result<()> {
    let &(_, lo, hi) = INT_RULES.iter().find(|r| r.0 == name).expect("every checked int parameter is in INT_RULES");
    c.within(name, v, lo, hi)
}

fn float_rule(name: &str) -> &'static str {
    FLOAT_RULES.iter().find(|r| r.0 == name).expect("every float parameter is in FLOAT_RULES").1
}

#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct RiacConfig {
    /// Measurements a leaf holds before it is split (200 in Portelas et al.).
    pub max_region_size: usize,
    /// Random cuts tried per split (50).
    pub split_attempts: usize,
    /// Least share of the leaf's measurements in each child (1/4).
    pub min_child_share: f64,
    /// Least width of a child in every dimension, as a share of the initial range (1/6).
    pub min_dims_range_ratio: f64,
    /// Share of goals from a leaf drawn by ALP, uniform in it (0.7).
    pub p_alp: f64,
    /// Share of goals uniform in the whole box (0.2); the rest go near a leaf's worst goal.
    pub p_random: f64,
}

impl Default for RiacConfig {
    fn default() -> Self {
        RiacConfig { max_region_size: 200, split_attempts: 50, min_child_share: 0.25, min_dims_range_ratio: 1.0 / 6.0, p_alp: 0.7, p_random: 0.2 }
    }
}

impl RiacConfig {
    pub fn validate(&self) -> Result<()> {
        let c = Check { owner: "RiacSelector" };
        check_int(&c, "max_region_size", self.max_region_size)?;
        check_int(&c, "split_attempts", self.split_attempts)?;
        if !(self.min_child_share.is_finite() && self.min_child_share > 0.0 && self.min_child_share <= 0.5) {
            return Err(invalid("RiacSelector", "min_child_share", float_rule("min_child_share"), Num(self.min_child_share)));
        }
        if !(self.min_dims_range_ratio.is_finite() && self.min_dims_range_ratio > 0.0 && self.min_dims_range_ratio <= 0.5) {
            return Err(invalid("RiacSelector", "min_dims_range_ratio", float_rule("min_dims_range_ratio"), Num(self.min_dims_range_ratio)));
        }
        c.probability("p_alp", self.p_alp)?;
        c.probability("p_random", self.p_random)?;
        if self.p_alp + self.p_random > 1.0 + 1e-12 {
            return Err(invalid("RiacSelector", "p_alp", format!("a float with p_alp + p_random <= 1 (p_random = {})", Num(self.p_random)), Num(self.p_alp)));
        }
        Ok(())
    }
}

/// The parameters both mixture teachers share (ALP-GMM's names and defaults).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct AlpGmmConfig {
    /// Tasks between refits, and the window they are fitted on (250).
    pub fit_rate: usize,
    /// Mixtures of 2 to this many components are tried (10).
    pub max_components: usize,
    /// Share of uniform goals after the bootstrap (0.2).
    pub random_task_ratio: f64,
    /// Uniform goals first (250, as fit_rate).
    pub bootstrap: usize,
}

impl Default for AlpGmmConfig {
    fn default() -> Self {
        AlpGmmConfig { fit_rate: 250, max_components: 10, random_task_ratio: 0.2, bootstrap: 250 }
    }
}

impl AlpGmmConfig {
    pub fn validate(&self, owner: &'static str) -> Result<()> {
        let c = Check { owner };
        check_int(&c, "fit_rate", self.fit_rate)?;
        check_int(&c, "max_components", self.max_components)?;
        check_int(&c, "bootstrap", self.bootstrap)?;
        c.probability("random_task_ratio", self.random_task_ratio)?;
        if self.max_components > self.fit_rate {
            return Err(invalid(owner, "max_components", format!("an int <= fit_rate (fit_rate = {})", self.fit_rate), self.max_components));
        }
        Ok(())
    }
}

impl CovarGmmConfig {
    pub fn validate(&self) -> Result<()> {
        self.mixture.validate("CovarGmmSelector")
    }
}

#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct CovarGmmConfig {
    /// Window, refit period, number of components, random share and bootstrap, as ALP-GMM's.
    pub mixture: AlpGmmConfig,
    /// Draw components by |progress| (true) or by positive progress only.
    pub absolute_lp: bool,
}

impl Default for CovarGmmConfig {
    fn default() -> Self {
        CovarGmmConfig { mixture: AlpGmmConfig::default(), absolute_lp: true }
    }
}

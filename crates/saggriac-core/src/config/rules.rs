//! The rules of the teachers' numeric parameters (and of SAGG-RIAC's region tree), stated once:
//! read by each `validate()` and by `param_rule`, so that a value of the wrong type is told the
//! same rule as a value out of range.

use crate::error::{Check, Result, MAX_COUNT};

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

pub(crate) fn float_rule(name: &str) -> &'static str {
    FLOAT_RULES.iter().find(|r| r.0 == name).expect("every float parameter is in FLOAT_RULES").1
}
